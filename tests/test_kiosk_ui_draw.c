/* The kiosk's touch panel drawn in GL (client/kiosk/kiosk_ui_draw.c) over a cleared sky at
 * 1280x720, 1920x1080 and 3840x2160, read back: the running scenario's button is lit in the
 * accent, a pressed button is lighter than the others, the dial's band of the streamed
 * wind carries its colour, the band labels and button faces have ink, and the sky above
 * the panel is untouched; drawn again unchanged (from the batch kept on the GPU) it is the
 * same picture, and a new wind redraws it. Writes kiosk_ui_<H>.png (the 4K one halved) to
 * look at. */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "check.h"
#include "hud.h"
#include "kiosk_ui.h"
#include "kiosk_ui_draw.h"

static const char *const titles[10] = { "Calm",         "Gusty afternoon", "Tropical storm",
                                        "Cat 1 steady", "Cat 2 steady",    "Cat 3 steady",
                                        "Cat 4 steady", "Cat 5 steady",    "Andrew 1992",
                                        "Charley 2004" };

static const uint8_t *px_at(const uint8_t *img, int w, float x, float y)
{
    return img + ((size_t)(int)y * (size_t)w + (size_t)(int)x) * 3;
}

static void draw_at(int W, int H)
{
    gale_err err = { 0 };
    hud *h = hud_create(&(hud_desc){ .px = H >= 1080 ? 22.0f * (float)H / 1080.0f : 18.0f },
                        &err);
    CHECK(h != NULL);
    if (!h) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    GLuint fbo, rb;
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, W, H);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
    CHECK(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    glViewport(0, 0, W, H);
    glClearColor(0.45f, 0.62f, 0.85f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);

    kiosk_ui ui;
    kiosk_ui_init(&ui);
    static const char *const names[10] = { "calm", "gusty", "storm", "cat1", "cat2",
                                           "cat3", "cat4", "cat5", "andrew1992", "charley2004" };
    for (int i = 0; i < 10; i++) {
        kiosk_ui_set_scenario(&ui, i, names[i], titles[i], i >= 8);
    }
    kiosk_ui_set_scenario_count(&ui, 10);
    wire_weather w = { .sustained_ms = 57.4f, .dir_from_deg = 120.0f, .replay_speed = 50.0f,
                       .flags = WIRE_WEATHER_STORM };
    snprintf(w.name, sizeof w.name, "Andrew 1992");
    kiosk_ui_set_weather(&ui, &w);
    kiosk_ui_layout(&ui, W, H);
    ui.pressed = kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 0); /* a finger on "Calm" */
    kiosk_ui_draw(h, &ui);

    uint8_t *rgb = malloc((size_t)W * H * 3), *img = malloc((size_t)W * H * 3);
    CHECK(rgb && img);
    if (!rgb || !img) {
        free(rgb);
        free(img);
        hud_destroy(h);
        return;
    }
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    CHECK(glGetError() == GL_NO_ERROR);
    for (int y = 0; y < H; y++) {
        memcpy(img + (size_t)y * W * 3, rgb + (size_t)(H - 1 - y) * W * 3, (size_t)W * 3);
    }
    char path[300];
    snprintf(path, sizeof path, GALE_TEST_DIR "/kiosk_ui_%d.png", H);
    if (W > 2000) { /* halved, to look at */
        int w2 = W / 2, h2 = H / 2;
        for (int y = 0; y < h2; y++) {
            for (int x = 0; x < w2; x++) {
                for (int k = 0; k < 3; k++) {
                    const uint8_t *a = img + ((size_t)(2 * y) * W + 2 * x) * 3 + k;
                    rgb[((size_t)y * w2 + x) * 3 + k] =
                        (uint8_t)((a[0] + a[3] + a[W * 3] + a[W * 3 + 3] + 2) / 4);
                }
            }
        }
        stbi_write_png(path, w2, h2, 3, rgb, w2 * 3);
    } else {
        stbi_write_png(path, W, H, 3, img, W * 3);
    }

    /* a button's fill, just under its top edge, above its text */
    const kiosk_ui_rect *run = &ui.c[kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 8)].r;
    const kiosk_ui_rect *other = &ui.c[kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 1)].r;
    const kiosk_ui_rect *pressed = &ui.c[kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 0)].r;
    float fx = 0.5f * (run->x1 - run->x0), fy = 0.12f * (run->y1 - run->y0);
    const uint8_t *pr = px_at(img, W, run->x0 + fx, run->y0 + fy);
    const uint8_t *po = px_at(img, W, other->x0 + fx, other->y0 + fy);
    const uint8_t *pp = px_at(img, W, pressed->x0 + fx, pressed->y0 + fy + 0.003f * H);
    CHECK(pr[0] > 220 && pr[1] > 160 && pr[2] < 120); /* the running one: accent */
    CHECK(po[0] < 70 && po[1] < 70 && po[2] < 90);    /* the others: dark */
    CHECK(pp[0] > po[0] + 30 && pp[2] > po[2] + 30);  /* pressed: lighter */
    /* the streamed wind's band (Cat 3) in its colour, at full strength */
    float bx, by;
    kiosk_ui_dial_point(&ui, 52.0f, &bx, &by);
    const uint8_t *pb = px_at(img, W, bx, by);
    CHECK(pb[0] > 200 && pb[1] < 110 && pb[2] < 90);
    /* ink: band labels and faces bright on the panel */
    int bright = 0;
    for (int y = (int)ui.panel_y0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            const uint8_t *p = img + ((size_t)y * W + x) * 3;
            bright += p[0] > 225 && p[1] > 225 && p[2] > 215;
        }
    }
    CHECK(bright > W * H / 400);
    /* the sky above the panel and its tab is untouched */
    const uint8_t *ps = px_at(img, W, 0.5f * (float)W, ui.panel_y0 - 0.1f * (float)H);
    CHECK(abs(ps[0] - 115) <= 2 && abs(ps[1] - 158) <= 2 && abs(ps[2] - 217) <= 2);
    /* again, nothing changed: the kept batch, the same picture */
    glClear(GL_COLOR_BUFFER_BIT);
    kiosk_ui_draw(h, &ui);
    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    size_t differ = 0;
    for (int y = 0; y < H; y++) {
        differ += memcmp(rgb + (size_t)(H - 1 - y) * W * 3, img + (size_t)y * W * 3,
                         (size_t)W * 3) != 0;
    }
    CHECK(differ == 0);
    /* held still: the third draw is the kept picture (hud.h), the same to 8-bit rounding */
    for (int k = 0; k < 2; k++) {
        glClear(GL_COLOR_BUFFER_BIT);
        kiosk_ui_draw(h, &ui);
    }
    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    int worst = 0;
    for (int y = 0; y < H; y++) {
        const uint8_t *a = rgb + (size_t)(H - 1 - y) * W * 3, *b = img + (size_t)y * W * 3;
        for (int x = 0; x < W * 3; x++) {
            worst = abs(a[x] - b[x]) > worst ? abs(a[x] - b[x]) : worst;
        }
    }
    CHECK(worst <= 2);
    /* a calmer wind: the needle and the figures move */
    w.sustained_ms = 20.0f;
    kiosk_ui_set_weather(&ui, &w);
    glClear(GL_COLOR_BUFFER_BIT);
    kiosk_ui_draw(h, &ui);
    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    kiosk_ui_dial_point(&ui, 52.0f, &bx, &by);
    pb = rgb + ((size_t)(H - 1 - (int)by) * (size_t)W + (size_t)(int)bx) * 3;
    CHECK(pb[0] < 200); /* Cat 3 is no longer the lit band */
    free(rgb);
    free(img);
    hud_destroy(h);
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &rb);
}

static void test_draw(void)
{
    if (!getenv("DISPLAY") || !glfwInit()) {
        fprintf(stderr, "test_draw: no display, skipped\n");
        return;
    }
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    GLFWwindow *win = glfwCreateWindow(64, 64, "kiosk_ui", NULL, NULL);
    CHECK(win != NULL);
    if (!win) {
        return;
    }
    glfwMakeContextCurrent(win);
    draw_at(1280, 720);
    draw_at(1920, 1080);
    draw_at(3840, 2160);
    glfwDestroyWindow(win);
    /* no glfwTerminate: it unloads the Mesa driver, and LeakSanitizer could then no longer
     * name (and so suppress, tests/lsan.supp) the driver's process-lifetime allocations */
}

int main(void)
{
    RUN(test_draw);
    return check_report();
}
