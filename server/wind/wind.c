/* The wind grid: stable fluids on a staggered grid (Oliapuram & Kumar 2010 section 2,
 * eqs. 4-10): advect, add forces (section 2.3 Gaussian ball and border inflow), project
 * with a multigrid pressure solve, free-slip ground and obstacle boxes. Sampling and the
 * coarse copy for clients live here too.
 *
 * Why a staggered (MAC) grid: each velocity component lives on the cell faces normal to
 * it, so the no-flux condition of eq. 10 at a solid face is one sample set to zero, exact
 * and without a stencil special case, and the tangential components there are left free
 * (free slip). Divergence and pressure gradient are then compact two-point differences:
 * the projected field is discretely divergence-free up to the solver residual, with no
 * checkerboard pressure modes that a collocated grid (the paper's float4 voxels) lets
 * through. */
#include <stdbool.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mono.h"
#include "wind_int.h"
#include "hash.h"

#define WIND_MAX_CELLS_AXIS 4096
#define WIND_DEFAULT_MAX_IT 30
/* A border becomes an inflow border when the wind at 10 m enters through it faster than
 * WIND_INFLOW_ON [m/s] and returns to open (p = 0) below WIND_INFLOW_OFF: the hysteresis
 * keeps gusts around calm from rebuilding the solver's coefficients every tick. */
#define WIND_INFLOW_ON 0.5f
#define WIND_INFLOW_OFF 0.2f


/* Uniform in [-1, 1). */
static float rng_sym(uint64_t *s)
{
    return (float)((double)(hash64_splitmix(s) >> 11) * (2.0 / 9007199254740992.0) - 1.0);
}

static int resolve_desc(const wind_desc *in, wind_desc *d, gale_err *err)
{
    *d = *in;
    if (d->nx == 0 && d->ny == 0 && d->nz == 0) {
        d->nx = 256;
        d->ny = 256;
        d->nz = 16;
    }
    const int n[3] = { d->nx, d->ny, d->nz };
    const char *names[3] = { "nx", "ny", "nz" };
    for (int a = 0; a < 3; a++) {
        if (n[a] < 1 || n[a] > WIND_MAX_CELLS_AXIS) {
            return gale_errf(err, GALE_E_RANGE, "wind_desc.%s: expected 1..%d cells, got %d",
                             names[a], WIND_MAX_CELLS_AXIS, n[a]);
        }
    }
    if (d->cell_m == 0.0f) {
        d->cell_m = 2.0f;
    }
    if (!(d->cell_m > 0.0f) || !isfinite(d->cell_m)) {
        return gale_errf(err, GALE_E_RANGE, "wind_desc.cell_m: expected > 0 m, got %g",
                         (double)d->cell_m);
    }
    for (int a = 0; a < 3; a++) {
        if (!isfinite(d->origin[a])) {
            return gale_errf(err, GALE_E_RANGE, "wind_desc.origin[%d]: expected finite, got %g",
                             a, (double)d->origin[a]);
        }
    }
    if (d->div_reduction == 0.0f) {
        d->div_reduction = 100.0f;
    }
    if (!(d->div_reduction >= 1.0f) || !(d->div_reduction <= 1e6f)) {
        return gale_errf(err, GALE_E_RANGE, "wind_desc.div_reduction: expected 1..1e6, got %g",
                         (double)d->div_reduction);
    }
    if (d->max_iterations == 0) {
        d->max_iterations = WIND_DEFAULT_MAX_IT;
    }
    if (d->max_iterations < 1 || d->max_iterations > 10000) {
        return gale_errf(err, GALE_E_RANGE, "wind_desc.max_iterations: expected 1..10000, got %d",
                         d->max_iterations);
    }
    if (d->threads == 0) {
        d->threads = 2;
    }
    if (d->threads < 1 || d->threads > 256) {
        return gale_errf(err, GALE_E_RANGE, "wind_desc.threads: expected 1..256, got %d",
                         d->threads);
    }
    if (d->subgrid_profile != 0 && d->subgrid_profile != 1) {
        return gale_errf(err, GALE_E_RANGE, "wind_desc.subgrid_profile: expected 0 or 1, got %d",
                         d->subgrid_profile);
    }
    if (d->n_obstacles < 0 || (d->n_obstacles > 0 && !d->obstacles)) {
        return gale_errf(err, GALE_E_ARG, "wind_desc.obstacles: %d boxes given without an array",
                         d->n_obstacles);
    }
    for (int b = 0; b < d->n_obstacles; b++) {
        for (int a = 0; a < 3; a++) {
            float lo = d->obstacles[b].min[a], hi = d->obstacles[b].max[a];
            if (!isfinite(lo) || !isfinite(hi) || !(hi > lo)) {
                return gale_errf(err, GALE_E_RANGE, "wind_desc.obstacles[%d]: axis %d: expected "
                                 "finite min < max, got %g .. %g", b, a, (double)lo, (double)hi);
            }
        }
    }
    return 0;
}

/* Cells whose centres lie inside [lo, hi] (cell units) along one axis; a box thinner than
 * a cell still blocks the cell holding its middle. Returns 0 when outside the grid. */
static int box_range(float lo, float hi, int n, int *i0, int *i1)
{
    if (hi <= 0.0f || lo >= (float)n) {
        return 0;
    }
    int a = (int)ceilf(lo - 0.5f), b = (int)floorf(hi - 0.5f) + 1;
    if (b <= a) {
        a = (int)floorf(0.5f * (lo + hi));
        b = a + 1;
    }
    *i0 = a < 0 ? 0 : a > n ? n : a;
    *i1 = b < 0 ? 0 : b > n ? n : b;
    return *i1 > *i0;
}

static void comp_init(wind_comp *c, int nx, int ny, int nz, int axis)
{
    c->n[0] = nx + (axis == 0);
    c->n[1] = ny + (axis == 1);
    c->n[2] = nz + (axis == 2);
    c->sy = c->n[0] + 2;
    c->sz = c->sy * (c->n[1] + 2);
    c->count = (size_t)c->sz * (size_t)(c->n[2] + 2);
    for (int a = 0; a < 3; a++) {
        c->off[a] = a == axis ? 0.0f : 0.5f;
    }
}

/* The log law U(z) = U10 ln(z/z0) / ln(10/z0), z clamped below at zmin. */
static float log_law(const wind_inflow *f, float z)
{
    z = fmaxf(z, f->zmin_m);
    return f->u10_ms * logf(z / f->z0_m) / logf(10.0f / f->z0_m);
}

/* The subgrid profile table (wind_int.h): U(z) - U~(z), U~ the log law at the heights of
 * the horizontal components' samples (cell centres), interpolated and clamped as
 * sample_comp reads them. A horizontally uniform inflow is what the grid carries there,
 * so what it lacks at a tree's height is this difference (a wall-function view of the
 * unresolved surface layer, Stull 1988 section 9.7). */
static void subgrid_resolve(wind_grid *w)
{
    const wind_inflow *f = &w->inflow;
    const float oz = w->d.origin[2];
    for (int e = 0; e < w->n_subgrid; e++) {
        float zc = (float)e / (float)WIND_SUBGRID_PER_CELL; /* height in cell units */
        float s = zc - 0.5f;
        s = s < 0.0f ? 0.0f : s > (float)(w->nz - 1) ? (float)(w->nz - 1) : s;
        int q = (int)s;
        q = q < w->nz - 1 ? q : (w->nz > 1 ? w->nz - 2 : 0);
        float t = s - (float)q;
        float u0 = log_law(f, ((float)q + 0.5f) * w->h + oz);
        float u1 = w->nz > 1 ? log_law(f, ((float)q + 1.5f) * w->h + oz) : u0;
        w->subgrid[e] = log_law(f, zc * w->h + oz) - (u0 + t * (u1 - u0));
    }
}

/* The inflow with its defaults in place of unset or non-finite fields. */
static wind_inflow inflow_clean(const wind_inflow *in)
{
    wind_inflow f = *in;
    if (!(f.z0_m > 0.0f) || !isfinite(f.z0_m)) {
        f.z0_m = 0.3f;
    }
    if (!(f.zmin_m > 0.0f) || !isfinite(f.zmin_m)) {
        f.zmin_m = 5.0f;
    }
    if (f.zmin_m < f.z0_m) {
        f.zmin_m = f.z0_m;
    }
    if (!isfinite(f.u10_ms)) {
        f.u10_ms = 0.0f;
    }
    if (!isfinite(f.dir_rad)) {
        f.dir_rad = 0.0f;
    }
    for (int a = 0; a < 3; a++) {
        if (!isfinite(f.gust[a])) {
            f.gust[a] = 0.0f;
        }
    }
    return f;
}

/* What the samplers read of the inflow: its direction and the subgrid table. The step
 * reads neither, so this may change while another thread steps the grid. */
static void inflow_sampled(wind_grid *w, const wind_inflow *f)
{
    w->inflow = *f;
    if (w->d.subgrid_profile) {
        subgrid_resolve(w);
    }
}

static void inflow_resolve(wind_grid *w, const wind_inflow *in)
{
    const wind_inflow f = inflow_clean(in);
    inflow_sampled(w, &f);
    const float cx = cosf(f.dir_rad), cy = sinf(f.dir_rad);
    const float ln10 = logf(10.0f / f.z0_m);
    for (int a = 0; a < 3; a++) {
        const wind_comp *c = &w->c[a];
        for (int k = -1; k <= c->n[2]; k++) {
            float z = ((float)k + c->off[2]) * w->h + w->d.origin[2];
            z = fmaxf(z, f.zmin_m);
            /* log law: U(z) = U10 ln(z/z0) / ln(10/z0) */
            float u = f.u10_ms * logf(z / f.z0_m) / ln10;
            float v = a == 0 ? u * cx : a == 1 ? u * cy : 0.0f;
            w->inflow_z[a][k + 1] = v + f.gust[a];
        }
    }
    /* An inflow side: the mean wind at 10 m enters through it. */
    float vx = f.u10_ms * cx + f.gust[0], vy = f.u10_ms * cy + f.gust[1];
    const float inward[WIND_NSIDES] = { vx, -vx, vy, -vy };
    int changed = 0;
    for (int s = 0; s < WIND_NSIDES; s++) {
        float on = w->dirichlet[s] ? WIND_INFLOW_ON : WIND_INFLOW_OFF;
        int open = !(inward[s] > on);
        changed |= open != w->dirichlet[s];
        w->dirichlet[s] = open;
    }
    if (changed) {
        wind_mg_setup(w);
    }
}

wind_grid *wind_create(const wind_desc *d, gale_err *err)
{
    wind_desc r;
    if (!d) {
        gale_errf(err, GALE_E_ARG, "wind_create: desc is NULL");
        return NULL;
    }
    if (resolve_desc(d, &r, err) < 0) {
        return NULL;
    }
    wind_grid *w = calloc(1, sizeof *w);
    if (!w) {
        gale_errf(err, GALE_E_NOMEM, "wind_create: out of memory");
        return NULL;
    }
    w->d = r;
    w->d.obstacles = NULL;
    w->nx = r.nx;
    w->ny = r.ny;
    w->nz = r.nz;
    w->h = r.cell_m;
    w->rng = r.seed ^ 0x6a09e667f3bcc908ull;
    for (int a = 0; a < 3; a++) {
        comp_init(&w->c[a], r.nx, r.ny, r.nz, a);
        w->c[a].d = calloc(w->c[a].count, sizeof(float));
        w->c[a].tmp = calloc(w->c[a].count, sizeof(float));
        w->inflow_z[a] = calloc((size_t)w->c[a].n[2] + 2, sizeof(float));
        if (!w->c[a].d || !w->c[a].tmp || !w->inflow_z[a]) {
            gale_errf(err, GALE_E_NOMEM, "wind_create: %dx%dx%d grid: out of memory", r.nx,
                      r.ny, r.nz);
            goto fail;
        }
    }
    size_t cells = (size_t)(r.nx + 2) * (size_t)(r.ny + 2) * (size_t)(r.nz + 2);
    w->solid = calloc(cells, 1);
    w->rowsum = calloc((size_t)r.ny * (size_t)r.nz, sizeof(double));
    w->boxes = calloc((size_t)(r.n_obstacles > 0 ? r.n_obstacles : 1), sizeof *w->boxes);
    w->n_subgrid = r.nz * WIND_SUBGRID_PER_CELL + 1;
    w->subgrid = calloc((size_t)w->n_subgrid, sizeof *w->subgrid);
    if (!w->solid || !w->rowsum || !w->boxes || !w->subgrid) {
        gale_errf(err, GALE_E_NOMEM, "wind_create: out of memory");
        goto fail;
    }
    const int sy = r.nx + 2, sz = sy * (r.ny + 2);
    for (int b = 0; b < r.n_obstacles; b++) {
        const wind_box *bx = &d->obstacles[b];
        int rg[6];
        const int n[3] = { r.nx, r.ny, r.nz };
        int inside = 1;
        for (int a = 0; a < 3; a++) {
            float lo = (bx->min[a] - r.origin[a]) / r.cell_m;
            float hi = (bx->max[a] - r.origin[a]) / r.cell_m;
            inside &= box_range(lo, hi, n[a], &rg[2 * a], &rg[2 * a + 1]);
        }
        if (!inside) {
            continue;
        }
        memcpy(w->boxes[w->n_boxes++], rg, sizeof rg);
        for (int k = rg[4]; k < rg[5]; k++) {
            for (int j = rg[2]; j < rg[3]; j++) {
                for (int i = rg[0]; i < rg[1]; i++) {
                    w->solid[wind_idx(sy, sz, i, j, k)] = 1;
                }
            }
        }
    }
    w->n_fluid = 0;
    for (int k = 0; k < r.nz; k++) {
        for (int j = 0; j < r.ny; j++) {
            for (int i = 0; i < r.nx; i++) {
                w->n_fluid += !w->solid[wind_idx(sy, sz, i, j, k)];
            }
        }
    }
    if (wind_mg_alloc(w, err) < 0) {
        goto fail;
    }
    for (int s = 0; s < WIND_NSIDES; s++) {
        w->dirichlet[s] = 1;
    }
    wind_mg_setup(w);
    inflow_resolve(w, &(wind_inflow){ 0 });
    return w;
fail:
    wind_destroy(w);
    return NULL;
}

void wind_destroy(wind_grid *w)
{
    if (!w) {
        return;
    }
    for (int a = 0; a < 3; a++) {
        free(w->c[a].d);
        free(w->c[a].tmp);
        free(w->c[a].pub);
        free(w->inflow_z[a]);
    }
    wind_mg_free(w);
    free(w->solid);
    free(w->rowsum);
    free(w->boxes);
    free(w->subgrid);
    free(w);
}

wind_desc wind_get_desc(const wind_grid *w)
{
    wind_desc d = w->d;
    d.obstacles = NULL;
    return d;
}

void wind_set_inflow(wind_grid *w, const wind_inflow *in)
{
    inflow_resolve(w, in);
}

void wind_set_subgrid_inflow(wind_grid *w, const wind_inflow *in)
{
    const wind_inflow f = inflow_clean(in);
    inflow_sampled(w, &f);
}

int wind_publish(wind_grid *w)
{
    if (!w->c[0].pub) {
        /* all three or none: a sampler never reads one component's copy beside another's
           field */
        float *pub[3];
        bool ok = true;
        for (int a = 0; a < 3; a++) {
            ok = (pub[a] = malloc(w->c[a].count * sizeof(float))) != NULL && ok;
        }
        if (!ok) {
            for (int a = 0; a < 3; a++) {
                free(pub[a]);
            }
            return GALE_E_NOMEM;
        }
        for (int a = 0; a < 3; a++) {
            w->c[a].pub = pub[a];
        }
    }
    for (int a = 0; a < 3; a++) {
        memcpy(w->c[a].pub, w->c[a].d, w->c[a].count * sizeof(float));
    }
    return 0;
}

void wind_add_ball(wind_grid *w, const wind_ball *b)
{
    if (w->n_balls == WIND_MAX_BALLS) {
        w->balls_dropped++;
        return;
    }
    w->balls[w->n_balls++] = *b;
}

/* Ghost layer: the far-field inflow on the four open sides (what a back-trace leaving
 * the domain reads), a copy of the nearest layer below the ground and above the lid for
 * the tangential components (free slip: no shear), zero normal velocity there. */
void wind_fill_ghosts(wind_grid *w)
{
    const size_t samples = (size_t)w->nx * (size_t)w->ny * (size_t)w->nz;
    const int threads = samples >= WIND_PAR_MIN ? w->d.threads : 1;
    /* Every write below hits a different ghost sample and reads only interior samples:
     * no barrier between the loops. One row end per row is a cache line each, so the
     * planes are split over the threads. */
#pragma omp parallel num_threads(threads)
    for (int a = 0; a < 3; a++) {
        wind_comp *c = &w->c[a];
        const float *prof = w->inflow_z[a];
#pragma omp for schedule(static) nowait
        for (int kk = 0; kk < c->n[2] + 2; kk++) {
            const int k = kk - 1;
            const float v = prof[k + 1];
            for (int j = -1; j <= c->n[1]; j++) {
                float *row = c->d + wind_idx(c->sy, c->sz, -1, j, k);
                if (j == -1 || j == c->n[1]) {
                    for (int i = 0; i < c->sy; i++) {
                        row[i] = v;
                    }
                } else {
                    row[0] = v;
                    row[c->n[0] + 1] = v;
                }
            }
        }
        /* the ground and the lid: free slip, the tangential components mirrored, w = 0 */
#pragma omp for schedule(static) nowait
        for (int j = 0; j < c->n[1]; j++) {
            float *lo = c->d + wind_idx(c->sy, c->sz, 0, j, -1);
            float *hi = c->d + wind_idx(c->sy, c->sz, 0, j, c->n[2]);
            for (int i = 0; i < c->n[0]; i++) {
                lo[i] = a == 2 ? 0.0f : lo[i + c->sz];
                hi[i] = a == 2 ? 0.0f : hi[i - c->sz];
            }
        }
    }
}

static void apply_ball(wind_grid *w, const wind_ball *b, float dt)
{
    float sigma = b->radius_m / w->h;
    if (!(sigma > 0.0f) || !isfinite(sigma)) {
        return;
    }
    float ctr[3];
    for (int a = 0; a < 3; a++) {
        float j = b->jitter_m > 0.0f ? b->jitter_m * rng_sym(&w->rng) : 0.0f;
        ctr[a] = (b->center[a] + j - w->d.origin[a]) / w->h;
    }
    const float inv2s2 = 1.0f / (2.0f * sigma * sigma);
    for (int a = 0; a < 3; a++) {
        float f = dt * b->force[a];
        if (f == 0.0f || !isfinite(f)) {
            continue;
        }
        wind_comp *c = &w->c[a];
        int lo[3], hi[3];
        for (int d = 0; d < 3; d++) {
            float x0 = ctr[d] - 3.0f * sigma - c->off[d], x1 = ctr[d] + 3.0f * sigma - c->off[d];
            lo[d] = x0 < 0.0f ? 0 : x0 > (float)c->n[d] ? c->n[d] : (int)ceilf(x0);
            hi[d] = x1 < 0.0f ? -1 : x1 >= (float)(c->n[d] - 1) ? c->n[d] - 1 : (int)floorf(x1);
        }
        for (int k = lo[2]; k <= hi[2]; k++) {
            float dz = (float)k + c->off[2] - ctr[2];
            for (int j = lo[1]; j <= hi[1]; j++) {
                float dy = (float)j + c->off[1] - ctr[1];
                float *row = c->d + wind_idx(c->sy, c->sz, 0, j, k);
                for (int i = lo[0]; i <= hi[0]; i++) {
                    float dx = (float)i + c->off[0] - ctr[0];
                    /* eq. 5: w2 = w1 + dt f, f a Gaussian ball */
                    row[i] += f * expf(-(dx * dx + dy * dy + dz * dz) * inv2s2);
                }
            }
        }
    }
}

/* Boundary conditions on the face samples before projection (eq. 10): zero normal
 * velocity on every solid face, the ground and the lid; the inflow profile on the faces
 * of inflow borders. */
static void apply_bc(wind_grid *w)
{
    wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2];
    for (int b = 0; b < w->n_boxes; b++) {
        const int *g = w->boxes[b];
        for (int k = g[4]; k < g[5]; k++) {
            for (int j = g[2]; j < g[3]; j++) {
                for (int i = g[0]; i <= g[1]; i++) {
                    cu->d[wind_idx(cu->sy, cu->sz, i, j, k)] = 0.0f;
                }
            }
            for (int j = g[2]; j <= g[3]; j++) {
                for (int i = g[0]; i < g[1]; i++) {
                    cv->d[wind_idx(cv->sy, cv->sz, i, j, k)] = 0.0f;
                }
            }
        }
        for (int k = g[4]; k <= g[5]; k++) {
            for (int j = g[2]; j < g[3]; j++) {
                for (int i = g[0]; i < g[1]; i++) {
                    cw->d[wind_idx(cw->sy, cw->sz, i, j, k)] = 0.0f;
                }
            }
        }
    }
    for (int j = 0; j < w->ny; j++) {
        float *lo = cw->d + wind_idx(cw->sy, cw->sz, 0, j, 0);
        float *hi = cw->d + wind_idx(cw->sy, cw->sz, 0, j, w->nz);
        for (int i = 0; i < w->nx; i++) {
            lo[i] = 0.0f;
            hi[i] = 0.0f;
        }
    }
    const uint8_t *s = w->solid;
    const int ssy = w->nx + 2, ssz = ssy * (w->ny + 2);
    for (int k = 0; k < w->nz; k++) {
        float u = w->inflow_z[0][k + 1], v = w->inflow_z[1][k + 1];
        for (int j = 0; j < w->ny; j++) {
            if (!w->dirichlet[WIND_SIDE_XLO] && !s[wind_idx(ssy, ssz, 0, j, k)]) {
                cu->d[wind_idx(cu->sy, cu->sz, 0, j, k)] = u;
            }
            if (!w->dirichlet[WIND_SIDE_XHI] && !s[wind_idx(ssy, ssz, w->nx - 1, j, k)]) {
                cu->d[wind_idx(cu->sy, cu->sz, w->nx, j, k)] = u;
            }
        }
        for (int i = 0; i < w->nx; i++) {
            if (!w->dirichlet[WIND_SIDE_YLO] && !s[wind_idx(ssy, ssz, i, 0, k)]) {
                cv->d[wind_idx(cv->sy, cv->sz, i, 0, k)] = v;
            }
            if (!w->dirichlet[WIND_SIDE_YHI] && !s[wind_idx(ssy, ssz, i, w->ny - 1, k)]) {
                cv->d[wind_idx(cv->sy, cv->sz, i, w->ny, k)] = v;
            }
        }
    }
}

/* Divergence row: b = -(sum of outgoing face velocities), zero where open[i] is 0
 * (closed cells); returns the row's sum of b^2. */
WIND_CLONES static float div_row(int nx, const float *restrict u, const float *restrict v,
                                 ptrdiff_t vsy, const float *restrict wz, ptrdiff_t wsz,
                                 const float *restrict open, float *restrict b)
{
    float s = 0.0f;
    /* the row's sum may be reassociated (a norm for the stopping test and the stats) */
#pragma omp simd reduction(+ : s)
    for (int i = 0; i < nx; i++) {
        float q = -(u[i + 1] - u[i] + v[i + vsy] - v[i] + wz[i + wsz] - wz[i]);
        q = wind_select(open[i] > 0.0f, q, 0.0f);
        b[i] = q;
        s += q * q;
    }
    return s;
}

/* div_row for the interior of a constant-coefficient row, whose cells are all open (their
 * x faces are): no mask to read. */
WIND_CLONES static float div_row_open(int nx, const float *restrict u, const float *restrict v,
                                      ptrdiff_t vsy, const float *restrict wz, ptrdiff_t wsz,
                                      float *restrict b)
{
    float s = 0.0f;
#pragma omp simd reduction(+ : s)
    for (int i = 0; i < nx; i++) {
        float q = -(u[i + 1] - u[i] + v[i + vsy] - v[i] + wz[i + wsz] - wz[i]);
        b[i] = q;
        s += q * q;
    }
    return s;
}

/* Right-hand side of eq. 9 on level 0 in cell units: b = -h div(u) = -(sum of outgoing
 * face velocities), zero in closed cells. Returns ||b||_2. */
static double divergence_rhs(wind_grid *w)
{
    wind_level *l = &w->lv[0];
    const wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2];
    const int nx = w->nx, ny = w->ny, rows = w->ny * w->nz;
    const int threads = (size_t)nx * (size_t)rows >= WIND_PAR_MIN ? w->d.threads : 1;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int r = 0; r < rows; r++) {
        int j = r % ny, k = r / ny;
        const float *u = cu->d + wind_idx(cu->sy, cu->sz, 0, j, k);
        const float *v = cv->d + wind_idx(cv->sy, cv->sz, 0, j, k);
        const float *wz = cw->d + wind_idx(cw->sy, cw->sz, 0, j, k);
        float *b = l->b + wind_idx(l->sy, l->sz, 0, j, k);
        const float *id = l->idiag + wind_idx(l->sy, l->sz, 0, j, k);
        const float *g = l->rowg + WIND_ROWG * (size_t)r;
        float s;
        if (g[0] < 0.0f || nx < 3) {
            s = div_row(nx, u, v, cv->sy, wz, cw->sz, id, b);
        } else {
            /* row sums in the same order as div_row: the first cell, the interior, the last;
             * the ends' open flags from the row's end entries (idiag) */
            s = div_row(1, u, v, cv->sy, wz, cw->sz, g + WIND_END0 + 7, b);
            s += div_row_open(nx - 2, u + 1, v + 1, cv->sy, wz + 1, cw->sz, b + 1);
            s += div_row(1, u + nx - 1, v + nx - 1, cv->sy, wz + nx - 1, cw->sz,
                         g + WIND_END1 + 7, b + nx - 1);
        }
        w->rowsum[r] = (double)s;
    }
    return sqrt(wind_sum_rows(w->rowsum, rows));
}

/* Eq. 7 along one row: u -= gx (p_i - p_{i-1}) on the x faces 0..nx, v -= gy (p - p_south),
 * w -= gz (p - p_below) on the row's own y and z faces. */
WIND_CLONES static void project_row(int nx, ptrdiff_t sy, ptrdiff_t sz, const float *restrict pp,
                                    const float *restrict ax, const float *restrict ay,
                                    const float *restrict az, float *restrict u,
                                    float *restrict v, float *restrict wz)
{
    for (int i = 0; i <= nx; i++) {
        u[i] -= ax[i] * (pp[i] - pp[i - 1]);
    }
    for (int i = 0; i < nx; i++) {
        v[i] -= ay[i] * (pp[i] - pp[i - sy]);
        wz[i] -= az[i] * (pp[i] - pp[i - sz]);
    }
}

/* project_row for the interior of a constant-coefficient row: x face i and cell i for
 * i in [0, n) relative to the pointers, with the row's g, without reading the coefficient
 * arrays (the same arithmetic). */
WIND_CLONES static void project_row_const(int n, ptrdiff_t sy, ptrdiff_t sz,
                                          const float *restrict pp, float gx, float gy,
                                          float gz, float *restrict u, float *restrict v,
                                          float *restrict wz)
{
    for (int i = 0; i < n; i++) {
        u[i] -= gx * (pp[i] - pp[i - 1]);
        v[i] -= gy * (pp[i] - pp[i - sy]);
        wz[i] -= gz * (pp[i] - pp[i - sz]);
    }
}

/* Eq. 7: u = w2 - grad p, p in the solver's units (dt/rho/h folded in), across every
 * open face: g (p_R - p_L) with g = 1 inside and 2 on open borders, whose ghost p = 0
 * lies half a cell beyond the border face. */
static void project(wind_grid *w)
{
    wind_level *l = &w->lv[0];
    const float *p = l->p;
    const wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2];
    const int nx = w->nx, ny = w->ny, rows = w->ny * w->nz;
    const ptrdiff_t sy = l->sy, sz = l->sz;
    const int threads = (size_t)nx * (size_t)rows >= WIND_PAR_MIN ? w->d.threads : 1;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int r = 0; r < rows; r++) {
        int j = r % ny, k = r / ny;
        size_t c0 = wind_idx(l->sy, l->sz, 0, j, k);
        float *u = cu->d + wind_idx(cu->sy, cu->sz, 0, j, k);
        float *v = cv->d + wind_idx(cv->sy, cv->sz, 0, j, k);
        float *wz = cw->d + wind_idx(cw->sy, cw->sz, 0, j, k);
        const float *pp = p + c0, *ax = l->ax + c0, *ay = l->ay + c0, *az = l->az + c0;
        const float *g = l->rowg + WIND_ROWG * (size_t)r;
        if (g[0] < 0.0f || nx < 4) {
            project_row(nx, sy, sz, pp, ax, ay, az, u, v, wz);
        } else {
            /* x faces 1..nx-1 and cells 1..nx-2 carry the row's g (g[0] = g[1] once the
             * row has two interior cells); face 0, cell 0, cell nx-1 and face nx take the
             * row's end entries */
            const int e = nx - 1;
            const float *q0 = g + WIND_END0, *q1 = g + WIND_END1;
            u[0] -= q0[0] * (pp[0] - pp[-1]);
            v[0] -= q0[2] * (pp[0] - pp[-sy]);
            wz[0] -= q0[4] * (pp[0] - pp[-sz]);
            project_row_const(nx - 2, sy, sz, pp + 1, g[0], g[2], g[4], u + 1, v + 1, wz + 1);
            u[e] -= g[0] * (pp[e] - pp[e - 1]);
            v[e] -= q1[2] * (pp[e] - pp[e - sy]);
            wz[e] -= q1[4] * (pp[e] - pp[e - sz]);
            u[nx] -= q1[1] * (pp[nx] - pp[nx - 1]);
        }
        if (j == ny - 1) {
            float *vt = v + cv->sy;
            for (int i = 0; i < nx; i++) {
                vt[i] -= ay[i + sy] * (pp[i + sy] - pp[i]);
            }
        }
    }
}

static void reset_field(wind_grid *w)
{
    for (int a = 0; a < 3; a++) {
        memset(w->c[a].d, 0, w->c[a].count * sizeof(float));
    }
    memset(w->lv[0].p, 0, w->lv[0].count * sizeof(float));
}

void wind_fill_inflow(wind_grid *w)
{
    for (int a = 0; a < 3; a++) {
        wind_comp *c = &w->c[a];
        for (int k = -1; k <= c->n[2]; k++) {
            float v = w->inflow_z[a][k + 1];
            float *plane = c->d + wind_idx(c->sy, c->sz, -1, -1, k);
            for (int q = 0; q < c->sz; q++) {
                plane[q] = v;
            }
        }
    }
    memset(w->lv[0].p, 0, w->lv[0].count * sizeof(float));
    apply_bc(w);
}

int wind_step(wind_grid *w, float dt_s, wind_step_stats *st)
{
    double t0 = mono_ms();
    if (!(dt_s > 0.0f) || !isfinite(dt_s)) {
        w->n_balls = 0;
        return GALE_E_ARG;
    }
    wind_fill_ghosts(w);
    wind_advect(w, dt_s / w->h);
    double t1 = mono_ms();
    for (int b = 0; b < w->n_balls; b++) {
        apply_ball(w, &w->balls[b], dt_s);
    }
    w->n_balls = 0;
    apply_bc(w);
    double b0 = divergence_rhs(w);
    double t2 = mono_ms();
    double r1 = 0.0;
    int it = wind_mg_solve(w, b0 / (double)w->d.div_reduction, w->d.max_iterations, &r1);
    if (!isfinite(b0) || !isfinite(r1)) {
        reset_field(w);
        return GALE_E_NUMERIC;
    }
    double t3 = mono_ms();
    project(w);
    if (st) {
        double norm = w->n_fluid > 0 ? 1.0 / (sqrt((double)w->n_fluid) * (double)w->h) : 0.0;
        st->div_before = b0 * norm;
        st->div_after = r1 * norm;
        st->iterations = it;
        st->residual = b0 > 0.0 ? r1 / b0 : 0.0;
        st->ms = mono_ms() - t0;
        st->ms_advect = t1 - t0;
        st->ms_forces = t2 - t1;
        st->ms_solve = t3 - t2;
        st->ms_project = t0 + st->ms - t3;
    }
    return 0;
}

double wind_divergence_rms(const wind_grid *w)
{
    const wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2];
    const int ssy = w->nx + 2, ssz = ssy * (w->ny + 2);
    double s = 0.0;
    for (int k = 0; k < w->nz; k++) {
        for (int j = 0; j < w->ny; j++) {
            double row = 0.0;
            for (int i = 0; i < w->nx; i++) {
                if (w->solid[wind_idx(ssy, ssz, i, j, k)]) {
                    continue;
                }
                double q = (double)cu->d[wind_idx(cu->sy, cu->sz, i + 1, j, k)] -
                           (double)cu->d[wind_idx(cu->sy, cu->sz, i, j, k)] +
                           (double)cv->d[wind_idx(cv->sy, cv->sz, i, j + 1, k)] -
                           (double)cv->d[wind_idx(cv->sy, cv->sz, i, j, k)] +
                           (double)cw->d[wind_idx(cw->sy, cw->sz, i, j, k + 1)] -
                           (double)cw->d[wind_idx(cw->sy, cw->sz, i, j, k)];
                row += q * q;
            }
            s += row;
        }
    }
    return w->n_fluid > 0 ? sqrt(s / w->n_fluid) / (double)w->h : 0.0;
}

/* Trilinear read clamped to the samples inside the domain (x, y, z in cell units). */
static inline float sample_comp(const wind_comp *c, float x, float y, float z)
{
    const float f[3] = { x - c->off[0], y - c->off[1], z - c->off[2] };
    int i[3];
    float t[3];
    for (int a = 0; a < 3; a++) {
        const int n = c->n[a];
        float v = f[a] < 0.0f ? 0.0f : f[a];
        v = v > (float)(n - 1) ? (float)(n - 1) : v;
        int q = (int)v;
        /* the last sample is reached as the upper end of the cell below it */
        q = q < n - 1 ? q : (n > 1 ? n - 2 : 0);
        i[a] = q;
        t[a] = v - (float)q;
    }
    const float *q = wind_comp_read(c) + wind_idx(c->sy, c->sz, i[0], i[1], i[2]);
    const ptrdiff_t sy = c->sy, sz = c->sz;
    float c00 = q[0] + t[0] * (q[1] - q[0]);
    float c10 = q[sy] + t[0] * (q[sy + 1] - q[sy]);
    float c01 = q[sz] + t[0] * (q[sz + 1] - q[sz]);
    float c11 = q[sz + sy] + t[0] * (q[sz + sy + 1] - q[sz + sy]);
    float c0 = c00 + t[1] * (c10 - c00);
    float c1 = c01 + t[1] * (c11 - c01);
    return c0 + t[2] * (c1 - c0);
}

/* The subgrid table at a height z in cell units, linear between entries, clamped. */
static inline float subgrid_at(const float *sg, int n, float z)
{
    float e = z * (float)WIND_SUBGRID_PER_CELL;
    e = e < 0.0f ? 0.0f : e > (float)(n - 1) ? (float)(n - 1) : e;
    int q = (int)e;
    q = q < n - 1 ? q : n - 2;
    float t = e - (float)q;
    return sg[q] + t * (sg[q + 1] - sg[q]);
}

static inline void sample_point(const wind_grid *w, const float p[3], float v[3])
{
    float inv = 1.0f / w->h;
    float x = (p[0] - w->d.origin[0]) * inv, y = (p[1] - w->d.origin[1]) * inv,
          z = (p[2] - w->d.origin[2]) * inv;
    for (int a = 0; a < 3; a++) {
        v[a] = sample_comp(&w->c[a], x, y, z);
    }
    if (w->d.subgrid_profile) {
        float du = subgrid_at(w->subgrid, w->n_subgrid, z);
        v[0] += du * cosf(w->inflow.dir_rad);
        v[1] += du * sinf(w->inflow.dir_rad);
    }
}

void wind_sample(const wind_grid *w, const float p[3], float v[3])
{
    sample_point(w, p, v);
}

/* One component's sampling constants, copied out of the grid so the point loop below
 * reads them from registers (a store to the output could otherwise alias them). */
typedef struct comp_view {
    const float *d;
    int nm1[3]; /* samples per axis - 1 */
    int hi[3];  /* last cell a sample may start in */
    int sy, sz;
    float off[3];
} comp_view;

static comp_view comp_view_of(const wind_comp *c)
{
    comp_view v = { .d = wind_comp_read(c), .sy = c->sy, .sz = c->sz };
    for (int a = 0; a < 3; a++) {
        v.nm1[a] = c->n[a] - 1;
        v.hi[a] = c->n[a] > 1 ? c->n[a] - 2 : 0;
        v.off[a] = c->off[a];
    }
    return v;
}

/* sample_comp with 32-bit offsets (the caller checks the array fits), so that the reads
 * become gathers when the point loop is vectorised; the same floats as sample_comp. */
static inline float sample_view(const comp_view *c, float x, float y, float z)
{
    const float f[3] = { x - c->off[0], y - c->off[1], z - c->off[2] };
    int i[3];
    float t[3];
    for (int a = 0; a < 3; a++) {
        float v = f[a] < 0.0f ? 0.0f : f[a];
        v = v > (float)c->nm1[a] ? (float)c->nm1[a] : v;
        int q = (int)v;
        q = q < c->nm1[a] ? q : c->hi[a];
        i[a] = q;
        t[a] = v - (float)q;
    }
    const int sy = c->sy, sz = c->sz;
    const int o = (i[2] + 1) * sz + (i[1] + 1) * sy + (i[0] + 1);
    const float *d = c->d;
    float c00 = d[o] + t[0] * (d[o + 1] - d[o]);
    float c10 = d[o + sy] + t[0] * (d[o + sy + 1] - d[o + sy]);
    float c01 = d[o + sz] + t[0] * (d[o + sz + 1] - d[o + sz]);
    float c11 = d[o + sz + sy] + t[0] * (d[o + sz + sy + 1] - d[o + sz + sy]);
    float c0 = c00 + t[1] * (c10 - c00);
    float c1 = c01 + t[1] * (c11 - c01);
    return c0 + t[2] * (c1 - c0);
}

/* Points [i0, i1): cloned for AVX-512 and AVX2, where the trilinear reads become vector
 * gathers over consecutive points; every clone computes the same floats. */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
static void sample_range(const wind_grid *w, int i0, int i1, const float *restrict p,
                         float *restrict v)
{
    const comp_view cu = comp_view_of(&w->c[0]), cv = comp_view_of(&w->c[1]),
                    cw = comp_view_of(&w->c[2]);
    const float inv = 1.0f / w->h;
    const float ox = w->d.origin[0], oy = w->d.origin[1], oz = w->d.origin[2];
    for (int i = i0; i < i1; i++) {
        float x = (p[3 * i] - ox) * inv, y = (p[3 * i + 1] - oy) * inv,
              z = (p[3 * i + 2] - oz) * inv;
        v[3 * i] = sample_view(&cu, x, y, z);
        v[3 * i + 1] = sample_view(&cv, x, y, z);
        v[3 * i + 2] = sample_view(&cw, x, y, z);
    }
    if (w->d.subgrid_profile) {
        const float *sg = w->subgrid;
        const int n = w->n_subgrid;
        const float cx = cosf(w->inflow.dir_rad), cy = sinf(w->inflow.dir_rad);
        for (int i = i0; i < i1; i++) {
            float du = subgrid_at(sg, n, (p[3 * i + 2] - oz) * inv);
            v[3 * i] += du * cx;
            v[3 * i + 1] += du * cy;
        }
    }
}

void wind_sample_many(const wind_grid *w, int n, const float *p, float *v)
{
    bool small = true;
    for (int a = 0; a < 3; a++) {
        small = small && w->c[a].count <= (size_t)INT32_MAX;
    }
    /* Each point is independent, so splitting them over the threads in fixed chunks
     * gives the same result bit for bit as one thread. Below a few thousand points the
     * fork costs more than it saves. */
    const int chunk = 1024;
    const int nc = (n + chunk - 1) / chunk;
    const int threads = n >= 4096 ? w->d.threads : 1;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int c = 0; c < nc; c++) {
        int i1 = (c + 1) * chunk < n ? (c + 1) * chunk : n;
        if (small) {
            sample_range(w, c * chunk, i1, p, v);
        } else {
            for (int i = c * chunk; i < i1; i++) {
                sample_point(w, p + 3 * i, v + 3 * i);
            }
        }
    }
}

void wind_add_subgrid(const wind_grid *w, int n, const float *p, float *v)
{
    if (!w->d.subgrid_profile) {
        return;
    }
    /* the second loop of sample_range, over the same floats */
    const float *sg = w->subgrid;
    const int m = w->n_subgrid;
    const float inv = 1.0f / w->h, oz = w->d.origin[2];
    const float cx = cosf(w->inflow.dir_rad), cy = sinf(w->inflow.dir_rad);
    for (int i = 0; i < n; i++) {
        float du = subgrid_at(sg, m, (p[3 * i + 2] - oz) * inv);
        v[3 * i] += du * cx;
        v[3 * i + 1] += du * cy;
    }
}

int wind_coarse(const wind_grid *w, int factor, float *out, int capacity, int dims[3])
{
    if (factor < 1) {
        return GALE_E_ARG;
    }
    const int n[3] = { w->nx, w->ny, w->nz };
    int f[3];
    for (int a = 0; a < 3; a++) {
        f[a] = factor < n[a] ? factor : n[a];
        dims[a] = (n[a] + f[a] - 1) / f[a];
    }
    long need = 3L * dims[0] * dims[1] * dims[2];
    if (!out || capacity < need) {
        return GALE_E_RANGE;
    }
    const wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2];
    const float *du = wind_comp_read(cu), *dv = wind_comp_read(cv), *dw = wind_comp_read(cw);
    for (int K = 0; K < dims[2]; K++) {
        for (int J = 0; J < dims[1]; J++) {
            for (int I = 0; I < dims[0]; I++) {
                double s[3] = { 0.0, 0.0, 0.0 };
                int cnt = 0;
                for (int k = K * f[2]; k < (K + 1) * f[2] && k < n[2]; k++) {
                    for (int j = J * f[1]; j < (J + 1) * f[1] && j < n[1]; j++) {
                        for (int i = I * f[0]; i < (I + 1) * f[0] && i < n[0]; i++) {
                            size_t u = wind_idx(cu->sy, cu->sz, i, j, k);
                            size_t v = wind_idx(cv->sy, cv->sz, i, j, k);
                            size_t q = wind_idx(cw->sy, cw->sz, i, j, k);
                            s[0] += 0.5 * ((double)du[u] + (double)du[u + 1]);
                            s[1] += 0.5 * ((double)dv[v] + (double)dv[v + (size_t)cv->sy]);
                            s[2] += 0.5 * ((double)dw[q] + (double)dw[q + (size_t)cw->sz]);
                            cnt++;
                        }
                    }
                }
                float *o = out + 3 * (((size_t)K * (size_t)dims[1] + (size_t)J) * (size_t)dims[0] +
                                      (size_t)I);
                for (int a = 0; a < 3; a++) {
                    o[a] = (float)(s[a] / cnt);
                }
            }
        }
    }
    return (int)need;
}
