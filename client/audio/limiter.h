/* A look-ahead peak limiter, both channels linked, with a ceiling no sample passes. The
 * gain each sample needs (ceiling / peak, at most 1) is held at its minimum over the
 * look-ahead window, released slowly, and averaged over a box of the window's length,
 * while the signal is delayed by the window: every gain in the box is at most what the
 * sample it meets needs, so their mean is too, and the gain is down before a peak arrives
 * without a step. What rounding leaves is clamped, and counted. */
#ifndef GALE_LIMITER_H
#define GALE_LIMITER_H

#include <stdint.h>

#define LIMITER_MAX_LOOKAHEAD 512

typedef struct limiter {
    float ceiling;                        /* linear, (0, 1] */
    int len;                              /* window [samples] */
    float xl[LIMITER_MAX_LOOKAHEAD + 1];  /* the delay line */
    float xr[LIMITER_MAX_LOOKAHEAD + 1];
    float need[LIMITER_MAX_LOOKAHEAD + 1];
    float held[LIMITER_MAX_LOOKAHEAD + 1];
    int at;
    float h;                              /* the released gain */
    float release;                        /* its step towards 1 a sample */
    uint64_t clamped;                     /* samples the final clamp changed */
    float min_gain;                       /* the least gain applied so far */
} limiter;

/* ceiling_dbfs ≤ 0, lookahead_ms and release_ms at rate_hz. */
void limiter_init(limiter *lim, float ceiling_dbfs, float lookahead_ms, float release_ms,
                  int rate_hz);

/* The ceiling anew (the limiter's state kept). */
void limiter_set_ceiling(limiter *lim, float ceiling_dbfs);

/* Limits n samples of l and r in place (delayed by the window). */
void limiter_run(limiter *lim, float *l, float *r, int n);

#endif
