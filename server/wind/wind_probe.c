/* Fixed sampling points with their stencils worked out once: see wind.h wind_probe. */
#include "wind_int.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

struct wind_probe {
    int n;
    int32_t *o[3];     /* owned [n]: padded index of the stencil's low corner, per component */
    float *t[3][3];    /* owned [n]: its fractions along x, y, z, per component */
};

void wind_probe_destroy(wind_probe *pr)
{
    if (!pr) {
        return;
    }
    for (int a = 0; a < 3; a++) {
        free(pr->o[a]);
        for (int b = 0; b < 3; b++) {
            free(pr->t[a][b]);
        }
    }
    free(pr);
}

wind_probe *wind_probe_create(const wind_grid *w, int n, const float *p, gale_err *err)
{
    if (n < 0 || (n > 0 && !p)) {
        gale_errf(err, GALE_E_ARG, "wind_probe_create: %d points", n);
        return NULL;
    }
    for (int a = 0; a < 3; a++) {
        if (w->c[a].count > (size_t)INT32_MAX) {
            gale_errf(err, GALE_E_RANGE, "wind_probe_create: component %d has %zu samples, "
                      "more than 32-bit indices reach", a, w->c[a].count);
            return NULL;
        }
    }
    wind_probe *pr = calloc(1, sizeof *pr);
    if (!pr) {
        gale_errf(err, GALE_E_NOMEM, "wind_probe_create: no memory");
        return NULL;
    }
    pr->n = n;
    const size_t m = n > 0 ? (size_t)n : 1;
    bool ok = true;
    for (int a = 0; a < 3; a++) {
        ok = ok && (pr->o[a] = malloc(m * sizeof(int32_t)));
        for (int b = 0; b < 3; b++) {
            ok = ok && (pr->t[a][b] = malloc(m * sizeof(float)));
        }
    }
    if (!ok) {
        wind_probe_destroy(pr);
        gale_errf(err, GALE_E_NOMEM, "wind_probe_create: no memory for %d points", n);
        return NULL;
    }
    /* the clamps and the cell of wind_sample.c's sample_comp, operation for operation, so the
       fractions are the floats it computes */
    const float inv = 1.0f / w->h;
    for (int i = 0; i < n; i++) {
        const float x[3] = { (p[3 * i] - w->d.origin[0]) * inv,
                             (p[3 * i + 1] - w->d.origin[1]) * inv,
                             (p[3 * i + 2] - w->d.origin[2]) * inv };
        for (int a = 0; a < 3; a++) {
            const wind_comp *c = &w->c[a];
            int q[3];
            for (int b = 0; b < 3; b++) {
                const int nb = c->n[b];
                float f = x[b] - c->off[b];
                float v = f < 0.0f ? 0.0f : f;
                v = v > (float)(nb - 1) ? (float)(nb - 1) : v;
                int k = (int)v;
                /* the last sample is reached as the upper end of the cell below it */
                k = k < nb - 1 ? k : (nb > 1 ? nb - 2 : 0);
                q[b] = k;
                pr->t[a][b][i] = v - (float)k;
            }
            pr->o[a][i] = (int32_t)wind_idx(c->sy, c->sz, q[0], q[1], q[2]);
        }
    }
    return pr;
}

/* One component at points [i0, i1), written every third float of v: the blend of
 * sample_comp in its order. Cloned for AVX-512 and AVX2, where the eight reads of
 * consecutive points become gathers; every clone computes the same floats. */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
static void probe_comp(const float *restrict d, int sy, int sz, const int32_t *restrict o,
                       const float *restrict tx, const float *restrict ty,
                       const float *restrict tz, int i0, int i1, float *restrict v)
{
    for (int i = i0; i < i1; i++) {
        const int k = o[i];
        const float t0 = tx[i], t1 = ty[i], t2 = tz[i];
        float c00 = d[k] + t0 * (d[k + 1] - d[k]);
        float c10 = d[k + sy] + t0 * (d[k + sy + 1] - d[k + sy]);
        float c01 = d[k + sz] + t0 * (d[k + sz + 1] - d[k + sz]);
        float c11 = d[k + sz + sy] + t0 * (d[k + sz + sy + 1] - d[k + sz + sy]);
        float c0 = c00 + t1 * (c10 - c00);
        float c1 = c01 + t1 * (c11 - c01);
        v[3 * i] = c0 + t2 * (c1 - c0);
    }
}

void wind_probe_sample(const wind_grid *w, const wind_probe *pr, int i0, int i1, float *v)
{
    i0 = i0 < 0 ? 0 : i0;
    i1 = i1 > pr->n ? pr->n : i1;
    for (int a = 0; a < 3; a++) {
        const wind_comp *c = &w->c[a];
        probe_comp(wind_comp_read(c), c->sy, c->sz, pr->o[a], pr->t[a][0], pr->t[a][1],
                   pr->t[a][2], i0, i1, v + a);
    }
}

static int cmp_uptr(const void *a, const void *b)
{
    const uintptr_t x = *(const uintptr_t *)a, y = *(const uintptr_t *)b;
    return (x > y) - (x < y);
}

int wind_probe_lines(const wind_grid *w, const wind_probe *pr, int i0, int i1, size_t *lines,
                     gale_err *err)
{
    i0 = i0 < 0 ? 0 : i0;
    i1 = i1 > pr->n ? pr->n : i1;
    *lines = 0;
    if (i1 <= i0) {
        return 0;
    }
    /* every sample's line, sorted, counted once each */
    enum { READS = 3 * 8 };
    const size_t n = (size_t)(i1 - i0) * READS;
    uintptr_t *id = malloc(n * sizeof *id);
    if (!id) {
        return gale_errf(err, GALE_E_NOMEM, "wind_probe_lines: no memory for %zu reads", n);
    }
    size_t m = 0;
    for (int a = 0; a < 3; a++) {
        const wind_comp *c = &w->c[a];
        const float *d = wind_comp_read(c);
        const size_t at[8] = { 0, 1, (size_t)c->sy, (size_t)c->sy + 1, (size_t)c->sz,
                               (size_t)c->sz + 1, (size_t)(c->sz + c->sy),
                               (size_t)(c->sz + c->sy) + 1 };
        for (int i = i0; i < i1; i++) {
            for (int s = 0; s < 8; s++) {
                id[m++] = (uintptr_t)(d + (size_t)pr->o[a][i] + at[s]) / 64u;
            }
        }
    }
    qsort(id, n, sizeof *id, cmp_uptr);
    size_t count = 1;
    for (size_t k = 1; k < n; k++) {
        count += id[k] != id[k - 1];
    }
    free(id);
    *lines = count;
    return 0;
}
