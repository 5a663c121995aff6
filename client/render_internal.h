/* gale_render internals shared by render.c (context, species, instances, frame) and
 * render_shader.c (run-time shader loading). Not part of the public API. */
#ifndef GALE_RENDER_INTERNAL_H
#define GALE_RENDER_INTERNAL_H

#include <epoxy/gl.h>

#include "err.h"

/* Texture units, fixed for every program. */
enum {
    RU_SKEL = 0,  /* skeleton texture: node positions per visible tree */
    RU_NODE = 1,  /* species rest positions + parents (buffer) */
    RU_LIST = 2,  /* per-frame draw list (buffer) */
    RU_TREES = 3, /* instance transforms (buffer) */
    RU_VW = 4,    /* species corrected mode shapes v, w (buffer) */
    RU_Q = 5,     /* modal state of every tree (buffer) */
    RU_LEAF = 6,  /* species leaf slots (buffer) */
    RU_WIND = 7,  /* coarse wind (3D) */
    RU_PATH = 8,  /* falling-leaf path */
    RU_IMP = 9,   /* billboard impostor */
};

/* Compiles and links shaders/<name>.vert + <name>.frag (each preceded by common.glsl)
 * from dir; binds the sampler uniforms to their units. 0 on failure with err set
 * (file:line of the compiler message). */
GLuint render_program_load(const char *dir, const char *name, gale_err *err);

#endif
