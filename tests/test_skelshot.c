/* gale-skelshot as a program: for each shipped species and a CSV skeleton the PNG it
 * writes is opened and held to the skeleton it draws (the same lsystem_generate or CSV
 * reader): the side (x-z) and top (x-y) views put ink at every node's projection and none
 * outside the projected outline; bad input exits non-zero naming the file and the fault. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include <stb_image.h>

#include "check.h"
#include "lsystem.h"
#include "skeleton.h"
#include "species.h"

#ifndef GALE_SKELSHOT_EXE
#error "GALE_SKELSHOT_EXE (path of gale-skelshot) must be defined by the build"
#endif

enum { SIZE = 240, MARGIN = 30 }; /* --size 240; skelshot_main.c's margin */

/* Runs cmd with stderr and stdout into out; returns the exit status. */
static int run(const char *cmd, char *out, size_t cap)
{
    char full[1400];
    snprintf(full, sizeof full, "%s 2>&1", cmd);
    FILE *p = popen(full, "r");
    size_t n = 0;
    if (p) {
        n = fread(out, 1, cap - 1, p);
    }
    out[n] = '\0';
    int st = p ? pclose(p) : -1;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int ink(const unsigned char *img, int w, int h, int x, int y)
{
    if (x < 0 || y < 0 || x >= w || y >= h) {
        return 0;
    }
    const unsigned char *p = &img[3 * (y * w + x)];
    return abs(p[0] - 250) + abs(p[1] - 250) + abs(p[2] - 246) > 30;
}

/* One view: pixel = origin + (world - centre) x scale on two world axes (y down). */
typedef struct proj {
    double ox, oy, scale, cx, cy;
    int ax, ay;
} proj;

static void to_px(const proj *v, const float *p, double *x, double *y)
{
    *x = v->ox + ((double)p[v->ax] - v->cx) * v->scale;
    *y = v->oy - ((double)p[v->ay] - v->cy) * v->scale;
}

/* Every node's projection has ink within 1 px; no ink in the panel [x0, x0 + SIZE) below
 * the title and above the labels farther than reach_px outside the nodes' bounding box. */
static void check_view(const char *what, const unsigned char *img, int w, int h, const proj *v,
                       const skeleton *s, int x0, double reach_px)
{
    int hit = 0;
    double lo_x = 1e30, lo_y = 1e30, hi_x = -1e30, hi_y = -1e30;
    for (int i = 0; i < s->n; i++) {
        double x, y;
        to_px(v, &s->pos[3 * i], &x, &y);
        lo_x = fmin(lo_x, x);
        hi_x = fmax(hi_x, x);
        lo_y = fmin(lo_y, y);
        hi_y = fmax(hi_y, y);
        int any = 0;
        for (int dy = -1; dy <= 1; dy++) {
            for (int dx = -1; dx <= 1; dx++) {
                any |= ink(img, w, h, (int)lround(x) + dx, (int)lround(y) + dy);
            }
        }
        hit += any;
    }
    int stray = 0, inside = 0;
    for (int y = MARGIN + 4; y < SIZE + MARGIN - 2; y++) {
        for (int x = x0 + 2; x < x0 + SIZE - 2; x++) {
            if (!ink(img, w, h, x, y)) {
                continue;
            }
            int out = x < lo_x - reach_px || x > hi_x + reach_px || y < lo_y - reach_px ||
                      y > hi_y + reach_px;
            stray += out;
            inside += !out;
        }
    }
    fprintf(stderr, "  %s: %d of %d nodes inked, %d px ink inside the outline, %d outside\n",
            what, hit, s->n, inside, stray);
    CHECK(hit == s->n);
    CHECK(inside > 0);
    CHECK(stray <= 20);
}

/* Runs gale-skelshot on --species or --skeleton `arg` and checks its PNG against s. */
static void check_shot(const char *flag, const char *arg, const skeleton *s)
{
    char png[512], cmd[1200], out[4096];
    snprintf(png, sizeof png, "%s/skelshot_%s.png", GALE_TEST_DIR, strrchr(arg, '/') + 1);
    snprintf(cmd, sizeof cmd, "'%s' %s '%s' --size %d --out '%s'", GALE_SKELSHOT_EXE, flag, arg,
             SIZE, png);
    CHECK(run(cmd, out, sizeof out) == 0);
    fprintf(stderr, "%s: %s", arg, out);
    int w = 0, h = 0, ch = 0;
    unsigned char *img = stbi_load(png, &w, &h, &ch, 3);
    CHECK(img != NULL && h == SIZE + 2 * MARGIN && (w == 2 * SIZE || w == 3 * SIZE));
    if (!img || h != SIZE + 2 * MARGIN) {
        stbi_image_free(img);
        return;
    }
    float lo[3] = { 1e30f, 1e30f, 1e30f }, hi[3] = { -1e30f, -1e30f, -1e30f };
    for (int i = 0; i < s->n; i++) {
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], s->pos[3 * i + k]);
            hi[k] = fmaxf(hi[k], s->pos[3 * i + k]);
        }
    }
    double span_side = fmax(fmax((double)(hi[0] - lo[0]), (double)(hi[2] - lo[2])), 1e-3);
    double span_top = fmax(fmax((double)(hi[0] - lo[0]), (double)(hi[1] - lo[1])), 1e-3);
    /* ink reaches past a node by its element's radius and a leaf blade (twice the leaf
       offset, under 1 m for every species) */
    double reach_m = 1.0;
    for (int i = 0; i < s->n; i++) {
        reach_m = fmax(reach_m, 1.0 + (double)s->radius[i]);
    }
    proj side = { .ox = 0.5 * SIZE, .oy = SIZE + MARGIN, .scale = (SIZE - 2 * MARGIN) / span_side,
                  .cx = 0.5 * (double)(lo[0] + hi[0]), .cy = 0.0, .ax = 0, .ay = 2 };
    proj top = { .ox = 1.5 * SIZE, .oy = MARGIN + 0.5 * SIZE, .scale = (SIZE - 2 * MARGIN) / span_top,
                 .cx = 0.5 * (double)(lo[0] + hi[0]), .cy = 0.5 * (double)(lo[1] + hi[1]),
                 .ax = 0, .ay = 1 };
    check_view("side", img, w, h, &side, s, 0, 3.0 + reach_m * side.scale);
    check_view("top", img, w, h, &top, s, SIZE, 3.0 + reach_m * top.scale);
    stbi_image_free(img);
}

static void test_species(void)
{
    static const char *names[] = { "oak", "palm", "pine" };
    for (int i = 0; i < 3; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, names[i]);
        species sp;
        skeleton s = { 0 };
        gale_err err = { 0 };
        species_default(&sp);
        CHECK(species_load(path, &sp, &err) == 0);
        CHECK(lsystem_generate(&sp.gen, &s, &err) == 0);
        check_shot("--species", path, &s);
        skeleton_fini(&s);
    }
}

static void test_csv(void)
{
    const char *path = GALE_SOURCE_DIR "/tests/fuzz/corpus/skeleton_csv/small.csv";
    skeleton s = { 0 };
    gale_err err = { 0 };
    CHECK(skeleton_load_csv(path, &s, &err) == 0);
    check_shot("--skeleton", path, &s);
    skeleton_fini(&s);
}

static void test_bad_input(void)
{
    char cmd[1200], out[4096];
    snprintf(cmd, sizeof cmd, "'%s' --skeleton '%s/tests/fuzz/corpus/skeleton_csv/cycle.csv' "
             "--out '%s/skelshot_bad.png'", GALE_SKELSHOT_EXE, GALE_SOURCE_DIR, GALE_TEST_DIR);
    CHECK(run(cmd, out, sizeof out) == 1);
    CHECK_STR_HAS(out, "cycle.csv: no root: expected one node with parent -1");
    snprintf(cmd, sizeof cmd, "'%s' --species '%s/configs/species/oak.json'", GALE_SKELSHOT_EXE,
             GALE_SOURCE_DIR);
    CHECK(run(cmd, out, sizeof out) == 2);
    CHECK_STR_HAS(out, "gale-skelshot: expected exactly one of --species/--skeleton, and --out");
    snprintf(cmd, sizeof cmd, "'%s' --skeleton x.csv --out y.png --size 9", GALE_SKELSHOT_EXE);
    CHECK(run(cmd, out, sizeof out) == 2);
    CHECK_STR_HAS(out, "gale-skelshot: --size: expected 64..4096, got \"9\"");
    snprintf(cmd, sizeof cmd, "'%s' --skeleton '%s/no_such.csv' --out '%s/skelshot_none.png'",
             GALE_SKELSHOT_EXE, GALE_TEST_DIR, GALE_TEST_DIR);
    CHECK(run(cmd, out, sizeof out) == 1);
    CHECK_STR_HAS(out, "no_such.csv");
}

int main(void)
{
    RUN(test_species);
    RUN(test_csv);
    RUN(test_bad_input);
    return check_report();
}
