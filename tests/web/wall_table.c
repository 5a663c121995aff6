/* gale-client's wall geometry (client/wall/wall.c) for every wall file named: each tile's
 * corners, view and projection for two camera views, and the tour's camera at a few times,
 * one JSON object a line, for tests/web/test_wall_js.mjs to hold web/wall_view.js to. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "wall.h"

static void vec(const char *name, const float *v, int n)
{
    printf(",\"%s\":[", name);
    for (int k = 0; k < n; k++) {
        printf("%s%.9g", k ? "," : "", (double)v[k]);
    }
    printf("]");
}

/* A camera's world-to-camera matrix (column-major): rotation about z by yaw, then about x
 * by pitch, then a translation; any rigid motion serves, the two sides read it here. */
static void cam_view(float yaw, float pitch, const float t[3], float m[16])
{
    const float cz = cosf(yaw), sz = sinf(yaw), cx = cosf(pitch), sx = sinf(pitch);
    const float rz[16] = { cz, sz, 0, 0, -sz, cz, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    const float rx[16] = { 1, 0, 0, 0, 0, cx, sx, 0, 0, -sx, cx, 0, 0, 0, 0, 1 };
    wall_mat_mul(rx, rz, m);
    m[12] = t[0];
    m[13] = t[1];
    m[14] = t[2];
}

int main(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0) {
        bool help = argc >= 2;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-wall-table WALL.json...\n"
                "  prints client/wall/wall.c's corners, view and projection of every tile for two\n"
                "  camera views, and the tour's camera at a few times, one JSON a line\n");
        return help ? 0 : 2;
    }
    static wall w;
    float views[2][16];
    cam_view(0.0f, 0.0f, (const float[3]){ 0, 0, 0 }, views[0]);
    cam_view(0.6f, -1.2f, (const float[3]){ 3.0f, -4.5f, -40.0f }, views[1]);
    for (int f = 1; f < argc; f++) {
        gale_err err = { 0 };
        if (wall_load(&w, argv[f], &err) != 0) {
            fprintf(stderr, "gale-web-wall-table: %s\n", err.msg);
            return 1;
        }
        for (int i = 0; i < w.n_tiles; i++) {
            for (int v = 0; v < 2; v++) {
                float pa[3], pb[3], pc[3], view[16], proj[16];
                wall_tile_corners(&w.tiles[i], pa, pb, pc);
                wall_tile_matrices(&w, i, views[v], 0.3f, 4500.0f, view, proj);
                printf("{\"file\":\"%s\",\"tile\":\"%s\"", argv[f], w.tiles[i].name);
                vec("pa", pa, 3);
                vec("pb", pb, 3);
                vec("pc", pc, 3);
                vec("cam_view", views[v], 16);
                vec("view", view, 16);
                vec("proj", proj, 16);
                printf("}\n");
            }
        }
        static const double at_s[] = { 0.0, 7.5, 20.0, 33.25, 39.999, 40.0, 41.0, 11975.372523 };
        for (size_t k = 0; w.n_stops >= 2 && k < sizeof at_s / sizeof at_s[0]; k++) {
            wall_stop s;
            wall_tour_at(&w, at_s[k], &s);
            printf("{\"file\":\"%s\",\"tour_at_s\":%.9g", argv[f], at_s[k]);
            vec("target_m", s.target_m, 3);
            printf(",\"distance_m\":%.9g,\"yaw_deg\":%.9g,\"pitch_deg\":%.9g}\n",
                   (double)s.distance_m, (double)s.yaw_deg, (double)s.pitch_deg);
        }
    }
    return 0;
}
