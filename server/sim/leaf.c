/* Leaf shedding: see leaf.h. Each (seed, tree, tick) gets its own counter-based random
 * stream, so the order trees are visited in does not change the result. */
#include "leaf.h"
#include "hash.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

static double rng_unit(uint64_t *s)
{
    return (double)(hash64_splitmix(s) >> 11) * (1.0 / 9007199254740992.0);
}

double leaf_rate(const leaf_desc *d, double speed_ms)
{
    double calm = (double)d->calm_ms, ref = (double)d->ref_ms;
    if (!(speed_ms > calm) || d->rate_hz <= 0 || !(ref > calm)) {
        return 0.0;
    }
    double x = (speed_ms - calm) / (ref - calm);
    return (double)d->rate_hz * x * x;
}

int leaf_shed(const leaf_desc *d, uint32_t instance, uint32_t n_slots, double speed_ms,
              uint32_t tick, double dt_s, leaf_seed *out, int cap, int *n)
{
    double mean = leaf_rate(d, speed_ms) * (double)n_slots * dt_s;
    if (!(mean > 0) || n_slots == 0) {
        return 0;
    }
    if (mean > 32) {
        mean = 32;
    }
    uint64_t st = hash64_final(d->seed ^ hash64_final(((uint64_t)instance << 32) | tick));
    double p = rng_unit(&st);
    /* No leaf when p <= e^-mean: e^-m >= 1 - m, and the margin covers the roundings of
     * both sides (<= 2^-52 together), so a p below it needs no exp (most trees, most
     * ticks: the mean is ~0.1 in a gale) and the draw is the same. */
    if (p < 1.0 - mean * (1.0 + 1e-9) - 1e-15) {
        return 0;
    }
    /* Knuth's Poisson draw: multiply uniforms until below e^-mean (mean <= 32 keeps
     * e^-mean far above the double's smallest normal). */
    double limit = exp(-mean);
    int k = 0;
    while (p > limit && k < 256) {
        k++;
        p *= rng_unit(&st);
    }
    int lost = 0;
    for (int i = 0; i < k; i++) {
        uint64_t r = hash64_splitmix(&st);
        if (*n >= cap) {
            lost++;
            continue;
        }
        out[*n] = (leaf_seed){ .instance = instance,
                               .slot = (uint32_t)((r >> 32) % n_slots),
                               .spawn_tick = tick,
                               .variation = (uint32_t)r };
        (*n)++;
    }
    return lost;
}

/* Trees screened at once by may_shed. */
#define SCREEN_BLOCK 256

/* Trees [t0, t0 + k): the wind speed at each crown, and whether leaf_shed may draw a leaf
 * for it this tick: its first uniform p is not below 1 - mean, leaf_shed's own test,
 * computed here for a block at once so that the hashes vectorise, with a margin of 1e-12
 * over roundings that may differ (the mean's, at most ~32 * 2^-52; p is exact), so a tree
 * it screens out is one leaf_shed would return from without a leaf: the draws are
 * leaf_shed's, tree for tree. Cloned for AVX-512 (64-bit multiplies in vector) and AVX2. */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
static void may_shed(const leaf_desc *d, uint32_t t0, uint32_t k, const float *wind,
                     const uint32_t *slots, uint32_t slots_all, uint32_t tick, double dt_s,
                     float *restrict speed, uint8_t *restrict maybe)
{
    const double calm = (double)d->calm_ms, ref = (double)d->ref_ms, rate = (double)d->rate_hz;
    const bool on = rate > 0 && ref > calm;
    const double inv = on ? 1.0 / (ref - calm) : 0.0;
    for (uint32_t i = 0; i < k; i++) {
        const uint32_t t = t0 + i;
        const float *v = &wind[3 * (size_t)t];
        const float sp = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        speed[i] = sp;
        const uint32_t ns = slots ? slots[t] : slots_all;
        const double x = ((double)sp - calm) * inv;
        double mean = rate * x * x * (double)ns * dt_s;
        mean = mean > 32 ? 32 : mean;
        uint64_t st = hash64_final(d->seed ^ hash64_final(((uint64_t)t << 32) | tick));
        const double p = (double)(hash64_splitmix(&st) >> 11) * (1.0 / 9007199254740992.0);
        maybe[i] = (uint8_t)(on & ((double)sp > calm) & (ns > 0) &
                             (p >= 1.0 - mean * (1.0 + 1e-9) - 1e-15 - 1e-12));
    }
}

/* Trees [t0, t1) into out[0..cap) from *n on. */
static int shed_range(const leaf_desc *d, uint32_t t0, uint32_t t1, const float *wind,
                      const uint32_t *slots, uint32_t slots_all, uint32_t tick, double dt_s,
                      leaf_seed *out, int cap, int *n, float *max_ms)
{
    int lost = 0;
    float vmax = 0.0f;
    float speed[SCREEN_BLOCK];
    uint8_t maybe[SCREEN_BLOCK];
    for (uint32_t b = t0; b < t1; b += SCREEN_BLOCK) {
        const uint32_t k = t1 - b < SCREEN_BLOCK ? t1 - b : SCREEN_BLOCK;
        may_shed(d, b, k, wind, slots, slots_all, tick, dt_s, speed, maybe);
        for (uint32_t i = 0; i < k; i++) {
            vmax = speed[i] > vmax ? speed[i] : vmax;
            if (maybe[i]) {
                lost += leaf_shed(d, b + i, slots ? slots[b + i] : slots_all, (double)speed[i],
                                  tick, dt_s, out, cap, n);
            }
        }
    }
    *max_ms = vmax;
    return lost;
}

int leaf_shed_trees(const leaf_desc *d, uint32_t n_trees, const float *wind,
                    const uint32_t *slots, uint32_t slots_all, uint32_t tick, double dt_s,
                    int n_threads, leaf_seed *scratch, leaf_seed *out, int cap, int *n,
                    float *max_ms)
{
    enum { MAX_SHARES = 64 };
    int shares = n_threads < 1 || !scratch ? 1 : n_threads > MAX_SHARES ? MAX_SHARES : n_threads;
    shares = n_trees < 4096u ? 1 : shares; /* below a few thousand trees a fork costs more */
    int got[MAX_SHARES] = { 0 }, lost[MAX_SHARES] = { 0 };
    float vmax[MAX_SHARES] = { 0 };
    const int n0 = *n;
#pragma omp parallel for schedule(static, 1) num_threads(shares) if (shares > 1)
    for (int i = 0; i < shares; i++) {
        const uint32_t t0 = (uint32_t)((uint64_t)n_trees * (uint32_t)i / (uint32_t)shares);
        const uint32_t t1 = (uint32_t)((uint64_t)n_trees * (uint32_t)(i + 1) / (uint32_t)shares);
        if (i == 0) {
            got[0] = n0;
            lost[0] = shed_range(d, t0, t1, wind, slots, slots_all, tick, dt_s, out, cap,
                                 &got[0], &vmax[0]);
        } else {
            lost[i] = shed_range(d, t0, t1, wind, slots, slots_all, tick, dt_s,
                                 scratch + (size_t)(i - 1) * (size_t)cap, cap, &got[i],
                                 &vmax[i]);
        }
    }
    int total_lost = lost[0], at = got[0];
    float m = vmax[0];
    for (int i = 1; i < shares; i++) {
        const int room = cap - at, take = got[i] < room ? got[i] : room;
        if (take > 0) {
            memcpy(out + at, scratch + (size_t)(i - 1) * (size_t)cap, sizeof *out * (size_t)take);
            at += take;
        }
        total_lost += lost[i] + (got[i] - (take > 0 ? take : 0));
        m = vmax[i] > m ? vmax[i] : m;
    }
    *n = at;
    if (max_ms) {
        *max_ms = m;
    }
    return total_lost;
}
