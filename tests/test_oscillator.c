/* The exact modal oscillator update (server/oscillator.c) against closed-form damped
 * responses in all three damping regimes, and the paper's explicit Euler reference
 * diverging where ω·dt is large while the exact update stays bounded. */
#include <math.h>

#include "check.h"
#include "oscillator.h"

/* Closed-form q(t) of q'' + γ q' + ω² q = f from (q0, v0), f constant. */
static double closed_q(double w, double g, double f, double q0, double v0, double t)
{
    const double qs = f / (w * w), x0 = q0 - qs, s = 0.5 * g;
    const double d2 = s * s - w * w;
    if (d2 < 0.0) {
        const double wd = sqrt(-d2);
        return qs + exp(-s * t) * (x0 * cos(wd * t) + (v0 + s * x0) / wd * sin(wd * t));
    }
    if (d2 == 0.0) {
        return qs + exp(-w * t) * (x0 + (v0 + w * x0) * t);
    }
    const double d = sqrt(d2), r1 = -s + d, r2 = -s - d;
    const double c1 = (v0 - r2 * x0) / (r1 - r2), c2 = x0 - c1;
    return qs + c1 * exp(r1 * t) + c2 * exp(r2 * t);
}

/* Steps n times in float and compares q at every step with the closed form. Tolerance:
 * float coefficients and state give ~1e-6 relative error per step, growing ~linearly. */
static double max_err(double w, double g, double f, double q0, double v0, double dt, int n)
{
    osc_coef c = osc_exact(w, g, dt);
    float q = (float)q0, v = (float)v0;
    double worst = 0.0, scale = fabs(q0) + fabs(v0) / w + fabs(f) / (w * w);
    for (int k = 1; k <= n; k++) {
        osc_step(&c, (float)f, &q, &v);
        double e = fabs((double)q - closed_q(w, g, f, q0, v0, k * dt)) / scale;
        if (e > worst) {
            worst = e;
        }
    }
    return worst;
}

static void test_underdamped(void)
{
    /* 1 Hz mode, 2% damping ratio, 60 Hz step, 10 s */
    double w = 2.0 * M_PI, g = 2.0 * 0.02 * w;
    CHECK_NEAR(max_err(w, g, 3.0, 0.1, -0.5, 1.0 / 60.0, 600), 0.0, 2e-5);
    /* undamped, ω dt = 3 (far beyond Euler's limit) */
    CHECK_NEAR(max_err(180.0, 0.0, 0.0, 1.0, 0.0, 1.0 / 60.0, 600), 0.0, 2e-4);
}

static void test_critical(void)
{
    double w = 5.0;
    CHECK_NEAR(max_err(w, 2.0 * w, 1.0, -0.2, 0.7, 0.01, 500), 0.0, 2e-5);
    /* just off critical on either side: the series branch must agree with both forms */
    CHECK_NEAR(max_err(w, 2.0 * w * (1.0 + 1e-6), 1.0, -0.2, 0.7, 0.01, 500), 0.0, 2e-5);
    CHECK_NEAR(max_err(w, 2.0 * w * (1.0 - 1e-6), 1.0, -0.2, 0.7, 0.01, 500), 0.0, 2e-5);
}

static void test_overdamped(void)
{
    CHECK_NEAR(max_err(3.0, 40.0, -2.0, 0.3, 1.0, 1.0 / 60.0, 300), 0.0, 2e-5);
    /* stiff: β ω² damping of a high mode, γ dt ≫ 1, must not overflow */
    osc_coef c = osc_exact(2000.0, 4000.0, 1.0 / 60.0);
    CHECK(isfinite(c.a11) && isfinite(c.a12) && isfinite(c.a21) && isfinite(c.a22));
    CHECK(isfinite(c.b1) && isfinite(c.b2));
}

/* A single step against exp(T dt) from a 40-term Taylor series of the 2x2 matrix. */
static void test_matrix_exponential(void)
{
    const double w = 7.0, g = 1.3, dt = 0.05;
    double T[4] = { 0, 1, -w * w, -g }, term[4] = { 1, 0, 0, 1 }, E[4] = { 1, 0, 0, 1 };
    for (int k = 1; k < 40; k++) {
        double n0 = (term[0] * T[0] + term[1] * T[2]) * dt / k;
        double n1 = (term[0] * T[1] + term[1] * T[3]) * dt / k;
        double n2 = (term[2] * T[0] + term[3] * T[2]) * dt / k;
        double n3 = (term[2] * T[1] + term[3] * T[3]) * dt / k;
        term[0] = n0, term[1] = n1, term[2] = n2, term[3] = n3;
        for (int i = 0; i < 4; i++) {
            E[i] += term[i];
        }
    }
    osc_coef c = osc_exact(w, g, dt);
    CHECK_NEAR(c.a11, E[0], 1e-6);
    CHECK_NEAR(c.a12, E[1], 1e-6);
    CHECK_NEAR(c.a21, E[2], 1e-5);
    CHECK_NEAR(c.a22, E[3], 1e-6);
    /* equilibrium is a fixed point: q = f/ω², v = 0 */
    float q = (float)(2.0 / (w * w)), v = 0.0f;
    osc_step(&c, 2.0f, &q, &v);
    CHECK_NEAR(q, 2.0 / (w * w), 1e-7);
    CHECK_NEAR(v, 0.0, 1e-6);
}

static void test_euler_diverges_exact_bounded(void)
{
    /* ω dt = 200/60 = 3.3 > 2: the explicit (symplectic) Euler update is unstable */
    const double w = 200.0, g = 2.0 * 0.01 * w, dt = 1.0 / 60.0;
    double qe = 1.0, ve = 0.0;
    osc_coef c = osc_exact(w, g, dt);
    float q = 1.0f, v = 0.0f;
    double qmax = 0.0;
    for (int k = 0; k < 200; k++) {
        osc_euler(w, g, dt, 0.0, &qe, &ve);
        osc_step(&c, 0.0f, &q, &v);
        if (fabs(q) > qmax) {
            qmax = fabs(q);
        }
    }
    CHECK(!(fabs(qe) < 1e6)); /* blown up (or inf/NaN) */
    CHECK(qmax <= 1.0 + 1e-6);
    /* and at small ω dt the reference agrees with the exact update (first order) */
    const double w2 = 2.0, dt2 = 1e-3;
    qe = 1.0, ve = 0.0;
    for (int k = 0; k < 1000; k++) {
        osc_euler(w2, 0.1, dt2, 0.5, &qe, &ve);
    }
    CHECK_NEAR(qe, closed_q(w2, 0.1, 0.5, 1.0, 0.0, 1.0), 5e-3);
}

int main(void)
{
    RUN(test_underdamped);
    RUN(test_critical);
    RUN(test_overdamped);
    RUN(test_matrix_exponential);
    RUN(test_euler_diverges_exact_bounded);
    return check_report();
}
