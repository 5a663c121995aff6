/* The HUD's panels: its lines in the top-left corner (kept as a picture while they hold
 * still), the wind arrow, the veil of a kiosk that lost its server, and touch buttons. */
#include "hud_internal.h"

#include <math.h>
#include <string.h>

/* Pushes the panel of hud_draw_lines (below) onto the batch. */
static void push_lines(hud *h, const char *const *lines, int n, int accent_line, float x, float y)
{
    const float pad = 0.6f * h->px;
    const float line_h =
        h->ascent - h->descent + h->line_gap + 0.25f * h->px;
    float w = 0.0f;
    for (int i = 0; i < n; i++) {
        w = fmaxf(w, hud_text_width(h->font, lines[i]));
    }
    const float panel[4] = { 0.05f, 0.07f, 0.10f, 0.62f };
    const float shadow[4] = { 0.0f, 0.0f, 0.0f, 0.85f };
    const float ink[4] = { 0.97f, 0.97f, 0.93f, 1.0f };
    const float accent[4] = { 1.0f, 0.80f, 0.30f, 1.0f };
    hud_push_rect(h, x, y, x + w + 2 * pad, y + n * line_h - 0.25f * h->px + 2 * pad, -1, 0, -1,
              0, panel);
    for (int i = 0; i < n; i++) {
        float bx = floorf(x + pad), by = floorf(y + pad + h->ascent + i * line_h);
        hud_push_text(h, bx + 1, by + 1, lines[i], shadow);
        hud_push_text(h, bx, by, lines[i], i == accent_line ? accent : ink);
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
    hud_flush_verts(h, fb_w, fb_h);
}

/* The wind arrow in the top-right corner: a disc-like panel and an arrow pointing where the
 * wind blows (downwind), relative to the view, longer with the class. */
static void draw_arrow(hud *h, const hud_state *s, int fb_w, int fb_h)
{
    const float r = 2.6f * h->px, margin = 0.8f * h->px;
    const float cx = (float)fb_w - margin - r, cy = margin + r;
    const float panel[4] = { 0.05f, 0.07f, 0.10f, 0.62f };
    const float ink[4] = { 1.0f, 0.80f, 0.30f, 1.0f };
    h->n_verts = 0;
    /* a 16-gon panel */
    for (int i = 0; i < 16; i++) {
        float a0 = (float)i * 0.3926991f, a1 = (float)(i + 1) * 0.3926991f;
        const float t[6] = { cx, cy, cx + r * cosf(a0), cy + r * sinf(a0), cx + r * cosf(a1),
                             cy + r * sinf(a1) };
        hud_push_tri(h, t, panel);
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
    hud_push_tri(h, head, ink);
    hud_push_tri(h, q0, ink);
    hud_push_tri(h, q1, ink);
    hud_flush_verts(h, fb_w, fb_h);
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
    const float margin = 0.8f * h->px;
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
    hud_push_rect(h, 0.0f, 0.0f, (float)fb_w, (float)fb_h, -1, 0, -1, 0, veil);
    hud_flush_verts(h, fb_w, fb_h);
    const float w = hud_text_width(h->font, text) + 1.2f * h->px;
    const char *lines[1] = { text };
    hud_draw_lines(h, lines, 1, 0, floorf(0.5f * ((float)fb_w - w)),
                   floorf(0.5f * (float)fb_h - h->px), fb_w, fb_h);
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
    hud_push_rect(h, x0, y0, x1, y1, -1, 0, -1, 0, panel);
    hud_push_rect(h, x0, y0, x1, y0 + t, -1, 0, -1, 0, edge);
    hud_push_rect(h, x0, y1 - t, x1, y1, -1, 0, -1, 0, edge);
    hud_push_rect(h, x0, y0, x0 + t, y1, -1, 0, -1, 0, edge);
    hud_push_rect(h, x1 - t, y0, x1, y1, -1, 0, -1, 0, edge);
    /* the atlas's glyphs magnified so the label's em is ~40 % of the button's height, as
     * the button itself scales with the framebuffer (camera_button.h) */
    const float em = h->ascent - h->descent;
    const float k = em > 0.0f ? 0.42f * bh / em : 1.0f;
    const float tw = k * hud_text_width(h->font, label);
    const float ox = floorf(0.5f * (x0 + x1 - tw));
    const float oy = floorf(0.5f * (y0 + y1) + 0.5f * k * (h->ascent + h->descent));
    uint32_t n = hud_text_quads(h->font, 0.0f, 0.0f, label, h->quads, HUD_MAX_GLYPHS, NULL);
    for (int pass = 0; pass < 2; pass++) {
        const float d = pass == 0 ? fmaxf(1.0f, floorf(k)) : 0.0f; /* shadow, then ink */
        for (uint32_t i = 0; i < n; i++) {
            const hud_quad *q = &h->quads[i];
            hud_push_rect(h, ox + d + k * q->x0, oy + d + k * q->y0, ox + d + k * q->x1,
                      oy + d + k * q->y1, q->s0, q->t0, q->s1, q->t1, pass == 0 ? shadow : ink);
        }
    }
    hud_flush_verts(h, fb_w, fb_h);
}
