/* Leaf shedding: zero in calm air, the rate law, Poisson counts against their expected
 * mean, reproducibility and the output cap. */
#include "check.h"
#include "leaf.h"
#include "hash.h"

#include <math.h>

static const leaf_desc D = { .rate_hz = 0.01f, .calm_ms = 3, .ref_ms = 20, .seed = 42 };

static void test_rate_law(void)
{
    CHECK(leaf_rate(&D, 0) == 0);
    CHECK(leaf_rate(&D, 3) == 0);
    CHECK_NEAR(leaf_rate(&D, 20), 0.01, 1e-8); /* rate_hz is a float */
    CHECK_NEAR(leaf_rate(&D, 37), 0.04, 4e-8); /* twice the excess speed: four times */
    CHECK(leaf_rate(&D, 10) < leaf_rate(&D, 11));
    CHECK(leaf_rate(&D, NAN) == 0);
}

static void test_calm_sheds_nothing(void)
{
    leaf_seed out[16];
    int n = 0;
    for (uint32_t t = 0; t < 10000; t++) {
        leaf_shed(&D, 1, 1000, 2.9, t, 1.0 / 60, out, 16, &n);
    }
    CHECK(n == 0);
}

static void test_poisson_mean(void)
{
    /* 1000 slots at 20 m/s: 10 leaves/s; 60 s at 60 Hz → 600 expected, σ ≈ 24.5 */
    static leaf_seed out[4096];
    int n = 0, lost = 0;
    for (uint32_t t = 0; t < 3600; t++) {
        lost += leaf_shed(&D, 7, 1000, 20, t, 1.0 / 60, out, 4096, &n);
    }
    CHECK(lost == 0);
    CHECK_NEAR(n, 600, 5 * 24.5);
    int bad = 0;
    for (int i = 0; i < n; i++) {
        bad += out[i].instance != 7 || out[i].slot >= 1000 || out[i].spawn_tick >= 3600;
    }
    CHECK(bad == 0);
    /* same inputs, same leaves */
    static leaf_seed again[4096];
    int m = 0;
    for (uint32_t t = 0; t < 3600; t++) {
        leaf_shed(&D, 7, 1000, 20, t, 1.0 / 60, again, 4096, &m);
    }
    CHECK(m == n && !memcmp(out, again, sizeof *out * (size_t)n));
}

static void test_cap(void)
{
    leaf_seed out[4];
    int n = 0, lost = 0;
    for (uint32_t t = 0; t < 100; t++) {
        lost += leaf_shed(&D, 1, 100000, 60, t, 1.0 / 60, out, 4, &n);
    }
    CHECK(n == 4);
    CHECK(lost > 0);
}

/* The draw written out as Knuth's (every tree computes e^-mean): leaf_shed gives the same
 * seeds for every tree, tick and speed, the calm and capped means and the small ones its
 * early exit takes included. */
static int knuth_ref(uint32_t instance, uint32_t n_slots, double speed_ms, uint32_t tick,
                     leaf_seed *out)
{
    double mean = leaf_rate(&D, speed_ms) * (double)n_slots / 60.0;
    if (!(mean > 0) || n_slots == 0) {
        return 0;
    }
    mean = mean > 32 ? 32 : mean;
    uint64_t st = hash64_final(D.seed ^ hash64_final(((uint64_t)instance << 32) | tick));
    double limit = exp(-mean);
    double p = (double)(hash64_splitmix(&st) >> 11) * (1.0 / 9007199254740992.0);
    int k = 0;
    while (p > limit && k < 256) {
        k++;
        p *= (double)(hash64_splitmix(&st) >> 11) * (1.0 / 9007199254740992.0);
    }
    for (int i = 0; i < k; i++) {
        uint64_t r = hash64_splitmix(&st);
        out[i] = (leaf_seed){ instance, (uint32_t)((r >> 32) % n_slots), tick, (uint32_t)r };
    }
    return k;
}

static void test_same_as_knuth(void)
{
    static leaf_seed got[64], want[64];
    int diff = 0, total = 0;
    for (uint32_t t = 0; t < 20000; t++) {
        const double speed = 3.0 + (double)(t % 200) * 0.25; /* calm to 53 m/s */
        const uint32_t slots = t % 7 == 0 ? 1 : 1500;
        const uint32_t tick = t * 2654435761u;
        int n = 0;
        leaf_shed(&D, t, slots, speed, tick, 1.0 / 60, got, 64, &n);
        int k = knuth_ref(t, slots, speed, tick, want);
        total += k;
        diff += n != k || memcmp(got, want, sizeof(leaf_seed) * (size_t)k) != 0;
    }
    CHECK(diff == 0);
    CHECK(total > 1000);
}

/* leaf_shed_trees (which screens trees in blocks before leaf_shed's draw) sheds what
 * leaf_shed gives tree by tree, in tree order, on 1 and 2 threads: winds from calm to a
 * storm, trees without slots, NaN and infinite samples, a leaf cap that overflows, a
 * rate high enough that a screen too strict by a rounding would show, and one whose
 * leaves come from every share and fit. */
static void test_trees_same_as_one_by_one(void)
{
    enum { N = 20000, CAP = 3000 };
    static float wind[3 * N];
    static uint32_t slots[N];
    static leaf_seed got[CAP], want[CAP], scratch[(2 * LEAF_SHARES_PER_THREAD - 1) * CAP];
    CHECK(leaf_scratch_seeds(2, CAP) <= sizeof scratch / sizeof scratch[0]);
    CHECK(leaf_scratch_seeds(1, CAP) == 0);
    const leaf_desc hot = { .rate_hz = 0.3f, .calm_ms = 3, .ref_ms = 20, .seed = 5 };
    /* many leaves from every share, all within the cap: the merge's order shows */
    const leaf_desc warm = { .rate_hz = 0.0008f, .calm_ms = 3, .ref_ms = 20, .seed = 9 };
    for (uint32_t t = 0; t < N; t++) {
        const float sp = (float)(t % 211) * 0.27f; /* 0 to 57 m/s */
        wind[3 * t] = sp * 0.6f;
        wind[3 * t + 1] = -sp * 0.8f;
        wind[3 * t + 2] = 0.01f * (float)(t % 5);
        slots[t] = t % 13 == 0 ? 0 : 200 + t % 3000;
    }
    /* samples a broken field could give: no leaf, and the largest speed ignores a NaN */
    wind[3 * 5] = NAN;
    wind[3 * 6 + 1] = -NAN;
    wind[3 * 19999] = INFINITY;
    int diff = 0, total = 0, within_cap = 0;
    for (int threads = 1; threads <= 2; threads++) {
        for (uint32_t tick = 0; tick < 6; tick++) {
            const leaf_desc *d = tick % 3 == 0 ? &D : tick % 3 == 1 ? &hot : &warm;
            int n = 0, m = 0, lost_want = 0;
            float vmax = 0, want_max = 0;
            int lost = leaf_shed_trees(d, N, wind, slots, 0, tick, 1.0 / 60, threads, scratch,
                                       got, CAP, &n, &vmax);
            for (uint32_t t = 0; t < N; t++) {
                const float *v = &wind[3 * t];
                const float sp = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                want_max = sp > want_max ? sp : want_max;
                if (slots[t]) {
                    lost_want += leaf_shed(d, t, slots[t], (double)sp, tick, 1.0 / 60, want,
                                           CAP, &m);
                }
            }
            total += m;
            within_cap += d == &warm && m > CAP / 4 && lost_want == 0;
            diff += n != m || lost != lost_want || vmax != want_max ||
                    memcmp(got, want, sizeof(leaf_seed) * (size_t)m) != 0;
        }
    }
    CHECK(diff == 0);
    CHECK(total > 2000);
    CHECK(within_cap == 4);
}

int main(void)
{
    RUN(test_rate_law);
    RUN(test_calm_sheds_nothing);
    RUN(test_poisson_mean);
    RUN(test_cap);
    RUN(test_same_as_knuth);
    RUN(test_trees_same_as_one_by_one);
    return check_report();
}
