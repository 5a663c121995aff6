/* The per-mode damped oscillator of Diener 2008 eq. 8-9, q'' + γ q' + ω² q = f, advanced
 * exactly over one step for f held constant (the transition exp(T dt) of the first-order
 * system), and the paper's explicit Euler update (section 3.3, step 2) as a reference. */
#include "oscillator.h"

#include <math.h>

/* With σ = γ/2 and T = [[0, 1], [-ω², -γ]] = -σ I + N, N = [[σ, 1], [-ω², -σ]] and
 * N² = (σ² - ω²) I = d² I, so exp(T dt) = e^{-σ dt} (C I + S N) with C = cosh(d dt),
 * S = sinh(d dt)/d (cos / sin for d² < 0). Near critical damping both come from their
 * series in x = d² dt², which is smooth through x = 0. */
osc_coef osc_exact(double omega, double gamma, double dt_s)
{
    const double sigma = 0.5 * gamma;
    const double d2 = sigma * sigma - omega * omega;
    const double x = d2 * dt_s * dt_s;
    double ec, es; /* e^{-σ dt} C and e^{-σ dt} S */
    if (fabs(x) < 1e-3) {
        const double e = exp(-sigma * dt_s);
        ec = e * (1.0 + x / 2.0 + x * x / 24.0 + x * x * x / 720.0);
        es = e * dt_s * (1.0 + x / 6.0 + x * x / 120.0 + x * x * x / 5040.0);
    } else if (d2 < 0.0) {
        const double wd = sqrt(-d2);
        const double e = exp(-sigma * dt_s);
        ec = e * cos(wd * dt_s);
        es = e * sin(wd * dt_s) / wd;
    } else {
        /* Over-damped: 0 <= d < σ, so e^{(d-σ) dt} and e^{-(d+σ) dt} cannot overflow
         * where cosh(d dt) alone could. */
        const double d = sqrt(d2);
        const double ep = exp((d - sigma) * dt_s), em = exp(-(d + sigma) * dt_s);
        ec = 0.5 * (ep + em);
        es = 0.5 * (ep - em) / d;
    }
    osc_coef c;
    const double a11 = ec + sigma * es, a12 = es;
    const double a21 = -omega * omega * es, a22 = ec - sigma * es;
    c.a11 = (float)a11;
    c.a12 = (float)a12;
    c.a21 = (float)a21;
    c.a22 = (float)a22;
    /* Constant f: the state relaxes towards (f/ω², 0), so b = (I - A)(1/ω², 0). */
    c.b1 = (float)((1.0 - a11) / (omega * omega));
    c.b2 = (float)es;
    return c;
}

/* Diener 2008 section 3.3 step 2 (unit modal mass): acceleration from the old state,
 * then velocity, then position with the new velocity. */
void osc_euler(double omega, double gamma, double dt_s, double f, double *q, double *v)
{
    const double acc = f - gamma * *v - omega * omega * *q;
    *v += dt_s * acc;
    *q += dt_s * *v;
}
