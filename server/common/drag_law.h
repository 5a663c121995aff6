/* Streamlining of a crown in strong wind (PHYSICS.md "Streamlining"): the drag
 * coefficient falls with speed as C_d(U) = C_d0 (max(U, U_0) / U_0)^B, B the species'
 * Vogel exponent (B < 0), so the force grows as U^(2+B) above U_0 instead of U². The fits
 * behind B stop at fit_max_ms; above it the exponent either goes on ("extend") or C_d is
 * held at its value there ("hold": force ∝ U² again). Header-only: the tick, the bake
 * report and the tests share this one copy. */
#ifndef GALE_DRAG_LAW_H
#define GALE_DRAG_LAW_H

#include <math.h>

typedef struct drag_law {
    float vogel_b;        /* B, in [-1.5, 0]; 0: rigid drag, C_d = C_d0 at every speed */
    float u0_ms;          /* U_0: below it C_d = C_d0 (the bake's drag_c) [m/s] */
    float fit_max_ms;     /* top of the speeds the fit of B covers [m/s] */
    int hold_above_fit;   /* 1: C_d constant above fit_max_ms; 0: B extends */
} drag_law;

/* C_d(U) / C_d0 at wind speed u_ms; 1 for B = 0 or a non-positive U_0. */
static inline float drag_law_scale(const drag_law *d, float u_ms)
{
    if (!(d->vogel_b < 0.0f) || !(d->u0_ms > 0.0f) || !(u_ms > d->u0_ms)) {
        return 1.0f;
    }
    float u = u_ms;
    if (d->hold_above_fit && d->fit_max_ms > d->u0_ms && u > d->fit_max_ms) {
        u = d->fit_max_ms;
    }
    return powf(u / d->u0_ms, d->vogel_b);
}

#endif
