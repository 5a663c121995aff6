/* In-code demo species: a trunk with whorls of branches and twigs (a few dozen to a few
 * thousand nodes), sway and branch modes whose shapes grow as (s/L)² from their base (a
 * clamped beam's first mode, roughly), and a quadratic term w that pulls a swaying node
 * down by |v|²/2z so branch length is nearly kept (Diener 2008 section 5.2). */
#include "render_demo.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hash.h"


static float rnd(uint32_t *s)
{
    *s = hash_mix32(*s + 0x9e3779b9u);
    return (float)(*s >> 8) / 16777216.0f;
}

typedef struct builder {
    uint32_t n, cap;
    int32_t *parent;
    float *rest, *radius;
    uint32_t *branch; /* which branch (mode group) a node belongs to; 0 = trunk */
    float *along;     /* distance from the base of its branch [m] */
    uint32_t *base;   /* base node of its branch */
} builder;

static int add_node(builder *b, int32_t parent, const float p[3], float r, uint32_t br,
                    float along, uint32_t base)
{
    if (b->n >= b->cap) {
        return -1;
    }
    uint32_t i = b->n++;
    b->parent[i] = parent;
    memcpy(&b->rest[3 * i], p, 3 * sizeof(float));
    b->radius[i] = r;
    b->branch[i] = br;
    b->along[i] = along;
    b->base[i] = base;
    return (int)i;
}

void render_demo_free(asset *a)
{
    if (!a) {
        return;
    }
    void *ptrs[] = { a->params_json, a->parent, a->rest, a->radius, a->omega, a->gamma,
                     a->wind_basis, a->phi, a->phi_rot, a->corr_v, a->corr_w, a->corr_a,
                     a->corr_b, a->mesh_pos, a->mesh_normal, a->mesh_bone, a->mesh_weight,
                     a->mesh_index, a->leaf_node, a->leaf_offset, a->leaf_normal,
                     a->leaf_size };
    for (size_t i = 0; i < sizeof ptrs / sizeof ptrs[0]; i++) {
        free(ptrs[i]);
    }
    memset(a, 0, sizeof *a);
}

static void basis(const float d[3], float u[3], float v[3])
{
    float k[3] = { 0, 0, 1 };
    if (fabsf(d[2]) > 0.9f) {
        k[0] = 1;
        k[2] = 0;
    }
    u[0] = d[1] * k[2] - d[2] * k[1];
    u[1] = d[2] * k[0] - d[0] * k[2];
    u[2] = d[0] * k[1] - d[1] * k[0];
    float l = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int c = 0; c < 3; c++) {
        u[c] /= l;
    }
    v[0] = d[1] * u[2] - d[2] * u[1];
    v[1] = d[2] * u[0] - d[0] * u[2];
    v[2] = d[0] * u[1] - d[1] * u[0];
}

int render_demo_asset(asset *a, const render_demo_desc *desc, gale_err *err)
{
    render_demo_desc d = desc ? *desc : (render_demo_desc){ 0 };
    if (d.n_nodes == 0) {
        d.n_nodes = 60;
    }
    if (d.n_modes == 0) {
        d.n_modes = 8;
    }
    if (d.leaves_per_tip == 0) {
        d.leaves_per_tip = 8;
    }
    if (d.height_m == 0.0f) {
        d.height_m = 9.0f;
    }
    if (d.seed == 0) {
        d.seed = 1;
    }
    if (d.n_nodes < 12 || d.n_nodes > 16000 || d.n_modes < 2 || d.n_modes > 64 ||
        d.leaf_shape > 2 || !(d.height_m > 0.5f) || d.leaves_per_tip > 64) {
        return gale_errf(err, GALE_E_ARG, "render_demo_asset: n_nodes 12..16000, n_modes "
                         "2..64, leaf_shape 0..2, height > 0.5, leaves_per_tip <= 64");
    }
    memset(a, 0, sizeof *a);
    builder b = { 0 };
    b.cap = d.n_nodes + 64;
    b.parent = calloc(b.cap, sizeof *b.parent);
    b.rest = calloc(3 * (size_t)b.cap, sizeof(float));
    b.radius = calloc(b.cap, sizeof(float));
    b.branch = calloc(b.cap, sizeof(uint32_t));
    b.along = calloc(b.cap, sizeof(float));
    b.base = calloc(b.cap, sizeof(uint32_t));
    if (!b.parent || !b.rest || !b.radius || !b.branch || !b.along || !b.base) {
        goto nomem;
    }
    uint32_t seed = d.seed;
    const float H = d.height_m;
    /* trunk: about a sixth of the nodes */
    uint32_t nt = d.n_nodes / 6 < 5 ? 5 : d.n_nodes / 6;
    float r0 = 0.018f * H + 0.05f;
    float p[3] = { 0, 0, 0 };
    add_node(&b, -1, p, r0, 0, 0.0f, 0);
    for (uint32_t i = 1; i < nt; i++) {
        float t = (float)i / (float)(nt - 1);
        float q[3] = { 0.15f * H * 0.05f * sinf(3.0f * t), 0.1f * H * 0.04f * cosf(2.0f * t),
                       t * H };
        add_node(&b, (int32_t)i - 1, q, r0 * (1.0f - 0.8f * t), 0, q[2], 0);
    }
    /* branches from the upper trunk, then twigs from branches, until the budget is used */
    uint32_t nbranch = 1;
    uint32_t per_branch = 4;
    uint32_t trunk_first = nt / 3;
    for (uint32_t pass = 0; b.n + per_branch + 1 < d.n_nodes && pass < d.n_nodes; pass++) {
        uint32_t from;
        if (pass < 2 * (nt - trunk_first)) {
            from = trunk_first + pass % (nt - trunk_first);
        } else {
            from = nt + (uint32_t)(rnd(&seed) * (float)(b.n - nt));
        }
        const float *fp = &b.rest[3 * from];
        float up = from < nt ? 0.35f + 0.3f * rnd(&seed) : 0.2f + 0.5f * rnd(&seed);
        float az = 6.2831853f * rnd(&seed);
        float dir[3] = { cosf(az) * sqrtf(1 - up * up), sinf(az) * sqrtf(1 - up * up), up };
        float len = (from < nt ? 0.45f : 0.25f) * H * (1.0f - 0.5f * fp[2] / H) *
                    (0.7f + 0.4f * rnd(&seed));
        float rb = b.radius[from] * 0.55f;
        uint32_t prev = from, base = from, br = nbranch++;
        for (uint32_t k = 1; k <= per_branch && b.n < d.n_nodes; k++) {
            float t = (float)k / (float)per_branch;
            float q[3] = { fp[0] + dir[0] * len * t, fp[1] + dir[1] * len * t,
                           fp[2] + dir[2] * len * t - 0.08f * len * t * t };
            int id = add_node(&b, (int32_t)prev, q, fmaxf(rb * (1.0f - 0.75f * t), 0.01f), br,
                              len * t, base);
            if (id < 0) {
                break;
            }
            prev = (uint32_t)id;
        }
    }
    uint32_t nn = b.n, nm = d.n_modes;
    a->n_nodes = nn;
    a->parent = b.parent;
    a->rest = b.rest;
    a->radius = b.radius;
    b.parent = NULL;
    b.rest = NULL;
    b.radius = NULL;
    for (uint32_t i = 0; i < nn; i++) {
        a->height_m = fmaxf(a->height_m, a->rest[3 * i + 2]);
    }
    strcpy(a->species, d.leaf_shape == 1 ? "demo-palm" : d.leaf_shape == 2 ? "demo-pine"
                                                                           : "demo-oak");
    a->n_modes = nm;
    a->omega = calloc(nm, sizeof(float));
    a->gamma = calloc(nm, sizeof(float));
    a->wind_basis = calloc(3 * (size_t)nm, sizeof(float));
    a->corr_v = calloc(3 * (size_t)nm * nn, sizeof(float));
    a->corr_w = calloc(3 * (size_t)nm * nn, sizeof(float));
    a->corr_a = calloc(nm, sizeof(float));
    a->corr_b = calloc(nm, sizeof(float));
    a->phi = calloc(3 * (size_t)nm * nn, sizeof(float));
    if (!a->omega || !a->gamma || !a->wind_basis || !a->corr_v || !a->corr_w || !a->corr_a ||
        !a->corr_b || !a->phi) {
        goto nomem;
    }
    for (uint32_t m = 0; m < nm; m++) {
        a->omega[m] = 6.2831853f * (0.4f + 0.35f * (float)m);
        a->gamma[m] = 0.3f + 0.02f * a->omega[m] * a->omega[m];
        a->corr_a[m] = 1.0f + 0.1f * (float)(m % 3);
        a->corr_b[m] = 1.0f / a->corr_a[m];
        float *vm = &a->phi[(size_t)m * 3 * nn];
        /* modes 0, 1: whole-tree sway in x and y; higher: pairs of branch modes, each
           moving the branches of one group across their axis */
        float dir[3] = { m % 2 == 0 ? 1.0f : 0.0f, m % 2 == 0 ? 0.0f : 1.0f, 0.0f };
        for (uint32_t i = 0; i < nn; i++) {
            float s = 0.0f;
            uint32_t br = b.branch[i];
            if (m < 2) {
                float z = a->rest[3 * i + 2] / H;
                s = 0.12f * H * z * z;
            } else if (br != 0) {
                uint32_t ngrp = (nm - 1) / 2;
                uint32_t grp = ((m - 2) / 2) % ngrp;
                if ((br - 1) % ngrp == grp) {
                    float t = b.along[i] / (0.45f * H);
                    s = 0.10f * H * t * t / (1.0f + (float)grp * 0.3f);
                }
                /* a twig rides on the branch it grows from */
                for (int c = 0; c < 3; c++) {
                    vm[3 * i + c] = vm[3 * b.base[i] + c];
                }
            }
            for (int c = 0; c < 3; c++) {
                vm[3 * i + c] += s * dir[c];
            }
        }
        /* p_i: sway modes catch the most wind; branch modes alternate sign */
        float pw = m < 2 ? 0.05f : (m % 4 < 2 ? 0.02f : -0.02f);
        a->wind_basis[3 * m] = dir[0] * pw;
        a->wind_basis[3 * m + 1] = dir[1] * pw;
    }

    /* the length-true pose's fields from these linear shapes (ASSET.md "CORR") */
    asset_pose_fields(a->rest, a->parent, nn, a->phi, nm, a->corr_v, a->corr_w);

    /* tube mesh: LOD 0 with 8 sides, LOD 1 with 4, one segment per non-root node */
    const uint32_t sides[2] = { 8, 4 };
    uint32_t nv = 0, ni = 0;
    for (int l = 0; l < 2; l++) {
        nv += (nn - 1) * 2 * sides[l];
        ni += (nn - 1) * 6 * sides[l];
    }
    a->n_verts = nv;
    a->n_indices = ni;
    a->mesh_pos = calloc(3 * (size_t)nv, sizeof(float));
    a->mesh_normal = calloc(3 * (size_t)nv, sizeof(float));
    a->mesh_bone = calloc(2 * (size_t)nv, sizeof(uint32_t));
    a->mesh_weight = calloc(nv, sizeof(float));
    a->mesh_index = calloc(ni, sizeof(uint32_t));
    if (!a->mesh_pos || !a->mesh_normal || !a->mesh_bone || !a->mesh_weight || !a->mesh_index) {
        goto nomem;
    }
    uint32_t v = 0, k = 0;
    a->n_lods = 2;
    for (int l = 0; l < 2; l++) {
        a->lod_first[l] = k;
        uint32_t S = sides[l];
        for (uint32_t j = 1; j < nn; j++) {
            uint32_t pj = (uint32_t)a->parent[j];
            const float *p0 = &a->rest[3 * pj], *p1 = &a->rest[3 * j];
            float dd[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
            float dl = sqrtf(dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2]);
            for (int c = 0; c < 3; c++) {
                dd[c] /= dl;
            }
            float u[3], w[3];
            basis(dd, u, w);
            /* a branch starts at its parent node with its own (thinner) radius */
            float rad0 = b.branch[j] != b.branch[pj] ? a->radius[j] * 1.15f : a->radius[pj];
            uint32_t v0 = v;
            for (int end = 0; end < 2; end++) {
                const float *c0 = end ? p1 : p0;
                float rad = end ? a->radius[j] : rad0;
                for (uint32_t s = 0; s < S; s++) {
                    float ang = 6.2831853f * (float)s / (float)S;
                    float n3[3];
                    for (int c = 0; c < 3; c++) {
                        n3[c] = cosf(ang) * u[c] + sinf(ang) * w[c];
                        a->mesh_pos[3 * v + c] = c0[c] + rad * n3[c];
                        a->mesh_normal[3 * v + c] = n3[c];
                    }
                    a->mesh_bone[2 * v] = pj;
                    a->mesh_bone[2 * v + 1] = j;
                    a->mesh_weight[v] = end ? 1.0f : 0.0f;
                    v++;
                }
            }
            for (uint32_t s = 0; s < S; s++) {
                uint32_t s1 = (s + 1) % S;
                uint32_t i0 = v0 + s, i1 = v0 + s1, i2 = v0 + S + s, i3 = v0 + S + s1;
                uint32_t tri[6] = { i0, i1, i3, i0, i3, i2 };
                memcpy(&a->mesh_index[k], tri, sizeof tri);
                k += 6;
            }
        }
        a->lod_count[l] = k - a->lod_first[l];
    }

    /* leaves on terminal nodes */
    uint8_t *has_child = calloc(nn, 1);
    if (!has_child) {
        goto nomem;
    }
    for (uint32_t j = 1; j < nn; j++) {
        has_child[a->parent[j]] = 1;
    }
    uint32_t ntip = 0;
    for (uint32_t j = 0; j < nn; j++) {
        ntip += !has_child[j];
    }
    /* leaves also along the outer half of each branch, so the crown is full */
    uint32_t nl = 0;
    for (uint32_t j = nt; j < nn; j++) {
        nl += !has_child[j] ? d.leaves_per_tip : (b.branch[j] ? d.leaves_per_tip / 2 : 0);
    }
    a->n_leaves = nl;
    a->leaf_node = calloc(nl + 1, sizeof(uint32_t));
    a->leaf_offset = calloc(3 * (size_t)nl + 1, sizeof(float));
    a->leaf_normal = calloc(3 * (size_t)nl + 1, sizeof(float));
    a->leaf_size = calloc(nl + 1, sizeof(float));
    if (!a->leaf_node || !a->leaf_offset || !a->leaf_normal || !a->leaf_size) {
        free(has_child);
        goto nomem;
    }
    float lsize = d.leaf_shape == 1 ? 0.09f * H : d.leaf_shape == 2 ? 0.035f * H : 0.03f * H;
    uint32_t li = 0;
    for (uint32_t j = nt; j < nn; j++) {
        uint32_t cnt = !has_child[j] ? d.leaves_per_tip : (b.branch[j] ? d.leaves_per_tip / 2 : 0);
        for (uint32_t c = 0; c < cnt; c++, li++) {
            float az = 6.2831853f * rnd(&seed), el = -0.5f + 1.2f * rnd(&seed);
            float sp = (d.leaf_shape == 1 ? 0.05f : 0.25f) * lsize * 4.0f * rnd(&seed);
            float o[3] = { cosf(az) * cosf(el) * sp, sinf(az) * cosf(el) * sp,
                           sinf(el) * sp };
            float na = 6.2831853f * rnd(&seed), ne = 0.3f + 0.6f * rnd(&seed);
            float n3[3] = { cosf(na) * cosf(ne), sinf(na) * cosf(ne), sinf(ne) };
            if (d.leaf_shape == 1) {
                /* palm fronds droop outward from the crown */
                o[2] = -0.2f * sp;
            }
            a->leaf_node[li] = j;
            memcpy(&a->leaf_offset[3 * li], o, sizeof o);
            memcpy(&a->leaf_normal[3 * li], n3, sizeof n3);
            a->leaf_size[li] = lsize * (0.75f + 0.5f * rnd(&seed));
        }
    }
    free(has_child);
    if (d.leaf_shape == 1) {
        const float bark[3] = { 0.55f, 0.48f, 0.38f }, leaf[3] = { 0.30f, 0.52f, 0.16f };
        memcpy(a->bark_rgb, bark, sizeof bark);
        memcpy(a->leaf_rgb, leaf, sizeof leaf);
    } else if (d.leaf_shape == 2) {
        const float bark[3] = { 0.36f, 0.24f, 0.17f }, leaf[3] = { 0.13f, 0.30f, 0.12f };
        memcpy(a->bark_rgb, bark, sizeof bark);
        memcpy(a->leaf_rgb, leaf, sizeof leaf);
    } else {
        const float bark[3] = { 0.38f, 0.30f, 0.22f }, leaf[3] = { 0.26f, 0.45f, 0.13f };
        memcpy(a->bark_rgb, bark, sizeof bark);
        memcpy(a->leaf_rgb, leaf, sizeof leaf);
    }
    a->leaf_shape = d.leaf_shape;
    free(b.branch);
    free(b.along);
    free(b.base);
    return 0;
nomem:
    free(b.parent);
    free(b.rest);
    free(b.radius);
    free(b.branch);
    free(b.along);
    free(b.base);
    render_demo_free(a);
    return gale_errf(err, GALE_E_NOMEM, "render_demo_asset: out of memory");
}

void render_demo_pose(const asset *a, const float wind[3], float t, uint32_t tree, float *q)
{
    float sp = sqrtf(wind[0] * wind[0] + wind[1] * wind[1] + wind[2] * wind[2]);
    for (uint32_t m = 0; m < a->n_modes; m++) {
        const float *p = &a->wind_basis[3 * m];
        float f = sp * (wind[0] * p[0] + wind[1] * p[1] + wind[2] * p[2]);
        float w2 = a->omega[m] * a->omega[m];
        uint32_t h = hash_mix32(tree * 131u + m * 7u + 1u);
        float ph = 6.2831853f * (float)(h >> 8) / 16777216.0f;
        /* static deflection plus a gust-driven oscillation at the mode's frequency */
        q[m] = f / w2 * (1.0f + 0.25f * sinf(a->omega[m] * t + ph)) +
               0.02f * sp * sinf(a->omega[m] * t + 2.0f * ph) / (1.0f + (float)m);
    }
}

void render_demo_forest(render_instance *out, uint32_t n, uint32_t n_species, float spacing,
                        uint32_t seed)
{
    uint32_t side = (uint32_t)ceilf(sqrtf((float)n));
    uint32_t s = seed ? seed : 1u;
    for (uint32_t i = 0; i < n; i++) {
        float gx = (float)(i % side) - 0.5f * (float)(side - 1);
        float gy = (float)(i / side) - 0.5f * (float)(side - 1);
        out[i] = (render_instance){ 0 }; /* standing, whole: no damage fields left unset */
        out[i].species = n_species ? (uint32_t)(rnd(&s) * (float)n_species) % n_species : 0;
        out[i].pos[0] = spacing * (gx + 0.7f * (rnd(&s) - 0.5f));
        out[i].pos[1] = spacing * (gy + 0.7f * (rnd(&s) - 0.5f));
        out[i].pos[2] = 0.0f;
        out[i].yaw = 6.2831853f * rnd(&s);
        out[i].scale = 0.8f + 0.4f * rnd(&s);
    }
}
