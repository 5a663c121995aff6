/* The trees a client holds of a scene too large for it: the nearest to a point, sorted by
 * squared 2D distance and index (hold.h; web/hold.js is the same). */
#include "hold.h"

#include <math.h>
#include <stdlib.h>

typedef struct hold_key {
    double d2; /* [m²] squared 2D distance to the point */
    uint32_t t;
} hold_key;

static int key_order(const void *a, const void *b)
{
    const hold_key *x = a, *y = b;
    if (x->d2 != y->d2) {
        return x->d2 < y->d2 ? -1 : 1;
    }
    return x->t < y->t ? -1 : x->t > y->t;
}

static int index_order(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

void hold_centre(const ctl_instance *inst, uint32_t n, double c[2])
{
    double sx = 0.0, sy = 0.0;
    for (uint32_t t = 0; t < n; t++) {
        sx += (double)inst[t].pos[0];
        sy += (double)inst[t].pos[1];
    }
    c[0] = n ? sx / (double)n : 0.0;
    c[1] = n ? sy / (double)n : 0.0;
}

int hold_nearest(const ctl_instance *inst, uint32_t n, double cx, double cy, uint32_t limit,
                 uint32_t *held, hold_circle *out, gale_err *err)
{
    const uint32_t k = limit < n ? limit : n;
    *out = (hold_circle){ .cx = cx, .cy = cy, .n_held = k };
    if (k == 0) {
        return 0;
    }
    hold_key *key = malloc((size_t)n * sizeof *key);
    if (!key) {
        return gale_errf(err, GALE_E_NOMEM, "hold_nearest: no memory to sort %u trees", n);
    }
    for (uint32_t t = 0; t < n; t++) {
        /* two statements, no fused multiply-add: web/hold.js rounds the same */
        const double dx = (double)inst[t].pos[0] - cx, dy = (double)inst[t].pos[1] - cy;
        const double dx2 = dx * dx, dy2 = dy * dy;
        key[t] = (hold_key){ .d2 = dx2 + dy2, .t = t };
    }
    qsort(key, n, sizeof *key, key_order);
    for (uint32_t i = 0; i < k; i++) {
        held[i] = key[i].t;
    }
    qsort(held, k, sizeof *held, index_order);
    out->radius_m = sqrt(key[k - 1].d2);
    out->edge_m = k < n ? 0.5 * (out->radius_m + sqrt(key[k].d2)) : out->radius_m;
    free(key);
    return 0;
}

double hold_view_radius_m(const hold_circle *h, double margin_m)
{
    const double r = h->edge_m - margin_m;
    return r > 1e6 ? 1e6 : r > 0.001 ? r : 0.001;
}
