/* Seeded gusts: an Ornstein–Uhlenbeck process per wind component (along, across, up) with
 * integral time scale T_u = L_u / U and standard deviations σ_u = I_u U, σ_v = 0.75 σ_u,
 * σ_w = 0.5 σ_u (PHYSICS.md "Wind with height and gusts": I_u ≈ 1/ln(z/z0)). */
#ifndef GALE_GUST_H
#define GALE_GUST_H

#include <stdint.h>

typedef struct gust_desc {
    uint64_t seed;     /* same seed, same sequence */
    double intensity;  /* I_u = σ_u / U; 0 → gust_intensity(z_m, z0_m) */
    double z_m;        /* reference height [m]; 0 → 10 */
    double z0_m;       /* roughness length [m]; 0 → 0.3 (EN 1991-1-4 terrain III) */
    double length_m;   /* integral length scale L_u [m]; 0 → 50 (near the ground) */
    double ratio_v;    /* σ_v / σ_u; 0 → 0.75 */
    double ratio_w;    /* σ_w / σ_u; 0 → 0.5 */
    double u_floor_ms; /* U below this uses it for T_u (keeps T_u finite); 0 → 1 */
} gust_desc;

/* The process state; a caller-owned value, no heap. */
typedef struct gust {
    gust_desc d;     /* resolved */
    uint64_t rng[4]; /* xoshiro256** state */
    double x[3];     /* unit-variance OU state per component */
} gust;

/* Turbulence intensity of the log law at height z over roughness z0: 1 / ln(z/z0)
 * (≈ 0.29 at 10 m over z0 = 0.3 m). z ≤ z0 is clamped to z = e·z0 (I = 1). */
double gust_intensity(double z_m, double z0_m);
/* Fills every zero field of d with its default and returns it. */
gust_desc gust_desc_resolve(const gust_desc *d);
/* Seeds the process and draws the start from the stationary distribution. */
void gust_init(gust *g, const gust_desc *d);
/* Advances by dt_s ≥ 0 with mean wind mean_ms and writes the gust velocity [m/s] as
 * (along, across, up) into out. Exact OU update for any dt:
 * x ← a x + sqrt(1 − a²) N(0,1), a = exp(−dt/T_u). */
void gust_step(gust *g, double dt_s, double mean_ms, double out[3]);
/* The next standard normal deviate of g's generator (for tests and jitter). */
double gust_normal(gust *g);

#endif
