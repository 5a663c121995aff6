/* HUD internals shared by its GL files: hud_gl.c (program, atlas, vertex batch),
 * hud_layer.c (batches kept as pictures), hud_draw.c (the HUD's panels, veil and button).
 * Not part of the public API (hud.h). */
#ifndef GALE_HUD_INTERNAL_H
#define GALE_HUD_INTERNAL_H

#include <epoxy/gl.h>

#include <stdbool.h>
#include <stdint.h>

#include "hud.h"

#define VERT_FLOATS   8 /* x y s t r g b a; s < 0: solid colour */
#define HUD_MAX_VERTS (6 * (HUD_MAX_GLYPHS + 16))
#define HUD_LAYERS    2 /* kept pictures: the HUD's lines and a kiosk panel (one hud draws both) */

/* A kept batch (hud_batch_flush_keep): its picture rendered into an offscreen buffer the
 * size of its bounding box, copied into a texture, then drawn each frame as one quad. On a
 * software rasteriser (llvmpipe) a draw's vertex shading, setup and binning run on the
 * caller's thread, about 0.1 us a vertex, so one quad instead of the ~3,000 vertices of a
 * kiosk panel keeps that off the frame.
 * - The texture is a copy (layer_copy) rather than the render target itself: llvmpipe
 *   makes a draw that samples a texture ever rendered to wait until everything drawn before
 *   it is rasterised (0.5-1 ms measured with the HUD and the panel).
 * - The copy waits for the offscreen picture to be rasterised, so it is made a frame later:
 *   a picture built for the first time is drawn straight; built again with the same key (it
 *   held still for a frame) it is also rendered offscreen; the next replay copies it and
 *   from then on draws the quad. A picture that changes every frame (a finger on the dial)
 *   is drawn straight every frame, as without keeping.
 * The texture holds premultiplied colour (the batch blended over transparent black, alpha by
 * ONE, ONE_MINUS_SRC_ALPHA), so drawing it with ONE, ONE_MINUS_SRC_ALPHA gives the batch
 * drawn straight onto the frame, to 8-bit rounding. */
typedef struct hud_layer {
    uint64_t key;     /* 0: none */
    bool ready;       /* the texture holds the picture (else only the offscreen buffer) */
    uint32_t used;    /* stamp of its last draw: a new picture replaces the older layer */
    int fb_w, fb_h;   /* framebuffer it was built for */
    int x0, y0, w, h; /* its box on that framebuffer [px, y down]; w or h 0: empty */
    int cap_w, cap_h; /* size of the buffers below [px] */
    GLuint fbo, rb;   /* where the batch is rendered */
    GLuint tex;       /* the picture drawn (never a render target) */
    GLuint vao, vbo;  /* its quad */
    uint8_t *pixels;  /* owned: cap_w x cap_h RGBA, the copy through memory (layer_copy) */
} hud_layer;

struct hud {
    hud_font *font; /* owned */
    float px, ascent, descent, line_gap; /* the font's em and metrics [px] */
    GLuint prog, vao, vbo, tex;
    GLint u_size, u_atlas, u_origin, u_layer;
    float verts[HUD_MAX_VERTS * VERT_FLOATS];
    uint32_t n_verts;
    hud_quad quads[HUD_MAX_GLYPHS];
    int batch_w, batch_h; /* framebuffer of the batch (hud_batch_begin) */
    bool batch_spilled;   /* the batch was drawn in parts (too many vertices to keep) */
    hud_layer layer[HUD_LAYERS];
    uint32_t stamp;              /* layer draws so far */
    uint64_t built[HUD_LAYERS];  /* keys of the last batches built (hud_batch_flush_keep) */
    bool copy_image;             /* glCopyImageSubData is there (GL 4.3, ARB_copy_image) */
    uint32_t built_next;         /* the entry of built the next new key replaces */
    /* the lines of the HUD picture hud_draw drew last (hud_drawn_lines) */
    char drawn[HUD_MAX_LINES][HUD_LINE_CHARS];
    int n_drawn;
};

/* ---- hud_gl.c ----------------------------------------------------------------------- */

/* The vertex layout (x y s t r g b a) on the bound vertex array and array buffer. */
void hud_vert_attribs(void);
/* Push a rectangle (s < 0: solid colour), a UTF-8 string at pen (x, baseline y), or a solid
 * triangle onto the vertex batch; what does not fit HUD_MAX_VERTS is dropped. */
void hud_push_rect(hud *h, float x0, float y0, float x1, float y1, float s0, float t0, float s1,
                   float t1, const float rgba[4]);
void hud_push_text(hud *h, float x, float y, const char *s, const float rgba[4]);
void hud_push_tri(hud *h, const float p[6], const float rgba[4]);
/* The HUD program, atlas and blending over the bound framebuffer of fb_w x fb_h pixels
 * (whose top left is the point (x0, y0) of the vertices [px]); hud_gl_state at (0, 0). */
void hud_gl_state_at(hud *h, int fb_w, int fb_h, int x0, int y0);
void hud_gl_state(hud *h, int fb_w, int fb_h);
/* Uploads and draws the batch's vertices in the state set above. */
void hud_draw_verts(hud *h);
/* Sets the state and draws the batch's vertices over the bound framebuffer. */
void hud_flush_verts(hud *h, int fb_w, int fb_h);
/* Room for n more vertices, drawing what the batch holds when it lacks it. */
void hud_batch_room(hud *h, uint32_t n);

#endif
