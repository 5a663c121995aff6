/* gale_render falling leaves (Vazquez 2008 sections 3-5): the shared path (simulated on
 * the CPU by falling_path.c before any GPU setup) as a texture, a ring of released leaves
 * in a vertex buffer, releasing a leaf from a tree's current pose, and their draw. */
#include "render_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hash.h"

/* The path as a 2-row texture image: positions (w unused), then orientations.
 * out has 8 n floats. */
static void fall_path_texels(const falling_path *p, float *out)
{
    for (uint32_t i = 0; i < p->n; i++) {
        memcpy(&out[4 * i], p->pos[i], 3 * sizeof(float));
        memcpy(&out[4 * (p->n + i)], p->quat[i], 4 * sizeof(float));
    }
}

int render_fall_gpu_create(render *r, gale_err *err)
{
    float *pt = calloc((size_t)r->path.n * 8, sizeof(float));
    if (!pt) {
        return gale_errf(err, GALE_E_NOMEM, "render: out of memory");
    }
    fall_path_texels(&r->path, pt);
    glGenTextures(1, &r->path_tex);
    glBindTexture(GL_TEXTURE_2D, r->path_tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, (GLsizei)r->path.n, 2, 0, GL_RGBA, GL_FLOAT, pt);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    free(pt);
    r->ring_cap = r->desc.max_falling;
    r->ring = calloc(r->ring_cap, sizeof *r->ring);
    if (!r->ring) {
        return gale_errf(err, GALE_E_NOMEM, "render: out of memory for %u falling leaves",
                         r->ring_cap);
    }
    glGenVertexArrays(1, &r->fall_vao);
    glBindVertexArray(r->fall_vao);
    glGenBuffers(1, &r->fall_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, r->fall_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(r->ring_cap * sizeof(rs_fall)), NULL,
                 GL_DYNAMIC_DRAW);
    for (int a = 0; a < 6; a++) {
        glEnableVertexAttribArray((GLuint)a);
        glVertexAttribPointer((GLuint)a, a < 5 ? 4 : 1, GL_FLOAT, GL_FALSE, sizeof(rs_fall),
                              (const void *)(uintptr_t)(a * 4 * sizeof(float)));
        glVertexAttribDivisor((GLuint)a, 1);
    }
    glBindVertexArray(0);
    r->dirty_lo = UINT32_MAX;
    return 0;
}

/* quaternion (x, y, z, w) of an orthonormal basis given as columns */
static void quat_from_basis(const float x[3], const float y[3], const float z[3], float q[4])
{
    float tr = x[0] + y[1] + z[2];
    if (tr > 0.0f) {
        float s = sqrtf(tr + 1.0f) * 2.0f;
        q[3] = 0.25f * s;
        q[0] = (y[2] - z[1]) / s;
        q[1] = (z[0] - x[2]) / s;
        q[2] = (x[1] - y[0]) / s;
    } else if (x[0] > y[1] && x[0] > z[2]) {
        float s = sqrtf(1.0f + x[0] - y[1] - z[2]) * 2.0f;
        q[3] = (y[2] - z[1]) / s;
        q[0] = 0.25f * s;
        q[1] = (y[0] + x[1]) / s;
        q[2] = (z[0] + x[2]) / s;
    } else if (y[1] > z[2]) {
        float s = sqrtf(1.0f + y[1] - x[0] - z[2]) * 2.0f;
        q[3] = (z[0] - x[2]) / s;
        q[0] = (y[0] + x[1]) / s;
        q[1] = 0.25f * s;
        q[2] = (z[1] + y[2]) / s;
    } else {
        float s = sqrtf(1.0f + z[2] - x[0] - y[1]) * 2.0f;
        q[3] = (x[1] - y[0]) / s;
        q[0] = (z[0] + x[2]) / s;
        q[1] = (z[1] + y[2]) / s;
        q[2] = 0.25f * s;
    }
}

int render_add_falling_leaf(render *r, const render_leaf_seed *ls, gale_err *err)
{
    if (ls->tree >= r->n_trees) {
        return gale_errf(err, GALE_E_RANGE, "render_add_falling_leaf: tree %u of %u", ls->tree,
                         r->n_trees);
    }
    const render_instance *in = &r->inst[ls->tree];
    const rs_species *s = &r->sp[in->species];
    if (ls->slot >= s->n_leaves) {
        return gale_errf(err, GALE_E_RANGE, "render_add_falling_leaf: tree %u: slot %u of %u",
                         ls->tree, ls->slot, s->n_leaves);
    }
    if (!isfinite(ls->spawn_time_s)) {
        return gale_errf(err, GALE_E_RANGE, "render_add_falling_leaf: spawn time not finite");
    }
    /* the slot's node in the tree's current pose, the length-true form of asset_reconstruct
       for that node only (PHYSICS.md "Length-true pose") */
    uint32_t j = s->leaf_node[ls->slot];
    const float *q = &r->q_stage[(size_t)ls->tree * r->q_stride];
    float x[3];
    asset_reconstruct_node(s->rest, s->parent, s->corr_v, s->corr_w, s->corr_a, s->corr_b, s->n_nodes, q,
                           s->n_modes, j, x);
    float sc = in->scale > 0.0f ? in->scale : 1.0f, cy = cosf(in->yaw), sy = sinf(in->yaw);
    const float *off = &s->leaf_offset[3 * ls->slot];
    float lp[3] = { (x[0] + off[0]) * sc, (x[1] + off[1]) * sc, (x[2] + off[2]) * sc };
    float wp[3] = { in->pos[0] + cy * lp[0] - sy * lp[1], in->pos[1] + sy * lp[0] + cy * lp[1],
                    in->pos[2] + lp[2] };
    float size = s->leaf_size[ls->slot] * sc;

    uint32_t seed = hash_mix32(ls->seed ^ (ls->tree * 2654435761u) ^ (ls->slot * 40503u));
    falling_var v;
    falling_var_from_seed(&r->path, seed, &v);
    float t_land = falling_path_land_time(&r->path, &v, wp[2], 600.0f);
    float wind[3];
    render_wind_at(r, wp, wind);

    rs_fall *f = &r->ring[r->ring_head];
    memset(f, 0, sizeof *f);
    f->start[0] = wp[0];
    f->start[1] = wp[1];
    f->start[2] = wp[2];
    f->start[3] = (float)render_rel_time(r, ls->spawn_time_s);
    f->var[0] = v.yaw;
    f->var[1] = v.sx;
    f->var[2] = v.sy;
    f->var[3] = (float)v.start;
    /* a leaf is carried at most of the wind's horizontal speed */
    f->drift[0] = 0.8f * wind[0];
    f->drift[1] = 0.8f * wind[1];
    f->drift[2] = t_land;
    memcpy(&f->drift[3], &v.seed, sizeof(float));
    /* orientation on the tree: blade axis x, normal z (rest pose, instance yaw) */
    const float *n0 = &s->leaf_normal[3 * ls->slot];
    float nz[3] = { cy * n0[0] - sy * n0[1], sy * n0[0] + cy * n0[1], n0[2] };
    float ax[3] = { 1.0f, 0.0f, 0.0f };
    if (fabsf(nz[0]) > 0.9f) {
        ax[0] = 0.0f;
        ax[1] = 1.0f;
    }
    float d = ax[0] * nz[0] + ax[1] * nz[1] + ax[2] * nz[2];
    for (int k = 0; k < 3; k++) {
        ax[k] -= d * nz[k];
    }
    float al = sqrtf(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    for (int k = 0; k < 3; k++) {
        ax[k] /= al;
    }
    float ay[3] = { nz[1] * ax[2] - nz[2] * ax[1], nz[2] * ax[0] - nz[0] * ax[2],
                    nz[0] * ax[1] - nz[1] * ax[0] };
    quat_from_basis(ax, ay, nz, f->q0);
    /* torn leaves: the species colour, some turned yellow-brown */
    float yel = 0.35f * (float)(hash_mix32(seed + 5u) >> 8) / 16777216.0f;
    const float brown[3] = { 0.62f, 0.48f, 0.16f };
    for (int k = 0; k < 3; k++) {
        f->look[k] = s->leaf_rgb[k] * (1.0f - yel) + brown[k] * yel;
    }
    f->look[3] = size;
    f->shape = (float)s->leaf_shape;

    if (r->ring_head < r->dirty_lo) {
        r->dirty_lo = r->ring_head;
    }
    if (r->ring_head + 1 > r->dirty_hi) {
        r->dirty_hi = r->ring_head + 1;
    }
    r->ring_head = (r->ring_head + 1) % r->ring_cap;
    if (r->ring_count < r->ring_cap) {
        r->ring_count++;
    }
    return 0;
}

void render_clear_falling(render *r)
{
    r->ring_head = 0;
    r->ring_count = 0;
    r->dirty_lo = UINT32_MAX;
    r->dirty_hi = 0;
}

void render_fall_draw(render *r, float time_rel)
{
    if (r->ring_count > 0) {
        glBindBuffer(GL_ARRAY_BUFFER, r->fall_vbo);
        if (r->dirty_lo < r->dirty_hi) {
            glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)(r->dirty_lo * sizeof(rs_fall)),
                            (GLsizeiptr)((r->dirty_hi - r->dirty_lo) * sizeof(rs_fall)),
                            &r->ring[r->dirty_lo]);
        }
        r->dirty_lo = UINT32_MAX;
        r->dirty_hi = 0;
        const render_prog *p = &r->p_fall;
        render_set_common(r, p, time_rel, r->desc.fog_dist);
        glUniform1i(p->u_npath, (GLint)r->path.n);
        glUniform1f(p->u_pdt, r->path.dt);
        glUniform1i(p->u_ncont, (GLint)r->path.n_cont);
        GLint cont[8] = { 0 };
        for (uint32_t i = 0; i < r->path.n_cont; i++) {
            cont[i] = (GLint)r->path.cont[i];
        }
        glUniform1iv(p->u_cont, 8, cont);
        glUniform1fv(p->u_aspects, 3, render_leaf_aspect);
        render_bind_tex(RU_PATH, GL_TEXTURE_2D, r->path_tex);
        glBindVertexArray(r->fall_vao);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)r->ring_count);
        r->stats.draw_calls++;
        r->stats.triangles += 2u * (uint64_t)r->ring_count;
    }
    r->stats.falling_live = r->ring_count;
}
