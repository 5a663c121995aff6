/* Holland (1980) profile against its closed form: peak at Rmax, calm centre, far-field
 * decay, B from Vmax and Δp, and Andrew's landfall figures from PHYSICS.md. */
#include <math.h>

#include "check.h"
#include "holland.h"

/* Andrew at landfall: p_c 922 hPa, p_n 1013 hPa, Rmax 18.5 km, B 2.36, 25.5° N. */
static holland_vortex andrew(void)
{
    return (holland_vortex){ .pc_pa = 92200.0,
                             .pn_pa = 101300.0,
                             .rmax_m = 18500.0,
                             .b = 2.36,
                             .f = holland_coriolis(25.5),
                             .rho = 1.15 };
}

static void test_coriolis(void)
{
    CHECK_NEAR(holland_coriolis(90.0), 2.0 * 7.292e-5, 1e-12);
    CHECK_NEAR(holland_coriolis(0.0), 0.0, 1e-15);
    CHECK_NEAR(holland_coriolis(30.0), 7.292e-5, 1e-12);
    CHECK(holland_coriolis(-25.0) < 0.0);
}

static void test_b_from_vmax(void)
{
    /* B = ρ e V² / Δp: Andrew's 145 kt surface wind / 0.9 = 82.9 m/s, Δp = 91 hPa */
    double vg = 145.0 * 0.514444 / 0.9;
    CHECK_NEAR(holland_b(vg, 9100.0, 1.15), 1.15 * M_E * vg * vg / 9100.0, 1e-12);
    CHECK_NEAR(holland_b(vg, 9100.0, 1.15), 2.36, 0.01);
    /* clamps */
    CHECK_NEAR(holland_b(10.0, 9100.0, 1.15), 1.0, 0.0);
    CHECK_NEAR(holland_b(120.0, 3000.0, 1.15), 2.5, 0.0);
    CHECK_NEAR(holland_b(50.0, 0.0, 1.15), 1.0, 0.0);
    CHECK_NEAR(holland_b(50.0, -5.0, 1.15), 1.0, 0.0);
    /* the inverse: the cyclostrophic peak of the fitted B is the V it came from */
    holland_vortex v = andrew();
    v.b = holland_b(70.0, 9100.0, 1.15);
    CHECK_NEAR(holland_vmax(&v), 70.0, 1e-9);
}

static void test_closed_form(void)
{
    holland_vortex v = andrew();
    double k = v.b * (v.pn_pa - v.pc_pa) / v.rho;
    for (double r = 1000.0; r < 400000.0; r *= 1.37) {
        double x = pow(v.rmax_m / r, v.b);
        double rf = r * v.f / 2.0;
        double want = sqrt(k * x * exp(-x) + rf * rf) - rf;
        CHECK_NEAR(holland_gradient_wind(&v, r), want, 1e-9 * (1.0 + want));
        CHECK_NEAR(holland_pressure(&v, r), v.pc_pa + (v.pn_pa - v.pc_pa) * exp(-x), 1e-6);
    }
}

static void test_shape(void)
{
    holland_vortex v = andrew();
    /* calm, lowest centre */
    CHECK_NEAR(holland_gradient_wind(&v, 0.0), 0.0, 0.0);
    CHECK_NEAR(holland_gradient_wind(&v, 1.0), 0.0, 1e-9);
    CHECK_NEAR(holland_pressure(&v, 0.0), v.pc_pa, 0.0);
    CHECK_NEAR(holland_pressure(&v, 1.0), v.pc_pa, 1e-6);
    CHECK_NEAR(holland_pressure(&v, 1e9), v.pn_pa, 1.0);
    /* peak at Rmax: scan finely; with Coriolis the peak sits within 1 % of Rmax */
    double best = 0.0, rbest = 0.0;
    for (double r = 5000.0; r < 60000.0; r += 10.0) {
        double s = holland_gradient_wind(&v, r);
        if (s > best) {
            best = s;
            rbest = r;
        }
    }
    CHECK_NEAR(rbest, v.rmax_m, 0.01 * v.rmax_m);
    /* the cyclostrophic peak sqrt(BΔp/(ρe)) less the Coriolis term r f / 2 (≈ 0.6 m/s) */
    CHECK_NEAR(best, holland_vmax(&v), 1.0);
    CHECK(best < holland_vmax(&v));
    /* monotone: rising inside Rmax, falling outside */
    double prev = 0.0;
    for (double r = 1000.0; r <= v.rmax_m * 0.99; r += 500.0) {
        double s = holland_gradient_wind(&v, r);
        CHECK(s >= prev);
        prev = s;
    }
    prev = 1e9;
    for (double r = v.rmax_m * 1.01; r < 500000.0; r += 2000.0) {
        double s = holland_gradient_wind(&v, r);
        CHECK(s <= prev);
        prev = s;
    }
    /* far field without rotation: V ≈ sqrt(BΔp/ρ) (R/r)^(B/2) */
    holland_vortex nf = v;
    nf.f = 0.0;
    double r = 20.0 * v.rmax_m;
    double far = sqrt(v.b * (v.pn_pa - v.pc_pa) / v.rho) * pow(v.rmax_m / r, v.b / 2.0);
    CHECK_NEAR(holland_gradient_wind(&nf, r), far, 0.001 * far);
    /* pressure rises monotonically outward */
    CHECK(holland_pressure(&v, 10000.0) < holland_pressure(&v, 20000.0));
    CHECK(holland_pressure(&v, 20000.0) < holland_pressure(&v, 80000.0));
}

static void test_andrew_figures(void)
{
    /* PHYSICS.md: V_g ≈ 0 at ≤ 5 km, 82 m/s at Rmax (18.5 km), 54 at 37 km, 16 at
     * 100 km. Tolerance ±1.5 m/s: the figures are quoted to whole m/s and the ambient
     * pressure (1010–1013 hPa) is not pinned. */
    holland_vortex v = andrew();
    CHECK_NEAR(holland_gradient_wind(&v, 5000.0), 0.0, 0.5);
    CHECK_NEAR(holland_gradient_wind(&v, 18500.0), 82.0, 1.5);
    CHECK_NEAR(holland_gradient_wind(&v, 37000.0), 54.0, 1.5);
    CHECK_NEAR(holland_gradient_wind(&v, 100000.0), 16.0, 1.5);
    /* southern hemisphere: the same speeds */
    holland_vortex s = v;
    s.f = -s.f;
    CHECK_NEAR(holland_gradient_wind(&s, 37000.0), holland_gradient_wind(&v, 37000.0), 1e-12);
}

int main(void)
{
    RUN(test_coriolis);
    RUN(test_b_from_vmax);
    RUN(test_closed_form);
    RUN(test_shape);
    RUN(test_andrew_figures);
    return check_report();
}
