/* Storm damage drawn by gale_render under Mesa (EGL, or Xvfb): a broken branch's sub-tree
 * is hidden exactly as damage_cut_mask says (the skeleton pass read back), its pixels go
 * from a render of the intact tree and nothing else does, the same branch drawn as a
 * debris piece in place fills them again, and a piece placed by debris_frame_matrix lands
 * on screen where the C copy of tree_frame puts it; far away a fallen tree is an impostor
 * laid along its fall (seen from above, its pixels lie along it, alike whether its cell is
 * listed whole or walked tree by tree), an uprooted one shows its root plate, a snapped one
 * stands on a stump, and a far tree's billboard thins by the leaves its crown lost. */
#include <cglm/cglm.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h>

#include "check.h"
#include "damage_cut.h"
#include "debris_path.h"
#include "render.h"
#include "render_demo.h"
#include "tip_fall.h"
#include "wire.h"

#define W 320
#define H 240

static render *R;
static asset A;
static gale_err err;
static uint32_t BRANCH; /* the node that breaks */

static const render_camera CAM = { .eye = { 0.0f, -15.0f, 4.5f }, .target = { 0.0f, 0.0f, 4.5f } };

static uint8_t *shot_cam(const render_camera *cam)
{
    uint8_t *rgb = malloc(W * H * 3);
    err = (gale_err){ 0 };
    CHECK(render_frame(R, cam, 1.0, &err) == 0);
    CHECK(render_read_rgb(R, rgb, &err) == 0);
    if (err.code) {
        fprintf(stderr, "render: %s\n", err.msg);
    }
    return rgb;
}

static uint8_t *shot(void)
{
    return shot_cam(&CAM);
}

static int differs(const uint8_t *a, const uint8_t *b, int i)
{
    int d = 0;
    for (int k = 0; k < 3; k++) {
        d = abs(a[3 * i + k] - b[3 * i + k]) > d ? abs(a[3 * i + k] - b[3 * i + k]) : d;
    }
    return d > 24;
}

/* one tree, rest pose, at the origin */
static void one_tree(float y)
{
    render_instance in = { .species = 0, .pos = { 0.0f, y, 0.0f }, .yaw = 0.4f, .scale = 1.0f };
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
}

/* a branch high in the crown with a fair share of the nodes: its sub-tree */
static uint32_t pick_branch(uint8_t *mask)
{
    uint32_t best = 0, best_n = 0;
    for (uint32_t b = 1; b < A.n_nodes; b++) {
        damage_cut_mask(A.parent, A.n_nodes, &b, 1, true, mask);
        uint32_t n = 0;
        for (uint32_t i = 0; i < A.n_nodes; i++) {
            n += mask[i];
        }
        if (n <= A.n_nodes / 4 && n > best_n && A.rest[3 * b + 2] > 2.0f) {
            best = b;
            best_n = n;
        }
    }
    damage_cut_mask(A.parent, A.n_nodes, &best, 1, true, mask);
    return best;
}

static void test_branch_hidden(void)
{
    uint8_t *want = malloc(A.n_nodes), *got = malloc(A.n_nodes);
    BRANCH = pick_branch(want);
    CHECK(BRANCH > 0);
    one_tree(0.0f);
    CHECK(render_set_instances(R, 0, NULL, &err) == 0);
    uint8_t *bg = shot();
    one_tree(0.0f);
    uint8_t *intact = shot();
    CHECK(render_read_attached(R, 0, got, &err) == 0);
    int attached = 0;
    for (uint32_t i = 0; i < A.n_nodes; i++) {
        attached += got[i];
    }
    CHECK(attached == (int)A.n_nodes);
    /* another tree's break and a node past the species change nothing here */
    const uint64_t keys[3] = { (0ull << 32) | BRANCH, (0ull << 32) | 0xFFFFFFu,
                               (5ull << 32) | 1u };
    CHECK(render_set_broken(R, 3, keys, &err) == 0);
    uint8_t *broken = shot();
    CHECK(render_read_attached(R, 0, got, &err) == 0);
    /* the GPU's flag is the C mask: exactly the descendants of the broken node go */
    damage_cut_mask(A.parent, A.n_nodes, &BRANCH, 1, false, want);
    CHECK(memcmp(got, want, A.n_nodes) == 0);
    int tree_px = 0, gone = 0, to_bg = 0, appeared = 0;
    for (int i = 0; i < W * H; i++) {
        tree_px += differs(intact, bg, i);
        if (differs(intact, broken, i)) {
            gone++;
            to_bg += !differs(broken, bg, i);
            appeared += !differs(intact, bg, i); /* drawn where the intact tree was not */
        }
    }
    fprintf(stderr, "tree %d px, branch %d px (%d now sky or ground), %d new\n", tree_px, gone,
            to_bg, appeared);
    CHECK(gone > 150 && gone < tree_px / 2);
    CHECK(to_bg > gone / 2);
    CHECK(appeared < gone / 20 + 5);
    /* the piece in place (the tree's own frame, rest pose) draws the branch again */
    const render_debris d = { .tree = 0, .node = BRANCH, .yaw = 0.4f };
    CHECK(render_set_debris(R, 1, &d, &err) == 0);
    uint8_t *both = shot();
    CHECK(render_read_attached(R, 1, got, &err) == 0);
    damage_cut_mask(A.parent, A.n_nodes, &BRANCH, 1, true, want);
    CHECK(memcmp(got, want, A.n_nodes) == 0);
    int off = 0;
    for (int i = 0; i < W * H; i++) {
        off += differs(both, intact, i);
    }
    fprintf(stderr, "piece in place: %d px off the intact tree\n", off);
    CHECK(off < gone / 6);
    /* bad input */
    const uint64_t desc[2] = { 5, 3 };
    CHECK(render_set_broken(R, 2, desc, &err) == GALE_E_ARG);
    CHECK_STR_HAS(err.msg, "ascending");
    const render_debris bad = { .tree = 3, .node = 1 };
    CHECK(render_set_debris(R, 1, &bad, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "tree 3");
    CHECK(render_set_debris(R, RENDER_MAX_DEBRIS + 1, &d, &err) == GALE_E_RANGE);
    CHECK(render_set_broken(R, 0, NULL, &err) == 0);
    CHECK(render_set_debris(R, 0, NULL, &err) == 0);
    uint8_t *healed = shot();
    off = 0;
    for (int i = 0; i < W * H; i++) {
        off += differs(healed, intact, i);
    }
    CHECK(off == 0);
    free(bg);
    free(intact);
    free(broken);
    free(both);
    free(healed);
    free(want);
    free(got);
}

/* screen position [px, top row 0] of world point p under cam, as render.c builds it */
static void project_cam(const render_camera *cam, const float p[3], float px[2])
{
    mat4 view, proj, vp;
    glm_lookat((vec3){ cam->eye[0], cam->eye[1], cam->eye[2] },
               (vec3){ cam->target[0], cam->target[1], cam->target[2] }, (vec3){ 0, 0, 1 }, view);
    glm_perspective(glm_rad(50.0f), (float)W / (float)H, 0.3f, 3000.0f, proj);
    glm_mat4_mul(proj, view, vp);
    vec4 c;
    glm_mat4_mulv(vp, (vec4){ p[0], p[1], p[2], 1.0f }, c);
    px[0] = (c[0] / c[3] * 0.5f + 0.5f) * W;
    px[1] = (0.5f - c[1] / c[3] * 0.5f) * H;
}

static void project(const float p[3], float px[2])
{
    project_cam(&CAM, p, px);
}

/* where the piece's nodes go: P + R · rest, averaged, on screen */
static void predicted(const float pos[3], float yaw, float fall, float az, const uint8_t *mask,
                      float px[2])
{
    float r[9], c[3] = { 0, 0, 0 };
    debris_frame_matrix(yaw, fall, az, r);
    int n = 0;
    for (uint32_t i = 0; i < A.n_nodes; i++) {
        if (!mask[i]) {
            continue;
        }
        const float *p = &A.rest[3 * i];
        for (int k = 0; k < 3; k++) {
            c[k] += pos[k] + r[k] * p[0] + r[3 + k] * p[1] + r[6 + k] * p[2];
        }
        n++;
    }
    for (int k = 0; k < 3; k++) {
        c[k] /= (float)n;
    }
    project(c, px);
}

static void test_piece_frame(void)
{
    uint8_t *mask = malloc(A.n_nodes);
    damage_cut_mask(A.parent, A.n_nodes, &BRANCH, 1, true, mask);
    one_tree(-60.0f); /* the tree itself behind the camera */
    uint8_t *bg = shot();
    const float pos[3] = { 1.0f, -2.0f, 10.0f };
    /* upside down (fall > π/2 reaches past the old 2 rad encoding), yawed, tipped to az */
    const float yaw = 0.9f, fall = 2.5f, az = 1.1f;
    float r[9], y2, f2, a2;
    debris_frame_matrix(yaw, fall, az, r);
    debris_frame_angles(r, &y2, &f2, &a2);
    const render_debris d = { .tree = 0, .node = BRANCH, .pos = { pos[0], pos[1], pos[2] },
                              .yaw = y2, .fall_rad = f2, .fall_az_rad = a2 };
    CHECK(render_set_debris(R, 1, &d, &err) == 0);
    uint8_t *img = shot();
    double sx = 0.0, sy = 0.0;
    int n = 0;
    for (int i = 0; i < W * H; i++) {
        if (differs(img, bg, i)) {
            sx += i % W + 0.5;
            sy += i / W + 0.5;
            n++;
        }
    }
    float want[2], other[2];
    predicted(pos, yaw, fall, az, mask, want);
    predicted(pos, yaw, fall, az + 1.5707963f, mask, other);
    fprintf(stderr, "piece: %d px at (%.1f, %.1f), C frame says (%.1f, %.1f)\n", n,
            n ? sx / n : 0.0, n ? sy / n : 0.0, (double)want[0], (double)want[1]);
    (void)y2;
    CHECK(n > 100);
    if (n > 0) {
        CHECK(hypot(sx / n - (double)want[0], sy / n - (double)want[1]) < 12.0);
        /* and the check can tell: another azimuth is far from it */
        CHECK(hypotf(other[0] - want[0], other[1] - want[1]) > 30.0f);
    }
    CHECK(render_set_debris(R, 0, NULL, &err) == 0);
    free(bg);
    free(img);
    free(mask);
}

/* The pixels of img that bg lacks: their count, centroid and extent [px]. */
typedef struct blob {
    int n;
    double cx, cy, sx, sy;
} blob;

static blob blob_of(const uint8_t *img, const uint8_t *bg)
{
    blob b = { 0 };
    double sx = 0, sy = 0, sxx = 0, syy = 0;
    for (int i = 0; i < W * H; i++) {
        if (differs(img, bg, i)) {
            const double x = i % W, y = i / W;
            b.n++;
            sx += x;
            sy += y;
            sxx += x * x;
            syy += y * y;
        }
    }
    if (b.n > 0) {
        b.cx = sx / b.n;
        b.cy = sy / b.n;
        b.sx = sqrt(fmax(sxx / b.n - b.cx * b.cx, 0.0));
        b.sy = sqrt(fmax(syy / b.n - b.cy * b.cy, 0.0));
    }
    return b;
}

/* far away a fallen tree is an impostor laid along its fall, as a standing one is an
 * impostor standing: from 320 m straight above (image right +x, up +y) a tree fallen towards
 * +x covers pixels right of its base, long along x and narrow along y, one fallen towards
 * +y pixels above its base; a standing one seen from above is a quad on edge. Within THIN
 * it is posed and lies as it lies; in THIN's fade band both. */
static void test_fallen_billboard(void)
{
    render_instance in = { .species = 0, .pos = { 0.0f, 400.0f, 0.0f }, .scale = 1.0f };
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    free(shot());
    render_stats st = render_get_stats(R);
    CHECK(st.trees_billboard == 1);
    render_set_damage(R, 0, 1.536f, 0.0f, 0);
    render_trees_commit(R);
    free(shot());
    st = render_get_stats(R);
    CHECK(st.trees_billboard == 1 && st.trees_full == 0);
    in.pos[1] = 150.0f;
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    render_set_damage(R, 0, 1.536f, 0.0f, 0);
    render_trees_commit(R);
    free(shot());
    st = render_get_stats(R);
    CHECK(st.trees_billboard == 0 && st.trees_full == 1 && st.trees_thin == 1);
    in.pos[1] = 220.0f; /* 235 m from the eye: in THIN's fade band */
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    render_set_damage(R, 0, 1.536f, 0.0f, 0);
    render_trees_commit(R);
    free(shot());
    st = render_get_stats(R);
    CHECK(st.trees_billboard == 1 && st.trees_full == 1);

    /* from above */
    const render_camera top = { .eye = { 0.0f, 0.0f, 320.0f }, .target = { 0.0f, 0.0f, 0.0f },
                                .up = { 0.0f, 1.0f, 0.0f }, .fov_y_deg = 3.0f };
    in.pos[1] = 0.0f;
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    render_set_damage(R, 0, 0.0f, 0.0f, 0);
    render_trees_commit(R);
    render_instance none = { .species = 0, .pos = { 5000.0f, 5000.0f, 0.0f }, .scale = 1.0f };
    CHECK(render_set_instances(R, 1, &none, &err) == 0);
    uint8_t *bg = shot_cam(&top);
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    uint8_t *standing = shot_cam(&top);
    st = render_get_stats(R);
    CHECK(st.trees_billboard == 1 && st.trees_full == 0);
    const blob bs = blob_of(standing, bg);
    render_set_damage(R, 0, 1.5707963f, 0.0f, 0); /* towards +x */
    render_trees_commit(R);
    uint8_t *fx = shot_cam(&top);
    st = render_get_stats(R);
    CHECK(st.trees_billboard == 1 && st.trees_full == 0);
    const blob bx = blob_of(fx, bg);
    render_set_damage(R, 0, 1.5707963f, 1.5707963f, 0); /* towards +y */
    render_trees_commit(R);
    uint8_t *fy = shot_cam(&top);
    const blob by = blob_of(fy, bg);
    fprintf(stderr,
            "from above: standing %d px; fallen +x %d px at (%.0f, %.0f) spread %.0f x %.0f; "
            "fallen +y %d px at (%.0f, %.0f) spread %.0f x %.0f (base at %d, %d)\n",
            bs.n, bx.n, bx.cx, bx.cy, bx.sx, bx.sy, by.n, by.cx, by.cy, by.sx, by.sy, W / 2,
            H / 2);
    CHECK(bx.n > 20 * (bs.n + 10));
    CHECK(bx.cx > W / 2 + 30 && fabs(bx.cy - H / 2) < 15 && bx.sx > 2.0 * bx.sy);
    CHECK(by.n > 20 * (bs.n + 10));
    CHECK(by.cy < H / 2 - 30 && fabs(by.cx - W / 2) < 15 && by.sy > 2.0 * by.sx);
    stbi_write_png(GALE_TEST_DIR "/render_fallen_impostor_top.png", W, H, 3, fx, W * 3);
    /* the view moved 8 m along +x: its edge cuts the tree's cell, which is then walked tree
       by tree, not listed whole as above; the same impostor, 8 m to the left */
    const render_camera cut = { .eye = { 8.0f, 0.0f, 320.0f }, .target = { 8.0f, 0.0f, 0.0f },
                                .up = { 0.0f, 1.0f, 0.0f }, .fov_y_deg = 3.0f };
    const float px_m = (float)H / (2.0f * 320.0f * tanf(1.5f * 3.1415927f / 180.0f));
    CHECK(render_set_instances(R, 1, &none, &err) == 0);
    uint8_t *bg_cut = shot_cam(&cut);
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    render_set_damage(R, 0, 1.5707963f, 0.0f, 0);
    render_trees_commit(R);
    uint8_t *fcut = shot_cam(&cut);
    st = render_get_stats(R);
    CHECK(st.trees_billboard == 1 && st.trees_full == 0);
    const blob bc = blob_of(fcut, bg_cut);
    fprintf(stderr,
            "cut cell: fallen +x %d px at (%.0f, %.0f), listed whole %.0f px further right\n",
            bc.n, bc.cx, bc.cy, 8.0 * (double)px_m);
    CHECK(abs(bc.n - bx.n) < bx.n / 10);
    CHECK(fabs(bc.cx + 8.0 * (double)px_m - bx.cx) < 3.0 && fabs(bc.cy - bx.cy) < 2.0);
    free(bg);
    free(bg_cut);
    free(standing);
    free(fx);
    free(fy);
    free(fcut);

    /* a picture: three standing impostors and one fallen towards +x between them, seen
       from 333 m off and 220 m up */
    render_instance four[4];
    for (int k = 0; k < 4; k++) {
        four[k] = (render_instance){ .species = 0, .pos = { -18.0f + 12.0f * (float)k, 0.0f, 0.0f },
                                     .scale = 1.0f };
    }
    CHECK(render_set_instances(R, 4, four, &err) == 0);
    render_set_damage(R, 2, 1.5707963f, 0.0f, 0);
    render_trees_commit(R);
    const render_camera side = { .eye = { 0.0f, -250.0f, 220.0f }, .target = { 0.0f, 0.0f, 3.0f },
                                 .fov_y_deg = 6.0f };
    uint8_t *pic = shot_cam(&side);
    st = render_get_stats(R);
    CHECK(st.trees_billboard == 4 && st.trees_full == 0);
    stbi_write_png(GALE_TEST_DIR "/render_fallen_impostor.png", W, H, 3, pic, W * 3);
    free(pic);
    render_set_damage(R, 2, 0.0f, 0.0f, 0);
    render_trees_commit(R);
}

/* an uprooted tree lifts its root plate: soil-brown pixels at its base that a snapped one
 * lying the same way does not have */
static void test_root_plate(void)
{
    one_tree(0.0f);
    render_set_damage(R, 0, 1.536f, 1.5707963f, 0); /* away from the camera */
    render_trees_commit(R);
    uint8_t *snapped = shot();
    render_set_uprooted(R, 0, true);
    render_trees_commit(R);
    uint8_t *uprooted = shot();
    int plate = 0, brown = 0;
    for (int i = 0; i < W * H; i++) {
        if (differs(uprooted, snapped, i)) {
            plate++;
            const uint8_t *p = &uprooted[3 * i];
            brown += p[0] > p[2] + 10 && p[0] >= p[1]; /* soil: red over blue, not green */
        }
    }
    double m[3] = { 0, 0, 0 };
    for (int i = 0; i < W * H; i++) {
        if (differs(uprooted, snapped, i)) {
            for (int k = 0; k < 3; k++) {
                m[k] += uprooted[3 * i + k] / (double)plate;
            }
        }
    }
    if (getenv("GALE_DUMP")) {
        stbi_write_png(getenv("GALE_DUMP"), W, H, 3, uprooted, W * 3);
    }
    fprintf(stderr, "root plate: %d px, %d soil-coloured, mean %.0f %.0f %.0f\n", plate, brown,
            m[0], m[1], m[2]);
    CHECK(plate > 200);
    CHECK(brown > plate / 3);
    render_set_uprooted(R, 0, false);
    render_set_damage(R, 0, 0.0f, 0.0f, 0);
    render_trees_commit(R);
    free(snapped);
    free(uprooted);
}

/* pixels of a far tree's billboard (a narrow lens on a tree 400 m off) that the background
 * lacks */
static int bill_px(const render_camera *cam, const uint8_t *bg)
{
    uint8_t *img = shot_cam(cam);
    CHECK(render_get_stats(R).trees_billboard == 1 && render_get_stats(R).trees_full == 0);
    if (getenv("GALE_DUMP_BILL")) {
        static int k;
        char path[512];
        snprintf(path, sizeof path, "%s%d.png", getenv("GALE_DUMP_BILL"), k++);
        stbi_write_png(path, W, H, 3, img, W * 3);
    }
    int n = 0;
    for (int i = 0; i < W * H; i++) {
        n += differs(img, bg, i);
    }
    free(img);
    return n;
}

/* A far tree's billboard keeps the share of its leaves the crown kept: stripped levels and
 * broken branches thin it by leaf slots left (damage_cut_mask), the wood stays. */
static void test_billboard_thins(void)
{
    const render_camera cam = { .eye = { 0.0f, 0.0f, 4.5f }, .target = { 0.0f, 400.0f, 4.5f },
                                .fov_y_deg = 2.5f };
    render_instance in = { .species = 0, .pos = { 0.0f, -60.0f, 0.0f }, .scale = 1.0f };
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    uint8_t *bg = shot_cam(&cam);
    in.pos[1] = 400.0f;
    CHECK(render_set_instances(R, 1, &in, &err) == 0);
    const int full = bill_px(&cam, bg);
    render_set_damage(R, 0, 0.0f, 0.0f, WIRE_DAMAGE_LEVELS);
    render_trees_commit(R);
    const int wood = bill_px(&cam, bg);
    render_set_damage(R, 0, 0.0f, 0.0f, WIRE_DAMAGE_LEVELS / 2);
    render_trees_commit(R);
    const int half = bill_px(&cam, bg);
    render_set_damage(R, 0, 0.0f, 0.0f, 0);
    render_trees_commit(R);
    /* a broken branch: the share of leaf slots on what stays */
    uint8_t *mask = malloc(A.n_nodes);
    damage_cut_mask(A.parent, A.n_nodes, &BRANCH, 1, false, mask);
    uint32_t kept = 0;
    for (uint32_t l = 0; l < A.n_leaves; l++) {
        kept += mask[A.leaf_node[l]];
    }
    const double share = (double)kept / A.n_leaves;
    const uint64_t key = BRANCH;
    CHECK(render_set_broken(R, 1, &key, &err) == 0);
    const int broken = bill_px(&cam, bg);
    CHECK(render_set_broken(R, 0, NULL, &err) == 0);
    const double leaf_px = full - wood;
    fprintf(stderr, "billboard: %d px whole, %d wood alone, %d at half the leaf levels (%.2f of "
                    "the leaves), %d with a branch off (%.2f, the slots left %.2f)\n",
            full, wood, half, (half - wood) / leaf_px, broken, (broken - wood) / leaf_px, share);
    CHECK(full > 400 && wood > 20 && leaf_px > full / 4);
    CHECK(fabs((half - wood) / leaf_px - 0.5) < 0.1);
    CHECK(fabs((broken - wood) / leaf_px - share) < 0.1);
    CHECK(share < 0.9);
    free(mask);
    free(bg);
}

/* A snapped tree leaves a stump up to its break (tip_fall_break_m, the C copy of the
 * shaders' stump_break_m) and its fallen part lies on the stump's top; an uprooted tree
 * has none. Tree 1 of two, so the hash is not only checked at 0. */
static void test_stump(void)
{
    const render_camera cam = { .eye = { 0.0f, -3.5f, 1.6f }, .target = { 0.0f, 0.0f, 0.9f } };
    render_instance in[2] = { { .species = 0, .pos = { 0.0f, -60.0f, 0.0f }, .scale = 1.0f },
                              { .species = 0, .pos = { 0.0f, -60.0f, 0.0f }, .yaw = 0.4f,
                                .scale = 1.0f } };
    CHECK(render_set_instances(R, 2, in, &err) == 0);
    uint8_t *bg = shot_cam(&cam);
    in[1].pos[1] = 0.0f;
    CHECK(render_set_instances(R, 2, in, &err) == 0);
    free(shot_cam(&cam));
    CHECK(render_get_stats(R).stumps == 0); /* standing */
    render_set_damage(R, 1, 1.536f, 0.0f, 0); /* lying towards +x, across the view */
    render_trees_commit(R);
    uint8_t *img = shot_cam(&cam);
    CHECK(render_get_stats(R).stumps == 1);
    if (getenv("GALE_DUMP_STUMP")) {
        stbi_write_png(getenv("GALE_DUMP_STUMP"), W, H, 3, img, W * 3);
    }
    const float h = tip_fall_break_m(1), r = A.radius[0];
    /* the stump's left half (the fallen butt starts at x ≈ 0): its top edge and its fill */
    float a[2], b[2], lo[2], hi[2], g[2];
    project_cam(&cam, (float[3]){ -0.85f * r, -r, 0.5f * h }, a);
    project_cam(&cam, (float[3]){ -0.45f * r, -r, 0.5f * h }, b);
    project_cam(&cam, (float[3]){ -0.65f * r, 0.0f, h - 0.2f }, lo);
    project_cam(&cam, (float[3]){ -0.65f * r, 0.0f, h + 0.25f }, hi);
    project_cam(&cam, (float[3]){ -0.65f * r, -r, 0.15f }, g);
    int tops = 0, good = 0, fill = 0, area = 0;
    for (int x = (int)ceilf(a[0]); x < (int)b[0]; x++) {
        int top = -1;
        for (int y = (int)hi[1] - 12; y < (int)g[1]; y++) {
            if (differs(img, bg, y * W + x)) {
                top = top < 0 ? y : top;
                if (y > (int)lo[1] + 3) {
                    fill++;
                }
            }
            area += y > (int)lo[1] + 3;
        }
        tops++;
        good += top >= (int)hi[1] - 1 && top <= (int)lo[1] + 1;
    }
    fprintf(stderr, "stump: h %.2f m, r %.2f m, %d columns, %d with their top at the break, "
                    "%d of %d px filled below it\n",
            (double)h, (double)r, tops, good, fill, area);
    CHECK(tops >= 4);
    CHECK(good >= tops - 1);
    CHECK(fill > area * 8 / 10);
    /* the fallen part lies on the stump: 1.2 m out, its stem is at the break's height */
    float e[2], want[2];
    project_cam(&cam, (float[3]){ 1.2f, 0.0f, h + 1.2f * cosf(1.536f) }, want);
    project_cam(&cam, (float[3]){ 1.2f, 0.0f, -0.5f }, e);
    double sy = 0.0;
    int n = 0;
    for (int y = (int)want[1] - 40; y < (int)e[1]; y++) {
        if (y >= 0 && y < H && differs(img, bg, y * W + (int)want[0])) {
            sy += y;
            n++;
        }
    }
    fprintf(stderr, "fallen stem 1.2 m out: %d px about row %.1f, the break's height is row %.1f\n",
            n, n ? sy / n : 0.0, (double)want[1]);
    CHECK(n >= 3);
    CHECK(n > 0 && fabs(sy / n - (double)want[1]) < 5.0);
    render_set_uprooted(R, 1, true);
    render_trees_commit(R);
    free(shot_cam(&cam));
    CHECK(render_get_stats(R).stumps == 0);
    render_set_uprooted(R, 1, false);
    render_set_damage(R, 1, 0.0f, 0.0f, 0);
    render_trees_commit(R);
    free(bg);
    free(img);
}

int main(void)
{
    R = render_create(&(render_desc){ .width = W, .height = H, .headless = true,
                                      .max_trees = 4, .max_falling = 64 }, &err);
    if (!R) {
        fprintf(stderr, "render_create: %s\n", err.msg);
        return 1;
    }
    if (render_demo_asset(&A, &(render_demo_desc){ .n_nodes = 150, .n_modes = 6, .seed = 3 },
                          &err) < 0 ||
        render_add_species(R, &A, &err) < 0) {
        fprintf(stderr, "species: %s\n", err.msg);
        return 1;
    }
    RUN(test_branch_hidden);
    RUN(test_piece_frame);
    RUN(test_fallen_billboard);
    RUN(test_root_plate);
    RUN(test_stump);
    RUN(test_billboard_thins);
    render_destroy(R);
    render_demo_free(&A);
    return check_report();
}
