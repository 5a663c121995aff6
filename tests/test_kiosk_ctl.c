/* Scripting a kiosk on the real gale-server, read back through the
 * WEATHER a viewer receives:
 * - gale-ctl wind holds a dial that outlives gale-ctl; gale-ctl release drops it;
 * - a kiosk's own dial is released when that kiosk disconnects, and when it idles out
 *   (--kiosk-idle);
 * - a viewer's wind command is refused (4006), and so is gale-ctl with a wrong token;
 * - gale-server --scenario FILE --start-min M --replay-speed X replays from minute M at X
 *   without an edited file; gale-ctl replay --at landfall --speed X jumps and changes
 *   speed, gale-ctl reset goes back to that start; an unknown scenario name is refused,
 *   gale-ctl naming the server's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "kiosk_fixture.h"

#ifndef GALE_CTL_EXE
#error "GALE_CTL_EXE (path of gale-ctl) must be defined by the build"
#endif

static int ctl(const char *token, const char *const *cmd)
{
    char log[300], url[64];
    snprintf(log, sizeof log, "%s/ctl.log", kf_dir);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", kf_port);
    const char *argv[16] = { GALE_CTL_EXE, "--url", url, "--token", token };
    int n = 5;
    for (int i = 0; cmd[i] && n < 15; i++) {
        argv[n++] = cmd[i];
    }
    argv[n] = NULL;
    pid_t p = kf_spawn((char *const *)argv, log, NULL);
    int st = proc_wait_exit(p, 30.0);
    if (st != 0) {
        proc_dump(log);
    }
    return st;
}

static bool dial_at(const wire_weather *w, double v)
{
    return (w->flags & WIRE_WEATHER_DIAL) && fabs((double)w->sustained_ms - v) < 0.05;
}

static bool no_dial(const wire_weather *w, double v)
{
    (void)v;
    return !(w->flags & WIRE_WEATHER_DIAL);
}

static bool dial_on(const wire_weather *w, double v)
{
    (void)v;
    return (w->flags & WIRE_WEATHER_DIAL) != 0;
}

static bool storm_near(const wire_weather *w, double min)
{
    return (w->flags & WIRE_WEATHER_STORM) && fabs((double)w->storm_min - min) < 3.0;
}

static kf_reader viewer;

static void test_ctl_dial_release(void)
{
    wire_weather w;
    CHECK(ctl(KIOSK_TOKEN, (const char *[]){ "wind", "--speed", "40", "--dir", "90", NULL }) == 0);
    CHECK(kf_reader_wait(&viewer, 20.0, dial_at, 40.0, &w));
    CHECK_NEAR(w.dir_from_deg, 90.0, 0.5);
    /* gale-ctl has hung up; the kept dial holds */
    usleep(500000);
    CHECK(kf_reader_wait(&viewer, 1.0, dial_at, 40.0, &w));
    CHECK(ctl(KIOSK_TOKEN, (const char *[]){ "release", NULL }) == 0);
    CHECK(kf_reader_wait(&viewer, 5.0, no_dial, 0, &w));
}

static void test_disconnect_releases(void)
{
    kf_reader k;
    wire_weather w;
    CHECK(kf_reader_start(&k, "kiosk", KIOSK_TOKEN) == 0);
    CHECK(wsraw_text(&k.c, "{\"type\": \"wind\", \"token\": \"" KIOSK_TOKEN "\", \"speed_ms\": 25}") == 0);
    CHECK(kf_reader_wait(&viewer, 20.0, dial_at, 25.0, &w));
    kf_reader_stop(&k); /* the visitor's kiosk goes away */
    CHECK(kf_reader_wait(&viewer, 5.0, no_dial, 0, &w));
    char slog[300];
    snprintf(slog, sizeof slog, "%s/server.log", kf_dir);
    CHECK(proc_wait_log(slog, "kiosk dial released (its kiosk disconnected)", 1, 2.0));
}

static void test_refusals(void)
{
    wsraw v = { .fd = -1 };
    CHECK(kf_hello(&v, "viewer", NULL) == 0);
    wsraw_text(&v, "{\"type\": \"wind\", \"token\": \"" KIOSK_TOKEN "\", \"speed_ms\": 50}");
    CHECK(wsraw_wait_close(&v, 5000) == WIRE_CLOSE_FORBIDDEN);
    CHECK_STR_HAS(v.close_reason, "only a kiosk may steer the wind");
    wsraw_close(&v);
    char log[300];
    snprintf(log, sizeof log, "%s/ctl.log", kf_dir);
    CHECK(ctl(KIOSK_TOKEN, (const char *[]){ "scenario", "charley2005", NULL }) == 1);
    CHECK(proc_log_count(log, "\"charley2005\": unknown; one of: andrew1992") == 1);
    CHECK(proc_log_count(log, "the server's scenarios: andrew1992, breeze, calm, camille1969, cat1, "
                            "cat2, cat3, cat3-synthetic, cat4, cat5, charley2004, gusty, "
                            "harvey2017, hugo1989, ian2022, ida2021, ike2008, irma2017, "
                            "katrina2005, laborday1935, laura2020, maria2017, michael2018, storm, "
                            "wilma2005") == 1);
    CHECK(ctl(KIOSK_TOKEN, (const char *[]){ "replay", "--at", "landfall", NULL }) == 1);
    CHECK(proc_log_count(log, "replays no storm") == 1);
    CHECK(ctl(KIOSK_TOKEN, (const char *[]){ "wind", "--speed", "500", NULL }) == 2);
    /* last: wrong tokens make the server delay this address's next kiosk checks */
    CHECK(ctl("wrong", (const char *[]){ "wind", "--speed", "50", NULL }) == 1);
    CHECK(proc_log_count(log, "wrong kiosk token") >= 1);
}

/* A second server: Andrew from storm minute -30 at x10, kiosks idle out after 2 s. */
static void test_replay_and_idle(void)
{
    const char *extra[] = { "--scenario", GALE_SOURCE_DIR "/configs/scenarios/andrew1992.json",
                            "--start-min", "-30", "--replay-speed", "10", "--kiosk-idle", "2",
                            NULL };
    CHECK(kf_start_server(NULL, extra) == 0);
    kf_reader v;
    wire_weather w;
    CHECK(kf_reader_start(&v, "viewer", NULL) == 0);
    CHECK(kf_reader_wait(&v, 10.0, storm_near, -30.0, &w));
    CHECK(strcmp(w.name, "Andrew 1992") == 0);
    CHECK_NEAR(w.replay_speed, 10.0, 1e-3);
    CHECK(w.flags & WIRE_WEATHER_CLOCK);
    CHECK(w.utc_offset_min == -240);
    CHECK(ctl(KIOSK_TOKEN, (const char *[]){ "replay", "--at", "landfall", "--speed", "50", NULL }) == 0);
    CHECK(kf_reader_wait(&v, 10.0, storm_near, 1.0, &w));
    CHECK_NEAR(w.replay_speed, 50.0, 1e-3);
    /* idle release: a connected kiosk that sends nothing more */
    kf_reader k;
    CHECK(kf_reader_start(&k, "kiosk", KIOSK_TOKEN) == 0);
    CHECK(wsraw_text(&k.c, "{\"type\": \"wind\", \"token\": \"" KIOSK_TOKEN "\", \"speed_ms\": 5}") == 0);
    CHECK(kf_reader_wait(&v, 10.0, dial_on, 0, &w));
    CHECK(kf_reader_wait(&v, 8.0, no_dial, 0, &w));
    pthread_mutex_lock(&k.lock);
    CHECK(k.close_code == 0); /* released, not disconnected */
    pthread_mutex_unlock(&k.lock);
    char slog[300];
    snprintf(slog, sizeof slog, "%s/server.log", kf_dir);
    CHECK(proc_log_count(slog, "kiosk dial released (idle)") == 1);
    /* reset: back to the configured start (--start-min -30, x10), not the file's */
    CHECK(ctl(KIOSK_TOKEN, (const char *[]){ "reset", NULL }) == 0);
    CHECK(kf_reader_wait(&v, 10.0, storm_near, -30.0, &w));
    CHECK_NEAR(w.replay_speed, 10.0, 1e-3);
    kf_reader_stop(&k);
    kf_reader_stop(&v);
    kf_stop_server();
}

int main(void)
{
    kf_init("test_kiosk_ctl");
    if (kf_start_server(NULL, NULL) != 0) {
        fprintf(stderr, "gale-server did not start\n");
        return 1;
    }
    CHECK(kf_reader_start(&viewer, "viewer", NULL) == 0);
    RUN(test_ctl_dial_release);
    RUN(test_disconnect_releases);
    RUN(test_refusals);
    kf_reader_stop(&viewer);
    kf_stop_server();
    RUN(test_replay_and_idle);
    return check_report();
}
