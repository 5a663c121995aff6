/* The HUD names the server's class: a kiosk dials steady 30, 45 and 60 m/s on
 * the real gale-server; once the server's WEATHER reports the dialled sustained wind, a
 * headless gale-client (Xvfb + Mesa) draws a few frames and prints the HUD text of its
 * last one; its wind line shows the server's sustained wind and its class line is the
 * server's class title (Tropical storm, Category 2, Category 4 hurricane). A viewer joining
 * gets a WEATHER with its first keyframe. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "hud.h"
#include "kiosk_fixture.h"
#include "wind_scale.h"

static bool near_dial(const wire_weather *w, double dial)
{
    return fabs((double)w->sustained_ms - dial) < 0.05 && (w->flags & WIRE_WEATHER_DIAL);
}

/* Runs a headless client; its "hud: " lines into lines[][] (count returned), -1 on a
 * failed run. */
static int run_client(const char *name, char lines[16][256])
{
    char log[300], out[300], url[64], cache[300];
    snprintf(log, sizeof log, "%s/%s.log", kf_dir, name);
    snprintf(out, sizeof out, "%s/%s.out", kf_dir, name);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", kf_port);
    snprintf(cache, sizeof cache, "%s/cache", kf_dir);
    char *argv[] = { GALE_CLIENT_EXE, "--url", url, "--headless", "--frames", "3", "--size",
                     "480x270", "--wait", "60", "--cache", cache, NULL };
    pid_t p = kf_spawn(argv, log, out);
    int st = proc_wait_exit(p, 120.0);
    if (st != 0) {
        fprintf(stderr, "gale-client exited %d\n", st);
        proc_dump(log);
        return -1;
    }
    FILE *f = fopen(out, "r");
    int n = 0;
    char line[256];
    while (f && n < 16 && fgets(line, sizeof line, f)) {
        if (!strncmp(line, "hud: ", 5)) {
            line[strcspn(line, "\n")] = 0;
            snprintf(lines[n++], 256, "%s", line + 5);
        }
    }
    if (f) {
        fclose(f);
    }
    return n;
}

static void test_dials(void)
{
    kf_reader k;
    CHECK(kf_reader_start(&k, "kiosk", KIOSK_TOKEN) == 0);
    const double dials[3] = { 30.0, 45.0, 60.0 };
    const char *want[3] = { "Tropical storm", "Category 2 hurricane", "Category 4 hurricane" };
    for (int i = 0; i < 3; i++) {
        char cmd[160];
        snprintf(cmd, sizeof cmd, "{\"type\": \"wind\", \"token\": \"" KIOSK_TOKEN "\", \"speed_ms\": %g}",
                 dials[i]);
        CHECK(wsraw_text(&k.c, cmd) == 0);
        wire_weather w;
        /* the dial ramps at 4 m/s per second (scenario dial_rate_ms2) */
        bool reached = kf_reader_wait(&k, 30.0, near_dial, dials[i], &w);
        CHECK(reached);
        if (!reached) {
            fprintf(stderr, "  dial %.0f: the server reports %.2f m/s\n", dials[i],
                    (double)w.sustained_ms);
            continue;
        }
        CHECK(strcmp(wind_scale_ss_title(w.ss_class), want[i]) == 0);
        char name[32], lines[16][256];
        snprintf(name, sizeof name, "client-%.0f", dials[i]);
        int n = run_client(name, lines);
        CHECK(n >= 3);
        if (n < 3) {
            continue;
        }
        /* the wind in the English HUD's first unit, within its class's mph range
         * (client/hud/hud_units.c): the dialled speed's own mph, or the range's end */
        char wind[64];
        snprintf(wind, sizeof wind, "Wind %ld mph",
                 hud_unit_sustained((double)w.sustained_ms, HUD_UNIT_MPH, (int)w.ss_class));
        CHECK_STR_HAS(lines[0], wind);
        /* the class line is the server's class, by its title */
        CHECK(strcmp(lines[1], wind_scale_ss_title(w.ss_class)) == 0);
        if (strcmp(lines[1], wind_scale_ss_title(w.ss_class)) != 0) {
            fprintf(stderr, "  HUD \"%s\", server class %u \"%s\"\n", lines[1], w.ss_class,
                    wind_scale_ss_title(w.ss_class));
        }
        CHECK_STR_HAS(lines[2], "dialled at the kiosk");
    }
    kf_reader_stop(&k);
}

/* A viewer that joins gets the weather right after its first keyframe. */
static void test_join(void)
{
    wsraw v = { .fd = -1 };
    CHECK(kf_hello(&v, "viewer", NULL) == 0);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 16, .max_modes = 32 },
                                          NULL);
    int frames = 0;
    bool key = false, weather_after_key = false;
    double until = mono_s() + 10.0;
    while (mono_s() < until && frames < 4 && !weather_after_key) {
        uint8_t *m;
        size_t n;
        int op = wsraw_recv(&v, &m, &n, 500);
        if (op == 2) {
            wire_frame f;
            if (wire_decode(d, m, n, &f, NULL) == 0) {
                frames++;
                /* apart (--no-bundle) or inside the keyframe's BUNDLE */
                key = key || (f.types & (1u << WIRE_MSG_KEYFRAME));
                weather_after_key = key && (f.types & (1u << WIRE_MSG_WEATHER));
            }
        }
        free(m);
    }
    CHECK(key);
    CHECK(weather_after_key); /* within the keyframe's snapshot: at most 3 frames after it */
    wire_decoder_destroy(d);
    wsraw_close(&v);
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        fprintf(stderr, "test_kiosk_weather: no display (run under xvfb-run); skipped\n");
        return 77;
    }
    kf_init("test_kiosk_weather");
    if (kf_start_server(NULL, NULL) != 0) {
        fprintf(stderr, "gale-server did not start\n");
        return 1;
    }
    RUN(test_join);
    RUN(test_dials);
    kf_stop_server();
    return check_report();
}
