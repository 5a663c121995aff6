/* The tick: the exact modal update against the closed-form step response of a damped
 * oscillator under the steady log-law wind, the tree-frame rotation, and leaves only
 * above the calm threshold. */
#include "check.h"
#include "tick.h"
#include "wind_worker.h"

#include <linux/capability.h>
#include <math.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static scene one_tree(float yaw_rad, float u10)
{
    static scene_tree tr;
    scene s;
    memset(&s, 0, sizeof s);
    s.tick_hz = 60;
    s.snapshot_hz = 30;
    s.n_species = 1;
    s.wind_u10_ms = u10;
    s.leaf_rate_hz = 0.01f;
    s.leaf_calm_ms = 3;
    s.leaf_ref_ms = 20;
    tr = (scene_tree){ .species = 0, .pos = { 0, 0, 0 }, .yaw_rad = yaw_rad, .scale = 1 };
    s.trees = &tr;
    s.n_trees = 1;
    return s;
}

static void test_step_response(void)
{
    /* ω = 2π·0.5 Hz, ζ = 0.05; p = (1e-3, 0, 0); crown at 0.7 · 14.29 m = 10 m → |v| = u10 */
    float omega[1] = { (float)(2 * M_PI * 0.5) }, gamma[1] = { (float)(2 * 0.05 * 2 * M_PI * 0.5) };
    float basis[3] = { 1e-3f, 0, 0 }, qstep[1] = { 1e-4f };
    tick_species sp = { .n_modes = 1, .omega = omega, .gamma = gamma, .wind_basis = basis,
                        .qstep = qstep,
                        .height_m = 10.0f / 0.7f, .n_leaves = 0 };
    scene s = one_tree(0, 8);
    tick_sim *t = tick_create(&(tick_desc){ .sc = &s, .species = &sp }, NULL);
    CHECK(t != NULL);
    if (!t) {
        return;
    }
    double f = 8.0 * 8.0 * 1e-3, w = omega[0], z = 0.05, wd = w * sqrt(1 - z * z);
    double worst = 0;
    int16_t qs[1];
    for (int n = 1; n <= 600; n++) {
        CHECK(tick_step(t, qs, NULL, NULL) == 0);
        double tt = n / 60.0;
        double want = f / (w * w) *
                      (1 - exp(-z * w * tt) * (cos(wd * tt) + z * w / wd * sin(wd * tt)));
        float q;
        CHECK(tick_get_q(t, 0, &q, 1) == 1);
        double d = fabs((double)q - want);
        worst = d > worst ? d : worst;
        /* the snapshot buffer holds q rounded to the step */
        if (fabs((double)qs[0] * 1e-4 - (double)q) > 0.5e-4 * (1 + 1e-3)) {
            worst = 1e9;
        }
    }
    /* exact discretisation: only float rounding, relative to the static deflection */
    CHECK_NEAR(worst, 0, 1e-4 * f / (w * w));
    CHECK(tick_now(t) == 600);
    tick_destroy(t);

    /* a yaw of 90°: the wind along world +x is along tree -y, so p = (1,0,0) feels none */
    s = one_tree((float)(M_PI / 2), 8);
    t = tick_create(&(tick_desc){ .sc = &s, .species = &sp }, NULL);
    for (int n = 0; n < 60; n++) {
        tick_step(t, NULL, NULL, NULL);
    }
    float q90;
    tick_get_q(t, 0, &q90, 1);
    CHECK_NEAR(q90, 0, 1e-6);
    tick_destroy(t);
}

static void test_leaves_and_errors(void)
{
    float omega[1] = { 3 }, gamma[1] = { 0.3f }, basis[3] = { 0, 0, 0 }, qstep[1] = { 1e-4f };
    tick_species sp = { .n_modes = 1, .omega = omega, .gamma = gamma, .wind_basis = basis,
                        .qstep = qstep,
                        .height_m = 10.0f / 0.7f, .n_leaves = 2000 };
    scene s = one_tree(0, 2); /* calm: 2 m/s */
    tick_sim *t = tick_create(&(tick_desc){ .sc = &s, .species = &sp }, NULL);
    int total = 0;
    const leaf_seed *ls;
    for (int n = 0; n < 600; n++) {
        tick_step(t, NULL, NULL, NULL);
        total += tick_leaves(t, &ls);
    }
    CHECK(total == 0);
    tick_set_inflow(t, &(wind_inflow){ .u10_ms = 30 }); /* a storm: 2000 · 0.01 · ((30-3)/17)² ≈ 50 leaves/s */
    tick_stats st;
    for (int n = 0; n < 600; n++) {
        tick_step(t, NULL, &st, NULL);
        total += tick_leaves(t, &ls);
    }
    CHECK(total > 300 && total < 700);
    CHECK_NEAR(st.max_speed_ms, 30, 1e-3);
    tick_destroy(t);

    omega[0] = 0;
    gale_err e;
    CHECK(tick_create(&(tick_desc){ .sc = &s, .species = &sp }, &e) == NULL);
    CHECK_STR_HAS(e.msg, "omega");
}

/* A wind grid stand-in that counts steps and the balls added before each. */
typedef struct fake_wind {
    int steps, balls, balls_at_step;
    float last_force;
} fake_wind;

static void fw_inflow(void *ctx, const wind_inflow *in)
{
    (void)ctx;
    (void)in;
}

static int fw_step(void *ctx, float dt_s, wind_step_stats *st)
{
    fake_wind *f = ctx;
    (void)dt_s;
    (void)st;
    f->steps++;
    f->balls_at_step += f->balls; /* balls added since the previous step act on this one */
    f->balls = 0;
    return 0;
}

static void fw_sample(void *ctx, int n, const float *p, float *v)
{
    (void)ctx;
    (void)p;
    memset(v, 0, sizeof(float) * 3 * (size_t)n);
}

static void fw_ball(void *ctx, const wind_ball *b)
{
    fake_wind *f = ctx;
    f->balls++;
    f->last_force = b->force[0];
}

/* The scenario's force balls reach the grid before every wind step (wind_every = 2). */
static void test_balls(void)
{
    float omega[1] = { 3 }, gamma[1] = { 0.3f }, basis[3] = { 0, 0, 0 }, qstep[1] = { 1e-4f };
    tick_species sp = { .n_modes = 1, .omega = omega, .gamma = gamma, .wind_basis = basis,
                        .qstep = qstep, .height_m = 10 };
    scene s = one_tree(0, 5);
    s.wind_every = 2;
    fake_wind f = { 0 };
    tick_wind tw = { .ctx = &f, .set_inflow = fw_inflow, .step = fw_step,
                     .sample_many = fw_sample, .add_ball = fw_ball };
    tick_sim *t = tick_create(&(tick_desc){ .sc = &s, .species = &sp, .wind = &tw }, NULL);
    CHECK(t != NULL);
    if (!t) {
        return;
    }
    wind_ball balls[2] = { { .radius_m = 5, .force = { 3, 0, 0 } },
                           { .radius_m = 5, .force = { 7, 0, 0 } } };
    tick_set_balls(t, balls, 2);
    for (int n = 0; n < 10; n++) {
        CHECK(tick_step(t, NULL, NULL, NULL) == 0);
    }
    CHECK(f.steps == 5);
    CHECK(f.balls_at_step == 10);
    CHECK_NEAR(f.last_force, 7, 0);
    tick_destroy(t);
}

/* A sampler that sleeps ms of wall time, or spins until its thread has had ms of CPU
 * time (however long that takes on a loaded machine). */
typedef struct slow_sampler {
    double ms;
    bool spin;
} slow_sampler;

static int no_step(void *ctx, float dt_s, wind_step_stats *st)
{
    (void)ctx;
    (void)dt_s;
    (void)st;
    return 0;
}

static void slow_sample(void *ctx, int n, const float *p, float *v)
{
    const slow_sampler *z = ctx;
    if (z->spin) {
        struct timespec c;
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c);
        const double until = (double)c.tv_sec * 1e3 + (double)c.tv_nsec * 1e-6 + z->ms;
        do {
            clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c);
        } while ((double)c.tv_sec * 1e3 + (double)c.tv_nsec * 1e-6 < until);
    } else {
        const long ns = (long)(z->ms * 1e6);
        nanosleep(&(struct timespec){ .tv_sec = ns / 1000000000L, .tv_nsec = ns % 1000000000L },
                  NULL);
    }
    fw_sample(ctx, n, p, v);
}

/* tick_stats puts a tick's time in its phase: a sampler that takes 20 ms shows in
 * sample_ms and not in the others, the phases add up to the tick's time, the time the
 * thread slept in it shows as off a CPU (ms - cpu_ms), and 20 ms of CPU spent in it shows
 * in cpu_ms. */
static void test_phases(void)
{
    float omega[1] = { 3 }, gamma[1] = { 0.3f }, basis[3] = { 1, 0, 0 }, qstep[1] = { 1e-4f };
    tick_species sp = { .n_modes = 1, .omega = omega, .gamma = gamma, .wind_basis = basis,
                        .qstep = qstep, .height_m = 10, .n_leaves = 100 };
    scene s = one_tree(0, 5);
    for (int spin = 0; spin < 2; spin++) {
        slow_sampler z = { .ms = 20.0, .spin = spin };
        tick_wind tw = { .ctx = &z, .set_inflow = fw_inflow, .step = no_step,
                         .sample_many = slow_sample };
        tick_sim *t = tick_create(&(tick_desc){ .sc = &s, .species = &sp, .wind = &tw }, NULL);
        CHECK(t != NULL);
        if (!t) {
            continue;
        }
        tick_stats st;
        CHECK(tick_step(t, NULL, &st, NULL) == 0);
        CHECK(st.sample_ms >= 19.9);
        /* the others take microseconds; 15 ms leaves room for a loaded machine's turns */
        CHECK(st.modal_ms < 15.0 && st.leaves_ms < 15.0 && st.damage_ms == 0.0 &&
              st.wind_ms < 15.0);
        const double phases = st.wind_ms + st.sample_ms + st.modal_ms + st.leaves_ms +
                              st.damage_ms;
        CHECK(phases <= st.ms + 1e-9 && phases >= st.ms - 5.0);
        CHECK(st.cpu_ms >= 0.0 && st.cpu_ms <= st.ms + 0.5);
        if (spin) {
            CHECK(st.cpu_ms >= 19.9);
        } else {
            CHECK(st.ms - st.cpu_ms >= 19.0);
        }
        tick_destroy(t);
    }
}

/* A wind grid stand-in whose pressure solve reports the iterations and residual set. */
typedef struct solve_wind {
    int iterations;
    double residual;
} solve_wind;

static int sw_step(void *ctx, float dt_s, wind_step_stats *st)
{
    const solve_wind *f = ctx;
    (void)dt_s;
    st->iterations = f->iterations;
    st->residual = f->residual;
    return 0;
}

/* tick_stats tells a pressure solve that used its whole budget and stayed above the
 * tolerance 1/div_reduction; ticks without a wind step say so. */
static void test_unconverged(void)
{
    float omega[1] = { 3 }, gamma[1] = { 0.3f }, basis[3] = { 0, 0, 0 }, qstep[1] = { 1e-4f };
    tick_species sp = { .n_modes = 1, .omega = omega, .gamma = gamma, .wind_basis = basis,
                        .qstep = qstep, .height_m = 10 };
    scene s = one_tree(0, 5);
    s.wind_every = 2;
    solve_wind f = { .iterations = 30, .residual = 0.02 };
    tick_wind tw = { .ctx = &f, .set_inflow = fw_inflow, .step = sw_step,
                     .sample_many = fw_sample, .max_iterations = 30, .div_reduction = 100 };
    tick_sim *t = tick_create(&(tick_desc){ .sc = &s, .species = &sp, .wind = &tw }, NULL);
    CHECK(t != NULL);
    if (!t) {
        return;
    }
    tick_stats st;
    CHECK(tick_step(t, NULL, &st, NULL) == 0); /* tick 0: a wind step */
    CHECK(st.wind_stepped && st.wind_unconverged);
    CHECK(st.wind_iters == 30);
    CHECK_NEAR(st.wind_residual, 0.02, 0);
    CHECK(tick_step(t, NULL, &st, NULL) == 0); /* tick 1: none (every 2) */
    CHECK(!st.wind_stepped && !st.wind_unconverged);
    f.residual = 0.005; /* within 1/100 on the last iteration */
    CHECK(tick_step(t, NULL, &st, NULL) == 0);
    CHECK(st.wind_stepped && !st.wind_unconverged);
    f = (solve_wind){ .iterations = 12, .residual = 0.02 }; /* stopped before the budget */
    tick_step(t, NULL, &st, NULL);
    tick_step(t, NULL, &st, NULL);
    CHECK(st.wind_stepped && !st.wind_unconverged);
    tick_destroy(t);

    tw.max_iterations = 0; /* budget unknown: never counted */
    f = (solve_wind){ .iterations = 30, .residual = 0.5 };
    t = tick_create(&(tick_desc){ .sc = &s, .species = &sp, .wind = &tw }, NULL);
    CHECK(t && tick_step(t, NULL, &st, NULL) == 0);
    CHECK(st.wind_stepped && !st.wind_unconverged);
    tick_destroy(t);
}

/* A wind field given by a formula of the sample point: what each crown gets tells whether
 * the samples went back to the right tree. */
static void field_at(const float *p, float *v)
{
    v[0] = 25.0f + 0.05f * p[0] + 3.0f * sinf(0.2f * p[1]);
    v[1] = 0.04f * p[1] - 2.0f;
    v[2] = 0.01f * p[0] + 0.02f * p[2];
}

static void field_sample(void *ctx, int n, const float *p, float *v)
{
    (void)ctx;
    for (int i = 0; i < n; i++) {
        field_at(p + 3 * i, v + 3 * i);
    }
}

static int field_step(void *ctx, float dt_s, wind_step_stats *st)
{
    (void)ctx;
    (void)dt_s;
    (void)st;
    return 0;
}

/* 6000 trees in random order over a grid of 2 m cells, on 1 and 3 tick threads, with a leaf
 * cap that overflows and one that does not: every crown gets the wind at its own crown
 * (sampled in the grid's Morton order, scattered back), and the snapshots, the leaves in
 * order, the leaves lost and the strongest wind are the same on both. */
static void test_threads_same_tick(void)
{
    enum { N = 6000, MODES = 4 };
    float omega[MODES] = { 3, 7, 13, 29 }, gamma[MODES] = { 0.3f, 0.5f, 0.9f, 2 };
    float basis[3 * MODES] = { 1e-3f, 2e-4f, 0, -5e-4f, 1e-3f, 1e-4f,
                               3e-4f, -2e-4f, 1e-4f, 1e-4f, 1e-4f, -1e-4f };
    float qstep[MODES] = { 1e-5f, 1e-5f, 1e-5f, 1e-5f };
    tick_species sp = { .n_modes = MODES, .omega = omega, .gamma = gamma, .wind_basis = basis,
                        .qstep = qstep, .height_m = 12, .n_leaves = 1500 };
    static scene_tree tr[N];
    uint64_t r = 99;
    for (int k = 0; k < N; k++) {
        r = r * 6364136223846793005ull + 1442695040888963407ull;
        float x = (float)(r >> 40) / 16777216.0f * 128.0f - 64.0f;
        r = r * 6364136223846793005ull + 1442695040888963407ull;
        float y = (float)(r >> 40) / 16777216.0f * 128.0f - 64.0f;
        tr[k] = (scene_tree){ .species = 0, .pos = { x, y, 0 }, .yaw_rad = 0.001f * (float)k,
                              .scale = 1 };
    }
    for (int cap = 0; cap < 2; cap++) {
        tick_sim *t[2];
        int16_t *q[2];
        /* borrowed by the simulations for their life */
        static scene s[2];
        static tick_wind tws[2];
        for (int j = 0; j < 2; j++) {
            s[j] = one_tree(0, 20);
            s[j].trees = tr;
            s[j].n_trees = N;
            s[j].cell_m = 2;
            s[j].origin[0] = s[j].origin[1] = -64;
            s[j].tick_threads = j ? 3 : 1;
            tws[j] = (tick_wind){ .set_inflow = fw_inflow, .step = field_step,
                                  .sample_many = field_sample };
            t[j] = tick_create(&(tick_desc){ .sc = &s[j], .species = &sp, .wind = &tws[j],
                                             .max_leaves_per_tick = cap ? 100000 : 700 },
                               NULL);
            q[j] = calloc((size_t)N * MODES, sizeof(int16_t));
            CHECK(t[j] != NULL && q[j] != NULL);
        }
        if (!t[0] || !t[1] || !q[0] || !q[1]) {
            return;
        }
        int lost = 0, shed = 0, wind_bad = 0;
        for (int n = 0; n < 8; n++) {
            tick_stats st[2];
            for (int j = 0; j < 2; j++) {
                CHECK(tick_step(t[j], q[j], &st[j], NULL) == 0);
            }
            CHECK(memcmp(q[0], q[1], sizeof(int16_t) * N * MODES) == 0);
            const leaf_seed *l[2];
            int nl[2] = { tick_leaves(t[0], &l[0]), tick_leaves(t[1], &l[1]) };
            CHECK(nl[0] == nl[1] && memcmp(l[0], l[1], sizeof(leaf_seed) * (size_t)nl[0]) == 0);
            CHECK(st[0].leaves_lost == st[1].leaves_lost);
            CHECK(st[0].max_speed_ms == st[1].max_speed_ms);
            lost += st[0].leaves_lost;
            shed += nl[0];
            for (int k = 0; k < N; k++) {
                float want[3], p[3] = { tr[k].pos[0], tr[k].pos[1], 0.7f * 12.0f };
                field_at(p, want);
                wind_bad += memcmp(&tick_crown_wind(t[1])[3 * k], want, sizeof want) != 0;
            }
        }
        CHECK(wind_bad == 0);
        CHECK(shed > 8 * 500);
        CHECK(cap ? lost == 0 : lost > 0);
        for (int j = 0; j < 2; j++) {
            tick_destroy(t[j]);
            free(q[j]);
        }
    }
}

/* The real wind grid behind tick_wind, with and without the probe's callbacks. */
static void g_inflow(void *ctx, const wind_inflow *in)
{
    wind_set_inflow(ctx, in);
}

static int g_step(void *ctx, float dt_s, wind_step_stats *st)
{
    return wind_step(ctx, dt_s, st);
}

static void g_sample(void *ctx, int n, const float *p, float *v)
{
    wind_sample_many(ctx, n, p, v);
}

static void *g_probe_create(void *ctx, int n, const float *p)
{
    return wind_probe_create(ctx, n, p, NULL);
}

static void g_probe_destroy(void *probe)
{
    wind_probe_destroy(probe);
}

static void g_probe_sample(void *ctx, const void *probe, int i0, int i1, float *v)
{
    wind_probe_sample(ctx, probe, i0, i1, v);
}

static void g_add_subgrid(void *ctx, int n, const float *p, float *v)
{
    wind_add_subgrid(ctx, n, p, v);
}

static int g_publish(void *ctx)
{
    return wind_publish(ctx);
}

static void g_subgrid_inflow(void *ctx, const wind_inflow *in)
{
    wind_set_subgrid_inflow(ctx, in);
}

/* 9000 trees over identical subgrid-profile grids stepped every `every` ticks, the inflow
 * changing every tick, the tick reading the grid through the probe on 1 and on 2
 * threads: on every tick each crown gets, float for float, what sampling every crown of
 * a third grid gives (wind_sample_many, an independent path) when that grid has taken the
 * steps up to the tick every - 1 ticks back (the read is spread over the ticks between
 * steps: tick.c sample_probe), with this tick's inflow; both tick counts leave the same
 * snapshots. With every > 1 the lag shows: some ticks differ from the grid as the samplers
 * see it. ahead: the steps one step ahead (tick_wind.publish; on 2 threads beside the
 * ticks, tick.c step_ahead), so each step after the first two is under the inflow of the
 * step's tick before it, where without them it is under its own tick's. */
static void probe_case(int every, bool ahead)
{
    enum { N = 9000, MODES = 2, TICKS = 13 };
    float omega[MODES] = { 3, 11 }, gamma[MODES] = { 0.3f, 0.8f };
    float basis[3 * MODES] = { 1e-3f, 2e-4f, 0, -5e-4f, 1e-3f, 1e-4f };
    float qstep[MODES] = { 1e-5f, 1e-5f };
    tick_species sp = { .n_modes = MODES, .omega = omega, .gamma = gamma, .wind_basis = basis,
                        .qstep = qstep, .height_m = 12, .n_leaves = 100 };
    static scene_tree tr[N];
    static float crown[3 * N], want[3 * N], now[3 * N];
    uint64_t r = 7;
    for (int k = 0; k < N; k++) {
        float c[3];
        for (int a = 0; a < 3; a++) {
            r = r * 6364136223846793005ull + 1442695040888963407ull;
            c[a] = (float)(r >> 40) / 16777216.0f;
        }
        /* some beyond the grid's sides, which clamp */
        tr[k] = (scene_tree){ .species = 0, .pos = { c[0] * 140.0f - 70.0f, c[1] * 140.0f - 70.0f, 0 },
                              .yaw_rad = 0.002f * (float)k, .scale = 0.3f + 1.2f * c[2] };
        crown[3 * k] = tr[k].pos[0];
        crown[3 * k + 1] = tr[k].pos[1];
        crown[3 * k + 2] = 0.7f * (12.0f * tr[k].scale);
    }
    static scene s[2];
    tick_sim *t[2];
    wind_grid *g[3];
    int16_t *q[2];
    tick_wind tw[2];
    for (int j = 0; j < 3; j++) {
        g[j] = wind_create(&(wind_desc){ .nx = 16, .ny = 16, .nz = 2, .cell_m = 8,
                                         .origin = { -64, -64, 0 }, .threads = 1, .seed = 3,
                                         .subgrid_profile = 1 },
                           NULL);
        CHECK(g[j] != NULL);
    }
    for (int j = 0; j < 2; j++) {
        s[j] = one_tree(0, 14);
        s[j].trees = tr;
        s[j].n_trees = N;
        s[j].cell_m = 8;
        s[j].origin[0] = s[j].origin[1] = -64;
        s[j].wind_every = every;
        s[j].tick_threads = j ? 2 : 1;
        tw[j] = (tick_wind){ .ctx = g[j], .set_inflow = g_inflow, .step = g_step,
                             .sample_many = g_sample, .probe_create = g_probe_create,
                             .probe_destroy = g_probe_destroy, .probe_sample = g_probe_sample,
                             .add_subgrid = g_add_subgrid,
                             .publish = ahead ? g_publish : NULL,
                             .set_subgrid_inflow = ahead ? g_subgrid_inflow : NULL };
        t[j] = g[j] ? tick_create(&(tick_desc){ .sc = &s[j], .species = &sp, .wind = &tw[j] },
                                  NULL)
                    : NULL;
        q[j] = calloc((size_t)N * MODES, sizeof(int16_t));
        CHECK(t[j] != NULL && q[j] != NULL);
    }
    if (!t[0] || !t[1] || !q[0] || !q[1] || !g[2]) {
        return;
    }
    wind_inflow in[TICKS];
    const float dt_s = (float)(1.0 / s[0].tick_hz);
    int wind_bad = 0, q_bad = 0, lagging = 0, steps_ref = 0;
    for (int n = 0; n < TICKS; n++) {
        in[n] = (wind_inflow){ .dir_rad = 0.4f + 0.05f * (float)n, .u10_ms = 14.0f + (float)n,
                               .gust = { 0.3f * (float)(n % 3), -0.2f, 0 } };
        for (int j = 0; j < 2; j++) {
            tick_set_inflow(t[j], &in[n]);
            CHECK(tick_step(t[j], q[j], NULL, NULL) == 0);
        }
        /* the reference grid: every step up to tick n - (every - 1) (the first always),
         * each under its own tick's inflow, or ahead the step's tick's before it (the
         * first two under the first tick's); sampled under this tick's */
        const int upto = n - (every - 1) > 0 ? n - (every - 1) : 0;
        while (steps_ref * every <= upto) {
            const int at = !ahead ? steps_ref : steps_ref > 0 ? steps_ref - 1 : 0;
            wind_set_inflow(g[2], &in[at * every]);
            CHECK(wind_step(g[2], dt_s * (float)every, NULL) == 0);
            steps_ref++;
        }
        wind_set_inflow(g[2], &in[n]);
        wind_sample_many(g[2], N, crown, want);
        wind_sample_many(g[0], N, crown, now);
        q_bad += memcmp(q[0], q[1], sizeof(int16_t) * N * MODES) != 0;
        for (int j = 0; j < 2; j++) {
            wind_bad += memcmp(tick_crown_wind(t[j]), want, sizeof(float) * 3 * N) != 0;
        }
        lagging += memcmp(tick_crown_wind(t[0]), now, sizeof(float) * 3 * N) != 0;
    }
    CHECK(wind_bad == 0);
    CHECK(q_bad == 0);
    CHECK(every > 1 ? lagging > 0 : lagging == 0);
    for (int j = 0; j < 2; j++) {
        tick_destroy(t[j]);
        free(q[j]);
    }
    for (int j = 0; j < 3; j++) {
        wind_destroy(g[j]);
    }
}

static void test_probe_same_tick(void)
{
    for (int ahead = 0; ahead < 2; ahead++) {
        probe_case(3, ahead);
        probe_case(4, ahead);
        probe_case(1, ahead);
    }
}

typedef struct sleepy {
    long ms;
    int policy_at_start, policy_at_end; /* the step's scheduling policy */
    atomic_int steps_done;              /* steps that have returned */
} sleepy;

static int sleepy_step(void *ctx, float dt_s, wind_step_stats *st)
{
    (void)dt_s;
    (void)st;
    sleepy *z = ctx;
    z->policy_at_start = sched_getscheduler(0);
    nanosleep(&(struct timespec){ .tv_sec = z->ms / 1000, .tv_nsec = z->ms % 1000 * 1000000L },
              NULL);
    z->policy_at_end = sched_getscheduler(0);
    atomic_fetch_add(&z->steps_done, 1);
    return 0;
}

/* Until `steps` steps have returned (at most 10 s), then 100 ms more for the worker to
 * mark the step done: under a loaded machine (ctest -j, sanitizers) a thread at
 * SCHED_IDLE may wait long for a core, so no fixed delay says a step has ended. */
static void await_steps(sleepy *z, int steps)
{
    for (int k = 0; k < 10000 && atomic_load(&z->steps_done) < steps; k++) {
        nanosleep(&(struct timespec){ .tv_nsec = 1000000L }, NULL);
    }
    nanosleep(&(struct timespec){ .tv_nsec = 100000000L }, NULL);
}

/* Beside ticks at the fair scheduler's priority the step runs at SCHED_IDLE; a join that
 * waits for it lends it its own policy (SCHED_OTHER here) until it ends, and a join after
 * it ended lends nothing. */
static void test_worker_lends(void)
{
    if (!wind_worker_unidle_permitted()) {
        printf("  (SCHED_IDLE to SCHED_OTHER not permitted here: lending not checked)\n");
        return;
    }
    sleepy z = { .ms = 50 };
    wind_worker *w = wind_worker_create(sleepy_step, &z, true, NULL);
    CHECK(w != NULL);
    if (!w) {
        return;
    }
    /* joined at once: lent, whether the step had begun (then it began at SCHED_IDLE) or
       not (then it began at the lent policy) */
    wind_join_times jt = { 0 };
    wind_worker_launch(w, 0.1f);
    CHECK(wind_worker_join(w, NULL, &jt) == 0);
    CHECK(jt.wait_ms > 0.0);
    CHECK(z.policy_at_end == SCHED_OTHER);
    /* the next step starts at SCHED_IDLE again, and joined after it ended is lent nothing */
    wind_worker_launch(w, 0.1f);
    await_steps(&z, 2);
    CHECK(wind_worker_join(w, NULL, &jt) == 0);
    CHECK(jt.wait_ms == 0.0);
    CHECK(z.policy_at_start == SCHED_IDLE && z.policy_at_end == SCHED_IDLE);
    wind_worker_destroy(w);
}

/* CAP_SYS_NICE out of every set of this process (a forked child's), as a service user
 * without capabilities has it; 0 on success. */
static int drop_sys_nice(void)
{
    struct __user_cap_header_struct h = { .version = _LINUX_CAPABILITY_VERSION_3 };
    struct __user_cap_data_struct d[2];
    if (syscall(SYS_capget, &h, d) != 0) {
        return -1;
    }
    const unsigned i = CAP_SYS_NICE / 32, bit = 1u << (CAP_SYS_NICE % 32);
    d[i].effective &= ~bit;
    d[i].permitted &= ~bit;
    d[i].inheritable &= ~bit;
    return (int)syscall(SYS_capset, &h, d);
}

/* In a child without CAP_SYS_NICE and with RLIMIT_NICE nice_rlim: the policy a step
 * beside fair ticks starts at, as the exit status (0 SCHED_OTHER, 1 SCHED_IDLE, 2 other,
 * 3 set-up failed). */
static int unprivileged_policy(rlim_t nice_rlim)
{
    const pid_t pid = fork();
    if (pid == 0) {
        if (drop_sys_nice() != 0 ||
            setrlimit(RLIMIT_NICE, &(struct rlimit){ nice_rlim, nice_rlim }) != 0) {
            _exit(3);
        }
        sleepy z = { .ms = 5 };
        wind_worker *w = wind_worker_create(sleepy_step, &z, true, NULL);
        if (!w) {
            _exit(3);
        }
        wind_worker_launch(w, 0.1f);
        await_steps(&z, 1);
        wind_worker_join(w, NULL, NULL);
        wind_worker_destroy(w);
        _exit(z.policy_at_start == SCHED_OTHER ? 0 : z.policy_at_start == SCHED_IDLE ? 1 : 2);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) {
        return 3;
    }
    return WEXITSTATUS(status);
}

/* Where the process may not leave SCHED_IDLE again (no CAP_SYS_NICE, RLIMIT_NICE 0: a
 * plain user's default) no waiting tick could lend the step its priority, so the step runs
 * at SCHED_OTHER; with RLIMIT_NICE 20 (nice 0 allowed: the service's LimitNICE=+0) at
 * SCHED_IDLE. */
static void test_worker_unprivileged(void)
{
    const int strict = unprivileged_policy(0), nice0 = unprivileged_policy(20);
    if (strict == 3) {
        printf("  (CAP_SYS_NICE not dropped here: the strict case not checked)\n");
    } else {
        CHECK(strict == 0);
    }
    if (nice0 == 3) {
        /* raising the hard limit needs CAP_SYS_RESOURCE, which some containers lack */
        printf("  (RLIMIT_NICE 20 not settable here: that case not checked)\n");
    } else {
        CHECK(nice0 == 1);
    }
}

/* What a join reports: a step of at least 50 ms on the worker's thread joined at once is
 * waited for, and one joined after it ended is not; either way the step's own time is
 * at least its sleep. Run in the join (no thread), the step is the join's, not a wait. */
static void test_worker_times(void)
{
    for (int own = 0; own < 2; own++) {
        sleepy z = { .ms = 50 };
        wind_worker *w = wind_worker_create(sleepy_step, &z, own, NULL);
        CHECK(w != NULL);
        if (!w) {
            continue;
        }
        wind_join_times jt = { 0 };
        wind_worker_launch(w, 0.1f);
        CHECK(wind_worker_join(w, NULL, &jt) == 0);
        CHECK(jt.step_ms >= 49.0 && jt.ms >= jt.step_ms - 1.0);
        CHECK(own ? jt.wait_ms > 0.0 && jt.wait_ms <= jt.ms : jt.wait_ms == 0.0);
        wind_worker_launch(w, 0.1f);
        if (own) {
            await_steps(&z, 2);
        }
        CHECK(wind_worker_join(w, NULL, &jt) == 0);
        CHECK(jt.step_ms >= 49.0);
        CHECK(jt.wait_ms == 0.0);
        CHECK(own || jt.ms >= 49.0);
        CHECK(wind_worker_join(w, NULL, &jt) == 0); /* none launched: nothing taken */
        CHECK(jt.step_ms == 0.0 && jt.wait_ms == 0.0);
        wind_worker_destroy(w);
    }
}

int main(void)
{
    RUN(test_step_response);
    RUN(test_balls);
    RUN(test_unconverged);
    RUN(test_leaves_and_errors);
    RUN(test_phases);
    RUN(test_threads_same_tick);
    RUN(test_probe_same_tick);
    RUN(test_worker_times);
    RUN(test_worker_lends);
    RUN(test_worker_unprivileged);
    return check_report();
}
