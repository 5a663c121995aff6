/* A scenario driving the real wind grid: the grid's wind at the centre of an empty
 * domain settles to the scenario's speed at 10 m and blows the way the scenario says
 * (the direction conventions of scenario.h and wind.h agree), and a kiosk dial moves it. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "scenario.h"
#include "wind.h"

/* Runs s on a 32 × 32 × 12 grid of 2 m cells for `seconds` and returns the mean over the
 * last quarter of the wind at the centre, 10 m up. */
static void settle(scenario *s, wind_grid *w, double t0, double seconds, float mean[3])
{
    const double dt = 0.1;
    int n = (int)lround(seconds / dt), counted = 0;
    float c[3] = { 0.0f, 0.0f, 10.0f };
    memset(mean, 0, 3 * sizeof *mean);
    for (int i = 0; i < n; i++) {
        scenario_apply(s, w, t0 + i * dt, NULL);
        CHECK(wind_step(w, (float)dt, NULL) == 0);
        if (i >= 3 * n / 4) {
            float v[3];
            wind_sample(w, c, v);
            for (int k = 0; k < 3; k++) {
                mean[k] += v[k];
            }
            counted++;
        }
    }
    for (int k = 0; k < 3; k++) {
        mean[k] /= (float)counted;
    }
}

static void test_steady_on_grid(void)
{
    const char *json = "{\"seed\":5,\"steady\":{\"u10_ms\":8,\"dir_from_deg\":270},"
                       "\"gust\":{\"enabled\":false}}";
    gale_err err = { 0 };
    scenario *s = scenario_parse("grid.json", json, strlen(json), &err);
    wind_grid *w = wind_create(&(wind_desc){ .nx = 32,
                                             .ny = 32,
                                             .nz = 12,
                                             .cell_m = 2.0f,
                                             .origin = { -32.0f, -32.0f, 0.0f },
                                             .seed = 5 },
                               &err);
    CHECK(s && w);
    if (!s || !w) {
        fprintf(stderr, "%s\n", err.msg);
        scenario_destroy(s);
        wind_destroy(w);
        return;
    }
    float m[3];
    /* from the west: toward +x at the log-law speed of 10 m, 8 m/s (±15 %) */
    settle(s, w, 0.0, 30.0, m);
    fprintf(stderr, "from 270: grid (%.2f, %.2f, %.2f) m/s\n", (double)m[0], (double)m[1],
            (double)m[2]);
    CHECK_NEAR(m[0], 8.0, 1.2);
    CHECK_NEAR(m[1], 0.0, 0.8);
    /* a kiosk holds 20 m/s from the north: toward −y */
    CHECK(scenario_set_dial(s, 20.0, &err) == 0);
    CHECK(scenario_set_direction(s, 0.0, &err) == 0);
    settle(s, w, 30.0, 40.0, m);
    fprintf(stderr, "dial 20 from 0: grid (%.2f, %.2f, %.2f) m/s\n", (double)m[0], (double)m[1],
            (double)m[2]);
    CHECK_NEAR(m[0], 0.0, 2.0);
    CHECK_NEAR(m[1], -20.0, 3.0);
    scenario_destroy(s);
    wind_destroy(w);
}

int main(void)
{
    RUN(test_steady_on_grid);
    return check_report();
}
