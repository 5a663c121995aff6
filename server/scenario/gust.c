/* Ornstein–Uhlenbeck gusts: see gust.h and PHYSICS.md "Wind with height and gusts". */
#include "gust.h"
#include "hash.h"

#include <math.h>
#include <string.h>

double gust_intensity(double z_m, double z0_m)
{
    if (!(z0_m > 0.0)) {
        z0_m = 0.3;
    }
    if (!(z_m > M_E * z0_m)) {
        return 1.0;
    }
    return 1.0 / log(z_m / z0_m);
}

gust_desc gust_desc_resolve(const gust_desc *d)
{
    gust_desc r = d ? *d : (gust_desc){ 0 };
    if (!(r.z_m > 0.0)) {
        r.z_m = 10.0;
    }
    if (!(r.z0_m > 0.0)) {
        r.z0_m = 0.3;
    }
    if (!(r.intensity > 0.0)) {
        r.intensity = gust_intensity(r.z_m, r.z0_m);
    }
    if (!(r.length_m > 0.0)) {
        r.length_m = 50.0;
    }
    if (!(r.ratio_v > 0.0)) {
        r.ratio_v = 0.75;
    }
    if (!(r.ratio_w > 0.0)) {
        r.ratio_w = 0.5;
    }
    if (!(r.u_floor_ms > 0.0)) {
        r.u_floor_ms = 1.0;
    }
    return r;
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

/* xoshiro256** (Blackman & Vigna 2018). */
static uint64_t next_u64(uint64_t s[4])
{
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

/* Uniform in (0, 1): 53 random bits, never 0 so log() below is finite. */
static double uniform01(uint64_t s[4])
{
    return ((double)(next_u64(s) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

double gust_normal(gust *g)
{
    /* Box–Muller, one deviate per call: no cached second value, so the sequence depends
     * only on the number of calls */
    double u1 = uniform01(g->rng), u2 = uniform01(g->rng);
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}

void gust_init(gust *g, const gust_desc *d)
{
    memset(g, 0, sizeof *g);
    g->d = gust_desc_resolve(d);
    uint64_t s = g->d.seed;
    /* splitmix64 expands the seed into the xoshiro state (Vigna's recommendation). */
    for (int i = 0; i < 4; i++) {
        g->rng[i] = hash64_splitmix(&s);
    }
    for (int k = 0; k < 3; k++) {
        g->x[k] = gust_normal(g);
    }
}

void gust_step(gust *g, double dt_s, double mean_ms, double out[3])
{
    double u = fabs(mean_ms);
    if (dt_s > 0.0) {
        double tu = g->d.length_m / (u > g->d.u_floor_ms ? u : g->d.u_floor_ms);
        double a = exp(-dt_s / tu);
        double q = sqrt(1.0 - a * a);
        for (int k = 0; k < 3; k++) {
            g->x[k] = a * g->x[k] + q * gust_normal(g);
        }
    }
    double su = g->d.intensity * u;
    out[0] = su * g->x[0];
    out[1] = g->d.ratio_v * su * g->x[1];
    out[2] = g->d.ratio_w * su * g->x[2];
}
