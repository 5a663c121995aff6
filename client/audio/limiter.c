/* The look-ahead limiter (limiter.h). */
#include <math.h>
#include <string.h>

#include "limiter.h"

void limiter_init(limiter *lim, float ceiling_dbfs, float lookahead_ms, float release_ms,
                  int rate_hz)
{
    memset(lim, 0, sizeof *lim);
    int len = (int)lrintf(lookahead_ms * 1e-3f * (float)rate_hz);
    lim->len = len < 1 ? 1 : len > LIMITER_MAX_LOOKAHEAD ? LIMITER_MAX_LOOKAHEAD : len;
    for (int i = 0; i <= lim->len; i++) {
        lim->need[i] = lim->held[i] = 1.0f;
    }
    lim->h = 1.0f;
    lim->min_gain = 1.0f;
    lim->release = 1.0f - expf(-1.0f / (release_ms * 1e-3f * (float)rate_hz));
    limiter_set_ceiling(lim, ceiling_dbfs);
}

void limiter_set_ceiling(limiter *lim, float ceiling_dbfs)
{
    lim->ceiling = fminf(powf(10.0f, fminf(ceiling_dbfs, 0.0f) / 20.0f), 1.0f);
}

void limiter_run(limiter *lim, float *l, float *r, int n)
{
    const int w = lim->len + 1;
    const float c = lim->ceiling;
    for (int i = 0; i < n; i++) {
        float pk = fmaxf(fabsf(l[i]), fabsf(r[i]));
        int at = lim->at;
        /* a hair under the ceiling, so the gain's rounding never lands a sample on the clamp */
        lim->need[at] = pk > c * 0.9999f ? c * 0.9999f / pk : 1.0f;
        float m = 1.0f;
        for (int k = 0; k < w; k++) {
            m = fminf(m, lim->need[k]);
        }
        lim->h = fminf(m, lim->h + (1.0f - lim->h) * lim->release);
        lim->held[at] = lim->h;
        float g = 0.0f;
        for (int k = 0; k < w; k++) {
            g += lim->held[k];
        }
        g /= (float)w;
        /* the sample that entered len samples ago leaves now */
        int out = (at + 1) % w;
        float yl = lim->xl[out] * g, yr = lim->xr[out] * g;
        lim->xl[at] = l[i];
        lim->xr[at] = r[i];
        if (fabsf(yl) > c || fabsf(yr) > c) {
            lim->clamped++;
            yl = fminf(fmaxf(yl, -c), c);
            yr = fminf(fmaxf(yr, -c), c);
        }
        lim->min_gain = fminf(lim->min_gain, g);
        l[i] = yl;
        r[i] = yr;
        lim->at = out;
    }
}
