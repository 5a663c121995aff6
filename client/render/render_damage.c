/* gale_render storm damage beyond the instance transform (PROTOCOL.md "DAMAGE"): branches
 * broken off and debris pieces, both drawn through the skeleton pass (shaders/skel.frag).
 *
 * Design. Asset nodes are numbered breadth-first (ASSET.md "Node numbering"), so a
 * sub-tree is no contiguous range of nodes. Instead every slot (tree or debris piece)
 * names a range of a list of cut nodes: per slot one RGBA32F texel (first, count,
 * keep-only), and the list holds each tree's broken nodes ascending (damage_view's order).
 * Pass 0 of the skeleton marks a listed node, pass 1 already walks every node's segments up
 * to the root and keeps the minimum of the marks on the way: a node is attached when no
 * node from it to the root is cut. Tube vertices and leaves read that flag from the texel
 * they read their position from. Cost: one texel fetch per skeleton row in skel.vert, and
 * count fetches per node only on a tree with count broken branches; an intact forest pays
 * nothing per node. Memory: 16 bytes per slot, 4 per broken branch. Also the root plates of
 * uprooted trees and the stumps of snapped ones (shaders/plate.*, shaders/stump.*). */
#include "render_internal.h"

#include "damage_cut.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int render_set_broken(render *r, uint32_t n, const uint64_t *keys, gale_err *err)
{
    for (uint32_t i = 1; i < n; i++) {
        if (keys[i] <= keys[i - 1]) {
            return gale_errf(err, GALE_E_ARG,
                             "render_set_broken: key %u: expected ascending (tree << 32 | node)",
                             i);
        }
    }
    if (n > r->cap_broken) {
        uint64_t *b = realloc(r->broken, (size_t)n * sizeof *b);
        if (!b) {
            return gale_errf(err, GALE_E_NOMEM, "render_set_broken: out of memory for %u", n);
        }
        r->broken = b;
        r->cap_broken = n;
    }
    if (n > 0) {
        memcpy(r->broken, keys, (size_t)n * sizeof *keys);
    }
    r->n_broken = n;
    r->cut_dirty = true;
    return 0;
}

int render_set_debris(render *r, uint32_t n, const render_debris *d, gale_err *err)
{
    if (n > RENDER_MAX_DEBRIS) {
        return gale_errf(err, GALE_E_RANGE, "render_set_debris: %u pieces, at most %u", n,
                         RENDER_MAX_DEBRIS);
    }
    for (uint32_t k = 0; k < n; k++) {
        if (d[k].tree >= r->n_trees ||
            d[k].node >= r->sp[r->inst[d[k].tree].species].n_nodes) {
            return gale_errf(err, GALE_E_RANGE,
                             "render_set_debris: piece %u: tree %u node %u outside the scene "
                             "(%u trees)",
                             k, d[k].tree, d[k].node, r->n_trees);
        }
        if (!isfinite(d[k].pos[0] + d[k].pos[1] + d[k].pos[2] + d[k].yaw + d[k].fall_rad +
                      d[k].fall_az_rad)) {
            return gale_errf(err, GALE_E_RANGE, "render_set_debris: piece %u: not finite", k);
        }
    }
    bool same = n == r->n_debris;
    for (uint32_t k = 0; k < n; k++) {
        const render_instance *src = &r->inst[d[k].tree];
        render_instance *in = &r->inst[r->cap_trees + 1 + k];
        *in = (render_instance){ .species = src->species,
                                 .pos = { d[k].pos[0], d[k].pos[1], d[k].pos[2] },
                                 .yaw = d[k].yaw,
                                 .scale = src->scale,
                                 .fall_rad = fminf(fmaxf(d[k].fall_rad, 0.0f), 3.1415926f),
                                 .fall_az_rad = d[k].fall_az_rad,
                                 .leaf_lost = src->leaf_lost };
        same = same && r->debris[k].tree == d[k].tree && r->debris[k].node == d[k].node;
        r->debris[k] = d[k];
    }
    /* the cut lists change only with the set of pieces, not as they move */
    r->cut_dirty |= !same;
    r->n_debris = n;
    if (n > 0) {
        /* only the debris slots' transforms, the layout of render_trees_upload */
        float t[8 * RENDER_MAX_DEBRIS];
        for (uint32_t k = 0; k < n; k++) {
            const render_instance *in = &r->inst[r->cap_trees + 1 + k];
            float *e = &t[8 * k];
            e[0] = in->pos[0];
            e[1] = in->pos[1];
            e[2] = in->pos[2];
            e[3] = in->yaw;
            e[4] = in->scale > 0.0f ? in->scale : 1.0f;
            e[5] = (float)in->species;
            e[6] = in->fall_rad + 4.0f * (float)in->leaf_lost;
            e[7] = in->fall_az_rad;
        }
        glBindBuffer(GL_TEXTURE_BUFFER, r->trees.buf);
        glBufferSubData(GL_TEXTURE_BUFFER, (GLintptr)((size_t)(r->cap_trees + 1) * 8 * sizeof(float)),
                        (GLsizeiptr)((size_t)n * 8 * sizeof(float)), t);
        glBindBuffer(GL_TEXTURE_BUFFER, 0);
    }
    return 0;
}

/* r->leaf_attached from the cut lists just built (head: first, count per slot; nodes): the
 * share of each tree's leaf slots whose node no broken branch takes, for the billboard
 * (shaders/bill.frag). Only trees with broken branches cost anything. */
static void leaf_attached_update(render *r, const float *head, const float *nodes)
{
    uint32_t cap = 0;
    for (uint32_t s = 0; s < r->n_species; s++) {
        cap = r->sp[s].n_nodes > cap ? r->sp[s].n_nodes : cap;
    }
    uint8_t *m = malloc(cap + 1);
    uint32_t *cut = malloc(((size_t)cap + 1) * sizeof *cut);
    for (uint32_t t = 0; t < r->cap_trees; t++) {
        r->leaf_attached[t] = 1.0f;
        const uint32_t n = (uint32_t)head[4 * t + 1], first = (uint32_t)head[4 * t];
        const rs_species *s = &r->sp[r->inst[t].species];
        if (n == 0 || t >= r->n_trees || !m || !cut || s->n_leaves == 0) {
            continue;
        }
        uint32_t nc = 0;
        for (uint32_t k = 0; k < n && nc < cap; k++) {
            cut[nc++] = (uint32_t)nodes[first + k];
        }
        damage_cut_mask(s->parent, s->n_nodes, cut, nc, false, m);
        uint32_t kept = 0;
        for (uint32_t l = 0; l < s->n_leaves; l++) {
            kept += m[s->leaf_node[l]];
        }
        r->leaf_attached[t] = (float)kept / (float)s->n_leaves;
    }
    free(m);
    free(cut);
    for (uint32_t t = 0; t < r->n_trees; t++) {
        render_bill_leaf_set(r, t);
    }
}

void render_damage_upload(render *r)
{
    if (!r->cut_dirty) {
        return;
    }
    const uint32_t slots = render_slots(r);
    float *head = calloc((size_t)slots * 4, sizeof(float));
    float *nodes = malloc(((size_t)r->n_broken + r->n_debris + 1) * sizeof(float));
    if (!head || !nodes) {
        free(head);
        free(nodes);
        return; /* stays dirty: the next frame tries again */
    }
    uint32_t nn = 0;
    for (uint32_t i = 0; i < r->n_broken; i++) {
        uint32_t t = (uint32_t)(r->broken[i] >> 32), node = (uint32_t)r->broken[i];
        if (t >= r->n_trees || node >= r->sp[r->inst[t].species].n_nodes) {
            continue;
        }
        float *h = &head[4 * t];
        if (h[1] == 0.0f) {
            h[0] = (float)nn;
        }
        h[1] += 1.0f;
        nodes[nn++] = (float)node;
    }
    for (uint32_t k = 0; k < r->n_debris; k++) {
        float *h = &head[4 * (r->cap_trees + 1 + k)];
        h[0] = (float)nn;
        h[1] = 1.0f;
        h[2] = 1.0f; /* keep only the sub-tree of the node */
        nodes[nn++] = (float)r->debris[k].node;
    }
    leaf_attached_update(r, head, nodes);
    render_buf_upload(&r->cut, GL_RGBA32F, head, (size_t)slots * 4 * sizeof(float));
    render_buf_upload(&r->cutn, GL_R32F, nodes, (size_t)(nn ? nn : 1) * sizeof(float));
    free(head);
    free(nodes);
    r->cut_dirty = false;
}

int render_piece_shape(render *r, uint32_t tree, uint32_t node, float centre[3], float axis[3],
                       float *extent_m, gale_err *err)
{
    if (tree >= r->n_trees || node >= r->sp[r->inst[tree].species].n_nodes) {
        return gale_errf(err, GALE_E_RANGE, "render_piece_shape: tree %u node %u outside the scene",
                         tree, node);
    }
    const rs_species *s = &r->sp[r->inst[tree].species];
    uint8_t *m = malloc(s->n_nodes);
    if (!m) {
        return gale_errf(err, GALE_E_NOMEM, "render_piece_shape: out of memory");
    }
    damage_cut_mask(s->parent, s->n_nodes, &node, 1, true, m);
    double c[3] = { 0, 0, 0 };
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->n_nodes; i++) {
        if (m[i]) {
            for (int k = 0; k < 3; k++) {
                c[k] += (double)s->rest[3 * i + k];
            }
            n++;
        }
    }
    float ext = 0.0f;
    for (int k = 0; k < 3; k++) {
        centre[k] = (float)(c[k] / (double)n); /* n >= 1: the node itself */
        axis[k] = centre[k] - s->rest[3 * node + k];
    }
    for (uint32_t i = 0; i < s->n_nodes; i++) {
        if (m[i]) {
            const float *p = &s->rest[3 * i];
            ext = fmaxf(ext, sqrtf((p[0] - centre[0]) * (p[0] - centre[0]) +
                                   (p[1] - centre[1]) * (p[1] - centre[1]) +
                                   (p[2] - centre[2]) * (p[2] - centre[2])));
        }
    }
    if (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2] < 1e-12f) {
        /* a single node: its own segment's direction */
        const int32_t p = s->parent[node];
        for (int k = 0; k < 3; k++) {
            axis[k] = p >= 0 ? s->rest[3 * node + k] - s->rest[3 * p + k] : (k == 2);
        }
    }
    *extent_m = ext;
    free(m);
    return 0;
}

float render_tree_height_m(const render *r, uint32_t tree)
{
    if (tree >= r->n_trees) {
        return 0.0f;
    }
    const render_instance *in = &r->inst[tree];
    return r->sp[in->species].height * (in->scale > 0.0f ? in->scale : 1.0f);
}

void render_plates_draw(render *r, float time_rel)
{
    if (r->n_plates == 0) {
        return;
    }
    render_buf_upload(&r->plate_buf, GL_R32F, r->plates, (size_t)r->n_plates * sizeof(float));
    render_set_common(r, &r->p_plate, time_rel, r->desc.fog_dist);
    render_bind_buf(RU_TREES, &r->trees);
    render_bind_buf(RU_PLATE, &r->plate_buf);
    glBindVertexArray(r->vao_empty);
    /* shaders/plate.vert: two fans and the side band of PLATE_SEG = 24 segments */
    glDrawArraysInstanced(GL_TRIANGLES, 0, 12 * 24, (GLsizei)r->n_plates);
    r->stats.draw_calls++;
    r->stats.triangles += RENDER_PLATE_TRIS * (uint64_t)r->n_plates;
}

void render_stumps_draw(render *r, float time_rel)
{
    r->stats.stumps = r->n_stumps;
    if (r->n_stumps == 0) {
        return;
    }
    render_buf_upload(&r->stump_buf, GL_RGBA32F, r->stumps,
                      (size_t)r->n_stumps * 8 * sizeof(float));
    render_set_common(r, &r->p_stump, time_rel, r->desc.fog_dist);
    render_bind_buf(RU_TREES, &r->trees);
    render_bind_buf(RU_STUMP, &r->stump_buf);
    glBindVertexArray(r->vao_empty);
    /* shaders/stump.vert: 21 vertices per segment, STUMP_SEG = 12 segments */
    glDrawArraysInstanced(GL_TRIANGLES, 0, 21 * 12, (GLsizei)r->n_stumps);
    r->stats.draw_calls++;
    r->stats.triangles += RENDER_STUMP_TRIS * (uint64_t)r->n_stumps;
}
