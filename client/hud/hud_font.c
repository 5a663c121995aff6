/* HUD font: a TrueType file baked into a glyph atlas with stb_truetype, and the layout of
 * UTF-8 text into glyph quads with the font's kerning (hud.h "font and layout"). No GL. */
#include "hud.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_truetype.h>

/* atlas side for an em of up to 40 px; each doubling of the em doubles both sides, so a
 * HUD sized for a 4K screen (about 44 px) fits */
#define ATLAS_W    1024
#define ATLAS_H    512
#define OVERSAMPLE 2

/* °, ·, ±, –, —, …, ×, − (the governor's "detail −2"), the quotes of NHC's sentences
 * (“ ” ’), and the letters Spanish and Haitian Creole need (configs/lang: ¡ ¿ á é í ó ú
 * ñ ü à è ò ç and their capitals) */
static const int extra_codepoints[] = {
    0x00B0, 0x00B7, 0x00B1, 0x2013, 0x2014, 0x2026, 0x00D7, 0x2212, 0x201C, 0x201D, 0x2019,
    0x00A1, 0x00BF, 0x00E1, 0x00E9, 0x00ED, 0x00F3, 0x00FA, 0x00F1, 0x00FC, 0x00E0, 0x00E8,
    0x00F2, 0x00E7, 0x00C1, 0x00C9, 0x00CD, 0x00D3, 0x00DA, 0x00D1, 0x00DC, 0x00C0, 0x00C8,
    0x00D2, 0x00C7,
};
#define N_ASCII 95 /* 32..126 */
#define N_EXTRA ((int)(sizeof extra_codepoints / sizeof extra_codepoints[0]))
#define N_GLYPHS (N_ASCII + N_EXTRA)

struct hud_font {
    uint8_t *ttf;   /* owned: the font file */
    uint8_t *atlas; /* owned: aw × ah coverage */
    int aw, ah;     /* atlas size [px] */
    stbtt_fontinfo info;
    stbtt_packedchar ascii[N_ASCII];
    stbtt_packedchar extra[N_EXTRA];
    /* kerning of every pair of baked glyphs [px] (glyph_index order), looked up once at
     * load: stb_truetype's look-up searches the font's tables each time */
    float kern[N_GLYPHS][N_GLYPHS];
    float px, scale; /* em height [px], font units → px */
    float ascent, descent, line_gap;
};

/* ---- font --------------------------------------------------------------------------- */

hud_font *hud_font_load(const char *ttf_path, float px, gale_err *err)
{
    hud_font *f = NULL;
    FILE *fp = NULL;
    if (!(px >= 4.0f && px <= 200.0f)) {
        gale_errf(err, GALE_E_ARG, "hud font size: expected 4..200 px, got %g", (double)px);
        return NULL;
    }
    f = calloc(1, sizeof *f);
    if (!f) {
        goto nomem;
    }
    fp = fopen(ttf_path, "rb");
    if (!fp) {
        gale_errf(err, GALE_E_IO, "%s: cannot open font", ttf_path);
        goto fail;
    }
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    if (n <= 12 || n > (64L << 20)) {
        gale_errf(err, GALE_E_FORMAT, "%s: font size expected 12 B..64 MiB, got %ld", ttf_path, n);
        goto fail;
    }
    f->ttf = malloc((size_t)n);
    f->aw = ATLAS_W;
    f->ah = ATLAS_H;
    for (float em = 40.0f; em < px; em *= 2.0f) {
        f->aw *= 2;
        f->ah *= 2;
    }
    f->atlas = calloc((size_t)f->aw * (size_t)f->ah, 1);
    if (!f->ttf || !f->atlas) {
        goto nomem;
    }
    if (fread(f->ttf, 1, (size_t)n, fp) != (size_t)n) {
        gale_errf(err, GALE_E_IO, "%s: short read", ttf_path);
        goto fail;
    }
    fclose(fp);
    fp = NULL;
    int off = stbtt_GetFontOffsetForIndex(f->ttf, 0);
    if (off < 0 || !stbtt_InitFont(&f->info, f->ttf, off)) {
        gale_errf(err, GALE_E_FORMAT, "%s: not a TrueType font", ttf_path);
        goto fail;
    }
    f->px = px;
    f->scale = stbtt_ScaleForPixelHeight(&f->info, px);
    int asc, desc, gap;
    stbtt_GetFontVMetrics(&f->info, &asc, &desc, &gap);
    f->ascent = (float)asc * f->scale;
    f->descent = (float)desc * f->scale;
    f->line_gap = (float)gap * f->scale;

    stbtt_pack_context pc;
    if (!stbtt_PackBegin(&pc, f->atlas, f->aw, f->ah, 0, 1, NULL)) {
        goto nomem;
    }
    stbtt_PackSetOversampling(&pc, OVERSAMPLE, OVERSAMPLE);
    int extra[N_EXTRA];
    memcpy(extra, extra_codepoints, sizeof extra);
    stbtt_pack_range ranges[2] = {
        { .font_size = px,
          .first_unicode_codepoint_in_range = 32,
          .num_chars = N_ASCII,
          .chardata_for_range = f->ascii },
        { .font_size = px,
          .array_of_unicode_codepoints = extra,
          .num_chars = N_EXTRA,
          .chardata_for_range = f->extra },
    };
    int ok = stbtt_PackFontRanges(&pc, f->ttf, 0, ranges, 2);
    stbtt_PackEnd(&pc);
    if (!ok) {
        gale_errf(err, GALE_E_RANGE, "%s: glyphs at %g px do not fit a %dx%d atlas", ttf_path,
                  (double)px, f->aw, f->ah);
        goto fail;
    }
    int gi[N_GLYPHS];
    for (int i = 0; i < N_GLYPHS; i++) {
        const int cp = i < N_ASCII ? 32 + i : extra_codepoints[i - N_ASCII];
        gi[i] = stbtt_FindGlyphIndex(&f->info, cp);
    }
    for (int a = 0; a < N_GLYPHS; a++) {
        for (int b = 0; b < N_GLYPHS; b++) {
            f->kern[a][b] = f->scale * (float)stbtt_GetGlyphKernAdvance(&f->info, gi[a], gi[b]);
        }
    }
    return f;
nomem:
    gale_errf(err, GALE_E_NOMEM, "%s: no memory for the font", ttf_path);
fail:
    if (fp) {
        fclose(fp);
    }
    hud_font_unload(f);
    return NULL;
}

void hud_font_unload(hud_font *f)
{
    if (!f) {
        return;
    }
    free(f->ttf);
    free(f->atlas);
    free(f);
}

void hud_font_metrics(const hud_font *f, float *ascent, float *descent, float *line_gap)
{
    *ascent = f->ascent;
    *descent = f->descent;
    *line_gap = f->line_gap;
}

const uint8_t *hud_font_atlas(const hud_font *f, int *w, int *h)
{
    *w = f->aw;
    *h = f->ah;
    return f->atlas;
}

/* Next code point of a UTF-8 string; malformed bytes give '?' and advance one byte. */
static int utf8_next(const unsigned char **s)
{
    const unsigned char *p = *s;
    int c = p[0], n = 0, cp;
    if (c < 0x80) {
        *s = p + 1;
        return c;
    } else if ((c & 0xE0) == 0xC0) {
        n = 1;
        cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
        n = 2;
        cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
        n = 3;
        cp = c & 0x07;
    } else {
        *s = p + 1;
        return '?';
    }
    for (int i = 1; i <= n; i++) {
        if ((p[i] & 0xC0) != 0x80) {
            *s = p + 1;
            return '?';
        }
        cp = (cp << 6) | (p[i] & 0x3F);
    }
    *s = p + n + 1;
    return cp;
}

/* Index of a code point among the baked glyphs (printable ASCII, then the extra ones), that
 * of '?' (the glyph drawn) when it is not baked. */
static int glyph_index(int cp)
{
    if (cp >= 32 && cp < 32 + N_ASCII) {
        return cp - 32;
    }
    for (int i = 0; i < N_EXTRA; i++) {
        if (extra_codepoints[i] == cp) {
            return N_ASCII + i;
        }
    }
    return '?' - 32;
}

bool hud_font_has(const char *utf8)
{
    const unsigned char *s = (const unsigned char *)utf8;
    while (*s) {
        int cp = utf8_next(&s);
        if (cp != '?' && glyph_index(cp) == '?' - 32) {
            return false;
        }
    }
    return true;
}

uint32_t hud_text_quads(const hud_font *f, float x, float y, const char *utf8, hud_quad *q,
                        uint32_t max, float *pen_x)
{
    const unsigned char *s = (const unsigned char *)utf8;
    uint32_t n = 0;
    int prev = -1;
    while (*s) {
        const int gi = glyph_index(utf8_next(&s));
        const stbtt_packedchar *g = gi < N_ASCII ? &f->ascii[gi] : &f->extra[gi - N_ASCII];
        if (prev >= 0) {
            x += f->kern[prev][gi];
        }
        if (gi != ' ' - 32 && n < max && q) {
            /* packed glyph box relative to the pen, in atlas pixels scaled back by the
             * oversampling (stbtt_GetPackedQuad without integer alignment) */
            q[n].x0 = x + g->xoff;
            q[n].y0 = y + g->yoff;
            q[n].x1 = x + g->xoff2;
            q[n].y1 = y + g->yoff2;
            q[n].s0 = (float)g->x0 / (float)f->aw;
            q[n].t0 = (float)g->y0 / (float)f->ah;
            q[n].s1 = (float)g->x1 / (float)f->aw;
            q[n].t1 = (float)g->y1 / (float)f->ah;
            n++;
        }
        x += g->xadvance;
        prev = gi;
    }
    if (pen_x) {
        *pen_x = x;
    }
    return n;
}

float hud_text_width(const hud_font *f, const char *utf8)
{
    float end;
    hud_text_quads(f, 0.0f, 0.0f, utf8, NULL, 0, &end);
    return end;
}

int hud_wrap(const hud_font *f, const char *utf8, float max_w, char lines[][HUD_LINE_CHARS],
             int max_lines)
{
    int n = 0;
    const char *s = utf8;
    while (*s && n < max_lines) {
        while (*s == ' ') {
            s++;
        }
        /* the longest run of whole words that fits; a word alone that does not fit is
         * cut at the line's size */
        size_t best = 0, len = strlen(s);
        char buf[HUD_LINE_CHARS];
        for (size_t i = 0; i <= len && i < HUD_LINE_CHARS; i++) {
            if (s[i] != ' ' && s[i] != '\0') {
                continue;
            }
            memcpy(buf, s, i);
            buf[i] = '\0';
            if (best && hud_text_width(f, buf) > max_w) {
                break;
            }
            best = i;
            if (s[i] == '\0') {
                break;
            }
        }
        if (best == 0) {
            best = len < HUD_LINE_CHARS - 1 ? len : HUD_LINE_CHARS - 1;
            while (best > 0 && ((unsigned char)s[best] & 0xC0) == 0x80) {
                best--; /* not inside a UTF-8 sequence */
            }
        }
        memcpy(lines[n], s, best);
        lines[n][best] = '\0';
        n++;
        s += best;
    }
    return n;
}
