/* HUD: text widths against the font's own advance widths, glyph ink against DejaVu Sans'
 * cap height, UTF-8 fallbacks, Saffir–Simpson boundaries in knots, the HUD's lines, and
 * (with a display) the GL pass drawn over a cleared frame and read back. */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>
#include <stb_truetype.h>

#include "check.h"
#include "hud.h"
#include "lang.h"

static hud_font *font36;

/* Independent width: advance widths and kerning read from the font file directly. */
static double ref_width(const char *ascii, float px)
{
    static unsigned char *ttf;
    static stbtt_fontinfo info;
    if (!ttf) {
        FILE *f = fopen(HUD_DEFAULT_FONT, "rb");
        fseek(f, 0, SEEK_END);
        long n = ftell(f);
        fseek(f, 0, SEEK_SET);
        ttf = malloc((size_t)n);
        CHECK(fread(ttf, 1, (size_t)n, f) == (size_t)n);
        fclose(f);
        stbtt_InitFont(&info, ttf, 0);
    }
    double scale = (double)stbtt_ScaleForPixelHeight(&info, px), w = 0.0;
    for (const char *p = ascii; *p; p++) {
        int adv, lsb;
        stbtt_GetCodepointHMetrics(&info, *p, &adv, &lsb);
        w += adv * scale;
        if (p[1]) {
            w += stbtt_GetCodepointKernAdvance(&info, p[0], p[1]) * scale;
        }
    }
    if (!ascii[0]) { /* last call: release */
        free(ttf);
        ttf = NULL;
    }
    return w;
}

static void test_widths(void)
{
    CHECK_NEAR(hud_text_width(font36, ""), 0.0, 0.0);
    const char *samples[] = { "M", "Wind 42.0 m/s", "Category 5 hurricane", "AVATAR Tt Ty",
                              "fps 60 latency 12.5 ms" };
    for (int i = 0; i < 5; i++) {
        /* float advance sums: 1e-3 px per glyph */
        CHECK_NEAR(hud_text_width(font36, samples[i]), ref_width(samples[i], 36.0f), 0.03);
    }
    CHECK_NEAR(hud_text_width(font36, "MMMM"), 4.0 * (double)hud_text_width(font36, "M"), 1e-3);
    CHECK(hud_text_width(font36, "iiii") < hud_text_width(font36, "WWWW"));
    /* DejaVu Sans: 'M' advances 1767/2048 em; px maps ascent − descent = 2384 units */
    CHECK_NEAR(hud_text_width(font36, "M"), 1767.0 * 36.0 / 2384.0, 0.01);
    /* outside the atlas and malformed UTF-8: drawn as '?' */
    float q = hud_text_width(font36, "?");
    CHECK_NEAR(hud_text_width(font36, "\xE4\xB8\xAD"), q, 1e-4); /* U+4E2D */
    CHECK_NEAR(hud_text_width(font36, "\xFF"), q, 1e-4);
    CHECK_NEAR(hud_text_width(font36, "\xC2"), q, 1e-4); /* truncated sequence */
    /* in the atlas: middle dot, en dash, degree */
    CHECK(hud_text_width(font36, "\xC2\xB7") < q);
    CHECK(hud_text_width(font36, "\xE2\x80\x93") > 0.0f);
    CHECK(hud_text_width(font36, "\xC2\xB0") > 0.0f);
    float asc, desc, gap;
    hud_font_metrics(font36, &asc, &desc, &gap);
    CHECK_NEAR(asc - desc, 36.0, 1e-3);
}

/* Rasterise quads into a CPU image (nearest atlas texel) and measure the ink. */
static void test_ink(void)
{
    enum { W = 640, H = 80 };
    static uint8_t img[W * H];
    memset(img, 0, sizeof img);
    hud_quad quads[64];
    const char *text = "HHHH Wind";
    float pen;
    uint32_t n = hud_text_quads(font36, 10.0f, 50.0f, text, quads, 64, &pen);
    CHECK(n == 8); /* the space makes no quad */
    CHECK_NEAR(pen - 10.0f, hud_text_width(font36, text), 1e-4);
    int aw, ah;
    const uint8_t *atlas = hud_font_atlas(font36, &aw, &ah);
    for (uint32_t i = 0; i < n; i++) {
        const hud_quad *g = &quads[i];
        for (int y = (int)g->y0; y < (int)g->y1 + 1; y++) {
            for (int x = (int)g->x0; x < (int)g->x1 + 1; x++) {
                float u = ((float)x + 0.5f - g->x0) / (g->x1 - g->x0);
                float v = ((float)y + 0.5f - g->y0) / (g->y1 - g->y0);
                if (u < 0 || u >= 1 || v < 0 || v >= 1 || x < 0 || x >= W || y < 0 || y >= H) {
                    continue;
                }
                int s = (int)((g->s0 + u * (g->s1 - g->s0)) * (float)aw);
                int t = (int)((g->t0 + v * (g->t1 - g->t0)) * (float)ah);
                uint8_t c = atlas[t * aw + s];
                if (c > img[y * W + x]) {
                    img[y * W + x] = c;
                }
            }
        }
    }
    int top = H, bottom = -1, left = W, right = -1;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            if (img[y * W + x] > 128) {
                top = y < top ? y : top;
                bottom = y > bottom ? y : bottom;
                left = x < left ? x : left;
                right = x > right ? x : right;
            }
        }
    }
    /* 'H' stands on the baseline (y = 50) and is cap height tall: DejaVu Sans capHeight
     * 1493 units of 2384 → 22.5 px at 36 px; ±1.5 px for sampling and oversampling */
    CHECK_NEAR(bottom + 1, 50, 1.5);
    CHECK_NEAR(bottom + 1 - top, 1493.0 * 36.0 / 2384.0, 1.5);
    /* ink spans the text minus side bearings: within 4 px of the pen advance */
    CHECK_NEAR(right + 1 - left, hud_text_width(font36, text), 6.0);
    CHECK(left >= 10 && left <= 14);
    stbi_write_png(GALE_TEST_DIR "/hud_ink.png", W, H, 1, img, W);
}

static void test_saffir_simpson(void)
{
    const double kt = 0.514444;
    /* class boundaries of server/PHYSICS.md "Hurricanes", in knots */
    const int lo[7] = { 0, 34, 64, 83, 96, 113, 137 };
    for (int c = 0; c < 7; c++) {
        CHECK(hud_saffir_simpson((float)(lo[c] * kt)) == c - 1);
        if (c > 0) {
            CHECK(hud_saffir_simpson((float)((lo[c] - 1) * kt)) == c - 2);
        }
    }
    CHECK(hud_saffir_simpson(0.0f) == -1);
    CHECK(hud_saffir_simpson(-5.0f) == -1);
    CHECK(hud_saffir_simpson(NAN) == -1);
    CHECK(hud_saffir_simpson(82.0f) == 5); /* Andrew's 160 kt class */
    CHECK(strcmp(hud_category_name(3), "Category 3 hurricane") == 0);
    CHECK(strcmp(hud_category_name(-1), "Tropical depression") == 0);
    CHECK(strcmp(hud_category_name(9), "?") == 0);
}

/* Beaufort forces at the WMO limits (a limit itself belongs to its force, 0.1 m/s above
 * to the next), and the names the HUD shows below tropical-storm strength. */
static void test_beaufort(void)
{
    const float upper[12] = { 0.2f, 1.5f, 3.3f, 5.4f, 7.9f, 10.7f,
                              13.8f, 17.1f, 20.7f, 24.4f, 28.4f, 32.6f };
    for (int b = 0; b < 12; b++) {
        CHECK(hud_beaufort(upper[b]) == b);
        CHECK(hud_beaufort(upper[b] + 0.1f) == b + 1);
    }
    CHECK(hud_beaufort(0.0f) == 0);
    CHECK(hud_beaufort(-3.0f) == 0);
    CHECK(hud_beaufort(NAN) == 0);
    CHECK(hud_beaufort(70.0f) == 12);
    CHECK(strcmp(hud_beaufort_name(6), "Strong breeze") == 0);
    CHECK(strcmp(hud_beaufort_name(13), "?") == 0);
    char lines[HUD_MAX_LINES][HUD_LINE_CHARS];
    hud_state s = { .have_wind = true, .wind_ms = 9.1f, .conn = HUD_CONN_LIVE };
    CHECK(hud_format(&s, lines) >= 2);
    CHECK_STR_HAS(lines[1], "Fresh breeze \xC2\xB7 Beaufort 5");
    s.wind_ms = 17.0f; /* 33 kt: still below tropical-storm strength */
    hud_format(&s, lines);
    CHECK_STR_HAS(lines[1], "Near gale \xC2\xB7 Beaufort 7");
    s.wind_ms = 17.5f; /* 34 kt */
    hud_format(&s, lines);
    CHECK_STR_HAS(lines[1], "Tropical storm");
}

static void test_format(void)
{
    char lines[HUD_MAX_LINES][HUD_LINE_CHARS];
    hud_state s = { .have_wind = true,
                    .wind_ms = 50.0f,
                    .conn = HUD_CONN_LIVE,
                    .server = "127.0.0.1:9000",
                    .fps = 59.6f,
                    .latency_ms = 3.25f,
                    .delay_ms = 100.0f,
                    .role = "kiosk" };
    int n = hud_format(&s, lines);
    CHECK(n == 4);
    /* 50 m/s = 180 km/h = 111.85 mph = 97.2 kt (Category 3): mph first in English */
    CHECK_STR_HAS(lines[0], "Wind 112 mph \xC2\xB7 180 km/h");
    CHECK_STR_HAS(lines[1], "Category 3 hurricane");
    CHECK_STR_HAS(lines[2], "Live \xC2\xB7 127.0.0.1:9000 \xC2\xB7 kiosk");
    CHECK_STR_HAS(lines[3], "60 fps \xC2\xB7 latency 3.2 ms \xC2\xB7 delay 100 ms");
    /* a rate not measured yet reads as a dash, not "0 fps" */
    s.fps = 0.0f;
    n = hud_format(&s, lines);
    CHECK_STR_HAS(lines[3], "\xE2\x80\x93 fps \xC2\xB7 latency 3.2 ms");
    /* a slow software renderer's rate keeps its tenths */
    s.fps = 0.44f;
    n = hud_format(&s, lines);
    CHECK_STR_HAS(lines[3], "0.4 fps \xC2\xB7 latency 3.2 ms");
    s.fps = 59.6f;
    s.conn = HUD_CONN_RECONNECTING;
    s.attempt = 3;
    s.retry_in_s = 1.5;
    s.frames_bad = 2;
    s.have_wind = false;
    s.latency_ms = -1.0f;
    n = hud_format(&s, lines);
    CHECK(n == 4);
    CHECK_STR_HAS(lines[0], "no wind data");
    CHECK_STR_HAS(lines[1], "Server lost \xC2\xB7 retry 3 in 1.5 s");
    CHECK_STR_HAS(lines[2], "latency \xE2\x80\x93");
    CHECK_STR_HAS(lines[3], "2 bad frames dropped");
    /* every character a visitor may read is one the font bakes: the governor's step too */
    s.detail_step = 2;
    s.conn = HUD_CONN_LIVE;
    s.have_wind = true;
    n = hud_format(&s, lines);
    CHECK_STR_HAS(lines[3], "detail \xE2\x88\x92" "2");
    for (int i = 0; i < n; i++) {
        CHECK(hud_font_has(lines[i]));
    }
    CHECK(!hud_font_has("\xE2\x86\x92")); /* an arrow is not baked: the check can tell */
    /* and every text of every language (configs/lang): Spanish's ñ ¿, Creole's ò */
    int texts = 0;
    for (int l = 0; l < LANG_COUNT; l++) {
        for (int k = 0; k < L_KEY_COUNT; k++) {
            if (!hud_font_has(lang_text(l, k))) {
                fprintf(stderr, "%s %s: not every character is baked: %s\n", lang_code(l),
                        lang_text(LANG_EN, k), lang_text(l, k));
                CHECK(0);
            }
            texts++;
        }
    }
    CHECK(texts == LANG_COUNT * L_KEY_COUNT);
    /* the same HUD in Spanish: km/h first, its words */
    s.lang = LANG_ES;
    s.wind_ms = 50.0f;
    s.detail_step = 0;
    hud_format(&s, lines);
    CHECK_STR_HAS(lines[0], "Viento 180 km/h \xC2\xB7 112 mph");
    CHECK_STR_HAS(lines[1], "Hurac\xC3\xA1n de categor\xC3\xAD" "a 3");
    CHECK_STR_HAS(lines[2], "En directo");
    /* a reduced view (CLIENT.md): a line under the rates, in the visitor's language */
    s.trees_held = 20000;
    s.trees_scene = 100000;
    n = hud_format(&s, lines);
    CHECK(n == 6); /* the bad frames' line after it */
    CHECK_STR_HAS(lines[4], "Vista reducida: los 20000 \xC3\xA1rboles m\xC3\xA1s cercanos de 100000");
    s.lang = LANG_EN;
    hud_format(&s, lines);
    CHECK_STR_HAS(lines[4], "Reduced view: the 20000 nearest of 100000 trees");
    s.trees_held = s.trees_scene = 0; /* the whole scene held: no line */
    CHECK(hud_format(&s, lines) == 5);
}

/* A steady scenario's title is shown until a kiosk dials: then the dial's wind is what
 * blows, and "Calm" under "Category 2 hurricane" would contradict it. */
static void test_format_dialled(void)
{
    char lines[HUD_MAX_LINES][HUD_LINE_CHARS];
    wire_weather wx = { .sustained_ms = 45.0f, .gust_ms = 45.0f, .dir_from_deg = 270.0f,
                        .ss_class = 4, .beaufort = 12 };
    snprintf(wx.name, sizeof wx.name, "Calm");
    hud_state s = { .wx = &wx, .conn = HUD_CONN_LIVE, .server = "127.0.0.1:9000",
                    .role = "viewer" };
    int n = hud_format(&s, lines);
    int named = 0;
    for (int i = 0; i < n; i++) {
        named += strcmp(lines[i], "Calm") == 0;
    }
    CHECK(named == 1);
    wx.flags |= WIRE_WEATHER_DIAL;
    n = hud_format(&s, lines);
    named = 0;
    for (int i = 0; i < n; i++) {
        named += strcmp(lines[i], "Calm") == 0;
    }
    CHECK(named == 0);
    CHECK_STR_HAS(lines[2], "dialled at the kiosk");
}

static void test_bad_font(void)
{
    gale_err err = { 0 };
    CHECK(hud_font_load("/nonexistent/x.ttf", 18.0f, &err) == NULL);
    CHECK_STR_HAS(err.msg, "/nonexistent/x.ttf: cannot open font");
    CHECK(hud_font_load(GALE_SOURCE_DIR "/CMakeLists.txt", 18.0f, &err) == NULL);
    CHECK_STR_HAS(err.msg, "CMakeLists.txt: not a TrueType font");
    CHECK(hud_font_load(HUD_DEFAULT_FONT, 0.5f, &err) == NULL);
    CHECK_STR_HAS(err.msg, "expected 4..200 px, got 0.5");
    hud_font_unload(NULL);
}

/* GL pass over a cleared frame: the panel darkens its rectangle, text is bright inside
 * it, and nothing outside the panel changes. */
/* hud_draw over a cleared W x H frame, read back (rows bottom up) into rgb. */
static void draw_read(hud *h, const hud_state *s, int W, int H, uint8_t *rgb)
{
    glClear(GL_COLOR_BUFFER_BIT);
    hud_draw(h, s, W, H);
    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);
}

/* Largest difference of two pictures in any channel. */
static int worst_diff(const uint8_t *a, const uint8_t *b, size_t n)
{
    int worst = 0;
    for (size_t i = 0; i < n; i++) {
        int d = abs((int)a[i] - (int)b[i]);
        worst = d > worst ? d : worst;
    }
    return worst;
}

/* s drawn by h three times (the third from the kept picture: hud_batch_flush_keep) into b,
 * and once by a fresh HUD (drawn straight) into c: the same to 8-bit rounding, and h says
 * it drew the lines s formats. */
static void check_kept(hud *h, const hud_state *s, int W, int H, uint8_t *b, uint8_t *c)
{
    for (int i = 0; i < 3; i++) {
        draw_read(h, s, W, H, b);
    }
    char want[HUD_MAX_LINES][HUD_LINE_CHARS], got[HUD_MAX_LINES][HUD_LINE_CHARS];
    int n_want = hud_format(s, want), n_got = hud_drawn_lines(h, got);
    CHECK(n_got == n_want);
    for (int i = 0; i < n_got && i < n_want; i++) {
        CHECK(strcmp(got[i], want[i]) == 0);
    }
    gale_err err = { 0 };
    hud *fresh = hud_create(&(hud_desc){ .px = 20.0f }, &err);
    CHECK(fresh != NULL);
    if (fresh) {
        draw_read(fresh, s, W, H, c);
        CHECK(worst_diff(b, c, (size_t)W * H * 3) <= 2);
        hud_destroy(fresh);
    }
}

/* The lines' panel is kept as a picture while it holds still: the kept picture is the lines
 * drawn straight (premultiplied compositing, to 8-bit rounding) and stays the same frame to
 * frame; after a weather change the picture and the lines it reports are the new ones. */
static void test_kept_lines(hud *h, const hud_state *calm, int W, int H)
{
    const size_t n_px = (size_t)W * (size_t)H * 3;
    uint8_t *a = malloc(n_px), *b = malloc(n_px), *c = malloc(n_px);
    CHECK(a && b && c);
    if (!a || !b || !c) {
        free(a);
        free(b);
        free(c);
        return;
    }
    wire_weather wx = { .sustained_ms = 45.0f, .gust_ms = 58.0f, .dir_from_deg = 200.0f,
                        .ss_class = 3, .beaufort = 12 };
    hud_state storm = *calm;
    storm.wx = &wx;
    check_kept(h, calm, W, H, a, c);
    draw_read(h, calm, W, H, b); /* unchanged: the kept picture again */
    CHECK(memcmp(a, b, n_px) == 0);
    check_kept(h, &storm, W, H, b, c);
    CHECK(memcmp(a, b, n_px) != 0);
    /* a weather change within the same class and wording: only the figures move */
    wx.sustained_ms = 46.0f;
    memcpy(a, b, n_px);
    check_kept(h, &storm, W, H, b, c);
    CHECK(memcmp(a, b, n_px) != 0);
    free(a);
    free(b);
    free(c);
}

static void test_gl_pass(void)
{
    if (!getenv("DISPLAY") || !glfwInit()) {
        fprintf(stderr, "test_gl_pass: no display, GL part skipped\n");
        return;
    }
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    enum { W = 800, H = 300 };
    GLFWwindow *win = glfwCreateWindow(W, H, "hud", NULL, NULL);
    CHECK(win != NULL);
    if (!win) {
        glfwTerminate();
        return;
    }
    glfwMakeContextCurrent(win);
    gale_err err = { 0 };
    hud *h = hud_create(&(hud_desc){ .px = 20.0f }, &err);
    CHECK(h != NULL);
    if (!h) {
        fprintf(stderr, "%s\n", err.msg);
        glfwDestroyWindow(win);
        glfwTerminate();
        return;
    }
    /* offscreen target so the read-back does not depend on the window system */
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
    hud_state s = { .have_wind = true,
                    .wind_ms = 64.0f,
                    .conn = HUD_CONN_LIVE,
                    .server = "127.0.0.1:9000",
                    .fps = 60.0f,
                    .latency_ms = 1.4f,
                    .delay_ms = 100.0f,
                    .role = "viewer" };
    hud_draw(h, &s, W, H);
    static uint8_t rgb[W * H * 3], flipped[W * H * 3];
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    CHECK(glGetError() == GL_NO_ERROR);
    for (int y = 0; y < H; y++) {
        memcpy(flipped + (size_t)y * W * 3, rgb + (size_t)(H - 1 - y) * W * 3, W * 3);
    }
    stbi_write_png(GALE_TEST_DIR "/hud_gl.png", W, H, 3, flipped, W * 3);
    /* panel: from the margin (16 px) to the widest line + padding */
    char lines[HUD_MAX_LINES][HUD_LINE_CHARS];
    int n = hud_format(&s, lines);
    float wmax = 0;
    for (int i = 0; i < n; i++) {
        float w = hud_text_width(hud_get_font(h), lines[i]);
        wmax = w > wmax ? w : wmax;
    }
    int panel_right = (int)(16.0f + wmax + 24.0f);
    int bright = 0, dark = 0, changed_outside = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            const uint8_t *p = flipped + ((size_t)y * W + x) * 3;
            bool inside = x >= 16 && x < panel_right && y >= 16 && y < 150;
            bool sky = abs(p[0] - 115) <= 2 && abs(p[1] - 158) <= 2 && abs(p[2] - 217) <= 2;
            if (!inside && !sky && (x > panel_right + 2 || y > 152)) {
                changed_outside++;
            }
            if (inside && p[0] > 230 && p[1] > 230) {
                bright++;
            }
            if (inside && p[2] < 120) {
                dark++;
            }
        }
    }
    CHECK(changed_outside == 0);
    CHECK(bright > 300);                         /* text ink */
    CHECK(dark > 10000);                         /* the panel */
    CHECK(flipped[(20 * W + 20) * 3 + 2] < 120); /* panel corner darkened */
    test_kept_lines(h, &s, W, H);
    hud_destroy(h);
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &rb);
    glfwDestroyWindow(win);
    /* no glfwTerminate: it unloads the Mesa driver, and LeakSanitizer could then no longer
     * name (and so suppress, tests/lsan.supp) the driver's process-lifetime allocations */
}

int main(void)
{
    gale_err err = { 0 };
    font36 = hud_font_load(HUD_DEFAULT_FONT, 36.0f, &err);
    CHECK(font36 != NULL);
    if (!font36) {
        fprintf(stderr, "%s\n", err.msg);
        return check_report();
    }
    RUN(test_widths);
    RUN(test_ink);
    RUN(test_saffir_simpson);
    RUN(test_beaufort);
    RUN(test_format);
    RUN(test_format_dialled);
    RUN(test_bad_font);
    RUN(test_gl_pass);
    ref_width("", 36.0f);
    hud_font_unload(font36);
    return check_report();
}
