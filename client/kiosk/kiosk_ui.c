/* The kiosk's touch panel: layout, hit-testing, touch state (kiosk_ui.h). */
#include "kiosk_ui.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hud.h"
#include "wind_scale.h"

/* Layout [fraction of the framebuffer height] */
#define MARGIN     0.02f
#define GAP        0.012f
#define DIAL_R1    0.132f /* outer ring radius */
#define DIAL_R0    0.086f /* inner ring radius */
#define DIAL_LABEL 0.16f  /* room for a band label beside the ring */
#define DIAL_BELOW 0.108f /* centre to the panel's bottom margin */
#define COMP_R     0.085f
#define HEAD_H     0.045f /* the button block's heading line */
#define HEAD2_H    0.032f /* the replay row's headings */
#define TAB_W      0.22f
#define TAB_H      0.062f /* 44 px at 720p, the height of a button */
#define LANG_W     0.13f  /* a language button: "Español" at the tab's text size */
#define SCEN_MIN_W 0.13f /* two lines of "Category 1 (steady)" fit */
#define SCEN_MAX_W 0.30f

static const float speed_x[KIOSK_UI_SPEEDS] = { 1.0f, 10.0f, 50.0f };

void kiosk_ui_init(kiosk_ui *ui)
{
    memset(ui, 0, sizeof *ui);
    ui->pressed = -1;
    ui->running = -1;
    ui->replay_speed = 0.0f;
}

static void copy_cut(char *dst, const char *src)
{
    snprintf(dst, KIOSK_UI_NAME_CHARS, "%s", src ? src : "");
}

void kiosk_ui_set_scenario(kiosk_ui *ui, int i, const char *name, const char *title, bool replay)
{
    if (i < 0 || i >= KIOSK_UI_MAX_SCENARIOS) {
        return;
    }
    copy_cut(ui->scen[i].name, name);
    copy_cut(ui->scen[i].title, title && title[0] ? title : name);
    ui->scen[i].replay = replay;
}

void kiosk_ui_set_scenario_count(kiosk_ui *ui, int n)
{
    ui->n_scen = n < 0 ? 0 : n > KIOSK_UI_MAX_SCENARIOS ? KIOSK_UI_MAX_SCENARIOS : n;
    ui->running = -1;
    ui->page = 0;
    ui->scen_gen++;
}

/* Letters and digits only, lower case: how the server matches scenario names (PROTOCOL.md
 * "wind"), so "Andrew 1992" names andrew1992. */
static void squash(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    for (; *s && n + 1 < cap; s++) {
        if (isalnum((unsigned char)*s)) {
            out[n++] = (char)tolower((unsigned char)*s);
        }
    }
    out[n] = '\0';
}

void kiosk_ui_set_weather(kiosk_ui *ui, const wire_weather *w)
{
    ui->have_wx = true;
    ui->wind_ms = w->sustained_ms;
    ui->dir_from_deg = w->dir_from_deg;
    ui->dial_held = (w->flags & WIRE_WEATHER_DIAL) != 0;
    ui->replay = (w->flags & WIRE_WEATHER_STORM) != 0;
    ui->paused = (w->flags & WIRE_WEATHER_PAUSED) != 0;
    ui->replay_speed = w->replay_speed;
    char want[KIOSK_UI_NAME_CHARS], a[KIOSK_UI_NAME_CHARS], b[KIOSK_UI_NAME_CHARS];
    squash(w->name, want, sizeof want);
    ui->running = -1;
    for (int i = 0; i < ui->n_scen && want[0]; i++) {
        squash(ui->scen[i].title, a, sizeof a);
        squash(ui->scen[i].name, b, sizeof b);
        if (strcmp(a, want) == 0 || strcmp(b, want) == 0) {
            ui->running = i;
            break;
        }
    }
}

/* ---- the dial's scale ---------------------------------------------------------------- */

float kiosk_ui_band_lower_ms(int b)
{
    switch (b) {
    case 0:
        return 0.0f;
    case 1: /* breeze: Beaufort 2 (light breeze) to 5 */
        return (float)wind_scale_beaufort_lower_ms(2);
    case 2: /* strong wind: Beaufort 6 (strong breeze) and 7 (near gale) */
        return (float)wind_scale_beaufort_lower_ms(6);
    case KIOSK_UI_BANDS:
        return KIOSK_UI_DIAL_MAX_MS;
    default: /* tropical storm, Cat 1..5 */
        return b > 2 && b < KIOSK_UI_BANDS ? (float)wind_scale_ss_lower_ms(WIND_SCALE_TS + b - 3)
                                           : -1.0f;
    }
}

const char *kiosk_ui_band_name(int lang, int b)
{
    if (b >= 0 && b < 3) {
        return lang_text(lang, L_KIOSK_BAND_CALM + b);
    }
    if (b == 3) {
        return lang_text(lang, L_SS_0 + WIND_SCALE_TS);
    }
    return b > 3 && b < KIOSK_UI_BANDS ? lang_text(lang, L_SS_ABBREV_0 + WIND_SCALE_TS + b - 3)
                                       : "?";
}

const char *kiosk_ui_band_label(int b)
{
    return kiosk_ui_band_name(LANG_EN, b);
}

int kiosk_ui_band(float speed_ms)
{
    int b = 0;
    for (int i = 1; i < KIOSK_UI_BANDS; i++) {
        if (speed_ms >= kiosk_ui_band_lower_ms(i)) {
            b = i;
        }
    }
    return b;
}

float kiosk_ui_dial_angle(float speed_ms)
{
    float v = fminf(fmaxf(isfinite(speed_ms) ? speed_ms : 0.0f, 0.0f), KIOSK_UI_DIAL_MAX_MS);
    int b = kiosk_ui_band(v);
    float lo = kiosk_ui_band_lower_ms(b), hi = kiosk_ui_band_lower_ms(b + 1);
    float f = hi > lo ? fminf((v - lo) / (hi - lo), 1.0f) : 0.0f;
    return -0.5f * KIOSK_UI_DIAL_SWEEP_RAD +
           ((float)b + f) * KIOSK_UI_DIAL_SWEEP_RAD / (float)KIOSK_UI_BANDS;
}

float kiosk_ui_dial_speed(float angle_rad)
{
    float u = (angle_rad + 0.5f * KIOSK_UI_DIAL_SWEEP_RAD) / KIOSK_UI_DIAL_SWEEP_RAD *
              (float)KIOSK_UI_BANDS;
    u = fminf(fmaxf(isfinite(u) ? u : 0.0f, 0.0f), (float)KIOSK_UI_BANDS);
    int b = (int)floorf(u);
    if (b >= KIOSK_UI_BANDS) {
        return KIOSK_UI_DIAL_MAX_MS;
    }
    float lo = kiosk_ui_band_lower_ms(b), hi = kiosk_ui_band_lower_ms(b + 1);
    return lo + (u - (float)b) * (hi - lo);
}

float kiosk_ui_speed_x(int i)
{
    return i >= 0 && i < KIOSK_UI_SPEEDS ? speed_x[i] : 0.0f;
}

/* ---- layout ---------------------------------------------------------------------------- */

/* The year a title ends with ("Andrew 1992" → 1992), 9999 when it ends with none, so a
 * storm library reads in time order and an undated replay comes last. */
static int title_year(const char *t)
{
    size_t n = strlen(t);
    if (n >= 4 && isdigit((unsigned char)t[n - 1]) && isdigit((unsigned char)t[n - 2]) &&
        isdigit((unsigned char)t[n - 3]) && isdigit((unsigned char)t[n - 4]) &&
        (n == 4 || !isdigit((unsigned char)t[n - 5]))) {
        return atoi(t + n - 4);
    }
    return 9999;
}

/* Pages of `per` buttons: the steady scenarios in the welcome's order, then the replays by
 * year (a stable insertion sort: ties keep the welcome's order); a page holds one kind. */
static void paginate(kiosk_ui *ui, int per)
{
    int n = 0;
    for (int i = 0; i < ui->n_scen; i++) {
        if (!ui->scen[i].replay) {
            ui->order[n++] = i;
        }
    }
    const int n_steady = n;
    for (int i = 0; i < ui->n_scen; i++) {
        if (!ui->scen[i].replay) {
            continue;
        }
        int y = title_year(ui->scen[i].title), j = n++;
        while (j > n_steady && title_year(ui->scen[ui->order[j - 1]].title) > y) {
            ui->order[j] = ui->order[j - 1];
            j--;
        }
        ui->order[j] = i;
    }
    ui->n_pages = 0;
    for (int g = 0; g < 2; g++) {
        int a = g == 0 ? 0 : n_steady, b = g == 0 ? n_steady : n;
        for (int i = a; i < b && ui->n_pages < KIOSK_UI_MAX_PAGES; i += per) {
            ui->page_start[ui->n_pages] = i;
            ui->page_len[ui->n_pages] = b - i < per ? b - i : per;
            ui->n_pages++;
        }
    }
    if (ui->page >= ui->n_pages) {
        ui->page = ui->n_pages > 0 ? ui->n_pages - 1 : 0;
    }
    ui->page = ui->page < 0 ? 0 : ui->page;
}

static void add(kiosk_ui *ui, int kind, int index, float x0, float y0, float x1, float y1)
{
    if (ui->n >= KIOSK_UI_MAX_CONTROLS) {
        return;
    }
    ui->c[ui->n++] = (kiosk_ui_control){ kind, index, { x0, y0, x1, y1 } };
}

/* The language buttons, each in its own language's name, in a row ending at x1 between
 * y0 and y1 (beside the panel's tab, where a visitor looks for it shown or hidden). */
static void add_languages(kiosk_ui *ui, float x1, float y0, float y1)
{
    const float w = LANG_W * (float)ui->fb_h, g = GAP * (float)ui->fb_h;
    for (int l = LANG_COUNT - 1; l >= 0; l--) {
        add(ui, KIOSK_UI_LANG, l, x1 - w, y0, x1, y1);
        x1 -= w + g;
    }
}

void kiosk_ui_layout(kiosk_ui *ui, int fb_w, int fb_h)
{
    ui->fb_w = fb_w;
    ui->fb_h = fb_h;
    ui->n = 0;
    if (fb_w <= 0 || fb_h <= 0) {
        return;
    }
    const float H = (float)fb_h, W = (float)fb_w, m = MARGIN * H, g = GAP * H;
    const float bh = KIOSK_UI_BUTTON_H_FRAC * H;
    if (ui->collapsed) {
        ui->panel_y0 = H;
        add(ui, KIOSK_UI_COLLAPSE, 0, W - m - TAB_W * H, H - m - TAB_H * H, W - m, H - m);
        add_languages(ui, W - m - TAB_W * H - g, H - m - TAB_H * H, H - m);
        return;
    }
    /* dial and compass side by side at the bottom left */
    const float dial_w = 2.0f * (DIAL_R1 + GAP + DIAL_LABEL) * H;
    const float comp_w = 2.0f * (COMP_R + 0.02f) * H;
    ui->dial_r1 = DIAL_R1 * H;
    ui->dial_r0 = DIAL_R0 * H;
    ui->dial_cx = m + 0.5f * dial_w;
    ui->comp_r = COMP_R * H;
    ui->comp_cx = m + dial_w + m + 0.5f * comp_w;
    /* the buttons to their right, or (a narrow screen) in a block above them */
    float bx0 = m + dial_w + m + comp_w + 1.5f * m, bx1 = W - m;
    bool above = bx1 - bx0 < 2.0f * SCEN_MIN_W * H + g;
    if (above) {
        bx0 = m;
    }
    const float bw_all = bx1 - bx0;
    int cols = (int)floorf((bw_all + g) / (SCEN_MIN_W * H + g));
    cols = cols < 1 ? 1 : cols;
    if (ui->n_scen > 0 && cols > ui->n_scen) {
        cols = ui->n_scen;
    }
    float sw = fminf((bw_all - (float)(cols - 1) * g) / (float)cols, SCEN_MAX_W * H);
    int scen_rows = (ui->n_scen + cols - 1) / cols;
    /* more rows than KIOSK_UI_SCEN_UNPAGED buttons take: a page at a time, the last two
     * places of its last row the Previous and Next buttons */
    int max_rows = (KIOSK_UI_SCEN_UNPAGED + cols - 1) / cols;
    max_rows = max_rows < 2 ? 2 : max_rows;
    const bool paged = scen_rows > max_rows;
    ui->n_pages = 1;
    if (paged) {
        scen_rows = max_rows;
        paginate(ui, cols * scen_rows - 2);
    }
    int rows = scen_rows + 1; /* and the replay / reset row */
    float block_h = HEAD_H * H + HEAD2_H * H + (float)rows * bh + (float)(rows - 1) * g;
    float dial_h = KIOSK_UI_PANEL_H_FRAC * H;
    float panel_h = above ? dial_h + block_h + m : fmaxf(dial_h, block_h + 2.0f * m);
    ui->panel_y0 = H - panel_h;
    ui->dial_cy = H - m - DIAL_BELOW * H;
    ui->comp_cy = ui->dial_cy;
    add(ui, KIOSK_UI_DIAL, 0, ui->dial_cx - 0.5f * dial_w,
        ui->dial_cy - ui->dial_r1 - 0.045f * H, ui->dial_cx + 0.5f * dial_w, H - m);
    add(ui, KIOSK_UI_COMPASS, 0, ui->comp_cx - 0.5f * comp_w,
        ui->comp_cy - ui->comp_r - 0.05f * H, ui->comp_cx + 0.5f * comp_w,
        ui->comp_cy + ui->comp_r + 0.02f * H);
    float y = (above ? ui->panel_y0 + m : H - m - block_h) + HEAD_H * H;
    const int shown = paged ? ui->page_len[ui->page] : ui->n_scen;
    for (int i = 0; i < shown; i++) {
        int r = i / cols, k = i % cols;
        float x = bx0 + (float)k * (sw + g), yy = y + (float)r * (bh + g);
        add(ui, KIOSK_UI_SCENARIO, paged ? ui->order[ui->page_start[ui->page] + i] : i, x, yy,
            x + sw, yy + bh);
    }
    for (int i = 0; paged && i < 2; i++) {
        int slot = cols * scen_rows - 2 + i, r = slot / cols, k = slot % cols;
        float x = bx0 + (float)k * (sw + g), yy = y + (float)r * (bh + g);
        add(ui, KIOSK_UI_PAGE, i, x, yy, x + sw, yy + bh);
    }
    /* the last row: play/pause, landfall, ×1 ×10 ×50 (during a replay), reset at the end */
    float yr = y + (float)scen_rows * (bh + g) + HEAD2_H * H;
    const float wa = 0.17f * H, ws = 0.085f * H, wr = 0.14f * H;
    float need = 2.0f * wa + 3.0f * ws + wr; /* and 5 gaps */
    float k = need + 5.0f * g > bw_all ? (bw_all - 5.0f * g) / need : 1.0f;
    float x = bx0;
    if (ui->replay) {
        add(ui, KIOSK_UI_PLAY, 0, x, yr, x + k * wa, yr + bh);
        x += k * wa + g;
        add(ui, KIOSK_UI_LANDFALL, 0, x, yr, x + k * wa, yr + bh);
        x += k * wa + g;
        for (int i = 0; i < KIOSK_UI_SPEEDS; i++) {
            add(ui, KIOSK_UI_SPEED, i, x, yr, x + k * ws, yr + bh);
            x += k * ws + g;
        }
    }
    add(ui, KIOSK_UI_RESET, 0, bx1 - k * wr, yr, bx1, yr + bh);
    /* the tab that hides the panel, on its top edge at the right */
    add(ui, KIOSK_UI_COLLAPSE, 0, W - m - TAB_W * H, ui->panel_y0 - TAB_H * H - 0.005f * H,
        W - m, ui->panel_y0 - 0.005f * H);
    add_languages(ui, W - m - TAB_W * H - g, ui->panel_y0 - TAB_H * H - 0.005f * H,
                  ui->panel_y0 - 0.005f * H);
}

/* ---- hit-testing and touch ----------------------------------------------------------- */

static bool in_rect(const kiosk_ui_rect *r, float x, float y)
{
    return x >= r->x0 && x < r->x1 && y >= r->y0 && y < r->y1;
}

/* Angle [rad, clockwise from straight up] of (x, y) about (cx, cy) and its distance. */
static float polar(float cx, float cy, float x, float y, float *d)
{
    float dx = x - cx, dy = y - cy;
    *d = sqrtf(dx * dx + dy * dy);
    return atan2f(dx, -dy);
}

int kiosk_ui_hit(const kiosk_ui *ui, float x, float y)
{
    for (int i = 0; i < ui->n; i++) {
        const kiosk_ui_control *k = &ui->c[i];
        if (!in_rect(&k->r, x, y)) {
            continue;
        }
        float d;
        if (k->kind == KIOSK_UI_DIAL) {
            float a = polar(ui->dial_cx, ui->dial_cy, x, y, &d);
            if (d >= 0.45f * ui->dial_r0 && d <= ui->dial_r1 + 0.035f * (float)ui->fb_h &&
                fabsf(a) <= 0.5f * KIOSK_UI_DIAL_SWEEP_RAD + 0.2f) {
                return i;
            }
        } else if (k->kind == KIOSK_UI_COMPASS) {
            polar(ui->comp_cx, ui->comp_cy, x, y, &d);
            if (d <= ui->comp_r + 0.02f * (float)ui->fb_h) {
                return i;
            }
        } else {
            return i;
        }
    }
    return -1;
}

static float bearing_deg(float a_rad)
{
    float b = a_rad * 57.29578f;
    b = fmodf(b + 360.0f, 360.0f);
    return b >= 360.0f ? 0.0f : b;
}

/* The dial or compass under the finger: its value from the position. */
static void drag(kiosk_ui *ui, const kiosk_ui_control *k, float x, float y, kiosk_ui_action *a)
{
    float d;
    if (k->kind == KIOSK_UI_DIAL) {
        float ang = polar(ui->dial_cx, ui->dial_cy, x, y, &d);
        if (fabsf(ang) > 0.5f * KIOSK_UI_DIAL_SWEEP_RAD && a->dragging) {
            /* in the gap below the dial: stay at the end the finger came from, so crossing
             * the bottom does not flip calm and Category 5 */
            ang = ui->drag_ms > 0.5f * KIOSK_UI_DIAL_MAX_MS ? KIOSK_UI_DIAL_SWEEP_RAD
                                                             : -KIOSK_UI_DIAL_SWEEP_RAD;
        }
        ui->drag_ms = kiosk_ui_dial_speed(ang);
        a->act = KIOSK_UI_ACT_SPEED;
        a->value = ui->drag_ms;
    } else {
        /* the ring is a compass seen from above, north up: the finger marks where the wind
         * comes from */
        ui->drag_from_deg = bearing_deg(polar(ui->comp_cx, ui->comp_cy, x, y, &d));
        a->act = KIOSK_UI_ACT_DIR;
        a->value = ui->drag_from_deg;
    }
}

bool kiosk_ui_touch(kiosk_ui *ui, int phase, float x, float y, kiosk_ui_action *a)
{
    *a = (kiosk_ui_action){ 0 };
    if (phase == KIOSK_UI_DOWN) {
        ui->pressed = kiosk_ui_hit(ui, x, y);
        if (ui->pressed < 0) {
            return false;
        }
        const kiosk_ui_control *k = &ui->c[ui->pressed];
        if (k->kind == KIOSK_UI_DIAL || k->kind == KIOSK_UI_COMPASS) {
            drag(ui, k, x, y, a);
            a->dragging = true;
            return true;
        }
        return false;
    }
    if (ui->pressed < 0 || ui->pressed >= ui->n) {
        ui->pressed = -1;
        return false;
    }
    const kiosk_ui_control k = ui->c[ui->pressed];
    bool dragged = k.kind == KIOSK_UI_DIAL || k.kind == KIOSK_UI_COMPASS;
    if (phase == KIOSK_UI_MOVE) {
        if (dragged) {
            a->dragging = true;
            drag(ui, &k, x, y, a);
            return true;
        }
        return false;
    }
    /* KIOSK_UI_UP */
    ui->pressed = -1;
    if (dragged) {
        a->dragging = true; /* (for the gap below the dial) */
        drag(ui, &k, x, y, a);
        a->dragging = false;
    } else if (in_rect(&k.r, x, y)) { /* a button acts when let go on it */
        switch (k.kind) {
        case KIOSK_UI_SCENARIO:
            a->act = KIOSK_UI_ACT_SCENARIO;
            a->index = k.index;
            break;
        case KIOSK_UI_PLAY:
            a->act = KIOSK_UI_ACT_PAUSE;
            a->value = ui->paused ? 0.0f : 1.0f;
            break;
        case KIOSK_UI_LANDFALL:
            a->act = KIOSK_UI_ACT_SEEK;
            a->value = 0.0f;
            break;
        case KIOSK_UI_SPEED:
            a->act = KIOSK_UI_ACT_REPLAY_SPEED;
            a->index = k.index;
            a->value = kiosk_ui_speed_x(k.index);
            break;
        case KIOSK_UI_RESET:
            a->act = KIOSK_UI_ACT_RESET;
            break;
        case KIOSK_UI_LANG:
            ui->lang = k.index;
            a->act = KIOSK_UI_ACT_LANG;
            a->index = k.index;
            break;
        case KIOSK_UI_PAGE:
            if (ui->n_pages > 0) {
                ui->page = (ui->page + (k.index ? 1 : ui->n_pages - 1)) % ui->n_pages;
            }
            a->act = KIOSK_UI_ACT_PAGE;
            a->index = ui->page;
            kiosk_ui_layout(ui, ui->fb_w, ui->fb_h);
            break;
        case KIOSK_UI_COLLAPSE:
            ui->collapsed = !ui->collapsed;
            a->act = KIOSK_UI_ACT_COLLAPSE;
            a->value = ui->collapsed ? 1.0f : 0.0f;
            kiosk_ui_layout(ui, ui->fb_w, ui->fb_h);
            break;
        default:
            break;
        }
    }
    if (a->act != KIOSK_UI_ACT_NONE) {
        kiosk_ui_label(ui, &k, ui->last, sizeof ui->last); /* as it read when touched */
        if (k.kind == KIOSK_UI_COLLAPSE) {
            snprintf(ui->last, sizeof ui->last, "%s",
                     lang_text(ui->lang, ui->collapsed ? L_KIOSK_HIDE : L_KIOSK_SHOW));
        }
    }
    return a->act != KIOSK_UI_ACT_NONE;
}

bool kiosk_ui_busy(const kiosk_ui *ui)
{
    return ui->pressed >= 0;
}

void kiosk_ui_dial_point(const kiosk_ui *ui, float speed_ms, float *x, float *y)
{
    float a = kiosk_ui_dial_angle(speed_ms), r = 0.5f * (ui->dial_r0 + ui->dial_r1);
    *x = ui->dial_cx + r * sinf(a);
    *y = ui->dial_cy - r * cosf(a);
}

void kiosk_ui_compass_point(const kiosk_ui *ui, float from_deg, float *x, float *y)
{
    float a = from_deg * 0.017453292f, r = 0.8f * ui->comp_r;
    *x = ui->comp_cx + r * sinf(a);
    *y = ui->comp_cy - r * cosf(a);
}

int kiosk_ui_find(const kiosk_ui *ui, int kind, int index)
{
    for (int i = 0; i < ui->n; i++) {
        if (ui->c[i].kind == kind && ui->c[i].index == index) {
            return i;
        }
    }
    return -1;
}

/* ---- words ------------------------------------------------------------------------------ */

void kiosk_ui_label(const kiosk_ui *ui, const kiosk_ui_control *k, char *buf, unsigned cap)
{
    switch (k->kind) {
    case KIOSK_UI_SCENARIO:
        snprintf(buf, cap, "%s",
                 k->index >= 0 && k->index < ui->n_scen
                     ? lang_scenario_title(ui->lang, ui->scen[k->index].title)
                     : "?");
        break;
    case KIOSK_UI_PLAY:
        snprintf(buf, cap, "%s", lang_text(ui->lang, ui->paused ? L_KIOSK_PLAY : L_KIOSK_PAUSE));
        break;
    case KIOSK_UI_LANDFALL:
        snprintf(buf, cap, "%s", lang_text(ui->lang, L_KIOSK_LANDFALL));
        break;
    case KIOSK_UI_LANG:
        snprintf(buf, cap, "%s", lang_text(k->index, L_LANG_NAME));
        break;
    case KIOSK_UI_SPEED:
        snprintf(buf, cap, "\xC3\x97%.0f", (double)kiosk_ui_speed_x(k->index));
        break;
    case KIOSK_UI_RESET:
        snprintf(buf, cap, "%s", lang_text(ui->lang, L_KIOSK_RESET));
        break;
    case KIOSK_UI_COLLAPSE:
        snprintf(buf, cap, "%s", lang_text(ui->lang, ui->collapsed ? L_KIOSK_SHOW : L_KIOSK_HIDE));
        break;
    case KIOSK_UI_PAGE:
        snprintf(buf, cap, "%s", lang_text(ui->lang, k->index ? L_KIOSK_NEXT : L_KIOSK_PREVIOUS));
        break;
    case KIOSK_UI_DIAL:
        snprintf(buf, cap, "%s", lang_text(ui->lang, L_KIOSK_WIND_SPEED));
        break;
    case KIOSK_UI_COMPASS:
        lang_format(buf, cap, ui->lang, L_KIOSK_WIND_FROM, "");
        break;
    default:
        snprintf(buf, cap, "?");
        break;
    }
}

void kiosk_ui_scen_heading(const kiosk_ui *ui, char *buf, unsigned cap)
{
    if (ui->n_pages <= 1 || ui->page >= ui->n_pages) {
        snprintf(buf, cap, "%s", lang_text(ui->lang, L_KIOSK_CHOOSE));
        return;
    }
    bool replays = ui->scen[ui->order[ui->page_start[ui->page]]].replay;
    lang_format(buf, cap, ui->lang, L_KIOSK_PAGE,
                lang_text(ui->lang, replays ? L_KIOSK_STORM_REPLAYS : L_KIOSK_STEADY_WINDS),
                ui->page + 1, ui->n_pages);
}

void kiosk_ui_describe(const kiosk_ui *ui, char *buf, unsigned cap)
{
    char wind[96], run[96] = "", rep[64] = "", last[80] = "";
    bool dial = ui->pressed >= 0 && ui->c[ui->pressed].kind == KIOSK_UI_DIAL;
    float v = dial ? ui->drag_ms : ui->wind_ms;
    snprintf(wind, sizeof wind, "%s %.0f m/s (%s) from %s", dial ? "dialling" : "wind",
             (double)v, kiosk_ui_band_label(kiosk_ui_band(v)), hud_compass_point(ui->dir_from_deg));
    if (ui->running >= 0) {
        snprintf(run, sizeof run, " \xC2\xB7 running %s", ui->scen[ui->running].title);
    }
    if (ui->replay) {
        snprintf(rep, sizeof rep, " \xC2\xB7 replay \xC3\x97%.0f %s", (double)ui->replay_speed,
                 ui->paused ? "paused" : "playing");
    }
    if (ui->last[0]) {
        snprintf(last, sizeof last, " \xC2\xB7 last touch %s", ui->last);
    }
    snprintf(buf, cap, "Panel: %s%s%s%s%s", ui->collapsed ? "hidden \xC2\xB7 " : "", wind, run,
             rep, last);
}
