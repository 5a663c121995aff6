/* Synthetic trees for the bake benchmark and tests: branches are chains of segments
 * grown breadth-first; each non-base node of a branch spawns a child branch at a random
 * azimuth, 60% of the parent's length and radius. */
#include "bake_tree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct branch {
    int from;        /* node the branch starts at */
    double dir[3];   /* unit growth direction */
    double length_m; /* whole branch */
    double r0_m;     /* radius at its base */
    int depth;
} branch;

static double rnd(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static void normalize(double v[3])
{
    const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) {
        v[k] /= n;
    }
}

int bake_tree_generate(int n, uint64_t seed, skeleton *s, gale_err *err)
{
    if (n < 2) {
        return gale_errf(err, GALE_E_RANGE, "bake_tree: %d nodes, expected at least 2", n);
    }
    int rc = skeleton_alloc(s, n, err);
    if (rc != GALE_OK) {
        return rc;
    }
    branch *q = malloc((size_t)n * sizeof *q);
    if (!q) {
        skeleton_fini(s);
        return gale_errf(err, GALE_E_NOMEM, "bake_tree: out of memory for %d nodes", n);
    }
    uint64_t st = seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
    if (st == 0) {
        st = 1;
    }
    s->parent[0] = -1;
    memset(s->pos, 0, 3 * sizeof *s->pos);
    s->radius[0] = 0.25f;
    s->order[0] = 0;
    int count = 1, head = 0, tail = 0;
    q[tail++] = (branch){ 0, { 0, 0, 1 }, 10.0, 0.25, 0 };
    while (head < tail && count < n) {
        branch b = q[head++];
        const int segs = b.depth == 0 ? 12 : b.depth == 1 ? 7 : 4;
        const double seg = b.length_m / segs;
        int prev = b.from;
        double dir[3] = { b.dir[0], b.dir[1], b.dir[2] };
        for (int k = 1; k <= segs && count < n; k++) {
            const int i = count++;
            /* a slight random bend, and tips curving up */
            for (int c = 0; c < 3; c++) {
                dir[c] += 0.12 * (rnd(&st) - 0.5);
            }
            dir[2] += 0.04;
            normalize(dir);
            s->parent[i] = prev;
            for (int c = 0; c < 3; c++) {
                s->pos[3 * i + c] = s->pos[3 * prev + c] + (float)(seg * dir[c]);
            }
            const double t = (double)k / segs;
            s->radius[i] = (float)(b.r0_m * (1.0 - 0.7 * t));
            s->order[i] = b.depth;
            if (k < segs && tail < n && (b.depth > 0 || k >= 4)) {
                /* child branch at a random azimuth about dir, 50 deg off it */
                double ref[3] = { 0, 0, 1 };
                if (fabs(dir[2]) > 0.9) {
                    ref[0] = 1, ref[2] = 0;
                }
                double u[3] = { dir[1] * ref[2] - dir[2] * ref[1],
                                dir[2] * ref[0] - dir[0] * ref[2],
                                dir[0] * ref[1] - dir[1] * ref[0] };
                normalize(u);
                double w[3] = { dir[1] * u[2] - dir[2] * u[1], dir[2] * u[0] - dir[0] * u[2],
                                dir[0] * u[1] - dir[1] * u[0] };
                const double az = 2.0 * M_PI * rnd(&st), el = 0.87;
                branch c = { i, { 0, 0, 0 }, b.length_m * (0.6 - 0.3 * t), (double)s->radius[i] * 0.6,
                             b.depth + 1 };
                for (int d = 0; d < 3; d++) {
                    c.dir[d] = cos(el) * dir[d] + sin(el) * (cos(az) * u[d] + sin(az) * w[d]);
                }
                normalize(c.dir);
                q[tail++] = c;
            }
            prev = i;
        }
    }
    /* if the queue ran dry (tiny n cannot), extend the last node straight up */
    while (count < n) {
        const int i = count++;
        s->parent[i] = i - 1;
        s->pos[3 * i + 0] = s->pos[3 * (i - 1) + 0];
        s->pos[3 * i + 1] = s->pos[3 * (i - 1) + 1];
        s->pos[3 * i + 2] = s->pos[3 * (i - 1) + 2] + 0.05f;
        s->radius[i] = s->radius[i - 1];
        s->order[i] = s->order[i - 1];
    }
    free(q);
    return GALE_OK;
}
