/* gale-client's frame-time governor (client/render/governor.c) over fixed sequences of frame
 * times, one JSON object a line, for tests/web/test_governor_js.mjs to hold web/governor.js
 * to: each sequence's target and software flag, then per frame its time, the clock, whether
 * the step changed, the step and the two scales. The sequences step down, hold in the band,
 * step up, start low on a software renderer, and take bad frame times. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "governor.h"

static void run(const char *name, double target_ms, int software, const double *ms, int n,
                double dt_s)
{
    governor g;
    double t = 0.0;
    governor_init(&g, target_ms, software != 0, t);
    printf("{\"seq\":\"%s\",\"target_ms\":%.17g,\"software\":%s}\n", name, target_ms,
           software ? "true" : "false");
    for (int i = 0; i < n; i++) {
        t += dt_s > 0.0 ? dt_s : ms[i] * 1e-3;
        bool changed = governor_frame(&g, ms[i], t);
        printf("{\"ms\":%.17g,\"t_s\":%.17g,\"changed\":%s,\"step\":%d,\"lod\":%.9g,\"res\":%.9g}\n",
               isfinite(ms[i]) ? ms[i] : -1.0, t, changed ? "true" : "false", g.step,
               (double)governor_lod_scale(&g), (double)governor_res_scale(&g));
    }
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        printf("usage: gale-web-governor-table (prints the sequences as JSON lines)\n");
        return strcmp(argv[1], "--help") == 0 ? 0 : 2;
    }
    static double ms[400];
    /* slow, then fast, then in the band */
    for (int i = 0; i < 400; i++) {
        ms[i] = i < 120 ? 80.0 + (i % 7) : i < 300 ? 10.0 + (i % 3) : 33.0 + (i % 5);
    }
    run("down-up-hold", 33.0, 0, ms, 400, 0.0);
    run("software", 33.0, 1, ms + 200, 200, 0.05);
    run("off", 0.0, 0, ms, 50, 0.0);
    double bad[20];
    for (int i = 0; i < 20; i++) {
        bad[i] = i % 4 == 0 ? -5.0 : 90.0;
    }
    run("bad", 20.0, 0, bad, 20, 0.2);
    return 0;
}
