/* gale_render species: checking and uploading one baked species (skeleton, corrected
 * modes, mesh with its LODs, leaf slots), its billboard impostor, and the three per-species
 * draws: skeleton rebuild on the GPU (Diener 2008 sections 5.1-5.2), skinned tube mesh
 * (Singh sections 2.1-2.4) and attached leaves (Vazquez 2008 section 5). */
#include "render_internal.h"

#include <cglm/cglm.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const float render_leaf_aspect[3] = { 0.55f, 0.16f, 1.0f };

void render_species_free(rs_species *s)
{
    if (s->vao) {
        glDeleteVertexArrays(1, &s->vao);
        glDeleteBuffers(1, &s->vbo);
        glDeleteBuffers(1, &s->ibo);
    }
    if (s->imp_tex) {
        glDeleteTextures(1, &s->imp_tex);
    }
    if (s->imp_wood_tex) {
        glDeleteTextures(1, &s->imp_wood_tex);
    }
    render_buf_free(&s->vw);
    render_buf_free(&s->node);
    render_buf_free(&s->leaf);
    free(s->rest);
    free(s->parent);
    free(s->corr_v);
    free(s->corr_w);
    free(s->leaf_offset);
    free(s->leaf_normal);
    free(s->leaf_size);
    free(s->leaf_node);
    memset(s, 0, sizeof *s);
}

static int species_check(const render *r, const asset *a, gale_err *err)
{
    const char *nm = a->species[0] ? a->species : "(unnamed)";
    if (r->n_species >= RENDER_MAX_SPECIES) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: at most %u species", nm,
                         RENDER_MAX_SPECIES);
    }
    if (a->n_nodes < 2 || a->n_nodes > 16384 || !a->parent || !a->rest) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: n_nodes %u (2..16384)", nm,
                         a->n_nodes);
    }
    if (a->n_modes > RENDER_MAX_MODES ||
        (a->n_modes && (!a->corr_v || !a->corr_w || !a->corr_a || !a->corr_b))) {
        return gale_errf(err, GALE_E_RANGE,
                         "render_add_species: %s: n_modes %u (0..%u, with "
                         "corr_v/w/a/b)",
                         nm, a->n_modes, RENDER_MAX_MODES);
    }
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        if ((i == 0) != (a->parent[i] < 0) || (i > 0 && (uint32_t)a->parent[i] >= i)) {
            return gale_errf(err, GALE_E_FORMAT,
                             "render_add_species: %s: parent[%u] = %d: "
                             "root first, then parent < index",
                             nm, i, a->parent[i]);
        }
    }
    for (uint32_t v = 0; v < 2 * a->n_verts; v++) {
        if (a->mesh_bone[v] >= a->n_nodes) {
            return gale_errf(err, GALE_E_FORMAT,
                             "render_add_species: %s: mesh_bone[%u] = %u "
                             ">= n_nodes %u",
                             nm, v, a->mesh_bone[v], a->n_nodes);
        }
    }
    for (uint32_t k = 0; k < a->n_indices; k++) {
        if (a->mesh_index[k] >= a->n_verts) {
            return gale_errf(err, GALE_E_FORMAT,
                             "render_add_species: %s: mesh_index[%u] = %u "
                             ">= n_verts %u",
                             nm, k, a->mesh_index[k], a->n_verts);
        }
    }
    if (a->n_lods < 1 || a->n_lods > ASSET_MAX_LODS) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: n_lods %u (1..%d)", nm,
                         a->n_lods, ASSET_MAX_LODS);
    }
    for (uint32_t l = 0; l < a->n_lods; l++) {
        if ((uint64_t)a->lod_first[l] + a->lod_count[l] > a->n_indices || a->lod_count[l] % 3) {
            return gale_errf(err, GALE_E_FORMAT,
                             "render_add_species: %s: LOD %u [%u, +%u) "
                             "outside %u indices or not triangles",
                             nm, l, a->lod_first[l], a->lod_count[l], a->n_indices);
        }
    }
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        if (a->leaf_node[l] >= a->n_nodes) {
            return gale_errf(err, GALE_E_FORMAT,
                             "render_add_species: %s: leaf_node[%u] = %u "
                             ">= n_nodes %u",
                             nm, l, a->leaf_node[l], a->n_nodes);
        }
    }
    if (a->leaf_shape > 2) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: leaf_shape %u (0..2)", nm,
                         a->leaf_shape);
    }
    return 0;
}

static float *dup_f(const float *s, size_t n)
{
    float *d = malloc(n * sizeof *d + 1);
    if (d && n) {
        memcpy(d, s, n * sizeof *d);
    }
    return d;
}

/* One impostor texture of s at rest under the view r->viewproj: wood, and the leaves too
 * when with_leaves. The skeleton texture holds s's rest pose in row 0. */
static GLuint impostor_draw(render *r, const rs_species *s, bool with_leaves)
{
    GLuint tex, fbo, depth;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, RENDER_IMP_W, RENDER_IMP_H, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, NULL);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, RENDER_IMP_W, RENDER_IMP_H);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    glViewport(0, 0, RENDER_IMP_W, RENDER_IMP_H);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    render_set_common(r, &r->p_tree, 0.0f, 1e9f);
    render_draw_tree(r, s, 0, 0, 1);
    if (with_leaves) {
        render_set_common(r, &r->p_leaf, 0.0f, 1e9f);
        render_draw_leaves(r, s, 0, 1, false);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &depth);
    glBindTexture(GL_TEXTURE_2D, tex);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

/* The impostor: the species at rest seen from the side, orthographic, on a clear
 * transparent background; far trees show it as a billboard. A second one of the wood
 * alone shows where a stripped or broken crown has lost leaves (shaders/bill.frag). */
static int species_impostor(render *r, rs_species *s, uint32_t sid, gale_err *err)
{
    float hw = s->crown_r * 1.05f + 0.2f, bottom = -0.05f * s->height;
    float top = s->height * 1.06f + 0.2f;
    s->bill[0] = hw;
    s->bill[1] = top - bottom;
    s->bill[2] = bottom;
    uint32_t slot = r->cap_trees;
    r->inst[slot] = (render_instance){ .species = sid, .scale = 1.0f };
    render_trees_upload(r);
    /* rest pose: zero q for the slot */
    memset(&r->q_stage[(size_t)slot * r->q_stride], 0, r->q_stride * sizeof(float));
    render_buf_upload(&r->q, GL_R32F, r->q_stage,
                      (size_t)(r->cap_trees + 1) * r->q_stride * sizeof(float));
    float ent[4] = { (float)slot, 0.0f, (float)s->n_modes, 1.0f };
    render_buf_upload(&r->list_buf, GL_RGBA32F, ent, sizeof ent);
    int rc = render_skel_ensure(r, (int)s->n_nodes, 1, err);
    if (rc < 0) {
        return rc;
    }
    render_draw_skeleton(r, s, 0, 1);

    mat4 view, proj, vp;
    float dist = 4.0f * (s->height + s->crown_r) + 10.0f;
    glm_lookat((vec3){ 0.0f, -dist, 0.5f * s->height }, (vec3){ 0.0f, 0.0f, 0.5f * s->height },
               (vec3){ 0.0f, 0.0f, 1.0f }, view);
    glm_ortho(-hw, hw, bottom - 0.5f * s->height, top - 0.5f * s->height, 0.1f, 2.0f * dist, proj);
    glm_mat4_mul(proj, view, vp);
    memcpy(r->viewproj, vp, sizeof r->viewproj);
    r->eye[0] = 0.0f;
    r->eye[1] = -dist;
    r->eye[2] = 0.5f * s->height;
    s->imp_tex = impostor_draw(r, s, true);
    s->imp_wood_tex = impostor_draw(r, s, false);
    return 0;
}

/* The impostor's sway (shaders/bill.vert): the crown's mean translation per unit q of
 * each of the lowest modes, c_k = Σ_j w_j φ_k(j) / Σ_j w_j with w_j the leaves on node j
 * (the highest node alone for a leafless species), and the crown's height z_c the same
 * mean of the nodes' rest heights. A quad vertex at height z moves by (z / z_c) Σ q̃_k c_k:
 * the lean that puts the crown's middle where the modes put it (Diener 2008 section 3). */
static void impostor_sway(rs_species *s, const asset *a)
{
    const size_t nn = a->n_nodes;
    double c[LOD_IMPOSTOR_MODES][3] = { { 0.0 } }, z = 0.0, w = 0.0;
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        const size_t j = a->leaf_node[l];
        for (uint32_t m = 0; m < LOD_IMPOSTOR_MODES && m < a->n_modes; m++) {
            for (int k = 0; k < 3; k++) {
                c[m][k] += (double)a->phi[(m * nn + j) * 3 + k];
            }
        }
        z += (double)a->rest[3 * j + 2];
        w += 1.0;
    }
    if (w == 0.0) {
        size_t top = 0;
        for (size_t j = 1; j < nn; j++) {
            top = a->rest[3 * j + 2] > a->rest[3 * top + 2] ? j : top;
        }
        for (uint32_t m = 0; m < LOD_IMPOSTOR_MODES && m < a->n_modes; m++) {
            for (int k = 0; k < 3; k++) {
                c[m][k] = (double)a->phi[(m * nn + top) * 3 + k];
            }
        }
        z = (double)a->rest[3 * top + 2];
        w = 1.0;
    }
    for (int m = 0; m < LOD_IMPOSTOR_MODES; m++) {
        for (int k = 0; k < 3; k++) {
            s->imp_sway[m][k] = (float)(c[m][k] / w);
        }
    }
    s->imp_crown_z = fmaxf((float)(z / w), 0.1f);
}

int render_add_species(render *r, const asset *a, gale_err *err)
{
    int rc = species_check(r, a, err);
    if (rc < 0) {
        return rc;
    }
    uint32_t sid = r->n_species;
    rs_species *s = &r->sp[sid];
    memset(s, 0, sizeof *s);
    s->n_nodes = a->n_nodes;
    s->n_modes = a->n_modes;
    s->n_leaves = a->n_leaves;
    s->n_lods = a->n_lods;
    s->leaf_shape = a->leaf_shape;
    memcpy(s->lod_first, a->lod_first, sizeof s->lod_first);
    memcpy(s->lod_count, a->lod_count, sizeof s->lod_count);
    memcpy(s->bark, a->bark_rgb, sizeof s->bark);
    memcpy(s->leaf_rgb, a->leaf_rgb, sizeof s->leaf_rgb);
    for (uint32_t m = 0; m < a->n_modes; m++) {
        s->ab[2 * m] = s->corr_a[m] = a->corr_a[m];
        s->ab[2 * m + 1] = s->corr_b[m] = a->corr_b[m];
    }
    size_t nn = a->n_nodes, nm = a->n_modes;
    float *tmp = malloc((nm * nn * 2 + nn + 2 * (size_t)a->n_leaves + 1) * 4 * sizeof(float));
    if (!tmp) {
        return gale_errf(err, GALE_E_NOMEM, "render_add_species: out of memory");
    }
    /* extent for culling, LOD and the impostor */
    float h = 0.0f, cr = 0.0f;
    for (size_t i = 0; i < nn; i++) {
        const float *p = &a->rest[3 * i];
        h = fmaxf(h, p[2]);
        cr = fmaxf(cr, sqrtf(p[0] * p[0] + p[1] * p[1]) + a->radius[i]);
    }
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        const float *p = &a->rest[3 * a->leaf_node[l]], *o = &a->leaf_offset[3 * l];
        float x = p[0] + o[0], y = p[1] + o[1];
        h = fmaxf(h, p[2] + o[2] + a->leaf_size[l]);
        cr = fmaxf(cr, sqrtf(x * x + y * y) + a->leaf_size[l]);
    }
    s->height = h;
    s->crown_r = cr;
    impostor_sway(s, a);
    s->leaves_thin = render_leaves_at(a->n_leaves, lod_leaf_share[LOD_THIN]);
    /* the stem at the base, for a snapped tree's stump: the root's radius, tapering as
       towards its thickest child */
    s->stem_r_m = a->radius[0];
    s->stem_taper = 0.0f;
    for (size_t i = 1, best = 0; i < nn; i++) {
        float dz = a->rest[3 * i + 2] - a->rest[2];
        if (a->parent[i] == 0 && dz > 0.05f && (best == 0 || a->radius[i] > a->radius[best])) {
            best = i;
            s->stem_taper = fminf((a->radius[i] - a->radius[0]) / dz, 0.0f);
        }
    }

    for (size_t m = 0; m < nm; m++) {
        for (size_t i = 0; i < nn; i++) {
            float *t = &tmp[((m * nn + i) * 2) * 4];
            memcpy(t, &a->corr_v[(m * nn + i) * 3], 3 * sizeof(float));
            t[3] = 0.0f;
            memcpy(t + 4, &a->corr_w[(m * nn + i) * 3], 3 * sizeof(float));
            t[7] = 0.0f;
        }
    }
    render_buf_create(&s->vw, GL_RGBA32F, tmp, nm * nn * 2 * 4 * sizeof(float));
    for (size_t i = 0; i < nn; i++) {
        memcpy(&tmp[4 * i], &a->rest[3 * i], 3 * sizeof(float));
        tmp[4 * i + 3] = (float)a->parent[i];
    }
    render_buf_create(&s->node, GL_RGBA32F, tmp, nn * 4 * sizeof(float));
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        float *t = &tmp[8 * l];
        memcpy(t, &a->leaf_offset[3 * l], 3 * sizeof(float));
        t[3] = (float)a->leaf_node[l];
        memcpy(t + 4, &a->leaf_normal[3 * l], 3 * sizeof(float));
        t[7] = a->leaf_size[l];
    }
    render_buf_create(&s->leaf, GL_RGBA32F, tmp, (size_t)a->n_leaves * 8 * sizeof(float));
    free(tmp);

    /* mesh: position, normal, bones, weight */
    glGenVertexArrays(1, &s->vao);
    glBindVertexArray(s->vao);
    size_t vb = (size_t)a->n_verts * (7 * sizeof(float) + 2 * sizeof(uint32_t));
    glGenBuffers(1, &s->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, s->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(vb ? vb : 16), NULL, GL_STATIC_DRAW);
    size_t o_pos = 0, o_nrm = (size_t)a->n_verts * 12, o_bone = (size_t)a->n_verts * 24,
           o_w = (size_t)a->n_verts * 32;
    if (a->n_verts) {
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_pos, (GLsizeiptr)a->n_verts * 12, a->mesh_pos);
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_nrm, (GLsizeiptr)a->n_verts * 12,
                        a->mesh_normal);
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_bone, (GLsizeiptr)a->n_verts * 8,
                        a->mesh_bone);
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_w, (GLsizeiptr)a->n_verts * 4, a->mesh_weight);
    }
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, (const void *)o_pos);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, (const void *)o_nrm);
    glEnableVertexAttribArray(2);
    glVertexAttribIPointer(2, 2, GL_UNSIGNED_INT, 0, (const void *)o_bone);
    glEnableVertexAttribArray(3);
    glVertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, 0, (const void *)o_w);
    glGenBuffers(1, &s->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, s->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(a->n_indices ? (size_t)a->n_indices * 4 : 4),
                 a->n_indices ? a->mesh_index : NULL, GL_STATIC_DRAW);
    glBindVertexArray(0);

    s->rest = dup_f(a->rest, 3 * nn);
    s->corr_v = dup_f(a->corr_v, 3 * nn * nm);
    s->corr_w = dup_f(a->corr_w, 3 * nn * nm);
    s->leaf_offset = dup_f(a->leaf_offset, 3 * (size_t)a->n_leaves);
    s->leaf_normal = dup_f(a->leaf_normal, 3 * (size_t)a->n_leaves);
    s->leaf_size = dup_f(a->leaf_size, a->n_leaves);
    s->leaf_node = malloc((size_t)a->n_leaves * sizeof(uint32_t) + 1);
    s->parent = malloc(nn * sizeof(int32_t));
    if (!s->rest || !s->parent || !s->corr_v || !s->corr_w || !s->leaf_offset || !s->leaf_normal ||
        !s->leaf_size || !s->leaf_node) {
        render_species_free(s);
        return gale_errf(err, GALE_E_NOMEM, "render_add_species: out of memory");
    }
    memcpy(s->leaf_node, a->leaf_node, (size_t)a->n_leaves * sizeof(uint32_t));
    memcpy(s->parent, a->parent, nn * sizeof(int32_t));

    /* q stride: the most modes of any species */
    if (a->n_modes > r->q_stride) {
        uint32_t old = r->q_stride;
        float *nq = calloc((size_t)render_slots(r) * a->n_modes, sizeof(float));
        if (!nq) {
            render_species_free(s);
            return gale_errf(err, GALE_E_NOMEM, "render_add_species: out of memory for q");
        }
        for (uint32_t t = 0; t < render_slots(r); t++) {
            memcpy(&nq[(size_t)t * a->n_modes], &r->q_stage[(size_t)t * old], old * sizeof(float));
        }
        free(r->q_stage);
        r->q_stage = nq;
        r->q_stride = a->n_modes;
    }
    r->n_species++;
    rc = species_impostor(r, s, sid, err);
    if (rc < 0) {
        r->n_species--;
        render_species_free(s);
        return rc;
    }
    return (int)sid;
}

void render_draw_skeleton(render *r, const rs_species *s, uint32_t base, uint32_t n)
{
    if (n == 0) {
        return;
    }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    const render_prog *p = &r->p_skel;
    glUseProgram(p->id);
    glUniform1i(p->u_base, (GLint)base);
    glUniform1i(p->u_nodes, (GLint)s->n_nodes);
    glUniform2f(p->u_target, (float)r->skel_w, (float)r->skel_h);
    glUniform1i(p->u_qstride, (GLint)r->q_stride);
    glUniform2fv(p->u_ab, (GLsizei)RENDER_MAX_MODES, s->ab);
    render_bind_buf(RU_LIST, &r->list_buf);
    render_bind_buf(RU_VW, &s->vw);
    render_bind_buf(RU_NODE, &s->node);
    render_bind_buf(RU_Q, &r->q);
    render_bind_buf(RU_CUT, &r->cut);
    render_bind_buf(RU_CUTN, &r->cutn);
    glBindVertexArray(r->vao_empty);
    /* shaders/skel.frag: posed segments into seg_tex, then their sums up to the root into
     * skel_tex (PHYSICS.md "Length-true pose") */
    glBindFramebuffer(GL_FRAMEBUFFER, r->seg_fbo);
    glViewport(0, 0, r->skel_w, r->skel_h);
    glUniform1i(p->u_pass, 0);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)n);
    glBindFramebuffer(GL_FRAMEBUFFER, r->skel_fbo);
    render_bind_tex(RU_SKEL, GL_TEXTURE_2D, r->seg_tex);
    glUniform1i(p->u_pass, 1);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)n);
    render_bind_tex(RU_SKEL, GL_TEXTURE_2D, r->skel_tex);
    r->stats.draw_calls += 2;
}

static void bind_tree_inputs(render *r, const rs_species *s)
{
    render_bind_tex(RU_SKEL, GL_TEXTURE_2D, r->skel_tex);
    render_bind_buf(RU_NODE, &s->node);
    render_bind_buf(RU_LIST, &r->list_buf);
    render_bind_buf(RU_TREES, &r->trees);
}

/* expects render_set_common(r, &r->p_tree, ...) and the target bound */
void render_draw_tree(render *r, const rs_species *s, uint32_t lod, uint32_t base, uint32_t n)
{
    if (n == 0 || lod >= s->n_lods || s->lod_count[lod] == 0) {
        return;
    }
    const render_prog *p = &r->p_tree;
    glUniform1i(p->u_base, (GLint)base);
    glUniform3fv(p->u_bark, 1, s->bark);
    bind_tree_inputs(r, s);
    glBindVertexArray(s->vao);
    glDrawElementsInstanced(GL_TRIANGLES, (GLsizei)s->lod_count[lod], GL_UNSIGNED_INT,
                            (const void *)((size_t)s->lod_first[lod] * 4), (GLsizei)n);
    r->stats.draw_calls++;
    r->stats.triangles += (uint64_t)(s->lod_count[lod] / 3u) * n;
}

/* expects render_set_common(r, &r->p_leaf, ...) */
void render_draw_leaves(render *r, const rs_species *s, uint32_t base, uint32_t n, bool thin)
{
    const uint32_t k = thin ? s->leaves_thin : s->n_leaves;
    if (n == 0 || k == 0) {
        return;
    }
    const render_prog *p = &r->p_leaf;
    glUniform1i(p->u_base, (GLint)base);
    glUniform1i(p->u_nleaves, (GLint)k);
    glUniform1i(p->u_leaf_total, (GLint)s->n_leaves);
    glUniform1f(p->u_leaf_grow, lod_leaf_grow[thin ? LOD_THIN : LOD_FULL]);
    glUniform1f(p->u_aspect, render_leaf_aspect[s->leaf_shape]);
    glUniform2f(p->u_crown, s->crown_r, s->height);
    glUniform3fv(p->u_leafcol, 1, s->leaf_rgb);
    glUniform1i(p->u_shape, (GLint)s->leaf_shape);
    bind_tree_inputs(r, s);
    render_bind_buf(RU_LEAF, &s->leaf);
    glBindVertexArray(r->vao_empty);
    glDisable(GL_CULL_FACE);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)(n * k));
    r->stats.draw_calls++;
    r->stats.leaves_drawn += (uint64_t)n * k;
    r->stats.triangles += 2u * (uint64_t)n * k;
}
