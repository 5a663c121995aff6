/* Projection of the MAC velocity (Oliapuram & Kumar 2010 eqs. 7 and 9): the divergence
 * that is the pressure solve's right-hand side, and the pressure gradient subtracted once
 * wind_mg.c has solved for it. */
#include <math.h>
#include <stddef.h>

#include "wind_int.h"

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
double wind_divergence_rhs(wind_grid *w)
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
void wind_project(wind_grid *w)
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
