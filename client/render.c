/* gale_render: context, species upload, instances and the frame. Per frame the CPU only
 * walks trees (cull, LOD, one draw-list upload, one q upload); nodes are rebuilt on the
 * GPU into a skeleton texture (Diener 2008 section 5.1, figure 5) that skins meshes and
 * carries leaves; falling leaves follow one shared path (Vazquez 2008 sections 3-4). */
#include "render.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <cglm/cglm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h>

#include "falling_path.h"
#include "gl_ctx.h"
#include "render_internal.h"

#define RENDER_MAX_SPECIES 32
#define RENDER_MAX_MODES   64
#define IMP_W              256
#define IMP_H              512
/* groups of the per-frame draw list, per species */
enum { G_SKEL = 0, G_MESH = 1, G_LEAF = G_MESH + ASSET_MAX_LODS, G_BILL, G_COUNT };

typedef struct rs_buf {
    GLuint buf, tex; /* a buffer and its buffer texture */
    size_t bytes;
} rs_buf;

typedef struct rs_species {
    uint32_t n_nodes, n_modes, n_leaves, n_lods, leaf_shape;
    uint32_t lod_first[ASSET_MAX_LODS], lod_count[ASSET_MAX_LODS];
    float height, crown_r, bark[3], leaf_rgb[3];
    float ab[2 * RENDER_MAX_MODES];
    GLuint vao, vbo, ibo, imp_tex;
    rs_buf vw, node, leaf;
    float bill[3]; /* half width, height, bottom [m] */
    /* CPU copies for releasing falling leaves (one node per leaf, never per frame) */
    float *rest, *corr_v, *corr_w, *leaf_offset, *leaf_normal, *leaf_size;
    uint32_t *leaf_node;
} rs_species;

/* one falling-leaf record, the vertex layout of shaders/fall.vert */
typedef struct rs_fall {
    float start[4], var[4], drift[4], q0[4], look[4], shape;
} rs_fall;

struct render {
    gl_ctx ctx;
    render_desc desc;
    char shader_dir[512];
    int w, h;
    GLuint fbo, fbo_col, fbo_depth; /* offscreen target (headless) */
    GLuint vao_empty;
    GLuint p_skel, p_tree, p_leaf, p_fall, p_sky, p_bill, p_house;
    GLuint house_vao, house_vbo;  /* houses: world-space triangles (house_mesh) */
    uint32_t house_verts;

    rs_species sp[RENDER_MAX_SPECIES];
    uint32_t n_species;

    uint32_t n_trees, cap_trees; /* cap_trees + 1 slots: the last is a rest-pose slot */
    render_instance *inst;
    rs_buf trees;
    float *q_stage;
    uint32_t q_stride;
    rs_buf q;
    float *list;                  /* 4 floats per entry */
    uint32_t list_cap;
    rs_buf list_buf;
    uint32_t *tree_row, *tree_group; /* scratch per tree */
    float *tree_lod;                 /* scratch: packed modes / fades */
    uint32_t grp_base[RENDER_MAX_SPECIES][G_COUNT], grp_n[RENDER_MAX_SPECIES][G_COUNT];

    GLuint skel_tex, skel_fbo;
    int skel_w, skel_h;

    GLuint wind_tex;
    float wind_uniform[3], wind_origin[3], wind_extent[3], wind_cell[3];
    uint32_t wind_n[3];
    float *wind_v;

    falling_path path;
    GLuint path_tex;
    rs_fall *ring;
    uint32_t ring_cap, ring_head, ring_count, dirty_lo, dirty_hi;
    GLuint fall_vao, fall_vbo;
    double t_base;
    bool t_base_set;

    float view[16], proj[16], viewproj[16], eye[3];
    render_stats stats;
};

/* ---- small helpers ---- */

static void buf_tex_create(rs_buf *b, GLenum fmt, const void *data, size_t bytes)
{
    glGenBuffers(1, &b->buf);
    glBindBuffer(GL_TEXTURE_BUFFER, b->buf);
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(bytes ? bytes : 16), data, GL_DYNAMIC_DRAW);
    glGenTextures(1, &b->tex);
    glBindTexture(GL_TEXTURE_BUFFER, b->tex);
    glTexBuffer(GL_TEXTURE_BUFFER, fmt, b->buf);
    b->bytes = bytes ? bytes : 16;
}

static void buf_tex_upload(rs_buf *b, GLenum fmt, const void *data, size_t bytes)
{
    glBindBuffer(GL_TEXTURE_BUFFER, b->buf);
    if (bytes > b->bytes) {
        glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)bytes, data, GL_DYNAMIC_DRAW);
        b->bytes = bytes;
        glBindTexture(GL_TEXTURE_BUFFER, b->tex);
        glTexBuffer(GL_TEXTURE_BUFFER, fmt, b->buf);
    } else if (bytes) {
        /* orphan the old storage: the GPU may still read last frame's copy, and a plain
           sub-data upload would wait for it */
        glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)b->bytes, NULL, GL_DYNAMIC_DRAW);
        glBufferSubData(GL_TEXTURE_BUFFER, 0, (GLsizeiptr)bytes, data);
        glBindTexture(GL_TEXTURE_BUFFER, b->tex);
        glTexBuffer(GL_TEXTURE_BUFFER, fmt, b->buf);
    }
}

static void buf_tex_free(rs_buf *b)
{
    if (b->buf) {
        glDeleteBuffers(1, &b->buf);
        glDeleteTextures(1, &b->tex);
    }
    memset(b, 0, sizeof *b);
}

static void bind_buf_tex(int unit, const rs_buf *b)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(GL_TEXTURE_BUFFER, b->tex);
}

static void bind_tex(int unit, GLenum target, GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(target, tex);
}

static GLint uloc(GLuint p, const char *name)
{
    return glGetUniformLocation(p, name);
}

static double rel_time(render *r, double t)
{
    if (!r->t_base_set) {
        r->t_base = floor(t);
        r->t_base_set = true;
    }
    return t - r->t_base;
}

/* Scene uniforms shared by every program (common.glsl). */
static void set_common(render *r, GLuint p, float time_rel, float fog_dist)
{
    glUseProgram(p);
    glUniformMatrix4fv(uloc(p, "u_viewproj"), 1, GL_FALSE, r->viewproj);
    glUniform3fv(uloc(p, "u_eye"), 1, r->eye);
    vec3 sun = { 0.45f, -0.35f, 0.62f };
    glm_vec3_normalize(sun);
    glUniform3fv(uloc(p, "u_sun_dir"), 1, sun);
    glUniform3f(uloc(p, "u_sun_col"), 1.05f, 0.97f, 0.86f);
    glUniform3f(uloc(p, "u_sky_zenith"), 0.30f, 0.50f, 0.82f);
    glUniform3f(uloc(p, "u_sky_horizon"), 0.74f, 0.82f, 0.90f);
    glUniform3f(uloc(p, "u_ground_col"), 0.30f, 0.40f, 0.17f);
    glUniform1f(uloc(p, "u_fog_dist"), fog_dist);
    glUniform1f(uloc(p, "u_time"), time_rel);
    glUniform3fv(uloc(p, "u_wind_origin"), 1, r->wind_origin);
    glUniform3fv(uloc(p, "u_wind_extent"), 1, r->wind_extent);
    glUniform3fv(uloc(p, "u_wind_uniform"), 1, r->wind_uniform);
    bind_tex(RU_WIND, GL_TEXTURE_3D, r->wind_tex);
}

/* ---- context ---- */

static int target_create(render *r, gale_err *err)
{
    if (r->ctx.kind == GL_CTX_WINDOW) {
        return 0;
    }
    if (r->fbo) {
        glDeleteFramebuffers(1, &r->fbo);
        glDeleteTextures(1, &r->fbo_col);
        glDeleteRenderbuffers(1, &r->fbo_depth);
    }
    glGenTextures(1, &r->fbo_col);
    glBindTexture(GL_TEXTURE_2D, r->fbo_col);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, r->w, r->h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenRenderbuffers(1, &r->fbo_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, r->fbo_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, r->w, r->h);
    glGenFramebuffers(1, &r->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, r->fbo_col, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              r->fbo_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        return gale_errf(err, GALE_E_STATE, "render: offscreen framebuffer %dx%d incomplete",
                         r->w, r->h);
    }
    return 0;
}

static void target_bind(render *r)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->ctx.kind == GL_CTX_WINDOW ? 0 : r->fbo);
    glViewport(0, 0, r->w, r->h);
}

static int skel_ensure(render *r, int width, int rows, gale_err *err)
{
    if (width <= r->skel_w && rows <= r->skel_h) {
        return 0;
    }
    GLint maxs = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxs);
    int w = width > r->skel_w ? width : r->skel_w;
    int h = rows > r->skel_h ? rows : r->skel_h;
    if (h < 2 * r->skel_h) {
        h = 2 * r->skel_h; /* grow geometrically: reallocation stays rare */
    }
    if (h > maxs) {
        h = maxs;
    }
    if (w > maxs || rows > maxs) {
        return gale_errf(err, GALE_E_RANGE,
                         "render: skeleton texture %dx%d exceeds GL_MAX_TEXTURE_SIZE %d", w,
                         rows, maxs);
    }
    if (!r->skel_tex) {
        glGenTextures(1, &r->skel_tex);
        glGenFramebuffers(1, &r->skel_fbo);
    }
    glBindTexture(GL_TEXTURE_2D, r->skel_tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, r->skel_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, r->skel_tex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        return gale_errf(err, GALE_E_STATE, "render: skeleton texture %dx%d not renderable "
                         "(RGBA32F)", w, h);
    }
    r->skel_w = w;
    r->skel_h = h;
    return 0;
}

static int trees_alloc(render *r, uint32_t cap, gale_err *err)
{
    free(r->inst);
    free(r->q_stage);
    free(r->list);
    free(r->tree_row);
    free(r->tree_group);
    free(r->tree_lod);
    r->cap_trees = cap;
    r->inst = calloc(cap + 1, sizeof *r->inst);
    r->q_stage = calloc((size_t)(cap + 1) * r->q_stride, sizeof(float));
    r->list_cap = 5 * (cap + 1);
    r->list = calloc((size_t)r->list_cap * 4, sizeof(float));
    r->tree_row = calloc(cap + 1, sizeof(uint32_t));
    r->tree_group = calloc(cap + 1, sizeof(uint32_t));
    r->tree_lod = calloc((size_t)(cap + 1) * 4, sizeof(float));
    if (!r->inst || !r->q_stage || !r->list || !r->tree_row || !r->tree_group ||
        !r->tree_lod) {
        return gale_errf(err, GALE_E_NOMEM, "render: out of memory for %u trees", cap);
    }
    /* the rest-pose slot (index cap): origin, unit scale */
    r->inst[cap].scale = 1.0f;
    return 0;
}

static void trees_upload(render *r)
{
    uint32_t n = r->cap_trees + 1;
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
    }
    buf_tex_upload(&r->trees, GL_RGBA32F, t, (size_t)n * 8 * sizeof(float));
    free(t);
}

render *render_create(const render_desc *desc, gale_err *err)
{
    render *r = calloc(1, sizeof *r);
    if (!r) {
        gale_errf(err, GALE_E_NOMEM, "render: out of memory");
        return NULL;
    }
    r->desc = desc ? *desc : (render_desc){ 0 };
    render_desc *d = &r->desc;
    if (d->width == 0) {
        d->width = 1280;
    }
    if (d->height == 0) {
        d->height = 720;
    }
    if (d->max_trees == 0) {
        d->max_trees = 8192;
    }
    if (d->max_falling == 0) {
        d->max_falling = 16384;
    }
    if (d->lod_mode_dist == 0.0f) {
        d->lod_mode_dist = 40.0f;
    }
    if (d->lod_billboard_dist == 0.0f) {
        d->lod_billboard_dist = 220.0f;
    }
    if (d->fog_dist == 0.0f) {
        d->fog_dist = 450.0f;
    }
    if (d->width < 1 || d->height < 1 || d->width > 16384 || d->height > 16384 ||
        d->max_trees > (1u << 22) || d->max_falling > (1u << 22) ||
        !(d->lod_mode_dist > 0.0f) || !(d->lod_billboard_dist > 0.0f) ||
        !(d->fog_dist > 0.0f)) {
        gale_errf(err, GALE_E_ARG, "render_create: size %dx%d (1..16384), max_trees %u, "
                  "max_falling %u (<= 4M), LOD and fog distances > 0",
                  d->width, d->height, d->max_trees, d->max_falling);
        free(r);
        return NULL;
    }
    const char *sd = d->shader_dir ? d->shader_dir : getenv("GALE_SHADER_DIR");
    snprintf(r->shader_dir, sizeof r->shader_dir, "%s",
             sd ? sd : GALE_SOURCE_DIR "/shaders");
    d->shader_dir = NULL;
    d->title = NULL;
    r->w = d->width;
    r->h = d->height;
    if (gl_ctx_create(&r->ctx, r->w, r->h, d->headless, d->vsync,
                      desc && desc->title ? desc->title : "gale", err) < 0) {
        free(r);
        return NULL;
    }
    if (target_create(r, err) < 0) {
        goto fail;
    }
    glGenVertexArrays(1, &r->vao_empty);
    struct {
        GLuint *p;
        const char *name;
    } progs[] = { { &r->p_skel, "skel" }, { &r->p_tree, "tree" }, { &r->p_leaf, "leaf" },
                  { &r->p_fall, "fall" }, { &r->p_sky, "sky" },   { &r->p_bill, "bill" },
                  { &r->p_house, "house" } };
    for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++) {
        *progs[i].p = render_program_load(r->shader_dir, progs[i].name, err);
        if (!*progs[i].p) {
            goto fail;
        }
    }
    r->q_stride = 1;
    if (trees_alloc(r, d->max_trees, err) < 0) {
        goto fail;
    }
    buf_tex_create(&r->trees, GL_RGBA32F, NULL, (size_t)(d->max_trees + 1) * 8 * sizeof(float));
    trees_upload(r);
    buf_tex_create(&r->q, GL_R32F, NULL, 0);
    buf_tex_create(&r->list_buf, GL_RGBA32F, NULL, (size_t)r->list_cap * 4 * sizeof(float));
    if (skel_ensure(r, 64, 64, err) < 0) {
        goto fail;
    }
    /* wind: a 1x1x1 texture until a grid arrives */
    glGenTextures(1, &r->wind_tex);
    glBindTexture(GL_TEXTURE_3D, r->wind_tex);
    float zero[4] = { 0 };
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, 1, 1, 1, 0, GL_RGBA, GL_FLOAT, zero);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);

    /* the shared falling path, as a 2-row texture: positions, orientations */
    if (falling_path_build(&r->path, NULL, err) < 0) {
        goto fail;
    }
    {
        float *pt = calloc((size_t)r->path.n * 8, sizeof(float));
        if (!pt) {
            gale_errf(err, GALE_E_NOMEM, "render: out of memory");
            goto fail;
        }
        for (uint32_t i = 0; i < r->path.n; i++) {
            memcpy(&pt[4 * i], r->path.pos[i], 3 * sizeof(float));
            memcpy(&pt[4 * (r->path.n + i)], r->path.quat[i], 4 * sizeof(float));
        }
        glGenTextures(1, &r->path_tex);
        glBindTexture(GL_TEXTURE_2D, r->path_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, (GLsizei)r->path.n, 2, 0, GL_RGBA, GL_FLOAT,
                     pt);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        free(pt);
    }
    r->ring_cap = d->max_falling;
    r->ring = calloc(r->ring_cap, sizeof *r->ring);
    if (!r->ring) {
        gale_errf(err, GALE_E_NOMEM, "render: out of memory for %u falling leaves", r->ring_cap);
        goto fail;
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
    return r;
fail:
    render_destroy(r);
    return NULL;
}

static void species_free(rs_species *s)
{
    if (s->vao) {
        glDeleteVertexArrays(1, &s->vao);
        glDeleteBuffers(1, &s->vbo);
        glDeleteBuffers(1, &s->ibo);
    }
    if (s->imp_tex) {
        glDeleteTextures(1, &s->imp_tex);
    }
    buf_tex_free(&s->vw);
    buf_tex_free(&s->node);
    buf_tex_free(&s->leaf);
    free(s->rest);
    free(s->corr_v);
    free(s->corr_w);
    free(s->leaf_offset);
    free(s->leaf_normal);
    free(s->leaf_size);
    free(s->leaf_node);
    memset(s, 0, sizeof *s);
}

void render_destroy(render *r)
{
    if (!r) {
        return;
    }
    if (r->ctx.kind == GL_CTX_WINDOW || r->ctx.egl_context || r->ctx.window) {
        for (uint32_t i = 0; i < r->n_species; i++) {
            species_free(&r->sp[i]);
        }
        GLuint progs[] = { r->p_skel, r->p_tree, r->p_leaf, r->p_fall,
                           r->p_sky,  r->p_bill, r->p_house };
        for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++) {
            if (progs[i]) {
                glDeleteProgram(progs[i]);
            }
        }
        buf_tex_free(&r->trees);
        buf_tex_free(&r->q);
        buf_tex_free(&r->list_buf);
        GLuint texs[] = { r->skel_tex, r->wind_tex, r->path_tex, r->fbo_col };
        for (size_t i = 0; i < sizeof texs / sizeof texs[0]; i++) {
            if (texs[i]) {
                glDeleteTextures(1, &texs[i]);
            }
        }
        GLuint fbos[] = { r->skel_fbo, r->fbo };
        for (size_t i = 0; i < 2; i++) {
            if (fbos[i]) {
                glDeleteFramebuffers(1, &fbos[i]);
            }
        }
        if (r->fbo_depth) {
            glDeleteRenderbuffers(1, &r->fbo_depth);
        }
        if (r->fall_vao) {
            glDeleteVertexArrays(1, &r->fall_vao);
            glDeleteBuffers(1, &r->fall_vbo);
        }
        if (r->vao_empty) {
            glDeleteVertexArrays(1, &r->vao_empty);
        }
        if (r->house_vao) {
            glDeleteVertexArrays(1, &r->house_vao);
            glDeleteBuffers(1, &r->house_vbo);
        }
    }
    gl_ctx_destroy(&r->ctx);
    free(r->inst);
    free(r->q_stage);
    free(r->list);
    free(r->tree_row);
    free(r->tree_group);
    free(r->tree_lod);
    free(r->wind_v);
    free(r->ring);
    free(r);
}

struct GLFWwindow *render_window(render *r)
{
    return r && r->ctx.kind == GL_CTX_WINDOW ? r->ctx.window : NULL;
}

/* ---- species ---- */

static int species_check(const render *r, const asset *a, gale_err *err)
{
    const char *nm = a->species[0] ? a->species : "(unnamed)";
    if (r->n_species >= RENDER_MAX_SPECIES) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: at most %d species", nm,
                         RENDER_MAX_SPECIES);
    }
    if (a->n_nodes < 2 || a->n_nodes > 16384 || !a->parent || !a->rest) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: n_nodes %u (2..16384)",
                         nm, a->n_nodes);
    }
    if (a->n_modes > RENDER_MAX_MODES || (a->n_modes && (!a->corr_v || !a->corr_w ||
                                                         !a->corr_a || !a->corr_b))) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: n_modes %u (0..%d, with "
                         "corr_v/w/a/b)", nm, a->n_modes, RENDER_MAX_MODES);
    }
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        if ((i == 0) != (a->parent[i] < 0) || (i > 0 && (uint32_t)a->parent[i] >= i)) {
            return gale_errf(err, GALE_E_FORMAT, "render_add_species: %s: parent[%u] = %d: "
                             "root first, then parent < index", nm, i, a->parent[i]);
        }
    }
    for (uint32_t v = 0; v < 2 * a->n_verts; v++) {
        if (a->mesh_bone[v] >= a->n_nodes) {
            return gale_errf(err, GALE_E_FORMAT, "render_add_species: %s: mesh_bone[%u] = %u "
                             ">= n_nodes %u", nm, v, a->mesh_bone[v], a->n_nodes);
        }
    }
    for (uint32_t k = 0; k < a->n_indices; k++) {
        if (a->mesh_index[k] >= a->n_verts) {
            return gale_errf(err, GALE_E_FORMAT, "render_add_species: %s: mesh_index[%u] = %u "
                             ">= n_verts %u", nm, k, a->mesh_index[k], a->n_verts);
        }
    }
    if (a->n_lods < 1 || a->n_lods > ASSET_MAX_LODS) {
        return gale_errf(err, GALE_E_RANGE, "render_add_species: %s: n_lods %u (1..%d)", nm,
                         a->n_lods, ASSET_MAX_LODS);
    }
    for (uint32_t l = 0; l < a->n_lods; l++) {
        if ((uint64_t)a->lod_first[l] + a->lod_count[l] > a->n_indices ||
            a->lod_count[l] % 3) {
            return gale_errf(err, GALE_E_FORMAT, "render_add_species: %s: LOD %u [%u, +%u) "
                             "outside %u indices or not triangles", nm, l, a->lod_first[l],
                             a->lod_count[l], a->n_indices);
        }
    }
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        if (a->leaf_node[l] >= a->n_nodes) {
            return gale_errf(err, GALE_E_FORMAT, "render_add_species: %s: leaf_node[%u] = %u "
                             ">= n_nodes %u", nm, l, a->leaf_node[l], a->n_nodes);
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

static const float leaf_aspect[3] = { 0.55f, 0.16f, 1.0f };

static void draw_skeleton(render *r, const rs_species *s, uint32_t base, uint32_t n);
static void draw_tree(render *r, const rs_species *s, uint32_t lod, uint32_t base, uint32_t n);
static void draw_leaves(render *r, const rs_species *s, uint32_t base, uint32_t n);

/* The impostor: the species at rest seen from the side, orthographic, on a clear
 * transparent background; far trees show it as a billboard. */
static int species_impostor(render *r, rs_species *s, uint32_t sid, gale_err *err)
{
    float hw = s->crown_r * 1.05f + 0.2f, bottom = -0.05f * s->height;
    float top = s->height * 1.06f + 0.2f;
    s->bill[0] = hw;
    s->bill[1] = top - bottom;
    s->bill[2] = bottom;
    uint32_t slot = r->cap_trees;
    r->inst[slot] = (render_instance){ .species = sid, .scale = 1.0f };
    trees_upload(r);
    /* rest pose: zero q for the slot */
    memset(&r->q_stage[(size_t)slot * r->q_stride], 0, r->q_stride * sizeof(float));
    buf_tex_upload(&r->q, GL_R32F, r->q_stage,
                   (size_t)(r->cap_trees + 1) * r->q_stride * sizeof(float));
    float ent[4] = { (float)slot, 0.0f, (float)s->n_modes, 1.0f };
    buf_tex_upload(&r->list_buf, GL_RGBA32F, ent, sizeof ent);
    int rc = skel_ensure(r, (int)s->n_nodes, 1, err);
    if (rc < 0) {
        return rc;
    }
    draw_skeleton(r, s, 0, 1);

    GLuint tex, fbo, depth;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, IMP_W, IMP_H, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, IMP_W, IMP_H);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    glViewport(0, 0, IMP_W, IMP_H);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    mat4 view, proj, vp;
    float dist = 4.0f * (s->height + s->crown_r) + 10.0f;
    glm_lookat((vec3){ 0.0f, -dist, 0.5f * s->height }, (vec3){ 0.0f, 0.0f, 0.5f * s->height },
               (vec3){ 0.0f, 0.0f, 1.0f }, view);
    glm_ortho(-hw, hw, bottom - 0.5f * s->height, top - 0.5f * s->height, 0.1f, 2.0f * dist,
              proj);
    glm_mat4_mul(proj, view, vp);
    memcpy(r->viewproj, vp, sizeof r->viewproj);
    r->eye[0] = 0.0f;
    r->eye[1] = -dist;
    r->eye[2] = 0.5f * s->height;
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    set_common(r, r->p_tree, 0.0f, 1e9f);
    draw_tree(r, s, 0, 0, 1);
    set_common(r, r->p_leaf, 0.0f, 1e9f);
    draw_leaves(r, s, 0, 1);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &depth);
    glBindTexture(GL_TEXTURE_2D, tex);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    s->imp_tex = tex;
    return 0;
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
        s->ab[2 * m] = a->corr_a[m];
        s->ab[2 * m + 1] = a->corr_b[m];
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

    for (size_t m = 0; m < nm; m++) {
        for (size_t i = 0; i < nn; i++) {
            float *t = &tmp[((m * nn + i) * 2) * 4];
            memcpy(t, &a->corr_v[(m * nn + i) * 3], 3 * sizeof(float));
            t[3] = 0.0f;
            memcpy(t + 4, &a->corr_w[(m * nn + i) * 3], 3 * sizeof(float));
            t[7] = 0.0f;
        }
    }
    buf_tex_create(&s->vw, GL_RGBA32F, tmp, nm * nn * 2 * 4 * sizeof(float));
    for (size_t i = 0; i < nn; i++) {
        memcpy(&tmp[4 * i], &a->rest[3 * i], 3 * sizeof(float));
        tmp[4 * i + 3] = (float)a->parent[i];
    }
    buf_tex_create(&s->node, GL_RGBA32F, tmp, nn * 4 * sizeof(float));
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        float *t = &tmp[8 * l];
        memcpy(t, &a->leaf_offset[3 * l], 3 * sizeof(float));
        t[3] = (float)a->leaf_node[l];
        memcpy(t + 4, &a->leaf_normal[3 * l], 3 * sizeof(float));
        t[7] = a->leaf_size[l];
    }
    buf_tex_create(&s->leaf, GL_RGBA32F, tmp, (size_t)a->n_leaves * 8 * sizeof(float));
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
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_pos, (GLsizeiptr)a->n_verts * 12,
                        a->mesh_pos);
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_nrm, (GLsizeiptr)a->n_verts * 12,
                        a->mesh_normal);
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_bone, (GLsizeiptr)a->n_verts * 8,
                        a->mesh_bone);
        glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)o_w, (GLsizeiptr)a->n_verts * 4,
                        a->mesh_weight);
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
    if (!s->rest || !s->corr_v || !s->corr_w || !s->leaf_offset || !s->leaf_normal ||
        !s->leaf_size || !s->leaf_node) {
        species_free(s);
        return gale_errf(err, GALE_E_NOMEM, "render_add_species: out of memory");
    }
    memcpy(s->leaf_node, a->leaf_node, (size_t)a->n_leaves * sizeof(uint32_t));

    /* q stride: the most modes of any species */
    if (a->n_modes > r->q_stride) {
        uint32_t old = r->q_stride;
        float *nq = calloc((size_t)(r->cap_trees + 1) * a->n_modes, sizeof(float));
        if (!nq) {
            species_free(s);
            return gale_errf(err, GALE_E_NOMEM, "render_add_species: out of memory for q");
        }
        for (uint32_t t = 0; t <= r->cap_trees; t++) {
            memcpy(&nq[(size_t)t * a->n_modes], &r->q_stage[(size_t)t * old],
                   old * sizeof(float));
        }
        free(r->q_stage);
        r->q_stage = nq;
        r->q_stride = a->n_modes;
    }
    r->n_species++;
    rc = species_impostor(r, s, sid, err);
    if (rc < 0) {
        r->n_species--;
        species_free(s);
        return rc;
    }
    return (int)sid;
}

/* ---- instances, q, wind, falling leaves ---- */

int render_set_instances(render *r, uint32_t n, const render_instance *inst, gale_err *err)
{
    if (n > r->cap_trees) {
        return gale_errf(err, GALE_E_RANGE, "render_set_instances: %u trees, max_trees %u", n,
                         r->cap_trees);
    }
    for (uint32_t i = 0; i < n; i++) {
        if (inst[i].species >= r->n_species) {
            return gale_errf(err, GALE_E_RANGE, "render_set_instances: tree %u: species %u "
                             "not added (%u species)", i, inst[i].species, r->n_species);
        }
        if (!isfinite(inst[i].pos[0] + inst[i].pos[1] + inst[i].pos[2] + inst[i].yaw +
                      inst[i].scale) || inst[i].scale < 0.0f) {
            return gale_errf(err, GALE_E_RANGE, "render_set_instances: tree %u: position, "
                             "yaw or scale not finite or scale < 0", i);
        }
    }
    if (n > 0) { /* inst may be NULL for an empty scene */
        memcpy(r->inst, inst, n * sizeof *inst);
    }
    memset(&r->inst[n], 0, (r->cap_trees - n) * sizeof *inst);
    r->inst[r->cap_trees].scale = 1.0f;
    r->n_trees = n;
    trees_upload(r);
    memset(r->q_stage, 0, (size_t)(r->cap_trees + 1) * r->q_stride * sizeof(float));
    render_clear_falling(r);
    return 0;
}

int render_set_q(render *r, uint32_t tree, const float *q, uint32_t n, gale_err *err)
{
    if (tree >= r->n_trees) {
        return gale_errf(err, GALE_E_RANGE, "render_set_q: tree %u of %u", tree, r->n_trees);
    }
    const rs_species *s = &r->sp[r->inst[tree].species];
    if (n != s->n_modes) {
        return gale_errf(err, GALE_E_RANGE, "render_set_q: tree %u: %u modes, species has %u",
                         tree, n, s->n_modes);
    }
    memcpy(&r->q_stage[(size_t)tree * r->q_stride], q, n * sizeof(float));
    return 0;
}

float *render_q_staging(render *r, uint32_t *stride)
{
    *stride = r->q_stride;
    return r->q_stage;
}

/* ---- houses ---- */

/* Vertex of shaders/house.vert: position, normal, (u, v, wall height, half width), material. */
enum { HV_FLOATS = 11, HV_PER_BOX = 42 };

typedef struct house_box {
    int ia, ib;        /* ridge axis, across axis (0 = x, 1 = y) */
    float lo[3], hi[3];
    float ca, cb;      /* centre along a and b */
    float zw;          /* eave height [m] */
    float *out;
} house_box;

static void house_vert(house_box *h, float a, float b, float z, float nx_a, float nx_b, float nz,
                       float u, float v, float half_w, float mat)
{
    float *o = h->out;
    o[h->ia] = a;
    o[h->ib] = b;
    o[2] = z;
    o[3 + h->ia] = nx_a;
    o[3 + h->ib] = nx_b;
    o[5] = nz;
    o[6] = u;
    o[7] = v;
    o[8] = h->zw - h->lo[2];
    o[9] = half_w;
    o[10] = mat;
    h->out += HV_FLOATS;
}

/* One box as a house: four walls up to the eaves at zw, the two end walls closed by gable
 * triangles, and two roof planes meeting in a ridge along the longer side at the box top.
 * Writes HV_PER_BOX vertices (triangles). The roof rises 40 % of the height, at most a
 * 40 degree pitch (tan 40° ≈ 0.84 over the half width). */
static float *house_mesh(const float *mm, float *out)
{
    house_box h = { .out = out };
    memcpy(h.lo, mm, sizeof h.lo);
    memcpy(h.hi, mm + 3, sizeof h.hi);
    h.ia = h.hi[0] - h.lo[0] >= h.hi[1] - h.lo[1] ? 0 : 1;
    h.ib = 1 - h.ia;
    float a0 = h.lo[h.ia], a1 = h.hi[h.ia], b0 = h.lo[h.ib], b1 = h.hi[h.ib];
    float z0 = h.lo[2], z1 = h.hi[2];
    h.ca = 0.5f * (a0 + a1);
    h.cb = 0.5f * (b0 + b1);
    float half_a = 0.5f * (a1 - a0), half_b = 0.5f * (b1 - b0);
    float rh = fminf(0.4f * (z1 - z0), 0.84f * half_b);
    h.zw = z1 - rh;
    /* long walls (normal -b, +b): u along a */
    for (int s = -1; s <= 1; s += 2) {
        float b = s < 0 ? b0 : b1, fs = (float)s;
        float q[4][2] = { { a0, z0 }, { a1, z0 }, { a1, h.zw }, { a0, h.zw } };
        int idx[6] = { 0, 1, 2, 0, 2, 3 };
        for (int k = 0; k < 6; k++) {
            const float *p = q[idx[k]];
            house_vert(&h, p[0], b, p[1], 0.0f, fs, 0.0f, p[0] - h.ca, p[1] - z0, half_a, 0.0f);
        }
    }
    /* end walls (normal -a, +a) with their gables: u along b */
    for (int s = -1; s <= 1; s += 2) {
        float a = s < 0 ? a0 : a1, fs = (float)s;
        float q[5][2] = { { b0, z0 }, { b1, z0 }, { b1, h.zw }, { b0, h.zw }, { h.cb, z1 } };
        int idx[9] = { 0, 1, 2, 0, 2, 3, 3, 2, 4 };
        for (int k = 0; k < 9; k++) {
            const float *p = q[idx[k]];
            house_vert(&h, a, p[0], p[1], fs, 0.0f, 0.0f, p[0] - h.cb, p[1] - z0, half_b, 0.0f);
        }
    }
    /* roof planes: from the eave at b0 or b1 up to the ridge; v along the slope */
    float slope = sqrtf(half_b * half_b + rh * rh);
    float nb = slope > 0.0f ? rh / slope : 0.0f, nz = slope > 0.0f ? half_b / slope : 1.0f;
    for (int s = -1; s <= 1; s += 2) {
        float b = s < 0 ? b0 : b1, fs = (float)s;
        float q[4][3] = { { a0, b, 0.0f }, { a1, b, 0.0f }, { a1, h.cb, slope }, { a0, h.cb, slope } };
        int idx[6] = { 0, 1, 2, 0, 2, 3 };
        for (int k = 0; k < 6; k++) {
            const float *p = q[idx[k]];
            float z = p[2] > 0.0f ? z1 : h.zw;
            house_vert(&h, p[0], p[1], z, 0.0f, fs * nb, nz, p[0] - h.ca, p[2], half_a, 1.0f);
        }
    }
    return h.out;
}

int render_set_obstacles(render *r, uint32_t n, const float *min_max, gale_err *err)
{
    if (n > RENDER_MAX_OBSTACLES || (n > 0 && !min_max)) {
        return gale_errf(err, GALE_E_ARG,
                         "render_set_obstacles: expected at most %u boxes and their corners, got %u%s",
                         RENDER_MAX_OBSTACLES, n, n > 0 && !min_max ? " and no array" : "");
    }
    for (uint32_t i = 0; i < n; i++) {
        const float *b = &min_max[6 * i];
        for (int k = 0; k < 6; k++) {
            if (!isfinite(b[k]) || fabsf(b[k]) > 1e6f) {
                return gale_errf(err, GALE_E_RANGE,
                                 "render_set_obstacles: box %u corner value %d: expected |value| <= 1e6, got %g",
                                 i, k, (double)b[k]);
            }
        }
        for (int k = 0; k < 3; k++) {
            if (b[k] > b[k + 3]) {
                return gale_errf(err, GALE_E_RANGE,
                                 "render_set_obstacles: box %u: expected min <= max on axis %c, got %g > %g",
                                 i, "xyz"[k], (double)b[k], (double)b[k + 3]);
            }
        }
    }
    r->house_verts = 0;
    if (n == 0) {
        return 0;
    }
    float *v = malloc((size_t)n * HV_PER_BOX * HV_FLOATS * sizeof(float));
    if (!v) {
        return gale_errf(err, GALE_E_NOMEM, "render_set_obstacles: out of memory for %u boxes", n);
    }
    float *end = v;
    for (uint32_t i = 0; i < n; i++) {
        end = house_mesh(&min_max[6 * i], end);
    }
    if (!r->house_vao) {
        glGenVertexArrays(1, &r->house_vao);
        glGenBuffers(1, &r->house_vbo);
        glBindVertexArray(r->house_vao);
        glBindBuffer(GL_ARRAY_BUFFER, r->house_vbo);
        const GLsizei stride = (GLsizei)(HV_FLOATS * sizeof(float));
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
    r->house_verts = n * HV_PER_BOX;
    return 0;
}

int render_set_wind(render *r, const render_wind *w, gale_err *err)
{
    if (!isfinite(w->uniform[0] + w->uniform[1] + w->uniform[2])) {
        return gale_errf(err, GALE_E_RANGE, "render_set_wind: uniform wind not finite");
    }
    memcpy(r->wind_uniform, w->uniform, sizeof r->wind_uniform);
    if (w->nx == 0) {
        memset(r->wind_extent, 0, sizeof r->wind_extent);
        r->wind_n[0] = 0;
        return 0;
    }
    uint64_t cells = (uint64_t)w->nx * w->ny * w->nz;
    if (w->ny == 0 || w->nz == 0 || w->nx > 1024 || w->ny > 1024 || w->nz > 256 || !w->v ||
        !(w->cell[0] > 0.0f) || !(w->cell[1] > 0.0f) || !(w->cell[2] > 0.0f)) {
        return gale_errf(err, GALE_E_RANGE, "render_set_wind: grid %ux%ux%u (<= 1024x1024x256) "
                         "with cell sizes > 0 and data", w->nx, w->ny, w->nz);
    }
    if (r->wind_n[0] != w->nx || r->wind_n[1] != w->ny || r->wind_n[2] != w->nz) {
        float *nv = realloc(r->wind_v, cells * 4 * sizeof(float));
        if (!nv) {
            return gale_errf(err, GALE_E_NOMEM, "render_set_wind: out of memory");
        }
        r->wind_v = nv;
    }
    for (uint64_t c = 0; c < cells; c++) {
        r->wind_v[4 * c] = w->v[3 * c];
        r->wind_v[4 * c + 1] = w->v[3 * c + 1];
        r->wind_v[4 * c + 2] = w->v[3 * c + 2];
        r->wind_v[4 * c + 3] = 0.0f;
    }
    glBindTexture(GL_TEXTURE_3D, r->wind_tex);
    if (r->wind_n[0] != w->nx || r->wind_n[1] != w->ny || r->wind_n[2] != w->nz) {
        glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, (GLsizei)w->nx, (GLsizei)w->ny,
                     (GLsizei)w->nz, 0, GL_RGBA, GL_FLOAT, r->wind_v);
    } else {
        glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, (GLsizei)w->nx, (GLsizei)w->ny,
                        (GLsizei)w->nz, GL_RGBA, GL_FLOAT, r->wind_v);
    }
    r->wind_n[0] = w->nx;
    r->wind_n[1] = w->ny;
    r->wind_n[2] = w->nz;
    for (int k = 0; k < 3; k++) {
        r->wind_origin[k] = w->origin[k];
        r->wind_cell[k] = w->cell[k];
        r->wind_extent[k] = w->cell[k] * (float)r->wind_n[k];
    }
    return 0;
}

static void wind_sample(const render *r, const float p[3], float out[3])
{
    memcpy(out, r->wind_uniform, 3 * sizeof(float));
    if (r->wind_n[0] == 0) {
        return;
    }
    uint32_t ijk[3];
    for (int k = 0; k < 3; k++) {
        float c = (p[k] - r->wind_origin[k]) / r->wind_cell[k];
        if (k == 2) {
            /* a slice or a low grid applies at every height: clamp vertically */
            c = fminf(fmaxf(c, 0.0f), (float)r->wind_n[2] - 0.5f);
        }
        if (!(c >= 0.0f) || c >= (float)r->wind_n[k]) {
            return;
        }
        ijk[k] = (uint32_t)c;
    }
    size_t c = ijk[0] + r->wind_n[0] * ((size_t)ijk[1] + r->wind_n[1] * ijk[2]);
    memcpy(out, &r->wind_v[4 * c], 3 * sizeof(float));
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
    /* the slot's node in the tree's current pose: rest + Σ q̃ v + q̃² w for that node only
       (Diener 2008 section 5.2) */
    uint32_t j = s->leaf_node[ls->slot];
    const float *q = &r->q_stage[(size_t)ls->tree * r->q_stride];
    float x[3];
    memcpy(x, &s->rest[3 * j], sizeof x);
    for (uint32_t m = 0; m < s->n_modes; m++) {
        float qt = s->ab[2 * m] * atanf(s->ab[2 * m + 1] * q[m]);
        for (int k = 0; k < 3; k++) {
            size_t o = ((size_t)m * s->n_nodes + j) * 3 + (size_t)k;
            x[k] += qt * s->corr_v[o] + qt * qt * s->corr_w[o];
        }
    }
    float sc = in->scale > 0.0f ? in->scale : 1.0f, cy = cosf(in->yaw), sy = sinf(in->yaw);
    const float *off = &s->leaf_offset[3 * ls->slot];
    float lp[3] = { (x[0] + off[0]) * sc, (x[1] + off[1]) * sc, (x[2] + off[2]) * sc };
    float wp[3] = { in->pos[0] + cy * lp[0] - sy * lp[1], in->pos[1] + sy * lp[0] + cy * lp[1],
                    in->pos[2] + lp[2] };
    float size = s->leaf_size[ls->slot] * sc;

    uint32_t seed = falling_hash(ls->seed ^ (ls->tree * 2654435761u) ^ (ls->slot * 40503u));
    falling_var v;
    falling_var_from_seed(&r->path, seed, &v);
    float t_land = falling_path_land_time(&r->path, &v, wp[2], 600.0f);
    float wind[3];
    wind_sample(r, wp, wind);

    rs_fall *f = &r->ring[r->ring_head];
    memset(f, 0, sizeof *f);
    f->start[0] = wp[0];
    f->start[1] = wp[1];
    f->start[2] = wp[2];
    f->start[3] = (float)rel_time(r, ls->spawn_time_s);
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
    float yel = 0.35f * (float)(falling_hash(seed + 5u) >> 8) / 16777216.0f;
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

/* ---- drawing ---- */

static void draw_skeleton(render *r, const rs_species *s, uint32_t base, uint32_t n)
{
    if (n == 0) {
        return;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, r->skel_fbo);
    glViewport(0, 0, r->skel_w, r->skel_h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    GLuint p = r->p_skel;
    glUseProgram(p);
    glUniform1i(uloc(p, "u_base"), (GLint)base);
    glUniform1i(uloc(p, "u_nodes"), (GLint)s->n_nodes);
    glUniform2f(uloc(p, "u_target"), (float)r->skel_w, (float)r->skel_h);
    glUniform1i(uloc(p, "u_qstride"), (GLint)r->q_stride);
    glUniform2fv(uloc(p, "u_ab"), RENDER_MAX_MODES, s->ab);
    bind_buf_tex(RU_LIST, &r->list_buf);
    bind_buf_tex(RU_VW, &s->vw);
    bind_buf_tex(RU_NODE, &s->node);
    bind_buf_tex(RU_Q, &r->q);
    glBindVertexArray(r->vao_empty);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)n);
    r->stats.draw_calls++;
}

static void bind_tree_inputs(render *r, const rs_species *s)
{
    bind_tex(RU_SKEL, GL_TEXTURE_2D, r->skel_tex);
    bind_buf_tex(RU_NODE, &s->node);
    bind_buf_tex(RU_LIST, &r->list_buf);
    bind_buf_tex(RU_TREES, &r->trees);
}

/* expects set_common(r, r->p_tree, ...) and the target bound */
static void draw_tree(render *r, const rs_species *s, uint32_t lod, uint32_t base, uint32_t n)
{
    if (n == 0 || lod >= s->n_lods || s->lod_count[lod] == 0) {
        return;
    }
    GLuint p = r->p_tree;
    glUniform1i(uloc(p, "u_base"), (GLint)base);
    glUniform3fv(uloc(p, "u_bark"), 1, s->bark);
    bind_tree_inputs(r, s);
    glBindVertexArray(s->vao);
    glDrawElementsInstanced(GL_TRIANGLES, (GLsizei)s->lod_count[lod], GL_UNSIGNED_INT,
                            (const void *)((size_t)s->lod_first[lod] * 4), (GLsizei)n);
    r->stats.draw_calls++;
}

/* expects set_common(r, r->p_leaf, ...) */
static void draw_leaves(render *r, const rs_species *s, uint32_t base, uint32_t n)
{
    if (n == 0 || s->n_leaves == 0) {
        return;
    }
    GLuint p = r->p_leaf;
    glUniform1i(uloc(p, "u_base"), (GLint)base);
    glUniform1i(uloc(p, "u_nleaves"), (GLint)s->n_leaves);
    glUniform1f(uloc(p, "u_aspect"), leaf_aspect[s->leaf_shape]);
    glUniform2f(uloc(p, "u_crown"), s->crown_r, s->height);
    glUniform3fv(uloc(p, "u_leafcol"), 1, s->leaf_rgb);
    glUniform1i(uloc(p, "u_shape"), (GLint)s->leaf_shape);
    bind_tree_inputs(r, s);
    bind_buf_tex(RU_LEAF, &s->leaf);
    glBindVertexArray(r->vao_empty);
    glDisable(GL_CULL_FACE);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)(n * s->n_leaves));
    r->stats.draw_calls++;
    r->stats.leaves_drawn += (uint64_t)n * s->n_leaves;
}

static void camera_matrices(render *r, const render_camera *cam)
{
    mat4 view, proj, vp;
    if (cam->matrices) {
        memcpy(view, cam->view, sizeof view);
        memcpy(proj, cam->proj, sizeof proj);
        mat4 inv;
        glm_mat4_inv(view, inv);
        r->eye[0] = inv[3][0];
        r->eye[1] = inv[3][1];
        r->eye[2] = inv[3][2];
    } else {
        vec3 up = { cam->up[0], cam->up[1], cam->up[2] };
        if (up[0] == 0.0f && up[1] == 0.0f && up[2] == 0.0f) {
            up[2] = 1.0f;
        }
        vec3 eye = { cam->eye[0], cam->eye[1], cam->eye[2] };
        vec3 tgt = { cam->target[0], cam->target[1], cam->target[2] };
        glm_lookat(eye, tgt, up, view);
        float fov = cam->fov_y_deg > 0.0f ? cam->fov_y_deg : 50.0f;
        float zn = cam->z_near > 0.0f ? cam->z_near : 0.3f;
        float zf = cam->z_far > 0.0f ? cam->z_far : 3000.0f;
        glm_perspective(glm_rad(fov), (float)r->w / (float)r->h, zn, zf, proj);
        memcpy(r->eye, cam->eye, sizeof r->eye);
    }
    glm_mat4_mul(proj, view, vp);
    memcpy(r->view, view, sizeof view);
    memcpy(r->proj, proj, sizeof proj);
    memcpy(r->viewproj, vp, sizeof vp);
}

static float smooth01(float x)
{
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return x * x * (3.0f - 2.0f * x);
}

/* Cull and choose LOD per tree, and fill the draw list grouped by species and kind. */
static void build_lists(render *r)
{
    vec4 planes[6];
    mat4 vp; /* cglm wants its 16-byte alignment */
    memcpy(vp, r->viewproj, sizeof vp);
    glm_frustum_planes(vp, planes);
    const float bill_end = r->desc.lod_billboard_dist, bill_start = 0.8f * bill_end;
    const float mode_d = r->desc.lod_mode_dist;
    memset(r->grp_n, 0, sizeof r->grp_n);
    /* pass 1: classify and count */
    uint32_t rows = 0;
    for (uint32_t i = 0; i < r->n_trees; i++) {
        const render_instance *in = &r->inst[i];
        const rs_species *s = &r->sp[in->species];
        float sc = in->scale > 0.0f ? in->scale : 1.0f;
        float c[3] = { in->pos[0], in->pos[1], in->pos[2] + 0.5f * s->height * sc };
        /* bound: the crown can sway by a good part of its height */
        float rad = sc * sqrtf(0.25f * s->height * s->height + s->crown_r * s->crown_r) * 1.3f;
        bool vis = true;
        for (int k = 0; k < 6 && vis; k++) {
            vis = planes[k][0] * c[0] + planes[k][1] * c[1] + planes[k][2] * c[2] +
                      planes[k][3] > -rad;
        }
        r->tree_group[i] = 0;
        if (!vis) {
            r->stats.trees_culled++;
            continue;
        }
        float dx = c[0] - r->eye[0], dy = c[1] - r->eye[1], dz = c[2] - r->eye[2];
        float d = sqrtf(dx * dx + dy * dy + dz * dz) / sc;
        float tb = smooth01((d - bill_start) / (bill_end - bill_start));
        float *lod = &r->tree_lod[4 * i];
        lod[0] = tb;
        uint32_t flags = 0;
        if (tb < 1.0f) {
            flags |= 1u;
            r->tree_row[i] = rows++;
            /* modes: all up to mode_d, then fewer as 1/d, never below 4 (section 5.1) */
            float nm = (float)s->n_modes;
            if (d > mode_d) {
                nm = fmaxf(fminf(4.0f, nm), nm * mode_d / d);
            }
            lod[1] = nm;
            /* mesh LODs share the distance up to the billboard band; the last 30 % of
               each band dithers into the next */
            float lf = fmaxf(d, 0.0f) / (bill_start / (float)s->n_lods);
            uint32_t k = (uint32_t)fminf(lf, (float)(s->n_lods - 1));
            float tt = k + 1 < s->n_lods ? smooth01((lf - (float)k - 0.7f) / 0.3f) : 0.0f;
            lod[2] = (float)k;
            lod[3] = tt;
            r->grp_n[in->species][G_SKEL]++;
            r->grp_n[in->species][G_LEAF]++;
            r->grp_n[in->species][G_MESH + k]++;
            if (tt > 0.0f) {
                r->grp_n[in->species][G_MESH + k + 1]++;
            }
            r->stats.trees_full++;
        }
        if (tb > 0.0f) {
            flags |= 2u;
            r->grp_n[in->species][G_BILL]++;
            r->stats.trees_billboard++;
        }
        r->tree_group[i] = flags;
    }
    uint32_t off = 0;
    for (uint32_t s = 0; s < r->n_species; s++) {
        for (int g = 0; g < G_COUNT; g++) {
            r->grp_base[s][g] = off;
            off += r->grp_n[s][g];
            r->grp_n[s][g] = 0;
        }
    }
    /* pass 2: fill */
    for (uint32_t i = 0; i < r->n_trees; i++) {
        uint32_t fl = r->tree_group[i];
        if (!fl) {
            continue;
        }
        uint32_t sp = r->inst[i].species;
        const float *lod = &r->tree_lod[4 * i];
        float tb = lod[0];
        float row = (float)r->tree_row[i];
#define PUT(g, a, b, c, d)                                                                     \
    do {                                                                                       \
        float *e = &r->list[4 * (r->grp_base[sp][g] + r->grp_n[sp][g]++)];                   \
        e[0] = (a);                                                                            \
        e[1] = (b);                                                                            \
        e[2] = (c);                                                                            \
        e[3] = (d);                                                                            \
    } while (0)
        if (fl & 1u) {
            float keep = 1.0f - tb; /* fading out toward the billboard */
            PUT(G_SKEL, (float)i, row, lod[1], 1.0f);
            PUT(G_LEAF, (float)i, row, 0.0f, keep);
            uint32_t k = (uint32_t)lod[2];
            float tt = lod[3];
            if (tt > 0.0f) {
                PUT(G_MESH + (int)k, (float)i, row, 0.0f, 1.0f - tt);
                PUT(G_MESH + (int)k + 1, (float)i, row, 0.0f, -tt);
            } else {
                PUT(G_MESH + (int)k, (float)i, row, 0.0f, keep);
            }
        }
        if (fl & 2u) {
            PUT(G_BILL, (float)i, 0.0f, 0.0f, (fl & 1u) ? -tb : 1.0f);
        }
#undef PUT
    }
    buf_tex_upload(&r->list_buf, GL_RGBA32F, r->list, (size_t)off * 4 * sizeof(float));
    r->tree_row[r->cap_trees] = rows; /* rows used this frame */
}

int render_frame(render *r, const render_camera *cam, double time_s, gale_err *err)
{
    memset(&r->stats, 0, sizeof r->stats);
    float t = (float)rel_time(r, time_s);
    camera_matrices(r, cam);
    /* one upload of every tree's q (the rest slot at cap_trees is uploaded when used) */
    if (r->n_trees > 0) {
        buf_tex_upload(&r->q, GL_R32F, r->q_stage,
                       (size_t)r->n_trees * r->q_stride * sizeof(float));
    }
    build_lists(r);
    uint32_t rows = r->tree_row[r->cap_trees];
    int maxw = 1;
    for (uint32_t s = 0; s < r->n_species; s++) {
        maxw = (int)r->sp[s].n_nodes > maxw ? (int)r->sp[s].n_nodes : maxw;
    }
    int rc = skel_ensure(r, maxw, rows > 0 ? (int)rows : 1, err);
    if (rc < 0) {
        return rc;
    }
    for (uint32_t s = 0; s < r->n_species; s++) {
        draw_skeleton(r, &r->sp[s], r->grp_base[s][G_SKEL], r->grp_n[s][G_SKEL]);
    }

    target_bind(r);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    /* sky and ground */
    glDepthFunc(GL_ALWAYS);
    set_common(r, r->p_sky, t, r->desc.fog_dist);
    mat4 inv, vp;
    memcpy(vp, r->viewproj, sizeof vp);
    glm_mat4_inv(vp, inv);
    glUniformMatrix4fv(uloc(r->p_sky, "u_inv_viewproj"), 1, GL_FALSE, (float *)inv);
    glBindVertexArray(r->vao_empty);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    r->stats.draw_calls++;
    glDepthFunc(GL_LESS);
    /* houses (both faces drawn: the mesh is closed, and thin boxes stay visible) */
    if (r->house_verts > 0) {
        set_common(r, r->p_house, t, r->desc.fog_dist);
        glUniform3f(uloc(r->p_house, "u_wall"), 0.92f, 0.82f, 0.64f);
        glUniform3f(uloc(r->p_house, "u_roof"), 0.52f, 0.22f, 0.15f);
        glUniform3f(uloc(r->p_house, "u_window"), 0.14f, 0.18f, 0.24f);
        glBindVertexArray(r->house_vao);
        glDrawArrays(GL_TRIANGLES, 0, (GLsizei)r->house_verts);
        r->stats.draw_calls++;
    }
    /* trunks and branches */
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    set_common(r, r->p_tree, t, r->desc.fog_dist);
    for (uint32_t s = 0; s < r->n_species; s++) {
        for (uint32_t l = 0; l < r->sp[s].n_lods; l++) {
            draw_tree(r, &r->sp[s], l, r->grp_base[s][G_MESH + l], r->grp_n[s][G_MESH + l]);
        }
    }
    glDisable(GL_CULL_FACE);
    set_common(r, r->p_leaf, t, r->desc.fog_dist);
    for (uint32_t s = 0; s < r->n_species; s++) {
        draw_leaves(r, &r->sp[s], r->grp_base[s][G_LEAF], r->grp_n[s][G_LEAF]);
    }
    /* billboards */
    set_common(r, r->p_bill, t, r->desc.fog_dist);
    bind_buf_tex(RU_LIST, &r->list_buf);
    bind_buf_tex(RU_TREES, &r->trees);
    for (uint32_t s = 0; s < r->n_species; s++) {
        uint32_t n = r->grp_n[s][G_BILL];
        if (n == 0) {
            continue;
        }
        glUniform1i(uloc(r->p_bill, "u_base"), (GLint)r->grp_base[s][G_BILL]);
        glUniform3fv(uloc(r->p_bill, "u_bsize"), 1, r->sp[s].bill);
        bind_tex(RU_IMP, GL_TEXTURE_2D, r->sp[s].imp_tex);
        glBindVertexArray(r->vao_empty);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)n);
        r->stats.draw_calls++;
    }
    /* falling and landed leaves */
    if (r->ring_count > 0) {
        glBindBuffer(GL_ARRAY_BUFFER, r->fall_vbo);
        if (r->dirty_lo < r->dirty_hi) {
            glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)(r->dirty_lo * sizeof(rs_fall)),
                            (GLsizeiptr)((r->dirty_hi - r->dirty_lo) * sizeof(rs_fall)),
                            &r->ring[r->dirty_lo]);
        }
        r->dirty_lo = UINT32_MAX;
        r->dirty_hi = 0;
        GLuint p = r->p_fall;
        set_common(r, p, t, r->desc.fog_dist);
        glUniform1i(uloc(p, "u_npath"), (GLint)r->path.n);
        glUniform1f(uloc(p, "u_pdt"), r->path.dt);
        glUniform1i(uloc(p, "u_ncont"), (GLint)r->path.n_cont);
        GLint cont[8] = { 0 };
        for (uint32_t i = 0; i < r->path.n_cont; i++) {
            cont[i] = (GLint)r->path.cont[i];
        }
        glUniform1iv(uloc(p, "u_cont"), 8, cont);
        glUniform1fv(uloc(p, "u_aspects"), 3, leaf_aspect);
        bind_tex(RU_PATH, GL_TEXTURE_2D, r->path_tex);
        glBindVertexArray(r->fall_vao);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)r->ring_count);
        r->stats.draw_calls++;
    }
    r->stats.falling_live = r->ring_count;
    glBindVertexArray(0);
    /* leave the target bound for overlays */
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        return gale_errf(err, GALE_E_STATE, "render_frame: OpenGL error 0x%x", (unsigned)e);
    }
    return 0;
}

void render_present(render *r)
{
    if (r->ctx.kind == GL_CTX_WINDOW) {
        glfwSwapBuffers(r->ctx.window);
    } else {
        glFinish();
    }
}

int render_resize(render *r, int width, int height, gale_err *err)
{
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        return gale_errf(err, GALE_E_ARG, "render_resize: %dx%d (1..16384)", width, height);
    }
    r->w = width;
    r->h = height;
    return target_create(r, err);
}

void render_size(const render *r, int *width, int *height)
{
    *width = r->w;
    *height = r->h;
}

int render_read_rgb(render *r, uint8_t *rgb, gale_err *err)
{
    target_bind(r);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (r->ctx.kind == GL_CTX_WINDOW) {
        glReadBuffer(GL_BACK);
    }
    glReadPixels(0, 0, r->w, r->h, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    /* bottom-up to top-down, in place */
    size_t row = (size_t)r->w * 3;
    for (int y = 0; y < r->h / 2; y++) {
        uint8_t *a = rgb + (size_t)y * row, *b = rgb + (size_t)(r->h - 1 - y) * row;
        for (size_t k = 0; k < row; k++) {
            uint8_t t = a[k];
            a[k] = b[k];
            b[k] = t;
        }
    }
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        return gale_errf(err, GALE_E_STATE, "render_read_rgb: OpenGL error 0x%x", (unsigned)e);
    }
    return 0;
}

int render_write_png(render *r, const char *path, gale_err *err)
{
    size_t n = (size_t)r->w * (size_t)r->h * 3;
    uint8_t *rgb = malloc(n);
    if (!rgb) {
        return gale_errf(err, GALE_E_NOMEM, "render_write_png: out of memory");
    }
    int rc = render_read_rgb(r, rgb, err);
    if (rc == 0 && !stbi_write_png(path, r->w, r->h, 3, rgb, r->w * 3)) {
        rc = gale_errf(err, GALE_E_IO, "%s: cannot write PNG", path);
    }
    free(rgb);
    return rc;
}

int render_read_skeleton(render *r, uint32_t tree, float *out, gale_err *err)
{
    if (tree >= r->n_trees) {
        return gale_errf(err, GALE_E_RANGE, "render_read_skeleton: tree %u of %u", tree,
                         r->n_trees);
    }
    const rs_species *s = &r->sp[r->inst[tree].species];
    buf_tex_upload(&r->q, GL_R32F, r->q_stage,
                   (size_t)(r->cap_trees + 1) * r->q_stride * sizeof(float));
    float ent[4] = { (float)tree, 0.0f, (float)s->n_modes, 1.0f };
    buf_tex_upload(&r->list_buf, GL_RGBA32F, ent, sizeof ent);
    int rc = skel_ensure(r, (int)s->n_nodes, 1, err);
    if (rc < 0) {
        return rc;
    }
    draw_skeleton(r, s, 0, 1);
    float *px = malloc((size_t)s->n_nodes * 4 * sizeof(float));
    if (!px) {
        return gale_errf(err, GALE_E_NOMEM, "render_read_skeleton: out of memory");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, r->skel_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, (GLsizei)s->n_nodes, 1, GL_RGBA, GL_FLOAT, px);
    for (uint32_t i = 0; i < s->n_nodes; i++) {
        memcpy(&out[3 * i], &px[4 * i], 3 * sizeof(float));
    }
    free(px);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        return gale_errf(err, GALE_E_STATE, "render_read_skeleton: OpenGL error 0x%x",
                         (unsigned)e);
    }
    return 0;
}

render_stats render_get_stats(const render *r)
{
    return r->stats;
}
