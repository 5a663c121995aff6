/* Client HUD: stb_truetype glyph atlas and layout, the HUD's text (wind in m/s, km/h and
 * mph with the Saffir–Simpson class or Beaufort force of protocol/wind_scale.h,
 * connection, fps, latency) and a GL 3.3 overlay pass of alpha-blended quads. */
#include <epoxy/gl.h>

#include "hud.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_truetype.h>

#include "wind_scale.h"

/* atlas side for an em of up to 40 px; each doubling of the em doubles both sides, so a
 * HUD sized for a 4K screen (about 44 px) fits */
#define ATLAS_W    1024
#define ATLAS_H    512
#define OVERSAMPLE 2

static const int extra_codepoints[] = { 0x00B0, 0x00B7, 0x00B1, 0x2013, 0x2014, 0x2026,
                                        0x00D7 };
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

/* ---- content ------------------------------------------------------------------------ */

int hud_saffir_simpson(float speed_ms)
{
    /* the HUD counts from tropical storm = 0, so a hurricane's number is its category */
    return wind_scale_ss_class((double)speed_ms) - 1;
}

const char *hud_category_name(int cls)
{
    return cls >= -1 && cls < WIND_SCALE_SS_COUNT - 1 ? wind_scale_ss_title(cls + 1) : "?";
}

int hud_beaufort(float speed_ms)
{
    return wind_scale_beaufort((double)speed_ms);
}

const char *hud_beaufort_name(int force)
{
    return wind_scale_beaufort_title(force);
}

const char *hud_compass_point(float bearing_deg)
{
    static const char *const pts[16] = { "N", "NNE", "NE", "ENE", "E", "ESE", "SE", "SSE",
                                         "S", "SSW", "SW", "WSW", "W", "WNW", "NW", "NNW" };
    if (!isfinite(bearing_deg)) {
        return "?";
    }
    double b = fmod((double)bearing_deg, 360.0);
    b = b < 0.0 ? b + 360.0 : b;
    return pts[(int)floor(b / 22.5 + 0.5) % 16];
}

/* "HH:MM" of minutes since the epoch (UTC) plus an offset, and its date "YYYY-MM-DD". */
static void civil(long long min, char *date, size_t dcap, char *hm, size_t hcap)
{
    long long days = min >= 0 ? min / 1440 : -((-min + 1439) / 1440);
    long long rem = min - days * 1440;
    /* days since 1970-01-01 → civil date (Hinnant's days_from_civil inverse) */
    long long z = days + 719468;
    long long era = (z >= 0 ? z : z - 146096) / 146097;
    long long doe = z - era * 146097;
    long long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    long long y = yoe + era * 400, doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    long long mp = (5 * doy + 2) / 153, d = doy - (153 * mp + 2) / 5 + 1;
    long long m = mp < 10 ? mp + 3 : mp - 9;
    y += m <= 2;
    snprintf(date, dcap, "%04lld-%02lld-%02lld", y, m, d);
    snprintf(hm, hcap, "%02lld:%02lld", rem / 60, rem % 60);
}

/* The lines of the server's weather: wind, class, direction, and a replay's storm. */
static int format_weather(const wire_weather *w, char lines[HUD_MAX_LINES][HUD_LINE_CHARS])
{
    int n = 0;
    double v = (double)w->sustained_ms;
    snprintf(lines[n++], HUD_LINE_CHARS,
             "Wind %.1f m/s \xC2\xB7 %.0f km/h \xC2\xB7 %.0f mph \xC2\xB7 gusts %.0f m/s", v,
             v * 3.6, v / 0.44704, (double)w->gust_ms);
    int cls = (int)w->ss_class; /* the server's class (wind_scale.h numbering) */
    if (cls >= WIND_SCALE_TS) {
        snprintf(lines[n++], HUD_LINE_CHARS, "%s", wind_scale_ss_title(cls));
    } else {
        snprintf(lines[n++], HUD_LINE_CHARS, "%s \xC2\xB7 Beaufort %d",
                 wind_scale_beaufort_title(w->beaufort), (int)w->beaufort);
    }
    snprintf(lines[n++], HUD_LINE_CHARS, "From the %s (%.0f\xC2\xB0)%s",
             hud_compass_point(w->dir_from_deg), (double)w->dir_from_deg,
             (w->flags & WIRE_WEATHER_DIAL) ? " \xC2\xB7 dialled at the kiosk" : "");
    if (w->flags & WIRE_WEATHER_STORM) {
        char clock[96] = "";
        if (w->flags & WIRE_WEATHER_CLOCK) {
            char d[32], hm[24], ld[32], lhm[24];
            civil((long long)w->utc_min, d, sizeof d, hm, sizeof hm);
            civil((long long)w->utc_min + w->utc_offset_min, ld, sizeof ld, lhm, sizeof lhm);
            snprintf(clock, sizeof clock, " \xC2\xB7 %s %s UTC (%s local)", d, hm, lhm);
        }
        snprintf(lines[n++], HUD_LINE_CHARS, "%s%s", w->name[0] ? w->name : "Storm", clock);
        snprintf(lines[n++], HUD_LINE_CHARS,
                 "Eye %.0f km %s \xC2\xB7 %.0f hPa \xC2\xB7 storm %s",
                 (double)w->distance_km, hud_compass_point(w->bearing_deg),
                 (double)w->central_hpa,
                 w->storm_class < WIND_SCALE_SS_COUNT ? wind_scale_ss_abbrev(w->storm_class) : "?");
        int pos = (int)w->replay_pos_s, len = (int)w->replay_len_s;
        if (len > 0) {
            snprintf(lines[n++], HUD_LINE_CHARS, "Replay %d:%02d / %d:%02d \xC2\xB7 \xC3\x97%.0f%s",
                     pos / 60, pos % 60, len / 60, len % 60, (double)w->replay_speed,
                     (w->flags & WIRE_WEATHER_FINISHED) ? " \xC2\xB7 ended" : "");
        } else {
            snprintf(lines[n++], HUD_LINE_CHARS, "Replay %d:%02d \xC2\xB7 \xC3\x97%.0f (looping)",
                     pos / 60, pos % 60, (double)w->replay_speed);
        }
    } else if (w->name[0] && !(w->flags & WIRE_WEATHER_DIAL)) {
        /* a dial overrides a steady scenario: its title would contradict the wind above */
        snprintf(lines[n++], HUD_LINE_CHARS, "%s", w->name);
    }
    return n;
}

int hud_format(const hud_state *s, char lines[HUD_MAX_LINES][HUD_LINE_CHARS])
{
    int n = 0;
    if (s->wx) {
        n = format_weather(s->wx, lines);
    } else if (s->have_wind) {
        float v = s->wind_ms;
        snprintf(lines[n++], HUD_LINE_CHARS, "Wind %.1f m/s \xC2\xB7 %.0f km/h \xC2\xB7 %.0f mph",
                 (double)v, (double)v * 3.6, (double)v / 0.44704);
        int cls = hud_saffir_simpson(v);
        if (cls >= 0) {
            snprintf(lines[n++], HUD_LINE_CHARS, "%s", hud_category_name(cls));
        } else {
            int b = hud_beaufort(v);
            snprintf(lines[n++], HUD_LINE_CHARS, "%s \xC2\xB7 Beaufort %d", hud_beaufort_name(b), b);
        }
    } else {
        snprintf(lines[n++], HUD_LINE_CHARS, "Wind \xE2\x80\x93 (no wind data yet)");
    }
    const char *srv = s->server ? s->server : "";
    switch (s->conn) {
    case HUD_CONN_LIVE:
        snprintf(lines[n++], HUD_LINE_CHARS, "Live \xC2\xB7 %s \xC2\xB7 %s", srv,
                 s->role ? s->role : "viewer");
        break;
    case HUD_CONN_WAIT_KEY:
        snprintf(lines[n++], HUD_LINE_CHARS,
                 "Connected \xC2\xB7 %s \xC2\xB7 waiting for a keyframe", srv);
        break;
    case HUD_CONN_RECONNECTING:
        snprintf(lines[n++], HUD_LINE_CHARS,
                 "Server lost \xC2\xB7 retry %u in %.1f s \xC2\xB7 showing last state", s->attempt,
                 s->retry_in_s);
        break;
    case HUD_CONN_FAILED:
        snprintf(lines[n++], HUD_LINE_CHARS, "Disconnected \xC2\xB7 %s", srv);
        break;
    default:
        snprintf(lines[n++], HUD_LINE_CHARS, "Connecting to %s\xE2\x80\xA6", srv);
        break;
    }
    char lat[48];
    if (s->latency_ms >= 0.0f) {
        snprintf(lat, sizeof lat, "%.1f ms", (double)s->latency_ms);
    } else {
        snprintf(lat, sizeof lat, "\xE2\x80\x93");
    }
    /* no rate before the first half-second window closes (a headless frame saved at once) */
    char fps[24];
    if (s->fps > 0.0f) {
        snprintf(fps, sizeof fps, "%.0f", (double)s->fps);
    } else {
        snprintf(fps, sizeof fps, "\xE2\x80\x93");
    }
    snprintf(lines[n++], HUD_LINE_CHARS, "%s fps \xC2\xB7 latency %s \xC2\xB7 delay %.0f ms", fps,
             lat, (double)s->delay_ms);
    if (s->frames_bad) {
        snprintf(lines[n++], HUD_LINE_CHARS, "%llu bad frames dropped",
                 (unsigned long long)s->frames_bad);
    }
    return n;
}

/* ---- GL pass ------------------------------------------------------------------------ */

#define VERT_FLOATS   8 /* x y s t r g b a; s < 0: solid colour */
#define HUD_MAX_VERTS (6 * (HUD_MAX_GLYPHS + 16))
#define HUD_LAYERS    2 /* kept pictures: the HUD's lines and a kiosk panel (one hud draws both) */

/* A kept batch (hud_batch_flush_keep): its picture rendered into an offscreen buffer the
 * size of its bounding box, copied into a texture, then drawn each frame as one quad. On a
 * software rasteriser (llvmpipe) a draw's vertex shading, setup and binning run on the
 * caller's thread, about 0.1 us a vertex, so one quad instead of the ~3,000 vertices of a
 * kiosk panel keeps that off the frame.
 * - The texture is a copy (layer_copy) rather than the render target itself: llvmpipe
 *   makes a draw that samples a texture ever rendered to wait until everything drawn before
 *   it is rasterised (0.5-1 ms measured with the HUD and the panel).
 * - The copy waits for the offscreen picture to be rasterised, so it is made a frame later:
 *   a picture built for the first time is drawn straight; built again with the same key (it
 *   held still for a frame) it is also rendered offscreen; the next replay copies it and
 *   from then on draws the quad. A picture that changes every frame (a finger on the dial)
 *   is drawn straight every frame, as without keeping.
 * The texture holds premultiplied colour (the batch blended over transparent black, alpha by
 * ONE, ONE_MINUS_SRC_ALPHA), so drawing it with ONE, ONE_MINUS_SRC_ALPHA gives the batch
 * drawn straight onto the frame, to 8-bit rounding. */
typedef struct hud_layer {
    uint64_t key;     /* 0: none */
    bool ready;       /* the texture holds the picture (else only the offscreen buffer) */
    uint32_t used;    /* stamp of its last draw: a new picture replaces the older layer */
    int fb_w, fb_h;   /* framebuffer it was built for */
    int x0, y0, w, h; /* its box on that framebuffer [px, y down]; w or h 0: empty */
    int cap_w, cap_h; /* size of the buffers below [px] */
    GLuint fbo, rb;   /* where the batch is rendered */
    GLuint tex;       /* the picture drawn (never a render target) */
    GLuint vao, vbo;  /* its quad */
    uint8_t *pixels;  /* owned: cap_w x cap_h RGBA, the copy through memory (layer_copy) */
} hud_layer;

struct hud {
    hud_font *font; /* owned */
    GLuint prog, vao, vbo, tex;
    GLint u_size, u_atlas, u_origin, u_layer;
    float verts[HUD_MAX_VERTS * VERT_FLOATS];
    uint32_t n_verts;
    hud_quad quads[HUD_MAX_GLYPHS];
    int batch_w, batch_h; /* framebuffer of the batch (hud_batch_begin) */
    bool batch_spilled;   /* the batch was drawn in parts (too many vertices to keep) */
    hud_layer layer[HUD_LAYERS];
    uint32_t stamp;              /* layer draws so far */
    uint64_t built[HUD_LAYERS];  /* keys of the last batches built (hud_batch_flush_keep) */
    bool copy_image;             /* glCopyImageSubData is there (GL 4.3, ARB_copy_image) */
    uint32_t built_next;         /* the entry of built the next new key replaces */
    /* the lines of the HUD picture hud_draw drew last (hud_drawn_lines) */
    char drawn[HUD_MAX_LINES][HUD_LINE_CHARS];
    int n_drawn;
};

static const char *hud_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec2 a_pos;\n"
    "layout(location = 1) in vec2 a_st;\n"
    "layout(location = 2) in vec4 a_rgba;\n"
    "uniform vec2 u_size;\n"
    "uniform vec2 u_origin;\n"
    "out vec2 v_st;\n"
    "out vec4 v_rgba;\n"
    "void main() {\n"
    "    vec2 p = a_pos - u_origin;\n"
    "    v_st = a_st;\n"
    "    v_rgba = a_rgba;\n"
    "    gl_Position = vec4(p.x / u_size.x * 2.0 - 1.0, 1.0 - p.y / u_size.y * 2.0, 0.0, 1.0);\n"
    "}\n";

static const char *hud_fs = "#version 330 core\n"
                            "in vec2 v_st;\n"
                            "in vec4 v_rgba;\n"
                            "uniform sampler2D u_atlas;\n"
                            "uniform int u_layer;\n"
                            "out vec4 o_color;\n"
                            "void main() {\n"
                            "    if (u_layer != 0) {\n"
                            "        o_color = texture(u_atlas, v_st);\n"
                            "        return;\n"
                            "    }\n"
                            "    float cov = v_st.x < 0.0 ? 1.0 : texture(u_atlas, v_st).r;\n"
                            "    o_color = vec4(v_rgba.rgb, v_rgba.a * cov);\n"
                            "}\n";

static GLuint compile(GLenum type, const char *src, gale_err *err)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[200];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        gale_errf(err, GALE_E_STATE, "hud %s shader: %s",
                  type == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

/* The vertex layout (x y s t r g b a) on the bound vertex array and array buffer. */
static void vert_attribs(void)
{
    const GLsizei stride = VERT_FLOATS * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, stride, (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride, (void *)(2 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, (void *)(4 * sizeof(float)));
}

hud *hud_create(const hud_desc *d, gale_err *err)
{
    hud_desc r = d ? *d : (hud_desc){ 0 };
    if (!r.font_path) {
        r.font_path = HUD_DEFAULT_FONT;
    }
    if (r.px == 0.0f) {
        r.px = 18.0f;
    }
    hud *h = calloc(1, sizeof *h);
    if (!h) {
        gale_errf(err, GALE_E_NOMEM, "hud: no memory");
        return NULL;
    }
    h->font = hud_font_load(r.font_path, r.px, err);
    if (!h->font) {
        free(h);
        return NULL;
    }
    GLuint vs = compile(GL_VERTEX_SHADER, hud_vs, err);
    GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, hud_fs, err) : 0;
    if (!vs || !fs) {
        if (vs) {
            glDeleteShader(vs);
        }
        hud_destroy(h);
        return NULL;
    }
    h->prog = glCreateProgram();
    glAttachShader(h->prog, vs);
    glAttachShader(h->prog, fs);
    glLinkProgram(h->prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(h->prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        gale_errf(err, GALE_E_STATE, "hud shader program does not link");
        hud_destroy(h);
        return NULL;
    }
    h->u_size = glGetUniformLocation(h->prog, "u_size");
    h->u_atlas = glGetUniformLocation(h->prog, "u_atlas");
    h->u_origin = glGetUniformLocation(h->prog, "u_origin");
    h->u_layer = glGetUniformLocation(h->prog, "u_layer");
    h->copy_image = epoxy_gl_version() >= 43 || epoxy_has_gl_extension("GL_ARB_copy_image");

    int aw, ah;
    const uint8_t *atlas = hud_font_atlas(h->font, &aw, &ah);
    glGenTextures(1, &h->tex);
    glBindTexture(GL_TEXTURE_2D, h->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, aw, ah, 0, GL_RED, GL_UNSIGNED_BYTE, atlas);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

    glGenVertexArrays(1, &h->vao);
    glGenBuffers(1, &h->vbo);
    glBindVertexArray(h->vao);
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof h->verts, NULL, GL_STREAM_DRAW);
    vert_attribs();
    glBindVertexArray(0);
    return h;
}

void hud_destroy(hud *h)
{
    if (!h) {
        return;
    }
    if (h->prog) {
        glDeleteProgram(h->prog);
    }
    if (h->vbo) {
        glDeleteBuffers(1, &h->vbo);
    }
    if (h->vao) {
        glDeleteVertexArrays(1, &h->vao);
    }
    for (int i = 0; i < HUD_LAYERS; i++) {
        hud_layer *L = &h->layer[i];
        if (L->fbo) {
            glDeleteFramebuffers(1, &L->fbo);
        }
        if (L->rb) {
            glDeleteRenderbuffers(1, &L->rb);
        }
        free(L->pixels);
        if (L->tex) {
            glDeleteTextures(1, &L->tex);
        }
        if (L->vbo) {
            glDeleteBuffers(1, &L->vbo);
        }
        if (L->vao) {
            glDeleteVertexArrays(1, &L->vao);
        }
    }
    if (h->tex) {
        glDeleteTextures(1, &h->tex);
    }
    hud_font_unload(h->font);
    free(h);
}

const hud_font *hud_get_font(const hud *h)
{
    return h->font;
}

static void push_rect(hud *h, float x0, float y0, float x1, float y1, float s0, float t0, float s1,
                      float t1, const float rgba[4])
{
    if (h->n_verts + 6 > HUD_MAX_VERTS) {
        return;
    }
    const float c[6][4] = { { x0, y0, s0, t0 }, { x1, y0, s1, t0 }, { x1, y1, s1, t1 },
                            { x0, y0, s0, t0 }, { x1, y1, s1, t1 }, { x0, y1, s0, t1 } };
    for (int i = 0; i < 6; i++) {
        float *v = h->verts + (size_t)h->n_verts * VERT_FLOATS;
        v[0] = c[i][0];
        v[1] = c[i][1];
        v[2] = c[i][2];
        v[3] = c[i][3];
        memcpy(v + 4, rgba, 4 * sizeof(float));
        h->n_verts++;
    }
}

static void push_text(hud *h, float x, float y, const char *s, const float rgba[4])
{
    uint32_t n = hud_text_quads(h->font, x, y, s, h->quads, HUD_MAX_GLYPHS, NULL);
    for (uint32_t i = 0; i < n; i++) {
        const hud_quad *q = &h->quads[i];
        push_rect(h, q->x0, q->y0, q->x1, q->y1, q->s0, q->t0, q->s1, q->t1, rgba);
    }
}

/* The HUD program, atlas and blending over the bound framebuffer of fb_w x fb_h pixels
 * (whose top left is the point (x0, y0) of the vertices [px]). */
static void batch_state_at(hud *h, int fb_w, int fb_h, int x0, int y0)
{
    glUseProgram(h->prog);
    glUniform2f(h->u_size, (float)fb_w, (float)fb_h);
    glUniform2f(h->u_origin, (float)x0, (float)y0);
    glUniform1i(h->u_layer, 0);
    glUniform1i(h->u_atlas, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, h->tex);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glViewport(0, 0, fb_w, fb_h);
}

static void batch_state(hud *h, int fb_w, int fb_h)
{
    batch_state_at(h, fb_w, fb_h, 0, 0);
}

/* Uploads and draws the vertices pushed since n_verts was reset, in the state batch_state
 * or batch_state_at set. */
static void draw_verts(hud *h)
{
    glBindVertexArray(h->vao);
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0,
                    (GLsizeiptr)((size_t)h->n_verts * VERT_FLOATS * sizeof(float)), h->verts);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)h->n_verts);
    glBindVertexArray(0);
    glUseProgram(0);
}

/* Uploads and draws the vertices pushed since n_verts was reset, over the bound framebuffer. */
static void flush_verts(hud *h, int fb_w, int fb_h)
{
    batch_state(h, fb_w, fb_h);
    draw_verts(h);
}

/* Pushes the panel of hud_draw_lines (below) onto the batch. */
static void push_lines(hud *h, const char *const *lines, int n, int accent_line, float x, float y)
{
    const float pad = 0.6f * h->font->px;
    const float line_h =
        h->font->ascent - h->font->descent + h->font->line_gap + 0.25f * h->font->px;
    float w = 0.0f;
    for (int i = 0; i < n; i++) {
        w = fmaxf(w, hud_text_width(h->font, lines[i]));
    }
    const float panel[4] = { 0.05f, 0.07f, 0.10f, 0.62f };
    const float shadow[4] = { 0.0f, 0.0f, 0.0f, 0.85f };
    const float ink[4] = { 0.97f, 0.97f, 0.93f, 1.0f };
    const float accent[4] = { 1.0f, 0.80f, 0.30f, 1.0f };
    push_rect(h, x, y, x + w + 2 * pad, y + n * line_h - 0.25f * h->font->px + 2 * pad, -1, 0, -1,
              0, panel);
    for (int i = 0; i < n; i++) {
        float bx = floorf(x + pad), by = floorf(y + pad + h->font->ascent + i * line_h);
        push_text(h, bx + 1, by + 1, lines[i], shadow);
        push_text(h, bx, by, lines[i], i == accent_line ? accent : ink);
    }
}

void hud_draw_lines(hud *h, const char *const *lines, int n, int accent_line, float x, float y,
                    int fb_w, int fb_h)
{
    if (fb_w <= 0 || fb_h <= 0 || n <= 0) {
        return;
    }
    h->n_verts = 0;
    push_lines(h, lines, n, accent_line, x, y);
    flush_verts(h, fb_w, fb_h);
}

static void push_tri(hud *h, const float p[6], const float rgba[4])
{
    if (h->n_verts + 3 > HUD_MAX_VERTS) {
        return;
    }
    for (int i = 0; i < 3; i++) {
        float *v = h->verts + (size_t)h->n_verts * VERT_FLOATS;
        v[0] = p[2 * i];
        v[1] = p[2 * i + 1];
        v[2] = -1.0f;
        v[3] = 0.0f;
        memcpy(v + 4, rgba, 4 * sizeof(float));
        h->n_verts++;
    }
}

/* The wind arrow in the top-right corner: a disc-like panel and an arrow pointing where the
 * wind blows (downwind), relative to the view, longer with the class. */
static void draw_arrow(hud *h, const hud_state *s, int fb_w, int fb_h)
{
    const float r = 2.6f * h->font->px, margin = 0.8f * h->font->px;
    const float cx = (float)fb_w - margin - r, cy = margin + r;
    const float panel[4] = { 0.05f, 0.07f, 0.10f, 0.62f };
    const float ink[4] = { 1.0f, 0.80f, 0.30f, 1.0f };
    h->n_verts = 0;
    /* a 16-gon panel */
    for (int i = 0; i < 16; i++) {
        float a0 = (float)i * 0.3926991f, a1 = (float)(i + 1) * 0.3926991f;
        const float t[6] = { cx, cy, cx + r * cosf(a0), cy + r * sinf(a0), cx + r * cosf(a1),
                             cy + r * sinf(a1) };
        push_tri(h, t, panel);
    }
    /* downwind bearing relative to the view; screen: up = ahead, y down */
    float rel = (s->wx->dir_from_deg + 180.0f - s->view_heading_deg) * 0.017453292f;
    float ux = sinf(rel), uy = -cosf(rel); /* unit along the arrow on screen */
    float px = -uy, py = ux;               /* across it */
    float len = r * (0.55f + 0.06f * (float)s->wx->ss_class), half = 0.22f * r;
    const float head[6] = { cx + ux * len, cy + uy * len, cx - ux * 0.1f * r + px * half,
                            cy - uy * 0.1f * r + py * half, cx - ux * 0.1f * r - px * half,
                            cy - uy * 0.1f * r - py * half };
    const float w = 0.08f * r;
    const float q0[6] = { cx + px * w, cy + py * w, cx - ux * len + px * w, cy - uy * len + py * w,
                          cx - ux * len - px * w, cy - uy * len - py * w };
    const float q1[6] = { cx + px * w, cy + py * w, cx - ux * len - px * w, cy - uy * len - py * w,
                          cx - px * w, cy - py * w };
    push_tri(h, head, ink);
    push_tri(h, q0, ink);
    push_tri(h, q1, ink);
    flush_verts(h, fb_w, fb_h);
}

/* Key of the HUD's lines panel (FNV-1a over what it depends on): the same key, the same
 * picture. */
static uint64_t lines_key(char lines[HUD_MAX_LINES][HUD_LINE_CHARS], int n, int accent,
                          int fb_w, int fb_h)
{
    const int32_t v[4] = { n, accent, fb_w, fb_h };
    uint64_t k = 14695981039346656037ull;
    for (size_t i = 0; i < sizeof v; i++) {
        k = (k ^ ((const unsigned char *)v)[i]) * 1099511628211ull;
    }
    for (int i = 0; i < n; i++) {
        for (const unsigned char *c = (const unsigned char *)lines[i];; c++) {
            k = (k ^ *c) * 1099511628211ull; /* the NUL too: it ends the line */
            if (!*c) {
                break;
            }
        }
    }
    return k | 1u; /* never 0, which keeps nothing */
}

void hud_draw(hud *h, const hud_state *s, int fb_w, int fb_h)
{
    if (fb_w <= 0 || fb_h <= 0) {
        return;
    }
    /* the arrow follows the camera every frame: drawn as it is (19 triangles) */
    if (s->wx) {
        draw_arrow(h, s, fb_w, fb_h);
    }
    /* the lines change a few times a second (WEATHER, fps, latency): built into a kept
     * layer when they do, that layer drawn otherwise */
    char lines[HUD_MAX_LINES][HUD_LINE_CHARS];
    int n = hud_format(s, lines);
    if (n <= 0) {
        h->n_drawn = 0;
        return;
    }
    const int accent = s->have_wind || s->wx ? 1 : -1;
    const uint64_t key = lines_key(lines, n, accent, fb_w, fb_h);
    if (hud_batch_replay(h, key, fb_w, fb_h)) {
        return;
    }
    const char *ptrs[HUD_MAX_LINES];
    for (int i = 0; i < n; i++) {
        ptrs[i] = lines[i];
        memcpy(h->drawn[i], lines[i], HUD_LINE_CHARS);
    }
    h->n_drawn = n;
    const float margin = 0.8f * h->font->px;
    hud_batch_begin(h, fb_w, fb_h);
    push_lines(h, ptrs, n, accent, margin, margin);
    hud_batch_flush_keep(h, key);
}

int hud_drawn_lines(const hud *h, char lines[HUD_MAX_LINES][HUD_LINE_CHARS])
{
    memcpy(lines, h->drawn, (size_t)h->n_drawn * HUD_LINE_CHARS);
    return h->n_drawn;
}

void hud_draw_veil(hud *h, const char *text, int fb_w, int fb_h)
{
    if (fb_w <= 0 || fb_h <= 0) {
        return;
    }
    const float veil[4] = { 0.02f, 0.03f, 0.05f, 0.55f };
    h->n_verts = 0;
    push_rect(h, 0.0f, 0.0f, (float)fb_w, (float)fb_h, -1, 0, -1, 0, veil);
    flush_verts(h, fb_w, fb_h);
    const float w = hud_text_width(h->font, text) + 1.2f * h->font->px;
    const char *lines[1] = { text };
    hud_draw_lines(h, lines, 1, 0, floorf(0.5f * ((float)fb_w - w)),
                   floorf(0.5f * (float)fb_h - h->font->px), fb_w, fb_h);
}


void hud_draw_button(hud *h, const char *label, float x0, float y0, float x1, float y1, int fb_w,
                     int fb_h)
{
    if (fb_w <= 0 || fb_h <= 0 || !(x1 > x0 && y1 > y0)) {
        return;
    }
    const float panel[4] = { 0.05f, 0.07f, 0.10f, 0.72f };
    const float edge[4] = { 1.0f, 0.80f, 0.30f, 0.9f };
    const float shadow[4] = { 0.0f, 0.0f, 0.0f, 0.85f };
    const float ink[4] = { 0.97f, 0.97f, 0.93f, 1.0f };
    const float bh = y1 - y0, t = fmaxf(2.0f, floorf(0.04f * bh));
    h->n_verts = 0;
    push_rect(h, x0, y0, x1, y1, -1, 0, -1, 0, panel);
    push_rect(h, x0, y0, x1, y0 + t, -1, 0, -1, 0, edge);
    push_rect(h, x0, y1 - t, x1, y1, -1, 0, -1, 0, edge);
    push_rect(h, x0, y0, x0 + t, y1, -1, 0, -1, 0, edge);
    push_rect(h, x1 - t, y0, x1, y1, -1, 0, -1, 0, edge);
    /* the atlas's glyphs magnified so the label's em is ~40 % of the button's height, as
     * the button itself scales with the framebuffer (camera_button.h) */
    const float em = h->font->ascent - h->font->descent;
    const float k = em > 0.0f ? 0.42f * bh / em : 1.0f;
    const float tw = k * hud_text_width(h->font, label);
    const float ox = floorf(0.5f * (x0 + x1 - tw));
    const float oy = floorf(0.5f * (y0 + y1) + 0.5f * k * (h->font->ascent + h->font->descent));
    uint32_t n = hud_text_quads(h->font, 0.0f, 0.0f, label, h->quads, HUD_MAX_GLYPHS, NULL);
    for (int pass = 0; pass < 2; pass++) {
        const float d = pass == 0 ? fmaxf(1.0f, floorf(k)) : 0.0f; /* shadow, then ink */
        for (uint32_t i = 0; i < n; i++) {
            const hud_quad *q = &h->quads[i];
            push_rect(h, ox + d + k * q->x0, oy + d + k * q->y0, ox + d + k * q->x1,
                      oy + d + k * q->y1, q->s0, q->t0, q->s1, q->t1, pass == 0 ? shadow : ink);
        }
    }
    flush_verts(h, fb_w, fb_h);
}

/* ---- batches for other panels --------------------------------------------------------- */

void hud_batch_begin(hud *h, int fb_w, int fb_h)
{
    h->n_verts = 0;
    h->batch_w = fb_w;
    h->batch_h = fb_h;
    h->batch_spilled = false;
}

void hud_batch_flush(hud *h)
{
    if (h->n_verts > 0 && h->batch_w > 0 && h->batch_h > 0) {
        flush_verts(h, h->batch_w, h->batch_h);
    }
    h->n_verts = 0;
}

/* Room for n more vertices, drawing what the batch holds when it lacks it. */
static void batch_room(hud *h, uint32_t n)
{
    if (h->n_verts + n > HUD_MAX_VERTS) {
        hud_batch_flush(h);
        h->batch_spilled = true;
    }
}


/* Draws a layer's quad over the bound framebuffer. */
static void draw_layer(hud *h, hud_layer *L)
{
    L->used = ++h->stamp;
    if (L->w <= 0 || L->h <= 0) {
        return;
    }
    batch_state(h, L->fb_w, L->fb_h);
    glUniform1i(h->u_layer, 1);
    glBindTexture(GL_TEXTURE_2D, L->tex);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied (hud_layer) */
    glBindVertexArray(L->vao);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glBindVertexArray(0);
    glUseProgram(0);
}

/* Room in L's buffers for its box: false when they cannot be made. Grows them (the only
 * allocation, when a picture is larger than any before it). */
static bool layer_room(hud_layer *L)
{
    if (!L->fbo) {
        glGenFramebuffers(1, &L->fbo);
        glGenRenderbuffers(1, &L->rb);
        glGenTextures(1, &L->tex);
        glGenVertexArrays(1, &L->vao);
        glGenBuffers(1, &L->vbo);
        glBindVertexArray(L->vao);
        glBindBuffer(GL_ARRAY_BUFFER, L->vbo);
        glBufferData(GL_ARRAY_BUFFER, 6 * VERT_FLOATS * sizeof(float), NULL, GL_DYNAMIC_DRAW);
        vert_attribs();
        glBindVertexArray(0);
    }
    if (L->w <= L->cap_w && L->h <= L->cap_h) {
        return true;
    }
    /* grown, never shrunk: a panel's box changes with what it shows */
    int cw = L->w > L->cap_w ? L->w : L->cap_w, ch = L->h > L->cap_h ? L->h : L->cap_h;
    uint8_t *px = realloc(L->pixels, (size_t)cw * (size_t)ch * 4);
    if (!px) {
        return false;
    }
    L->pixels = px;
    L->cap_w = cw;
    L->cap_h = ch;
    glBindTexture(GL_TEXTURE_2D, L->tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, cw, ch, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    /* texel for pixel: the quad lies on whole pixels */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindRenderbuffer(GL_RENDERBUFFER, L->rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, cw, ch);
    GLint prev = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, L->fbo);
    glFramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, L->rb);
    bool ok = glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev);
    if (!ok) {
        L->cap_w = L->cap_h = 0;
    }
    return ok;
}

/* Renders the batch into L's offscreen buffer (its box clipped to the framebuffer); the
 * batch is left as it is. */
static bool layer_render(hud *h, hud_layer *L)
{
    float bx0 = (float)h->batch_w, by0 = (float)h->batch_h, bx1 = 0.0f, by1 = 0.0f;
    for (uint32_t i = 0; i < h->n_verts; i++) {
        const float *v = h->verts + (size_t)i * VERT_FLOATS;
        bx0 = fminf(bx0, v[0]);
        by0 = fminf(by0, v[1]);
        bx1 = fmaxf(bx1, v[0]);
        by1 = fmaxf(by1, v[1]);
    }
    int x0 = (int)fmaxf(floorf(bx0), 0.0f), y0 = (int)fmaxf(floorf(by0), 0.0f);
    int x1 = (int)fminf(ceilf(bx1), (float)h->batch_w);
    int y1 = (int)fminf(ceilf(by1), (float)h->batch_h);
    L->fb_w = h->batch_w;
    L->fb_h = h->batch_h;
    L->x0 = x0;
    L->y0 = y0;
    L->w = x1 > x0 ? x1 - x0 : 0;
    L->h = y1 > y0 ? y1 - y0 : 0;
    if (L->w == 0 || L->h == 0) {
        return true;
    }
    if (!layer_room(L)) {
        return false;
    }
    GLint prev = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev);
    GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, L->fbo);
    glDisable(GL_SCISSOR_TEST);
    const GLfloat clear[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    glClearBufferfv(GL_COLOR, 0, clear);
    batch_state_at(h, L->w, L->h, x0, y0);
    draw_verts(h);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev);
    if (scissor) {
        glEnable(GL_SCISSOR_TEST);
    }
    /* the quad: the texture's row 0 is the box's bottom */
    const float fx0 = (float)x0, fy0 = (float)y0, fx1 = (float)x1, fy1 = (float)y1;
    const float s1 = (float)L->w / (float)L->cap_w, t1 = (float)L->h / (float)L->cap_h;
    const float q[6][4] = { { fx0, fy0, 0, t1 }, { fx1, fy0, s1, t1 }, { fx1, fy1, s1, 0 },
                            { fx0, fy0, 0, t1 }, { fx1, fy1, s1, 0 },  { fx0, fy1, 0, 0 } };
    float v[6 * VERT_FLOATS] = { 0 };
    for (int i = 0; i < 6; i++) {
        memcpy(v + i * VERT_FLOATS, q[i], sizeof q[i]);
    }
    glBindBuffer(GL_ARRAY_BUFFER, L->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)sizeof v, v);
    return true;
}

/* Copies L's offscreen picture into its texture: within the driver where GL 4.3's image copy
 * is there (llvmpipe: a memory copy, 0.05-0.4 ms for the HUD and the panel), else through
 * memory (RGBA rows are whole words: any alignment reads them). */
static void layer_copy(const hud *h, hud_layer *L)
{
    if (L->w > 0 && L->h > 0 && h->copy_image) {
        glCopyImageSubData(L->rb, GL_RENDERBUFFER, 0, 0, 0, 0, L->tex, GL_TEXTURE_2D, 0, 0, 0,
                           0, L->w, L->h, 1);
    } else if (L->w > 0 && L->h > 0) {
        GLint prev_read = 0;
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, L->fbo);
        glReadPixels(0, 0, L->w, L->h, GL_RGBA, GL_UNSIGNED_BYTE, L->pixels);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_read);
        glBindTexture(GL_TEXTURE_2D, L->tex);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, L->w, L->h, GL_RGBA, GL_UNSIGNED_BYTE,
                        L->pixels);
    }
    L->ready = true;
}

void hud_batch_flush_keep(hud *h, uint64_t key)
{
    if (h->batch_spilled || key == 0 || h->batch_w <= 0 || h->batch_h <= 0) {
        hud_batch_flush(h);
        return;
    }
    bool again = false;
    for (int i = 0; i < HUD_LAYERS; i++) {
        again |= h->built[i] == key;
    }
    if (!again) {
        h->built[h->built_next] = key;
        h->built_next = (h->built_next + 1) % HUD_LAYERS;
    } else {
        /* held still for a frame: into the layer under this key, else the one drawn longest
         * ago */
        hud_layer *L = &h->layer[0];
        for (int i = 0; i < HUD_LAYERS; i++) {
            if (h->layer[i].key == key) {
                L = &h->layer[i];
                break;
            }
            if (h->layer[i].used < L->used) {
                L = &h->layer[i];
            }
        }
        L->key = 0;
        L->ready = false;
        L->used = ++h->stamp;
        if (layer_render(h, L)) {
            L->key = key;
        }
    }
    hud_batch_flush(h); /* this frame: drawn straight */
}

bool hud_batch_replay(hud *h, uint64_t key, int fb_w, int fb_h)
{
    for (int i = 0; key != 0 && i < HUD_LAYERS; i++) {
        hud_layer *L = &h->layer[i];
        if (L->key == key && L->fb_w == fb_w && L->fb_h == fb_h) {
            if (!L->ready) {
                layer_copy(h, L);
            }
            draw_layer(h, L);
            return true;
        }
    }
    return false;
}

void hud_batch_rect(hud *h, float x0, float y0, float x1, float y1, const float rgba[4])
{
    batch_room(h, 6);
    push_rect(h, x0, y0, x1, y1, -1, 0, -1, 0, rgba);
}

void hud_batch_tri(hud *h, const float xy[6], const float rgba[4])
{
    batch_room(h, 3);
    push_tri(h, xy, rgba);
}

float hud_batch_text(hud *h, float x, float y, float px, const char *utf8, const float rgba[4],
                     float align, const float *shadow_rgba)
{
    const float k = px / h->font->px;
    float end = 0.0f;
    uint32_t n = hud_text_quads(h->font, 0.0f, 0.0f, utf8, h->quads, HUD_MAX_GLYPHS, &end);
    x = floorf(x - align * k * end);
    y = floorf(y);
    batch_room(h, (shadow_rgba ? 12 : 6) * n);
    for (int pass = shadow_rgba ? 0 : 1; pass < 2; pass++) {
        const float d = pass == 0 ? fmaxf(1.0f, floorf(px / 18.0f)) : 0.0f;
        for (uint32_t i = 0; i < n; i++) {
            const hud_quad *q = &h->quads[i];
            push_rect(h, x + d + k * q->x0, y + d + k * q->y0, x + d + k * q->x1,
                      y + d + k * q->y1, q->s0, q->t0, q->s1, q->t1,
                      pass == 0 ? shadow_rgba : rgba);
        }
    }
    return k * end;
}

float hud_batch_text_width(const hud *h, const char *utf8, float px)
{
    return hud_text_width(h->font, utf8) * px / h->font->px;
}
