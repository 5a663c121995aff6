/* Leaf shedding: see leaf.h. Each (seed, tree, tick) gets its own counter-based random
 * stream, so the order trees are visited in does not change the result. */
#include "leaf.h"
#include "hash.h"

#include <math.h>
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

/* Trees [t0, t1) into out[0..cap) from *n on. */
static int shed_range(const leaf_desc *d, uint32_t t0, uint32_t t1, const float *wind,
                      const uint32_t *slots, uint32_t slots_all, uint32_t tick, double dt_s,
                      leaf_seed *out, int cap, int *n, float *max_ms)
{
    int lost = 0;
    float vmax = 0.0f;
    for (uint32_t t = t0; t < t1; t++) {
        const float *v = &wind[3 * (size_t)t];
        const float speed = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        vmax = speed > vmax ? speed : vmax;
        const uint32_t ns = slots ? slots[t] : slots_all;
        if (ns) {
            lost += leaf_shed(d, t, ns, (double)speed, tick, dt_s, out, cap, n);
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
