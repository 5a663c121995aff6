/* Jitter buffer and clock: interpolation exact for quadratic motion and within the
 * Hermite error bound for a sine, C1 across snapshots, playout delay, gaps, out-of-order,
 * duplicate and late snapshots, eviction, clock offset from ping/pong. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "jitter.h"

#define NV 3

static const double PI = 3.14159265358979323846;

/* Three test signals, one per value. */
static void quad_signal(double t, float *q)
{
    q[0] = (float)(3.0 + 2.0 * t - 5.0 * t * t);
    q[1] = (float)(-1.0 + 0.5 * t * t);
    q[2] = (float)(0.25 - 4.0 * t);
}

static void sine_signal(double t, float *q)
{
    q[0] = (float)sin(2 * PI * 1.0 * t);
    q[1] = (float)(0.5 * cos(2 * PI * 0.7 * t));
    q[2] = (float)(2.0 * sin(2 * PI * 0.3 * t + 1.0));
}

static jitter *make(uint32_t cap, double delay)
{
    gale_err err = { 0 };
    jitter *j = jitter_create(
        &(jitter_desc){ .n_values = NV, .capacity = cap, .playout_delay_s = delay }, &err);
    CHECK(j != NULL);
    return j;
}

/* Non-uniform spacing: interior intervals reproduce a quadratic to float rounding. */
static void test_quadratic_exact(void)
{
    jitter *j = make(64, 0.1);
    double t = 0.0;
    double times[40];
    for (int k = 0; k < 40; k++) {
        times[k] = t;
        float q[NV];
        quad_signal(t, q);
        CHECK(jitter_insert(j, (uint64_t)k, t, q, NULL) == JITTER_INSERTED);
        t += 1.0 / 60.0 * (0.6 + 0.8 * ((k * 37) % 11) / 10.0);
    }
    double max_err = 0.0;
    for (int k = 1; k < 38; k++) { /* intervals [k, k+1] with neighbours k-1, k+2 */
        for (int m = 0; m <= 16; m++) {
            double rt = times[k] + (times[k + 1] - times[k]) * m / 16.0;
            float got[NV], want[NV];
            CHECK(jitter_sample(j, rt, got, NULL) == 0);
            quad_signal(rt, want);
            for (int v = 0; v < NV; v++) {
                max_err = fmax(max_err, fabs((double)got[v] - (double)want[v]));
            }
        }
    }
    /* values up to ~|5 t²| ≈ 2 over 0.66 s; float rounding of c0..c3 ~ 1e-6 relative */
    CHECK_NEAR(max_err, 0.0, 2e-5);
    jitter_destroy(j);
}

/* Sine at 60 Hz snapshots: error within the bound of parabola-slope Hermite (~h³ q'''),
 * well under what linear interpolation would give (h²/8 q'' ≈ 1.4e-3 for the 1 Hz one). */
static void test_sine_accuracy_and_smoothness(void)
{
    jitter *j = make(256, 0.1);
    const double h = 1.0 / 60.0;
    for (int k = 0; k < 200; k++) {
        float q[NV];
        sine_signal(k * h, q);
        CHECK(jitter_insert(j, (uint64_t)k, k * h, q, NULL) == JITTER_INSERTED);
    }
    double max_err = 0.0, max_jump = 0.0;
    const double dt = 1.0 / 1000.0; /* a 1 kHz display: any step would show */
    float prev[NV];
    bool have_prev = false;
    for (double rt = 2 * h; rt < 197 * h; rt += dt) {
        float got[NV], want[NV];
        CHECK(jitter_sample(j, rt, got, NULL) == 0);
        sine_signal(rt, want);
        for (int v = 0; v < NV; v++) {
            max_err = fmax(max_err, fabs((double)got[v] - (double)want[v]));
            if (have_prev) {
                max_jump = fmax(max_jump, fabs((double)got[v] - (double)prev[v]));
            }
            prev[v] = got[v];
        }
        have_prev = true;
    }
    /* bound: both tangents err by h²/6 |q'''| (|q'''| <= (2π)³ ≈ 248), weighted by
     * h |h10 + h11| <= 0.096 h: 1.84e-5; plus float rounding ~1e-6 */
    CHECK_NEAR(max_err, 0.0, 2.2e-5);
    /* steps: the largest frame-to-frame change is the slope bound max|q'| dt = 2π·1e-3 */
    CHECK(max_jump <= 2 * PI * dt * 1.02);
    jitter_destroy(j);
}

/* C1 at a snapshot: one-sided slopes on both sides agree. */
static void test_c1_at_knots(void)
{
    jitter *j = make(64, 0.1);
    const double h = 1.0 / 30.0;
    for (int k = 0; k < 30; k++) {
        float q[NV];
        sine_signal(k * h, q);
        jitter_insert(j, (uint64_t)k, k * h, q, NULL);
    }
    for (int k = 3; k < 26; k += 5) {
        const double tk = k * h, e = 1e-4;
        float a[NV], b[NV], c[NV];
        jitter_sample(j, tk - e, a, NULL);
        jitter_sample(j, tk, b, NULL);
        jitter_sample(j, tk + e, c, NULL);
        for (int v = 0; v < NV; v++) {
            double left = ((double)b[v] - (double)a[v]) / e,
                   right = ((double)c[v] - (double)b[v]) / e;
            /* second-derivative term e·q''/2 ≈ 4e-3 plus float rounding 1e-7/1e-4 */
            CHECK_NEAR(left, right, 2e-2);
        }
    }
    jitter_destroy(j);
}

/* Missing ticks: the gap is bridged smoothly, quadratic still exact. */
static void test_gaps(void)
{
    jitter *j = make(64, 0.1);
    const double h = 1.0 / 60.0;
    for (int k = 0; k < 50; k++) {
        if (k % 5 == 2 || k == 20 || k == 21) {
            continue;
        }
        float q[NV];
        quad_signal(k * h, q);
        jitter_insert(j, (uint64_t)k, k * h, q, NULL);
    }
    double max_err = 0.0;
    for (double rt = 1 * h; rt < 46 * h; rt += 0.0021) {
        float got[NV], want[NV];
        jitter_sample(j, rt, got, NULL);
        quad_signal(rt, want);
        for (int v = 0; v < NV; v++) {
            max_err = fmax(max_err, fabs((double)got[v] - (double)want[v]));
        }
    }
    CHECK_NEAR(max_err, 0.0, 2e-5);
    jitter_destroy(j);
}

/* Shuffled arrival gives the same samples as ordered arrival. */
static void test_out_of_order(void)
{
    jitter *a = make(64, 0.1), *b = make(64, 0.1);
    const double h = 1.0 / 60.0;
    int perm[30];
    for (int k = 0; k < 30; k++) {
        perm[k] = k;
    }
    for (int k = 0; k < 30; k += 3) { /* swap neighbours and rotate triples */
        int t = perm[k];
        perm[k] = perm[k + 2];
        perm[k + 2] = perm[k + 1];
        perm[k + 1] = t;
    }
    for (int k = 0; k < 30; k++) {
        float q[NV];
        sine_signal(k * h, q);
        jitter_insert(a, (uint64_t)k, k * h, q, NULL);
        sine_signal(perm[k] * h, q);
        jitter_insert(b, (uint64_t)perm[k], perm[k] * h, q, NULL);
    }
    CHECK(jitter_count(a) == 30 && jitter_count(b) == 30);
    CHECK(jitter_get_stats(b).out_of_order > 0);
    CHECK(jitter_get_stats(a).out_of_order == 0);
    for (double rt = 0.0; rt < 30 * h; rt += 0.003) {
        float qa[NV], qb[NV];
        jitter_sample(a, rt, qa, NULL);
        jitter_sample(b, rt, qb, NULL);
        for (int v = 0; v < NV; v++) {
            CHECK(qa[v] == qb[v]);
        }
    }
    jitter_destroy(a);
    jitter_destroy(b);
}

static void test_late_duplicate_underrun(void)
{
    jitter *j = make(8, 0.1);
    float q[NV] = { 1, 2, 3 }, out[NV];
    CHECK(jitter_sample(j, 0.0, out, NULL) == GALE_E_STATE);
    jitter_insert(j, 10, 1.0, q, NULL);
    CHECK(jitter_insert(j, 10, 1.0, q, NULL) == JITTER_DUPLICATE);
    q[0] = 5;
    jitter_insert(j, 12, 1.2, q, NULL);
    jitter_sample_info inf;
    CHECK(jitter_sample(j, 1.15, out, &inf) == 0);
    CHECK(inf.tick0 == 10 && inf.tick1 == 12);
    /* tick 11 at t = 1.1 is behind the playout (1.15): late, not taken */
    CHECK(jitter_insert(j, 11, 1.1, q, NULL) == JITTER_LATE);
    CHECK(jitter_count(j) == 2);
    CHECK(jitter_get_stats(j).late == 1 && jitter_get_stats(j).duplicates == 1);
    /* past the newest: hold it */
    CHECK(jitter_sample(j, 2.0, out, &inf) == 0);
    CHECK(inf.underrun && out[0] == 5.0f);
    CHECK(jitter_get_stats(j).underruns == 1);
    /* that underrun showed the newest (1.2) and passed no later time: a snapshot between
     * it and 2.0 that arrives now is taken */
    q[0] = 7;
    CHECK(jitter_insert(j, 13, 1.5, q, NULL) == JITTER_INSERTED);
    CHECK(jitter_sample(j, 2.1, out, &inf) == 0 && inf.underrun && out[0] == 7.0f);
    CHECK(jitter_get_stats(j).late == 1);
    /* before the first (after a reset) */
    jitter_reset(j);
    jitter_insert(j, 3, 0.5, q, NULL);
    CHECK(jitter_sample(j, 0.1, out, &inf) == 0 && inf.before_first && out[0] == 7.0f);
    jitter_destroy(j);
}

static void test_eviction(void)
{
    jitter *j = make(4, 0.1);
    float q[NV] = { 0 };
    for (int k = 0; k < 10; k++) {
        q[0] = (float)k;
        CHECK(jitter_insert(j, (uint64_t)k, k * 0.1, q, NULL) == JITTER_INSERTED);
    }
    CHECK(jitter_count(j) == 4);
    CHECK(jitter_get_stats(j).evicted == 6);
    CHECK_NEAR(jitter_oldest_time(j), 0.6, 1e-12);
    CHECK_NEAR(jitter_newest_time(j), 0.9, 1e-12);
    /* full and older than all held: late */
    CHECK(jitter_insert(j, 2, 0.2, q, NULL) == JITTER_LATE);
    float out[NV];
    jitter_sample(j, 0.75, out, NULL);
    CHECK_NEAR(out[0], 7.5, 1e-5); /* linear data stays linear */
    jitter_destroy(j);
}

static void test_bad_input(void)
{
    gale_err err = { 0 };
    CHECK(jitter_create(&(jitter_desc){ 0 }, &err) == NULL);
    CHECK_STR_HAS(err.msg, "n_values: expected > 0, got 0");
    CHECK(jitter_create(&(jitter_desc){ .n_values = 1, .capacity = 1 }, &err) == NULL);
    CHECK_STR_HAS(err.msg, "capacity: expected 2..256, got 1");
    CHECK(jitter_create(&(jitter_desc){ .n_values = 1, .playout_delay_s = -1 }, &err) == NULL);
    CHECK_STR_HAS(err.msg, "playout_delay_s");
    jitter *j = make(8, 0.0);
    CHECK_NEAR(jitter_get_desc(j).playout_delay_s, 0.1, 0);
    CHECK(jitter_get_desc(j).capacity == 8);
    float q[NV] = { 0 };
    CHECK(jitter_insert(j, 1, NAN, q, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "snapshot tick 1: server time not finite");
    jitter_insert(j, 5, 1.0, q, NULL);
    CHECK(jitter_insert(j, 6, 0.5, q, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "snapshot tick 6: server time 0.500000 s out of tick order");
    CHECK(jitter_count(j) == 1);
    jitter_destroy(j);
    jitter_destroy(NULL);
}

/* Clock: true offset 1000.25 s; asymmetric, varying delays. The min-rtt sample's offset
 * is within its rtt/2 of the truth; render time = server estimate − delay. */
static void test_clock(void)
{
    const double offset = 1000.25;
    jitter_clock c;
    jitter_clock_init(&c);
    double s;
    CHECK(!jitter_clock_server_time(&c, 5.0, &s) && s == 5.0);
    CHECK(jitter_clock_rtt(&c) < 0);
    /* before pongs: snapshot arrivals bound the offset from below by the one-way delay */
    jitter_clock_arrival(&c, 10.0 + offset - 0.030, 10.0);
    jitter_clock_arrival(&c, 11.0 + offset - 0.012, 11.0);
    CHECK(jitter_clock_server_time(&c, 20.0, &s));
    CHECK_NEAR(s, 20.0 + offset - 0.012, 1e-9);
    const double up[5] = { 0.020, 0.004, 0.050, 0.010, 0.007 };
    const double down[5] = { 0.005, 0.002, 0.010, 0.030, 0.003 };
    double t = 100.0;
    for (int k = 0; k < 5; k++) {
        double server = t + up[k] + offset;
        jitter_clock_pong(&c, t, server, t + up[k] + down[k]);
        t += 1.0;
    }
    jitter_clock_pong(&c, 5.0, 1.0, 4.0); /* received before sent: ignored */
    CHECK_NEAR(jitter_clock_rtt(&c), 0.006, 1e-9);
    CHECK(jitter_clock_server_time(&c, 200.0, &s));
    /* the chosen sample (up 4 ms, down 2 ms) errs by (up − down)/2 = 1 ms ≤ rtt/2 */
    CHECK_NEAR(s, 200.0 + offset, 0.003);
    CHECK_NEAR(s, 200.0 + offset + 0.001, 1e-9);
    jitter *j = make(8, 0.08);
    CHECK_NEAR(jitter_render_time(j, s), s - 0.08, 1e-12);
    jitter_destroy(j);
}

/* Two wall tiles with different clock offsets and arrival orders show the same q at the
 * same wall-clock instant. */
static void test_tiles_same_instant(void)
{
    jitter *a = make(64, 0.1), *b = make(64, 0.1);
    jitter_clock ca, cb;
    jitter_clock_init(&ca);
    jitter_clock_init(&cb);
    /* tile A's local clock = server − 3 s; tile B's = server + 7.5 s */
    jitter_clock_pong(&ca, 10.0, 13.001, 10.002);
    jitter_clock_pong(&cb, 10.0, 2.501, 10.002);
    const double h = 1.0 / 60.0;
    for (int k = 0; k < 60; k++) {
        float q[NV];
        sine_signal(k * h, q);
        jitter_insert(a, (uint64_t)k, k * h, q, NULL);
        int kb = (k % 2) ? k - 1 : k + 1;
        sine_signal(kb * h, q);
        jitter_insert(b, (uint64_t)kb, kb * h, q, NULL);
    }
    for (double server = 0.3; server < 0.9; server += 0.0123) {
        double la = server - 3.0, lb = server + 7.5, sa, sb;
        jitter_clock_server_time(&ca, la, &sa);
        jitter_clock_server_time(&cb, lb, &sb);
        float qa[NV], qb[NV];
        jitter_sample(a, jitter_render_time(a, sa), qa, NULL);
        jitter_sample(b, jitter_render_time(b, sb), qb, NULL);
        for (int v = 0; v < NV; v++) {
            CHECK_NEAR(qa[v], qb[v], 1e-6);
        }
    }
    jitter_destroy(a);
    jitter_destroy(b);
}

int main(void)
{
    RUN(test_quadratic_exact);
    RUN(test_sine_accuracy_and_smoothness);
    RUN(test_c1_at_knots);
    RUN(test_gaps);
    RUN(test_out_of_order);
    RUN(test_late_duplicate_underrun);
    RUN(test_eviction);
    RUN(test_bad_input);
    RUN(test_clock);
    RUN(test_tiles_same_instant);
    return check_report();
}
