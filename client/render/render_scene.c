/* gale_render scene state: the trees (instances and their staged modal state q) and the
 * houses (obstacle boxes meshed by render_house.c and uploaded once per set); the coarse
 * wind is render_wind.c's. */
#include "render_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_house.h"

int render_trees_alloc(render *r, uint32_t cap, gale_err *err)
{
    free(r->inst);
    free(r->q_stage);
    free(r->list);
    free(r->tree_row);
    free(r->tree_group);
    free(r->tree_lod);
    free(r->tree_dist);
    free(r->vis);
    free(r->plates);
    free(r->stumps);
    free(r->leaf_attached);
    r->cap_trees = cap;
    const uint32_t slots = render_slots(r);
    r->inst = calloc(slots, sizeof *r->inst);
    r->q_stage = calloc((size_t)slots * r->q_stride, sizeof(float));
    r->list_cap = 6 * slots; /* skeleton, two leaf levels, two meshes, impostor */
    r->list = calloc((size_t)r->list_cap * 4, sizeof(float));
    r->tree_row = calloc(slots, sizeof(uint32_t));
    r->tree_group = calloc(slots, sizeof(uint32_t));
    r->tree_lod = calloc(slots, sizeof *r->tree_lod);
    r->tree_dist = calloc(slots, sizeof(float));
    r->vis = calloc(slots, sizeof(uint32_t));
    r->plates = calloc(cap + 1, sizeof(float));
    r->stumps = calloc((size_t)(cap + 1) * 8, sizeof(float));
    r->leaf_attached = malloc((size_t)(cap + 1) * sizeof(float));
    for (uint32_t i = 0; r->leaf_attached && i <= cap; i++) {
        r->leaf_attached[i] = 1.0f;
    }
    if (!r->plates || !r->stumps || !r->leaf_attached || !r->inst || !r->q_stage || !r->list || !r->tree_row || !r->tree_group || !r->tree_lod ||
        !r->tree_dist || !r->vis) {
        return gale_errf(err, GALE_E_NOMEM, "render: out of memory for %u trees", cap);
    }
    /* the rest-pose slot (index cap): origin, unit scale */
    r->inst[cap].scale = 1.0f;
    return 0;
}

void render_trees_upload(render *r)
{
    uint32_t n = render_slots(r);
    float *t = calloc((size_t)n * 8, sizeof(float));
    if (!t) {
        return;
    }
    for (uint32_t i = 0; i < n; i++) {
        const render_instance *in = &r->inst[i];
        t[8 * i + 0] = in->pos[0];
        t[8 * i + 1] = in->pos[1];
        t[8 * i + 2] = in->pos[2];
        t[8 * i + 3] = in->yaw;
        t[8 * i + 4] = in->scale > 0.0f ? in->scale : 1.0f;
        t[8 * i + 5] = (float)in->species;
        /* slot 1 .z: render_tree_code (render_set_debris writes its slots alike) */
        t[8 * i + 6] = render_tree_code(r, i);
        t[8 * i + 7] = in->fall_az_rad;
    }
    render_buf_upload(&r->trees, GL_RGBA32F, t, (size_t)n * 8 * sizeof(float));
    free(t);
}

int render_set_instances(render *r, uint32_t n, const render_instance *inst, gale_err *err)
{
    if (n > RENDER_MAX_TREES) {
        return gale_errf(err, GALE_E_RANGE, "render_set_instances: %u trees, at most %u", n,
                         RENDER_MAX_TREES);
    }
    for (uint32_t i = 0; i < n; i++) {
        if (inst[i].species >= r->n_species) {
            return gale_errf(err, GALE_E_RANGE,
                             "render_set_instances: tree %u: species %u "
                             "not added (%u species)",
                             i, inst[i].species, r->n_species);
        }
        if (!isfinite(inst[i].pos[0] + inst[i].pos[1] + inst[i].pos[2] + inst[i].yaw +
                      inst[i].scale) ||
            inst[i].scale < 0.0f) {
            return gale_errf(err, GALE_E_RANGE,
                             "render_set_instances: tree %u: position, "
                             "yaw or scale not finite or scale < 0",
                             i);
        }
    }
    if (n > r->cap_trees) {
        /* storage follows the scene: what max_trees gave at create is where it starts; the
           per-tree arrays are scratch or rewritten below, the GPU buffers grow on upload */
        uint32_t cap = n + n / 4 < RENDER_MAX_TREES ? n + n / 4 : RENDER_MAX_TREES;
        if (render_trees_alloc(r, cap, err) < 0) {
            render_trees_alloc(r, 0, NULL);
            r->n_trees = 0;
            return gale_errf(err, GALE_E_NOMEM, "render_set_instances: no memory for %u trees",
                             n);
        }
    }
    if (n > 0) { /* inst may be NULL for an empty scene */
        memcpy(r->inst, inst, n * sizeof *inst);
    }
    memset(&r->inst[n], 0, (r->cap_trees - n) * sizeof *inst);
    r->inst[r->cap_trees].scale = 1.0f;
    r->n_trees = n;
    render_cull_species cs[RENDER_MAX_SPECIES];
    for (uint32_t k = 0; k < r->n_species; k++) {
        cs[k] = render_cull_species_of(&r->sp[k]);
    }
    if (render_cells_build(&r->cells, r->inst, n, cs) < 0) {
        r->n_trees = 0;
        return gale_errf(err, GALE_E_NOMEM, "render_set_instances: no memory for the cells of "
                         "%u trees", n);
    }
    for (uint32_t t = 0; t < n; t++) {
        render_bill_leaf_set(r, t);
    }
    r->n_debris = 0;
    r->n_broken = 0;
    r->cut_dirty = true;
    render_trees_upload(r);
    memset(r->q_stage, 0, (size_t)render_slots(r) * r->q_stride * sizeof(float));
    render_clear_falling(r);
    return 0;
}

uint32_t render_max_trees(const render *r, uint32_t n_modes)
{
    (void)r; /* the limit is the context's, current on this thread */
    GLint texels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    const uint64_t per_tree = n_modes > 2 ? n_modes : 2;
    const uint64_t slots = (uint64_t)(texels > 0 ? texels : 0) / per_tree;
    if (slots <= 1 + RENDER_MAX_DEBRIS) {
        return 0;
    }
    /* render_set_instances takes n + n / 4 slots for n trees, then the debris's */
    const uint64_t n = (slots - 1 - RENDER_MAX_DEBRIS) * 4 / 5;
    return n < RENDER_MAX_TREES ? (uint32_t)n : RENDER_MAX_TREES;
}

int render_set_q(render *r, uint32_t tree, const float *q, uint32_t n, gale_err *err)
{
    if (tree >= r->n_trees) {
        return gale_errf(err, GALE_E_RANGE, "render_set_q: tree %u of %u", tree, r->n_trees);
    }
    const rs_species *s = &r->sp[r->inst[tree].species];
    if (n != s->n_modes) {
        return gale_errf(err, GALE_E_RANGE, "render_set_q: tree %u: %u modes, species has %u", tree,
                         n, s->n_modes);
    }
    memcpy(&r->q_stage[(size_t)tree * r->q_stride], q, n * sizeof(float));
    return 0;
}

float *render_q_staging(render *r, uint32_t *stride)
{
    *stride = r->q_stride;
    return r->q_stage;
}

int render_set_obstacles(render *r, uint32_t n, const float *min_max, gale_err *err)
{
    if (n > RENDER_MAX_OBSTACLES || (n > 0 && !min_max)) {
        return gale_errf(err, GALE_E_ARG,
                         "render_set_obstacles: expected at most %u boxes and their corners, "
                         "got %u%s",
                         RENDER_MAX_OBSTACLES, n, n > 0 && !min_max ? " and no array" : "");
    }
    for (uint32_t i = 0; i < n; i++) {
        const float *b = &min_max[6 * i];
        for (int k = 0; k < 6; k++) {
            if (!isfinite(b[k]) || fabsf(b[k]) > 1e6f) {
                return gale_errf(err, GALE_E_RANGE,
                                 "render_set_obstacles: box %u corner value %d: expected "
                                 "|value| <= 1e6, got %g",
                                 i, k, (double)b[k]);
            }
        }
        for (int k = 0; k < 3; k++) {
            if (b[k] > b[k + 3]) {
                return gale_errf(err, GALE_E_RANGE,
                                 "render_set_obstacles: box %u: expected min <= max on "
                                 "axis %c, got %g > %g",
                                 i, "xyz"[k], (double)b[k], (double)b[k + 3]);
            }
        }
    }
    r->house_verts = 0;
    if (n == 0) {
        return 0;
    }
    float *v = malloc((size_t)n * RENDER_HOUSE_VERTS * RENDER_HOUSE_FLOATS * sizeof(float));
    if (!v) {
        return gale_errf(err, GALE_E_NOMEM, "render_set_obstacles: out of memory for %u boxes", n);
    }
    float *end = v;
    for (uint32_t i = 0; i < n; i++) {
        end = render_house_mesh(&min_max[6 * i], end);
    }
    if (!r->house_vao) {
        glGenVertexArrays(1, &r->house_vao);
        glGenBuffers(1, &r->house_vbo);
        glBindVertexArray(r->house_vao);
        glBindBuffer(GL_ARRAY_BUFFER, r->house_vbo);
        const GLsizei stride = (GLsizei)(RENDER_HOUSE_FLOATS * sizeof(float));
        const int size[4] = { 3, 3, 4, 1 }, off[4] = { 0, 3, 6, 10 };
        for (int a = 0; a < 4; a++) {
            glEnableVertexAttribArray((GLuint)a);
            glVertexAttribPointer((GLuint)a, size[a], GL_FLOAT, GL_FALSE, stride,
                                  (const void *)(uintptr_t)((size_t)off[a] * sizeof(float)));
        }
        glBindVertexArray(0);
    }
    glBindBuffer(GL_ARRAY_BUFFER, r->house_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)(end - v) * sizeof(float)), v,
                 GL_STATIC_DRAW);
    free(v);
    r->house_verts = n * RENDER_HOUSE_VERTS;
    return 0;
}

void render_bill_leaf_set(render *r, uint32_t t)
{
    if (t < r->n_trees && t < r->cells.n_trees) {
        const uint32_t at = r->cells.at_of[t];
        r->cells.bill_leaf[at] = render_bill_leaf_share(r, t);
        r->cells.bill_fall[at] = render_bill_fall(r, t);
    }
}

void render_set_damage(render *r, uint32_t t, float fall_rad, float fall_az_rad,
                       uint32_t leaf_lost)
{
    if (t < r->cap_trees) {
        r->inst[t].fall_rad = fall_rad;
        r->inst[t].fall_az_rad = fall_az_rad;
        r->inst[t].leaf_lost = leaf_lost;
        render_bill_leaf_set(r, t);
    }
}

void render_set_uprooted(render *r, uint32_t t, bool uprooted)
{
    if (t < r->cap_trees) {
        r->inst[t].uprooted = uprooted ? 1u : 0u;
    }
}

void render_trees_commit(render *r)
{
    render_trees_upload(r);
}
