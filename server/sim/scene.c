/* Scene config: validation (cfg.h) and forest layout. Generated forests place trees by
 * seeded dart throwing with a minimum spacing against every tree already placed and
 * outside obstacle boxes (Oliapuram & Kumar 2010 section 4: a forest of instanced
 * trees over a terrain). */
#include "scene.h"
#include "hash.h"

#include <errno.h>
#include <libgen.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cfg.h"
#include "wire.h"

extern const unsigned char scene_default_json[];
extern const size_t scene_default_json_len;

#define DEG2RAD 0.017453292519943295

static double rng_unit(uint64_t *s)
{
    return (double)(hash64_splitmix(s) >> 11) * (1.0 / 9007199254740992.0);
}

/* out = base_dir/p unless p is absolute; false when it does not fit. */
static bool resolve_path(char *out, size_t cap, const char *base_dir, const char *p)
{
    int n;
    if (p[0] == '/' || !base_dir || !base_dir[0]) {
        n = snprintf(out, cap, "%s", p);
    } else {
        n = snprintf(out, cap, "%s/%s", base_dir, p);
    }
    return n >= 0 && (size_t)n < cap;
}

/* A uniform bucket grid over the forest bounds for the spacing test: a tree is checked
 * against the 3 x 3 buckets around it, each bucket min_spacing wide. */
typedef struct spacing_grid {
    double x0, y0, cell;
    int nx, ny;
    int *head; /* owned [nx ny] first tree index in the bucket, -1 empty */
    int *next; /* owned [cap] next tree in the same bucket */
} spacing_grid;

/* Whether (x, y) lies within margin_m of a box's footprint. */
static bool inside_box(const wind_box *b, int n, double x, double y, double margin_m)
{
    for (int i = 0; i < n; i++) {
        if (x >= (double)b[i].min[0] - margin_m && x <= (double)b[i].max[0] + margin_m &&
            y >= (double)b[i].min[1] - margin_m && y <= (double)b[i].max[1] + margin_m) {
            return true;
        }
    }
    return false;
}

static bool spacing_ok(const spacing_grid *g, const scene_tree *t, double x, double y,
                       double min_d)
{
    int cx = (int)floor((x - g->x0) / g->cell), cy = (int)floor((y - g->y0) / g->cell);
    for (int j = cy - 1; j <= cy + 1; j++) {
        for (int i = cx - 1; i <= cx + 1; i++) {
            if (i < 0 || j < 0 || i >= g->nx || j >= g->ny) {
                continue;
            }
            for (int k = g->head[j * g->nx + i]; k >= 0; k = g->next[k]) {
                double dx = (double)t[k].pos[0] - x, dy = (double)t[k].pos[1] - y;
                if (dx * dx + dy * dy < min_d * min_d) {
                    return false;
                }
            }
        }
    }
    return true;
}

static void spacing_add(spacing_grid *g, int k, double x, double y)
{
    int cx = (int)floor((x - g->x0) / g->cell), cy = (int)floor((y - g->y0) / g->cell);
    if (cx < 0 || cy < 0 || cx >= g->nx || cy >= g->ny) {
        return; /* outside this block: cannot collide with trees placed inside it */
    }
    g->next[k] = g->head[cy * g->nx + cx];
    g->head[cy * g->nx + cx] = k;
}

/* Places `count` trees in [lo, hi] (x, y) at least min_d apart from each other and from
 * every tree already in s->trees, outside obstacles. At most 60 darts per tree. */
static int place_forest(scene *s, const cfg_doc *d, const char *path, int sp, int count,
                        const double lo[2], const double hi[2], double min_d,
                        const double scale[2], uint64_t seed, gale_err *err)
{
    spacing_grid g = { 0 };
    double cell = min_d > 0 ? min_d : 1e9;
    /* The bucket grid covers the block padded by one spacing, capped in size. */
    g.x0 = lo[0] - min_d;
    g.y0 = lo[1] - min_d;
    double w = hi[0] - lo[0] + 2 * min_d, h = hi[1] - lo[1] + 2 * min_d;
    if (min_d > 0) {
        while ((w / cell) * (h / cell) > 4e6) {
            cell *= 2;
        }
    }
    g.cell = cell;
    g.nx = (int)(w / cell) + 1;
    g.ny = (int)(h / cell) + 1;
    int cap = s->n_trees + count;
    g.head = malloc(sizeof(int) * (size_t)g.nx * (size_t)g.ny);
    g.next = malloc(sizeof(int) * (size_t)cap);
    if (!g.head || !g.next) {
        free(g.head);
        free(g.next);
        return gale_errf(err, GALE_E_NOMEM, "%s: %s: no memory for the spacing grid", d->name,
                         path);
    }
    for (int i = 0; i < g.nx * g.ny; i++) {
        g.head[i] = -1;
    }
    for (int k = 0; k < s->n_trees; k++) {
        spacing_add(&g, k, s->trees[k].pos[0], s->trees[k].pos[1]);
    }
    uint64_t st = seed;
    int placed = 0;
    long long darts = 0, budget = 60LL * count;
    while (placed < count && darts < budget) {
        darts++;
        double x = lo[0] + (hi[0] - lo[0]) * rng_unit(&st);
        double y = lo[1] + (hi[1] - lo[1]) * rng_unit(&st);
        double yaw = 2 * M_PI * rng_unit(&st);
        double sc = scale[0] + (scale[1] - scale[0]) * rng_unit(&st);
        /* the minimum spacing stands for a crown radius: keep it from the houses too, so
         * crowns do not grow through walls and roofs stay visible */
        if (inside_box(s->obstacles, s->n_obstacles, x, y, min_d) ||
            (min_d > 0 && !spacing_ok(&g, s->trees, x, y, min_d))) {
            continue;
        }
        int k = s->n_trees++;
        s->trees[k] = (scene_tree){ .species = sp,
                                    .pos = { (float)x, (float)y, 0.0f },
                                    .yaw_rad = (float)yaw,
                                    .scale = (float)sc };
        spacing_add(&g, k, x, y);
        placed++;
    }
    free(g.head);
    free(g.next);
    if (placed < count) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: %s: placed only %d of count %d trees %.3g m apart in "
                         "[%g, %g] x [%g, %g] after %lld tries: expected a larger area, "
                         "smaller min_spacing_m or count",
                         d->name, path, placed, count, min_d, lo[0], hi[0], lo[1], hi[1],
                         darts);
    }
    return GALE_OK;
}

static int parse_wind(scene *s, const cfg_doc *d, const cJSON *root, gale_err *err)
{
    static const char *const keys[] = { "grid",    "cell_m", "origin", "every",   "dir_deg",
                                        "u10_ms",  "solver", "threads", "subgrid_profile",
                                        NULL };
    bool found = false;
    const cJSON *w = cfg_child(d, root, "", "wind", cJSON_Object, false, &found, err);
    s->grid[0] = 64;
    s->grid[1] = 64;
    s->grid[2] = 16;
    s->cell_m = 2;
    s->wind_u10_ms = 8;
    s->wind_every = 1;
    s->wind_threads = 1;
    if (!found) {
        if (err->code) {
            return err->code;
        }
        s->grid_on = false;
        return GALE_OK;
    }
    int rc = cfg_check_keys(d, w, "wind", keys, err);
    if (rc) {
        return rc;
    }
    bool solver = true, subgrid = false;
    double g[3] = { 64, 64, 16 }, cell = 2, o[3], every = 1, dir = 0, u10 = 8;
    long long threads = 1;
    if ((rc = cfg_bool(d, w, "wind", "solver", false, true, &solver, err)) ||
        (rc = cfg_bool(d, w, "wind", "subgrid_profile", false, false, &subgrid, err)) ||
        (rc = cfg_vec(d, w, "wind", "grid", false, 3, g, 2, 1024, g, err)) ||
        (rc = cfg_number(d, w, "wind", "cell_m", false, 2, 0.1, 50, &cell, err)) ||
        (rc = cfg_number(d, w, "wind", "every", false, 1, 1, 64, &every, err)) ||
        (rc = cfg_number(d, w, "wind", "dir_deg", false, 0, -360, 360, &dir, err)) ||
        (rc = cfg_number(d, w, "wind", "u10_ms", false, 8, 0, 120, &u10, err)) ||
        (rc = cfg_int(d, w, "wind", "threads", false, 1, 1, 64, &threads, err))) {
        return rc;
    }
    s->wind_threads = (int)threads;
    for (int i = 0; i < 3; i++) {
        if (g[i] != floor(g[i])) {
            return gale_errf(err, GALE_E_RANGE, "%s: wind.grid[%d]: expected an integer, got %g",
                             d->name, i, g[i]);
        }
        s->grid[i] = (int)g[i];
    }
    /* checked here, not at allocation: wind_create would fail (or swap) only at start */
    long long cells = (long long)s->grid[0] * s->grid[1] * s->grid[2];
    if (cells > SCENE_MAX_GRID_CELLS) {
        const double gib = 1024.0 * 1024.0 * 1024.0;
        return gale_errf(err, GALE_E_RANGE,
                         "%s: wind.grid: %d x %d x %d = %lld cells, about %.3g GiB at %d bytes a "
                         "cell: expected at most %d cells (%.3g GiB)",
                         d->name, s->grid[0], s->grid[1], s->grid[2], cells,
                         (double)cells * SCENE_GRID_CELL_BYTES / gib, SCENE_GRID_CELL_BYTES,
                         SCENE_MAX_GRID_CELLS,
                         (double)SCENE_MAX_GRID_CELLS * SCENE_GRID_CELL_BYTES / gib);
    }
    if (every != floor(every)) {
        return gale_errf(err, GALE_E_RANGE, "%s: wind.every: expected an integer, got %g",
                         d->name, every);
    }
    o[0] = -0.5 * g[0] * cell;
    o[1] = -0.5 * g[1] * cell;
    o[2] = 0;
    if ((rc = cfg_vec(d, w, "wind", "origin", false, 3, o, -1e5, 1e5, o, err))) {
        return rc;
    }
    s->grid_on = solver;
    s->wind_subgrid = subgrid;
    s->cell_m = (float)cell;
    s->wind_every = (int)every;
    s->wind_dir_deg = (float)dir;
    s->wind_u10_ms = (float)u10;
    for (int i = 0; i < 3; i++) {
        s->origin[i] = (float)o[i];
    }
    return GALE_OK;
}

static int parse_leaves(scene *s, const cfg_doc *d, const cJSON *root, gale_err *err)
{
    static const char *const keys[] = { "rate_hz", "calm_ms", "ref_ms", "seed", NULL };
    bool found = false;
    s->leaf_rate_hz = 0.002f;
    s->leaf_calm_ms = 3;
    s->leaf_ref_ms = 20;
    const cJSON *l = cfg_child(d, root, "", "leaves", cJSON_Object, false, &found, err);
    if (!found) {
        return err->code ? err->code : GALE_OK;
    }
    int rc = cfg_check_keys(d, l, "leaves", keys, err);
    double rate, calm, ref;
    long long seed;
    if (rc || (rc = cfg_number(d, l, "leaves", "rate_hz", false, 0.002, 0, 10, &rate, err)) ||
        (rc = cfg_number(d, l, "leaves", "calm_ms", false, 3, 0, 100, &calm, err)) ||
        (rc = cfg_number(d, l, "leaves", "ref_ms", false, 20, 0.1, 200, &ref, err)) ||
        (rc = cfg_int(d, l, "leaves", "seed", false, 1, 0, 0x7fffffffffffffffLL, &seed, err))) {
        return rc;
    }
    if (ref <= calm) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: leaves.ref_ms: expected > leaves.calm_ms (%g), got %g", d->name,
                         calm, ref);
    }
    s->leaf_rate_hz = (float)rate;
    s->leaf_calm_ms = (float)calm;
    s->leaf_ref_ms = (float)ref;
    s->leaf_seed = (uint64_t)seed;
    return GALE_OK;
}

static int parse_species(scene *s, const cfg_doc *d, const cJSON *root, const char *base,
                         gale_err *err)
{
    static const char *const keys[] = { "name", "file", "modes", NULL };
    const cJSON *arr = cfg_child(d, root, "", "species", cJSON_Array, true, NULL, err);
    if (!arr) {
        return err ? err->code : GALE_E_PARSE;
    }
    int n = cJSON_GetArraySize(arr);
    if (n < 1 || n > SCENE_MAX_SPECIES) {
        return gale_errf(err, GALE_E_RANGE, "%s: species: expected 1 to %d entries, got %d",
                         d->name, SCENE_MAX_SPECIES, n);
    }
    for (int i = 0; i < n; i++) {
        char p[96];
        cfg_path_index(p, sizeof p, "species", i);
        const cJSON *e = cJSON_GetArrayItem(arr, i);
        char file[SCENE_PATH_MAX];
        long long modes = 32;
        int rc = cfg_check_keys(d, e, p, keys, err);
        if (rc || (rc = cfg_int(d, e, p, "modes", false, 32, 1, 64, &modes, err)) ||
            (rc = cfg_string(d, e, p, "name", true, NULL, s->species[i].name,
                             sizeof s->species[i].name, err)) ||
            (rc = cfg_string(d, e, p, "file", true, NULL, file, sizeof file, err))) {
            return rc;
        }
        if (!s->species[i].name[0]) {
            return gale_errf(err, GALE_E_RANGE, "%s: %s.name: expected a non-empty name",
                             d->name, p);
        }
        for (int j = 0; j < i; j++) {
            if (!strcmp(s->species[j].name, s->species[i].name)) {
                return gale_errf(err, GALE_E_RANGE,
                                 "%s: %s.name: duplicate species \"%s\" (also species[%d])",
                                 d->name, p, s->species[i].name, j);
            }
        }
        s->species[i].modes = (int)modes;
        if (!resolve_path(s->species[i].file, sizeof s->species[i].file, base, file)) {
            return gale_errf(err, GALE_E_RANGE, "%s: %s.file: path too long", d->name, p);
        }
        s->n_species = i + 1;
    }
    return GALE_OK;
}

static int parse_obstacles(scene *s, const cfg_doc *d, const cJSON *root, gale_err *err)
{
    static const char *const keys[] = { "min", "max", NULL };
    bool found = false;
    const cJSON *arr = cfg_child(d, root, "", "obstacles", cJSON_Array, false, &found, err);
    if (!found) {
        return err->code ? err->code : GALE_OK;
    }
    int n = cJSON_GetArraySize(arr);
    if (n > SCENE_MAX_OBSTACLES) {
        return gale_errf(err, GALE_E_RANGE, "%s: obstacles: expected at most %d boxes, got %d",
                         d->name, SCENE_MAX_OBSTACLES, n);
    }
    s->obstacles = calloc((size_t)(n ? n : 1), sizeof *s->obstacles);
    if (!s->obstacles) {
        return gale_errf(err, GALE_E_NOMEM, "%s: obstacles: no memory", d->name);
    }
    for (int i = 0; i < n; i++) {
        char p[96];
        cfg_path_index(p, sizeof p, "obstacles", i);
        const cJSON *e = cJSON_GetArrayItem(arr, i);
        double lo[3], hi[3];
        int rc = cfg_check_keys(d, e, p, keys, err);
        if (rc || (rc = cfg_vec(d, e, p, "min", true, 3, NULL, -1e5, 1e5, lo, err)) ||
            (rc = cfg_vec(d, e, p, "max", true, 3, NULL, -1e5, 1e5, hi, err))) {
            return rc;
        }
        for (int k = 0; k < 3; k++) {
            if (!(hi[k] > lo[k])) {
                return gale_errf(err, GALE_E_RANGE,
                                 "%s: %s.max[%d]: expected > min[%d] (%g), got %g", d->name, p,
                                 k, k, lo[k], hi[k]);
            }
            s->obstacles[i].min[k] = (float)lo[k];
            s->obstacles[i].max[k] = (float)hi[k];
        }
        s->n_obstacles = i + 1;
    }
    return GALE_OK;
}

static int species_ref(const scene *s, const cfg_doc *d, const cJSON *e, const char *p, int *sp,
                       gale_err *err)
{
    char name[64];
    int rc = cfg_string(d, e, p, "species", true, NULL, name, sizeof name, err);
    if (rc) {
        return rc;
    }
    *sp = scene_species_index(s, name);
    if (*sp < 0) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: %s.species: expected one of the names in species[], got \"%s\"",
                         d->name, p, name);
    }
    return GALE_OK;
}

/* Trees x modes: every state frame is sized for all trees at the scene's most modes
 * (wire_state_bound), and a client refuses a frame over WIRE_MAX_FRAME_BYTES, so a scene
 * whose keyframe could exceed it is refused here, before any tree is placed, rather than
 * on the wire. */
static int check_frame_size(const scene *s, const cfg_doc *d, long long n_trees,
                            gale_err *err)
{
    int most = 0;
    for (int i = 1; i < s->n_species; i++) {
        most = s->species[i].modes > s->species[most].modes ? i : most;
    }
    int modes = s->species[most].modes;
    size_t bound = wire_state_bound((uint32_t)n_trees, (uint32_t)modes, (uint32_t)s->n_species);
    if (bound > WIRE_MAX_FRAME_BYTES) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: species[%d].modes: %lld trees x %d modes: a keyframe may take %zu "
                         "bytes: expected at most %u (the largest frame a client accepts); "
                         "fewer trees or modes",
                         d->name, most, n_trees, modes, bound, WIRE_MAX_FRAME_BYTES);
    }
    return GALE_OK;
}

/* playlist: scenario names (file stems of the scenarios folder, checked against it when
 * the server loads that folder), 1..SCENE_MAX_PLAYLIST. */
static int parse_playlist(scene *s, const cfg_doc *d, const cJSON *root, gale_err *err)
{
    bool have = false;
    const cJSON *a = cfg_child(d, root, "", "playlist", cJSON_Array, false, &have, err);
    if (!have) {
        return err->code;
    }
    int n = cJSON_GetArraySize(a);
    if (n < 1 || n > SCENE_MAX_PLAYLIST) {
        return gale_errf(err, GALE_E_RANGE, "%s: playlist: expected 1..%d scenario names, got %d",
                         d->name, SCENE_MAX_PLAYLIST, n);
    }
    for (int i = 0; i < n; i++) {
        const cJSON *e = cJSON_GetArrayItem(a, i);
        size_t len = cJSON_IsString(e) ? strlen(e->valuestring) : 0;
        if (!cJSON_IsString(e) || len == 0 || len >= SCENE_NAME_MAX) {
            return gale_errf(err, GALE_E_PARSE,
                             "%s: playlist[%d]: expected a scenario name of 1..%d bytes (a file "
                             "stem of the scenarios folder)",
                             d->name, i, SCENE_NAME_MAX - 1);
        }
        snprintf(s->playlist[i], sizeof s->playlist[i], "%s", e->valuestring);
    }
    s->n_playlist = n;
    return GALE_OK;
}

static int parse_trees(scene *s, const cfg_doc *d, const cJSON *root, gale_err *err)
{
    static const char *const tkeys[] = { "species", "pos", "yaw_deg", "scale", NULL };
    static const char *const fkeys[] = { "species",  "count", "area_min",      "area_max",
                                         "min_spacing_m", "seed",  "scale", NULL };
    bool have_t = false, have_f = false;
    const cJSON *ta = cfg_child(d, root, "", "trees", cJSON_Array, false, &have_t, err);
    if (!have_t && err->code) {
        return err->code;
    }
    const cJSON *fa = cfg_child(d, root, "", "forest", cJSON_Array, false, &have_f, err);
    if (!have_f && err->code) {
        return err->code;
    }
    int nt = have_t ? cJSON_GetArraySize(ta) : 0;
    int nf = have_f ? cJSON_GetArraySize(fa) : 0;
    if (nf > SCENE_MAX_FORESTS) {
        return gale_errf(err, GALE_E_RANGE, "%s: forest: expected at most %d blocks, got %d",
                         d->name, SCENE_MAX_FORESTS, nf);
    }
    /* Counts first, so the array is allocated once and bounded. */
    long long total = nt;
    long long counts[SCENE_MAX_FORESTS];
    for (int i = 0; i < nf; i++) {
        char p[96];
        cfg_path_index(p, sizeof p, "forest", i);
        const cJSON *e = cJSON_GetArrayItem(fa, i);
        int rc = cfg_check_keys(d, e, p, fkeys, err);
        if (rc || (rc = cfg_int(d, e, p, "count", true, 0, 0, SCENE_MAX_TREES, &counts[i], err))) {
            return rc;
        }
        total += counts[i];
    }
    if (total < 1 || total > SCENE_MAX_TREES) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: trees + forest: expected 1 to %d trees in all, got %lld", d->name,
                         SCENE_MAX_TREES, total);
    }
    if (check_frame_size(s, d, total, err)) {
        return err->code;
    }
    s->trees = calloc((size_t)total, sizeof *s->trees);
    if (!s->trees) {
        return gale_errf(err, GALE_E_NOMEM, "%s: no memory for %lld trees", d->name, total);
    }
    for (int i = 0; i < nt; i++) {
        char p[96];
        cfg_path_index(p, sizeof p, "trees", i);
        const cJSON *e = cJSON_GetArrayItem(ta, i);
        double pos[3] = { 0, 0, 0 }, yaw, scale;
        int sp, rc = cfg_check_keys(d, e, p, tkeys, err);
        const cJSON *pj = rc ? NULL : cJSON_GetObjectItemCaseSensitive(e, "pos");
        int npos = cJSON_IsArray(pj) && cJSON_GetArraySize(pj) == 2 ? 2 : 3;
        if (rc || (rc = species_ref(s, d, e, p, &sp, err)) ||
            (rc = cfg_vec(d, e, p, "pos", true, npos, NULL, -1e5, 1e5, pos, err)) ||
            (rc = cfg_number(d, e, p, "yaw_deg", false, 0, -360, 360, &yaw, err)) ||
            (rc = cfg_number(d, e, p, "scale", false, 1, 0.05, 20, &scale, err))) {
            return rc;
        }
        if (npos == 2) {
            pos[2] = 0;
        }
        s->trees[s->n_trees++] = (scene_tree){ .species = sp,
                                               .pos = { (float)pos[0], (float)pos[1],
                                                        (float)pos[2] },
                                               .yaw_rad = (float)(yaw * DEG2RAD),
                                               .scale = (float)scale };
    }
    for (int i = 0; i < nf; i++) {
        char p[96];
        cfg_path_index(p, sizeof p, "forest", i);
        const cJSON *e = cJSON_GetArrayItem(fa, i);
        double lo[2], hi[2], min_d, sc[2] = { 1, 1 };
        long long seed;
        int sp, rc;
        if ((rc = species_ref(s, d, e, p, &sp, err)) ||
            (rc = cfg_vec(d, e, p, "area_min", true, 2, NULL, -1e5, 1e5, lo, err)) ||
            (rc = cfg_vec(d, e, p, "area_max", true, 2, NULL, -1e5, 1e5, hi, err)) ||
            (rc = cfg_number(d, e, p, "min_spacing_m", false, 0, 0, 1000, &min_d, err)) ||
            (rc = cfg_int(d, e, p, "seed", false, 1, 0, 0x7fffffffffffffffLL, &seed, err)) ||
            (rc = cfg_vec(d, e, p, "scale", false, 2, sc, 0.05, 20, sc, err))) {
            return rc;
        }
        for (int k = 0; k < 2; k++) {
            if (!(hi[k] > lo[k])) {
                return gale_errf(err, GALE_E_RANGE,
                                 "%s: %s.area_max[%d]: expected > area_min[%d] (%g), got %g",
                                 d->name, p, k, k, lo[k], hi[k]);
            }
        }
        if (sc[1] < sc[0]) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: %s.scale: expected [min, max] with min <= max, got [%g, %g]",
                             d->name, p, sc[0], sc[1]);
        }
        if ((rc = place_forest(s, d, p, sp, (int)counts[i], lo, hi, min_d, sc, (uint64_t)seed,
                               err))) {
            return rc;
        }
    }
    return GALE_OK;
}

/* s->kiosk_token = token, refused when a hello could not carry it (where: its origin). */
static int set_kiosk_token(scene *s, const char *token, const char *where, gale_err *err)
{
    size_t n = strlen(token);
    if (n > (size_t)SCENE_KIOSK_TOKEN_MAX) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: expected at most %d bytes (what a kiosk's hello may carry), "
                         "got %zu",
                         where, SCENE_KIOSK_TOKEN_MAX, n);
    }
    memcpy(s->kiosk_token, token, n + 1);
    return GALE_OK;
}

/* The first line of the file at path into out[cap], without its "\n" or "\r\n"; *len
 * gets its whole length (counting stops past 65536 bytes). */
static int read_first_line(const char *path, char *out, size_t cap, size_t *len, gale_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "kiosk token file %s: cannot open: %s", path,
                         strerror(errno));
    }
    size_t n = 0;
    int c;
    while (n <= 65536 && (c = fgetc(f)) != EOF && c != '\n') {
        if (n + 1 < cap) {
            out[n] = (char)c;
        }
        n++;
    }
    bool bad = ferror(f) != 0;
    fclose(f);
    if (bad) {
        return gale_errf(err, GALE_E_IO, "kiosk token file %s: cannot read", path);
    }
    if (n > 0 && n < cap && out[n - 1] == '\r') {
        n--;
    }
    out[n < cap ? n : cap - 1] = 0;
    *len = n;
    return GALE_OK;
}

int scene_kiosk_token_resolve(scene *s, const char *token_file, const char *env_token,
                              char *source, size_t source_cap, gale_err *err)
{
    char where[SCENE_PATH_MAX + 32];
    int rc = GALE_OK;
    const char *from = s->kiosk_token[0] ? "the config's kiosk_token" : "";
    if (token_file) {
        char line[SCENE_KIOSK_TOKEN_MAX + 2];
        size_t n = 0;
        snprintf(where, sizeof where, "kiosk token file %s", token_file);
        if ((rc = read_first_line(token_file, line, sizeof line, &n, err))) {
            return rc;
        }
        if (n == 0) {
            return gale_errf(err, GALE_E_RANGE, "%s: the first line is empty (expected the "
                                                "kiosk token)", where);
        }
        if (n > (size_t)SCENE_KIOSK_TOKEN_MAX) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: expected at most %d bytes (what a kiosk's hello may carry), "
                             "got %s%zu",
                             where, SCENE_KIOSK_TOKEN_MAX, n > 65536 ? "more than " : "",
                             n > 65536 ? (size_t)65536 : n);
        }
        rc = set_kiosk_token(s, line, where, err);
        from = where;
    } else if (env_token && env_token[0]) {
        rc = set_kiosk_token(s, env_token, SCENE_KIOSK_TOKEN_ENV, err);
        from = SCENE_KIOSK_TOKEN_ENV;
    }
    if (!rc && source) {
        snprintf(source, source_cap, "%s", from);
    }
    return rc;
}

int scene_species_index(const scene *s, const char *name)
{
    for (int i = 0; i < s->n_species; i++) {
        if (!strcmp(s->species[i].name, name)) {
            return i;
        }
    }
    return -1;
}

int scene_parse(scene *s, const char *name, const char *text, size_t len, const char *base_dir,
                gale_err *err_out)
{
    /* A local buffer so that the helpers can tell "absent" from "wrong type" even when
     * the caller passes no err. */
    gale_err le = { 0 }, *err = &le;
    static const char *const keys[] = { "name",     "tick_hz", "snapshot_hz", "kiosk_token",
                                        "scenario", "wind",    "leaves",      "species",
                                        "obstacles", "trees",  "forest",      "playlist",
                                        "tick_threads", "tick_rt_priority",
                                        NULL };
    memset(s, 0, sizeof *s);
    gale_err_clear(err_out);
    cfg_doc d;
    int rc = cfg_parse(&d, name, text, len, err);
    if (rc) {
        if (err_out) {
            *err_out = le;
        }
        return rc;
    }
    const cJSON *r = d.root;
    char scen[SCENE_PATH_MAX], token[1024], where[SCENE_PATH_MAX + 16];
    snprintf(where, sizeof where, "%s: kiosk_token", d.name);
    if ((rc = cfg_check_keys(&d, r, "", keys, err)) ||
        (rc = cfg_string(&d, r, "", "name", false, "scene", s->name, sizeof s->name, err)) ||
        (rc = cfg_number(&d, r, "", "tick_hz", false, 60, 1, 1000, &s->tick_hz, err)) ||
        (rc = cfg_number(&d, r, "", "snapshot_hz", false, 30, 0.1, 1000, &s->snapshot_hz,
                         err)) ||
        (rc = cfg_string(&d, r, "", "kiosk_token", false, "", token, sizeof token, err)) ||
        (rc = set_kiosk_token(s, token, where, err)) ||
        (rc = cfg_string(&d, r, "", "scenario", false, "", scen, sizeof scen, err)) ||
        (rc = parse_wind(s, &d, r, err)) || (rc = parse_leaves(s, &d, r, err)) ||
        (rc = parse_species(s, &d, r, base_dir, err)) ||
        (rc = parse_obstacles(s, &d, r, err)) || (rc = parse_trees(s, &d, r, err)) ||
        (rc = parse_playlist(s, &d, r, err))) {
        goto fail;
    }
    long long tick_threads = 2;
    if ((rc = cfg_int(&d, r, "", "tick_threads", false, 2, 1, 64, &tick_threads, err))) {
        goto fail;
    }
    s->tick_threads = (int)tick_threads;
    long long rt_priority = 0;
    if ((rc = cfg_int(&d, r, "", "tick_rt_priority", false, 0, 0, 99, &rt_priority, err))) {
        goto fail;
    }
    s->tick_rt_priority = (int)rt_priority;
    if (s->n_playlist > 0 && scen[0]) {
        rc = gale_errf(err, GALE_E_PARSE, "%s: scenario: not used with a playlist (the "
                       "playlist's first entry starts): expected one of the two", d.name);
        goto fail;
    }
    snprintf(s->base_dir, sizeof s->base_dir, "%s", base_dir ? base_dir : ".");
    if (s->snapshot_hz > s->tick_hz) {
        rc = gale_errf(err, GALE_E_RANGE, "%s: snapshot_hz: expected <= tick_hz (%g), got %g",
                       d.name, s->tick_hz, s->snapshot_hz);
        goto fail;
    }
    if (scen[0] && !resolve_path(s->scenario, sizeof s->scenario, base_dir, scen)) {
        rc = gale_errf(err, GALE_E_RANGE, "%s: scenario: path too long", d.name);
        goto fail;
    }
    cfg_fini(&d);
    return GALE_OK;
fail:
    cfg_fini(&d);
    scene_fini(s);
    if (err_out) {
        *err_out = le;
    }
    return rc;
}

int scene_load(scene *s, const char *path, gale_err *err)
{
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open", path);
    }
    char *buf = NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0) {
        n = ftell(f);
    }
    if (n < 0 || n > (16 << 20) || fseek(f, 0, SEEK_SET) != 0 ||
        !(buf = malloc((size_t)n + 1)) || fread(buf, 1, (size_t)n, f) != (size_t)n) {
        fclose(f);
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: cannot read (or larger than 16 MiB)", path);
    }
    fclose(f);
    char dir[SCENE_PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    int rc = scene_parse(s, path, buf, (size_t)n, dirname(dir), err);
    free(buf);
    return rc;
}

int scene_load_default(scene *s, const char *share_dir, gale_err *err)
{
    char base[SCENE_PATH_MAX];
    snprintf(base, sizeof base, "%s/configs/scenes", share_dir ? share_dir : GALE_SOURCE_DIR);
    return scene_parse(s, "<embedded default.json>", (const char *)scene_default_json,
                       scene_default_json_len, base, err);
}

void scene_scenarios_dir(const scene *s, const char *share_dir, char *out, size_t cap)
{
    struct stat st;
    snprintf(out, cap, "%s/../scenarios", s->base_dir[0] ? s->base_dir : ".");
    if (stat(out, &st) != 0 || !S_ISDIR(st.st_mode)) {
        snprintf(out, cap, "%s/configs/scenarios", share_dir ? share_dir : GALE_SOURCE_DIR);
    }
}

void scene_fini(scene *s)
{
    if (!s) {
        return;
    }
    free(s->obstacles);
    free(s->trees);
    memset(s, 0, sizeof *s);
}
