/* Leaf shedding: see leaf.h. Each (seed, tree, tick) gets its own counter-based random
 * stream, so the order trees are visited in does not change the result. */
#include "leaf.h"
#include "hash.h"
#include "sim_team.h"

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

/* Trees screened at once by may_shed: a fixed trip count, a whole number of vectors, so
 * that the loops vectorise at -O2 with no remainder. */
#define SCREEN_BLOCK 256

/* Trees [t0, t0 + SCREEN_BLOCK), their wind wb[3 i + k] and leaf slots ns[i] (0: none, as
 * for the lanes past the last tree): the wind speed at each crown, and whether leaf_shed
 * may draw a leaf for it this tick. leaf_shed draws none when its first uniform p is below
 * 1 - mean; the screen asks p >= thr = 1 - mean (1 + 1e-9) - 1e-15 - 1e-12, with a margin
 * of 1e-12 over the roundings that may differ (the mean's, at most ~32 * 2^-52; p is
 * exact). It compares in integers: p's 52 high bits (h >> 12, which is floor(2^52 p))
 * against the mantissa of 1 + thr (2^52 thr rounded, thr in [0, 1)), which the margin
 * keeps conservative (2^-52 << 1e-12). So a tree it screens out is one leaf_shed would
 * return from without a leaf: the draws are leaf_shed's, tree for tree. Returns the
 * largest speed as float bits (non-negative floats order as their bits; NaN counts 0).
 * Cloned for AVX-512 (64-bit multiplies in vector) and AVX2. */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
static uint32_t may_shed(const leaf_desc *d, uint32_t t0, const float *restrict wb,
                         const uint32_t *restrict ns, uint32_t tick, double dt_s,
                         float *restrict speed, uint8_t *restrict maybe)
{
    const double calm = (double)d->calm_ms, ref = (double)d->ref_ms, rate = (double)d->rate_hz;
    const bool on = rate > 0 && ref > calm;
    const double inv = on ? 1.0 / (ref - calm) : 0.0;
    /* the bar each draw's 52 high bits must reach: 0 where thr < 0, past every draw where
     * no leaf can fall */
    uint64_t bar[SCREEN_BLOCK];
    uint32_t top = 0;
    for (uint32_t i = 0; i < SCREEN_BLOCK; i++) {
        const float *v = wb + 3 * (size_t)i;
        const float sp = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        speed[i] = sp;
        const double x = ((double)sp - calm) * inv;
        const double mean = rate * x * x * (double)ns[i] * dt_s;
        const double thr = 1.0 - mean * (1.0 + 1e-9) - 1e-15 - 1e-12;
        const double y = thr + 1.0;
        uint64_t yb;
        memcpy(&yb, &y, sizeof yb);
        yb = thr < 0 ? 0 : yb & 0xfffffffffffffull;
        bar[i] = on & ((double)sp > calm) & (ns[i] > 0) ? yb : UINT64_MAX;
    }
    for (uint32_t i = 0; i < SCREEN_BLOCK; i++) {
        uint32_t bits;
        memcpy(&bits, &speed[i], sizeof bits);
        bits &= -(uint32_t)(bits <= 0x7f800000u); /* NaN (either sign) counts 0 */
        top = bits > top ? bits : top;
    }
    for (uint32_t i = 0; i < SCREEN_BLOCK; i++) {
        uint64_t st = hash64_final(d->seed ^ hash64_final(((uint64_t)(t0 + i) << 32) | tick));
        maybe[i] = (uint8_t)((hash64_splitmix(&st) >> 12) >= bar[i]);
    }
    return top;
}

/* Trees [t0, t1) into out[0..cap) from *n on. */
static int shed_range(const leaf_desc *d, uint32_t t0, uint32_t t1, const float *wind,
                      const uint32_t *slots, uint32_t slots_all, uint32_t tick, double dt_s,
                      leaf_seed *out, int cap, int *n, float *max_ms)
{
    int lost = 0;
    uint32_t top = 0;
    float speed[SCREEN_BLOCK];
    uint32_t ns[SCREEN_BLOCK];
    _Alignas(8) uint8_t maybe[SCREEN_BLOCK];
    float tail[3 * SCREEN_BLOCK]; /* the last block's wind, padded */
    for (uint32_t b = t0; b < t1; b += SCREEN_BLOCK) {
        const uint32_t k = t1 - b < SCREEN_BLOCK ? t1 - b : SCREEN_BLOCK;
        const float *wb = &wind[3 * (size_t)b];
        for (uint32_t i = 0; i < k; i++) {
            ns[i] = slots ? slots[b + i] : slots_all;
        }
        if (k < SCREEN_BLOCK) {
            memset(ns + k, 0, (SCREEN_BLOCK - k) * sizeof *ns);
            memcpy(tail, wb, 3 * sizeof(float) * k);
            memset(tail + 3 * k, 0, 3 * sizeof(float) * (SCREEN_BLOCK - k));
            wb = tail;
        }
        const uint32_t block_top = may_shed(d, b, wb, ns, tick, dt_s, speed, maybe);
        top = block_top > top ? block_top : top;
        /* most trees shed nothing: skip eight at a time */
        for (uint32_t i = 0; i < k; i += 8) {
            uint64_t any;
            memcpy(&any, &maybe[i], sizeof any);
            if (!any) {
                continue;
            }
            for (uint32_t j = i; j < i + 8 && j < k; j++) {
                if (maybe[j]) {
                    lost += leaf_shed(d, b + j, ns[j], (double)speed[j], tick, dt_s, out, cap, n);
                }
            }
        }
    }
    memcpy(max_ms, &top, sizeof top);
    return lost;
}

enum { MAX_SHARES = 64, SHARE_MIN_TREES = 4096 };

/* The most shares on n_threads threads. */
static int max_shares(int n_threads)
{
    if (n_threads <= 1) {
        return 1;
    }
    const int64_t k = (int64_t)n_threads * LEAF_SHARES_PER_THREAD;
    return k > MAX_SHARES ? MAX_SHARES : (int)k;
}

size_t leaf_scratch_seeds(int n_threads, int cap)
{
    return (size_t)(max_shares(n_threads) - 1) * (size_t)(cap > 0 ? cap : 0);
}

/* One leaf_shed_trees call's shares (each share's outputs its own). */
typedef struct shed_job {
    const leaf_desc *d;
    uint32_t n_trees;
    const float *wind;
    const uint32_t *slots;
    uint32_t slots_all, tick;
    double dt_s;
    leaf_seed *scratch, *out;
    int cap, shares;
    int *got, *lost;
    float *vmax;
} shed_job;

static void shed_share(void *ctx, int i)
{
    const shed_job *j = ctx;
    const uint32_t shares = (uint32_t)j->shares;
    const uint32_t t0 = (uint32_t)((uint64_t)j->n_trees * (uint32_t)i / shares);
    const uint32_t t1 = (uint32_t)((uint64_t)j->n_trees * (uint32_t)(i + 1) / shares);
    /* the first share writes straight to out after what is there, the others to scratch */
    leaf_seed *dst = i == 0 ? j->out : j->scratch + (size_t)(i - 1) * (size_t)j->cap;
    j->lost[i] = shed_range(j->d, t0, t1, j->wind, j->slots, j->slots_all, j->tick, j->dt_s,
                            dst, j->cap, &j->got[i], &j->vmax[i]);
}

int leaf_shed_trees(const leaf_desc *d, uint32_t n_trees, const float *wind,
                    const uint32_t *slots, uint32_t slots_all, uint32_t tick, double dt_s,
                    int n_threads, leaf_seed *scratch, leaf_seed *out, int cap, int *n,
                    float *max_ms)
{
    /* below a few thousand trees a share, a fork costs more than it saves */
    const uint32_t fit = n_trees / SHARE_MIN_TREES;
    int shares = scratch ? max_shares(n_threads) : 1;
    shares = fit < (uint32_t)shares ? (fit > 1 ? (int)fit : 1) : shares;
    const int team = shares < n_threads ? shares : n_threads > 1 ? n_threads : 1;
    int got[MAX_SHARES] = { 0 }, lost[MAX_SHARES] = { 0 };
    float vmax[MAX_SHARES] = { 0 };
    got[0] = *n;
    shed_job j = { .d = d, .n_trees = n_trees, .wind = wind, .slots = slots,
                   .slots_all = slots_all, .tick = tick, .dt_s = dt_s, .scratch = scratch,
                   .out = out, .cap = cap, .shares = shares, .got = got, .lost = lost,
                   .vmax = vmax };
    sim_team_run(team, shares, shed_share, &j);
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
