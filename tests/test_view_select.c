/* Tests of the server's interest and LOD selection (server/serve/view_select.h): circle
 * and frustum views with LOD and margins, against positions worked out by hand; the grid's
 * selection against the rule tree by tree over random scenes and views. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "view_select.h"

/* Circle and frustum interest with LOD, against positions worked out by hand. */
static void test_view_select(void)
{
    const float pos[5 * 3] = { 0, 0, 0, 50, 0, 0, 0, 120, 0, -10, 0, 0, 0, 104, 0 };
    const uint8_t full[5] = { 32, 32, 16, 32, 32 };
    uint8_t n[5];
    ctl_view all = { .kind = CTL_VIEW_ALL };
    view_select(&all, 5, pos, full, 0, 8, n);
    CHECK(n[0] == 32 && n[2] == 16 && n[4] == 32);
    /* Circle at the origin, radius 100, LOD beyond 40 m, 5 m margin. */
    ctl_view c = { .kind = CTL_VIEW_CIRCLE, .radius_m = 100, .lod_m = 40 };
    view_select(&c, 5, pos, full, 5, 8, n);
    CHECK(n[0] == 32);  /* centre */
    CHECK(n[1] == 8);   /* 50 m: inside, beyond LOD */
    CHECK(n[2] == 0);   /* 120 m: outside */
    CHECK(n[3] == 32);  /* 10 m */
    CHECK(n[4] == 8);   /* 104 m: outside the radius, inside the margin */
    /* Frustum from (0, -10, 0) looking +y, 90 degrees, far 150. */
    ctl_view f = { .kind = CTL_VIEW_FRUSTUM, .eye = { 0, -10, 0 }, .dir = { 0, 2, 0 },
                   .fov_deg = 90, .far_m = 150 };
    view_select(&f, 5, pos, full, 0, 8, n);
    CHECK(n[0] == 32);  /* on the axis, 10 m ahead */
    CHECK(n[1] == 0);   /* (50, 10): 78.7 degrees off axis */
    CHECK(n[2] == 16);  /* 130 m ahead */
    CHECK(n[3] == 32);  /* (-10, 10): exactly on the 45 degree edge */
    f.far_m = 100;
    view_select(&f, 5, pos, full, 0, 8, n);
    CHECK(n[2] == 0 && n[4] == 0);
    view_select(&f, 5, pos, full, 20, 8, n);
    CHECK(n[4] == 32 && n[1] == 0); /* 114 m within far + margin; 50 m across is not */
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

/* Uniform in [0, 1) (xorshift64*). */
static double rnd(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 0x2545f4914f6cdd1dull) >> 11) * 0x1.0p-53;
}

static float rnd_in(double lo, double hi)
{
    return (float)(lo + (hi - lo) * rnd());
}

/* A random view about (cx, cy) at scale span_m: circles and frustums of every fov, eyes on
 * the ground, on roofs and in the air, some with a tree exactly on the boundary. */
static ctl_view random_view(const float *pos, uint32_t n, double cx, double cy, double span_m,
                            float margin_m)
{
    ctl_view v = { .kind = rnd() < 0.3 ? CTL_VIEW_CIRCLE : CTL_VIEW_FRUSTUM };
    v.lod_m = rnd() < 0.3 ? 0.0f : rnd_in(1, span_m);
    const float *t = pos + 3 * (size_t)(n ? (uint32_t)(rnd() * n) % n : 0);
    const bool tie = n && rnd() < 0.3;
    if (v.kind == CTL_VIEW_CIRCLE) {
        v.x = rnd_in(cx - span_m, cx + span_m);
        v.y = rnd_in(cy - span_m, cy + span_m);
        v.radius_m = rnd_in(0.001, span_m);
        if (tie) {
            float dx = t[0] - v.x, dy = t[1] - v.y;
            v.radius_m = fmaxf(sqrtf(dx * dx + dy * dy) - margin_m, 0.001f);
        }
        return v;
    }
    const double z[3] = { 1.75, 12, 150 };
    v.eye[0] = rnd_in(cx - span_m, cx + span_m);
    v.eye[1] = rnd_in(cy - span_m, cy + span_m);
    v.eye[2] = (float)(z[(int)(rnd() * 3) % 3] * (0.5 + rnd()));
    v.dir[0] = rnd_in(-1, 1);
    v.dir[1] = rnd_in(-1, 1);
    v.dir[2] = rnd_in(-1, 0.3);
    if (rnd() < 0.1) {
        v.dir[0] = v.dir[1] = 0.0f; /* straight down */
        v.dir[2] = -1.0f;
    }
    if (rnd() < 0.1 && n) {
        for (int a = 0; a < 3; a++) {
            v.dir[a] = t[a] - v.eye[a]; /* a tree on the axis */
        }
    }
    if (fabsf(v.dir[0]) + fabsf(v.dir[1]) + fabsf(v.dir[2]) == 0.0f) {
        v.dir[0] = 1.0f;
    }
    const double fov[5] = { 1, 30, 60, 120, 179 };
    v.fov_deg = rnd() < 0.5 ? (float)fov[(int)(rnd() * 5) % 5] : rnd_in(1, 179);
    v.far_m = rnd_in(0.001, 2 * span_m);
    if (tie) {
        float dn = sqrtf(v.dir[0] * v.dir[0] + v.dir[1] * v.dir[1] + v.dir[2] * v.dir[2]);
        float along = ((t[0] - v.eye[0]) * v.dir[0] + (t[1] - v.eye[1]) * v.dir[1] +
                       (t[2] - v.eye[2]) * v.dir[2]) / dn;
        v.far_m = fmaxf(along - margin_m, 0.001f);
    }
    return v;
}

/* The grid's selection equals the rule tree by tree (view_select) for random views of
 * random scenes: a landscape, a clump, trees far from the origin, one tree, none. */
static void test_grid_matches_rule(void)
{
    enum { N_MAX = 20000 };
    float *pos = malloc(sizeof(float) * 3 * N_MAX);
    uint8_t *full = malloc(N_MAX), *ref = malloc(N_MAX), *fast = malloc(N_MAX);
    CHECK(pos && full && ref && fast);
    if (!pos || !full || !ref || !fast) {
        goto done;
    }
    struct { uint32_t n; double cx, cy, span_m, cell_m, dz_m; } scenes[] = {
        { 20000, 0, 0, 1000, 32, 30 },      /* a landscape with hills */
        { 5000, 40, -20, 3, 8, 0.5 },       /* a clump in few cells */
        { 3000, 9.5e5, -9.9e5, 400, 16, 5 },/* far from the origin: coarse floats */
        { 1, 10, 10, 50, 32, 0 },
        { 0, 0, 0, 100, 32, 0 },
    };
    int views = 0, mismatched = 0;
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
        const uint32_t n = scenes[k].n;
        const double cx = scenes[k].cx, cy = scenes[k].cy, span = scenes[k].span_m;
        for (uint32_t t = 0; t < n; t++) {
            pos[3 * t] = rnd_in(cx - span, cx + span);
            pos[3 * t + 1] = rnd_in(cy - span, cy + span);
            pos[3 * t + 2] = rnd_in(0, scenes[k].dz_m);
            full[t] = (uint8_t)(1 + (t % 3) * 15);
        }
        view_grid g;
        gale_err e;
        CHECK(view_grid_build(&g, n, pos, (float)scenes[k].cell_m, &e) == 0);
        for (int i = 0; i < 600; i++) {
            const float margin_m = rnd() < 0.2 ? 0.0f : rnd_in(0, 30);
            const ctl_view v = random_view(pos, n, cx, cy, span, margin_m);
            const uint32_t lod = 1 + (uint32_t)(rnd() * 8);
            view_select(&v, n, pos, full, margin_m, lod, ref);
            view_select_grid(&g, &v, full, margin_m, lod, fast);
            views++;
            if (memcmp(ref, fast, n) != 0) {
                mismatched++;
            }
        }
        view_grid_fini(&g);
    }
    if (mismatched) {
        fprintf(stderr, "view_select_grid differs from view_select in %d of %d views\n",
                mismatched, views);
    }
    CHECK(mismatched == 0);
    /* the grid is bounded: a scene spread far and wide gets coarser cells */
    for (uint32_t t = 0; t < 1000; t++) {
        pos[3 * t] = rnd_in(-1e6, 1e6);
        pos[3 * t + 1] = rnd_in(-1e6, 1e6);
        pos[3 * t + 2] = 0.0f;
    }
    view_grid g;
    gale_err e;
    CHECK(view_grid_build(&g, 1000, pos, 1.0f, &e) == 0);
    CHECK((uint64_t)g.nx * g.ny <= VIEW_GRID_MAX_CELLS);
    view_grid_fini(&g);
    pos[4] = NAN;
    CHECK(view_grid_build(&g, 1000, pos, 1.0f, &e) != 0);
    CHECK_STR_HAS(e.msg, "tree 1");
done:
    free(pos);
    free(full);
    free(ref);
    free(fast);
}

int main(void)
{
    RUN(test_view_select);
    RUN(test_grid_matches_rule);
    return check_report();
}
