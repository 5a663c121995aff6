/* OpenGL 3.3 core context: GLFW window, EGL with no surface (EGL_MESA_platform_surfaceless
 * or EGL_EXT_platform_device, so a GPU machine without X can render), or a hidden GLFW
 * window under Xvfb. */
#include "gl_ctx.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

static int glfw_users;

static void glfw_error_cb(int code, const char *msg)
{
    (void)code;
    (void)msg; /* reported through the failing call */
}

static bool egl_has_ext(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) {
            return true;
        }
    }
    return false;
}

static EGLDisplay egl_open_display(void)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client) {
        return EGL_NO_DISPLAY;
    }
    /* An EGL device first (the GPU of a display-less server), then Mesa surfaceless. */
    if (egl_has_ext(client, "EGL_EXT_platform_device") &&
        egl_has_ext(client, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT dev[8];
        EGLint n = 0;
        if (eglQueryDevicesEXT(8, dev, &n) && n > 0) {
            for (EGLint i = 0; i < n; i++) {
                EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, dev[i], NULL);
                EGLint maj, min;
                if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min)) {
                    const char *vendor = eglQueryString(d, EGL_VENDOR);
                    /* Mesa lists its software device too; prefer a real GPU and keep
                       software for the surfaceless path below. */
                    const char *dexts = eglQueryDeviceStringEXT
                        ? eglQueryDeviceStringEXT(dev[i], EGL_EXTENSIONS) : NULL;
                    bool software = dexts && egl_has_ext(dexts, "EGL_MESA_device_software");
                    if (!software || (vendor && !strstr(vendor, "Mesa"))) {
                        return d;
                    }
                    eglTerminate(d);
                }
            }
        }
    }
    if (egl_has_ext(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                EGL_DEFAULT_DISPLAY, NULL);
        EGLint maj, min;
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min)) {
            return d;
        }
    }
    return EGL_NO_DISPLAY;
}

static int egl_create(gl_ctx *c, gale_err *err)
{
    EGLDisplay d = egl_open_display();
    if (d == EGL_NO_DISPLAY) {
        return gale_errf(err, GALE_E_STATE, "gl_ctx: no EGL device or surfaceless display");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        eglTerminate(d);
        return gale_errf(err, GALE_E_STATE, "gl_ctx: EGL cannot bind the OpenGL API");
    }
    const EGLint cfg_attr[] = { EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                EGL_OPENGL_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8,
                                EGL_BLUE_SIZE, 8, EGL_NONE };
    EGLConfig cfg = NULL;
    EGLint ncfg = 0;
    if (!eglChooseConfig(d, cfg_attr, &cfg, 1, &ncfg) || ncfg < 1) {
        /* surfaceless displays may expose configs without pbuffer support */
        const EGLint cfg2[] = { EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE };
        if (!eglChooseConfig(d, cfg2, &cfg, 1, &ncfg) || ncfg < 1) {
            cfg = NULL; /* EGL_KHR_no_config_context */
        }
    }
    const EGLint ctx_attr[] = { EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE };
    EGLContext ctx = eglCreateContext(d, cfg, EGL_NO_CONTEXT, ctx_attr);
    if (ctx == EGL_NO_CONTEXT) {
        eglTerminate(d);
        return gale_errf(err, GALE_E_STATE, "gl_ctx: eglCreateContext 3.3 core failed: 0x%x",
                         (unsigned)eglGetError());
    }
    if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        eglDestroyContext(d, ctx);
        eglTerminate(d);
        return gale_errf(err, GALE_E_STATE, "gl_ctx: eglMakeCurrent (no surface) failed: 0x%x",
                         (unsigned)eglGetError());
    }
    c->kind = GL_CTX_EGL;
    c->egl_display = d;
    c->egl_context = ctx;
    return 0;
}

static int glfw_create(gl_ctx *c, int width, int height, bool visible, bool vsync,
                       const char *title, gale_err *err)
{
    glfwSetErrorCallback(glfw_error_cb);
    if (glfw_users == 0 && !glfwInit()) {
        const char *why = NULL;
        glfwGetError(&why);
        return gale_errf(err, GALE_E_STATE, "gl_ctx: glfwInit failed: %s (no display?)",
                         why ? why : "unknown");
    }
    glfw_users++;
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, visible ? 4 : 0);
    GLFWwindow *w = glfwCreateWindow(width, height, title ? title : "gale", NULL, NULL);
    if (!w) {
        const char *why = NULL;
        glfwGetError(&why);
        if (--glfw_users == 0) {
            glfwTerminate();
        }
        return gale_errf(err, GALE_E_STATE, "gl_ctx: cannot create a 3.3 core window: %s",
                         why ? why : "unknown");
    }
    glfwMakeContextCurrent(w);
    glfwSwapInterval(vsync ? 1 : 0);
    c->kind = visible ? GL_CTX_WINDOW : GL_CTX_HIDDEN_WINDOW;
    c->window = w;
    return 0;
}

int gl_ctx_create(gl_ctx *c, int width, int height, bool headless, bool vsync,
                  const char *title, gale_err *err)
{
    memset(c, 0, sizeof *c);
    int rc;
    if (headless) {
        gale_err egl_err = { 0 };
        rc = getenv("GALE_NO_EGL") ? GALE_E_STATE : egl_create(c, &egl_err);
        if (rc < 0) {
            rc = glfw_create(c, width, height, false, false, title, err);
            if (rc < 0) {
                char glfw_msg[256];
                snprintf(glfw_msg, sizeof glfw_msg, "%s", err ? err->msg : "");
                return gale_errf(err, rc, "gl_ctx: headless: EGL: %s; GLFW: %s",
                                 egl_err.msg[0] ? egl_err.msg : "disabled", glfw_msg);
            }
        }
    } else {
        rc = glfw_create(c, width, height, true, vsync, title, err);
        if (rc < 0) {
            return rc;
        }
    }
    if (epoxy_gl_version() < 33) {
        int v = epoxy_gl_version();
        gl_ctx_destroy(c);
        return gale_errf(err, GALE_E_STATE, "gl_ctx: OpenGL 3.3 needed, got %d.%d", v / 10,
                         v % 10);
    }
    const char *rend = (const char *)glGetString(GL_RENDERER);
    snprintf(c->renderer, sizeof c->renderer, "%s", rend ? rend : "?");
    return 0;
}

void gl_ctx_destroy(gl_ctx *c)
{
    if (!c) {
        return;
    }
    if (c->kind == GL_CTX_EGL && c->egl_display) {
        eglMakeCurrent(c->egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(c->egl_display, c->egl_context);
        /* No eglTerminate: the platform display is a per-process singleton that a later
           context reuses, and terminating it unloads the driver under LeakSanitizer,
           which then cannot name (or suppress) the driver's process-lifetime caches. */
        eglReleaseThread();
    } else if (c->window) {
        glfwDestroyWindow(c->window);
        if (--glfw_users == 0) {
            glfwTerminate();
        }
    }
    memset(c, 0, sizeof *c);
}
