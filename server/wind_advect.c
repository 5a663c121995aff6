/* Semi-Lagrangian advection of the MAC velocity (Oliapuram & Kumar 2010 eq. 4,
 * w1(x) = w0(x - dt w0(x)); Stam 1999): every face sample is traced back through the
 * velocity at its own position and the component is read there by trilinear
 * interpolation. The ghost layer holds the far-field inflow, so back-traces that leave
 * the domain read the wind coming in. */
#include <math.h>

#include "wind_int.h"

/* Trilinear read of a padded component at index coordinates (fx, fy, fz), clamped to the
 * ghost range [-1, n]: branch-free apart from the clamps. */
static inline float trilin(const float *restrict d, int sy, int sz, const int n[3], float fx,
                           float fy, float fz)
{
    fx = fminf(fmaxf(fx, -1.0f), (float)n[0]);
    fy = fminf(fmaxf(fy, -1.0f), (float)n[1]);
    fz = fminf(fmaxf(fz, -1.0f), (float)n[2]);
    int i = (int)(fx + 1.0f) - 1, j = (int)(fy + 1.0f) - 1, k = (int)(fz + 1.0f) - 1;
    i = i < n[0] ? i : n[0] - 1;
    j = j < n[1] ? j : n[1] - 1;
    k = k < n[2] ? k : n[2] - 1;
    float tx = fx - (float)i, ty = fy - (float)j, tz = fz - (float)k;
    const float *q = d + wind_idx(sy, sz, i, j, k);
    const ptrdiff_t y = sy, z = sz;
    float c00 = q[0] + tx * (q[1] - q[0]);
    float c10 = q[y] + tx * (q[y + 1] - q[y]);
    float c01 = q[z] + tx * (q[z + 1] - q[z]);
    float c11 = q[z + y] + tx * (q[z + y + 1] - q[z + y]);
    float c0 = c00 + ty * (c10 - c00);
    float c1 = c01 + ty * (c11 - c01);
    return c0 + tz * (c1 - c0);
}

/* Advects component a; the other two are averaged from their four nearest samples to the
 * position of each sample of a (exactly their trilinear value there). */
static void advect_comp(wind_grid *w, int a, float s)
{
    wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2], *ca = &w->c[a];
    const float *restrict U = cu->d, *restrict V = cv->d, *restrict W = cw->d;
    const float *restrict src = ca->d;
    float *restrict dst = ca->tmp;
    const int nx = ca->n[0], ny = ca->n[1], nz = ca->n[2], rows = ny * nz;
    const ptrdiff_t usy = cu->sy, usz = cu->sz, vsy = cv->sy, vsz = cv->sz, wsy = cw->sy,
                    wsz = cw->sz;
    const int threads = (size_t)nx * (size_t)rows >= WIND_PAR_MIN ? w->d.threads : 1;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int r = 0; r < rows; r++) {
        int j = r % ny, k = r / ny;
        for (int i = 0; i < nx; i++) {
            float uu, vv, ww;
            if (a == 0) {
                const float *v0 = V + wind_idx(cv->sy, cv->sz, i - 1, j, k);
                const float *w0 = W + wind_idx(cw->sy, cw->sz, i - 1, j, k);
                uu = U[wind_idx(cu->sy, cu->sz, i, j, k)];
                vv = 0.25f * (v0[0] + v0[1] + v0[vsy] + v0[vsy + 1]);
                ww = 0.25f * (w0[0] + w0[1] + w0[wsz] + w0[wsz + 1]);
            } else if (a == 1) {
                const float *u0 = U + wind_idx(cu->sy, cu->sz, i, j - 1, k);
                const float *w0 = W + wind_idx(cw->sy, cw->sz, i, j - 1, k);
                uu = 0.25f * (u0[0] + u0[1] + u0[usy] + u0[usy + 1]);
                vv = V[wind_idx(cv->sy, cv->sz, i, j, k)];
                ww = 0.25f * (w0[0] + w0[wsy] + w0[wsz] + w0[wsz + wsy]);
            } else {
                const float *u0 = U + wind_idx(cu->sy, cu->sz, i, j, k - 1);
                const float *v0 = V + wind_idx(cv->sy, cv->sz, i, j, k - 1);
                uu = 0.25f * (u0[0] + u0[1] + u0[usz] + u0[usz + 1]);
                vv = 0.25f * (v0[0] + v0[vsy] + v0[vsz] + v0[vsz + vsy]);
                ww = W[wind_idx(cw->sy, cw->sz, i, j, k)];
            }
            /* index coordinates of the foot of the characteristic on a's own lattice */
            float fx = (float)i - s * uu, fy = (float)j - s * vv, fz = (float)k - s * ww;
            dst[wind_idx(ca->sy, ca->sz, i, j, k)] = trilin(src, ca->sy, ca->sz, ca->n, fx, fy, fz);
        }
    }
}

void wind_advect(wind_grid *w, float dt_over_h)
{
    for (int a = 0; a < 3; a++) {
        advect_comp(w, a, dt_over_h);
    }
    for (int a = 0; a < 3; a++) {
        float *t = w->c[a].d;
        w->c[a].d = w->c[a].tmp;
        w->c[a].tmp = t;
    }
}
