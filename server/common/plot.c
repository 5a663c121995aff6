/* A small software raster for figures: anti-aliased lines by distance-to-segment
 * coverage, rectangles, arrows, text (stb_easy_font's quad glyphs, 8 px cell), a
 * viridis-like colour map, PNG output through stb_image_write. */
#include "plot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h>

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#endif
#include <stb/stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

/* Largest side accepted: keeps w*h*3 far from overflow and a figure under ~200 MB. */
#define PLOT_MAX_SIDE 8192

int plot_init(plot *p, int w, int h, const uint8_t bg[3], gale_err *err)
{
    memset(p, 0, sizeof *p);
    if (w <= 0 || h <= 0 || w > PLOT_MAX_SIDE || h > PLOT_MAX_SIDE) {
        return gale_errf(err, GALE_E_RANGE, "plot: size %dx%d: expected 1..%d per side", w, h,
                         PLOT_MAX_SIDE);
    }
    p->rgb = malloc((size_t)w * (size_t)h * 3);
    if (!p->rgb) {
        return gale_errf(err, GALE_E_NOMEM, "plot: out of memory for %dx%d", w, h);
    }
    p->w = w;
    p->h = h;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        memcpy(p->rgb + 3 * i, bg, 3);
    }
    return GALE_OK;
}

void plot_fini(plot *p)
{
    if (!p) {
        return;
    }
    free(p->rgb);
    memset(p, 0, sizeof *p);
}

/* Blends colour c over pixel (x, y) with coverage a in [0, 1]. */
static void plot_blend(plot *p, int x, int y, float a, const uint8_t c[3])
{
    if (x < 0 || y < 0 || x >= p->w || y >= p->h || !(a > 0.0f)) {
        return;
    }
    if (a > 1.0f) {
        a = 1.0f;
    }
    uint8_t *px = p->rgb + 3 * ((size_t)y * (size_t)p->w + (size_t)x);
    for (int k = 0; k < 3; k++) {
        float v = (float)px[k] + a * ((float)c[k] - (float)px[k]);
        px[k] = (uint8_t)(v + 0.5f);
    }
}

static int plot_clampi(float v, int lo, int hi)
{
    if (!(v > (float)lo)) {
        return lo;
    }
    if (v > (float)hi) {
        return hi;
    }
    return (int)v;
}

void plot_line(plot *p, float x0, float y0, float x1, float y1, float width, const uint8_t c[3])
{
    if (!p->rgb || !isfinite(x0) || !isfinite(y0) || !isfinite(x1) || !isfinite(y1)) {
        return;
    }
    if (!(width > 0.0f)) {
        width = 1.0f;
    }
    float hw = 0.5f * width;
    float pad = hw + 1.0f;
    int ix0 = plot_clampi(fminf(x0, x1) - pad, 0, p->w - 1);
    int ix1 = plot_clampi(fmaxf(x0, x1) + pad, 0, p->w - 1);
    int iy0 = plot_clampi(fminf(y0, y1) - pad, 0, p->h - 1);
    int iy1 = plot_clampi(fmaxf(y0, y1) + pad, 0, p->h - 1);
    float dx = x1 - x0, dy = y1 - y0;
    float len2 = dx * dx + dy * dy;
    for (int y = iy0; y <= iy1; y++) {
        for (int x = ix0; x <= ix1; x++) {
            /* pixel centre, distance to the segment, coverage of a 1-px box filter */
            float px = (float)x + 0.5f, py = (float)y + 0.5f;
            float t = len2 > 0.0f ? ((px - x0) * dx + (py - y0) * dy) / len2 : 0.0f;
            t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
            float ex = x0 + t * dx - px, ey = y0 + t * dy - py;
            float d = sqrtf(ex * ex + ey * ey);
            float a = hw + 0.5f - d;
            if (width < 1.0f) {
                a *= width; /* thinner than a pixel: fainter, not narrower */
            }
            plot_blend(p, x, y, a, c);
        }
    }
}

void plot_rect(plot *p, int x0, int y0, int x1, int y1, const uint8_t c[3])
{
    if (!p->rgb) {
        return;
    }
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > p->w ? p->w : x1;
    y1 = y1 > p->h ? p->h : y1;
    for (int y = y0; y < y1; y++) {
        for (int x = x0; x < x1; x++) {
            memcpy(p->rgb + 3 * ((size_t)y * (size_t)p->w + (size_t)x), c, 3);
        }
    }
}

void plot_arrow(plot *p, float x0, float y0, float x1, float y1, float width, const uint8_t c[3])
{
    plot_line(p, x0, y0, x1, y1, width, c);
    float dx = x1 - x0, dy = y1 - y0;
    float len = sqrtf(dx * dx + dy * dy);
    if (!(len > 0.0f)) {
        return;
    }
    float head = fminf(0.35f * len, 4.0f + 3.0f * width);
    float ux = dx / len, uy = dy / len;
    /* two barbs at ±25° from the shaft */
    const float cs = 0.906f, sn = 0.423f;
    float bx = -ux * cs + uy * sn, by = -uy * cs - ux * sn;
    float cx = -ux * cs - uy * sn, cy = -uy * cs + ux * sn;
    plot_line(p, x1, y1, x1 + head * bx, y1 + head * by, width, c);
    plot_line(p, x1, y1, x1 + head * cx, y1 + head * cy, width, c);
}

void plot_text(plot *p, int x, int y, int scale, const char *s, const uint8_t c[3])
{
    if (!p->rgb || !s) {
        return;
    }
    if (scale < 1) {
        scale = 1;
    }
    /* stb_easy_font draws each glyph as axis-aligned quads on a unit grid, ~7 units
     * tall with descenders; the buffer holds one line of up to 120 characters at a time. */
    static char buf[120 * 270];
    char line[121];
    int row = 0;
    while (*s) {
        size_t n = strcspn(s, "\n");
        size_t take = n < sizeof line - 1 ? n : sizeof line - 1;
        memcpy(line, s, take);
        line[take] = '\0';
        int quads = stb_easy_font_print(0.0f, 0.0f, line, NULL, buf, (int)sizeof buf);
        for (int q = 0; q < quads; q++) {
            const float *v0 = (const float *)(const void *)(buf + (size_t)q * 64);
            const float *v2 = (const float *)(const void *)(buf + (size_t)q * 64 + 32);
            int qx0 = x + (int)lroundf(v0[0] * (float)scale);
            int qy0 = y + row * 10 * scale + (int)lroundf(v0[1] * (float)scale);
            int qx1 = x + (int)lroundf(v2[0] * (float)scale);
            int qy1 = y + row * 10 * scale + (int)lroundf(v2[1] * (float)scale);
            plot_rect(p, qx0, qy0, qx1, qy1, c);
        }
        s += n;
        if (*s == '\n') {
            s++;
        }
        row++;
    }
}

void plot_colormap(float t, uint8_t out[3])
{
    /* viridis sampled at nine points, linear in between */
    static const float k[9][3] = {
        { 68, 1, 84 },    { 71, 44, 122 }, { 59, 81, 139 },  { 44, 113, 142 }, { 33, 144, 141 },
        { 39, 173, 129 }, { 92, 200, 99 }, { 170, 220, 50 }, { 253, 231, 37 },
    };
    if (!(t > 0.0f)) {
        t = 0.0f;
    }
    if (t > 1.0f) {
        t = 1.0f;
    }
    float f = t * 8.0f;
    int i = (int)f;
    if (i > 7) {
        i = 7;
    }
    float u = f - (float)i;
    for (int c = 0; c < 3; c++) {
        float v = k[i][c] + u * (k[i + 1][c] - k[i][c]);
        out[c] = (uint8_t)(v + 0.5f);
    }
}

int plot_write_png(const plot *p, const char *path, gale_err *err)
{
    if (!p->rgb) {
        return gale_errf(err, GALE_E_STATE, "%s: plot has no pixels", path);
    }
    if (!stbi_write_png(path, p->w, p->h, 3, p->rgb, p->w * 3)) {
        return gale_errf(err, GALE_E_IO, "%s: cannot write PNG", path);
    }
    return GALE_OK;
}
