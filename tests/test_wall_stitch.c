/* A 2×2 wall (configs/walls/flat-2x2.json) drawn headless tile by tile through the wall
 * frusta stitches into the single view of the same camera through the whole wall's
 * rectangle, bezels aside: at 5 mm a pixel the 10 mm bezels are 4 pixels between tiles, so
 * each tile is compared with its own pixels of the single view. Tolerance: mean |difference|
 * per channel <= 1 level and at most 0.5 % of a tile's pixels off by more than 32 levels
 * (edges of thin branches rasterise a hair apart under two frusta). Writes
 * wall_stitch_2x2.png (tiles with their bezels black), wall_single_2x2.png and
 * wall_cylinder.png (six CAVE2 columns side by side) in the build directory. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h>

#include "camera.h"
#include "check.h"
#include "render.h"
#include "render_demo.h"
#include "wall.h"

#ifndef GALE_SOURCE_DIR
#error "GALE_SOURCE_DIR must be defined by the build"
#endif

#define TW 240 /* 1.2 m at 5 mm a pixel */
#define TH 135 /* 0.675 m */
#define GAP 4  /* two 10 mm bezels */
#define SW (2 * TW + GAP)
#define SH (2 * TH + GAP)

static render *R;
static asset A[3];
static gale_err err;
static camera cam;

static void scene(void)
{
    render_instance in[9];
    render_demo_forest(in, 9, 3, 7.0f, 5);
    for (int i = 0; i < 9; i++) {
        in[i].pos[1] += 18.0f; /* in front of the camera */
    }
    CHECK(render_set_instances(R, 9, in, &err) == 0);
    for (uint32_t i = 0; i < 9; i++) {
        float q[64];
        render_demo_pose(&A[in[i].species], (const float[3]){ 8.0f, 2.0f, 0.0f }, 0.5f, i, q);
        CHECK(render_set_q(R, i, q, A[in[i].species].n_modes, &err) == 0);
    }
}

/* One frame through view/proj at w × h into a new RGB buffer. */
static uint8_t *shot(int w, int h, const float view[16], const float proj[16])
{
    CHECK(render_resize(R, w, h, &err) == 0);
    render_camera rc = { .z_near = 0.3f, .z_far = 3000.0f, .matrices = true };
    memcpy(rc.view, view, sizeof rc.view);
    memcpy(rc.proj, proj, sizeof rc.proj);
    uint8_t *rgb = malloc((size_t)w * h * 3);
    CHECK(render_frame(R, &rc, 1.0, &err) == 0);
    CHECK(render_read_rgb(R, rgb, &err) == 0);
    return rgb;
}

static void test_stitch_2x2(void)
{
    static wall w;
    CHECK(wall_load(&w, GALE_SOURCE_DIR "/configs/walls/flat-2x2.json", &err) == 0);
    float cv[16], view[16], proj[16];
    camera_view(&cam, cv);
    /* the whole wall's rectangle: c0r1's lower left, c1r1's lower right, c0r0's upper left */
    float pa[3], pb[3], pc[3], t0[3], t1[3], rot[16];
    wall_tile_corners(&w.tiles[wall_find_tile(&w, "c0r1")], pa, t0, t1);
    wall_tile_corners(&w.tiles[wall_find_tile(&w, "c1r1")], t0, pb, t1);
    wall_tile_corners(&w.tiles[wall_find_tile(&w, "c0r0")], t0, t1, pc);
    wall_offaxis(pa, pb, pc, w.eye_m, 0.3f, 3000.0f, rot, proj);
    const float to_wall[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    wall_mat_mul(to_wall, cv, view);
    wall_mat_mul(rot, view, view);
    uint8_t *single = shot(SW, SH, view, proj);
    uint8_t *stitched = calloc((size_t)SW * SH * 3, 1);
    const char *names[4] = { "c0r0", "c1r0", "c0r1", "c1r1" };
    for (int i = 0; i < 4; i++) {
        int t = wall_find_tile(&w, names[i]);
        wall_tile_matrices(&w, t, cv, 0.3f, 3000.0f, view, proj);
        uint8_t *tile = shot(TW, TH, view, proj);
        const int x0 = (i % 2) * (TW + GAP), y0 = (i / 2) * (TH + GAP);
        double sum = 0.0;
        int far = 0;
        for (int y = 0; y < TH; y++) {
            for (int x = 0; x < TW; x++) {
                const uint8_t *a = &tile[3 * (y * TW + x)];
                const uint8_t *b = &single[3 * ((y0 + y) * SW + x0 + x)];
                int worst = 0;
                for (int k = 0; k < 3; k++) {
                    int d = abs(a[k] - b[k]);
                    sum += d;
                    worst = d > worst ? d : worst;
                }
                far += worst > 32;
                memcpy(&stitched[3 * ((y0 + y) * SW + x0 + x)], a, 3);
            }
        }
        const double mean = sum / (3.0 * TW * TH);
        fprintf(stderr, "  tile %s: mean |diff| %.3f levels, %d of %d pixels off by > 32\n",
                names[i], mean, far, TW * TH);
        CHECK(mean <= 1.0);
        CHECK(far <= TW * TH / 200);
        free(tile);
    }
    CHECK(stbi_write_png("wall_stitch_2x2.png", SW, SH, 3, stitched, SW * 3) != 0);
    CHECK(stbi_write_png("wall_single_2x2.png", SW, SH, 3, single, SW * 3) != 0);
    free(stitched);
    free(single);
}

/* Six middle columns of the CAVE2 cylinder, each 103 × 231 px (1 cm a pixel), side by side
 * with a 2 px black gap: a picture to look at, not a comparison. */
static void test_cylinder_shot(void)
{
    static wall w;
    CHECK(wall_load(&w, GALE_SOURCE_DIR "/configs/walls/cave2-cylinder.json", &err) == 0);
    const int cw = 103, ch = 231, n = 6, gw = n * cw + (n - 1) * 2;
    uint8_t *out = calloc((size_t)gw * ch * 3, 1);
    float cv[16], view[16], proj[16];
    camera_view(&cam, cv);
    for (int i = 0; i < n; i++) {
        char name[16];
        snprintf(name, sizeof name, "col%02d", 6 + i);
        int t = wall_find_tile(&w, name);
        CHECK(t >= 0);
        wall_tile_matrices(&w, t, cv, 0.3f, 3000.0f, view, proj);
        uint8_t *tile = shot(cw, ch, view, proj);
        for (int y = 0; y < ch; y++) {
            memcpy(&out[3 * (y * gw + i * (cw + 2))], &tile[3 * y * cw], 3 * (size_t)cw);
        }
        free(tile);
    }
    CHECK(stbi_write_png("wall_cylinder.png", gw, ch, 3, out, gw * 3) != 0);
    free(out);
}

int main(void)
{
    R = render_create(&(render_desc){ .width = SW, .height = SH, .headless = true,
                                      .max_trees = 16, .max_falling = 512 }, &err);
    if (!R) {
        fprintf(stderr, "render_create: %s\n", err.msg);
        return 1;
    }
    for (uint32_t s = 0; s < 3; s++) {
        if (render_demo_asset(&A[s], &(render_demo_desc){ .n_nodes = 150, .n_modes = 10,
                                     .leaf_shape = s, .seed = s + 1 }, &err) < 0 ||
            render_add_species(R, &A[s], &err) < 0) {
            fprintf(stderr, "species %u: %s\n", s, err.msg);
            return 1;
        }
    }
    /* standing 1.7 m up at the origin, looking along +y, 5° down */
    camera_init(&cam, (const float[3]){ 0.0f, 10.0f, 1.7f }, 10.0f);
    camera_set_mode(&cam, CAMERA_FLY);
    cam.eye[0] = 0.0f;
    cam.eye[1] = 0.0f;
    cam.eye[2] = 1.7f;
    cam.yaw = 1.5707963f;
    cam.pitch = -0.087f;
    scene();
    RUN(test_stitch_2x2);
    RUN(test_cylinder_shot);
    render_destroy(R);
    for (int s = 0; s < 3; s++) {
        render_demo_free(&A[s]);
    }
    return check_report();
}
