/* One damped modal oscillator q'' + γ q' + ω² q = f per mode (Diener 2008 eq. 8-9),
 * advanced by the exact discrete update for f held constant over the step: a 2×2
 * transition on (q, q') plus a forcing column, precomputed per species and dt. The
 * paper's explicit Euler is kept as a reference for tests. */
#ifndef GALE_OSCILLATOR_H
#define GALE_OSCILLATOR_H

typedef struct osc_coef {
    float a11, a12, a21, a22; /* (q, v)' = A (q, v) + b f */
    float b1, b2;
} osc_coef;

/* Exact transition for one step dt_s of an oscillator with angular frequency omega
 * [rad/s] > 0 and damping gamma [1/s] >= 0 (under-, critically or over-damped). */
osc_coef osc_exact(double omega, double gamma, double dt_s);

/* Advances (q, v) one step under constant force f with coefficients c. */
static inline void osc_step(const osc_coef *c, float f, float *q, float *v)
{
    float q0 = *q, v0 = *v;
    *q = c->a11 * q0 + c->a12 * v0 + c->b1 * f;
    *v = c->a21 * q0 + c->a22 * v0 + c->b2 * f;
}

/* The paper's explicit Euler step (reference only; unstable for large ω dt). */
void osc_euler(double omega, double gamma, double dt_s, double f, double *q, double *v);

#endif
