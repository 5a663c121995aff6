/* The scenario library, playlist and kiosk controls on the real gale-server, read back
 * through the WEATHER and DAMAGE frames a viewer receives (server/SERVER.md "Scenarios"):
 * - gale-ctl scenarios prints the welcome's list (the shipped scenarios folder);
 * - a kiosk switches to andrew1992 at run time and WEATHER names it; "" goes back to the
 *   scene's scenario; an unknown name is refused (4002) with the valid names listed;
 * - replay --pause holds the storm clock (storm_min constant over a second, the PAUSED
 *   flag) and --play runs it again;
 * - a jump from Andrew's eyewall into the eye starts the 3-s gust window over;
 * - with a playlist of two short test-local replays, the next starts when one finishes
 *   and the list loops; reset heals the forest (an empty whole DAMAGE state), drops the
 *   dial and goes back to the playlist's head; a viewer's reset is refused (4006); a
 *   kiosk's pick ends after the kiosk idle time (attract), back to the playlist. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "kiosk_fixture.h"

#ifndef GALE_CTL_EXE
#error "GALE_CTL_EXE (path of gale-ctl) must be defined by the build"
#endif

/* gale-ctl with the token and cmd; its stdout into out (NULL: the log). Exit status. */
static int ctl_out(const char *const *cmd, const char *out)
{
    char log[300], url[64];
    snprintf(log, sizeof log, "%s/ctl.log", kf_dir);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", kf_port);
    const char *argv[16] = { GALE_CTL_EXE, "--url", url, "--token", KIOSK_TOKEN };
    int n = 5;
    for (int i = 0; cmd[i] && n < 15; i++) {
        argv[n++] = cmd[i];
    }
    argv[n] = NULL;
    pid_t p = kf_spawn((char *const *)argv, log, out);
    int st = proc_wait_exit(p, 30.0);
    if (st != 0) {
        proc_dump(log);
    }
    return st;
}

static int ctl(const char *const *cmd)
{
    return ctl_out(cmd, NULL);
}

static const char *want_name; /* what named() waits for */
static kf_reader viewer;       /* on the first server */

static bool named(const wire_weather *w, double arg)
{
    (void)arg;
    return strcmp(w->name, want_name) == 0;
}

static bool wait_name(kf_reader *r, const char *name, double timeout_s, wire_weather *w)
{
    want_name = name;
    return kf_reader_wait(r, timeout_s, named, 0, w);
}

static bool a_short(const wire_weather *w, double arg)
{
    (void)arg;
    return strncmp(w->name, "Short ", 6) == 0;
}

static bool paused(const wire_weather *w, double arg)
{
    (void)arg;
    return (w->flags & WIRE_WEATHER_PAUSED) != 0;
}

static bool running(const wire_weather *w, double arg)
{
    (void)arg;
    return (w->flags & WIRE_WEATHER_STORM) && !(w->flags & WIRE_WEATHER_PAUSED);
}

static bool storm_near(const wire_weather *w, double min)
{
    return (w->flags & WIRE_WEATHER_STORM) && fabs((double)w->storm_min - min) < 1.0;
}

static bool dial_on(const wire_weather *w, double arg)
{
    (void)arg;
    return (w->flags & WIRE_WEATHER_DIAL) != 0;
}

static bool gust_above(const wire_weather *w, double v)
{
    return (double)w->gust_ms > v;
}

static bool gust_below(const wire_weather *w, double v)
{
    return (double)w->gust_ms < v;
}

/* The welcome's list as gale-ctl prints it: the shipped scenarios, Categories included. */
static void test_list(void)
{
    char out[300];
    snprintf(out, sizeof out, "%s/scenarios.txt", kf_dir);
    CHECK(ctl_out((const char *[]){ "scenarios", NULL }, out) == 0);
    CHECK(proc_log_count(out, "andrew1992\treplay\t0.0\tAndrew 1992") == 1);
    CHECK(proc_log_count(out, "charley2004\treplay\t0.0\tCharley 2004") == 1);
    CHECK(proc_log_count(out, "cat4\tsteady\t64.0\tCategory 4 (steady)") == 1);
    CHECK(proc_log_count(out, "calm\tsteady\t0.8\tCalm") == 1);
    CHECK(proc_log_count(out, "katrina2005\treplay\t0.0\tKatrina 2005") == 1);
    CHECK(proc_log_count(out, "laborday1935\treplay\t0.0\tLabor Day 1935") == 1);
    CHECK(proc_log_count(out, "\t") >= 25);
}

/* Switch to Andrew at run time, pause and play its clock, then "" back to the scene's. */
static void test_switch_pause(void)
{
    kf_reader *v = &viewer;
    wire_weather w;
    CHECK(wait_name(v, "Gusty afternoon", 10.0, &w));
    CHECK(ctl((const char *[]){ "scenario", "andrew1992", NULL }) == 0);
    CHECK(wait_name(v, "Andrew 1992", 5.0, &w));
    CHECK(w.flags & WIRE_WEATHER_STORM);
    CHECK(ctl((const char *[]){ "replay", "--at", "-60", "--speed", "50", NULL }) == 0);
    CHECK(kf_reader_wait(v, 5.0, storm_near, -59.0, &w));
    /* paused: the storm clock holds */
    CHECK(ctl((const char *[]){ "replay", "--pause", NULL }) == 0);
    CHECK(kf_reader_wait(v, 5.0, paused, 0, &w));
    const float held = w.storm_min;
    usleep(1200000);
    CHECK(kf_reader_wait(v, 1.0, paused, 0, &w));
    CHECK(w.storm_min == held);
    /* played: at x50 a second is 0.83 storm minutes */
    CHECK(ctl((const char *[]){ "replay", "--play", NULL }) == 0);
    CHECK(kf_reader_wait(v, 5.0, running, 0, &w));
    usleep(1200000);
    CHECK(kf_reader_wait(v, 1.0, running, 0, &w));
    CHECK(w.storm_min > held + 0.5f);
    CHECK(ctl((const char *[]){ "scenario", "", NULL }) == 0);
    CHECK(wait_name(v, "Gusty afternoon", 5.0, &w));
    char slog[300];
    snprintf(slog, sizeof slog, "%s/server.log", kf_dir);
    CHECK(proc_log_count(slog, "scenario Andrew 1992 (picked by a kiosk)") == 1);
}

/* An unknown name: 4002, the valid names in the reason. */
static void test_bad_name(void)
{
    wsraw k = { .fd = -1 };
    CHECK(kf_hello(&k, "kiosk", KIOSK_TOKEN) == 0);
    wsraw_text(&k, "{\"type\": \"wind\", \"token\": \"" KIOSK_TOKEN "\", \"scenario\": \"andrew1993\"}");
    /* the error message before the close carries the whole reason (a close frame's
     * reason is cut at 123 bytes) */
    char err_text[1024] = "";
    for (int i = 0; i < 200 && !err_text[0]; i++) {
        uint8_t *m;
        size_t n;
        int op = wsraw_recv(&k, &m, &n, 5000);
        if (op == 1 && m && strstr((const char *)m, "\"error\"")) {
            snprintf(err_text, sizeof err_text, "%.*s", (int)n, (const char *)m);
        }
        free(m);
        if (op < 0 || op == 8) {
            break;
        }
    }
    CHECK_STR_HAS(err_text, "wind.scenario: \\\"andrew1993\\\": unknown; one of: andrew1992, "
                            "breeze, calm, ");
    CHECK_STR_HAS(err_text, ", ...");
    CHECK(wsraw_wait_close(&k, 5000) == WIRE_CLOSE_BAD_FIELD);
    CHECK_STR_HAS(k.close_reason, "wind.scenario: \"andrew1993\": unknown; one of: andrew1992");
    /* the log has them all */
    char slog[300];
    snprintf(slog, sizeof slog, "%s/server.log", kf_dir);
    CHECK(proc_log_count(slog, "wind.scenario \"andrew1993\" refused: the scenarios are andrew1992, "
                             "breeze, calm, camille1969, cat1, cat2, cat3, cat3-synthetic, cat4, "
                             "cat5, charley2004, gusty, harvey2017, hugo1989, ian2022, ida2021, "
                             "ike2008, irma2017, katrina2005, laborday1935, laura2020, maria2017, "
                             "michael2018, storm, wilma2005") == 1);
    wsraw_close(&k);
    /* a pick of a steady scenario with a replay field is refused whole: no pick made */
    wsraw k2 = { .fd = -1 };
    CHECK(kf_hello(&k2, "kiosk", KIOSK_TOKEN) == 0);
    wsraw_text(&k2, "{\"type\": \"wind\", \"token\": \"" KIOSK_TOKEN "\", \"scenario\": \"cat4\", "
                    "\"replay_at_min\": 0}");
    CHECK(wsraw_wait_close(&k2, 5000) == WIRE_CLOSE_BAD_FIELD);
    CHECK_STR_HAS(k2.close_reason, "wind.replay: \"cat4\" replays no storm");
    wsraw_close(&k2);
    CHECK(proc_log_count(slog, "scenario Category 4 (steady) (picked by a kiosk)") == 0);
}

/* Andrew's eyewall at storm speed 1 fills the gust window with ~57 m/s; a jump into the
 * eye must not carry that peak (it would for the window's 60 s). The wind ramps from the
 * eyewall's into the eye's at the dial's 4 m/s per second (scenario_ramp_from), ~14 s;
 * once there, the window holds the eye's winds only. */
static void test_gust_jump(void)
{
    kf_reader *v = &viewer;
    wire_weather w;
    CHECK(ctl((const char *[]){ "scenario", "andrew1992", NULL }) == 0);
    CHECK(ctl((const char *[]){ "replay", "--at", "-18", "--speed", "1", NULL }) == 0);
    CHECK(kf_reader_wait(v, 25.0, gust_above, 45.0, &w));
    CHECK(ctl((const char *[]){ "replay", "--at", "20", NULL }) == 0);
    /* the ramp: in the first weather of the eye's minute the wind the trees feel is still
       falling (57 m/s to the eye's ~2 at 4 m/s per second takes ~14 s) */
    CHECK(kf_reader_wait(v, 5.0, storm_near, 20.0, &w));
    fprintf(stderr, "  first weather after the jump into the eye: sustained %.1f m/s, gust %.1f m/s\n",
            (double)w.sustained_ms, (double)w.gust_ms);
    CHECK(w.sustained_ms > 10.0f);
    CHECK(kf_reader_wait(v, 25.0, gust_below, 10.0, &w));
    fprintf(stderr, "  after the ramp: sustained %.1f m/s, gust %.1f m/s\n",
            (double)w.sustained_ms, (double)w.gust_ms);
    CHECK(w.gust_ms < 10.0f);
    CHECK(ctl((const char *[]){ "scenario", "", NULL }) == 0);
}

/* A scene of its own beside a scenarios folder of its own (under the build tree): two
 * replays of 2.5 s and a steady Category 5, the playlist the two replays. */
static int write_playlist_scene(char *scene_path, size_t cap)
{
    char dir[400], path[500];
    snprintf(dir, sizeof dir, "%s/scenes", kf_dir);
    mkdir(dir, 0755);
    snprintf(dir, sizeof dir, "%s/scenarios", kf_dir);
    mkdir(dir, 0755);
    static const char *const names[] = { "short1", "short2" };
    for (int i = 0; i < 2; i++) {
        snprintf(path, sizeof path, "%s/%s.json", dir, names[i]);
        FILE *f = fopen(path, "w");
        if (!f) {
            return -1;
        }
        /* 60 storm minutes at x1440: 2.5 s */
        fprintf(f,
                "{\"name\": \"Short %d\", \"kind\": \"hurricane\", \"seed\": %d,\n"
                " \"hurricane\": {\"site\": {\"lat_deg\": 27.0}, \"time_scale\": 1440,\n"
                "  \"track\": [{\"t_min\": -30, \"x_km\": -5, \"y_km\": -40, \"p_hpa\": 960,"
                " \"rmax_km\": 20, \"vmax_ms\": 45},\n"
                "   {\"t_min\": 30, \"x_km\": -5, \"y_km\": 40, \"p_hpa\": 960, \"rmax_km\": 20,"
                " \"vmax_ms\": 45}]}}\n",
                i + 1, i + 1);
        fclose(f);
    }
    snprintf(path, sizeof path, "%s/gale.json", dir);
    FILE *f = fopen(path, "w");
    if (!f) {
        return -1;
    }
    /* the fastest ramp from the replay's wind (scenario_ramp_from), so it blows in a second */
    fprintf(f, "{\"name\": \"Gale\", \"kind\": \"steady\", \"dial_rate_ms2\": 100, \"steady\": {\"u10_ms\": 77,"
               " \"dir_from_deg\": 90}}\n");
    fclose(f);
    char cwd[400];
    if (!getcwd(cwd, sizeof cwd)) {
        return -1;
    }
    int k = snprintf(scene_path, cap, "%s/%s/scenes/playlist.json", cwd, kf_dir);
    if (k < 0 || (size_t)k >= cap) {
        return -1;
    }
    f = fopen(scene_path, "w");
    if (!f) {
        return -1;
    }
    fprintf(f,
            "{\"name\": \"playlist-test\", \"kiosk_token\": \"" KIOSK_TOKEN "\",\n"
            " \"playlist\": [\"short1\", \"short2\"],\n"
            " \"wind\": {\"solver\": false},\n"
            " \"species\": [{\"name\": \"palm\", \"file\": \"" GALE_SOURCE_DIR
            "/configs/species/palm.json\", \"modes\": 16}],\n"
            " \"trees\": [{\"species\": \"palm\", \"pos\": [0, 0]}, {\"species\": \"palm\", "
            "\"pos\": [6, 2], \"scale\": 0.9},\n"
            "  {\"species\": \"palm\", \"pos\": [-5, 4], \"scale\": 1.1}, {\"species\": \"palm\", "
            "\"pos\": [2, -6]}]}\n");
    fclose(f);
    return 0;
}

static void test_playlist_reset(void)
{
    char scene_path[1024];
    CHECK(write_playlist_scene(scene_path, sizeof scene_path) == 0);
    const char *extra[] = { "--kiosk-idle", "5", NULL };
    CHECK(kf_start_server(scene_path, extra) == 0);
    kf_reader v;
    wire_weather w;
    CHECK(kf_reader_start(&v, "viewer", NULL) == 0);
    /* the playlist plays in order and loops (2.5 s of storm each; the waits leave room for
     * a loaded machine, where the server's clock restarts behind the wall clock) */
    CHECK(wait_name(&v, "Short 1", 10.0, &w));
    CHECK(wait_name(&v, "Short 2", 15.0, &w));
    CHECK(wait_name(&v, "Short 1", 15.0, &w));
    CHECK(wait_name(&v, "Short 2", 15.0, &w));
    char slog[300];
    snprintf(slog, sizeof slog, "%s/server.log", kf_dir);
    CHECK(proc_log_count(slog, "scenario Short 1 (playlist entry 1 of 2)") >= 1);
    /* a steady Category 5 breaks palms; a dial holds the wind */
    CHECK(ctl((const char *[]){ "scenario", "gale", NULL }) == 0);
    CHECK(wait_name(&v, "Gale", 10.0, &w));
    CHECK(ctl((const char *[]){ "wind", "--speed", "80", NULL }) == 0);
    CHECK(kf_reader_wait(&v, 5.0, dial_on, 0, &w));
    usleep(2500000);
    pthread_mutex_lock(&v.lock);
    int events = v.dmg_events, empty = v.dmg_empty;
    pthread_mutex_unlock(&v.lock);
    fprintf(stderr, "  at 77-80 m/s for 2.5 s: %d damage events\n", events);
    CHECK(events > 0);
    /* a viewer may not reset */
    wsraw vw = { .fd = -1 };
    CHECK(kf_hello(&vw, "viewer", NULL) == 0);
    wsraw_text(&vw, "{\"type\": \"reset\", \"token\": \"" KIOSK_TOKEN "\"}");
    CHECK(wsraw_wait_close(&vw, 5000) == WIRE_CLOSE_FORBIDDEN);
    CHECK_STR_HAS(vw.close_reason, "reset: only a kiosk may reset the exhibit");
    wsraw_close(&vw);
    /* reset: healed (the whole, empty state), no dial, the playlist's head */
    CHECK(ctl((const char *[]){ "reset", NULL }) == 0);
    CHECK(wait_name(&v, "Short 1", 10.0, &w));
    CHECK(!(w.flags & WIRE_WEATHER_DIAL));
    /* the healed state follows the reset within a few ticks; a loaded (sanitizer) run may
     * deliver it after the first weather of the new scenario */
    int healed = 0;
    for (int i = 0; i < 100 && !healed; i++) {
        pthread_mutex_lock(&v.lock);
        healed = v.dmg_empty > empty;
        pthread_mutex_unlock(&v.lock);
        if (!healed) {
            usleep(50000);
        }
    }
    CHECK(healed);
    CHECK(proc_log_count(slog, "reset: the forest healed, scenario Short 1 from its start") == 1);
    CHECK(proc_log_count(slog, "kiosk dial released (reset)") == 1);
    /* and the playlist goes on from there */
    CHECK(wait_name(&v, "Short 2", 15.0, &w));
    /* attract: a pick nobody follows up ends after the kiosk idle time (5 s here) */
    CHECK(ctl((const char *[]){ "scenario", "gale", NULL }) == 0);
    CHECK(wait_name(&v, "Gale", 10.0, &w));
    CHECK(proc_wait_log(slog, "(the playlist)", 1, 10.0));
    CHECK(kf_reader_wait(&v, 5.0, a_short, 0, &w));
    kf_reader_stop(&v);
    kf_stop_server();
}

int main(void)
{
    kf_init("test_kiosk_scenarios");
    if (kf_start_server(NULL, NULL) != 0) {
        fprintf(stderr, "gale-server did not start\n");
        return 1;
    }
    CHECK(kf_reader_start(&viewer, "viewer", NULL) == 0);
    RUN(test_list);
    RUN(test_switch_pause);
    RUN(test_bad_name);
    RUN(test_gust_jump);
    kf_reader_stop(&viewer);
    kf_stop_server();
    RUN(test_playlist_reset);
    return check_report();
}
