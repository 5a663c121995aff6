/* Scene config: defaults, forest layout (count, spacing, obstacles, determinism) and the
 * exact error text for bad configs (key path, expected, got); no shipped scene carries a
 * kiosk token; the operator's token (file over environment over config) and its limits. */
#include "check.h"
#include "scene.h"

#include <dirent.h>
#include <stdlib.h>

static int parse(scene *s, const char *text, gale_err *e)
{
    return scene_parse(s, "t.json", text, strlen(text), "/base", e);
}

#define SP "\"species\": [{\"name\": \"oak\", \"file\": \"oak.json\"}]"

static void test_defaults(void)
{
    scene s;
    gale_err e;
    CHECK(parse(&s, "{" SP ", \"trees\": [{\"species\": \"oak\", \"pos\": [1, 2]}]}", &e) == 0);
    CHECK_NEAR(s.tick_hz, 60, 0);
    CHECK_NEAR(s.snapshot_hz, 30, 0);
    CHECK(s.tick_threads == 2 && s.tick_rt_priority == 0);
    CHECK(s.n_trees == 1 && s.n_species == 1);
    CHECK_STR_HAS(s.species[0].file, "/base/oak.json");
    CHECK(s.species[0].modes == 32);
    CHECK_NEAR(s.trees[0].pos[0], 1, 0);
    CHECK_NEAR(s.trees[0].pos[1], 2, 0);
    CHECK_NEAR(s.trees[0].scale, 1, 0);
    CHECK(!s.grid_on);
    CHECK(s.kiosk_token[0] == 0);
    scene_fini(&s);
    scene_fini(&s); /* a second fini is a no-op */
}

static void test_forest_spacing(void)
{
    const char *cfg = "{" SP ", \"obstacles\": [{\"min\": [-5, -5, 0], \"max\": [5, 5, 6]}],"
                      "\"trees\": [{\"species\": \"oak\", \"pos\": [20, 20], \"yaw_deg\": 90}],"
                      "\"forest\": [{\"species\": \"oak\", \"count\": 400, \"area_min\": [-50, -50],"
                      " \"area_max\": [50, 50], \"min_spacing_m\": 3, \"seed\": 5,"
                      " \"scale\": [0.5, 2]}]}";
    scene a, b;
    gale_err e;
    CHECK(parse(&a, cfg, &e) == 0);
    CHECK(parse(&b, cfg, &e) == 0);
    CHECK(a.n_trees == 401);
    CHECK_NEAR(a.trees[0].yaw_rad, 1.5707963, 1e-6);
    double dmin = 1e9;
    int in_box = 0, out_area = 0, bad_scale = 0;
    for (int i = 0; i < a.n_trees; i++) {
        const float *p = a.trees[i].pos;
        in_box += p[0] >= -5 && p[0] <= 5 && p[1] >= -5 && p[1] <= 5;
        out_area += i > 0 && (p[0] < -50 || p[0] > 50 || p[1] < -50 || p[1] > 50);
        bad_scale += i > 0 && (a.trees[i].scale < 0.5f || a.trees[i].scale > 2.0f);
        for (int j = 0; j < i; j++) {
            double dx = p[0] - a.trees[j].pos[0], dy = p[1] - a.trees[j].pos[1];
            double d = sqrt(dx * dx + dy * dy);
            dmin = d < dmin ? d : dmin;
        }
    }
    CHECK(dmin >= 3.0 - 1e-4);
    CHECK(in_box == 0 && out_area == 0 && bad_scale == 0);
    CHECK(!memcmp(a.trees, b.trees, sizeof *a.trees * (size_t)a.n_trees)); /* same seed */
    scene_fini(&a);
    scene_fini(&b);
}

static void check_err(const char *text, const char *want)
{
    scene s;
    gale_err e = { 0 };
    int rc = parse(&s, text, &e);
    CHECK(rc < 0);
    CHECK(s.trees == NULL);
    CHECK_STR_HAS(e.msg, want);
}

static void test_errors(void)
{
    check_err("{" SP ", \"tick_hz\": 0, \"trees\": [{\"species\": \"oak\", \"pos\": [0,0]}]}",
              "t.json: tick_hz: expected a number in [1, 1000], got 0");
    check_err("{" SP ", \"tik_hz\": 5}", "tik_hz");
    check_err("{" SP ", \"tick_rt_priority\": 100, \"trees\": [{\"species\": \"oak\", "
              "\"pos\": [0,0]}]}",
              "t.json: tick_rt_priority: expected an integer in [0, 99], got 100");
    check_err("{" SP ", \"trees\": [{\"species\": \"elm\", \"pos\": [0,0]}]}",
              "trees[0].species: expected one of the names in species[], got \"elm\"");
    check_err("{" SP ", \"trees\": [{\"species\": \"oak\", \"pos\": \"x\"}]}", "trees[0].pos");
    check_err("{" SP ", \"trees\": []}", "expected 1 to 200000 trees in all, got 0");
    check_err("{" SP ", \"forest\": [{\"species\": \"oak\", \"count\": 500, \"area_min\": [0,0],"
              " \"area_max\": [10,10], \"min_spacing_m\": 5}]}",
              "forest[0]: placed only");
    check_err("{" SP ", \"snapshot_hz\": 90, \"trees\": [{\"species\": \"oak\", \"pos\": [0,0]}]}",
              "snapshot_hz: expected <= tick_hz (60), got 90");
    check_err("{" SP ", \"obstacles\": [{\"min\": [0,0,0], \"max\": [1,1,-1]}],"
              " \"trees\": [{\"species\": \"oak\", \"pos\": [0,0]}]}",
              "obstacles[0].max[2]: expected > min[2] (0), got -1");
    check_err("{" SP ", \"wind\": 3, \"trees\": [{\"species\": \"oak\", \"pos\": [0,0]}]}",
              "wind: expected an object, got a number");
    check_err("{\"species\": [], \"trees\": []}", "species: expected 1 to 16 entries, got 0");
    check_err("{\"species\": [{\"name\": \"a\", \"file\": \"f\", \"modes\": 65}]}",
              "species[0].modes: expected an integer in [1, 64], got 65");
    check_err("{" SP ",\n \"trees\": [", "t.json:2:");
    /* a playlist: names, 1..32 of them, and not beside a scenario */
    check_err("{" SP ", \"playlist\": [], \"trees\": [{\"species\": \"oak\", \"pos\": [0,0]}]}",
              "t.json: playlist: expected 1..32 scenario names, got 0");
    check_err("{" SP ", \"playlist\": [\"calm\", 3], \"trees\": [{\"species\": \"oak\", \"pos\": [0,0]}]}",
              "t.json: playlist[1]: expected a scenario name of 1..63 bytes");
    check_err("{" SP ", \"playlist\": [\"calm\"], \"scenario\": \"x.json\", \"trees\": [{\"species\": "
              "\"oak\", \"pos\": [0,0]}]}",
              "t.json: scenario: not used with a playlist");
    /* NULL err: still fails cleanly */
    scene s;
    CHECK(scene_parse(&s, "t", "{\"wind\": 1}", 11, NULL, NULL) < 0);
}

#define TREE "\"trees\": [{\"species\": \"oak\", \"pos\": [0,0]}]"

/* Nothing but JSON whitespace may follow the object: a second object, stray text or a
 * NUL is refused at its line:col, whitespace is not. */
static void test_trailing_bytes(void)
{
    check_err("{" SP ", " TREE "}\n}", "t.json:2:1: trailing bytes after the JSON object: "
                                       "expected the end of the file");
    check_err("{" SP ", " TREE "}\n\n  {" SP ", " TREE "}\n",
              "t.json:3:3: trailing bytes after the JSON object: expected the end of the file");
    check_err("{" SP ", " TREE "} x", "t.json:1:");
    const char nul[] = "{" SP ", " TREE "}\n";
    scene s;
    gale_err e = { 0 };
    CHECK(scene_parse(&s, "t.json", nul, sizeof nul, "/base", &e) == GALE_E_PARSE);
    CHECK_STR_HAS(e.msg, "t.json:2:1: trailing bytes after the JSON object");
    CHECK(s.trees == NULL);
    CHECK(parse(&s, "\n {" SP ", " TREE "} \t\r\n \n", &e) == 0);
    CHECK(s.n_trees == 1);
    scene_fini(&s);
}

/* Sizes refused at validation, before anything is allocated: the wind grid's cells and
 * trees x modes against the largest frame a client accepts. */
static void test_size_limits(void)
{
    check_err("{" SP ", \"wind\": {\"grid\": [1024, 1024, 1024]}, " TREE "}",
              "t.json: wind.grid: 1024 x 1024 x 1024 = 1073741824 cells, about 60 GiB at 60 "
              "bytes a cell: expected at most 16777216 cells (0.938 GiB)");
    check_err("{" SP ", \"wind\": {\"grid\": [1024, 1024, 17]}, " TREE "}",
              "t.json: wind.grid: 1024 x 1024 x 17 = 17825792 cells, about 0.996 GiB at 60 "
              "bytes a cell: expected at most 16777216 cells (0.938 GiB)");
    scene s;
    gale_err e = { 0 };
    CHECK(parse(&s, "{" SP ", \"wind\": {\"grid\": [1024, 1024, 16]}, " TREE "}", &e) == 0);
    CHECK(s.grid[0] * s.grid[1] * s.grid[2] == SCENE_MAX_GRID_CELLS);
    scene_fini(&s);
    /* 200 000 trees at 64 modes: about 30 MB of keyframe; at 32 modes they fit */
#define MANY(modes)                                                                           \
    "{\"species\": [{\"name\": \"a\", \"file\": \"a.json\", \"modes\": 8},"                   \
    " {\"name\": \"oak\", \"file\": \"oak.json\", \"modes\": " #modes "}],"                     \
    " \"forest\": [{\"species\": \"oak\", \"count\": 200000, \"area_min\": [0, 0],"             \
    " \"area_max\": [2000, 2000]}]}"
    check_err(MANY(64), "t.json: species[1].modes: 200000 trees x 64 modes: a keyframe may "
                        "take 31800561 bytes: expected at most 16777216 (the largest frame a "
                        "client accepts); fewer trees or modes");
    CHECK(parse(&s, MANY(32), &e) == 0);
    CHECK(s.n_trees == 200000);
    scene_fini(&s);
#undef MANY
}

/* The two scenes hold the same content: every field, every tree, every box (the scenario
 * path may differ only in how it is resolved, so its file name is compared). */
static void check_same_scene(const scene *a, const scene *b)
{
    CHECK(!strcmp(a->name, b->name));
    CHECK(a->tick_hz == b->tick_hz && a->snapshot_hz == b->snapshot_hz);
    CHECK(a->wind_every == b->wind_every && a->grid_on == b->grid_on);
    CHECK(!memcmp(a->grid, b->grid, sizeof a->grid) && a->cell_m == b->cell_m);
    CHECK(!memcmp(a->origin, b->origin, sizeof a->origin));
    CHECK(a->wind_dir_deg == b->wind_dir_deg && a->wind_u10_ms == b->wind_u10_ms);
    CHECK(a->leaf_rate_hz == b->leaf_rate_hz && a->leaf_calm_ms == b->leaf_calm_ms &&
          a->leaf_ref_ms == b->leaf_ref_ms && a->leaf_seed == b->leaf_seed);
    const char *sa = strrchr(a->scenario, '/'), *sb = strrchr(b->scenario, '/');
    CHECK(a->scenario[0] ? sa && sb && !strcmp(sa, sb) : !b->scenario[0]);
    CHECK(a->n_playlist == b->n_playlist);
    for (int i = 0; i < a->n_playlist && i < b->n_playlist; i++) {
        CHECK(!strcmp(a->playlist[i], b->playlist[i]));
    }
    CHECK(a->n_species == b->n_species);
    for (int i = 0; i < a->n_species && i < b->n_species; i++) {
        CHECK(!strcmp(a->species[i].name, b->species[i].name));
        CHECK(a->species[i].modes == b->species[i].modes);
    }
    CHECK(a->n_obstacles == b->n_obstacles && a->n_trees == b->n_trees);
    if (a->n_obstacles == b->n_obstacles) {
        CHECK(!memcmp(a->obstacles, b->obstacles, (size_t)a->n_obstacles * sizeof *a->obstacles));
    }
    if (a->n_trees == b->n_trees) {
        CHECK(!memcmp(a->trees, b->trees, (size_t)a->n_trees * sizeof *a->trees));
    }
}

/* The built-in scene is configs/scenes/default.json: its content pinned here (the town
 * block of five houses and three seeded forests), and the file on disk parses to the same
 * scene field by field. */
static void test_default_scene(void)
{
    scene s, f;
    gale_err e = { 0 };
    int rc = scene_load_default(&s, NULL, &e);
    if (rc) {
        fprintf(stderr, "default scene: %s\n", e.msg);
    }
    CHECK(rc == 0);
    CHECK(!strcmp(s.name, "town-block"));
    CHECK_NEAR(s.tick_hz, 60, 0);
    CHECK_NEAR(s.snapshot_hz, 30, 0);
    CHECK(s.grid_on && s.grid[0] == 48 && s.grid[1] == 48 && s.grid[2] == 12);
    CHECK_NEAR(s.cell_m, 2.5, 0);
    CHECK_NEAR(s.origin[0], -60, 0);
    CHECK_NEAR(s.origin[1], -60, 0);
    CHECK(s.wind_every == 4);
    /* the kiosk's attract loop: the gusty afternoon, then Andrew and Charley */
    CHECK(s.scenario[0] == 0 && s.n_playlist == 3);
    CHECK(!strcmp(s.playlist[0], "gusty") && !strcmp(s.playlist[1], "andrew1992") &&
          !strcmp(s.playlist[2], "charley2004"));
    CHECK(s.n_species == 3 && !strcmp(s.species[0].name, "oak") &&
          !strcmp(s.species[1].name, "palm") && !strcmp(s.species[2].name, "pine"));
    CHECK(s.species[0].modes == 32 && s.species[1].modes == 24 && s.species[2].modes == 32);
    CHECK(s.n_obstacles == 5);
    if (s.n_obstacles == 5) {
        CHECK_NEAR(s.obstacles[1].min[0], -5, 0);
        CHECK_NEAR(s.obstacles[4].max[2], 9, 0);
    }
    /* the explicit oak, then 70 of each forest (the spacing lets all of them stand) */
    CHECK(s.n_trees == 211);
    if (s.n_trees > 0) {
        CHECK(s.trees[0].species == 0 && s.trees[0].pos[0] == 0.0f && s.trees[0].pos[1] == 0.0f);
        CHECK_NEAR(s.trees[0].scale, 1.2, 1e-6);
    }
    int per[3] = { 0 };
    for (int i = 1; i < s.n_trees; i++) {
        per[s.trees[i].species < 3 ? s.trees[i].species : 0]++;
        CHECK(fabsf(s.trees[i].pos[0]) <= 58.0f && fabsf(s.trees[i].pos[1]) <= 58.0f);
        /* palms in the south half, pines in the north (their forests' areas) */
        CHECK(s.trees[i].species != 1 || s.trees[i].pos[1] <= 0.0f);
        CHECK(s.trees[i].species != 2 || s.trees[i].pos[1] >= 0.0f);
    }
    CHECK(per[0] == 70 && per[1] == 70 && per[2] == 70);
    CHECK(s.kiosk_token[0] == 0); /* a kiosk needs the operator's token */
    /* the file on disk parses the same */
    CHECK(scene_load(&f, GALE_SOURCE_DIR "/configs/scenes/default.json", &e) == 0);
    check_same_scene(&s, &f);
    scene_fini(&f);
    scene_fini(&s);
    CHECK(scene_load(&s, "/nonexistent/scene.json", &e) == GALE_E_IO);
    CHECK_STR_HAS(e.msg, "/nonexistent/scene.json: cannot open");
}

/* Every scene shipped in configs/scenes/ leaves kiosks off: a token in a public file would
 * let anyone steer the wind. */
static void test_no_shipped_token(void)
{
    DIR *d = opendir(GALE_SOURCE_DIR "/configs/scenes");
    CHECK(d != NULL);
    int files = 0;
    for (struct dirent *de; d && (de = readdir(d));) {
        size_t n = strlen(de->d_name);
        if (n < 6 || strcmp(de->d_name + n - 5, ".json")) {
            continue;
        }
        char path[600];
        snprintf(path, sizeof path, GALE_SOURCE_DIR "/configs/scenes/%s", de->d_name);
        scene s;
        gale_err e = { 0 };
        int rc = scene_load(&s, path, &e);
        if (rc) {
            fprintf(stderr, "%s: %s\n", path, e.msg);
        }
        CHECK(rc == 0);
        if (s.kiosk_token[0]) {
            fprintf(stderr, "%s carries a kiosk token\n", path);
        }
        CHECK(s.kiosk_token[0] == 0);
        scene_fini(&s);
        files++;
    }
    if (d) {
        closedir(d);
    }
    CHECK(files >= 1);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

#define T63 "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789+"
#define AND_TREE ", \"trees\": [{\"species\": \"oak\", \"pos\": [0, 0]}]"

static void test_kiosk_token(void)
{
    scene s;
    gale_err e = { 0 };
    char src[600];
    /* the config's token: 63 bytes are what a hello may carry, 64 are refused */
    CHECK(strlen(T63) == 63);
    CHECK(parse(&s, "{" SP AND_TREE ", \"kiosk_token\": \"" T63 "\"}", &e) == 0);
    CHECK(!strcmp(s.kiosk_token, T63));
    CHECK(scene_kiosk_token_resolve(&s, NULL, NULL, src, sizeof src, &e) == 0);
    CHECK(!strcmp(s.kiosk_token, T63));
    CHECK_STR_HAS(src, "the config's kiosk_token");
    scene_fini(&s);
    check_err("{" SP AND_TREE ", \"kiosk_token\": \"" T63 "x\"}",
              "t.json: kiosk_token: expected at most 63 bytes (what a kiosk's hello may carry), "
              "got 64");
    check_err("{" SP AND_TREE ", \"kiosk_token\": 5}", "t.json: kiosk_token: expected a string");

    /* no token anywhere: kiosks off, source "" */
    CHECK(parse(&s, "{" SP AND_TREE "}", &e) == 0);
    CHECK(scene_kiosk_token_resolve(&s, NULL, "", src, sizeof src, &e) == 0);
    CHECK(s.kiosk_token[0] == 0 && src[0] == 0);
    /* the environment over the config */
    scene_fini(&s);
    CHECK(parse(&s, "{" SP AND_TREE ", \"kiosk_token\": \"cfg\"}", &e) == 0);
    CHECK(scene_kiosk_token_resolve(&s, NULL, "from-env", src, sizeof src, &e) == 0);
    CHECK(!strcmp(s.kiosk_token, "from-env"));
    CHECK(!strcmp(src, SCENE_KIOSK_TOKEN_ENV));
    /* the file over both: its first line, without "\n" or "\r\n" */
    write_file("kiosk_token_a.txt", "from-file\nsecond line\n");
    CHECK(scene_kiosk_token_resolve(&s, "kiosk_token_a.txt", "from-env", src, sizeof src, &e) ==
          0);
    CHECK(!strcmp(s.kiosk_token, "from-file"));
    CHECK(!strcmp(src, "kiosk token file kiosk_token_a.txt"));
    write_file("kiosk_token_b.txt", " spaced token \r\n");
    CHECK(scene_kiosk_token_resolve(&s, "kiosk_token_b.txt", NULL, NULL, 0, &e) == 0);
    CHECK(!strcmp(s.kiosk_token, " spaced token "));
    write_file("kiosk_token_c.txt", T63); /* no newline at all */
    CHECK(scene_kiosk_token_resolve(&s, "kiosk_token_c.txt", NULL, NULL, 0, &e) == 0);
    CHECK(!strcmp(s.kiosk_token, T63));
    /* failures name the file or the variable and leave the token as it was */
    write_file("kiosk_token_long.txt", T63 "x\n");
    CHECK(scene_kiosk_token_resolve(&s, "kiosk_token_long.txt", NULL, src, sizeof src, &e) ==
          GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "kiosk token file kiosk_token_long.txt: expected at most 63 bytes (what "
                         "a kiosk's hello may carry), got 64");
    CHECK(!strcmp(s.kiosk_token, T63));
    write_file("kiosk_token_empty.txt", "\nsecond\n");
    CHECK(scene_kiosk_token_resolve(&s, "kiosk_token_empty.txt", "env", NULL, 0, &e) ==
          GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "kiosk token file kiosk_token_empty.txt: the first line is empty");
    write_file("kiosk_token_empty.txt", "");
    CHECK(scene_kiosk_token_resolve(&s, "kiosk_token_empty.txt", "env", NULL, 0, &e) ==
          GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "kiosk token file kiosk_token_empty.txt: the first line is empty");
    CHECK(scene_kiosk_token_resolve(&s, "no_such_token_file.txt", "env", NULL, 0, &e) ==
          GALE_E_IO);
    CHECK_STR_HAS(e.msg, "kiosk token file no_such_token_file.txt: cannot open: ");
    CHECK(scene_kiosk_token_resolve(&s, NULL, T63 "x", NULL, 0, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, SCENE_KIOSK_TOKEN_ENV ": expected at most 63 bytes (what a kiosk's "
                         "hello may carry), got 64");
    CHECK(!strcmp(s.kiosk_token, T63));
    /* a very long first line is refused without reading all of it */
    FILE *f = fopen("kiosk_token_huge.txt", "wb");
    for (int i = 0; f && i < 100000; i++) {
        fputc('y', f);
    }
    if (f) {
        fclose(f);
    }
    CHECK(scene_kiosk_token_resolve(&s, "kiosk_token_huge.txt", NULL, NULL, 0, &e) ==
          GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "got more than 65536");
    scene_fini(&s);
}

int main(void)
{
    RUN(test_defaults);
    RUN(test_forest_spacing);
    RUN(test_errors);
    RUN(test_trailing_bytes);
    RUN(test_size_limits);
    RUN(test_default_scene);
    RUN(test_no_shipped_token);
    RUN(test_kiosk_token);
    return check_report();
}
