/* The Holland (1980) parametric hurricane: sea-level pressure and gradient wind as a
 * function of radius from the centre, with the shape parameter B taken from the peak wind
 * and the pressure deficit (PHYSICS.md "Hurricanes"). SI units throughout. */
#ifndef GALE_HOLLAND_H
#define GALE_HOLLAND_H

#define HOLLAND_RHO_AIR 1.15     /* boundary-layer air density [kg/m³] */
#define HOLLAND_OMEGA   7.292e-5 /* Earth's rotation rate [rad/s] */
#define HOLLAND_B_MIN   1.0
#define HOLLAND_B_MAX   2.5

typedef struct holland_vortex {
    double pc_pa;  /* central pressure [Pa] */
    double pn_pa;  /* ambient (environmental) pressure [Pa], > pc_pa */
    double rmax_m; /* radius of maximum wind [m] */
    double b;      /* shape parameter, [1, 2.5] */
    double f;      /* Coriolis parameter 2Ω sin φ [1/s]; its sign gives the hemisphere */
    double rho;    /* air density [kg/m³] */
} holland_vortex;

/* f = 2Ω sin φ [1/s] at latitude lat_deg (negative in the southern hemisphere). */
double holland_coriolis(double lat_deg);
/* B from the peak gradient wind and the pressure deficit, Holland 1980 eq. 11 inverted:
 * V_max = sqrt(B Δp / (ρ e)) ⇒ B = ρ e V_max² / Δp, clamped to [1, 2.5]. Non-positive
 * Δp gives HOLLAND_B_MIN. */
double holland_b(double vmax_ms, double dp_pa, double rho);
/* Sea-level pressure [Pa] at radius r_m: p = p_c + Δp exp(−(R/r)^B) (Holland eq. 2);
 * p_c at r = 0. */
double holland_pressure(const holland_vortex *v, double r_m);
/* Gradient wind speed [m/s] at radius r_m (Holland eq. 6):
 * V = sqrt((B Δp/ρ)(R/r)^B exp(−(R/r)^B) + (r f/2)²) − r|f|/2; 0 at r = 0. */
double holland_gradient_wind(const holland_vortex *v, double r_m);
/* The cyclostrophic peak sqrt(B Δp / (ρ e)) [m/s], reached at r = Rmax (Holland eq. 11). */
double holland_vmax(const holland_vortex *v);

#endif
