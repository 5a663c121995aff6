/* Culling and LOD without a GL context: with a camera at the origin looking along +y, a
 * tree ahead is kept, one behind the camera or far to the side is culled; near trees get
 * every mode and mesh LOD 0, distance lowers the mode count (never below 4) and raises the
 * mesh LOD, the billboard band fades in past 80 % of the billboard distance, and a
 * tree's scale stretches those distances. */
#include <cglm/cglm.h>
#include <math.h>
#include <string.h>

#include "check.h"
#include "render_cull.h"

static float planes[6][4];
static const float eye[3] = { 0.0f, 0.0f, 2.0f };
static const render_cull_species sp = {
    .height_m = 10.0f, .crown_r_m = 3.0f, .n_modes = 32, .n_lods = 3
};
static const render_lod_desc ld = { .mode_dist_m = 40.0f, .billboard_dist_m = 220.0f };

static void setup(void)
{
    mat4 view, proj, vp;
    glm_lookat((vec3){ eye[0], eye[1], eye[2] }, (vec3){ 0.0f, 1.0f, 2.0f },
               (vec3){ 0.0f, 0.0f, 1.0f }, view);
    glm_perspective(glm_rad(50.0f), 16.0f / 9.0f, 0.3f, 3000.0f, proj);
    glm_mat4_mul(proj, view, vp);
    float m[16];
    memcpy(m, vp, sizeof m);
    render_cull_planes(m, planes);
}

static render_tree_lod at(float x, float y, float scale)
{
    render_instance in = { .pos = { x, y, 0.0f }, .scale = scale };
    return render_cull_tree(planes, eye, &in, &sp, &ld);
}

static void test_frustum(void)
{
    CHECK(at(0.0f, 20.0f, 1.0f).flags != 0);   /* ahead */
    CHECK(at(0.0f, -20.0f, 1.0f).flags == 0);  /* behind the camera */
    CHECK(at(200.0f, 20.0f, 1.0f).flags == 0); /* far outside the side planes */
    CHECK(at(0.0f, 5000.0f, 1.0f).flags == 0); /* past the far plane */
    /* the bound keeps a tree whose crown still reaches into view: just behind the eye */
    CHECK(at(0.0f, -1.0f, 1.0f).flags != 0);
    render_tree_lod c = at(0.0f, -20.0f, 1.0f);
    CHECK(c.bill_t == 0.0f && c.n_modes == 0.0f && c.mesh_lod == 0);
}

static void test_lod_by_distance(void)
{
    render_tree_lod n = at(0.0f, 20.0f, 1.0f);
    CHECK(n.flags == RENDER_LOD_FULL);
    CHECK(n.n_modes == 32.0f); /* within mode_dist: every mode */
    CHECK(n.mesh_lod == 0);
    CHECK(n.bill_t == 0.0f);

    /* 80 m (crown centre at 5 m height, eye at 2 m): modes as 32 x 40 / d */
    render_tree_lod m = at(0.0f, 80.0f, 1.0f);
    float d = sqrtf(80.0f * 80.0f + 3.0f * 3.0f);
    CHECK(m.flags == RENDER_LOD_FULL);
    CHECK_NEAR(m.n_modes, 32.0f * 40.0f / d, 1e-3);
    /* mesh bands of 0.8 x 220 / 3 = 58.7 m: 80 m is in band 1 */
    CHECK(m.mesh_lod == 1);

    /* far past mode_dist: never fewer than 4 modes */
    render_tree_lod f = at(0.0f, 170.0f, 1.0f);
    CHECK(f.flags == RENDER_LOD_FULL);
    CHECK(f.n_modes >= 4.0f && f.n_modes < 8.0f);
    CHECK(f.mesh_lod == 2);
    CHECK(f.mesh_fade == 0.0f); /* the last LOD dithers into nothing */

    /* the billboard band (176..220 m): both drawn, then billboard only */
    render_tree_lod b = at(0.0f, 200.0f, 1.0f);
    CHECK(b.flags == (RENDER_LOD_FULL | RENDER_LOD_BILLBOARD));
    CHECK(b.bill_t > 0.0f && b.bill_t < 1.0f);
    render_tree_lod o = at(0.0f, 400.0f, 1.0f);
    CHECK(o.flags == RENDER_LOD_BILLBOARD);
    CHECK(o.bill_t == 1.0f);
}

static float smooth01(float x)
{
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return x * x * (3.0f - 2.0f * x);
}

/* distance from the eye to the crown centre (5 m up) of a tree at (0, y) */
static float crown_dist(float y)
{
    return sqrtf(y * y + 3.0f * 3.0f);
}

static void test_mode_floor(void)
{
    /* 8 modes at 170 m would be 8 x 40 / 170 < 2: held at 4 */
    const render_cull_species s8 = {
        .height_m = 10.0f, .crown_r_m = 3.0f, .n_modes = 8, .n_lods = 3
    };
    render_instance in = { .pos = { 0.0f, 170.0f, 0.0f }, .scale = 1.0f };
    CHECK(render_cull_tree(planes, eye, &in, &s8, &ld).n_modes == 4.0f);
    /* a species with fewer than 4 modes keeps all of them */
    const render_cull_species s2 = {
        .height_m = 10.0f, .crown_r_m = 3.0f, .n_modes = 2, .n_lods = 3
    };
    CHECK(render_cull_tree(planes, eye, &in, &s2, &ld).n_modes == 2.0f);
}

static void test_billboard_band(void)
{
    /* the band starts at 0.8 x 220 = 176 m: at 180 m the billboard fades in */
    render_tree_lod b = at(0.0f, 180.0f, 1.0f);
    CHECK(b.flags == (RENDER_LOD_FULL | RENDER_LOD_BILLBOARD));
    CHECK_NEAR(b.bill_t, smooth01((crown_dist(180.0f) - 176.0f) / 44.0f), 1e-6);
    CHECK(at(0.0f, 172.0f, 1.0f).flags == RENDER_LOD_FULL);
}

static void test_dither_and_scale(void)
{
    /* band 0 is 0.8 x 220 / 3 m; its last 30 % fades toward LOD 1 */
    const float band = 0.8f * 220.0f / 3.0f;
    for (float y = 40.0f; y < 58.0f; y += 3.0f) {
        render_tree_lod t = at(0.0f, y, 1.0f);
        float lf = crown_dist(y) / band;
        CHECK(t.mesh_lod == 0);
        CHECK_NEAR(t.mesh_fade, smooth01((lf - 0.7f) / 0.3f), 1e-6);
    }
    /* end of band 0 (last 30 % of 58.7 m): fading toward LOD 1 */
    render_tree_lod t = at(0.0f, 55.0f, 1.0f);
    CHECK(t.mesh_lod == 0);
    CHECK(t.mesh_fade > 0.0f && t.mesh_fade < 1.0f);
    CHECK(at(0.0f, 30.0f, 1.0f).mesh_fade == 0.0f);
    /* a tree twice the size counts as half as far: 400 m is then in the fade band */
    render_tree_lod s = at(0.0f, 400.0f, 2.0f);
    CHECK(s.flags == (RENDER_LOD_FULL | RENDER_LOD_BILLBOARD));
}

int main(void)
{
    setup();
    RUN(test_frustum);
    RUN(test_lod_by_distance);
    RUN(test_mode_floor);
    RUN(test_billboard_band);
    RUN(test_dither_and_scale);
    return check_report();
}
