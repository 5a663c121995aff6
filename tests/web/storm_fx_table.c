/* The storm look of client/render/storm_fx.c over a grid of winds, directions and qualities, one
 * JSON object a line, for tests/web/test_storm_fx_js.mjs to hold web/storm_fx.js to. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "storm_fx.h"

static void vec(const char *name, const float *v, int n)
{
    printf(",\"%s\":[", name);
    for (int k = 0; k < n; k++) {
        printf("%s%.9g", k ? "," : "", (double)v[k]);
    }
    printf("]");
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        bool help = strcmp(argv[1], "--help") == 0;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-storm-table\n"
                "  prints client/render/storm_fx.c's storm look for a grid of sustained winds [m/s],\n"
                "  directions [deg from] and qualities (0 off, 1 low, 2 high), one JSON a line\n");
        return help ? 0 : 2;
    }
    static const float ms[] = { 0.0f, 5.0f, 10.8f, 10.81f, 15.0f, 17.4f, 17.5f, 25.0f, 32.6f,
                                32.7f, 45.0f, 60.0f, 70.0f, 85.0f, 250.0f, NAN };
    static const float dir[] = { 0.0f, 90.0f, 225.0f, 300.0f };
    for (size_t i = 0; i < sizeof ms / sizeof ms[0]; i++) {
        for (size_t j = 0; j < sizeof dir / sizeof dir[0]; j++) {
            for (int q = 0; q < 3; q++) {
                storm_fx fx;
                storm_fx_from_weather(ms[i], dir[j], (storm_fx_quality)q, &fx);
                if (isnan(ms[i])) {
                    printf("{\"sustained_ms\":null");
                } else {
                    printf("{\"sustained_ms\":%.9g", (double)ms[i]);
                }
                printf(",\"dir_from_deg\":%.9g,\"q\":%d,\"intensity\":%.9g", (double)dir[j], q,
                       (double)fx.intensity);
                vec("sun_col", fx.sun_col, 3);
                vec("sky_zenith", fx.sky_zenith, 3);
                vec("sky_horizon", fx.sky_horizon, 3);
                vec("ground_col", fx.ground_col, 3);
                vec("wind_to", fx.wind_to, 2);
                printf(",\"fog_scale\":%.9g,\"rain\":%.9g,\"rain_layers\":%d,\"spray\":%.9g,"
                       "\"wet\":%.9g,\"subject_clear\":%.9g}\n",
                       (double)fx.fog_scale, (double)fx.rain, fx.rain_layers, (double)fx.spray,
                       (double)fx.wet, (double)fx.subject_clear);
            }
        }
    }
    return 0;
}
