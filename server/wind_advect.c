/* Semi-Lagrangian advection of the MAC velocity (Oliapuram & Kumar 2010 eq. 4,
 * w1(x) = w0(x - dt w0(x)); Stam 1999): every face sample is traced back through the
 * velocity at its own position and the component is read there by trilinear
 * interpolation. The ghost layer holds the far-field inflow, so back-traces that leave
 * the domain read the wind coming in. */
#include <math.h>

#include "wind_int.h"

/* One row (j, k) of component a. The other two components are averaged from their four
 * nearest samples to the position of each sample of a (exactly their trilinear value
 * there): pa / pb point at the first of those four samples for i = 0, at offsets
 * 0, da0, da1, da0 + da1. The foot of the characteristic (eq. 4) is read from src by
 * trilinear interpolation, clamped to the ghost range [-1, n]. Written with 32-bit
 * offsets and no calls so that it vectorises (gathers); cloned for AVX-512 and AVX2 with
 * a run-time choice, so the build stays portable. The clones do the same IEEE operations
 * per element (no contraction in ISO C mode), so the field is the same bits on each. */
WIND_CLONES static void advect_row(int a, float s, int j, int k, const int n[3], int sy, int sz,
                              const float *restrict own, const float *restrict pa, int da0,
                              int da1, const float *restrict pb, int db0, int db1,
                              const float *restrict src, float *restrict dst)
{
    const int nx = n[0];
    const float hx = (float)n[0], hy = (float)n[1], hz = (float)n[2];
    const int mx = n[0] - 1, my = n[1] - 1, mz = n[2] - 1;
    const float fj = (float)j, fk = (float)k;
    for (int i = 0; i < nx; i++) {
        float ea = 0.25f * (pa[i] + pa[i + da0] + pa[i + da1] + pa[i + da0 + da1]);
        float eb = 0.25f * (pb[i] + pb[i + db0] + pb[i + db1] + pb[i + db0 + db1]);
        float o = own[i];
        float uu = a == 0 ? o : ea;
        float vv = a == 0 ? ea : a == 1 ? o : eb;
        float ww = a == 2 ? o : eb;
        float fx = (float)i - s * uu, fy = fj - s * vv, fz = fk - s * ww;
        fx = fx < -1.0f ? -1.0f : fx > hx ? hx : fx;
        fy = fy < -1.0f ? -1.0f : fy > hy ? hy : fy;
        fz = fz < -1.0f ? -1.0f : fz > hz ? hz : fz;
        int ii = (int)(fx + 1.0f) - 1, jj = (int)(fy + 1.0f) - 1, kk = (int)(fz + 1.0f) - 1;
        ii = ii < mx ? ii : mx;
        jj = jj < my ? jj : my;
        kk = kk < mz ? kk : mz;
        float tx = fx - (float)ii, ty = fy - (float)jj, tz = fz - (float)kk;
        int q = (kk + 1) * sz + (jj + 1) * sy + ii + 1;
        float c00 = src[q] + tx * (src[q + 1] - src[q]);
        float c10 = src[q + sy] + tx * (src[q + sy + 1] - src[q + sy]);
        float c01 = src[q + sz] + tx * (src[q + sz + 1] - src[q + sz]);
        float c11 = src[q + sz + sy] + tx * (src[q + sz + sy + 1] - src[q + sz + sy]);
        float c0 = c00 + ty * (c10 - c00);
        float c1 = c01 + ty * (c11 - c01);
        dst[i] = c0 + tz * (c1 - c0);
    }
}

static void advect_comp(wind_grid *w, int a, float s)
{
    const wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2], *ca = &w->c[a];
    const int ny = ca->n[1], nz = ca->n[2], rows = ny * nz;
    const int threads = (size_t)ca->n[0] * (size_t)rows >= WIND_PAR_MIN ? w->d.threads : 1;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int r = 0; r < rows; r++) {
        int j = r % ny, k = r / ny;
        const float *own = ca->d + wind_idx(ca->sy, ca->sz, 0, j, k);
        float *dst = ca->tmp + wind_idx(ca->sy, ca->sz, 0, j, k);
        if (a == 0) {
            /* v at (i-1..i, j..j+1), w at (i-1..i, k..k+1) */
            advect_row(0, s, j, k, ca->n, ca->sy, ca->sz, own,
                       cv->d + wind_idx(cv->sy, cv->sz, -1, j, k), 1, cv->sy,
                       cw->d + wind_idx(cw->sy, cw->sz, -1, j, k), 1, cw->sz, ca->d, dst);
        } else if (a == 1) {
            /* u at (i..i+1, j-1..j), w at (j-1..j, k..k+1) */
            advect_row(1, s, j, k, ca->n, ca->sy, ca->sz, own,
                       cu->d + wind_idx(cu->sy, cu->sz, 0, j - 1, k), 1, cu->sy,
                       cw->d + wind_idx(cw->sy, cw->sz, 0, j - 1, k), cw->sy, cw->sz, ca->d, dst);
        } else {
            /* u at (i..i+1, k-1..k), v at (j..j+1, k-1..k) */
            advect_row(2, s, j, k, ca->n, ca->sy, ca->sz, own,
                       cu->d + wind_idx(cu->sy, cu->sz, 0, j, k - 1), 1, cu->sz,
                       cv->d + wind_idx(cv->sy, cv->sz, 0, j, k - 1), cv->sy, cv->sz, ca->d, dst);
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
