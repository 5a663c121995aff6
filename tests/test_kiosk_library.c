/* The kiosk's panel with the shipped library of 25 scenarios (9 steady, 16 replays, in the
 * welcome's order: sorted by file stem). At 1280x720 and 1920x1080 it shows a page at a
 * time: steady winds first, then the replays oldest first, Previous / Next in the last two
 * places; every control at least 44 px each way (WCAG 2.2 AAA target size), none
 * overlapping another, all on screen, the panel no taller than with the 10 buttons of two
 * rows; every scenario on exactly one page; Next and Previous cycle the pages and send
 * nothing; a scenario button on page 2 still names its own scenario. Drawn in GL (with a
 * display) to kiosk_library_<H>_p<N>.png to look at. */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "check.h"
#include "ctl.h"
#include "hud.h"
#include "kiosk_ui.h"
#include "kiosk_ui_draw.h"

/* configs/scenarios/: stem, its "name" (the welcome's title), and whether it replays */
static const struct {
    const char *name, *title;
    bool replay;
} lib[] = {
    { "andrew1992", "Andrew 1992", true },        { "breeze", "Breeze", false },
    { "calm", "Calm", false },                    { "camille1969", "Camille 1969", true },
    { "cat1", "Category 1 (steady)", false },     { "cat2", "Category 2 (steady)", false },
    { "cat3", "Category 3 (steady)", false },     { "cat3-synthetic", "Category 3 (synthetic)", true },
    { "cat4", "Category 4 (steady)", false },     { "cat5", "Category 5 (steady)", false },
    { "charley2004", "Charley 2004", true },      { "gusty", "Gusty afternoon", false },
    { "harvey2017", "Harvey 2017", true },        { "hugo1989", "Hugo 1989", true },
    { "ian2022", "Ian 2022", true },              { "ida2021", "Ida 2021", true },
    { "ike2008", "Ike 2008", true },              { "irma2017", "Irma 2017", true },
    { "katrina2005", "Katrina 2005", true },      { "laborday1935", "Labor Day 1935", true },
    { "laura2020", "Laura 2020", true },          { "maria2017", "Maria 2017", true },
    { "michael2018", "Michael 2018", true },      { "storm", "Tropical storm", false },
    { "wilma2005", "Wilma 2005", true },
};
#define N_LIB ((int)(sizeof lib / sizeof lib[0]))

static void fill(kiosk_ui *ui)
{
    kiosk_ui_init(ui);
    for (int i = 0; i < N_LIB; i++) {
        kiosk_ui_set_scenario(ui, i, lib[i].name, lib[i].title, lib[i].replay);
    }
    kiosk_ui_set_scenario_count(ui, N_LIB);
}

static bool overlap(const kiosk_ui_rect *a, const kiosk_ui_rect *b)
{
    return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

/* Taps the centre of control i; the action. */
static kiosk_ui_action tap(kiosk_ui *ui, int i)
{
    kiosk_ui_action a;
    const kiosk_ui_rect r = ui->c[i].r;
    float x = 0.5f * (r.x0 + r.x1), y = 0.5f * (r.y0 + r.y1);
    kiosk_ui_touch(ui, KIOSK_UI_DOWN, x, y, &a);
    kiosk_ui_touch(ui, KIOSK_UI_UP, x, y, &a);
    return a;
}

static void layout_at(int W, int H)
{
    kiosk_ui ui;
    fill(&ui);
    /* the panel of ten buttons (two rows), the height a page may take */
    kiosk_ui ten;
    kiosk_ui_init(&ten);
    for (int i = 0; i < 10; i++) {
        kiosk_ui_set_scenario(&ten, i, lib[i].name, lib[i].title, lib[i].replay);
    }
    kiosk_ui_set_scenario_count(&ten, 10);
    kiosk_ui_layout(&ten, W, H);
    CHECK(ten.n_pages == 1 && kiosk_ui_find(&ten, KIOSK_UI_PAGE, 1) < 0);

    kiosk_ui_layout(&ui, W, H);
    fprintf(stderr, "  %dx%d: %d pages, panel from y = %.0f (ten buttons: %.0f)\n", W, H,
            ui.n_pages, (double)ui.panel_y0, (double)ten.panel_y0);
    CHECK(ui.n_pages == 3);
    CHECK(ui.panel_y0 >= ten.panel_y0 - 0.5f);
    int seen[N_LIB] = { 0 };
    for (int p = 0; p < ui.n_pages; p++) {
        CHECK(ui.page == p);
        char head[96];
        kiosk_ui_scen_heading(&ui, head, sizeof head);
        CHECK_STR_HAS(head, p == 0 ? "Steady winds" : "Storm replays");
        int n_scen = 0, prev_year = 0;
        for (int i = 0; i < ui.n; i++) {
            const kiosk_ui_control *k = &ui.c[i];
            const kiosk_ui_rect *r = &k->r;
            if (k->kind != KIOSK_UI_DIAL && k->kind != KIOSK_UI_COMPASS) {
                bool big = r->x1 - r->x0 >= 44.0f && r->y1 - r->y0 >= 44.0f;
                if (!big) {
                    fprintf(stderr, "  control %d (kind %d) is %.1f x %.1f px\n", i, k->kind,
                            (double)(r->x1 - r->x0), (double)(r->y1 - r->y0));
                }
                CHECK(big);
            }
            CHECK(r->x0 >= 0.0f && r->y0 >= 0.0f && r->x1 <= (float)W && r->y1 <= (float)H);
            for (int j = 0; j < i; j++) {
                if (overlap(r, &ui.c[j].r)) {
                    fprintf(stderr, "  controls %d and %d overlap\n", i, j);
                }
                CHECK(!overlap(r, &ui.c[j].r));
            }
            if (k->kind == KIOSK_UI_SCENARIO) {
                n_scen++;
                seen[k->index]++;
                CHECK(lib[k->index].replay == (p > 0));
                /* the replays oldest first (an undated one last) */
                const char *t = lib[k->index].title;
                size_t len = strlen(t);
                int y = len > 4 && t[len - 1] >= '0' && t[len - 1] <= '9' ? atoi(t + len - 4)
                                                                          : 9999;
                CHECK(p == 0 || y >= prev_year);
                prev_year = y;
            }
        }
        CHECK(n_scen >= 6);
        int next = kiosk_ui_find(&ui, KIOSK_UI_PAGE, 1);
        CHECK(next >= 0 && kiosk_ui_find(&ui, KIOSK_UI_PAGE, 0) >= 0);
        if (next < 0) {
            return;
        }
        char face[64];
        kiosk_ui_label(&ui, &ui.c[next], face, sizeof face);
        CHECK(!strcmp(face, "Next"));
        if (p == 1) {
            /* a replay on this page names its own scenario: Camille is the second oldest */
            int s = kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 3);
            CHECK(s >= 0);
            if (s >= 0) {
                kiosk_ui_action a = tap(&ui, s);
                CHECK(a.act == KIOSK_UI_ACT_SCENARIO && a.index == 3);
                ctl_msg m;
                CHECK(kiosk_ui_message(&ui, &a, "t", &m) == 0);
                CHECK(!strcmp(m.u.wind.scenario, "camille1969"));
            }
        }
        kiosk_ui_action a = tap(&ui, kiosk_ui_find(&ui, KIOSK_UI_PAGE, 1));
        CHECK(a.act == KIOSK_UI_ACT_PAGE && a.index == (p + 1) % ui.n_pages);
        ctl_msg m;
        CHECK(kiosk_ui_message(&ui, &a, "t", &m) == 1); /* a page turn sends nothing */
    }
    for (int i = 0; i < N_LIB; i++) {
        CHECK(seen[i] == 1);
    }
    /* back round: page 0 again; Previous from there is the last page */
    CHECK(ui.page == 0);
    kiosk_ui_action a = tap(&ui, kiosk_ui_find(&ui, KIOSK_UI_PAGE, 0));
    CHECK(a.act == KIOSK_UI_ACT_PAGE && ui.page == ui.n_pages - 1);
    /* a new list starts again at the first page */
    kiosk_ui_set_scenario_count(&ui, N_LIB);
    kiosk_ui_layout(&ui, W, H);
    CHECK(ui.page == 0);
}

static void test_layout(void)
{
    layout_at(1280, 720);
    layout_at(1920, 1080);
}

static void draw_page(hud *h, int W, int H, int page)
{
    glClearColor(0.45f, 0.62f, 0.85f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    kiosk_ui ui;
    fill(&ui);
    wire_weather w = { .sustained_ms = 47.0f, .dir_from_deg = 100.0f, .replay_speed = 80.0f,
                       .flags = WIRE_WEATHER_STORM };
    snprintf(w.name, sizeof w.name, "Katrina 2005");
    kiosk_ui_set_weather(&ui, &w);
    ui.page = page;
    kiosk_ui_layout(&ui, W, H);
    kiosk_ui_draw(h, &ui);
    uint8_t *rgb = malloc((size_t)W * H * 3), *img = malloc((size_t)W * H * 3);
    CHECK(rgb && img);
    if (rgb && img) {
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);
        for (int y = 0; y < H; y++) {
            memcpy(img + (size_t)y * W * 3, rgb + (size_t)(H - 1 - y) * W * 3, (size_t)W * 3);
        }
        char path[300];
        snprintf(path, sizeof path, GALE_TEST_DIR "/kiosk_library_%d_p%d.png", H, page + 1);
        CHECK(stbi_write_png(path, W, H, 3, img, W * 3) != 0);
        /* the running replay (Katrina, on page 2) lit in the accent, under its top edge */
        int k = kiosk_ui_find(&ui, KIOSK_UI_SCENARIO, 18);
        if (page == 1) {
            CHECK(k >= 0);
        }
        if (k >= 0) {
            const kiosk_ui_rect *r = &ui.c[k].r;
            const uint8_t *p = img + ((size_t)(r->y0 + 0.12f * (r->y1 - r->y0)) * W +
                                      (size_t)(0.5f * (r->x0 + r->x1))) * 3;
            CHECK(p[0] > 220 && p[1] > 160 && p[2] < 120);
        }
    }
    free(rgb);
    free(img);
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
    GLFWwindow *win = glfwCreateWindow(64, 64, "kiosk_library", NULL, NULL);
    CHECK(win != NULL);
    if (!win) {
        return;
    }
    glfwMakeContextCurrent(win);
    static const int size[2][2] = { { 1280, 720 }, { 1920, 1080 } };
    for (int s = 0; s < 2; s++) {
        int W = size[s][0], H = size[s][1];
        gale_err err = { 0 };
        hud *h = hud_create(&(hud_desc){ .px = H >= 1080 ? 22.0f * (float)H / 1080.0f : 18.0f },
                            &err);
        CHECK(h != NULL);
        if (!h) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
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
        for (int p = 0; p < 3; p++) {
            draw_page(h, W, H, p);
        }
        hud_destroy(h);
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(1, &rb);
    }
    glfwDestroyWindow(win);
}

int main(void)
{
    RUN(test_layout);
    RUN(test_draw);
    return check_report();
}
