/* Streamlining of a crown in strong wind (PHYSICS.md "Streamlining"): the drag
 * coefficient falls with speed as C_d(U) = C_d0 (max(U, U_0) / U_0)^B, B the species'
 * Vogel exponent (B < 0), so the force grows as U^(2+B) above U_0 instead of U². The fits
 * behind B stop at fit_max_ms; above it the exponent either goes on ("extend") or C_d is
 * held at its value there ("hold": force ∝ U² again). Header-only: the tick, the bake
 * report and the tests share this one copy. */
#ifndef GALE_DRAG_LAW_H
#define GALE_DRAG_LAW_H

#include <math.h>
#include <stdint.h>

typedef struct drag_law {
    float vogel_b;        /* B, in [-1.5, 0]; 0: rigid drag, C_d = C_d0 at every speed */
    float u0_ms;          /* U_0: below it C_d = C_d0 (the bake's drag_c) [m/s] */
    float fit_max_ms;     /* top of the speeds the fit of B covers [m/s] */
    int hold_above_fit;   /* 1: C_d constant above fit_max_ms; 0: B extends */
} drag_law;

/* x^b for x >= 1 and b <= 0, as 2^(b log2 x) in float arithmetic alone (no libm call,
 * so a loop of it vectorises, and every caller rounds alike): log2 x from x's exponent
 * and the series ln m = 2 atanh((m - 1)/(m + 1)) of its mantissa folded into
 * [sqrt(1/2), sqrt(2)) (truncation < 1e-9), 2^y from y's nearest integer and the Taylor
 * series of e^(f ln 2) to f^7 for the rest, |f| <= 1/2 (truncation < 1e-8). Within 5e-7
 * of pow for x < 2^16 and b >= -1.5 (tests/test_drag.c); 0 below 2^-126. */
static inline float drag_pow(float x, float b)
{
    /* signed words throughout: x > 0, so its sign bit is clear; the words read through
       unions, which vectorise where memcpy's copies do not */
    const int32_t ix = (union { float f; int32_t i; }){ .f = x }.i;
    int32_t e = (ix >> 23) - 127;
    const int32_t im = (ix & 0x7fffff) | 0x3f800000;
    float m = (union { int32_t i; float f; }){ .i = im }.f;
    const int32_t big = m > 1.41421356f;
    m = big ? 0.5f * m : m;
    e += big;
    const float s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
    const float ln_m =
        2.0f * s * (1.0f + s2 * (1.0f / 3.0f + s2 * (1.0f / 5.0f + s2 * (1.0f / 7.0f + s2 * (1.0f / 9.0f)))));
    /* y = b log2 x, and its split into the nearest integer n and f, in double: in float
       the rounding of log2 x near 16 alone would be 1e-6 of the power */
    double y = (double)b * ((double)ln_m * 1.4426950408889634 + (double)e);
    y = y > -126.0 ? y : -126.0;
    /* y's nearest integer by adding 1.5 2^52, which leaves it in the low mantissa bits
       (|y| < 2^51): no floor, which not every target takes in vectors */
    const double k = y + 6755399441055744.0;
    const int32_t n = (int32_t)((union { double f; int64_t i; }){ .f = k }.i - 0x4338000000000000);
    const float g = (float)((y - (k - 6755399441055744.0)) * 0.6931471805599453);
    const float p =
        1.0f + g * (1.0f + g * (0.5f + g * (1.0f / 6.0f + g * (1.0f / 24.0f + g * (1.0f / 120.0f +
                                                                              g * (1.0f / 720.0f + g * (1.0f / 5040.0f)))))));
    /* 2^n: n added to the exponent (p in [0.7, 1.5], n >= -126) */
    const int32_t ip = (union { float f; int32_t i; }){ .f = p }.i + n * (1 << 23);
    const float r = (union { int32_t i; float f; }){ .i = ip }.f;
    return y > -126.0 ? r : 0.0f;
}

/* The terms of C_d(U) / C_d0 = drag_pow(drag_base(U, u0, cap), b) that do not depend on
 * U: U_0, the cap on U (the fit's top with "hold", else none) and B; u0 = cap = 1, b = 0
 * (a scale of exactly 1) for B = 0 or a non-positive U_0. */
static inline void drag_law_terms(const drag_law *d, float *u0, float *cap, float *b)
{
    const int on = d->vogel_b < 0.0f && d->u0_ms > 0.0f;
    *u0 = on ? d->u0_ms : 1.0f;
    *cap = !on ? 1.0f : d->hold_above_fit && d->fit_max_ms > d->u0_ms ? d->fit_max_ms : INFINITY;
    *b = on ? d->vogel_b : 0.0f;
}

/* The base max(U, U_0) / U_0, U capped at cap: exactly 1 at U <= U_0 (and for a NaN U).
 * A max and a min where branches would do, so a loop over many trees takes it in vectors:
 * over a forest U crosses U_0 and the fit's top from tree to tree, and a branch on it is
 * guessed wrong about as often as right. */
static inline float drag_base(float u_ms, float u0, float cap)
{
    float u = u_ms > u0 ? u_ms : u0;
    u = u < cap ? u : cap;
    return u / u0;
}

/* C_d(U) / C_d0 at wind speed u_ms; 1 for B = 0 or a non-positive U_0. */
static inline float drag_law_scale(const drag_law *d, float u_ms)
{
    float u0, cap, b;
    drag_law_terms(d, &u0, &cap, &b);
    return drag_pow(drag_base(u_ms, u0, cap), b);
}

#endif
