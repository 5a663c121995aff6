/* Tests of the batch modal update (server/modal.c): the force formula against a hand
 * computation, the batch update against a per-tree osc_step reference (Diener 2008
 * eq. 8-9 with f_i = |v| v.p_i, section 4), quantisation into the snapshot rows, thread
 * count independence, Σ q² and the force scale kept for the damage step, and bad input. */
#include <stdlib.h>

#include "check.h"
#include "modal.h"
#include "oscillator.h"
#include "wire.h"

/* Yaw 90 degrees, world wind (3, 4, 0): tree-frame wind (4, -3, 0), |v| = 5,
 * p = (1, 2, 0.5): v.p = 4 - 6 = -2, f = -10. From rest, one step gives q = b1 f,
 * q' = b2 f. */
static void test_force_by_hand(void)
{
    const float omega[2] = { 2.0f, 10.0f }, gamma[2] = { 0.1f, 0.5f };
    const float p[6] = { 1.0f, 2.0f, 0.5f, 0.0f, 0.0f, 1.0f };
    const float step[2] = { 1e-3f, 1e-3f };
    modal_species sp = { 2, omega, gamma, p, step };
    uint8_t ts[2] = { 0, 0 };
    float yaw[2] = { (float)(M_PI / 2), 0.0f };
    gale_err e;
    modal *m = modal_create(&(modal_desc){ .n_trees = 2, .n_species = 1, .species = &sp,
                                           .tree_species = ts, .tree_yaw_rad = yaw,
                                           .dt_s = 0.01, .n_threads = 1 },
                            &e);
    CHECK(m != NULL);
    /* Tree 1 (yaw 0) gets (0, 0, -2): |v| = 2, mode 1 f = 2 * (-2 * 1) = -4. */
    const float wind[6] = { 3.0f, 4.0f, 0.0f, 0.0f, 0.0f, -2.0f };
    int16_t snap[4];
    modal_tick(m, wind, snap);
    osc_coef c0 = osc_exact(2.0, 0.1, 0.01), c1 = osc_exact(10.0, 0.5, 0.01);
    float q[2], v[2];
    CHECK(modal_get(m, 0, q, v) == 2);
    CHECK_NEAR(q[0], c0.b1 * -10.0f, 1e-7);
    CHECK_NEAR(v[0], c0.b2 * -10.0f, 1e-6);
    CHECK_NEAR(q[1], c1.b1 * 0.0f, 1e-9);
    CHECK(modal_get(m, 1, q, v) == 2);
    CHECK_NEAR(q[0], c0.b1 * -2.0f, 1e-8); /* (0,0,-2).(1,2,0.5) = -1, |v| = 2: f = -2 */
    CHECK_NEAR(q[1], c1.b1 * -4.0f, 1e-7);
    CHECK_NEAR(v[1], c1.b2 * -4.0f, 1e-6);
    /* Snapshot: q / step rounded. */
    CHECK(snap[0] == wire_quantize(c0.b1 * -10.0f, 1e3f));
    CHECK(snap[3] == wire_quantize(c1.b1 * -4.0f, 1e3f));
    modal_destroy(m);
}

static uint64_t rng = 0x2545f4914f6cdd1dull;
static float frand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (float)((rng >> 11) * (1.0 / 9007199254740992.0));
}

#define NT 1000
#define NS 3

/* Batch vs per-tree reference over 200 ticks of changing wind, three species with
 * different mode counts (5, 32, 17), random yaws; 1 and 2 threads. */
static void test_batch_vs_reference(void)
{
    static const uint32_t nmodes[NS] = { 5, 32, 17 };
    static float omega[NS][32], gamma[NS][32], p[NS][32 * 3], step[NS][32];
    modal_species sp[NS];
    for (int s = 0; s < NS; s++) {
        for (uint32_t i = 0; i < nmodes[s]; i++) {
            omega[s][i] = 1.0f + 40.0f * frand();
            gamma[s][i] = 0.05f + 2.0f * frand();
            for (int k = 0; k < 3; k++) {
                p[s][3 * i + (uint32_t)k] = 0.02f * (frand() - 0.5f);
            }
            step[s][i] = 1e-4f * (1.0f + frand());
        }
        sp[s] = (modal_species){ nmodes[s], omega[s], gamma[s], p[s], step[s] };
    }
    static uint8_t ts[NT];
    static float yaw[NT], wind[NT * 3];
    static float rq[NT][32], rv[NT][32];
    for (int t = 0; t < NT; t++) {
        ts[t] = (uint8_t)(t * 7 % NS);
        yaw[t] = 6.2831853f * frand();
    }
    gale_err e;
    modal_desc d = { .n_trees = NT, .n_species = NS, .species = sp, .tree_species = ts,
                     .tree_yaw_rad = yaw, .dt_s = 1.0 / 60, .n_threads = 1 };
    modal *m1 = modal_create(&d, &e);
    d.n_threads = 2;
    modal *m2 = modal_create(&d, &e);
    CHECK(m1 && m2);
    CHECK(modal_stride(m1) == 32);
    CHECK(modal_tree_modes(m1, 1) == nmodes[7 % NS]);
    osc_coef coef[NS][32];
    for (int s = 0; s < NS; s++) {
        for (uint32_t i = 0; i < nmodes[s]; i++) {
            coef[s][i] = osc_exact(omega[s][i], gamma[s][i], 1.0 / 60);
        }
    }
    static int16_t snap1[NT * 32], snap2[NT * 32];
    double max_err = 0.0, max_q = 0.0;
    double max_n2_rel = 0.0, max_fs_rel = 0.0;
    int q_off = 0, q_far = 0, same_threads = 1, tail_zero = 1;
    for (int tick = 0; tick < 200; tick++) {
        for (int t = 0; t < NT; t++) {
            wind[3 * t] = 30.0f * (frand() - 0.3f);
            wind[3 * t + 1] = 30.0f * (frand() - 0.5f);
            wind[3 * t + 2] = 4.0f * (frand() - 0.5f);
        }
        memset(snap1, 0x55, sizeof snap1);
        modal_tick(m1, wind, snap1);
        modal_tick(m2, wind, snap2);
        same_threads &= memcmp(snap1, snap2, sizeof snap1) == 0;
        for (int t = 0; t < NT; t++) {
            int s = ts[t];
            /* Reference: rotate by -yaw in double, force, osc_step per mode. */
            double c = cos((double)yaw[t]), sn = sin((double)yaw[t]);
            double wx = wind[3 * t], wy = wind[3 * t + 1], wz = wind[3 * t + 2];
            double lx = c * wx + sn * wy, ly = -sn * wx + c * wy, lz = wz;
            double speed = sqrt(wx * wx + wy * wy + wz * wz);
            float q[32], v[32];
            modal_get(m1, (uint32_t)t, q, v);
            for (uint32_t i = 0; i < nmodes[s]; i++) {
                const float *pi = &p[s][3 * i];
                float f = (float)(speed * (lx * (double)pi[0] + ly * (double)pi[1] +
                                           lz * (double)pi[2]));
                osc_step(&coef[s][i], f, &rq[t][i], &rv[t][i]);
                double dq = fabs((double)q[i] - (double)rq[t][i]);
                double aq = fabs((double)rq[t][i]);
                max_err = dq > max_err ? dq : max_err;
                max_q = aq > max_q ? aq : max_q;
                int16_t want = wire_quantize(rq[t][i], 1.0f / step[s][i]);
                int16_t got = snap1[t * 32 + (int)i];
                q_off += got != want;
                q_far += abs(got - want) > 1;
            }
            for (uint32_t i = nmodes[s]; i < 32; i++) {
                tail_zero &= snap1[t * 32 + (int)i] == 0;
            }
            /* Σ q² as damage.c screens with it, against a double sum of the state */
            double n2 = 0.0;
            for (uint32_t i = 0; i < nmodes[s]; i++) {
                n2 += (double)q[i] * (double)q[i];
            }
            const double n2_got = modal_get_rows(m1).qnorm2[t];
            max_n2_rel = fmax(max_n2_rel, fabs(n2_got - n2) / fmax(n2, 1e-30));
            max_fs_rel = fmax(max_fs_rel, fabs((double)modal_get_rows(m1).force_scale[t] - speed) / speed);
        }
    }
    /* float rotation vs double reference: ~1e-7 relative per step in f, carried forward
     * by the state; 1e-4 of the largest |q| is generous and still catches a wrong sign,
     * axis or mode (those are O(1) of it). */
    double max_rel = max_err / max_q;
    CHECK(max_q > 0.0);
    CHECK(max_rel < 1e-4);
    fprintf(stderr, "  max |q - reference| / max |q| = %.2e, quantised off by one %d\n",
            max_rel, q_off);
    CHECK(q_far == 0);
    CHECK(q_off < NT); /* only values sitting on a rounding boundary */
    /* 32 float squares summed in any order: within 32 roundings, 2e-6 of the sum; a lane
     * left out is O(1/32) of it; the force scale of rigid drag is |v|, one sqrtf */
    fprintf(stderr, "  max |qnorm2 - sum q^2| / sum q^2 = %.2e, force scale %.2e\n", max_n2_rel,
            max_fs_rel);
    CHECK(max_n2_rel < 4e-6);
    CHECK(max_fs_rel < 1e-6);
    CHECK(same_threads);
    CHECK(tail_zero);
    modal_destroy(m1);
    modal_destroy(m2);
}

/* Bad samples do not poison the state; bad descs are refused with a reason. */
static void test_bad_input(void)
{
    const float omega[1] = { 3.0f }, gamma[1] = { 0.2f }, p[3] = { 1.0f, 0.0f, 0.0f };
    const float step[1] = { 1e-3f };
    modal_species sp = { 1, omega, gamma, p, step };
    uint8_t ts[1] = { 0 };
    gale_err e;
    modal *m = modal_create(&(modal_desc){ .n_trees = 1, .n_species = 1, .species = &sp,
                                           .tree_species = ts },
                            &e);
    CHECK(m != NULL);
    const float bad[3][3] = { { NAN, 0, 0 }, { INFINITY, 1, 0 }, { 1e30f, 0, 0 } };
    int16_t snap[1];
    for (int k = 0; k < 3; k++) {
        modal_tick(m, bad[k], snap);
        float q, v;
        modal_get(m, 0, &q, &v);
        CHECK(q == 0.0f && v == 0.0f && snap[0] == 0);
    }
    float big = 1e30f;
    modal_set(m, 0, &big, NULL);
    const float calm[3] = { 0, 0, 0 };
    modal_tick(m, calm, snap);
    CHECK(snap[0] == WIRE_QMAX);
    modal_destroy(m);

    ts[0] = 2;
    CHECK(modal_create(&(modal_desc){ .n_trees = 1, .n_species = 1, .species = &sp,
                                      .tree_species = ts },
                       &e) == NULL);
    CHECK_STR_HAS(e.msg, "modal_create: tree_species[0]: expected < 1, got 2");
    ts[0] = 0;
    const float neg[1] = { -1.0f };
    sp.omega = neg;
    CHECK(modal_create(&(modal_desc){ .n_trees = 1, .n_species = 1, .species = &sp,
                                      .tree_species = ts },
                       &e) == NULL);
    CHECK_STR_HAS(e.msg, "modal_create: species[0] mode 0: expected omega > 0, gamma >= 0, qstep > 0 (finite), got -1, 0.2, 0.001");
    CHECK(modal_create(&(modal_desc){ .n_trees = 0 }, &e) == NULL);
    CHECK_STR_HAS(e.msg, "modal_create: n_trees: expected 1..262144, got 0");
    modal_destroy(NULL);
}

/* The snapshot rows go through the real encoder and decoder: after a keyframe and a
 * chain of deltas the client's dequantised q is within half a step of the server's
 * float q for every tree and mode (plus float rounding of q / step). */
static void test_snapshot_through_wire(void)
{
    enum { N = 300, M = 12 };
    static float omega[M], gamma[M], p[3 * M], step[M];
    for (int i = 0; i < M; i++) {
        omega[i] = 2.0f + 5.0f * (float)i;
        gamma[i] = 0.2f;
        p[3 * i] = 0.01f;
        p[3 * i + 1] = -0.004f * (float)i;
        p[3 * i + 2] = 0.0f;
        step[i] = 1e-4f * (float)(i + 1);
    }
    modal_species sp = { M, omega, gamma, p, step };
    static uint8_t ts[N], nm[N];
    static float yaw[N], wind[3 * N];
    static int16_t snap[3][N * M];
    for (int t = 0; t < N; t++) {
        yaw[t] = 0.02f * (float)t;
        nm[t] = M;
    }
    gale_err e;
    modal *m = modal_create(&(modal_desc){ .n_trees = N, .n_species = 1, .species = &sp,
                                           .tree_species = ts, .tree_yaw_rad = yaw },
                            &e);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = N, .max_modes = M }, &e);
    CHECK(m && d);
    wire_scene sc = { .n_trees = N, .n_species = 1, .species = ts };
    sc.n_modes[0] = M;
    memcpy(sc.step[0], step, sizeof step);
    static uint8_t buf[1 << 16];
    bool ok = true;
    double worst = 0.0;
    for (uint32_t seq = 1; seq <= 90; seq++) {
        for (int t = 0; t < N; t++) {
            wind[3 * t] = 15.0f + 10.0f * sinf(0.1f * (float)seq + 0.3f * (float)t);
            wind[3 * t + 1] = 5.0f * cosf(0.17f * (float)seq);
            wind[3 * t + 2] = 0.5f;
        }
        modal_tick(m, wind, NULL);
        modal_tick(m, wind, snap[seq % 3]);
        wire_state cur = { N, M, nm, snap[seq % 3] };
        wire_state p1 = { N, M, nm, snap[(seq + 2) % 3] };
        wire_state p2 = { N, M, nm, snap[(seq + 1) % 3] };
        wire_header h = { .tick = 2 * seq };
        size_t len = 0;
        int rc = seq == 1 ? wire_encode_keyframe(&h, seq, &sc, &cur, buf, sizeof buf, &len, &e)
                          : wire_encode_delta(&h, seq, &sc, &cur, &p1, seq > 2 ? &p2 : NULL, buf,
                                              sizeof buf, &len, &e);
        ok &= rc == 0;
        ok &= wire_decode(d, buf, len, &(wire_frame){ 0 }, &e) == 0;
        for (uint32_t t = 0; t < N; t++) {
            float qs[M], qc[M];
            modal_get(m, t, qs, NULL);
            ok &= wire_decoder_q(d, t, qc, M) == M;
            for (int i = 0; i < M; i++) {
                double err = fabs((double)qs[i] - (double)qc[i]) / (double)step[i];
                worst = err > worst ? err : worst;
            }
        }
    }
    CHECK(ok);
    CHECK(worst <= 0.5 + 1e-3);
    CHECK(worst > 0.3); /* the bound is reached, so the check can fail */
    fprintf(stderr, "  worst |q_client - q_server| = %.4f steps\n", worst);
    wire_decoder_destroy(d);
    modal_destroy(m);
}

int main(void)
{
    RUN(test_snapshot_through_wire);
    RUN(test_force_by_hand);
    RUN(test_batch_vs_reference);
    RUN(test_bad_input);
    return check_report();
}
