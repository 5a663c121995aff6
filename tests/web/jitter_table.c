/* gale-client's jitter buffer (client/playout/jitter.c) over a fixed sequence of snapshots, one
 * JSON object a line, for tests/web/test_jitter_js.mjs to hold web/jitter.js and the
 * browser's blend of quantised snapshots (shaders/skel.frag GALE_Q_RING) to: each insert
 * with its quantised values Q, its steps and what the buffer answered, each sample with
 * the q the native client draws (Q dequantised as client/app/client_stream.c does, then
 * jitter_sample) and where it fell, the stats at the end. The sequence holds in order,
 * out of order, duplicate and late snapshots, evictions at capacity, holds before the
 * first and past the newest, a snapshot taken after the underrun, a single snapshot, a
 * reset and a change of steps (a new keyframe scene). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "jitter.h"
#include "wire.h"

#define N_TREES 3
#define STRIDE 4
#define N_VALUES (N_TREES * STRIDE)
#define CAPACITY 6

static const int species[N_TREES] = { 0, 1, 0 };
static const int n_modes[2] = { 4, 3 }; /* species 1 has no mode 3: Q and step 0 there */
static float step[2][STRIDE];

static jitter *jit;

static void set_steps(float scale)
{
    for (int s = 0; s < 2; s++) {
        for (int m = 0; m < STRIDE; m++) {
            step[s][m] = m < n_modes[s] ? scale * 0.0007f * (float)(1 + m + 3 * s) : 0.0f;
        }
    }
}

/* A smooth motion, quantised: each value a sinusoid of its own phase and rate. */
static void insert(uint64_t tick, double t_s)
{
    int16_t qi[N_VALUES];
    float q[N_VALUES];
    for (int i = 0; i < N_VALUES; i++) {
        int t = i / STRIDE, m = i % STRIDE;
        double v = m < n_modes[species[t]] ? 9000.0 * sin(0.37 * (double)i + (2.0 + 0.3 * m) * t_s)
                                           : 0.0;
        qi[i] = (int16_t)lround(v);
        q[i] = wire_dequantize(qi[i], step[species[t]][m]);
    }
    gale_err err = { 0 };
    int r = jitter_insert(jit, tick, t_s, q, &err);
    printf("{\"op\":\"insert\",\"tick\":%llu,\"t_s\":%.17g,\"result\":%d,\"Q\":[",
           (unsigned long long)tick, t_s, r);
    for (int i = 0; i < N_VALUES; i++) {
        printf("%s%d", i ? "," : "", qi[i]);
    }
    printf("],\"step\":[");
    for (int s = 0; s < 2; s++) {
        printf("%s[", s ? "," : "");
        for (int m = 0; m < n_modes[s]; m++) {
            printf("%s%.9g", m ? "," : "", (double)step[s][m]);
        }
        printf("]");
    }
    printf("]}\n");
}

static void sample(double t_s)
{
    float out[N_VALUES];
    jitter_sample_info inf;
    int r = jitter_sample(jit, t_s, out, &inf);
    printf("{\"op\":\"sample\",\"t_s\":%.17g,\"result\":%d", t_s, r);
    if (r == 0) {
        printf(",\"tick0\":%llu,\"tick1\":%llu,\"s\":%.9g,\"underrun\":%d,\"before_first\":%d,"
               "\"q\":[",
               (unsigned long long)inf.tick0, (unsigned long long)inf.tick1, (double)inf.s,
               inf.underrun, inf.before_first);
        for (int i = 0; i < N_VALUES; i++) {
            printf("%s%.9g", i ? "," : "", (double)out[i]);
        }
        printf("]");
    }
    printf("}\n");
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        int help = strcmp(argv[1], "--help") == 0;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-jitter-table\n"
                "  prints the scene (\"scene\"), then the jitter buffer's inserts and samples\n"
                "  over a fixed sequence (\"op\") and its stats (\"stats\"), JSON lines\n");
        return help ? 0 : 2;
    }
    gale_err err = { 0 };
    jit = jitter_create(&(jitter_desc){ .n_values = N_VALUES, .capacity = CAPACITY,
                                        .playout_delay_s = 0.1 },
                        &err);
    if (!jit) {
        fprintf(stderr, "gale-web-jitter-table: %s\n", err.msg);
        return 1;
    }
    printf("{\"scene\":{\"n_trees\":%d,\"stride\":%d,\"capacity\":%d,\"species\":[%d,%d,%d]}}\n",
           N_TREES, STRIDE, CAPACITY, species[0], species[1], species[2]);
    set_steps(1.0f);
    sample(0.0); /* empty */
    insert(100, 1.0);
    sample(0.9); /* one snapshot: held */
    sample(1.0);
    /* 30 Hz ticks with uneven arrival times; 104 arrives before 103 */
    insert(101, 1.0 + 1.0 / 30);
    insert(102, 1.0 + 2.1 / 30);
    insert(104, 1.0 + 4.0 / 30);
    sample(1.0 + 0.5 / 30); /* two sides one-sided, then with neighbours */
    insert(103, 1.0 + 2.9 / 30);
    insert(103, 1.0 + 2.9 / 30); /* duplicate */
    for (int k = 0; k <= 12; k++) {
        sample(0.99 + (double)k * 0.0125);
    }
    insert(105, 1.0 + 5.0 / 30);
    insert(106, 1.0 + 6.0 / 30);
    insert(107, 1.0 + 7.2 / 30); /* full: evicts the oldest */
    insert(108, 1.0 + 8.0 / 30);
    sample(1.0 + 6.5 / 30);
    insert(102, 1.0 + 2.1 / 30); /* older than the played-out time: late */
    set_steps(1.7f);            /* a new keyframe scene with other steps */
    insert(109, 1.0 + 9.0 / 30);
    insert(110, 1.0 + 10.0 / 30);
    for (int k = 0; k <= 10; k++) {
        sample(1.0 + (7.0 + 0.33 * k) / 30);
    }
    sample(2.0); /* past the newest: underrun */
    insert(111, 1.0 + 11.0 / 30); /* after the newest that underrun showed: taken */
    sample(2.0);
    sample(1.0 + 10.5 / 30); /* between the two newest */
    jitter_reset(jit);
    printf("{\"op\":\"reset\"}\n");
    insert(200, 3.0);
    insert(201, 3.0 + 1.0 / 30);
    sample(3.0 + 0.4 / 30);
    jitter_stats st = jitter_get_stats(jit);
    printf("{\"stats\":{\"inserted\":%llu,\"duplicates\":%llu,\"late\":%llu,\"out_of_order\":%llu,"
           "\"evicted\":%llu,\"underruns\":%llu}}\n",
           (unsigned long long)st.inserted, (unsigned long long)st.duplicates,
           (unsigned long long)st.late, (unsigned long long)st.out_of_order,
           (unsigned long long)st.evicted, (unsigned long long)st.underruns);
    jitter_destroy(jit);
    return 0;
}
