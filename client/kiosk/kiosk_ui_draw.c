/* The kiosk's touch panel in GL (kiosk_ui.h): the wind dial with its coloured bands, the
 * compass ring, the buttons, through the HUD's batch of shapes and text (hud.h). Colours
 * of the hurricane bands follow the usual warm ramp of Saffir–Simpson charts. */
#include "kiosk_ui_draw.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lang.h"
#include "wind_scale.h"

static const float band_rgb[KIOSK_UI_BANDS][3] = {
    { 0.62f, 0.82f, 0.95f }, /* calm */
    { 0.45f, 0.80f, 0.60f }, /* breeze */
    { 0.72f, 0.85f, 0.38f }, /* strong wind */
    { 0.98f, 0.86f, 0.30f }, /* tropical storm */
    { 1.00f, 0.68f, 0.25f }, /* Cat 1 */
    { 1.00f, 0.50f, 0.20f }, /* Cat 2 */
    { 0.94f, 0.30f, 0.20f }, /* Cat 3 */
    { 0.84f, 0.16f, 0.36f }, /* Cat 4 */
    { 0.68f, 0.18f, 0.68f }, /* Cat 5 */
};

static const float ink[4] = { 0.97f, 0.97f, 0.93f, 1.0f };
static const float dim_ink[4] = { 0.80f, 0.82f, 0.84f, 1.0f };
static const float accent[4] = { 1.0f, 0.80f, 0.30f, 1.0f };
static const float dark_ink[4] = { 0.08f, 0.08f, 0.10f, 1.0f };
static const float panel_rgba[4] = { 0.04f, 0.06f, 0.09f, 0.62f };
static const float button_rgba[4] = { 0.10f, 0.13f, 0.18f, 1.0f };
static const float pressed_rgba[4] = { 0.35f, 0.42f, 0.52f, 1.0f };

/* Text; align -1 left, 0 centre, 1 right of x. No shadow: the panel under it is dark
 * (and every glyph less keeps the panel cheap on a software rasteriser). */
static void text(hud *h, float x, float y, float px, const char *s, const float rgba[4],
                 int align)
{
    hud_batch_text(h, x, y, px, s, rgba, 0.5f * (float)(align + 1), NULL);
}

/* A ring sector from angle a0 to a1 [rad, clockwise from up] between radii r0 and r1 (a
 * pie slice when r0 is 0), in chords within a pixel of the true arc. */
static void sector(hud *h, float cx, float cy, float r0, float r1, float a0, float a1,
                   const float rgba[4])
{
    const float step = fmaxf(0.1f, 2.5f / sqrtf(fmaxf(r1, 1.0f)));
    int n = (int)ceilf(fabsf(a1 - a0) / step);
    n = n < 1 ? 1 : n;
    for (int i = 0; i < n; i++) {
        float b0 = a0 + (a1 - a0) * (float)i / (float)n;
        float b1 = a0 + (a1 - a0) * (float)(i + 1) / (float)n;
        float s0 = sinf(b0), c0 = cosf(b0), s1 = sinf(b1), c1 = cosf(b1);
        const float t0[6] = { cx + r0 * s0, cy - r0 * c0, cx + r1 * s0, cy - r1 * c0,
                              cx + r1 * s1, cy - r1 * c1 };
        hud_batch_tri(h, t0, rgba);
        if (r0 > 0.0f) {
            const float t1[6] = { cx + r0 * s0, cy - r0 * c0, cx + r1 * s1, cy - r1 * c1,
                                  cx + r0 * s1, cy - r0 * c1 };
            hud_batch_tri(h, t1, rgba);
        }
    }
}

static void disc(hud *h, float cx, float cy, float r, const float rgba[4])
{
    sector(h, cx, cy, 0.0f, r, 0.0f, 6.2831853f, rgba);
}

/* A thick line from (x0, y0) to (x1, y1), w pixels wide. */
static void line(hud *h, float x0, float y0, float x1, float y1, float w, const float rgba[4])
{
    float dx = x1 - x0, dy = y1 - y0, l = sqrtf(dx * dx + dy * dy);
    if (l <= 0.0f) {
        return;
    }
    float px = -dy / l * 0.5f * w, py = dx / l * 0.5f * w;
    const float t0[6] = { x0 + px, y0 + py, x1 + px, y1 + py, x1 - px, y1 - py };
    const float t1[6] = { x0 + px, y0 + py, x1 - px, y1 - py, x0 - px, y0 - py };
    hud_batch_tri(h, t0, rgba);
    hud_batch_tri(h, t1, rgba);
}

static void draw_dial(hud *h, const kiosk_ui *ui, bool dragging)
{
    const float H = (float)ui->fb_h, cx = ui->dial_cx, cy = ui->dial_cy;
    const float r0 = ui->dial_r0, r1 = ui->dial_r1;
    const float v = dragging ? ui->drag_ms : ui->wind_ms;
    const int cur = kiosk_ui_band(v);
    const float label_px = 0.023f * H;
    disc(h, cx, cy, r1 + 0.006f * H, panel_rgba);
    for (int b = 0; b < KIOSK_UI_BANDS; b++) {
        float a0 = kiosk_ui_dial_angle(kiosk_ui_band_lower_ms(b));
        float a1 = b + 1 < KIOSK_UI_BANDS ? kiosk_ui_dial_angle(kiosk_ui_band_lower_ms(b + 1))
                                          : 0.5f * KIOSK_UI_DIAL_SWEEP_RAD;
        bool on = b == cur && (ui->have_wx || dragging);
        const float rgba[4] = { band_rgb[b][0], band_rgb[b][1], band_rgb[b][2], on ? 1.0f : 0.62f };
        sector(h, cx, cy, r0, on ? r1 + 0.008f * H : r1, a0 + 0.006f, a1 - 0.006f, rgba);
        /* the band's name outside the ring, anchored to the side it is on */
        float am = 0.5f * (a0 + a1), s = sinf(am), c = cosf(am);
        float rl = r1 + 0.016f * H;
        float lx = cx + rl * s, ly = cy - rl * c;
        int align = s > 0.3f ? -1 : s < -0.3f ? 1 : 0;
        float base = c > 0.3f ? ly - 0.004f * H : c < -0.3f ? ly + 0.8f * label_px
                                                           : ly + 0.35f * label_px;
        text(h, lx, base, on ? 1.12f * label_px : label_px, kiosk_ui_band_name(ui->lang, b),
             on ? accent : dim_ink, align);
    }
    /* the streamed wind: a white pointer across the ring */
    if (ui->have_wx) {
        float a = kiosk_ui_dial_angle(ui->wind_ms), s = sinf(a), c = cosf(a);
        line(h, cx + (r0 - 0.01f * H) * s, cy - (r0 - 0.01f * H) * c, cx + (r1 + 0.01f * H) * s,
             cy - (r1 + 0.01f * H) * c, 0.008f * H, ink);
    }
    /* the finger's value: a knob on the ring */
    if (dragging) {
        float x, y;
        kiosk_ui_dial_point(ui, ui->drag_ms, &x, &y);
        disc(h, x, y, 0.5f * (r1 - r0) + 0.006f * H, dark_ink);
        disc(h, x, y, 0.5f * (r1 - r0), ink);
    }
    /* the figures in the middle: the language's first unit large, then its second and
     * m/s, each kept inside the range of the class the dial's band names (hud_units.c) */
    const int lang = ui->lang, cls = wind_scale_ss_class((double)v);
    const bool kmh_first = lang_kmh_first(lang);
    char big[32], small1[32], small2[32];
    long mph = hud_unit_sustained((double)v, HUD_UNIT_MPH, cls);
    long kmh = hud_unit_sustained((double)v, HUD_UNIT_KMH, cls);
    lang_format(big, sizeof big, lang, kmh_first ? L_UNIT_KMH : L_UNIT_MPH,
                (int)(kmh_first ? kmh : mph));
    lang_format(small1, sizeof small1, lang, kmh_first ? L_UNIT_MPH : L_UNIT_KMH,
                (int)(kmh_first ? mph : kmh));
    lang_format(small2, sizeof small2, lang, L_UNIT_MS,
                (int)hud_unit_sustained((double)v, HUD_UNIT_MS, cls));
    const bool known = ui->have_wx || dragging;
    text(h, cx, cy - 0.05f * H, 0.019f * H,
         lang_text(lang, dragging ? L_KIOSK_LET_GO : L_KIOSK_WIND_SPEED),
         dragging ? accent : dim_ink, 0);
    /* "211 km/h" is wider than "59 m/s": the figure shrinks to stay inside the ring */
    const float big_w1 = hud_batch_text_width(h, big, 1.0f);
    const float big_px = big_w1 > 0.0f ? fminf(0.043f * H, 1.55f * r0 / big_w1) : 0.043f * H;
    text(h, cx, cy + 0.012f * H, big_px, known ? big : "\xE2\x80\x93", dragging ? accent : ink,
         0);
    if (known) {
        text(h, cx, cy + 0.042f * H, 0.019f * H, small1, dim_ink, 0);
        text(h, cx, cy + 0.064f * H, 0.019f * H, small2, dim_ink, 0);
    }
    text(h, cx, cy + r1 * 0.84f, 0.021f * H,
         lang_text(lang, ui->dial_held ? L_KIOSK_SET_HERE : L_KIOSK_DRAG),
         ui->dial_held ? accent : ink, 0);
}

static void draw_compass(hud *h, const kiosk_ui *ui, bool dragging)
{
    const float H = (float)ui->fb_h, cx = ui->comp_cx, cy = ui->comp_cy, r = ui->comp_r;
    const float ring[4] = { 0.20f, 0.26f, 0.34f, 0.9f };
    disc(h, cx, cy, r, panel_rgba);
    sector(h, cx, cy, 0.74f * r, r, 0.0f, 6.2831853f, ring);
    float from = dragging ? ui->drag_from_deg : ui->dir_from_deg;
    float a = from * 0.017453292f, s = sinf(a), c = cosf(a);
    const float *col = dragging ? accent : ink;
    if (ui->have_wx || dragging) {
        /* an arrow across the disc, pointing where the wind blows; its tail, the ring you
         * drag, sits on the side the wind comes from */
        float tx = cx + 0.6f * r * s, ty = cy - 0.6f * r * c;
        float hx = cx - 0.6f * r * s, hy = cy + 0.6f * r * c;
        line(h, tx, ty, hx + 0.15f * r * s, hy - 0.15f * r * c, 0.018f * H, col);
        float px = c, py = s; /* across the arrow */
        const float head[6] = { hx - 0.12f * r * s, hy + 0.12f * r * c,
                                hx + 0.2f * r * s + 0.22f * r * px, hy - 0.2f * r * c + 0.22f * r * py,
                                hx + 0.2f * r * s - 0.22f * r * px, hy - 0.2f * r * c - 0.22f * r * py };
        hud_batch_tri(h, head, col);
        float kx = cx + 0.87f * r * s, ky = cy - 0.87f * r * c;
        sector(h, kx, ky, 0.12f * r, 0.17f * r, 0.0f, 6.2831853f, accent);
    }
    /* the compass points over it, so the ring round one leaves it readable */
    for (int i = 0; i < 4; i++) {
        float b = (float)i * 1.5707963f;
        text(h, cx + 0.87f * r * sinf(b), cy - 0.87f * r * cosf(b) + 0.35f * 0.024f * H,
             0.024f * H, lang_text(ui->lang, L_COMPASS_0 + 4 * i), ink, 0);
    }
    char title[48];
    lang_format(title, sizeof title, ui->lang, L_KIOSK_WIND_FROM,
                hud_compass_text(ui->lang, from));
    text(h, cx, cy - r - 0.018f * H, 0.023f * H, title, dragging ? accent : ink, 0);
}

/* A touch button: selected (the running scenario, the replay's speed) is filled with the
 * accent, pressed is lit while the finger is on it. */
static void draw_button(hud *h, const kiosk_ui *ui, const kiosk_ui_control *k, bool pressed,
                        bool selected)
{
    const kiosk_ui_rect *r = &k->r;
    const float bh = r->y1 - r->y0, bw = r->x1 - r->x0, t = fmaxf(2.0f, floorf(0.045f * bh));
    const float edge[4] = { selected ? 1.0f : 0.62f, selected ? 0.80f : 0.52f,
                            selected ? 0.30f : 0.25f, 1.0f };
    float d = pressed ? fmaxf(1.0f, floorf(0.04f * bh)) : 0.0f; /* pressed: sinks a little */
    /* the edge, and the face inside it (opaque, so two rectangles draw both) */
    hud_batch_rect(h, r->x0 + d, r->y0 + d, r->x1 + d, r->y1 + d, edge);
    hud_batch_rect(h, r->x0 + d + t, r->y0 + d + t, r->x1 + d - t, r->y1 + d - t,
                   pressed ? pressed_rgba : selected ? accent : button_rgba);
    char label[KIOSK_UI_NAME_CHARS];
    kiosk_ui_label(ui, k, label, sizeof label);
    float icon = 0.0f; /* room for the play / pause sign */
    if (k->kind == KIOSK_UI_PLAY) {
        icon = 0.42f * bh;
    }
    const float room = bw - 0.25f * bh - icon;
    float px = 0.40f * bh, w1 = hud_batch_text_width(h, label, 1.0f);
    const float *col = selected && !pressed ? dark_ink : ink;
    const float cx = 0.5f * (r->x0 + r->x1 + icon) + d, cy = 0.5f * (r->y0 + r->y1) + d;
    char *cut = NULL;
    if (w1 > 0.0f && px * w1 > room) {
        px = room / w1; /* a long title shrinks to fit its button */
        /* much smaller than the rest: two lines, split at the space nearest the middle */
        size_t len = strlen(label);
        for (char *p = label; *p; p++) {
            if (*p == ' ' && (!cut || labs((long)(p - label) * 2 - (long)len) <
                                          labs((long)(cut - label) * 2 - (long)len))) {
                cut = p;
            }
        }
        if (px >= 0.30f * bh) {
            cut = NULL;
        }
    }
    if (cut) {
        *cut = '\0';
        const char *l2 = cut + 1;
        float w2 = fmaxf(hud_batch_text_width(h, label, 1.0f), hud_batch_text_width(h, l2, 1.0f));
        float p2 = fminf(0.32f * bh, w2 > 0.0f ? room / w2 : 0.32f * bh);
        text(h, cx, cy - 0.12f * p2, p2, label, col, 0);
        text(h, cx, cy + 0.95f * p2, p2, l2, col, 0);
        return;
    }
    float tw = px * w1, x = cx - 0.5f * tw;
    float base = cy + 0.35f * px;
    if (k->kind == KIOSK_UI_PLAY) {
        float ix = x - icon, iy = cy, s = 0.16f * bh;
        if (ui->paused) {
            const float tri[6] = { ix, iy - s, ix, iy + s, ix + 1.6f * s, iy };
            hud_batch_tri(h, tri, col);
        } else {
            hud_batch_rect(h, ix, iy - s, ix + 0.55f * s, iy + s, col);
            hud_batch_rect(h, ix + s, iy - s, ix + 1.55f * s, iy + s, col);
        }
    }
    text(h, x, base, px, label, col, -1);
}

/* Everything the panel's picture depends on, to the resolution it is drawn at (the wind to
 * 0.1 m/s, directions to the degree), hashed (FNV-1a): the same key, the same picture. */
static uint64_t picture_key(const kiosk_ui *ui)
{
    const int32_t v[] = { ui->fb_w,
                          ui->fb_h,
                          ui->collapsed,
                          ui->page,
                          ui->pressed,
                          ui->n,
                          (int32_t)ui->scen_gen,
                          ui->running,
                          ui->replay,
                          ui->paused,
                          (int32_t)lroundf(ui->replay_speed * 10.0f),
                          ui->have_wx,
                          ui->dial_held,
                          (int32_t)lroundf(ui->wind_ms * 10.0f),
                          (int32_t)lroundf(ui->dir_from_deg),
                          (int32_t)lroundf(ui->drag_ms * 10.0f),
                          (int32_t)lroundf(ui->drag_from_deg),
                          ui->lang };
    uint64_t k = 14695981039346656037ull;
    const unsigned char *p = (const unsigned char *)v;
    for (size_t i = 0; i < sizeof v; i++) {
        k = (k ^ p[i]) * 1099511628211ull;
    }
    return k | 1u; /* never 0, which keeps nothing */
}

void kiosk_ui_draw(hud *h, const kiosk_ui *ui)
{
    if (ui->fb_w <= 0 || ui->fb_h <= 0) {
        return;
    }
    const uint64_t key = picture_key(ui);
    if (hud_batch_replay(h, key, ui->fb_w, ui->fb_h)) {
        return; /* nothing on the panel changed: its vertices are on the GPU already */
    }
    const float H = (float)ui->fb_h, W = (float)ui->fb_w;
    hud_batch_begin(h, ui->fb_w, ui->fb_h);
    if (!ui->collapsed) {
        const float top[4] = { 1.0f, 0.80f, 0.30f, 0.5f };
        hud_batch_rect(h, 0.0f, ui->panel_y0, W, H, panel_rgba);
        hud_batch_rect(h, 0.0f, ui->panel_y0, W, ui->panel_y0 + fmaxf(1.0f, 0.002f * H), top);
    }
    int pressed_kind = ui->pressed >= 0 ? ui->c[ui->pressed].kind : -1;
    for (int i = 0; i < ui->n; i++) {
        const kiosk_ui_control *k = &ui->c[i];
        bool pressed = i == ui->pressed;
        switch (k->kind) {
        case KIOSK_UI_DIAL:
            draw_dial(h, ui, pressed_kind == KIOSK_UI_DIAL);
            break;
        case KIOSK_UI_COMPASS:
            draw_compass(h, ui, pressed_kind == KIOSK_UI_COMPASS);
            break;
        case KIOSK_UI_SCENARIO:
            if (i == 0 || ui->c[i - 1].kind != KIOSK_UI_SCENARIO) { /* the block's first */
                char head[96];
                kiosk_ui_scen_heading(ui, head, sizeof head);
                text(h, k->r.x0, k->r.y0 - 0.014f * H, 0.024f * H, head, ink, -1);
            }
            draw_button(h, ui, k, pressed, k->index == ui->running);
            break;
        case KIOSK_UI_PLAY:
            text(h, k->r.x0, k->r.y0 - 0.01f * H, 0.021f * H,
                 lang_text(ui->lang, L_KIOSK_STORM_REPLAY), ink, -1);
            draw_button(h, ui, k, pressed, false);
            break;
        case KIOSK_UI_SPEED:
            if (k->index == 0) {
                text(h, k->r.x0, k->r.y0 - 0.01f * H, 0.021f * H,
                     lang_text(ui->lang, L_KIOSK_REPLAY_SPEED), ink, -1);
            }
            draw_button(h, ui, k, pressed,
                        fabsf(ui->replay_speed - kiosk_ui_speed_x(k->index)) < 0.5f);
            break;
        case KIOSK_UI_LANG:
            draw_button(h, ui, k, pressed, k->index == ui->lang);
            break;
        default:
            draw_button(h, ui, k, pressed, false);
            break;
        }
    }
    hud_batch_flush_keep(h, key);
}
