/* gale_render GPU plumbing: buffer textures and their uploads, texture binding, the
 * offscreen target, the skeleton texture (Diener 2008 section 5.1, figure 5) and the scene
 * uniforms every program shares. */
#include "render_internal.h"

#include <cglm/cglm.h>
#include <math.h>
#include <string.h>

void render_buf_create(rs_buf *b, GLenum fmt, const void *data, size_t bytes)
{
    glGenBuffers(1, &b->buf);
    glBindBuffer(GL_TEXTURE_BUFFER, b->buf);
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(bytes ? bytes : 16), data, GL_DYNAMIC_DRAW);
    glGenTextures(1, &b->tex);
    glBindTexture(GL_TEXTURE_BUFFER, b->tex);
    glTexBuffer(GL_TEXTURE_BUFFER, fmt, b->buf);
    b->bytes = bytes ? bytes : 16;
}

void render_buf_upload(rs_buf *b, GLenum fmt, const void *data, size_t bytes)
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

void render_buf_free(rs_buf *b)
{
    if (b->buf) {
        glDeleteBuffers(1, &b->buf);
        glDeleteTextures(1, &b->tex);
    }
    memset(b, 0, sizeof *b);
}

void render_bind_buf(int unit, const rs_buf *b)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(GL_TEXTURE_BUFFER, b->tex);
}

void render_bind_tex(int unit, GLenum target, GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(target, tex);
}

double render_rel_time(render *r, double t)
{
    if (!r->t_base_set) {
        r->t_base = floor(t);
        r->t_base_set = true;
    }
    return t - r->t_base;
}

/* Scene uniforms shared by every program (common.glsl). */
void render_set_common(render *r, const render_prog *p, float time_rel, float fog_dist)
{
    glUseProgram(p->id);
    glUniformMatrix4fv(p->u_viewproj, 1, GL_FALSE, r->viewproj);
    glUniform3fv(p->u_eye, 1, r->eye);
    vec3 sun = { 0.45f, -0.35f, 0.62f };
    glm_vec3_normalize(sun);
    glUniform3fv(p->u_sun_dir, 1, sun);
    glUniform3fv(p->u_sun_col, 1, r->fx.sun_col);
    glUniform3fv(p->u_sky_zenith, 1, r->fx.sky_zenith);
    glUniform3fv(p->u_sky_horizon, 1, r->fx.sky_horizon);
    glUniform3fv(p->u_ground_col, 1, r->fx.ground_col);
    glUniform1f(p->u_fog_dist, fog_dist * r->fx.fog_scale);
    /* the storm fog is fog_dist * fog_scale; up to the subject it is thinned towards the
     * calm fog_dist (common.glsl fog_apply) */
    glUniform4f(p->u_storm, r->fx.wet, r->subject_m, fog_dist, r->fx.subject_clear);
    glUniform1f(p->u_time, time_rel);
    glUniform3fv(p->u_wind_origin, 1, r->wind_origin);
    glUniform3fv(p->u_wind_extent, 1, r->wind_extent);
    glUniform3fv(p->u_wind_uniform, 1, r->wind_uniform);
    render_bind_tex(RU_WIND, GL_TEXTURE_3D, r->wind_tex);
}

/* ---- targets ---- */

int render_target_create(render *r, gale_err *err)
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
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->fbo_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        return gale_errf(err, GALE_E_STATE, "render: offscreen framebuffer %dx%d incomplete", r->w,
                         r->h);
    }
    return 0;
}

void render_target_bind(render *r)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->ctx.kind == GL_CTX_WINDOW ? 0 : r->fbo);
    glViewport(0, 0, r->w, r->h);
}

int render_skel_ensure(render *r, int width, int rows, gale_err *err)
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
                         "render: skeleton texture %dx%d exceeds GL_MAX_TEXTURE_SIZE %d", w, rows,
                         maxs);
    }
    GLuint *texs[2] = { &r->skel_tex, &r->seg_tex }, *fbos[2] = { &r->skel_fbo, &r->seg_fbo };
    for (int k = 0; k < 2; k++) {
        if (!*texs[k]) {
            glGenTextures(1, texs[k]);
            glGenFramebuffers(1, fbos[k]);
        }
        glBindTexture(GL_TEXTURE_2D, *texs[k]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, *fbos[k]);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *texs[k], 0);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            return gale_errf(err, GALE_E_STATE,
                             "render: skeleton texture %dx%d not renderable "
                             "(RGBA32F)",
                             w, h);
        }
    }
    r->skel_w = w;
    r->skel_h = h;
    return 0;
}

/* The lower-resolution scene target: the target's size × res_scale, at least 16 px. */
static int scene_low_ensure(render *r, gale_err *err)
{
    int w = (int)lroundf((float)r->w * r->res_scale), h = (int)lroundf((float)r->h * r->res_scale);
    w = w < 16 ? 16 : w;
    h = h < 16 ? 16 : h;
    if (r->low_fbo && w == r->low_w && h == r->low_h) {
        return 0;
    }
    if (!r->low_fbo) {
        glGenFramebuffers(1, &r->low_fbo);
        glGenTextures(1, &r->low_col);
        glGenRenderbuffers(1, &r->low_depth);
    }
    glBindTexture(GL_TEXTURE_2D, r->low_col);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glBindRenderbuffer(GL_RENDERBUFFER, r->low_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, r->low_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, r->low_col, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->low_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        return gale_errf(err, GALE_E_STATE, "render: scene framebuffer %dx%d incomplete", w, h);
    }
    r->low_w = w;
    r->low_h = h;
    return 0;
}

int render_scene_bind(render *r, gale_err *err)
{
    if (!(r->res_scale < 1.0f)) {
        render_target_bind(r);
        return 0;
    }
    int rc = scene_low_ensure(r, err);
    if (rc < 0) {
        return rc;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, r->low_fbo);
    glViewport(0, 0, r->low_w, r->low_h);
    return 0;
}

void render_scene_present(render *r)
{
    if (!(r->res_scale < 1.0f)) {
        return;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->low_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->ctx.kind == GL_CTX_WINDOW ? 0 : r->fbo);
    glBlitFramebuffer(0, 0, r->low_w, r->low_h, 0, 0, r->w, r->h, GL_COLOR_BUFFER_BIT,
                      GL_LINEAR);
    render_target_bind(r);
}
