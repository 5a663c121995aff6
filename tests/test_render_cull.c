/* Culling and LOD without a GL context: with a camera at the origin looking along +y, a
 * tree ahead is kept, one behind the camera or far to the side is culled; near trees get
 * every mode and mesh LOD 0, distance lowers the mode count (never below 4) and raises the
 * mesh LOD, the leaves thin past FULL and the impostor fades in past THIN over the last
 * 20 % of each level (lod_policy.h), a piece that stays posed (debris) never turns into an
 * impostor, and the
 * frame's budget scale pulls the levels in so that what is drawn fits. The cone a client asks the server for holds
 * every point of its frustum (PROTOCOL.md's cone rule, no margin), symmetric or off-axis,
 * and is no wider than the frustum's diagonal. Culling by cells keeps exactly the trees
 * the test of each tree keeps, from cameras all over a scattered forest. */
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
static const render_lod_desc ld = { .mode_dist_m = 40.0f, .scale = 1.0f };

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

static void test_lod_by_distance(void)
{
    render_tree_lod n = at(0.0f, 20.0f, 1.0f);
    CHECK(n.flags == RENDER_LOD_FULL && n.level == LOD_FULL);
    CHECK(n.n_modes == 32.0f); /* within mode_dist: every mode */
    CHECK(n.mesh_lod == 0);
    CHECK(n.bill_t == 0.0f && n.thin_t == 0.0f);

    /* 50 m (crown centre at 5 m height, eye at 2 m): modes as 32 x 40 / d; mesh steps of
       30 m: band 1 */
    render_tree_lod m = at(0.0f, 50.0f, 1.0f);
    CHECK(m.flags == RENDER_LOD_FULL && m.level == LOD_FULL);
    CHECK_NEAR(m.n_modes, 32.0f * 40.0f / crown_dist(50.0f), 1e-3);
    CHECK(m.mesh_lod == 1);

    /* THIN (90..250 m): the thinned leaves, the coarsest mesh, at most 4 modes */
    render_tree_lod f = at(0.0f, 150.0f, 1.0f);
    CHECK(f.flags == RENDER_LOD_FULL && f.level == LOD_THIN);
    CHECK(f.thin_t == 1.0f && f.bill_t == 0.0f);
    CHECK(f.n_modes == 4.0f);
    CHECK(f.mesh_lod == 2 && f.mesh_fade == 0.0f);

    /* the impostor band (200..250 m): both drawn, then the impostor alone */
    render_tree_lod b = at(0.0f, 230.0f, 1.0f);
    CHECK(b.flags == (RENDER_LOD_FULL | RENDER_LOD_BILLBOARD) && b.level == LOD_IMPOSTOR);
    CHECK(b.bill_t > 0.0f && b.bill_t < 1.0f);
    render_tree_lod o = at(0.0f, 400.0f, 1.0f);
    CHECK(o.flags == RENDER_LOD_BILLBOARD);
    CHECK(o.bill_t == 1.0f);
    /* past the impostors' reach: nothing */
    const render_cull_species cs = sp;
    const render_lod_desc d1 = { .mode_dist_m = 40.0f, .scale = 1.0f };
    CHECK(render_lod_pick(3999.0f, &cs, &d1, false).flags == RENDER_LOD_BILLBOARD);
    CHECK(render_lod_pick(4001.0f, &cs, &d1, false).flags == 0);
}

static void test_mode_floor(void)
{
    /* 8 modes at 85 m would be 8 x 40 / 85 < 4: held at 4 */
    const render_cull_species s8 = {
        .height_m = 10.0f, .crown_r_m = 3.0f, .n_modes = 8, .n_lods = 3
    };
    render_instance in = { .pos = { 0.0f, 85.0f, 0.0f }, .scale = 1.0f };
    CHECK(render_cull_tree(planes, eye, &in, &s8, &ld).n_modes == 4.0f);
    /* a species with fewer than 4 modes keeps all of them */
    const render_cull_species s2 = {
        .height_m = 10.0f, .crown_r_m = 3.0f, .n_modes = 2, .n_lods = 3
    };
    CHECK(render_cull_tree(planes, eye, &in, &s2, &ld).n_modes == 2.0f);
}

static void test_fade_bands(void)
{
    /* FULL's last 20 % (72..90 m) dithers the leaves into THIN's */
    for (float y = 60.0f; y < 100.0f; y += 4.0f) {
        render_tree_lod t = at(0.0f, y, 1.0f);
        CHECK_NEAR(t.thin_t, smooth01((crown_dist(y) - 72.0f) / 18.0f), 1e-6);
        CHECK(t.bill_t == 0.0f);
    }
    /* THIN's last 20 % (200..250 m) dithers into the impostor */
    render_tree_lod b = at(0.0f, 210.0f, 1.0f);
    CHECK(b.flags == (RENDER_LOD_FULL | RENDER_LOD_BILLBOARD));
    CHECK_NEAR(b.bill_t, smooth01((crown_dist(210.0f) - 200.0f) / 50.0f), 1e-6);
    CHECK(at(0.0f, 195.0f, 1.0f).flags == RENDER_LOD_FULL);
    /* a piece that stays posed (a debris piece; a fallen tree is an impostor as a standing
       one is, laid along its fall) is never an impostor: THIN, fading out over THIN's band
       with no impostor fading in, and past it not drawn */
    const render_lod_desc d1 = { .mode_dist_m = 40.0f, .scale = 1.0f };
    render_tree_lod p = render_lod_pick(150.0f, &sp, &d1, true);
    CHECK(p.flags == RENDER_LOD_FULL && p.level == LOD_THIN && p.bill_t == 0.0f);
    render_tree_lod pf = render_lod_pick(230.0f, &sp, &d1, true);
    CHECK(pf.flags == RENDER_LOD_FULL && pf.level == LOD_THIN);
    CHECK(pf.bill_t > 0.0f && pf.bill_t < 1.0f);
    CHECK(render_lod_pick(260.0f, &sp, &d1, true).flags == 0);
    CHECK(render_lod_pick(1000.0f, &sp, &d1, true).flags == 0);
}

static void test_dither_and_scale(void)
{
    /* mesh steps of 30 m; the last 30 % of each fades toward the next */
    for (float y = 10.0f; y < 29.0f; y += 3.0f) {
        render_tree_lod t = at(0.0f, y, 1.0f);
        float lf = crown_dist(y) / 30.0f;
        CHECK(t.mesh_lod == 0);
        CHECK_NEAR(t.mesh_fade, smooth01((lf - 0.7f) / 0.3f), 1e-6);
    }
    CHECK(at(0.0f, 15.0f, 1.0f).mesh_fade == 0.0f);
    /* the frame's scale pulls FULL and THIN in: at scale 0.5, 150 m is an impostor */
    const render_lod_desc half = { .mode_dist_m = 20.0f, .scale = 0.5f };
    render_tree_lod s = render_lod_pick(150.0f, &sp, &half, false);
    CHECK(s.flags == RENDER_LOD_BILLBOARD);
    CHECK(render_lod_pick(60.0f, &sp, &half, false).level == LOD_THIN);
}

/* The budget: a frame of trees whose worst case fits at scale 1 keeps it; one over it
 * gets the largest scale (within the bisection's step) that fits, and the cost there,
 * counted tree by tree from render_lod_pick, stays within the budget. */
static void test_budget(void)
{
    static uint32_t hist[RENDER_LOD_BINS];
    const render_lod_cost cost = { .full_leaves = 20000.0f, .mesh = { 0.0f }, .n_lods = 1,
                                   .thin = 5000.0f, .impostor = 2.0f, .nodes = 1000.0f };
    /* 10 trees in every bin out to 500 m */
    float dist[2000];
    uint32_t n = 0;
    for (float x = 1.0f; x < 500.0f; x += 0.5f) {
        dist[n++] = x;
    }
    for (uint32_t i = 0; i < n; i++) {
        hist[render_lod_bin(dist[i])]++;
    }
    const render_lod_desc d1 = { .mode_dist_m = 40.0f, .scale = 1.0f };
    double at1 = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        render_tree_lod t = render_lod_pick(dist[i], &sp, &d1, false);
        at1 += (t.flags & RENDER_LOD_FULL) ? (t.thin_t < 1.0f ? 20000.0 : 0.0) : 0.0;
        at1 += (t.flags & RENDER_LOD_FULL) && t.thin_t > 0.0f ? 5000.0 : 0.0;
        at1 += (t.flags & RENDER_LOD_BILLBOARD) ? 2.0 : 0.0;
    }
    /* a budget above the whole cost keeps scale 1 */
    CHECK(render_lod_budget(hist, NULL, &cost, 1, 1.0f, 2.0 * at1, 1e12) == 1.0f);
    /* a quarter of it: the scale drops, and what the frame then draws fits */
    const double budget = 0.25 * at1;
    float sc = render_lod_budget(hist, NULL, &cost, 1, 1.0f, budget, 1e12);
    CHECK(sc > 0.05f && sc < 1.0f);
    const render_lod_desc ds = { .mode_dist_m = 40.0f * sc, .scale = sc };
    double drawn = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        render_tree_lod t = render_lod_pick(dist[i], &sp, &ds, false);
        drawn += (t.flags & RENDER_LOD_FULL) && t.thin_t < 1.0f ? 20000.0 : 0.0;
        drawn += (t.flags & RENDER_LOD_FULL) && t.thin_t > 0.0f ? 5000.0 : 0.0;
        drawn += (t.flags & RENDER_LOD_BILLBOARD) ? 2.0 : 0.0;
    }
    CHECK(drawn <= budget);
    /* and not far below it: the scale 5 % larger would not fit the worst case */
    CHECK(drawn > 0.5 * budget);
    /* the nodes' budget binds the same way */
    float sn = render_lod_budget(hist, NULL, &cost, 1, 1.0f, 1e12, 50.0 * 1000.0);
    uint32_t posed = 0;
    const render_lod_desc dn = { .mode_dist_m = 40.0f * sn, .scale = sn };
    for (uint32_t i = 0; i < n; i++) {
        posed += (render_lod_pick(dist[i], &sp, &dn, false).flags & RENDER_LOD_FULL) != 0;
    }
    CHECK(posed <= 50 && posed > 20);
    /* every tree felled: each posed draws a root plate or stump besides itself, which
       for trees of few leaves is most of their cost; the frame with them still fits */
    static uint32_t felled[RENDER_LOD_BINS];
    memcpy(felled, hist, sizeof felled);
    const render_lod_cost small = { .full_leaves = 100.0f, .mesh = { 0.0f }, .n_lods = 1,
                                    .thin = 20.0f, .impostor = 2.0f, .nodes = 10.0f };
    const double tight = 20000.0;
    float sf = render_lod_budget(hist, felled, &small, 1, 1.0f, tight, 1e12);
    float s0 = render_lod_budget(hist, NULL, &small, 1, 1.0f, tight, 1e12);
    CHECK(sf > 0.0f && sf < 0.8f * s0);
    double with_felled = 0.0;
    const render_lod_desc df = { .mode_dist_m = 40.0f * sf, .scale = sf };
    for (uint32_t i = 0; i < n; i++) {
        render_tree_lod t = render_lod_pick(dist[i], &sp, &df, false);
        with_felled += (t.flags & RENDER_LOD_FULL) && t.thin_t < 1.0f ? 100.0 : 0.0;
        with_felled += (t.flags & RENDER_LOD_FULL) && t.thin_t > 0.0f ? 20.0 : 0.0;
        with_felled += (t.flags & RENDER_LOD_FULL) ? (double)RENDER_FELLED_TRIS_MAX : 0.0;
        with_felled += (t.flags & RENDER_LOD_BILLBOARD) ? 2.0 : 0.0;
    }
    CHECK(with_felled <= tight);
}

/* PROTOCOL.md view "frustum": in the cone when out <= 0 and 0 <= along <= far_m. */
static bool in_cone(const float e[3], const float axis[3], float fov_deg, float far_m,
                    const float p[3], float slack_m)
{
    float r[3] = { p[0] - e[0], p[1] - e[1], p[2] - e[2] };
    float d2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    float along = r[0] * axis[0] + r[1] * axis[1] + r[2] * axis[2];
    float across = sqrtf(fmaxf(d2 - along * along, 0.0f));
    float h = 0.5f * fov_deg * (float)M_PI / 180.0f;
    float out = across * cosf(h) - along * sinf(h);
    return out <= slack_m && along >= -slack_m && along <= far_m + slack_m;
}

/* Points spread through the frustum of viewproj (clip-space grid mapped to the world). */
static int frustum_points_outside(const mat4 vp, const float e[3], const float axis[3],
                                  float fov_deg, float far_m)
{
    mat4 inv;
    glm_mat4_inv((vec4 *)vp, inv);
    int outside = 0;
    for (int i = 0; i <= 8; i++) {
        for (int j = 0; j <= 8; j++) {
            for (int k = 0; k <= 8; k++) {
                vec4 c = { -1.0f + 0.25f * (float)i, -1.0f + 0.25f * (float)j,
                           -1.0f + 0.25f * (float)k, 1.0f }, w;
                glm_mat4_mulv(inv, c, w);
                float p[3] = { w[0] / w[3], w[1] / w[3], w[2] / w[3] };
                /* float slack: 1e-4 of the distance */
                float slack = 1e-4f * sqrtf((p[0] - e[0]) * (p[0] - e[0]) +
                                            (p[1] - e[1]) * (p[1] - e[1]) +
                                            (p[2] - e[2]) * (p[2] - e[2]));
                outside += !in_cone(e, axis, fov_deg, far_m, p, slack);
            }
        }
    }
    return outside;
}

static void test_view_cone(void)
{
    /* symmetric: 50° vertical at 16:9, looking down the street and a little down */
    vec3 e = { 3.0f, -40.0f, 1.75f }, tgt = { 10.0f, 30.0f, 0.0f }, up = { 0.0f, 0.0f, 1.0f };
    mat4 view, proj, vp;
    glm_lookat(e, tgt, up, view);
    glm_perspective(glm_rad(50.0f), 16.0f / 9.0f, 0.3f, 3000.0f, proj);
    glm_mat4_mul(proj, view, vp);
    float axis[3], fov, far_m;
    CHECK(render_cull_cone((float *)vp, e, axis, &fov, &far_m));
    float th = tanf(glm_rad(25.0f)), tw = th * 16.0f / 9.0f;
    float diag_deg = 2.0f * atanf(sqrtf(th * th + tw * tw)) * 180.0f / (float)M_PI;
    CHECK_NEAR(fov, diag_deg, 0.01f);
    vec3 fwd;
    glm_vec3_sub(tgt, e, fwd);
    glm_vec3_normalize(fwd);
    CHECK_NEAR(axis[0] * fwd[0] + axis[1] * fwd[1] + axis[2] * fwd[2], 1.0f, 1e-5f);
    /* the far plane, square to the axis (1e-3: the float inverse of a 0.3-3000 m depth) */
    CHECK_NEAR(far_m, 3000.0f, 3.0f);
    CHECK(frustum_points_outside(vp, e, axis, fov, far_m) == 0);
    /* a cone a degree narrower leaves the frustum's edges out */
    CHECK(frustum_points_outside(vp, e, axis, fov - 1.0f, far_m) > 0);

    /* off-axis: a wall tile's frustum, its eye off the tile's centre */
    mat4 off;
    glm_frustum(-0.05f, 0.25f, -0.02f, 0.12f, 0.3f, 3000.0f, off);
    glm_mat4_mul(off, view, vp);
    CHECK(render_cull_cone((float *)vp, e, axis, &fov, &far_m));
    CHECK(frustum_points_outside(vp, e, axis, fov, far_m) == 0);
    CHECK(frustum_points_outside(vp, e, axis, fov - 1.0f, far_m) > 0);
    CHECK(fov > 1.0f && fov < 179.0f);

    /* no inverse: refused */
    mat4 zero = { { 0 } };
    CHECK(!render_cull_cone((float *)zero, e, axis, &fov, &far_m));
}

static uint32_t lcg(uint32_t *x)
{
    *x = *x * 1664525u + 1013904223u;
    return *x >> 8;
}

static void test_cells_match_trees(void)
{
    enum { N = 5000 };
    static render_instance inst[N];
    const render_cull_species sps[2] = { sp, { .height_m = 22.0f, .crown_r_m = 5.0f,
                                               .n_modes = 24, .n_lods = 2 } };
    uint32_t x = 7;
    for (uint32_t i = 0; i < N; i++) {
        inst[i] = (render_instance){ .species = i % 2,
                                     .pos = { (float)(lcg(&x) % 60000) * 0.01f - 300.0f,
                                              (float)(lcg(&x) % 40000) * 0.01f - 100.0f,
                                              (float)(lcg(&x) % 300) * 0.01f },
                                     .scale = 0.7f + (float)(lcg(&x) % 60) * 0.01f };
    }
    render_cells g = { 0 };
    CHECK(render_cells_build(&g, inst, N, sps) == 0);
    CHECK(g.n_trees == N && g.n_cells > 16);
    uint32_t in_cells = 0;
    for (uint32_t c = 0; c < g.n_cells; c++) {
        in_cells += g.cell[c].count;
    }
    CHECK(in_cells == N);
    int mismatches = 0, kept_total = 0, inside_cells = 0, out_cells = 0;
    static uint8_t by_cell[N];
    for (int cam = 0; cam < 24; cam++) {
        vec3 e = { (float)(lcg(&x) % 800) - 400.0f, (float)(lcg(&x) % 600) - 300.0f,
                   1.5f + (float)(lcg(&x) % 200) };
        vec3 t = { (float)(lcg(&x) % 600) - 300.0f, (float)(lcg(&x) % 400) - 100.0f, 0.0f };
        vec3 up = { 0.0f, 0.0f, 1.0f };
        mat4 view, proj, vp;
        glm_lookat(e, t, up, view);
        glm_perspective(glm_rad(30.0f + (float)(cam % 4) * 15.0f), 16.0f / 9.0f, 0.3f,
                        cam % 3 == 0 ? 150.0f : 3000.0f, proj);
        glm_mat4_mul(proj, view, vp);
        float pl[6][4];
        render_cull_planes((float *)vp, pl);
        memset(by_cell, 0, sizeof by_cell);
        for (uint32_t c = 0; c < g.n_cells; c++) {
            int where = render_cell_test(&g.cell[c], pl);
            inside_cells += where == RENDER_CELL_IN;
            out_cells += where == RENDER_CELL_OUT;
            for (uint32_t k = 0; k < g.cell[c].count && where != RENDER_CELL_OUT; k++) {
                uint32_t i = g.tree[g.cell[c].first + k];
                render_tree_lod l = render_cull_tree(where == RENDER_CELL_IN ? NULL : pl, e,
                                                     &inst[i], &sps[inst[i].species], &ld);
                by_cell[i] = l.flags ? 1 : 0;
            }
        }
        for (uint32_t i = 0; i < N; i++) {
            render_tree_lod l = render_cull_tree(pl, e, &inst[i], &sps[inst[i].species], &ld);
            mismatches += (l.flags ? 1 : 0) != by_cell[i];
            kept_total += by_cell[i];
        }
    }
    CHECK(mismatches == 0);
    /* the cameras saw some of the forest, some of it wholly, and missed some */
    CHECK(kept_total > 0 && inside_cells > 0 && out_cells > 0);
    render_cells_free(&g);
    CHECK(g.cell == NULL && g.n_cells == 0);
}

int main(void)
{
    setup();
    RUN(test_frustum);
    RUN(test_lod_by_distance);
    RUN(test_mode_floor);
    RUN(test_fade_bands);
    RUN(test_budget);
    RUN(test_dither_and_scale);
    RUN(test_view_cone);
    RUN(test_cells_match_trees);
    return check_report();
}
