/* OpenGL 3.3 core context for gale_render: an interactive GLFW window, or an offscreen
 * context with no display at all (EGL, Mesa surfaceless or an EGL device), falling back to
 * a hidden GLFW window (which needs an X server such as Xvfb). */
#ifndef GALE_GL_CTX_H
#define GALE_GL_CTX_H

#include <stdbool.h>

#include "err.h"

struct GLFWwindow;

typedef enum gl_ctx_kind {
    GL_CTX_WINDOW = 0,    /* visible GLFW window */
    GL_CTX_EGL,           /* EGL context with no surface; draw into an FBO */
    GL_CTX_HIDDEN_WINDOW, /* invisible GLFW window; draw into an FBO */
} gl_ctx_kind;

typedef struct gl_ctx {
    gl_ctx_kind kind;
    struct GLFWwindow *window; /* GL_CTX_WINDOW and GL_CTX_HIDDEN_WINDOW */
    void *egl_display;         /* GL_CTX_EGL */
    void *egl_context;
    char renderer[128];        /* GL_RENDERER string */
} gl_ctx;

/* Makes a 3.3 core context current on this thread. headless: EGL first (unless the
 * environment sets GALE_NO_EGL), then a hidden GLFW window. 0 or negative GALE_E_*. */
int gl_ctx_create(gl_ctx *c, int width, int height, bool headless, bool vsync,
                  const char *title, gale_err *err);

/* Destroys the context (and window). Zeroed or NULL is a no-op. */
void gl_ctx_destroy(gl_ctx *c);

#endif
