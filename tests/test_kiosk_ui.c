/* The kiosk's touch panel without GL (client/kiosk/kiosk_ui.c, kiosk_ui_msg.c):
 * - at 1280x720, 1920x1080 and 3840x2160 (and 4:3 screens) every control lies inside the
 *   framebuffer, none overlaps or touches another or the camera button, each a touch target of
 *   at least 9 mm on a 24" panel (0.03 of the height);
 * - the dial's bands are the Beaufort and Saffir-Simpson classes of protocol/wind_scale.h,
 *   and its angle and speed map back and forth;
 * - touches: a tap or drag on the dial, a tap on the compass, a scenario, the replay
 *   controls, reset and the tab act (buttons on release, inside), and each action's
 *   control message says what PROTOCOL.md "wind" / "reset" expects. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "camera_button.h"
#include "check.h"
#include "ctl.h"
#include "kiosk_ui.h"
#include "lang.h"
#include "wind_scale.h"

static const char *const names[10] = { "calm", "gusty", "storm", "cat1", "cat2",
                                       "cat3", "cat4", "cat5", "andrew1992", "charley2004" };
static const char *const titles[10] = { "Calm",         "Gusty afternoon", "Tropical storm",
                                        "Cat 1 steady", "Cat 2 steady",    "Cat 3 steady",
                                        "Cat 4 steady", "Cat 5 steady",    "Andrew 1992",
                                        "Charley 2004" };

static void setup(kiosk_ui *ui, bool replay)
{
    kiosk_ui_init(ui);
    for (int i = 0; i < 10; i++) {
        kiosk_ui_set_scenario(ui, i, names[i], titles[i], i >= 8);
    }
    kiosk_ui_set_scenario_count(ui, 10);
    wire_weather w = { .sustained_ms = 30.0f, .dir_from_deg = 90.0f, .replay_speed = 50.0f };
    if (replay) {
        w.flags = WIRE_WEATHER_STORM;
        snprintf(w.name, sizeof w.name, "Andrew 1992");
    } else {
        snprintf(w.name, sizeof w.name, "Gusty afternoon");
    }
    kiosk_ui_set_weather(ui, &w);
}

/* a and b closer than gap pixels (a finger between two controls needs a gap) */
static bool overlap_gap(const kiosk_ui_rect *a, const kiosk_ui_rect *b, float gap)
{
    return a->x0 < b->x1 + gap && b->x0 < a->x1 + gap && a->y0 < b->y1 + gap &&
           b->y0 < a->y1 + gap;
}

static bool overlap(const kiosk_ui_rect *a, const kiosk_ui_rect *b)
{
    return overlap_gap(a, b, 0.0f);
}

static void check_layout(int w, int h, bool replay)
{
    kiosk_ui ui;
    setup(&ui, replay);
    kiosk_ui_layout(&ui, w, h);
    int want = 2 + 10 + 1 + 1 + LANG_COUNT + (replay ? 2 + KIOSK_UI_SPEEDS : 0);
    CHECK(ui.n == want);
    camera_button_rect cb = camera_button_layout(w, h);
    kiosk_ui_rect cam = { cb.x0, cb.y0, cb.x1, cb.y1 };
    const float min_px = KIOSK_UI_MIN_TARGET_FRAC * (float)h;
    for (int i = 0; i < ui.n; i++) {
        const kiosk_ui_rect *r = &ui.c[i].r;
        bool inside = r->x0 >= 0.0f && r->y0 >= 0.0f && r->x1 <= (float)w && r->y1 <= (float)h;
        bool big = r->x1 - r->x0 >= min_px && r->y1 - r->y0 >= min_px;
        if (!inside || !big || overlap(r, &cam)) {
            fprintf(stderr, "%dx%d: control %d (kind %d, index %d) at %.0f,%.0f-%.0f,%.0f\n", w,
                    h, i, ui.c[i].kind, ui.c[i].index, (double)r->x0, (double)r->y0,
                    (double)r->x1, (double)r->y1);
        }
        CHECK(inside);
        CHECK(big);
        CHECK(!overlap(r, &cam));
        for (int j = i + 1; j < ui.n; j++) {
            /* apart by at least 0.005 of the height (5 px at 1080p) */
            bool near = overlap_gap(r, &ui.c[j].r, 0.005f * (float)h);
            if (near) {
                fprintf(stderr, "%dx%d: controls %d and %d overlap or touch\n", w, h, i, j);
            }
            CHECK(!near);
        }
        /* the middle of each control answers as that control */
        float mx = 0.5f * (r->x0 + r->x1), my = 0.5f * (r->y0 + r->y1);
        if (ui.c[i].kind == KIOSK_UI_DIAL) {
            kiosk_ui_dial_point(&ui, 40.0f, &mx, &my);
        }
        CHECK(kiosk_ui_hit(&ui, mx, my) == i);
    }
    /* the panel keeps to the bottom: the trees above it stay in view (a 4:3 screen
     * stacks the buttons higher) */
    CHECK(ui.panel_y0 >= (w * 9 == h * 16 ? 0.65f : 0.45f) * (float)h);
    /* 9 mm on a 24" 1080p panel (299 mm high) is 33 px */
    if (h == 1080) {
        CHECK(min_px <= 33.0f);
    }
}

static void test_layout_sizes(void)
{
    const int sizes[5][2] = { { 1280, 720 }, { 1920, 1080 }, { 3840, 2160 }, { 1280, 1024 },
                              { 1024, 768 } };
    for (int i = 0; i < 5; i++) {
        check_layout(sizes[i][0], sizes[i][1], true);
        check_layout(sizes[i][0], sizes[i][1], false);
    }
}

/* The same layout in proportion at every height of one aspect. */
static void test_layout_scales(void)
{
    kiosk_ui a, b;
    setup(&a, true);
    setup(&b, true);
    kiosk_ui_layout(&a, 1920, 1080);
    kiosk_ui_layout(&b, 3840, 2160);
    CHECK(a.n == b.n);
    for (int i = 0; i < a.n && i < b.n; i++) {
        CHECK_NEAR(2.0f * a.c[i].r.x0, b.c[i].r.x0, 0.5);
        CHECK_NEAR(2.0f * a.c[i].r.y1, b.c[i].r.y1, 0.5);
    }
}

static void test_bands(void)
{
    for (int b = 0; b < KIOSK_UI_BANDS; b++) {
        CHECK(kiosk_ui_band_lower_ms(b) < kiosk_ui_band_lower_ms(b + 1));
    }
    CHECK(strcmp(kiosk_ui_band_label(0), "Calm") == 0);
    CHECK(strcmp(kiosk_ui_band_label(3), "Tropical storm") == 0);
    CHECK(strcmp(kiosk_ui_band_label(8), "Cat 5") == 0);
    CHECK(strcmp(kiosk_ui_band_label(9), "?") == 0);
    /* every speed's band is its wind_scale class */
    for (float v = 0.0f; v <= KIOSK_UI_DIAL_MAX_MS; v += 0.05f) {
        int b = kiosk_ui_band(v), ss = wind_scale_ss_class(v), bf = wind_scale_beaufort(v);
        bool ok = b >= 3 ? ss == WIND_SCALE_TS + b - 3
                         : ss == WIND_SCALE_TD && (b == 0   ? bf <= 1
                                                   : b == 1 ? bf >= 2 && bf <= 5
                                                            : bf >= 6 && bf <= 8);
        if (!ok) {
            fprintf(stderr, "%.2f m/s: band %d, class %d, force %d\n", (double)v, b, ss, bf);
        }
        CHECK(ok);
        if (!ok) {
            break;
        }
        /* angle and speed, back and forth */
        CHECK_NEAR(kiosk_ui_dial_speed(kiosk_ui_dial_angle(v)), v, 0.01);
    }
    /* equal shares of the sweep, ends clamped */
    CHECK_NEAR(kiosk_ui_dial_angle(0.0f), -0.5f * KIOSK_UI_DIAL_SWEEP_RAD, 1e-5);
    CHECK_NEAR(kiosk_ui_dial_angle(200.0f), 0.5f * KIOSK_UI_DIAL_SWEEP_RAD, 1e-5);
    CHECK_NEAR(kiosk_ui_dial_angle((float)wind_scale_ss_lower_ms(WIND_SCALE_CAT1)),
               -0.5f * KIOSK_UI_DIAL_SWEEP_RAD + 4.0f * KIOSK_UI_DIAL_SWEEP_RAD / 9.0f, 1e-4);
    CHECK_NEAR(kiosk_ui_dial_speed(-10.0f), 0.0, 0.0);
    CHECK_NEAR(kiosk_ui_dial_speed(10.0f), KIOSK_UI_DIAL_MAX_MS, 0.0);
    /* the Beaufort lower edges behind the low bands */
    CHECK_NEAR(wind_scale_beaufort_lower_ms(0), 0.0, 0.0);
    CHECK(wind_scale_beaufort(wind_scale_beaufort_lower_ms(6)) == 6);
    CHECK(wind_scale_beaufort(wind_scale_beaufort_lower_ms(6) - 0.02) == 5);
    CHECK(wind_scale_beaufort_lower_ms(13) < 0.0);
}

/* The message of an action, encoded and decoded as the server would read it. */
static ctl_msg sent(kiosk_ui *ui, const kiosk_ui_action *a)
{
    ctl_msg m, back;
    memset(&back, 0, sizeof back);
    CHECK(kiosk_ui_message(ui, a, "tok", &m) == 0);
    char *json = NULL;
    size_t len = 0;
    gale_err err = { 0 };
    CHECK(ctl_encode(&m, &json, &len, &err) == 0);
    if (json) {
        CHECK(ctl_decode(json, len, 0, &back, NULL, &err) == 0);
        free(json);
    }
    return back;
}

static void tap(kiosk_ui *ui, float x, float y, kiosk_ui_action *a)
{
    kiosk_ui_touch(ui, KIOSK_UI_DOWN, x, y, a);
    kiosk_ui_touch(ui, KIOSK_UI_UP, x, y, a);
}

static void centre(const kiosk_ui *ui, int kind, int index, float *x, float *y)
{
    int i = kiosk_ui_find(ui, kind, index);
    CHECK(i >= 0);
    if (i < 0) {
        *x = *y = -1.0f;
        return;
    }
    *x = 0.5f * (ui->c[i].r.x0 + ui->c[i].r.x1);
    *y = 0.5f * (ui->c[i].r.y0 + ui->c[i].r.y1);
}

static void test_dial_touch(void)
{
    kiosk_ui ui;
    setup(&ui, false);
    kiosk_ui_layout(&ui, 1920, 1080);
    kiosk_ui_action a;
    float x, y;
    kiosk_ui_dial_point(&ui, 45.0f, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_SPEED && !a.dragging);
    CHECK_NEAR(a.value, 45.0, 0.3);
    ctl_msg m = sent(&ui, &a);
    CHECK(m.type == CTL_WIND && m.u.wind.has_speed && !m.u.wind.has_dir);
    CHECK_NEAR(m.u.wind.speed_ms, 45.0, 0.3);
    CHECK(strcmp(m.u.wind.token, "tok") == 0);
    /* a drag: values while the finger moves, the last on release */
    kiosk_ui_dial_point(&ui, 10.0f, &x, &y);
    CHECK(kiosk_ui_touch(&ui, KIOSK_UI_DOWN, x, y, &a) && a.dragging);
    CHECK(kiosk_ui_busy(&ui));
    kiosk_ui_dial_point(&ui, 62.0f, &x, &y);
    CHECK(kiosk_ui_touch(&ui, KIOSK_UI_MOVE, x, y, &a) && a.dragging);
    CHECK_NEAR(ui.drag_ms, 62.0, 0.3);
    char line[256];
    kiosk_ui_describe(&ui, line, sizeof line);
    CHECK_STR_HAS(line, "dialling 62 m/s (Cat 4)");
    kiosk_ui_dial_point(&ui, 72.0f, &x, &y);
    /* the finger may leave the ring while dragging: the angle still counts */
    CHECK(kiosk_ui_touch(&ui, KIOSK_UI_UP, x + 300.0f, y, &a) && !a.dragging);
    CHECK(a.act == KIOSK_UI_ACT_SPEED && a.value > 62.0f);
    CHECK(!kiosk_ui_busy(&ui));
    /* crossing the gap under the dial keeps the end the finger came from */
    kiosk_ui_dial_point(&ui, 80.0f, &x, &y);
    kiosk_ui_touch(&ui, KIOSK_UI_DOWN, x, y, &a);
    kiosk_ui_touch(&ui, KIOSK_UI_MOVE, ui.dial_cx + 5.0f, ui.dial_cy + 150.0f, &a);
    CHECK_NEAR(a.value, KIOSK_UI_DIAL_MAX_MS, 1e-3);
    kiosk_ui_touch(&ui, KIOSK_UI_MOVE, ui.dial_cx - 5.0f, ui.dial_cy + 150.0f, &a);
    CHECK_NEAR(a.value, KIOSK_UI_DIAL_MAX_MS, 1e-3);
    kiosk_ui_touch(&ui, KIOSK_UI_UP, ui.dial_cx - 5.0f, ui.dial_cy + 150.0f, &a);
    CHECK_NEAR(a.value, KIOSK_UI_DIAL_MAX_MS, 1e-3);
    /* the centre of the dial and a miss are not the dial */
    CHECK(!kiosk_ui_touch(&ui, KIOSK_UI_DOWN, ui.dial_cx, ui.dial_cy, &a));
    kiosk_ui_touch(&ui, KIOSK_UI_UP, ui.dial_cx, ui.dial_cy, &a);
    CHECK(!kiosk_ui_touch(&ui, KIOSK_UI_DOWN, 960.0f, 300.0f, &a) && a.act == KIOSK_UI_ACT_NONE);
    CHECK(!kiosk_ui_busy(&ui));
}

static void test_compass_touch(void)
{
    kiosk_ui ui;
    setup(&ui, false);
    kiosk_ui_layout(&ui, 1280, 720);
    kiosk_ui_action a;
    float x, y;
    kiosk_ui_compass_point(&ui, 90.0f, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_DIR);
    CHECK_NEAR(a.value, 90.0, 0.5);
    ctl_msg m = sent(&ui, &a);
    /* from the east = blowing towards the west: 180° from +x counter-clockwise */
    CHECK(m.u.wind.has_dir && !m.u.wind.has_speed);
    CHECK_NEAR(m.u.wind.dir_deg, 180.0, 0.5);
    /* a dialled speed then keeps the direction chosen, a new direction the speed */
    kiosk_ui_dial_point(&ui, 30.0f, &x, &y);
    tap(&ui, x, y, &a);
    m = sent(&ui, &a);
    CHECK(m.u.wind.has_speed && m.u.wind.has_dir);
    CHECK_NEAR(m.u.wind.dir_deg, 180.0, 0.5);
    kiosk_ui_compass_point(&ui, 225.0f, &x, &y);
    tap(&ui, x, y, &a);
    m = sent(&ui, &a);
    CHECK(m.u.wind.has_speed && m.u.wind.has_dir);
    CHECK_NEAR(m.u.wind.speed_ms, 30.0, 0.3);
    CHECK_NEAR(m.u.wind.dir_deg, 45.0, 0.5); /* from the south-west: towards the north-east */
}

static void test_buttons(void)
{
    kiosk_ui ui;
    setup(&ui, true);
    kiosk_ui_layout(&ui, 1920, 1080);
    CHECK(ui.running == 8); /* WEATHER names Andrew 1992 */
    kiosk_ui_action a;
    float x, y;
    centre(&ui, KIOSK_UI_SCENARIO, 9, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_SCENARIO && a.index == 9);
    ctl_msg m = sent(&ui, &a);
    CHECK(m.u.wind.has_scenario && strcmp(m.u.wind.scenario, "charley2004") == 0);
    CHECK(!m.u.wind.has_speed);
    centre(&ui, KIOSK_UI_SPEED, 1, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_REPLAY_SPEED);
    m = sent(&ui, &a);
    CHECK(m.u.wind.has_replay_speed && !m.u.wind.has_replay_at);
    CHECK_NEAR(m.u.wind.replay_speed, 10.0, 0.0);
    centre(&ui, KIOSK_UI_LANDFALL, 0, &x, &y);
    tap(&ui, x, y, &a);
    m = sent(&ui, &a);
    CHECK(m.u.wind.has_replay_at && !m.u.wind.has_replay_speed);
    CHECK_NEAR(m.u.wind.replay_at_min, 0.0, 0.0);
    centre(&ui, KIOSK_UI_PLAY, 0, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_PAUSE && a.value == 1.0f); /* playing: the button pauses */
    m = sent(&ui, &a);
    CHECK(m.type == CTL_WIND && m.u.wind.has_replay_paused && m.u.wind.replay_paused);
    CHECK(!m.u.wind.has_replay_at && !m.u.wind.has_replay_speed && !m.u.wind.has_speed);
    centre(&ui, KIOSK_UI_RESET, 0, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_RESET);
    m = sent(&ui, &a);
    CHECK(m.type == CTL_RESET && strcmp(m.u.reset.token, "tok") == 0);
    /* pressed state: lit while down; let go elsewhere, nothing happens */
    CHECK(!kiosk_ui_touch(&ui, KIOSK_UI_DOWN, x, y, &a));
    CHECK(ui.pressed == kiosk_ui_find(&ui, KIOSK_UI_RESET, 0));
    CHECK(!kiosk_ui_touch(&ui, KIOSK_UI_UP, x, y - 200.0f, &a) && a.act == KIOSK_UI_ACT_NONE);
    CHECK(ui.pressed == -1);
    /* what the HUD text says */
    wire_weather w = { .sustained_ms = 57.0f, .dir_from_deg = 270.0f, .replay_speed = 10.0f,
                       .flags = WIRE_WEATHER_STORM | WIRE_WEATHER_PAUSED };
    snprintf(w.name, sizeof w.name, "Andrew 1992");
    kiosk_ui_set_weather(&ui, &w);
    CHECK(ui.paused);
    char line[256];
    kiosk_ui_describe(&ui, line, sizeof line);
    CHECK_STR_HAS(line, "Panel: wind 57 m/s (Cat 3) from W");
    CHECK_STR_HAS(line, "running Andrew 1992");
    CHECK_STR_HAS(line, "replay \xC3\x97" "10 paused");
    CHECK_STR_HAS(line, "last touch Reset");
    /* paused: the button plays */
    centre(&ui, KIOSK_UI_PLAY, 0, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_PAUSE && a.value == 0.0f);
    m = sent(&ui, &a);
    CHECK(m.u.wind.has_replay_paused && !m.u.wind.replay_paused);
    /* without a replay: no replay controls, reset stays */
    w.flags = 0;
    kiosk_ui_set_weather(&ui, &w);
    kiosk_ui_layout(&ui, 1920, 1080);
    CHECK(kiosk_ui_find(&ui, KIOSK_UI_PLAY, 0) < 0);
    CHECK(kiosk_ui_find(&ui, KIOSK_UI_SPEED, 0) < 0);
    CHECK(kiosk_ui_find(&ui, KIOSK_UI_RESET, 0) >= 0);
}

static void test_collapse(void)
{
    kiosk_ui ui;
    setup(&ui, true);
    kiosk_ui_layout(&ui, 1920, 1080);
    kiosk_ui_action a;
    float x, y;
    centre(&ui, KIOSK_UI_COLLAPSE, 0, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_COLLAPSE && ui.collapsed);
    ctl_msg m;
    CHECK(kiosk_ui_message(&ui, &a, "tok", &m) == 1); /* the server is not told */
    CHECK(ui.n == 1 + LANG_COUNT && ui.c[0].kind == KIOSK_UI_COLLAPSE);
    CHECK(kiosk_ui_find(&ui, KIOSK_UI_LANG, LANG_HT) >= 0); /* a language, hidden or not */
    CHECK(ui.panel_y0 == 1080.0f);
    char line[256];
    kiosk_ui_describe(&ui, line, sizeof line);
    CHECK_STR_HAS(line, "Panel: hidden");
    centre(&ui, KIOSK_UI_COLLAPSE, 0, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(!ui.collapsed && ui.n > 10);
}

/* The language buttons: each in its own language's name, a tap switches the panel's words
 * (the client the rest: client_kiosk.c), and the server is not told. */
static void test_language(void)
{
    kiosk_ui ui;
    setup(&ui, true);
    kiosk_ui_layout(&ui, 1280, 720);
    char label[KIOSK_UI_NAME_CHARS];
    int es = kiosk_ui_find(&ui, KIOSK_UI_LANG, LANG_ES);
    CHECK(es >= 0);
    kiosk_ui_label(&ui, &ui.c[es], label, sizeof label);
    CHECK(strcmp(label, "Espa\xC3\xB1ol") == 0);
    const float min_px = KIOSK_UI_MIN_TARGET_FRAC * 720.0f;
    CHECK(ui.c[es].r.x1 - ui.c[es].r.x0 >= min_px && ui.c[es].r.y1 - ui.c[es].r.y0 >= min_px);
    kiosk_ui_action a;
    float x, y;
    centre(&ui, KIOSK_UI_LANG, LANG_ES, &x, &y);
    tap(&ui, x, y, &a);
    CHECK(a.act == KIOSK_UI_ACT_LANG && a.index == LANG_ES && ui.lang == LANG_ES);
    ctl_msg m;
    CHECK(kiosk_ui_message(&ui, &a, "tok", &m) == 1);
    kiosk_ui_label(&ui, &ui.c[kiosk_ui_find(&ui, KIOSK_UI_RESET, 0)], label, sizeof label);
    CHECK(strcmp(label, "Reiniciar") == 0);
    kiosk_ui_label(&ui, &ui.c[kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 1)], label, sizeof label);
    CHECK(strcmp(label, "Tarde con rachas") == 0);
    kiosk_ui_label(&ui, &ui.c[kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 8)], label, sizeof label);
    CHECK(strcmp(label, "Andrew 1992") == 0);
    CHECK(strcmp(kiosk_ui_band_name(LANG_HT, 0), "Kalm") == 0);
}

int main(void)
{
    RUN(test_layout_sizes);
    RUN(test_layout_scales);
    RUN(test_bands);
    RUN(test_dial_touch);
    RUN(test_compass_touch);
    RUN(test_buttons);
    RUN(test_collapse);
    RUN(test_language);
    return check_report();
}
