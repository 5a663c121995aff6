/* Forces and boundary conditions of the wind step (Oliapuram & Kumar 2010 section 2.3,
 * eqs. 5 and 10): the border inflow (its log-law profile, the borders it enters through,
 * the subgrid profile table), the ghost layer, the Gaussian force balls, and zero normal
 * velocity on solid faces, the ground and the lid. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "hash.h"
#include "wind_int.h"

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

/* The log law U(z) = U10 ln(z/z0) / ln(10/z0), z clamped below at zmin. */
static float log_law(const wind_inflow *f, float z)
{
    z = fmaxf(z, f->zmin_m);
    return f->u10_ms * logf(z / f->z0_m) / logf(10.0f / f->z0_m);
}

/* The subgrid profile table (wind_int.h): U(z) - U~(z), U~ the log law at the heights of
 * the horizontal components' samples (cell centres), interpolated and clamped as
 * wind_sample.c's sample_comp reads them. A horizontally uniform inflow is what the grid
 * carries there, so what it lacks at a tree's height is this difference (a wall-function
 * view of the unresolved surface layer, Stull 1988 section 9.7). */
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

void wind_inflow_resolve(wind_grid *w, const wind_inflow *in)
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

void wind_set_inflow(wind_grid *w, const wind_inflow *in)
{
    wind_inflow_resolve(w, in);
}

void wind_set_subgrid_inflow(wind_grid *w, const wind_inflow *in)
{
    const wind_inflow f = inflow_clean(in);
    inflow_sampled(w, &f);
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

void wind_apply_ball(wind_grid *w, const wind_ball *b, float dt)
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
void wind_apply_bc(wind_grid *w)
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
    wind_apply_bc(w);
}
