/* Semi-Lagrangian advection of the MAC velocity (Oliapuram & Kumar 2010 eq. 4,
 * w1(x) = w0(x - dt w0(x)); Stam 1999): every face sample is traced back through the
 * velocity at its own position and the component is read there by trilinear
 * interpolation. The ghost layer holds the far-field inflow, so back-traces that leave
 * the domain read the wind coming in. */
#include <math.h>
#include <omp.h>

#include "wind_int.h"

/* Displacements over dt of one row (j, k) of component a's samples, in cells: the
 * velocity at each sample, its own component read directly and the other two averaged
 * from their four nearest samples (exactly their trilinear value there); pa / pb point at
 * the first of those four for i = 0, at offsets 0, da0, da1, da0 + da1. */
WIND_CLONES static void advect_disp(int a, float s, int nx, const float *restrict own,
                                    const float *restrict pa, int da0, int da1,
                                    const float *restrict pb, int db0, int db1,
                                    float *restrict dx, float *restrict dy, float *restrict dz)
{
    /* Own component goes to the output of axis a, the averaged ones to the other two
     * in order: selected once per row so the loop has no branches and vectorises. */
    float *restrict po = a == 0 ? dx : a == 1 ? dy : dz;
    float *restrict pea = a == 0 ? dy : dx;
    float *restrict peb = a == 2 ? dy : dz;
#pragma omp simd
    for (int i = 0; i < nx; i++) {
        po[i] = s * own[i];
        pea[i] = s * (0.25f * (pa[i] + pa[i + da0] + pa[i + da1] + pa[i + da0 + da1]));
        peb[i] = s * (0.25f * (pb[i] + pb[i + db0] + pb[i + db1] + pb[i + db0 + db1]));
    }
}

/* General back-trace (eq. 4): trilinear read of src at (i - dx, j - dy, k - dz), clamped
 * to the ghost range [-1, n]. 32-bit offsets, no calls: vectorises with gathers. */
WIND_CLONES static void advect_far(int j, int k, const int n[3], int sy, int sz,
                                   const float *restrict dxs, const float *restrict dys,
                                   const float *restrict dzs, const float *restrict src,
                                   float *restrict dst)
{
    const int nx = n[0];
    const float hx = (float)n[0], hy = (float)n[1], hz = (float)n[2];
    const int mx = n[0] - 1, my = n[1] - 1, mz = n[2] - 1;
    const float fj = (float)j, fk = (float)k;
#pragma omp simd
    for (int i = 0; i < nx; i++) {
        float fx = (float)i - dxs[i], fy = fj - dys[i], fz = fk - dzs[i];
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

/* Linear interpolation at distance |d| <= 1 from the sample a toward the upwind
 * neighbour (lo when d > 0, hi when d < 0): the same value as the general read. */
static inline float upwind(float lo, float a, float hi, float d)
{
    float nb = wind_select(d > 0.0f, lo, hi);
    float t = d > 0.0f ? d : -d;
    return a + t * (nb - a);
}

/* Back-trace of a row whose displacements are all within one cell, fused with their
 * computation (own component a, a constant in each caller so the selections fold away):
 * the displacement of each sample stays in registers, and as the foot lies in the 3x3x3
 * block around the sample, the trilinear read becomes upwind selections from nine
 * contiguous rows of the own component (no gathers). Returns nonzero when some
 * displacement exceeds one cell, in which case the row's output is not valid and the
 * caller redoes it by the general path (NaN counts as near, whose reads stay in the row's
 * neighbourhood; the step's divergence check then resets the field). */
static inline __attribute__((always_inline)) int
advect_row_fused(int a, float s, int nx, int sy, int sz, const float *restrict own,
                 const float *restrict pa, int da0, int da1, const float *restrict pb, int db0,
                 int db1, float *restrict dst)
{
    int far = 0;
#pragma omp simd reduction(| : far)
    for (int i = 0; i < nx; i++) {
        const float d_own = s * own[i];
        const float d_a = s * (0.25f * (pa[i] + pa[i + da0] + pa[i + da1] + pa[i + da0 + da1]));
        const float d_b = s * (0.25f * (pb[i] + pb[i + db0] + pb[i + db1] + pb[i + db0 + db1]));
        const float dx = a == 0 ? d_own : d_a;
        const float dy = a == 1 ? d_own : a == 0 ? d_a : d_b;
        const float dz = a == 2 ? d_own : d_b;
        far |= (dx > 1.0f) | (dx < -1.0f) | (dy > 1.0f) | (dy < -1.0f) | (dz > 1.0f) |
               (dz < -1.0f);
        const float *r = own + i;
#define WIND_XR(b, c) upwind(r[(b)*sz + (c)*sy - 1], r[(b)*sz + (c)*sy], r[(b)*sz + (c)*sy + 1], dx)
        const float xr[3][3] = {
            {WIND_XR(-1, -1), WIND_XR(-1, 0), WIND_XR(-1, 1)},
            {WIND_XR(0, -1), WIND_XR(0, 0), WIND_XR(0, 1)},
            {WIND_XR(1, -1), WIND_XR(1, 0), WIND_XR(1, 1)},
        };
#undef WIND_XR
        float y0 = upwind(xr[0][0], xr[0][1], xr[0][2], dy);
        float y1 = upwind(xr[1][0], xr[1][1], xr[1][2], dy);
        float y2 = upwind(xr[2][0], xr[2][1], xr[2][2], dy);
        dst[i] = upwind(y0, y1, y2, dz);
    }
    return far;
}

WIND_CLONES static int advect_row_u(float s, int nx, int sy, int sz, const float *restrict own,
                                    const float *restrict pa, int da0, int da1,
                                    const float *restrict pb, int db0, int db1,
                                    float *restrict dst)
{
    return advect_row_fused(0, s, nx, sy, sz, own, pa, da0, da1, pb, db0, db1, dst);
}

WIND_CLONES static int advect_row_v(float s, int nx, int sy, int sz, const float *restrict own,
                                    const float *restrict pa, int da0, int da1,
                                    const float *restrict pb, int db0, int db1,
                                    float *restrict dst)
{
    return advect_row_fused(1, s, nx, sy, sz, own, pa, da0, da1, pb, db0, db1, dst);
}

WIND_CLONES static int advect_row_w(float s, int nx, int sy, int sz, const float *restrict own,
                                    const float *restrict pa, int da0, int da1,
                                    const float *restrict pb, int db0, int db1,
                                    float *restrict dst)
{
    return advect_row_fused(2, s, nx, sy, sz, own, pa, da0, da1, pb, db0, db1, dst);
}

/* Row r of component a: the fused one-cell kernel, and where a displacement in the row
 * exceeds a cell, the displacements and the general back-trace. */
static void advect_row(wind_grid *w, int a, float s, int r)
{
    const wind_comp *cu = &w->c[0], *cv = &w->c[1], *cw = &w->c[2], *ca = &w->c[a];
    const int nx = ca->n[0], ny = ca->n[1];
    const int j = r % ny, k = r / ny;
    const float *own = ca->d + wind_idx(ca->sy, ca->sz, 0, j, k);
    float *dst = ca->tmp + wind_idx(ca->sy, ca->sz, 0, j, k);
    const float *pa, *pb;
    int da0, da1, db0, db1;
    if (a == 0) {
        /* v at (i-1..i, j..j+1), w at (i-1..i, k..k+1) */
        pa = cv->d + wind_idx(cv->sy, cv->sz, -1, j, k), da0 = 1, da1 = cv->sy;
        pb = cw->d + wind_idx(cw->sy, cw->sz, -1, j, k), db0 = 1, db1 = cw->sz;
    } else if (a == 1) {
        /* u at (i..i+1, j-1..j), w at (j-1..j, k..k+1) */
        pa = cu->d + wind_idx(cu->sy, cu->sz, 0, j - 1, k), da0 = 1, da1 = cu->sy;
        pb = cw->d + wind_idx(cw->sy, cw->sz, 0, j - 1, k), db0 = cw->sy, db1 = cw->sz;
    } else {
        /* u at (i..i+1, k-1..k), v at (j..j+1, k-1..k) */
        pa = cu->d + wind_idx(cu->sy, cu->sz, 0, j, k - 1), da0 = 1, da1 = cu->sz;
        pb = cv->d + wind_idx(cv->sy, cv->sz, 0, j, k - 1), db0 = cv->sy, db1 = cv->sz;
    }
    static int (*const fused[3])(float, int, int, int, const float *, const float *, int, int,
                                 const float *, int, int, float *) = {
        advect_row_u, advect_row_v, advect_row_w
    };
    if (!fused[a](s, nx, ca->sy, ca->sz, own, pa, da0, da1, pb, db0, db1, dst)) {
        return;
    }
    float *dx = w->scratch + (size_t)omp_get_thread_num() * WIND_SCRATCH_ROW(w);
    float *dy = dx + nx + 1, *dz = dy + nx + 1;
    advect_disp(a, s, nx, own, pa, da0, da1, pb, db0, db1, dx, dy, dz);
    advect_far(j, k, ca->n, ca->sy, ca->sz, dx, dy, dz, ca->d, dst);
}

/* Rows per block of the advection sweep: a block is swept plane by plane (k outer, j
 * inner), and each row (j, k) of all three components is traced in the same pass, so the
 * three planes a row reads (k - 1, k, k + 1) of u, v and w for the block's few rows stay
 * in the core's L2 across the sweep and each velocity array comes from memory about once
 * per step (not once per component). */
#define ADVECT_BLOCK_ROWS 16

void wind_advect(wind_grid *w, float dt_over_h)
{
    const size_t samples = (size_t)w->nx * (size_t)w->ny * (size_t)w->nz;
    const int threads = samples >= WIND_PAR_MIN ? w->d.threads : 1;
    /* MAC components differ by one sample on their own axis: sweep the largest extent
     * and skip the rows a component lacks. Each output row is the same function of the
     * old field whichever pass computes it (writes go to tmp), so the result does not
     * depend on the order or the split; static block chunks give the same rows to the
     * same thread every step. */
    int ny = 0, nz = 0;
    for (int a = 0; a < 3; a++) {
        ny = w->c[a].n[1] > ny ? w->c[a].n[1] : ny;
        nz = w->c[a].n[2] > nz ? w->c[a].n[2] : nz;
    }
    const int nb = (ny + ADVECT_BLOCK_ROWS - 1) / ADVECT_BLOCK_ROWS;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int b = 0; b < nb; b++) {
        const int j0 = b * ADVECT_BLOCK_ROWS;
        const int j1 = j0 + ADVECT_BLOCK_ROWS < ny ? j0 + ADVECT_BLOCK_ROWS : ny;
        for (int k = 0; k < nz; k++) {
            for (int j = j0; j < j1; j++) {
                for (int a = 0; a < 3; a++) {
                    const int na1 = w->c[a].n[1], na2 = w->c[a].n[2];
                    if (j < na1 && k < na2) {
                        advect_row(w, a, dt_over_h, k * na1 + j);
                    }
                }
            }
        }
    }
    for (int a = 0; a < 3; a++) {
        float *t = w->c[a].d;
        w->c[a].d = w->c[a].tmp;
        w->c[a].tmp = t;
    }
}
