/* The kiosk's touch panel end to end: a headless gale-client kiosk (Xvfb + Mesa) on the
 * real gale-server is given synthetic touches (--touch) on the controls where
 * client/kiosk/kiosk_ui.c lays them out for its framebuffer; what it sends is read back from its
 * log ("kiosk sent {json}", decoded as the server decodes it), what the server did from
 * the WEATHER a viewer receives, and what the panel showed from the HUD text the client
 * prints:
 * - the compass (wind from the east) and a drag on the dial set the direction and the
 *   dialled speed; the panel's HUD line names them;
 * - during a replay, ×10 and "Go to landfall" change the replay's speed and position;
 * - pause sends replay_paused and reset a reset message (PROTOCOL.md "wind", "reset"); a
 *   server whose welcome lists scenarios holds the storm clock and goes back to the
 *   scene's first scenario from its start;
 * - a scenario button, when the welcome lists scenarios, switches to that scenario. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "ctl.h"
#include "kiosk_fixture.h"
#include "kiosk_ui.h"

#define FB_W 1280
#define FB_H 720

static kf_reader viewer;

/* The panel as the kiosk lays it out: the welcome's scenarios (read on a connection of
 * its own) and the replay state of the viewer's weather. */
static int panel(kiosk_ui *ui)
{
    kiosk_ui_init(ui);
    wsraw c = { .fd = -1 };
    if (wsraw_open(&c, kf_port, 0)) {
        return -1;
    }
    wsraw_text(&c, "{\"type\": \"hello\", \"protocol\": 1, \"role\": \"viewer\"}");
    uint8_t *m = NULL;
    size_t n = 0;
    int op = wsraw_recv(&c, &m, &n, 10000);
    ctl_msg w;
    int rc = op == 1 && m ? ctl_decode((const char *)m, n, CTL_MAX_SERVER_BYTES, &w, NULL, NULL)
                          : -1;
    free(m);
    wsraw_close(&c);
    if (rc != 0 || w.type != CTL_WELCOME) {
        return -1;
    }
    for (uint32_t i = 0; i < w.u.welcome.n_scenarios && i < KIOSK_UI_MAX_SCENARIOS; i++) {
        const ctl_scenario_info *s = &w.u.welcome.scenarios[i];
        kiosk_ui_set_scenario(ui, (int)i, s->name, s->title, s->kind == CTL_SCENARIO_REPLAY);
    }
    kiosk_ui_set_scenario_count(ui, (int)w.u.welcome.n_scenarios);
    ctl_msg_fini(&w);
    wire_weather x;
    if (!kf_reader_wait(&viewer, 10.0, NULL, 0, &x)) {
        return -1;
    }
    kiosk_ui_set_weather(ui, &x);
    kiosk_ui_layout(ui, FB_W, FB_H);
    return 0;
}

static void add(char *spec, size_t cap, const char *verb, float x, float y)
{
    size_t l = strlen(spec);
    snprintf(spec + l, cap - l, "%s %.1f,%.1f; ", verb, (double)x, (double)y);
}

static void add_wait(char *spec, size_t cap, int n)
{
    for (int i = 0; i < n; i++) {
        size_t l = strlen(spec);
        snprintf(spec + l, cap - l, "wait; ");
    }
}

static void tap_control(char *spec, size_t cap, const kiosk_ui *ui, int kind, int index)
{
    int i = kiosk_ui_find(ui, kind, index);
    CHECK(i >= 0);
    if (i >= 0) {
        const kiosk_ui_rect *r = &ui->c[i].r;
        add(spec, cap, "tap", 0.5f * (r->x0 + r->x1), 0.5f * (r->y0 + r->y1));
    }
}

typedef struct kiosk_run {
    pid_t pid;
    char log[300], out[300];
} kiosk_run;

static int start_kiosk_args(kiosk_run *k, const char *name, const char *touch,
                            const char *attract_s);

static int start_kiosk(kiosk_run *k, const char *name, const char *touch)
{
    return start_kiosk_args(k, name, touch, NULL);
}

static int start_kiosk_args(kiosk_run *k, const char *name, const char *touch,
                            const char *attract_s)
{
    char url[64], cache[300], size[32], token_file[300];
    /* the token from a file, as deploy/kiosk.sh gives it (out of the process list) */
    snprintf(token_file, sizeof token_file, "%s/kiosk-token", kf_dir);
    FILE *tf = fopen(token_file, "w");
    if (!tf) {
        return -1;
    }
    fprintf(tf, "%s\n", KIOSK_TOKEN);
    fclose(tf);
    snprintf(k->log, sizeof k->log, "%s/%s.log", kf_dir, name);
    snprintf(k->out, sizeof k->out, "%s/%s.out", kf_dir, name);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", kf_port);
    snprintf(cache, sizeof cache, "%s/cache", kf_dir);
    snprintf(size, sizeof size, "%dx%d", FB_W, FB_H);
    char *argv[] = { GALE_CLIENT_EXE, "--url", url, "--role", "kiosk", "--token-file", token_file,
                     "--headless", "--frames", "100000", "--size", size, "--wait", "120",
                     "--cache", cache, "--touch", (char *)touch,
                     attract_s ? "--attract" : NULL, (char *)attract_s, NULL };
    unlink(k->log);
    k->pid = kf_spawn(argv, k->log, k->out);
    return k->pid > 0 ? 0 : -1;
}

/* The messages the kiosk logged as sent, decoded (at most max). */
static int sent(const kiosk_run *k, ctl_msg *m, int max)
{
    FILE *f = fopen(k->log, "r");
    int n = 0;
    char line[2048];
    const char *tag = "gale-client: kiosk sent ";
    while (f && n < max && fgets(line, sizeof line, f)) {
        const char *p = strstr(line, tag);
        if (!p) {
            continue;
        }
        p += strlen(tag);
        size_t len = strcspn(p, "\n");
        gale_err err = { 0 };
        if (ctl_decode(p, len, CTL_MAX_CLIENT_BYTES, &m[n], NULL, &err) != 0) {
            fprintf(stderr, "undecodable: %.*s: %s\n", (int)len, p, err.msg);
            continue;
        }
        n++;
    }
    if (f) {
        fclose(f);
    }
    return n;
}

/* Stops the kiosk (SIGTERM: it ends its loop and prints its HUD text); the line starting
 * "Panel:" into panel_line. */
static void stop_kiosk(kiosk_run *k, char *panel_line, size_t cap)
{
    kill(k->pid, SIGTERM);
    int st = proc_wait_exit(k->pid, 30.0);
    CHECK(st == 0);
    if (st != 0) {
        proc_dump(k->log);
    }
    panel_line[0] = '\0';
    FILE *f = fopen(k->out, "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        if (!strncmp(line, "hud: Panel:", 11)) {
            line[strcspn(line, "\n")] = 0;
            snprintf(panel_line, cap, "%s", line + 5);
        }
    }
    if (f) {
        fclose(f);
    }
}

static bool dial_dir(const wire_weather *w, double v)
{
    return (w->flags & WIRE_WEATHER_DIAL) && fabs((double)w->sustained_ms - v) < 0.05 &&
           fabs((double)w->dir_from_deg - 90.0) < 1.0;
}

static void test_dial_and_compass(void)
{
    kiosk_ui ui;
    CHECK(panel(&ui) == 0);
    char spec[2048] = "";
    float x, y;
    add_wait(spec, sizeof spec, 2);
    kiosk_ui_compass_point(&ui, 90.0f, &x, &y);
    add(spec, sizeof spec, "tap", x, y);
    add_wait(spec, sizeof spec, 2);
    const float path[4] = { 10.0f, 20.0f, 28.0f, 33.0f };
    for (int i = 0; i < 4; i++) {
        kiosk_ui_dial_point(&ui, path[i], &x, &y);
        add(spec, sizeof spec, i == 0 ? "down" : i == 3 ? "up" : "move", x, y);
    }
    kiosk_run k;
    CHECK(start_kiosk(&k, "dial", spec) == 0);
    /* the compass's direction first, the dial's value on release last */
    ctl_msg m[16];
    int n = 0;
    double until = mono_s() + 120.0;
    while (mono_s() < until) {
        n = sent(&k, m, 16);
        if (n >= 2 && m[n - 1].u.wind.has_speed && !m[n - 1].u.wind.has_replay_at &&
            fabs((double)m[n - 1].u.wind.speed_ms - 33.0) < 0.3) {
            break;
        }
        usleep(100000);
    }
    CHECK(n >= 2);
    if (n < 2) {
        proc_dump(k.log);
        stop_kiosk(&k, spec, sizeof spec);
        return;
    }
    CHECK(m[0].type == CTL_WIND && m[0].u.wind.has_dir && !m[0].u.wind.has_speed);
    CHECK_NEAR(m[0].u.wind.dir_deg, 180.0, 0.5); /* from the east: towards the west */
    CHECK(strcmp(m[0].u.wind.token, KIOSK_TOKEN) == 0);
    const ctl_wind *last = &m[n - 1].u.wind;
    CHECK(last->has_speed && last->has_dir);
    CHECK_NEAR(last->speed_ms, 33.0, 0.3);
    /* the server holds what the kiosk dialled (the scenario's dial ramps at 4 m/s²) */
    wire_weather w;
    bool held = kf_reader_wait(&viewer, 30.0, dial_dir, last->speed_ms, &w);
    CHECK(held);
    if (!held) {
        fprintf(stderr, "  WEATHER %.2f m/s from %.0f, flags %#x\n", (double)w.sustained_ms,
                (double)w.dir_from_deg, w.flags);
    }
    usleep(3000000); /* the kiosk's next frames show it (a few frames a second under load) */
    char line[512];
    stop_kiosk(&k, line, sizeof line);
    char want[96];
    snprintf(want, sizeof want, "Panel: wind %.0f m/s (Cat 1) from E", (double)last->speed_ms);
    CHECK_STR_HAS(line, want);
    CHECK_STR_HAS(line, "last touch Wind speed");
}

static bool replay_at(const wire_weather *w, double speed)
{
    return (w->flags & WIRE_WEATHER_STORM) && fabs((double)w->replay_speed - speed) < 0.01 &&
           fabs((double)w->storm_min) < 3.0;
}

static void test_replay_controls(void)
{
    kiosk_ui ui;
    CHECK(panel(&ui) == 0);
    CHECK(ui.replay);
    char spec[2048] = "";
    add_wait(spec, sizeof spec, 2);
    tap_control(spec, sizeof spec, &ui, KIOSK_UI_SPEED, 1);
    add_wait(spec, sizeof spec, 1);
    tap_control(spec, sizeof spec, &ui, KIOSK_UI_LANDFALL, 0);
    kiosk_run k;
    CHECK(start_kiosk(&k, "replay", spec) == 0);
    /* ×10 and landfall: the storm at minute 0, running 10 storm seconds a second */
    wire_weather w;
    bool moved = kf_reader_wait(&viewer, 60.0, replay_at, 10.0, &w);
    CHECK(moved);
    if (!moved) {
        fprintf(stderr, "  WEATHER minute %.1f at x%.0f\n", (double)w.storm_min,
                (double)w.replay_speed);
        proc_dump(k.log);
    }
    ctl_msg m[16];
    int n = sent(&k, m, 16);
    CHECK(n == 2);
    if (n == 2) {
        CHECK(m[0].u.wind.has_replay_speed && m[0].u.wind.replay_speed == 10.0f);
        CHECK(m[1].u.wind.has_replay_at && m[1].u.wind.replay_at_min == 0.0f);
    }
    usleep(3000000); /* the kiosk's panel reads it */
    char line[512];
    stop_kiosk(&k, line, sizeof line);
    if (ui.n_scen > 0) { /* the running scenario is lit when the welcome lists them */
        CHECK_STR_HAS(line, "running Andrew 1992");
    }
    CHECK_STR_HAS(line, "replay \xC3\x97" "10 playing");
    CHECK_STR_HAS(line, "last touch Go to landfall");
}

/* Waits for the kiosk to have logged n messages as sent; how many it did. */
static int wait_sent(const kiosk_run *k, ctl_msg *m, int max, int n, double timeout_s)
{
    int got = 0;
    double until = mono_s() + timeout_s;
    while ((got = sent(k, m, max)) < n && mono_s() < until) {
        usleep(100000);
    }
    return got;
}

static bool paused(const wire_weather *w, double unused)
{
    (void)unused;
    return (w->flags & WIRE_WEATHER_PAUSED) != 0;
}

static bool restarted(const wire_weather *w, double unused)
{
    (void)unused;
    return (w->flags & WIRE_WEATHER_STORM) && !(w->flags & WIRE_WEATHER_PAUSED) &&
           w->storm_min < -40.0f;
}

/* Pause, then (another visitor) reset: the messages, and where the server knows them
 * (its welcome lists the scenarios it can switch to) what it did with them. */
static void test_pause_and_reset(void)
{
    kiosk_ui ui;
    CHECK(panel(&ui) == 0);
    const bool server_knows = ui.n_scen > 0;
    char spec[512] = "";
    add_wait(spec, sizeof spec, 2);
    tap_control(spec, sizeof spec, &ui, KIOSK_UI_PLAY, 0);
    kiosk_run k;
    CHECK(start_kiosk(&k, "pause", spec) == 0);
    ctl_msg m[4];
    CHECK(wait_sent(&k, m, 4, 1, 120.0) == 1);
    CHECK(m[0].type == CTL_WIND && m[0].u.wind.has_replay_paused && m[0].u.wind.replay_paused);
    wire_weather w, w2;
    if (server_knows) {
        CHECK(kf_reader_wait(&viewer, 20.0, paused, 0, &w));
        usleep(1000000);
        CHECK(kf_reader_wait(&viewer, 1.0, paused, 0, &w2));
        CHECK_NEAR(w2.storm_min, w.storm_min, 0.01); /* the storm's clock holds */
        usleep(3000000); /* the kiosk's panel reads it */
    }
    char line[512];
    stop_kiosk(&k, line, sizeof line);
    CHECK_STR_HAS(line, "last touch Pause");
    if (server_knows) {
        CHECK_STR_HAS(line, "paused");
    }
    /* the storm is past landfall now (test_replay_controls jumped there) */
    spec[0] = '\0';
    add_wait(spec, sizeof spec, 2);
    tap_control(spec, sizeof spec, &ui, KIOSK_UI_RESET, 0);
    CHECK(start_kiosk(&k, "reset", spec) == 0);
    CHECK(wait_sent(&k, m, 4, 1, 120.0) == 1);
    CHECK(m[0].type == CTL_RESET && strcmp(m[0].u.reset.token, KIOSK_TOKEN) == 0);
    if (server_knows) {
        /* back to the scene's first scenario from its start (minute -60), running */
        CHECK(kf_reader_wait(&viewer, 20.0, restarted, 0, &w));
    }
    stop_kiosk(&k, line, sizeof line);
    CHECK_STR_HAS(line, "last touch Reset");
}

static bool named(const wire_weather *w, double unused)
{
    (void)unused;
    return strcmp(w->name, "Charley 2004") == 0;
}

/* A scenario button (when the welcome lists them; Next to its page first): the server
 * switches to it. */
static void test_scenario_button(void)
{
    kiosk_ui ui;
    CHECK(panel(&ui) == 0);
    int charley = -1;
    for (int i = 0; i < ui.n_scen; i++) {
        charley = strcmp(ui.scen[i].name, "charley2004") == 0 ? i : charley;
    }
    if (charley < 0) {
        fprintf(stderr, "  the server lists no scenario charley2004 (%d listed): skipped\n",
                ui.n_scen);
        return;
    }
    char spec[256] = "";
    add_wait(spec, sizeof spec, 2);
    /* a library longer than a page: Next until Charley's page shows (it sends nothing) */
    for (int p = 0; p < ui.n_pages && kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, charley) < 0; p++) {
        int next = kiosk_ui_find(&ui, KIOSK_UI_PAGE, 1);
        CHECK(next >= 0);
        if (next < 0) {
            break;
        }
        const kiosk_ui_rect r = ui.c[next].r;
        kiosk_ui_action a;
        kiosk_ui_touch(&ui, KIOSK_UI_DOWN, 0.5f * (r.x0 + r.x1), 0.5f * (r.y0 + r.y1), &a);
        kiosk_ui_touch(&ui, KIOSK_UI_UP, 0.5f * (r.x0 + r.x1), 0.5f * (r.y0 + r.y1), &a);
        add(spec, sizeof spec, "tap", 0.5f * (r.x0 + r.x1), 0.5f * (r.y0 + r.y1));
        add_wait(spec, sizeof spec, 1);
    }
    tap_control(spec, sizeof spec, &ui, KIOSK_UI_SCENARIO, charley);
    kiosk_run k;
    CHECK(start_kiosk(&k, "scenario", spec) == 0);
    ctl_msg m[4];
    CHECK(wait_sent(&k, m, 4, 1, 120.0) == 1);
    CHECK(m[0].u.wind.has_scenario && strcmp(m[0].u.wind.scenario, "charley2004") == 0);
    wire_weather w;
    CHECK(kf_reader_wait(&viewer, 30.0, named, 0, &w));
    usleep(3000000); /* the kiosk's panel reads it */
    char line[512];
    stop_kiosk(&k, line, sizeof line);
    CHECK_STR_HAS(line, "running Charley 2004");
}

/* Attract mode: a kiosk nobody touches for its idle time (1 s here) drops its dial and
 * asks for the scene's own scenarios back (scenario ""), and the next touch only wakes it:
 * no control is sent for it. */
static void test_attract_wake(void)
{
    kiosk_ui ui;
    CHECK(panel(&ui) == 0);
    char spec[1024] = "";
    add_wait(spec, sizeof spec, 30);
    float x, y;
    kiosk_ui_dial_point(&ui, 40.0f, &x, &y);
    add(spec, sizeof spec, "tap", x, y);
    add_wait(spec, sizeof spec, 10);
    kiosk_run k;
    CHECK(start_kiosk_args(&k, "attract", spec, "1") == 0);
    double until = mono_s() + 60.0;
    while (mono_s() < until && proc_log_count(k.log, "attract mode: woken by a touch") < 1) {
        usleep(100000);
    }
    char line[512];
    stop_kiosk(&k, line, sizeof line);
    CHECK(proc_log_count(k.log, "attract mode: dial released, back to the scene's scenarios") == 1);
    CHECK(proc_log_count(k.log, "attract mode: woken by a touch") == 1);
    ctl_msg m[8];
    int n = sent(&k, m, 8);
    CHECK(n == 1);
    if (n >= 1) {
        CHECK(m[0].type == CTL_WIND && m[0].u.wind.release && m[0].u.wind.has_scenario &&
              m[0].u.wind.scenario[0] == '\0' && !m[0].u.wind.has_speed);
    }
    if (n != 1) {
        proc_dump(k.log);
    }
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        fprintf(stderr, "test_kiosk_ui_live: no display (run under xvfb-run); skipped\n");
        return 77;
    }
    kf_init("test_kiosk_ui_live");
    if (kf_start_server(NULL, NULL) != 0 || kf_reader_start(&viewer, "viewer", NULL) != 0) {
        fprintf(stderr, "gale-server did not start\n");
        return 1;
    }
    RUN(test_dial_and_compass);
    RUN(test_attract_wake);
    kf_reader_stop(&viewer);
    kf_stop_server();
    /* a replay of Andrew an hour before landfall */
    const char *extra[] = { "--scenario", GALE_SOURCE_DIR "/configs/scenarios/andrew1992.json",
                            "--start-min", "-60", NULL };
    if (kf_start_server(NULL, extra) != 0 || kf_reader_start(&viewer, "viewer", NULL) != 0) {
        fprintf(stderr, "gale-server did not start with the Andrew replay\n");
        return 1;
    }
    RUN(test_replay_controls);
    RUN(test_pause_and_reset);
    RUN(test_scenario_button);
    kf_reader_stop(&viewer);
    kf_stop_server();
    return check_report();
}
