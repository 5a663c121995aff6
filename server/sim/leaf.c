/* Leaf shedding: see leaf.h. Each (seed, tree, tick) gets its own counter-based random
 * stream, so the order trees are visited in does not change the result. */
#include "leaf.h"
#include "hash.h"

#include <math.h>

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
    /* Knuth's Poisson draw: multiply uniforms until below e^-mean (mean <= 32 keeps
     * e^-mean far above the double's smallest normal). */
    double limit = exp(-mean), p = rng_unit(&st);
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
