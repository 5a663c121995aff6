/* Wind field tests (Oliapuram & Kumar 2010 section 2): the projection meets its divergence
 * reduction on random and obstacle-rich fields, no flux through solid faces, uniform
 * inflow stays uniform, advection against closed-form displacements, determinism, force
 * ball direction, trilinear sampling, the probe's stencils and the lines they read, the
 * coarse copy and bad descs. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "wind.h"
#include "wind_int.h"

static uint64_t rng_state = 12345;

static float frand(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (float)((double)(rng_state >> 40) / 16777216.0) * 2.0f - 1.0f;
}

static float *at(wind_grid *w, int a, int i, int j, int k)
{
    wind_comp *c = &w->c[a];
    return c->d + wind_idx(c->sy, c->sz, i, j, k);
}

static void randomise(wind_grid *w, float amp)
{
    for (int a = 0; a < 3; a++) {
        wind_comp *c = &w->c[a];
        for (int k = 0; k < c->n[2]; k++) {
            for (int j = 0; j < c->n[1]; j++) {
                for (int i = 0; i < c->n[0]; i++) {
                    *at(w, a, i, j, k) = amp * frand();
                }
            }
        }
    }
}

static int is_solid(const wind_grid *w, int i, int j, int k)
{
    return w->solid[wind_idx(w->nx + 2, (w->nx + 2) * (w->ny + 2), i, j, k)];
}

/* Every face of a solid cell carries exactly zero normal velocity; returns the largest
 * magnitude found. */
static float max_solid_flux(wind_grid *w)
{
    float m = 0.0f;
    for (int k = 0; k < w->nz; k++) {
        for (int j = 0; j < w->ny; j++) {
            for (int i = 0; i < w->nx; i++) {
                if (!is_solid(w, i, j, k)) {
                    continue;
                }
                float f[6] = { *at(w, 0, i, j, k), *at(w, 0, i + 1, j, k), *at(w, 1, i, j, k),
                               *at(w, 1, i, j + 1, k), *at(w, 2, i, j, k),
                               *at(w, 2, i, j, k + 1) };
                for (int q = 0; q < 6; q++) {
                    m = fmaxf(m, fabsf(f[q]));
                }
            }
        }
    }
    return m;
}

/* Steps from a fresh random field several times; the reduction must hold every step,
 * both as the solver reports it and recomputed from the face velocities. */
static void check_reduction(wind_grid *w, const wind_inflow *in, int steps)
{
    wind_set_inflow(w, in);
    for (int s = 0; s < steps; s++) {
        randomise(w, 5.0f);
        wind_step_stats st;
        CHECK(wind_step(w, 0.05f, &st) == 0);
        double after = wind_divergence_rms(w);
        CHECK(st.div_before > 0.0);
        CHECK(st.div_after * 100.0 <= st.div_before);
        /* recomputed in double from the projected faces: equal to the solver's residual up
         * to float rounding of the face updates (1 % of the bound) */
        CHECK(after * 100.0 <= st.div_before * 1.01);
        CHECK(st.iterations >= 1 && st.iterations <= 30);
        CHECK_NEAR(st.residual, st.div_after / st.div_before, 1e-9);
    }
}

static void test_reduction_random(void)
{
    for (int threads = 1; threads <= 2; threads++) {
        gale_err err = { 0 };
        wind_grid *w = wind_create(&(wind_desc){ .nx = 32, .ny = 32, .nz = 8, .threads = threads },
                                   &err);
        CHECK(w != NULL);
        if (!w) {
            return;
        }
        check_reduction(w, &(wind_inflow){ 0 }, 4);
        check_reduction(w, &(wind_inflow){ .dir_rad = 0.6f, .u10_ms = 12.0f }, 4);
        wind_destroy(w);
    }
}

static void test_reduction_obstacles(void)
{
    /* 30 random boxes on an odd-sized grid (exercises uneven coarsening) */
    wind_box boxes[30];
    const float h = 2.0f;
    for (int b = 0; b < 30; b++) {
        float cx = (0.5f + 0.5f * frand()) * 45.0f * h, cy = (0.5f + 0.5f * frand()) * 37.0f * h;
        float sx = (3.0f + 3.0f * (frand() + 1.0f)) * h, sy = (2.0f + 3.0f * (frand() + 1.0f)) * h;
        float top = (2.0f + 3.0f * (frand() + 1.0f)) * h;
        boxes[b] = (wind_box){ .min = { cx - sx, cy - sy, -1.0f }, .max = { cx + sx, cy + sy, top } };
    }
    gale_err err = { 0 };
    wind_grid *w = wind_create(&(wind_desc){ .nx = 45, .ny = 37, .nz = 10, .cell_m = h,
                                             .obstacles = boxes, .n_obstacles = 30 },
                               &err);
    CHECK(w != NULL);
    if (!w) {
        return;
    }
    int solid = 0;
    for (int k = 0; k < w->nz; k++) {
        for (int j = 0; j < w->ny; j++) {
            for (int i = 0; i < w->nx; i++) {
                solid += is_solid(w, i, j, k);
            }
        }
    }
    /* obstacle-rich: at least a fifth of the volume solid */
    CHECK(solid * 5 >= w->nx * w->ny * w->nz);
    check_reduction(w, &(wind_inflow){ .dir_rad = 2.5f, .u10_ms = 20.0f }, 5);
    CHECK(max_solid_flux(w) == 0.0f);
    /* and when the field is driven only by the inflow and a ball */
    wind_fill_inflow(w);
    for (int s = 0; s < 10; s++) {
        wind_add_ball(w, &(wind_ball){ .center = { 40.0f, 30.0f, 6.0f }, .radius_m = 8.0f,
                                       .force = { 50.0f, 20.0f, 5.0f }, .jitter_m = 4.0f });
        wind_step_stats st;
        CHECK(wind_step(w, 0.05f, &st) == 0);
        CHECK(st.div_before <= 0.0 || st.div_after * 100.0 <= st.div_before);
    }
    CHECK(max_solid_flux(w) == 0.0f);
    wind_destroy(w);
}

static float log_law(float z, float u10, float z0, float zmin)
{
    z = fmaxf(z, zmin);
    return u10 * logf(z / z0) / logf(10.0f / z0);
}

static void test_uniform_inflow(void)
{
    const float dirs[2] = { 0.0f, 0.7f };
    for (int q = 0; q < 2; q++) {
        gale_err err = { 0 };
        const float h = 2.5f;
        wind_grid *w = wind_create(&(wind_desc){ .nx = 32, .ny = 24, .nz = 8, .cell_m = h }, &err);
        CHECK(w != NULL);
        if (!w) {
            return;
        }
        wind_inflow in = { .dir_rad = dirs[q], .u10_ms = 15.0f, .gust = { 1.5f, -0.5f, 0.0f } };
        wind_set_inflow(w, &in);
        wind_fill_inflow(w);
        for (int s = 0; s < 20; s++) {
            wind_step_stats st;
            CHECK(wind_step(w, 0.05f, &st) == 0);
        }
        float err_max = 0.0f;
        for (int k = 0; k < w->nz; k++) {
            float z = ((float)k + 0.5f) * h;
            /* defaults: z0 = 0.3 m, zmin = 5 m */
            float u = log_law(z, 15.0f, 0.3f, 5.0f);
            float eu = u * cosf(dirs[q]) + 1.5f, ev = u * sinf(dirs[q]) - 0.5f;
            for (int j = 0; j < w->ny; j++) {
                for (int i = 0; i < w->nx; i++) {
                    err_max = fmaxf(err_max, fabsf(*at(w, 0, i, j, k) - eu));
                    err_max = fmaxf(err_max, fabsf(*at(w, 1, i, j, k) - ev));
                    err_max = fmaxf(err_max, fabsf(*at(w, 2, i, j, k)));
                }
            }
        }
        /* float rounding of a 15 m/s field over 20 steps */
        CHECK_NEAR(err_max, 0.0, 1e-4);
        wind_destroy(w);
    }
}

/* u = U0, v = A sin(kx), w = 0 solves the inviscid equations with v(x, t) = A sin(k(x -
 * U0 t)) (v depends on x only, so v dv/dy = 0). A whole-cell displacement per step is
 * reproduced exactly by the trilinear back-trace (up to rounding), both by the one-cell
 * path and the general one (two cells); a half-cell one damps each step by cos(kh/2)
 * with the phase exact (the two-point average of a sine). */
static void test_advection_closed_form(void)
{
    const float h = 1.0f, A = 0.2f, L = 16.0f, kw = 2.0f * (float)M_PI / L;
    const float shifts[3] = { 1.0f, 0.5f, 2.0f };
    for (int q = 0; q < 3; q++) {
        gale_err err = { 0 };
        wind_grid *w = wind_create(&(wind_desc){ .nx = 64, .ny = 40, .nz = 4, .cell_m = h }, &err);
        CHECK(w != NULL);
        if (!w) {
            return;
        }
        const float dt = 0.1f, U0 = shifts[q] * h / dt;
        for (int a = 0; a < 3; a++) {
            memset(w->c[a].d, 0, w->c[a].count * sizeof(float));
        }
        for (int k = 0; k < 4; k++) {
            for (int j = 0; j < 40; j++) {
                for (int i = 0; i <= 64; i++) {
                    *at(w, 0, i, j, k) = U0;
                }
                for (int i = 0; i < 64; i++) {
                    *at(w, 1, i, j, k) = A * sinf(kw * ((float)i + 0.5f) * h);
                }
            }
            for (int i = 0; i < 64; i++) {
                *at(w, 1, i, 40, k) = A * sinf(kw * ((float)i + 0.5f) * h);
            }
        }
        const int steps = 8;
        for (int s = 0; s < steps; s++) {
            wind_fill_ghosts(w);
            wind_advect(w, dt / h);
        }
        float t = (float)steps * dt;
        float damp = q != 1 ? 1.0f : powf(cosf(0.5f * kw * h), (float)steps);
        float e_max = 0.0f, u_max = 0.0f;
        /* cells the calm far field of the ghost layer can reach in 8 steps (one cell per
         * step of interpolation support plus the displacement) are skipped */
        for (int k = 0; k < 4; k++) {
            for (int j = 10; j < 30; j++) {
                for (int i = 4 + steps * (1 + (int)shifts[q]); i < 54; i++) {
                    float x = ((float)i + 0.5f) * h;
                    float ex = damp * A * sinf(kw * (x - U0 * t));
                    e_max = fmaxf(e_max, fabsf(*at(w, 1, i, j, k) - ex));
                    u_max = fmaxf(u_max, fabsf(*at(w, 0, i, j, k) - U0));
                }
            }
        }
        CHECK_NEAR(e_max, 0.0, 2e-5);
        CHECK_NEAR(u_max, 0.0, 1e-5);
        wind_destroy(w);
    }
}

/* Sample (i, j, k) of component a of a saved padded copy (ghosts at -1 and n). */
static float saved_at(const wind_grid *w, float *const src[3], int a, int i, int j, int k)
{
    const wind_comp *c = &w->c[a];
    return src[a][wind_idx(c->sy, c->sz, i, j, k)];
}

/* Eq. 4 done the slow way, independently of wind_advect.c's row kernels: the velocity at
 * the face sample (own component, the others averaged over their four nearest samples),
 * the foot x - dt v in cell units clamped to the ghost range, a trilinear read there. */
static float ref_advect(const wind_grid *w, float *const src[3], int a, int i, int j, int k,
                        float s)
{
    const int o[3] = { i, j, k };
    float d[3];
    for (int b = 0; b < 3; b++) {
        if (b == a) {
            d[b] = s * saved_at(w, src, a, i, j, k);
            continue;
        }
        /* component b's samples sit half a cell from a's along a and b */
        double sum = 0.0;
        for (int q = 0; q < 4; q++) {
            int p[3] = { i, j, k };
            p[a] -= (q & 1) ? 0 : 1;
            p[b] += (q & 2) ? 1 : 0;
            sum += (double)saved_at(w, src, b, p[0], p[1], p[2]);
        }
        d[b] = s * (float)(sum * 0.25);
    }
    const wind_comp *c = &w->c[a];
    int i0[3];
    double t[3];
    for (int b = 0; b < 3; b++) {
        double f = (double)o[b] - (double)d[b];
        f = fmin(fmax(f, -1.0), (double)c->n[b]);
        i0[b] = (int)floor(f);
        i0[b] = i0[b] > c->n[b] - 1 ? c->n[b] - 1 : i0[b];
        t[b] = f - (double)i0[b];
    }
    double v = 0.0;
    for (int q = 0; q < 8; q++) {
        int di = q & 1, dj = (q >> 1) & 1, dk = (q >> 2) & 1;
        double wt = (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dk ? t[2] : 1 - t[2]);
        v += wt * (double)saved_at(w, src, a, i0[0] + di, i0[1] + dj, i0[2] + dk);
    }
    return (float)v;
}

/* A random field advected one step matches the slow reference at every sample: small
 * displacements (every row by the one-cell kernel) and large ones (most rows by the
 * general back-trace, with ghost reads). */
static void test_advection_reference(void)
{
    const float amps[2] = { 0.9f, 3.0f };
    for (int q = 0; q < 2; q++) {
        gale_err err = { 0 };
        wind_grid *w = wind_create(&(wind_desc){ .nx = 37, .ny = 21, .nz = 6, .cell_m = 1.0f,
                                                 .threads = 2 },
                                   &err);
        CHECK(w != NULL);
        if (!w) {
            return;
        }
        wind_set_inflow(w, &(wind_inflow){ .dir_rad = 0.4f, .u10_ms = 3.0f });
        wind_fill_inflow(w);
        randomise(w, amps[q]);
        wind_fill_ghosts(w);
        float *src[3];
        for (int a = 0; a < 3; a++) {
            src[a] = malloc(w->c[a].count * sizeof(float));
            CHECK(src[a] != NULL);
            if (!src[a]) {
                return;
            }
            memcpy(src[a], w->c[a].d, w->c[a].count * sizeof(float));
        }
        /* dt / h = 0.5: the first field moves at most 0.45 cells, the second up to 1.5 */
        wind_advect(w, 0.5f);
        float e_max = 0.0f;
        for (int a = 0; a < 3; a++) {
            const wind_comp *c = &w->c[a];
            for (int k = 0; k < c->n[2]; k++) {
                for (int j = 0; j < c->n[1]; j++) {
                    for (int i = 0; i < c->n[0]; i++) {
                        float ref = ref_advect(w, src, a, i, j, k, 0.5f);
                        e_max = fmaxf(e_max, fabsf(*at(w, a, i, j, k) - ref));
                    }
                }
            }
        }
        /* float rounding of a handful of lerps of values up to amps[q]; the general path
         * also rounds the foot's coordinate (up to 37 cells: ulp 4e-6) times a gradient
         * of up to 2 amps[q] per cell */
        CHECK_NEAR(e_max, 0.0, (q == 0 ? 2e-6 : 1e-5) * (double)amps[q]);
        for (int a = 0; a < 3; a++) {
            free(src[a]);
        }
        wind_destroy(w);
    }
}

static void run_scripted(wind_grid *w)
{
    wind_set_inflow(w, &(wind_inflow){ .dir_rad = 1.0f, .u10_ms = 10.0f, .gust = { 1, 0, 0 } });
    for (int s = 0; s < 12; s++) {
        wind_add_ball(w, &(wind_ball){ .center = { 30.0f, 30.0f, 5.0f }, .radius_m = 6.0f,
                                       .force = { 40.0f, -10.0f, 3.0f }, .jitter_m = 5.0f });
        CHECK(wind_step(w, 1.0f / 30.0f, NULL) == 0);
    }
}

static int same_field(const wind_grid *a, const wind_grid *b)
{
    for (int c = 0; c < 3; c++) {
        if (memcmp(a->c[c].d, b->c[c].d, a->c[c].count * sizeof(float)) != 0) {
            return 0;
        }
    }
    return 1;
}

static void test_determinism(void)
{
    wind_box box = { .min = { 40, 40, 0 }, .max = { 50, 46, 8 } };
    wind_desc d = { .nx = 40, .ny = 36, .nz = 8, .seed = 7, .threads = 2, .obstacles = &box,
                    .n_obstacles = 1 };
    gale_err err = { 0 };
    wind_grid *a = wind_create(&d, &err), *b = wind_create(&d, &err);
    d.seed = 8;
    wind_grid *c = wind_create(&d, &err);
    d.seed = 7;
    d.threads = 1;
    wind_grid *e = wind_create(&d, &err);
    CHECK(a && b && c && e);
    if (a && b && c && e) {
        run_scripted(a);
        run_scripted(b);
        run_scripted(c);
        run_scripted(e);
        CHECK(same_field(a, b));
        /* the seed drives the jitter: another seed gives another field */
        CHECK(!same_field(a, c));
        /* row-partitioned sums: the thread count does not change the bits either */
        CHECK(same_field(a, e));
    }
    wind_destroy(a);
    wind_destroy(b);
    wind_destroy(c);
    wind_destroy(e);
}

static void test_ball_direction(void)
{
    const float forces[3][3] = { { 20, 0, 0 }, { 0, -20, 0 }, { 0, 0, 20 } };
    for (int q = 0; q < 3; q++) {
        gale_err err = { 0 };
        wind_grid *w = wind_create(&(wind_desc){ .nx = 32, .ny = 32, .nz = 16, .cell_m = 1.0f },
                                   &err);
        CHECK(w != NULL);
        if (!w) {
            return;
        }
        const float dt = 0.05f;
        wind_ball b = { .center = { 16, 16, 8 }, .radius_m = 3.0f };
        memcpy(b.force, forces[q], sizeof b.force);
        wind_add_ball(w, &b);
        CHECK(wind_step(w, dt, NULL) == 0);
        float v[3];
        wind_sample(w, b.center, v);
        for (int a = 0; a < 3; a++) {
            float f = dt * forces[q][a];
            if (f != 0.0f) {
                /* same sign as the force; projection keeps between a third and all of it
                 * at the centre of an isolated Gaussian (the rest returns around it) */
                CHECK(v[a] * f > 0.0f);
                CHECK(fabsf(v[a]) >= fabsf(f) / 3.0f && fabsf(v[a]) <= fabsf(f));
            } else {
                CHECK_NEAR(v[a], 0.0, 1e-3 * (double)fabsf(dt * 20.0f));
            }
        }
        /* the ball is used for one step only */
        wind_step_stats st;
        CHECK(wind_step(w, dt, &st) == 0);
        wind_destroy(w);
    }
}

/* Independent trilinear reference on a component's lattice: sample (i, j, k) sits at
 * origin + h (i + off). */
static float ref_trilinear(wind_grid *w, int a, const float p[3])
{
    wind_comp *c = &w->c[a];
    float f[3];
    int i0[3];
    for (int d = 0; d < 3; d++) {
        f[d] = (p[d] - w->d.origin[d]) / w->h - c->off[d];
        f[d] = fminf(fmaxf(f[d], 0.0f), (float)(c->n[d] - 1));
        i0[d] = (int)floorf(f[d]);
        if (i0[d] > c->n[d] - 2) {
            i0[d] = c->n[d] - 2;
        }
        f[d] -= (float)i0[d];
    }
    float s = 0.0f;
    for (int q = 0; q < 8; q++) {
        int di = q & 1, dj = (q >> 1) & 1, dk = (q >> 2) & 1;
        float wt = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
        s += wt * *at(w, a, i0[0] + di, i0[1] + dj, i0[2] + dk);
    }
    return s;
}

static void test_sampling(void)
{
    gale_err err = { 0 };
    wind_grid *w = wind_create(&(wind_desc){ .nx = 12, .ny = 10, .nz = 6, .cell_m = 1.5f,
                                             .origin = { -5, 3, 0 } },
                               &err);
    CHECK(w != NULL);
    if (!w) {
        return;
    }
    randomise(w, 3.0f);
    /* Enough points for the threaded, vectorised path of wind_sample_many; some beyond
     * every side of the grid, to check clamping. */
    enum { NP = 5000 };
    static float pts[3 * NP], many[3 * NP];
    for (int n = 0; n < NP; n++) {
        pts[3 * n + 0] = -5.0f + (-0.2f + 1.4f * frand()) * 18.0f;
        pts[3 * n + 1] = 3.0f + (-0.2f + 1.4f * frand()) * 15.0f;
        pts[3 * n + 2] = (-0.2f + 1.4f * frand()) * 9.0f;
    }
    wind_sample_many(w, NP, pts, many);
    for (int n = 0; n < NP; n++) {
        float v[3];
        wind_sample(w, pts + 3 * n, v);
        for (int a = 0; a < 3; a++) {
            CHECK_NEAR(v[a], ref_trilinear(w, a, pts + 3 * n), 1e-5);
            CHECK(v[a] == many[3 * n + a]);
        }
    }
    /* a face sample is reproduced exactly */
    float p[3] = { -5.0f + 3 * 1.5f, 3.0f + 4.5f * 1.5f, 2.5f * 1.5f }, v[3];
    wind_sample(w, p, v);
    CHECK_NEAR(v[0], *at(w, 0, 3, 4, 2), 1e-6);
    wind_destroy(w);
}

/* A probe's stencils read the grid as wind_sample does, float for float, at points
 * inside and beyond every side, with and without the subgrid profile, after the field
 * changed under them (a step, a new inflow): the tick reads its crowns so. */
static void test_probe(void)
{
    for (int subgrid = 0; subgrid < 2; subgrid++) {
        gale_err err = { 0 };
        wind_grid *w = wind_create(&(wind_desc){ .nx = 14, .ny = 11, .nz = 3, .cell_m = 4.0f,
                                                 .origin = { -20, 7, 0 },
                                                 .subgrid_profile = subgrid, .threads = 1 },
                                   &err);
        CHECK(w != NULL);
        if (!w) {
            return;
        }
        enum { NP = 3000 };
        static float pts[3 * NP], got[3 * NP];
        for (int n = 0; n < NP; n++) {
            pts[3 * n + 0] = -20.0f + (-0.2f + 1.4f * frand()) * 56.0f;
            pts[3 * n + 1] = 7.0f + (-0.2f + 1.4f * frand()) * 44.0f;
            pts[3 * n + 2] = (-0.2f + 1.4f * frand()) * 12.0f;
        }
        wind_probe *pr = wind_probe_create(w, NP, pts, &err);
        CHECK(pr != NULL);
        if (!pr) {
            wind_destroy(w);
            return;
        }
        int bad = 0;
        for (int round = 0; round < 3; round++) {
            if (round == 1) {
                randomise(w, 3.0f);
            } else if (round == 2) {
                wind_set_inflow(w, &(wind_inflow){ .dir_rad = 2.1f, .u10_ms = 17.0f });
                CHECK(wind_step(w, 0.1f, NULL) == 0);
            }
            /* in two shares, as the tick's threads split them */
            wind_probe_sample(w, pr, 0, 1000, got);
            wind_probe_sample(w, pr, 1000, NP, got);
            wind_add_subgrid(w, NP, pts, got);
            for (int n = 0; n < NP; n++) {
                float v[3];
                wind_sample(w, pts + 3 * n, v);
                bad += memcmp(v, got + 3 * n, sizeof v) != 0;
            }
        }
        CHECK(bad == 0);
        wind_probe_destroy(pr);
        wind_destroy(w);
    }
}

/* wind_probe_lines: the distinct 64-byte lines the stencils read, against a count of its
 * own (each point's eight samples per component found as ref_trilinear finds them,
 * marked in a bitmap of each component's lines), for ranges of random points inside and
 * beyond every side; a point read twice adds no line, an empty range reads none. */
static void test_probe_lines(void)
{
    gale_err err = { 0 };
    wind_grid *w = wind_create(&(wind_desc){ .nx = 40, .ny = 23, .nz = 5, .cell_m = 2.0f,
                                             .origin = { -10, 4, 0 }, .threads = 1 },
                               &err);
    CHECK(w != NULL);
    if (!w) {
        return;
    }
    enum { NP = 400 };
    static float pts[3 * 2 * NP];
    for (int n = 0; n < NP; n++) {
        pts[3 * n + 0] = -10.0f + (-0.2f + 1.4f * frand()) * 80.0f;
        pts[3 * n + 1] = 4.0f + (-0.2f + 1.4f * frand()) * 46.0f;
        pts[3 * n + 2] = (-0.2f + 1.4f * frand()) * 10.0f;
    }
    memcpy(pts + 3 * NP, pts, sizeof(float) * 3 * NP); /* the same points again */
    wind_probe *pr = wind_probe_create(w, 2 * NP, pts, &err);
    CHECK(pr != NULL);
    if (!pr) {
        wind_destroy(w);
        return;
    }
    const int ranges[][2] = { { 0, NP }, { 0, 1 }, { 17, 18 }, { 5, 60 }, { 0, 2 * NP },
                              { NP - 30, NP + 30 } };
    for (size_t r = 0; r < sizeof ranges / sizeof ranges[0]; r++) {
        size_t want = 0;
        for (int a = 0; a < 3; a++) {
            const wind_comp *c = &w->c[a];
            const uintptr_t base = (uintptr_t)c->d / 64u;
            const size_t n_lines = ((uintptr_t)(c->d + c->count) + 63u) / 64u - base;
            unsigned char *seen = calloc(n_lines, 1);
            CHECK(seen != NULL);
            if (!seen) {
                break;
            }
            for (int n = ranges[r][0]; n < ranges[r][1]; n++) {
                const float *p = pts + 3 * n;
                int i0[3];
                for (int d = 0; d < 3; d++) {
                    float f = (p[d] - w->d.origin[d]) / w->h - c->off[d];
                    f = fminf(fmaxf(f, 0.0f), (float)(c->n[d] - 1));
                    i0[d] = (int)floorf(f);
                    i0[d] = i0[d] > c->n[d] - 2 ? c->n[d] - 2 : i0[d];
                }
                for (int q = 0; q < 8; q++) {
                    const float *s = c->d + wind_idx(c->sy, c->sz, i0[0] + (q & 1),
                                                     i0[1] + ((q >> 1) & 1),
                                                     i0[2] + ((q >> 2) & 1));
                    const size_t line = (uintptr_t)s / 64u - base;
                    want += !seen[line];
                    seen[line] = 1;
                }
            }
            free(seen);
        }
        size_t got = 0;
        CHECK(wind_probe_lines(w, pr, ranges[r][0], ranges[r][1], &got, &err) == 0);
        CHECK(got == want);
        /* one point reads four to eight lines a component (a pair along x may straddle) */
        if (ranges[r][1] - ranges[r][0] == 1) {
            CHECK(got >= 12 && got <= 24);
        }
    }
    size_t all = 0, first = 0, none = 1;
    CHECK(wind_probe_lines(w, pr, 0, 2 * NP, &all, &err) == 0);
    CHECK(wind_probe_lines(w, pr, 0, NP, &first, &err) == 0);
    CHECK(all == first && all > 0);
    CHECK(wind_probe_lines(w, pr, 9, 9, &none, &err) == 0);
    CHECK(none == 0);
    wind_probe_destroy(pr);
    wind_destroy(w);
}

/* wind_publish: the samplers (wind_sample, wind_probe_sample, wind_coarse) read the field
 * as it stood at the last publish while the grid steps on, float for float what a twin
 * grid stepped only that far gives; wind_set_subgrid_inflow moves the subgrid term at once
 * and leaves the step's inflow as wind_set_inflow gave it. */
static void test_publish(void)
{
    const wind_desc d = { .nx = 12, .ny = 10, .nz = 3, .cell_m = 4.0f, .origin = { -24, -20, 0 },
                          .subgrid_profile = 1, .threads = 1, .seed = 5 };
    wind_grid *a = wind_create(&d, NULL), *b = wind_create(&d, NULL);
    CHECK(a && b);
    if (!a || !b) {
        wind_destroy(a);
        wind_destroy(b);
        return;
    }
    enum { NP = 500 };
    static float pts[3 * NP], va[3 * NP], vb[3 * NP];
    for (int n = 0; n < NP; n++) {
        pts[3 * n + 0] = -24.0f + frand() * 48.0f;
        pts[3 * n + 1] = -20.0f + frand() * 40.0f;
        pts[3 * n + 2] = frand() * 12.0f;
    }
    wind_probe *pr = wind_probe_create(a, NP, pts, NULL);
    CHECK(pr != NULL);
    const wind_inflow x = { .dir_rad = 0.4f, .u10_ms = 12.0f, .gust = { 1.0f, -0.5f, 0 } };
    const wind_inflow y = { .dir_rad = 1.3f, .u10_ms = 21.0f };
    const wind_inflow z = { .dir_rad = 2.6f, .u10_ms = 7.0f };
    float ca[3 * 3 * 3 * 1], cb[3 * 3 * 3 * 1];
    int dims[3];
    for (int round = 0; round < 2 && pr; round++) {
        /* a: stepped under x (then y), published, stepped again under y, the subgrid
           term then z's; b: the steps up to the publish only, the subgrid term z's */
        wind_set_inflow(a, round ? &y : &x);
        wind_set_inflow(b, round ? &y : &x);
        CHECK(wind_step(a, 0.2f, NULL) == 0 && wind_step(b, 0.2f, NULL) == 0);
        CHECK(wind_publish(a) == 0);
        wind_set_inflow(a, &y);
        CHECK(wind_step(a, 0.2f, NULL) == 0);
        wind_set_subgrid_inflow(a, &z);
        wind_set_subgrid_inflow(b, &z);
        int bad = 0;
        for (int n = 0; n < NP; n++) {
            wind_sample(a, pts + 3 * n, va + 3 * n);
            wind_sample(b, pts + 3 * n, vb + 3 * n);
        }
        bad += memcmp(va, vb, sizeof va) != 0;
        wind_probe_sample(a, pr, 0, NP, va);
        wind_add_subgrid(a, NP, pts, va);
        bad += memcmp(va, vb, sizeof va) != 0;
        CHECK(wind_coarse(a, 4, ca, 27, dims) == 27 && wind_coarse(b, 4, cb, 27, dims) == 27);
        bad += memcmp(ca, cb, sizeof ca) != 0;
        CHECK(bad == 0);
        /* b's next step is a's last: only a publish shows it, and then exactly */
        wind_set_inflow(b, &y);
        CHECK(wind_step(b, 0.2f, NULL) == 0);
        wind_set_subgrid_inflow(b, &z);
        wind_sample_many(a, NP, pts, va);
        wind_sample_many(b, NP, pts, vb);
        CHECK(memcmp(va, vb, sizeof va) != 0);
        CHECK(wind_publish(a) == 0);
        wind_sample_many(a, NP, pts, va);
        CHECK(memcmp(va, vb, sizeof va) == 0);
        /* both one step on, a under the inflow its last wind_set_inflow gave (y: the
           subgrid inflow since must not reach the step), b under y given afresh */
        wind_set_inflow(b, &y);
        CHECK(wind_step(b, 0.2f, NULL) == 0);
        CHECK(wind_step(a, 0.2f, NULL) == 0);
        CHECK(wind_publish(a) == 0);
    }
    wind_probe_destroy(pr);
    wind_destroy(a);
    wind_destroy(b);
}

static void test_coarse(void)
{
    gale_err err = { 0 };
    wind_grid *w = wind_create(&(wind_desc){ .nx = 10, .ny = 8, .nz = 3 }, &err);
    CHECK(w != NULL);
    if (!w) {
        return;
    }
    randomise(w, 2.0f);
    float out[3 * 3 * 2 * 1];
    int dims[3];
    CHECK(wind_coarse(w, 4, out, 3, dims) == GALE_E_RANGE);
    CHECK(wind_coarse(w, 0, out, 18, dims) == GALE_E_ARG);
    int n = wind_coarse(w, 4, out, 18, dims);
    CHECK(n == 18);
    CHECK(dims[0] == 3 && dims[1] == 2 && dims[2] == 1);
    /* block (2, 1, 0): cells x 8..9, y 4..7, z 0..2 (factor capped to nz = 3) */
    double s = 0.0;
    for (int k = 0; k < 3; k++) {
        for (int j = 4; j < 8; j++) {
            for (int i = 8; i < 10; i++) {
                s += 0.5 * ((double)*at(w, 1, i, j, k) + (double)*at(w, 1, i, j + 1, k));
            }
        }
    }
    CHECK_NEAR(out[3 * (1 * 3 + 2) + 1], s / 24.0, 1e-5);
    wind_destroy(w);
}

static void test_bad_desc(void)
{
    gale_err err = { 0 };
    CHECK(wind_create(&(wind_desc){ .nx = -3, .ny = 4, .nz = 4 }, &err) == NULL);
    CHECK(err.code == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "wind_desc.nx: expected 1..4096 cells, got -3");
    wind_box bad = { .min = { 0, 0, 0 }, .max = { 4, -1, 3 } };
    CHECK(wind_create(&(wind_desc){ .obstacles = &bad, .n_obstacles = 1 }, &err) == NULL);
    CHECK_STR_HAS(err.msg, "wind_desc.obstacles[0]: axis 1");
    CHECK(wind_create(&(wind_desc){ .cell_m = -1.0f }, &err) == NULL);
    CHECK_STR_HAS(err.msg, "wind_desc.cell_m");
    CHECK(wind_create(&(wind_desc){ .div_reduction = 0.5f }, &err) == NULL);
    CHECK_STR_HAS(err.msg, "wind_desc.div_reduction");
    wind_grid *w = wind_create(&(wind_desc){ .nx = 8, .ny = 8, .nz = 2 }, &err);
    CHECK(w != NULL);
    if (w) {
        wind_desc d = wind_get_desc(w);
        CHECK(d.cell_m == 2.0f && d.div_reduction == 100.0f && d.threads == 2);
        CHECK(wind_step(w, -1.0f, NULL) == GALE_E_ARG);
        CHECK(wind_step(w, NAN, NULL) == GALE_E_ARG);
        wind_destroy(w);
    }
    wind_destroy(NULL);
}

int main(void)
{
    RUN(test_reduction_random);
    RUN(test_reduction_obstacles);
    RUN(test_uniform_inflow);
    RUN(test_advection_closed_form);
    RUN(test_advection_reference);
    RUN(test_determinism);
    RUN(test_ball_direction);
    RUN(test_sampling);
    RUN(test_probe);
    RUN(test_probe_lines);
    RUN(test_publish);
    RUN(test_coarse);
    RUN(test_bad_desc);
    return check_report();
}
