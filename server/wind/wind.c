/* The wind grid: stable fluids on a staggered grid (Oliapuram & Kumar 2010 section 2,
 * eqs. 4-10): advect, add forces (section 2.3 Gaussian ball and border inflow), project
 * with a multigrid pressure solve, free-slip ground and obstacle boxes. This file creates
 * and destroys the grid and runs the step through its stages: wind_advect.c (advection),
 * wind_force.c (inflow, forces, boundary conditions), wind_mg.c (pressure solve) and
 * wind_project.c (divergence, projection). Sampling and the coarse copy for clients are
 * wind_sample.c's.
 *
 * Why a staggered (MAC) grid: each velocity component lives on the cell faces normal to
 * it, so the no-flux condition of eq. 10 at a solid face is one sample set to zero, exact
 * and without a stencil special case, and the tangential components there are left free
 * (free slip). Divergence and pressure gradient are then compact two-point differences:
 * the projected field is discretely divergence-free up to the solver residual, with no
 * checkerboard pressure modes that a collocated grid (the paper's float4 voxels) lets
 * through. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mono.h"
#include "wind_int.h"

#define WIND_MAX_CELLS_AXIS 4096
#define WIND_DEFAULT_MAX_IT 30

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
    wind_inflow_resolve(w, &(wind_inflow){ 0 });
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

static void reset_field(wind_grid *w)
{
    for (int a = 0; a < 3; a++) {
        memset(w->c[a].d, 0, w->c[a].count * sizeof(float));
    }
    memset(w->lv[0].p, 0, w->lv[0].count * sizeof(float));
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
        wind_apply_ball(w, &w->balls[b], dt_s);
    }
    w->n_balls = 0;
    wind_apply_bc(w);
    double b0 = wind_divergence_rhs(w);
    double t2 = mono_ms();
    double r1 = 0.0;
    int it = wind_mg_solve(w, b0 / (double)w->d.div_reduction, w->d.max_iterations, &r1);
    if (!isfinite(b0) || !isfinite(r1)) {
        reset_field(w);
        return GALE_E_NUMERIC;
    }
    double t3 = mono_ms();
    wind_project(w);
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
