/* Frustum culling for gale_render (see render_cull.h): a sphere per tree, cells of trees,
 * and the cone a client asks the server for. No GL here, so tests run it without a
 * context. */
#include "render_cull.h"

#include <cglm/cglm.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

void render_cull_planes(const float viewproj[16], float planes[6][4])
{
    vec4 pl[6];
    mat4 vp; /* cglm wants its 16-byte alignment */
    memcpy(vp, viewproj, sizeof vp);
    glm_frustum_planes(vp, pl);
    memcpy(planes, pl, sizeof pl);
}

float render_cull_sphere(const render_instance *in, const render_cull_species *s, float c[3])
{
    float sc = in->scale > 0.0f ? in->scale : 1.0f;
    c[0] = in->pos[0];
    c[1] = in->pos[1];
    c[2] = in->pos[2] + 0.5f * s->height_m * sc;
    /* bound: the crown can sway by a good part of its height */
    return sc * sqrtf(0.25f * s->height_m * s->height_m + s->crown_r_m * s->crown_r_m) * 1.3f;
}

void render_cells_free(render_cells *g)
{
    free(g->cell);
    free(g->tree);
    free(g->sphere);
    free(g->species);
    free(g->bill_leaf);
    free(g->bill_fall);
    free(g->at_of);
    free(g->bulk);
    free(g->cell_of);
    free(g->where);
    *g = (render_cells){ 0 };
}

int render_cells_build(render_cells *g, const render_instance *inst, uint32_t n,
                       const render_cull_species *sp)
{
    render_cells_free(g);
    if (n == 0) {
        return 0;
    }
    float lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
    for (uint32_t i = 0; i < n; i++) {
        for (int k = 0; k < 2; k++) {
            lo[k] = fminf(lo[k], inst[i].pos[k]);
            hi[k] = fmaxf(hi[k], inst[i].pos[k]);
        }
    }
    /* square cells holding RENDER_CELL_TREES trees on average, at most 1024 a side */
    float w = fmaxf(hi[0] - lo[0], 1.0f), h = fmaxf(hi[1] - lo[1], 1.0f);
    float side = sqrtf(w * h * (float)RENDER_CELL_TREES / (float)n);
    uint32_t nx = (uint32_t)fminf(fmaxf(ceilf(w / side), 1.0f), 1024.0f);
    uint32_t ny = (uint32_t)fminf(fmaxf(ceilf(h / side), 1.0f), 1024.0f);
    uint32_t *start = calloc((size_t)nx * ny + 1, sizeof *start);
    uint32_t *of = malloc((size_t)n * sizeof *of);
    g->tree = malloc((size_t)n * sizeof *g->tree);
    g->sphere = malloc((size_t)n * sizeof *g->sphere);
    g->species = malloc((size_t)n * sizeof *g->species);
    g->bill_leaf = malloc((size_t)n * sizeof *g->bill_leaf);
    g->bill_fall = malloc((size_t)n * sizeof *g->bill_fall);
    g->at_of = malloc((size_t)n * sizeof *g->at_of);
    render_cell *all = calloc((size_t)nx * ny, sizeof *all);
    if (!start || !of || !g->tree || !g->sphere || !g->species || !g->bill_leaf ||
        !g->bill_fall || !g->at_of || !all) {
        free(start);
        free(of);
        free(all);
        render_cells_free(g);
        return -1;
    }
    for (uint32_t i = 0; i < n; i++) {
        uint32_t cx = (uint32_t)fminf((inst[i].pos[0] - lo[0]) / w * (float)nx, (float)(nx - 1));
        uint32_t cy = (uint32_t)fminf((inst[i].pos[1] - lo[1]) / h * (float)ny, (float)(ny - 1));
        of[i] = cy * nx + cx;
        start[of[i] + 1]++;
    }
    for (uint32_t k = 0; k < nx * ny; k++) {
        start[k + 1] += start[k];
        all[k] = (render_cell){ .lo = { INFINITY, INFINITY, INFINITY },
                                .hi = { -INFINITY, -INFINITY, -INFINITY },
                                .first = start[k] };
    }
    for (uint32_t i = 0; i < n; i++) {
        render_cell *c = &all[of[i]];
        const uint32_t at = c->first + c->count++;
        g->tree[at] = i;
        float ctr[3];
        float rad = render_cull_sphere(&inst[i], &sp[inst[i].species], ctr);
        memcpy(g->sphere[at], ctr, sizeof ctr);
        g->sphere[at][3] = rad;
        g->species[at] = inst[i].species;
        g->at_of[i] = at;
        g->bill_leaf[at] = 1.0f;
        g->bill_fall[at] = 0.0f;
        for (int k = 0; k < 3; k++) {
            c->lo[k] = fminf(c->lo[k], ctr[k] - rad);
            c->hi[k] = fmaxf(c->hi[k], ctr[k] + rad);
        }
    }
    /* the empty cells left out: start[] becomes the grid's index of the kept ones */
    uint32_t m = 0;
    for (uint32_t k = 0; k < nx * ny; k++) {
        start[k] = m;
        if (all[k].count) {
            all[m++] = all[k];
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        of[i] = start[of[i]];
    }
    free(start);
    g->cell = all;
    g->n_cells = m;
    g->cell_of = of;
    g->where = malloc(m);
    g->bulk = malloc((size_t)m * sizeof *g->bulk);
    g->n_trees = n;
    if (!g->where || !g->bulk) {
        render_cells_free(g);
        return -1;
    }
    return 0;
}

int render_cell_test(const render_cell *c, const float planes[6][4])
{
    bool cut = false;
    for (int k = 0; k < 6; k++) {
        const float *p = planes[k];
        /* the box's corner farthest along the plane's normal, and the nearest */
        float far_d = p[3], near_d = p[3];
        for (int i = 0; i < 3; i++) {
            far_d += p[i] * (p[i] >= 0.0f ? c->hi[i] : c->lo[i]);
            near_d += p[i] * (p[i] >= 0.0f ? c->lo[i] : c->hi[i]);
        }
        if (far_d <= 0.0f) {
            return RENDER_CELL_OUT;
        }
        cut |= near_d <= 0.0f;
    }
    return cut ? RENDER_CELL_CUT : RENDER_CELL_IN;
}

bool render_cull_visible(const float planes[6][4], const float eye[3],
                         const render_instance *in, const render_cull_species *s, float *dist_m)
{
    float c[3];
    float rad = render_cull_sphere(in, s, c);
    return render_cull_sphere_visible(planes, eye, c, rad, dist_m);
}

render_tree_lod render_cull_tree(const float planes[6][4], const float eye[3],
                                 const render_instance *in, const render_cull_species *s,
                                 const render_lod_desc *d)
{
    float dist_m;
    if (!render_cull_visible(planes, eye, in, s, &dist_m)) {
        return (render_tree_lod){ 0 };
    }
    return render_lod_pick(dist_m, s, d, false);
}

bool render_cull_cone(const float viewproj[16], const float eye[3], float axis[3],
                      float *fov_deg, float *far_m)
{
    mat4 vp, inv;
    memcpy(vp, viewproj, sizeof vp);
    if (!(fabsf(glm_mat4_det(vp)) > 0.0f)) {
        return false;
    }
    glm_mat4_inv(vp, inv);
    /* the frustum's corners, near (z = -1) and far (z = +1) in clip space, in the world */
    float corner[8][3], dir[8][3];
    float sum[3] = { 0.0f, 0.0f, 0.0f };
    for (int k = 0; k < 8; k++) {
        vec4 clip = { (k & 1) ? 1.0f : -1.0f, (k & 2) ? 1.0f : -1.0f, (k & 4) ? 1.0f : -1.0f,
                      1.0f };
        vec4 w;
        glm_mat4_mulv(inv, clip, w);
        if (!(fabsf(w[3]) > 0.0f)) {
            return false;
        }
        float len2 = 0.0f;
        for (int i = 0; i < 3; i++) {
            corner[k][i] = w[i] / w[3];
            dir[k][i] = corner[k][i] - eye[i];
            len2 += dir[k][i] * dir[k][i];
        }
        float len = sqrtf(len2);
        for (int i = 0; i < 3; i++) {
            dir[k][i] = len > 0.0f ? dir[k][i] / len : 0.0f;
            sum[i] += (k & 4) ? dir[k][i] : 0.0f; /* the far corners span the view */
        }
    }
    float n = sqrtf(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (!(n > 0.0f)) {
        return false;
    }
    float min_cos = 1.0f, depth = 0.0f;
    for (int i = 0; i < 3; i++) {
        axis[i] = sum[i] / n;
    }
    for (int k = 0; k < 8; k++) {
        float c = dir[k][0] * axis[0] + dir[k][1] * axis[1] + dir[k][2] * axis[2];
        float d = (corner[k][0] - eye[0]) * axis[0] + (corner[k][1] - eye[1]) * axis[1] +
                  (corner[k][2] - eye[2]) * axis[2];
        min_cos = fminf(min_cos, c);
        depth = fmaxf(depth, d);
    }
    *fov_deg = 2.0f * acosf(fmaxf(-1.0f, fminf(1.0f, min_cos))) * (180.0f / (float)M_PI);
    *far_m = depth;
    return true;
}
