/* gale-client input: left-drag orbit, right-drag pan, wheel zoom, WASD/QE fly, F11
 * fullscreen, F12 or P screenshot, R reset view, C or the camera button the next camera
 * preset, + / - the kiosk's wind dial, a kiosk's touches on its panel (kiosk_ui.h), Esc
 * quit. */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <time.h>

#include "camera_button.h"
#include "client.h"
#include "mono.h"

void client_input_screenshot_name(char *buf, size_t cap)
{
    time_t t = time(NULL);
    struct tm tm;
    localtime_r(&t, &tm);
    strftime(buf, cap, "gale-%Y%m%d-%H%M%S.png", &tm);
}

void client_input_toggle_fullscreen(client *c, GLFWwindow *win)
{
    if (!c->fullscreen) {
        GLFWmonitor *m = glfwGetPrimaryMonitor();
        const GLFWvidmode *mode = m ? glfwGetVideoMode(m) : NULL;
        if (!mode) {
            return;
        }
        glfwGetWindowPos(win, &c->win_pos[0], &c->win_pos[1]);
        glfwGetWindowSize(win, &c->win_size[0], &c->win_size[1]);
        glfwSetWindowMonitor(win, m, 0, 0, mode->width, mode->height, mode->refreshRate);
    } else {
        glfwSetWindowMonitor(win, NULL, c->win_pos[0], c->win_pos[1], c->win_size[0],
                             c->win_size[1], 0);
    }
    c->fullscreen = !c->fullscreen;
}

bool client_input_woke(client *c)
{
    if (!attract_input(&c->attract, mono_s())) {
        return false;
    }
    client_scene_reset_camera(c); /* back from the tour to the kiosk's own view */
    fprintf(stderr, "gale-client: attract mode: woken by a touch\n");
    return true;
}

static void key_cb(GLFWwindow *win, int key, int scancode, int action, int mods)
{
    client *c = glfwGetWindowUserPointer(win);
    (void)scancode;
    (void)mods;
    if (action != GLFW_PRESS || client_input_woke(c)) {
        return;
    }
    switch (key) {
    case GLFW_KEY_ESCAPE:
        glfwSetWindowShouldClose(win, GLFW_TRUE);
        break;
    case GLFW_KEY_F11:
        client_input_toggle_fullscreen(c, win);
        break;
    case GLFW_KEY_F12:
    case GLFW_KEY_P:
        c->want_screenshot = true;
        break;
    case GLFW_KEY_R:
        client_scene_reset_camera(c);
        break;
    case GLFW_KEY_C:
        client_kiosk_camera_next(c);
        break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
        client_kiosk_dial(c, 5.0f);
        break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
        client_kiosk_dial(c, -5.0f);
        break;
    case GLFW_KEY_RIGHT_BRACKET:
        client_audio_volume(c, +1);
        break;
    case GLFW_KEY_LEFT_BRACKET:
        client_audio_volume(c, -1);
        break;
    default:
        break;
    }
}

/* A kiosk's press on its camera button (a touch under GLFW is a left press). */
static bool on_camera_button(client *c, GLFWwindow *win)
{
    if (c->a.role != CTL_ROLE_KIOSK || !c->hud_on) {
        return false;
    }
    int fb_w, fb_h, win_w, win_h;
    double x, y;
    glfwGetFramebufferSize(win, &fb_w, &fb_h);
    glfwGetWindowSize(win, &win_w, &win_h);
    glfwGetCursorPos(win, &x, &y);
    return camera_button_hit(fb_w, fb_h, win_w, win_h, x, y);
}

/* The cursor in framebuffer pixels (a HiDPI framebuffer is larger than the window). */
static void cursor_fb(GLFWwindow *win, double x, double y, float *fx, float *fy)
{
    int fb_w, fb_h, win_w, win_h;
    glfwGetFramebufferSize(win, &fb_w, &fb_h);
    glfwGetWindowSize(win, &win_w, &win_h);
    *fx = win_w > 0 ? (float)(x * fb_w / win_w) : (float)x;
    *fy = win_h > 0 ? (float)(y * fb_h / win_h) : (float)y;
}

/* A kiosk's touch (the left button) on its panel: true when the panel took it. */
static bool panel_touch(client *c, GLFWwindow *win, int phase)
{
    if (c->a.role != CTL_ROLE_KIOSK) {
        return false;
    }
    double x, y;
    float fx, fy;
    glfwGetCursorPos(win, &x, &y);
    cursor_fb(win, x, y, &fx, &fy);
    return client_kiosk_touch(c, phase, fx, fy);
}

static void mouse_cb(GLFWwindow *win, int button, int action, int mods)
{
    client *c = glfwGetWindowUserPointer(win);
    (void)mods;
    if (action == GLFW_PRESS && client_input_woke(c)) {
        return;
    }
    if (action == GLFW_PRESS && button == GLFW_MOUSE_BUTTON_LEFT && on_camera_button(c, win)) {
        client_kiosk_camera_next(c);
        return;
    }
    if (button == GLFW_MOUSE_BUTTON_LEFT &&
        panel_touch(c, win, action == GLFW_PRESS ? KIOSK_UI_DOWN : KIOSK_UI_UP)) {
        c->drag = 0;
        return;
    }
    if (action == GLFW_PRESS) {
        c->drag = button == GLFW_MOUSE_BUTTON_LEFT ? 1 : button == GLFW_MOUSE_BUTTON_RIGHT ? 2 : 0;
        glfwGetCursorPos(win, &c->cursor[0], &c->cursor[1]);
    } else {
        c->drag = 0;
    }
}

static void cursor_cb(GLFWwindow *win, double x, double y)
{
    client *c = glfwGetWindowUserPointer(win);
    if (c->a.role == CTL_ROLE_WALL_TILE) {
        return; /* every tile shows one fixed camera */
    }
    if (kiosk_ui_busy(&c->kiosk)) {
        float fx, fy;
        cursor_fb(win, x, y, &fx, &fy);
        client_kiosk_touch(c, KIOSK_UI_MOVE, fx, fy);
        c->cursor[0] = x;
        c->cursor[1] = y;
        return;
    }
    float dx = (float)(x - c->cursor[0]), dy = (float)(y - c->cursor[1]);
    c->cursor[0] = x;
    c->cursor[1] = y;
    int w, h;
    glfwGetWindowSize(win, &w, &h);
    if (c->drag == 1) {
        camera_orbit(&c->cam, dx, dy);
    } else if (c->drag == 2) {
        camera_pan(&c->cam, dx, dy, h);
    }
}

static void scroll_cb(GLFWwindow *win, double xoff, double yoff)
{
    client *c = glfwGetWindowUserPointer(win);
    (void)xoff;
    if (client_input_woke(c)) {
        return;
    }
    if (c->a.role != CTL_ROLE_WALL_TILE) {
        camera_zoom(&c->cam, (float)yoff);
    }
}

void client_input_fly(client *c, GLFWwindow *win, float dt)
{
    if (c->a.role == CTL_ROLE_WALL_TILE) {
        return;
    }
#define KEY(k) (glfwGetKey(win, (k)) == GLFW_PRESS ? 1.0f : 0.0f)
    float f = KEY(GLFW_KEY_W) - KEY(GLFW_KEY_S);
    float r = KEY(GLFW_KEY_D) - KEY(GLFW_KEY_A);
    float u = KEY(GLFW_KEY_E) - KEY(GLFW_KEY_Q);
#undef KEY
    camera_fly(&c->cam, f, r, u, dt);
}

void client_input_attach(client *c, GLFWwindow *win)
{
    glfwSetWindowUserPointer(win, c);
    glfwSetKeyCallback(win, key_cb);
    glfwSetMouseButtonCallback(win, mouse_cb);
    glfwSetCursorPosCallback(win, cursor_cb);
    glfwSetScrollCallback(win, scroll_cb);
}
