/* Wall files and tile frusta (client/wall/wall.h): the shipped walls parse; a CAVE2 cylinder
 * tile's projection matches a closed form computed here from the cylinder itself (radius,
 * column angle, bezels), not from the file's centre/normal/up; its glass corners land on
 * the clip square's corners and points along eye rays keep their place; bad files are
 * refused naming file and key path. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "wall.h"

#ifndef GALE_SOURCE_DIR
#error "GALE_SOURCE_DIR must be defined by the build"
#endif
#define WALLS GALE_SOURCE_DIR "/configs/walls/"

/* clip = proj · view · (p, 1); ndc = clip.xyz / clip.w */
static void project(const float view[16], const float proj[16], const double p[3],
                    double ndc[3], double *w)
{
    float m[16];
    wall_mat_mul(proj, view, m);
    double c[4];
    for (int r = 0; r < 4; r++) {
        c[r] = m[12 + r];
        for (int k = 0; k < 3; k++) {
            c[r] += (double)m[k * 4 + r] * p[k];
        }
    }
    for (int k = 0; k < 3; k++) {
        ndc[k] = c[k] / c[3];
    }
    *w = c[3];
}

static void test_shipped(void)
{
    const char *names[] = { "flat-2x2.json", "angled-3x1.json", "cave2-cylinder.json" };
    const int tiles[] = { 4, 3, 18 };
    for (int i = 0; i < 3; i++) {
        char path[512];
        snprintf(path, sizeof path, WALLS "%s", names[i]);
        static wall w;
        gale_err e = { 0 };
        CHECK(wall_load(&w, path, &e) == 0);
        if (e.msg[0]) {
            fprintf(stderr, "%s\n", e.msg);
        }
        CHECK(w.n_tiles == tiles[i]);
        CHECK(w.hud_tile >= 0);
    }
}

/* CAVE2 (configs/walls/README.md): 18 columns of 1.03 × 2.312 m with 5 mm bezels on a
 * cylinder of radius 3.59 m, each 2 atan(0.52 / 3.59) around; eye 0.25 m up on the axis. */
static void test_cylinder_frustum(void)
{
    static wall w;
    gale_err e = { 0 };
    CHECK(wall_load(&w, WALLS "cave2-cylinder.json", &e) == 0);
    const double R = 3.59, TW = 1.03, TH = 2.312, TB = 0.005;
    const double step = 2.0 * atan((TW / 2 + TB) / R);
    const double eye[3] = { 0.0, 0.25, 0.0 };
    const float ident[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    const int cols[] = { 0, 3, 8, 17 };
    for (int ci = 0; ci < 4; ci++) {
        const int col = cols[ci];
        char name[16];
        snprintf(name, sizeof name, "col%02d", col);
        int t = wall_find_tile(&w, name);
        CHECK(t >= 0);
        if (t < 0) {
            continue;
        }
        const double th = (col - 8.5) * step;
        const double centre[3] = { R * sin(th), 0.0, -R * cos(th) };
        const double right[3] = { cos(th), 0.0, sin(th) };
        const double up[3] = { 0.0, 1.0, 0.0 };
        const double normal[3] = { -sin(th), 0.0, cos(th) };
        double ex = 0, ey = 0, d = 0;
        for (int k = 0; k < 3; k++) {
            ex += (eye[k] - centre[k]) * right[k];
            ey += (eye[k] - centre[k]) * up[k];
            d += (eye[k] - centre[k]) * normal[k];
        }
        float view[16], proj[16];
        const float n = 0.3f, f = 3000.0f;
        wall_tile_matrices(&w, t, ident, n, f, view, proj);
        /* glFrustum of the glass seen from the eye: 2d/w, 2d/h, offsets -2e/w (Kooima
         * eqs. 7-10 with l, r = n (∓w/2 - ex)/d, ...) */
        CHECK_NEAR(proj[0], 2.0 * d / TW, 1e-4);
        CHECK_NEAR(proj[5], 2.0 * d / TH, 1e-4);
        CHECK_NEAR(proj[8], -2.0 * ex / TW, 1e-4);
        CHECK_NEAR(proj[9], -2.0 * ey / TH, 1e-4);
        /* corners of the glass → the clip square's corners, at w = d; twice as far along
         * the same eye ray → the same place. World = wall − eye (the camera at the eye). */
        for (int cx = -1; cx <= 1; cx += 2) {
            for (int cy = -1; cy <= 1; cy += 2) {
                double p[3], p2[3], ndc[3], ndc2[3], wc, wc2;
                for (int k = 0; k < 3; k++) {
                    double q = centre[k] + cx * TW / 2 * right[k] + cy * TH / 2 * up[k];
                    p[k] = q - eye[k];
                    p2[k] = 2.0 * p[k];
                }
                project(view, proj, p, ndc, &wc);
                project(view, proj, p2, ndc2, &wc2);
                CHECK_NEAR(ndc[0], cx, 1e-4);
                CHECK_NEAR(ndc[1], cy, 1e-4);
                CHECK_NEAR(wc, d, 1e-4);
                CHECK_NEAR(ndc2[0], cx, 1e-4);
                CHECK_NEAR(ndc2[1], cy, 1e-4);
                CHECK(ndc[2] > -1.0 && ndc[2] < ndc2[2] && ndc2[2] < 1.0);
            }
        }
    }
    /* neighbours: col03's right bezel edge is col04's left one (bezel compensation) */
    float a[3], b[3], c[3], a4[3], b4[3], c4[3];
    wall_tile_corners(&w.tiles[3], a, b, c);
    wall_tile_corners(&w.tiles[4], a4, b4, c4);
    const double th3 = (3 - 8.5) * step, th4 = (4 - 8.5) * step;
    for (int k = 0; k < 3; k += 2) {
        double e3 = (double)b[k] + TB * (k == 0 ? cos(th3) : sin(th3));
        double e4 = (double)a4[k] - TB * (k == 0 ? cos(th4) : sin(th4));
        CHECK_NEAR(e3, e4, 1e-5);
    }
}

/* A flat wall: the camera turned 90° sees the tile where the turned eye rays point. */
static void test_camera_moves_frustum(void)
{
    static wall w;
    gale_err e = { 0 };
    CHECK(wall_load(&w, WALLS "flat-2x2.json", &e) == 0);
    /* camera at world (5, 0, 0) looking along world +x: world→camera = R · T(-5, 0, 0) with
     * camera x = world -y, camera y = world z, camera z = world -x */
    const float cam[16] = { 0, 0, -1, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 5, 1 };
    float view[16], proj[16];
    wall_tile_matrices(&w, wall_find_tile(&w, "c1r1"), cam, 0.3f, 100.0f, view, proj);
    /* c1r1's centre (0.61, -0.3475, -2) in the wall frame is 2 m ahead, 0.61 right and
     * 0.3475 down of the eye: world (7, -0.61, -0.3475) */
    double p[3] = { 7.0, -0.61, -0.3475 }, ndc[3], wc;
    project(view, proj, p, ndc, &wc);
    CHECK_NEAR(ndc[0], 0.0, 1e-4);
    CHECK_NEAR(ndc[1], 0.0, 1e-4);
    CHECK_NEAR(wc, 2.0, 1e-4);
}

static void expect_fail(const char *text, const char *msg)
{
    static wall w;
    gale_err e = { 0 };
    CHECK(wall_parse(&w, "t.json", text, strlen(text), &e) != 0);
    CHECK_STR_HAS(e.msg, msg);
    CHECK(w.n_tiles == 0);
}

#define TILE(extra)                                                                      \
    "{\"name\":\"a\",\"px\":[64,32],\"size_m\":[1,0.5],\"centre_m\":[0,0,-2]," extra "}"

static void test_bad_files(void)
{
    expect_fail("{\"name\":\"w\",\"eye_m\":[0,0,0],\"tiles\":[" TILE("\"normal\":[0,0,1],"
                "\"up\":[0,1,0.5]") "]}",
                "t.json: wall.tiles[0].up: expected orthogonal to normal");
    expect_fail("{\"name\":\"w\",\"eye_m\":[0,0,0],\"tiles\":[" TILE("\"normal\":[0,0,-1],"
                "\"up\":[0,1,0]") "]}",
                "t.json: wall.tiles[0].normal: expected the eye in front of the tile");
    expect_fail("{\"name\":\"w\",\"eye_m\":[0,0,0],\"tiles\":[" TILE("\"normal\":[0,0,1],"
                "\"up\":[0,1,0]") "," TILE("\"normal\":[0,0,1],\"up\":[0,1,0]") "]}",
                "t.json: wall.tiles[1].name: \"a\" repeats wall.tiles[0]");
    expect_fail("{\"name\":\"w\",\"eye_m\":[0,0,0],\"hud_tile\":\"b\",\"tiles\":["
                TILE("\"normal\":[0,0,1],\"up\":[0,1,0]") "]}",
                "t.json: wall.hud_tile: expected a tile name or \"off\", got \"b\"");
    expect_fail("{\"name\":\"w\",\"eye_m\":[0,0,0],\"tiles\":[" TILE("\"normal\":[0,0,1],"
                "\"up\":[0,1,0],\"colour\":1") "]}",
                "t.json: wall.tiles[0].colour: unknown key");
    expect_fail("{\"name\":\"w\",\n\"eye_m\":[0,0,0],,}", "t.json:2:");
    static wall w;
    gale_err e = { 0 };
    CHECK(wall_load(&w, WALLS "no-such-wall.json", &e) == GALE_E_IO);
    CHECK_STR_HAS(e.msg, "no-such-wall.json: cannot open");
    const char *ok = "{\"name\":\"w\",\"eye_m\":[0,0,0],\"hud_tile\":\"off\",\"tiles\":["
                     TILE("\"normal\":[0,0,2],\"up\":[0,3,0]") "]}";
    CHECK(wall_parse(&w, "t.json", ok, strlen(ok), &e) == 0);
    CHECK(w.hud_tile == -1);
    CHECK_NEAR(w.tiles[0].normal[2], 1.0, 1e-6); /* normalised */
}

/* The HUD on the chosen tile only, its text hud_text_mm tall on the glass. */
static void test_hud_placement(void)
{
    static wall w;
    gale_err e = { 0 };
    CHECK(wall_load(&w, WALLS "flat-2x2.json", &e) == 0);
    const int hud = wall_find_tile(&w, "c0r0");
    CHECK(w.hud_tile == hud);
    /* 10 mm on 0.675 m of glass drawn 1080 px high: 16 px; at 540 px the floor of 8 */
    CHECK_NEAR(wall_hud_px(&w, hud, 1080), 16.0, 1e-3);
    CHECK_NEAR(wall_hud_px(&w, hud, 540), 8.0, 1e-3);
    CHECK(wall_hud_px(&w, wall_find_tile(&w, "c1r1"), 1080) == 0.0f);
    CHECK(wall_load(&w, WALLS "cave2-cylinder.json", &e) == 0);
    /* 25 mm on 2.312 m drawn 3072 px high: 33.2 px, on col08 alone */
    CHECK_NEAR(wall_hud_px(&w, wall_find_tile(&w, "col08"), 3072), 25e-3 * 3072 / 2.312, 1e-3);
    CHECK(wall_hud_px(&w, wall_find_tile(&w, "col09"), 3072) == 0.0f);
    w.hud_tile = -1; /* "off" */
    CHECK(wall_hud_px(&w, wall_find_tile(&w, "col08"), 3072) == 0.0f);
}

int main(void)
{
    RUN(test_hud_placement);
    RUN(test_shipped);
    RUN(test_cylinder_frustum);
    RUN(test_camera_moves_frustum);
    RUN(test_bad_files);
    return check_report();
}
