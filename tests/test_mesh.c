/* Tube mesh and leaf slots: counts on a small hand-made skeleton, unit normals, weights
 * in [0, 1], each vertex skinned to an element's two nodes, rings at the node radius,
 * triangles wound outward, every LOD's indices in range, leaves only on terminal nodes;
 * the same on a generated oak, which must also pass the asset decoder's checks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "asset.h"
#include "check.h"
#include "lsystem.h"
#include "mesh.h"
#include "species.h"

static double dist3(const float *a, const float *b)
{
    double a0 = a[0], a1 = a[1], a2 = a[2], b0 = b[0], b1 = b[1], b2 = b[2];
    double dx = a0 - b0, dy = a1 - b1, dz = a2 - b2;
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static double norm3(const float *v)
{
    double x = v[0], y = v[1], z = v[2];
    return sqrt(x * x + y * y + z * z);
}

/* Invariants of any mesh_build output. */
static void check_mesh(const skeleton *s, const species *sp, const asset *a)
{
    int bad_normal = 0, bad_weight = 0, bad_bone = 0, bad_ring = 0;
    for (uint32_t v = 0; v < a->n_verts; v++) {
        double l = norm3(&a->mesh_normal[3 * v]);
        bad_normal += fabs(l - 1.0) > 1e-5;
        float w = a->mesh_weight[v];
        bad_weight += !(w >= 0.0f && w <= 1.0f);
        uint32_t b0 = a->mesh_bone[2 * v], b1 = a->mesh_bone[2 * v + 1];
        if (b0 >= (uint32_t)s->n || b1 >= (uint32_t)s->n) {
            bad_bone++;
            continue;
        }
        /* the two bones are an element: b0 is b1's parent (the root ring: b0 = 0, weight 0) */
        bad_bone += !(s->parent[b1] == (int)b0 || (b0 == 0 && w == 0.0f));
        /* a ring vertex sits at its node's radius: the end ring (weight 1) around b1 with
         * b1's radius, a start ring (weight 0) around b0 with the branch's radius (b1's) */
        uint32_t centre = w > 0.5f ? b1 : b0;
        double want = s->radius[b1];
        if (b0 == 0 && w == 0.0f && (b1 == 0 || s->parent[b1] == 0)) {
            /* root ring or a branch starting at the root: either radius */
            double d = dist3(&a->mesh_pos[3 * v], &s->pos[0]);
            double r0 = s->radius[0], r1 = s->radius[b1];
            bad_ring += !(fabs(d - r0) < 1e-4 || fabs(d - r1) < 1e-4);
        } else {
            bad_ring += fabs(dist3(&a->mesh_pos[3 * v], &s->pos[3 * centre]) - want) > 1e-4;
        }
    }
    CHECK(bad_normal == 0);
    CHECK(bad_weight == 0);
    CHECK(bad_bone == 0);
    CHECK(bad_ring == 0);
    CHECK(a->n_lods >= 1 && a->n_lods <= ASSET_MAX_LODS);
    uint32_t expect_first = 0;
    for (uint32_t l = 0; l < a->n_lods; l++) {
        CHECK(a->lod_first[l] == expect_first);
        CHECK(a->lod_count[l] % 3 == 0);
        expect_first += a->lod_count[l];
        if (l > 0) {
            CHECK(a->lod_count[l] <= a->lod_count[l - 1]);
        }
    }
    CHECK(expect_first == a->n_indices);
    int bad_index = 0, inward = 0;
    for (uint32_t i = 0; i < a->n_indices; i++) {
        bad_index += a->mesh_index[i] >= a->n_verts;
    }
    CHECK(bad_index == 0);
    if (bad_index == 0) {
        /* outward winding: the face normal agrees with the vertex normals */
        for (uint32_t t = 0; t < a->lod_count[0] / 3; t++) {
            const uint32_t *ix = &a->mesh_index[3 * t];
            const float *p0 = &a->mesh_pos[3 * ix[0]], *p1 = &a->mesh_pos[3 * ix[1]],
                        *p2 = &a->mesh_pos[3 * ix[2]];
            double e1[3], e2[3], fn[3], vn[3];
            for (int k = 0; k < 3; k++) {
                double q0 = p0[k], q1 = p1[k], q2 = p2[k];
                double n0 = a->mesh_normal[3 * ix[0] + k], n1 = a->mesh_normal[3 * ix[1] + k],
                       n2 = a->mesh_normal[3 * ix[2] + k];
                e1[k] = q1 - q0;
                e2[k] = q2 - q0;
                vn[k] = n0 + n1 + n2;
            }
            fn[0] = e1[1] * e2[2] - e1[2] * e2[1];
            fn[1] = e1[2] * e2[0] - e1[0] * e2[2];
            fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
            inward += fn[0] * vn[0] + fn[1] * vn[1] + fn[2] * vn[2] < 0.0;
        }
        CHECK(inward == 0);
    }
    /* leaves: only on terminal nodes, unit normals, the species' count per tip */
    int *nchild = calloc((size_t)s->n, sizeof *nchild);
    int terminals = 0;
    for (int i = 1; i < s->n; i++) {
        nchild[s->parent[i]]++;
    }
    for (int i = 1; i < s->n; i++) {
        terminals += nchild[i] == 0;
    }
    CHECK(a->n_leaves == (uint32_t)(terminals * sp->leaves_per_tip));
    int bad_leaf = 0;
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        uint32_t nd = a->leaf_node[l];
        const float *n = &a->leaf_normal[3 * l];
        double ln = norm3(n), off = norm3(&a->leaf_offset[3 * l]), nz = n[2];
        double size = a->leaf_size[l], want = sp->leaf_size_m, spread = sp->leaf_spread_deg;
        bad_leaf += nd == 0 || nd >= (uint32_t)s->n || nchild[nd] != 0 || fabs(ln - 1.0) > 1e-5 ||
                    !(size >= 0.79 * want && size <= 1.21 * want) || fabs(off - 0.5 * size) > 1e-4;
        /* blade normals within the spread of straight up */
        bad_leaf += acos(fmin(1.0, nz / ln)) > spread * 3.14159266 / 180.0;
    }
    CHECK(bad_leaf == 0);
    free(nchild);
    CHECK(memcmp(a->bark_rgb, sp->bark_rgb, sizeof a->bark_rgb) == 0);
    CHECK(memcmp(a->leaf_rgb, sp->leaf_rgb, sizeof a->leaf_rgb) == 0);
    CHECK(a->leaf_shape == (uint32_t)sp->leaf_shape);
}

static void test_small(void)
{
    /* root, trunk node 1, trunk top 2 (continuation), side branch 3 from node 1 */
    skeleton s;
    gale_err err = { 0 };
    CHECK(skeleton_alloc(&s, 4, &err) == 0);
    const int parent[4] = { -1, 0, 1, 1 };
    const float pos[12] = { 0, 0, 0, 0, 0, 2, 0, 0, 4, 1, 0, 3 };
    const float rad[4] = { 0.3f, 0.2f, 0.1f, 0.08f };
    const int order[4] = { 0, 0, 0, 1 };
    memcpy(s.parent, parent, sizeof parent);
    memcpy(s.pos, pos, sizeof pos);
    memcpy(s.radius, rad, sizeof rad);
    memcpy(s.order, order, sizeof order);
    species sp;
    species_default(&sp);
    sp.leaves_per_tip = 3;
    asset a;
    memset(&a, 0, sizeof a);
    CHECK(mesh_build(&s, &sp, &a, &err) == 0);
    /* a ring of 8 at each of 4 nodes, plus the side branch's own start ring */
    CHECK(a.n_verts == 5 * 8);
    /* LOD 0: 3 elements x 8 sides x 2 triangles */
    CHECK(a.lod_count[0] == 3 * 8 * 6);
    CHECK(a.n_lods == 3);
    /* LOD 1 (4 sides) drops elements whose thinner end is below 0.08 x 0.3 = 0.024 m:
     * none here */
    CHECK(a.lod_count[1] == 3 * 4 * 6);
    /* LOD 2 keeps thinner ends >= 0.2 x 0.3 = 0.06 m: the side branch (0.08) stays */
    CHECK(a.lod_count[2] == 3 * 4 * 6);
    CHECK(a.n_leaves == 2 * 3);
    check_mesh(&s, &sp, &a);
    /* the trunk continues through node 1: its element to node 2 starts on node 1's ring,
     * the side branch has a start ring centred on node 1 with the branch's radius */
    int side_start = 0;
    for (uint32_t v = 0; v < a.n_verts; v++) {
        if (a.mesh_bone[2 * v] == 1 && a.mesh_bone[2 * v + 1] == 3 && a.mesh_weight[v] == 0.0f) {
            side_start++;
        }
    }
    CHECK(side_start == 8);
    asset_fini(&a);

    /* a thin twig disappears at the coarse LODs */
    s.radius[3] = 0.005f;
    memset(&a, 0, sizeof a);
    CHECK(mesh_build(&s, &sp, &a, &err) == 0);
    CHECK(a.lod_count[0] == 3 * 8 * 6);
    CHECK(a.lod_count[1] == 2 * 4 * 6);
    check_mesh(&s, &sp, &a);
    asset_fini(&a);
    skeleton_fini(&s);
}

static void test_single_node(void)
{
    skeleton s;
    gale_err err = { 0 };
    CHECK(skeleton_alloc(&s, 1, &err) == 0);
    s.radius[0] = 0.1f;
    species sp;
    species_default(&sp);
    asset a;
    memset(&a, 0, sizeof a);
    CHECK(mesh_build(&s, &sp, &a, &err) == 0);
    CHECK(a.n_verts == 0 && a.n_indices == 0 && a.n_lods == 0 && a.n_leaves == 0);
    asset_fini(&a);
    skeleton_fini(&s);
    skeleton empty = { 0 };
    CHECK(mesh_build(&empty, &sp, &a, &err) == GALE_E_ARG);
}

static void test_species_meshes(void)
{
    const char *names[] = { "oak", "palm", "pine" };
    for (int k = 0; k < 3; k++) {
        char path[512];
        snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, names[k]);
        species sp;
        gale_err err = { 0 };
        CHECK(species_load(path, &sp, &err) == 0);
        skeleton s;
        CHECK(lsystem_generate(&sp.gen, &s, &err) == 0);
        asset a, b;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        CHECK(mesh_build(&s, &sp, &a, &err) == 0);
        CHECK(mesh_build(&s, &sp, &b, &err) == 0);
        check_mesh(&s, &sp, &a);
        /* deterministic */
        CHECK(a.n_verts == b.n_verts && a.n_leaves == b.n_leaves);
        CHECK(memcmp(a.mesh_pos, b.mesh_pos, 3 * a.n_verts * sizeof(float)) == 0);
        CHECK(memcmp(a.leaf_normal, b.leaf_normal, 3 * a.n_leaves * sizeof(float)) == 0);
        /* coarser LODs are much lighter */
        CHECK(a.lod_count[1] < a.lod_count[0] / 2);
        CHECK(a.lod_count[2] < a.lod_count[1]);
        /* the decoder accepts it: fill the skeleton part and round-trip */
        b.n_nodes = (uint32_t)s.n;
        asset_fini(&b);
        a.n_nodes = (uint32_t)s.n;
        a.parent = malloc((size_t)s.n * sizeof *a.parent);
        a.rest = malloc((size_t)s.n * 3 * sizeof *a.rest);
        a.radius = malloc((size_t)s.n * sizeof *a.radius);
        memcpy(a.parent, s.parent, (size_t)s.n * sizeof *a.parent);
        memcpy(a.rest, s.pos, (size_t)s.n * 3 * sizeof *a.rest);
        memcpy(a.radius, s.radius, (size_t)s.n * sizeof *a.radius);
        uint8_t *buf;
        size_t len;
        CHECK(asset_encode(&a, &buf, &len, &err) == 0);
        int rc = asset_decode(buf, len, names[k], &b, &err);
        if (rc) {
            fprintf(stderr, "%s\n", err.msg);
        }
        CHECK(rc == 0);
        free(buf);
        asset_fini(&a);
        asset_fini(&b);
        skeleton_fini(&s);
    }
}

int main(void)
{
    RUN(test_small);
    RUN(test_single_node);
    RUN(test_species_meshes);
    return check_report();
}
