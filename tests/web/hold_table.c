/* gale-client's reduced view (client/playout/hold.c) over fixed scenes, one JSON object a
 * line, for tests/web/test_hold_js.mjs to hold web/hold.js to: each scene's positions (as
 * the floats a welcome gives, to every digit), its centre, then per point and limit the
 * trees held, their radius and edge and a view's radius for a margin. The scenes: a grid
 * (distances tie everywhere), a random forest with fractional positions off the origin,
 * and trees all on one point. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hold.h"

#define MAX_TREES 1200

static uint32_t rng = 12345u;

static float uniform(float lo, float hi)
{
    rng = rng * 1664525u + 1013904223u; /* Numerical Recipes' LCG: a fixed sequence */
    return lo + (hi - lo) * (float)(rng >> 8) / (float)(1u << 24);
}

static void run(const char *name, const ctl_instance *inst, uint32_t n, const double *points,
                int n_points, const uint32_t *limits, int n_limits)
{
    printf("{\"scene\":\"%s\",\"xy\":[", name);
    for (uint32_t t = 0; t < n; t++) {
        printf("%s%.9g,%.9g", t ? "," : "", (double)inst[t].pos[0], (double)inst[t].pos[1]);
    }
    double c[2];
    hold_centre(inst, n, c);
    printf("],\"centre\":[%.17g,%.17g]}\n", c[0], c[1]);
    static uint32_t held[MAX_TREES];
    for (int p = 0; p <= n_points; p++) {
        /* the scene's centre first, then the points given */
        const double cx = p == 0 ? c[0] : points[2 * (p - 1)];
        const double cy = p == 0 ? c[1] : points[2 * (p - 1) + 1];
        for (int l = 0; l < n_limits; l++) {
            hold_circle h;
            if (hold_nearest(inst, n, cx, cy, limits[l], held, &h, NULL) != 0) {
                fprintf(stderr, "hold_table: hold_nearest failed\n");
                exit(1);
            }
            printf("{\"cx\":%.17g,\"cy\":%.17g,\"limit\":%u,\"n_held\":%u,\"radius_m\":%.17g,"
                   "\"edge_m\":%.17g,\"view_radius_m\":%.17g,\"held\":[",
                   cx, cy, limits[l], h.n_held, h.radius_m, h.edge_m, hold_view_radius_m(&h, 7.5));
            for (uint32_t i = 0; i < h.n_held; i++) {
                printf("%s%u", i ? "," : "", held[i]);
            }
            printf("]}\n");
        }
    }
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        printf("usage: gale-web-hold-table (prints the scenes as JSON lines)\n");
        return strcmp(argv[1], "--help") == 0 ? 0 : 2;
    }
    static ctl_instance inst[MAX_TREES];
    const uint32_t limits[] = { 0, 1, 2, 37, 200, 399, 400, 401, 1000, 5000 };
    const int n_limits = (int)(sizeof limits / sizeof limits[0]);
    /* a 20 x 20 grid, 3 m apart */
    for (uint32_t t = 0; t < 400; t++) {
        inst[t] = (ctl_instance){ .pos = { 3.0f * (float)(t % 20), 3.0f * (float)(t / 20), 0 },
                                  .scale = 1.0f };
    }
    const double grid_points[] = { 0.0, 0.0, 30.0, 1.5, -100.0, 7.25 };
    run("grid", inst, 400, grid_points, 3, limits, n_limits);
    /* 1,000 trees in a 2 km square off the origin */
    for (uint32_t t = 0; t < 1000; t++) {
        inst[t] = (ctl_instance){ .pos = { uniform(-700.0f, 1300.0f), uniform(-1000.0f, 1000.0f),
                                           uniform(0.0f, 20.0f) },
                                  .scale = 1.0f };
    }
    const double forest_points[] = { 0.1, -0.2, 1299.0, 999.5, 412.345678, -87.654321 };
    run("forest", inst, 1000, forest_points, 3, limits, n_limits);
    /* 50 trees on one point */
    for (uint32_t t = 0; t < 50; t++) {
        inst[t] = (ctl_instance){ .pos = { 12.5f, -3.25f, 0 }, .scale = 1.0f };
    }
    const double one_points[] = { 12.5, -3.25 };
    run("one-point", inst, 50, one_points, 1, limits, n_limits);
    return 0;
}
