/* Skeleton storage: allocation and release. CSV import lives in skeleton_csv.c. */
#include "skeleton.h"

#include <stdlib.h>
#include <string.h>

int skeleton_alloc(skeleton *s, int n, gale_err *err)
{
    memset(s, 0, sizeof *s);
    if (n <= 0) {
        return gale_errf(err, GALE_E_RANGE, "skeleton: expected at least 1 node, got %d", n);
    }
    s->n = n;
    s->parent = malloc((size_t)n * sizeof *s->parent);
    s->pos = calloc((size_t)n * 3, sizeof *s->pos);
    s->radius = calloc((size_t)n, sizeof *s->radius);
    s->order = calloc((size_t)n, sizeof *s->order);
    if (!s->parent || !s->pos || !s->radius || !s->order) {
        skeleton_fini(s);
        return gale_errf(err, GALE_E_NOMEM, "skeleton: out of memory for %d nodes", n);
    }
    for (int i = 0; i < n; i++) {
        s->parent[i] = -1;
    }
    return GALE_OK;
}

void skeleton_fini(skeleton *s)
{
    if (!s) {
        return;
    }
    free(s->parent);
    free(s->pos);
    free(s->radius);
    free(s->order);
    free(s->src_id);
    memset(s, 0, sizeof *s);
}
