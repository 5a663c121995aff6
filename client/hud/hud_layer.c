/* HUD batches kept on the GPU as pictures (hud_batch_flush_keep, hud_batch_replay): a
 * panel that holds still is drawn as one textured quad. */
#include "hud_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Draws a layer's quad over the bound framebuffer. */
static void draw_layer(hud *h, hud_layer *L)
{
    L->used = ++h->stamp;
    if (L->w <= 0 || L->h <= 0) {
        return;
    }
    hud_gl_state(h, L->fb_w, L->fb_h);
    glUniform1i(h->u_layer, 1);
    glBindTexture(GL_TEXTURE_2D, L->tex);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied (hud_layer) */
    glBindVertexArray(L->vao);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glBindVertexArray(0);
    glUseProgram(0);
}

/* Room in L's buffers for its box: false when they cannot be made. Grows them (the only
 * allocation, when a picture is larger than any before it). */
static bool layer_room(hud_layer *L)
{
    if (!L->fbo) {
        glGenFramebuffers(1, &L->fbo);
        glGenRenderbuffers(1, &L->rb);
        glGenTextures(1, &L->tex);
        glGenVertexArrays(1, &L->vao);
        glGenBuffers(1, &L->vbo);
        glBindVertexArray(L->vao);
        glBindBuffer(GL_ARRAY_BUFFER, L->vbo);
        glBufferData(GL_ARRAY_BUFFER, 6 * VERT_FLOATS * sizeof(float), NULL, GL_DYNAMIC_DRAW);
        hud_vert_attribs();
        glBindVertexArray(0);
    }
    if (L->w <= L->cap_w && L->h <= L->cap_h) {
        return true;
    }
    /* grown, never shrunk: a panel's box changes with what it shows */
    int cw = L->w > L->cap_w ? L->w : L->cap_w, ch = L->h > L->cap_h ? L->h : L->cap_h;
    uint8_t *px = realloc(L->pixels, (size_t)cw * (size_t)ch * 4);
    if (!px) {
        return false;
    }
    L->pixels = px;
    L->cap_w = cw;
    L->cap_h = ch;
    glBindTexture(GL_TEXTURE_2D, L->tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, cw, ch, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    /* texel for pixel: the quad lies on whole pixels */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindRenderbuffer(GL_RENDERBUFFER, L->rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, cw, ch);
    GLint prev = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, L->fbo);
    glFramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, L->rb);
    bool ok = glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev);
    if (!ok) {
        L->cap_w = L->cap_h = 0;
    }
    return ok;
}

/* Renders the batch into L's offscreen buffer (its box clipped to the framebuffer); the
 * batch is left as it is. */
static bool layer_render(hud *h, hud_layer *L)
{
    float bx0 = (float)h->batch_w, by0 = (float)h->batch_h, bx1 = 0.0f, by1 = 0.0f;
    for (uint32_t i = 0; i < h->n_verts; i++) {
        const float *v = h->verts + (size_t)i * VERT_FLOATS;
        bx0 = fminf(bx0, v[0]);
        by0 = fminf(by0, v[1]);
        bx1 = fmaxf(bx1, v[0]);
        by1 = fmaxf(by1, v[1]);
    }
    int x0 = (int)fmaxf(floorf(bx0), 0.0f), y0 = (int)fmaxf(floorf(by0), 0.0f);
    int x1 = (int)fminf(ceilf(bx1), (float)h->batch_w);
    int y1 = (int)fminf(ceilf(by1), (float)h->batch_h);
    L->fb_w = h->batch_w;
    L->fb_h = h->batch_h;
    L->x0 = x0;
    L->y0 = y0;
    L->w = x1 > x0 ? x1 - x0 : 0;
    L->h = y1 > y0 ? y1 - y0 : 0;
    if (L->w == 0 || L->h == 0) {
        return true;
    }
    if (!layer_room(L)) {
        return false;
    }
    GLint prev = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev);
    GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, L->fbo);
    glDisable(GL_SCISSOR_TEST);
    const GLfloat clear[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    glClearBufferfv(GL_COLOR, 0, clear);
    hud_gl_state_at(h, L->w, L->h, x0, y0);
    hud_draw_verts(h);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev);
    if (scissor) {
        glEnable(GL_SCISSOR_TEST);
    }
    /* the quad: the texture's row 0 is the box's bottom */
    const float fx0 = (float)x0, fy0 = (float)y0, fx1 = (float)x1, fy1 = (float)y1;
    const float s1 = (float)L->w / (float)L->cap_w, t1 = (float)L->h / (float)L->cap_h;
    const float q[6][4] = { { fx0, fy0, 0, t1 }, { fx1, fy0, s1, t1 }, { fx1, fy1, s1, 0 },
                            { fx0, fy0, 0, t1 }, { fx1, fy1, s1, 0 },  { fx0, fy1, 0, 0 } };
    float v[6 * VERT_FLOATS] = { 0 };
    for (int i = 0; i < 6; i++) {
        memcpy(v + i * VERT_FLOATS, q[i], sizeof q[i]);
    }
    glBindBuffer(GL_ARRAY_BUFFER, L->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)sizeof v, v);
    return true;
}

/* Copies L's offscreen picture into its texture: within the driver where GL 4.3's image copy
 * is there (llvmpipe: a memory copy, 0.05-0.4 ms for the HUD and the panel), else through
 * memory (RGBA rows are whole words: any alignment reads them). */
static void layer_copy(const hud *h, hud_layer *L)
{
    if (L->w > 0 && L->h > 0 && h->copy_image) {
        glCopyImageSubData(L->rb, GL_RENDERBUFFER, 0, 0, 0, 0, L->tex, GL_TEXTURE_2D, 0, 0, 0,
                           0, L->w, L->h, 1);
    } else if (L->w > 0 && L->h > 0) {
        GLint prev_read = 0;
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, L->fbo);
        glReadPixels(0, 0, L->w, L->h, GL_RGBA, GL_UNSIGNED_BYTE, L->pixels);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_read);
        glBindTexture(GL_TEXTURE_2D, L->tex);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, L->w, L->h, GL_RGBA, GL_UNSIGNED_BYTE,
                        L->pixels);
    }
    L->ready = true;
}

void hud_batch_flush_keep(hud *h, uint64_t key)
{
    if (h->batch_spilled || key == 0 || h->batch_w <= 0 || h->batch_h <= 0) {
        hud_batch_flush(h);
        return;
    }
    bool again = false;
    for (int i = 0; i < HUD_LAYERS; i++) {
        again |= h->built[i] == key;
    }
    if (!again) {
        h->built[h->built_next] = key;
        h->built_next = (h->built_next + 1) % HUD_LAYERS;
    } else {
        /* held still for a frame: into the layer under this key, else the one drawn longest
         * ago */
        hud_layer *L = &h->layer[0];
        for (int i = 0; i < HUD_LAYERS; i++) {
            if (h->layer[i].key == key) {
                L = &h->layer[i];
                break;
            }
            if (h->layer[i].used < L->used) {
                L = &h->layer[i];
            }
        }
        L->key = 0;
        L->ready = false;
        L->used = ++h->stamp;
        if (layer_render(h, L)) {
            L->key = key;
        }
    }
    hud_batch_flush(h); /* this frame: drawn straight */
}

bool hud_batch_replay(hud *h, uint64_t key, int fb_w, int fb_h)
{
    for (int i = 0; key != 0 && i < HUD_LAYERS; i++) {
        hud_layer *L = &h->layer[i];
        if (L->key == key && L->fb_w == fb_w && L->fb_h == fb_h) {
            if (!L->ready) {
                layer_copy(h, L);
            }
            draw_layer(h, L);
            return true;
        }
    }
    return false;
}
