/* Reading the wind field: the samplers' copy (wind_publish), trilinear sampling at
 * points with the subgrid profile added where the grid has one, and the coarse copy for
 * clients. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "wind_int.h"

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
