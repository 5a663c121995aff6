/* The HUD's GL 3.3 pass: one program, the glyph atlas as a texture, and a batch of
 * alpha-blended quads and triangles (text, solid shapes) drawn over the frame. */
#include "hud_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *hud_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec2 a_pos;\n"
    "layout(location = 1) in vec2 a_st;\n"
    "layout(location = 2) in vec4 a_rgba;\n"
    "uniform vec2 u_size;\n"
    "uniform vec2 u_origin;\n"
    "out vec2 v_st;\n"
    "out vec4 v_rgba;\n"
    "void main() {\n"
    "    vec2 p = a_pos - u_origin;\n"
    "    v_st = a_st;\n"
    "    v_rgba = a_rgba;\n"
    "    gl_Position = vec4(p.x / u_size.x * 2.0 - 1.0, 1.0 - p.y / u_size.y * 2.0, 0.0, 1.0);\n"
    "}\n";

static const char *hud_fs = "#version 330 core\n"
                            "in vec2 v_st;\n"
                            "in vec4 v_rgba;\n"
                            "uniform sampler2D u_atlas;\n"
                            "uniform int u_layer;\n"
                            "out vec4 o_color;\n"
                            "void main() {\n"
                            "    if (u_layer != 0) {\n"
                            "        o_color = texture(u_atlas, v_st);\n"
                            "        return;\n"
                            "    }\n"
                            "    float cov = v_st.x < 0.0 ? 1.0 : texture(u_atlas, v_st).r;\n"
                            "    o_color = vec4(v_rgba.rgb, v_rgba.a * cov);\n"
                            "}\n";

static GLuint compile(GLenum type, const char *src, gale_err *err)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[200];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        gale_errf(err, GALE_E_STATE, "hud %s shader: %s",
                  type == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

/* The vertex layout (x y s t r g b a) on the bound vertex array and array buffer. */
void hud_vert_attribs(void)
{
    const GLsizei stride = VERT_FLOATS * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, stride, (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride, (void *)(2 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, (void *)(4 * sizeof(float)));
}

hud *hud_create(const hud_desc *d, gale_err *err)
{
    hud_desc r = d ? *d : (hud_desc){ 0 };
    if (!r.font_path) {
        r.font_path = HUD_DEFAULT_FONT;
    }
    if (r.px == 0.0f) {
        r.px = 18.0f;
    }
    hud *h = calloc(1, sizeof *h);
    if (!h) {
        gale_errf(err, GALE_E_NOMEM, "hud: no memory");
        return NULL;
    }
    h->font = hud_font_load(r.font_path, r.px, err);
    if (!h->font) {
        free(h);
        return NULL;
    }
    h->px = r.px;
    hud_font_metrics(h->font, &h->ascent, &h->descent, &h->line_gap);
    GLuint vs = compile(GL_VERTEX_SHADER, hud_vs, err);
    GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, hud_fs, err) : 0;
    if (!vs || !fs) {
        if (vs) {
            glDeleteShader(vs);
        }
        hud_destroy(h);
        return NULL;
    }
    h->prog = glCreateProgram();
    glAttachShader(h->prog, vs);
    glAttachShader(h->prog, fs);
    glLinkProgram(h->prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(h->prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        gale_errf(err, GALE_E_STATE, "hud shader program does not link");
        hud_destroy(h);
        return NULL;
    }
    h->u_size = glGetUniformLocation(h->prog, "u_size");
    h->u_atlas = glGetUniformLocation(h->prog, "u_atlas");
    h->u_origin = glGetUniformLocation(h->prog, "u_origin");
    h->u_layer = glGetUniformLocation(h->prog, "u_layer");
    h->copy_image = epoxy_gl_version() >= 43 || epoxy_has_gl_extension("GL_ARB_copy_image");

    int aw, ah;
    const uint8_t *atlas = hud_font_atlas(h->font, &aw, &ah);
    glGenTextures(1, &h->tex);
    glBindTexture(GL_TEXTURE_2D, h->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, aw, ah, 0, GL_RED, GL_UNSIGNED_BYTE, atlas);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

    glGenVertexArrays(1, &h->vao);
    glGenBuffers(1, &h->vbo);
    glBindVertexArray(h->vao);
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof h->verts, NULL, GL_STREAM_DRAW);
    hud_vert_attribs();
    glBindVertexArray(0);
    return h;
}

void hud_destroy(hud *h)
{
    if (!h) {
        return;
    }
    if (h->prog) {
        glDeleteProgram(h->prog);
    }
    if (h->vbo) {
        glDeleteBuffers(1, &h->vbo);
    }
    if (h->vao) {
        glDeleteVertexArrays(1, &h->vao);
    }
    for (int i = 0; i < HUD_LAYERS; i++) {
        hud_layer *L = &h->layer[i];
        if (L->fbo) {
            glDeleteFramebuffers(1, &L->fbo);
        }
        if (L->rb) {
            glDeleteRenderbuffers(1, &L->rb);
        }
        free(L->pixels);
        if (L->tex) {
            glDeleteTextures(1, &L->tex);
        }
        if (L->vbo) {
            glDeleteBuffers(1, &L->vbo);
        }
        if (L->vao) {
            glDeleteVertexArrays(1, &L->vao);
        }
    }
    if (h->tex) {
        glDeleteTextures(1, &h->tex);
    }
    hud_font_unload(h->font);
    free(h);
}

const hud_font *hud_get_font(const hud *h)
{
    return h->font;
}

void hud_push_rect(hud *h, float x0, float y0, float x1, float y1, float s0, float t0, float s1,
                      float t1, const float rgba[4])
{
    if (h->n_verts + 6 > HUD_MAX_VERTS) {
        return;
    }
    const float c[6][4] = { { x0, y0, s0, t0 }, { x1, y0, s1, t0 }, { x1, y1, s1, t1 },
                            { x0, y0, s0, t0 }, { x1, y1, s1, t1 }, { x0, y1, s0, t1 } };
    for (int i = 0; i < 6; i++) {
        float *v = h->verts + (size_t)h->n_verts * VERT_FLOATS;
        v[0] = c[i][0];
        v[1] = c[i][1];
        v[2] = c[i][2];
        v[3] = c[i][3];
        memcpy(v + 4, rgba, 4 * sizeof(float));
        h->n_verts++;
    }
}

void hud_push_text(hud *h, float x, float y, const char *s, const float rgba[4])
{
    uint32_t n = hud_text_quads(h->font, x, y, s, h->quads, HUD_MAX_GLYPHS, NULL);
    for (uint32_t i = 0; i < n; i++) {
        const hud_quad *q = &h->quads[i];
        hud_push_rect(h, q->x0, q->y0, q->x1, q->y1, q->s0, q->t0, q->s1, q->t1, rgba);
    }
}

/* The HUD program, atlas and blending over the bound framebuffer of fb_w x fb_h pixels
 * (whose top left is the point (x0, y0) of the vertices [px]). */
void hud_gl_state_at(hud *h, int fb_w, int fb_h, int x0, int y0)
{
    glUseProgram(h->prog);
    glUniform2f(h->u_size, (float)fb_w, (float)fb_h);
    glUniform2f(h->u_origin, (float)x0, (float)y0);
    glUniform1i(h->u_layer, 0);
    glUniform1i(h->u_atlas, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, h->tex);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glViewport(0, 0, fb_w, fb_h);
}

void hud_gl_state(hud *h, int fb_w, int fb_h)
{
    hud_gl_state_at(h, fb_w, fb_h, 0, 0);
}

/* Uploads and draws the vertices pushed since n_verts was reset, in the state hud_gl_state
 * or hud_gl_state_at set. */
void hud_draw_verts(hud *h)
{
    glBindVertexArray(h->vao);
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0,
                    (GLsizeiptr)((size_t)h->n_verts * VERT_FLOATS * sizeof(float)), h->verts);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)h->n_verts);
    glBindVertexArray(0);
    glUseProgram(0);
}

/* Uploads and draws the vertices pushed since n_verts was reset, over the bound framebuffer. */
void hud_flush_verts(hud *h, int fb_w, int fb_h)
{
    hud_gl_state(h, fb_w, fb_h);
    hud_draw_verts(h);
}

void hud_push_tri(hud *h, const float p[6], const float rgba[4])
{
    if (h->n_verts + 3 > HUD_MAX_VERTS) {
        return;
    }
    for (int i = 0; i < 3; i++) {
        float *v = h->verts + (size_t)h->n_verts * VERT_FLOATS;
        v[0] = p[2 * i];
        v[1] = p[2 * i + 1];
        v[2] = -1.0f;
        v[3] = 0.0f;
        memcpy(v + 4, rgba, 4 * sizeof(float));
        h->n_verts++;
    }
}

/* ---- batches for other panels --------------------------------------------------------- */

void hud_batch_begin(hud *h, int fb_w, int fb_h)
{
    h->n_verts = 0;
    h->batch_w = fb_w;
    h->batch_h = fb_h;
    h->batch_spilled = false;
}

void hud_batch_flush(hud *h)
{
    if (h->n_verts > 0 && h->batch_w > 0 && h->batch_h > 0) {
        hud_flush_verts(h, h->batch_w, h->batch_h);
    }
    h->n_verts = 0;
}

/* Room for n more vertices, drawing what the batch holds when it lacks it. */
void hud_batch_room(hud *h, uint32_t n)
{
    if (h->n_verts + n > HUD_MAX_VERTS) {
        hud_batch_flush(h);
        h->batch_spilled = true;
    }
}

void hud_batch_rect(hud *h, float x0, float y0, float x1, float y1, const float rgba[4])
{
    hud_batch_room(h, 6);
    hud_push_rect(h, x0, y0, x1, y1, -1, 0, -1, 0, rgba);
}

void hud_batch_tri(hud *h, const float xy[6], const float rgba[4])
{
    hud_batch_room(h, 3);
    hud_push_tri(h, xy, rgba);
}

float hud_batch_text(hud *h, float x, float y, float px, const char *utf8, const float rgba[4],
                     float align, const float *shadow_rgba)
{
    const float k = px / h->px;
    float end = 0.0f;
    uint32_t n = hud_text_quads(h->font, 0.0f, 0.0f, utf8, h->quads, HUD_MAX_GLYPHS, &end);
    x = floorf(x - align * k * end);
    y = floorf(y);
    hud_batch_room(h, (shadow_rgba ? 12 : 6) * n);
    for (int pass = shadow_rgba ? 0 : 1; pass < 2; pass++) {
        const float d = pass == 0 ? fmaxf(1.0f, floorf(px / 18.0f)) : 0.0f;
        for (uint32_t i = 0; i < n; i++) {
            const hud_quad *q = &h->quads[i];
            hud_push_rect(h, x + d + k * q->x0, y + d + k * q->y0, x + d + k * q->x1,
                      y + d + k * q->y1, q->s0, q->t0, q->s1, q->t1,
                      pass == 0 ? shadow_rgba : rgba);
        }
    }
    return k * end;
}

float hud_batch_text_width(const hud *h, const char *utf8, float px)
{
    return hud_text_width(h->font, utf8) * px / h->px;
}
