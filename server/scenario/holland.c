/* The Holland (1980) parametric hurricane profile: see holland.h and PHYSICS.md
 * "Hurricanes". */
#include "holland.h"

#include <math.h>

double holland_coriolis(double lat_deg)
{
    return 2.0 * HOLLAND_OMEGA * sin(lat_deg * M_PI / 180.0);
}

double holland_b(double vmax_ms, double dp_pa, double rho)
{
    if (!(dp_pa > 0.0) || !(rho > 0.0) || !isfinite(vmax_ms)) {
        return HOLLAND_B_MIN;
    }
    double b = rho * M_E * vmax_ms * vmax_ms / dp_pa;
    if (b < HOLLAND_B_MIN) {
        b = HOLLAND_B_MIN;
    }
    if (b > HOLLAND_B_MAX) {
        b = HOLLAND_B_MAX;
    }
    return b;
}

/* (Rmax/r)^B, which overflows to +inf near the centre; the callers take exp(−x), which
 * is then exactly 0 (the calm, low centre). */
static double scaled(const holland_vortex *v, double r_m)
{
    return pow(v->rmax_m / r_m, v->b);
}

double holland_pressure(const holland_vortex *v, double r_m)
{
    if (!(r_m > 0.0)) {
        return v->pc_pa;
    }
    return v->pc_pa + (v->pn_pa - v->pc_pa) * exp(-scaled(v, r_m));
}

double holland_gradient_wind(const holland_vortex *v, double r_m)
{
    if (!(r_m > 0.0)) {
        return 0.0;
    }
    double x = scaled(v, r_m);
    double e = exp(-x);
    /* x·e(−x) is 0·inf = NaN once x overflows; the limit is 0 */
    double core = e > 0.0 ? v->b * (v->pn_pa - v->pc_pa) / v->rho * x * e : 0.0;
    double rf2 = 0.5 * r_m * fabs(v->f);
    double vg = sqrt(core + rf2 * rf2) - rf2;
    return vg > 0.0 ? vg : 0.0;
}

double holland_vmax(const holland_vortex *v)
{
    return sqrt(v->b * (v->pn_pa - v->pc_pa) / (v->rho * M_E));
}
