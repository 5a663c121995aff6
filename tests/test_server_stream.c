/* The one snapshot-stream encoder (srv_stream.h): the shared stream and a view stream
 * with the same per-tree modes give the same bytes, both equal to the wire encoders
 * called directly; deltas appear as the stream holds one and two snapshots, and a failed
 * or skipped snapshot starts it over with a keyframe, and so does every key_every-th seq. */
#include "check.h"
#include "srv_stream.h"

#include <stdlib.h>

#define N 6
#define STRIDE 4
#define CAP 4096

static const uint8_t species[N] = { 0, 1, 0, 1, 1, 0 };
static const uint8_t full_modes[N] = { 4, 3, 4, 3, 3, 4 };

static wire_scene make_scene(void)
{
    wire_scene sc = { .n_trees = N, .n_species = 2, .species = species };
    sc.n_modes[0] = 4;
    sc.n_modes[1] = 3;
    for (int m = 0; m < 4; m++) {
        sc.step[0][m] = 1e-3f * (float)(m + 1);
        sc.step[1][m] = 2e-3f * (float)(m + 1);
    }
    return sc;
}

typedef struct snap_bufs {
    net_snap s;
    uint8_t key[CAP], d1[CAP], d2[CAP];
} snap_bufs;

static void snap_init(snap_bufs *b)
{
    memset(b, 0, sizeof *b);
    b->s.cap = CAP;
    b->s.key = b->key;
    b->s.delta1 = b->d1;
    b->s.delta2 = b->d2;
}

/* The state of snapshot k: a deterministic wave per tree and mode. */
static void fill_q(int16_t *q, int k)
{
    for (int t = 0; t < N; t++) {
        for (int m = 0; m < STRIDE; m++) {
            q[t * STRIDE + m] = (int16_t)(100 * t - 37 * m + 11 * k * (m + 1) - 5 * k * k);
        }
    }
}

/* What the wire encoders give for snapshot seq with `held` previous snapshots. */
static void reference(const wire_header *h, uint32_t seq, const wire_scene *sc,
                      const srv_qhist *qh, const uint8_t *modes, int held, snap_bufs *r)
{
    snap_init(r);
    wire_state cur = { .n_trees = N, .stride = STRIDE, .n_modes = modes, .q = qh->q[0] };
    wire_state prev = cur, prev2 = cur;
    prev.q = qh->q[1];
    prev2.q = qh->q[2];
    CHECK(wire_encode_keyframe(h, seq, sc, &cur, r->key, CAP, &r->s.key_len, NULL) == 0);
    if (held >= 1) {
        CHECK(wire_encode_delta(h, seq, sc, &cur, &prev, NULL, r->d1, CAP, &r->s.delta1_len,
                                NULL) == 0);
    }
    if (held >= 2) {
        CHECK(wire_encode_delta(h, seq, sc, &cur, &prev, &prev2, r->d2, CAP, &r->s.delta2_len,
                                NULL) == 0);
    }
}

static int same(const snap_bufs *a, const snap_bufs *b)
{
    return a->s.key_len == b->s.key_len && a->s.delta1_len == b->s.delta1_len &&
           a->s.delta2_len == b->s.delta2_len && !memcmp(a->key, b->key, a->s.key_len) &&
           !memcmp(a->d1, b->d1, a->s.delta1_len) && !memcmp(a->d2, b->d2, a->s.delta2_len);
}

static void test_shared_equals_view(void)
{
    wire_scene sc = make_scene();
    uint8_t view_modes[N], lod_modes[N] = { 4, 0, 2, 3, 0, 1 };
    memcpy(view_modes, full_modes, N);
    srv_stream shared, view, lod;
    srv_stream_start(&shared, 0, full_modes, 0);
    srv_stream_start(&view, 7, view_modes, 0);
    srv_stream_start(&lod, 9, lod_modes, 0);
    int16_t q[3][N * STRIDE];
    int cur = 0;
    for (int k = 1; k <= 5; k++) {
        fill_q(q[cur], k);
        srv_qhist qh = { .q = { q[cur], q[(cur + 2) % 3], q[(cur + 1) % 3] },
                         .n_trees = N,
                         .stride = STRIDE };
        wire_header h = { .tick = 2u * (uint32_t)k, .server_time_us = 1000u * (uint64_t)k };
        snap_bufs a, b, c, ra, rc;
        snap_init(&a);
        snap_init(&b);
        snap_init(&c);
        CHECK(srv_stream_encode(&shared, &h, (uint32_t)k, &sc, &qh, NET_WANT_ALL, &a.s, NULL) == 0);
        CHECK(srv_stream_encode(&view, &h, (uint32_t)k, &sc, &qh, NET_WANT_ALL, &b.s, NULL) == 0);
        CHECK(srv_stream_encode(&lod, &h, (uint32_t)k, &sc, &qh, NET_WANT_ALL, &c.s, NULL) == 0);
        int held = k - 1 < 2 ? k - 1 : 2;
        reference(&h, (uint32_t)k, &sc, &qh, full_modes, held, &ra);
        reference(&h, (uint32_t)k, &sc, &qh, lod_modes, held, &rc);
        CHECK(same(&a, &b));
        CHECK(same(&a, &ra));
        CHECK(same(&c, &rc));
        CHECK(!same(&a, &c));
        CHECK(a.s.key_len > 0 && (a.s.delta1_len > 0) == (k >= 2) &&
              (a.s.delta2_len > 0) == (k >= 3));
        CHECK(a.s.seq == (uint32_t)k && b.s.seq == (uint32_t)k);
        CHECK(a.s.stream == 0 && b.s.stream == 7 && c.s.stream == 9);
        cur = (cur + 1) % 3;
    }
    CHECK(shared.held == 2 && view.held == 2);
}

static void test_failure_and_skip(void)
{
    wire_scene sc = make_scene();
    uint8_t modes[N];
    memcpy(modes, full_modes, N);
    srv_stream st;
    srv_stream_start(&st, 3, modes, 0);
    int16_t q[3][N * STRIDE];
    for (int k = 0; k < 3; k++) {
        fill_q(q[k], k);
    }
    srv_qhist qh = { .q = { q[0], q[1], q[2] }, .n_trees = N, .stride = STRIDE };
    wire_header h = { .tick = 2 };
    snap_bufs a;
    for (uint32_t seq = 1; seq <= 3; seq++) {
        snap_init(&a);
        CHECK(srv_stream_encode(&st, &h, seq, &sc, &qh, NET_WANT_ALL, &a.s, NULL) == 0);
    }
    CHECK(st.held == 2 && a.s.delta2_len > 0);

    modes[1] = 4; /* species 1 has 3 modes */
    gale_err e;
    snap_init(&a);
    CHECK(srv_stream_encode(&st, &h, 4, &sc, &qh, NET_WANT_ALL, &a.s, &e) != 0);
    CHECK_STR_HAS(e.msg, "wire_encode_keyframe: cur.n_modes[1]: expected <= 3");
    CHECK(st.held == 0);
    modes[1] = 3;
    snap_init(&a);
    CHECK(srv_stream_encode(&st, &h, 5, &sc, &qh, NET_WANT_ALL, &a.s, NULL) == 0);
    CHECK(a.s.key_len > 0 && a.s.delta1_len == 0 && a.s.delta2_len == 0);
    snap_init(&a);
    CHECK(srv_stream_encode(&st, &h, 6, &sc, &qh, NET_WANT_ALL, &a.s, NULL) == 0);
    CHECK(a.s.delta1_len > 0 && a.s.delta2_len == 0);

    srv_stream_skip(&st);
    snap_init(&a);
    CHECK(srv_stream_encode(&st, &h, 8, &sc, &qh, NET_WANT_ALL, &a.s, NULL) == 0);
    CHECK(a.s.key_len > 0 && a.s.delta1_len == 0 && a.s.delta2_len == 0);
}

/* With key_every 4, snapshots 4, 8, 12 carry a keyframe only (every connection takes it)
 * and the two after each rebuild delta1 then delta2. */
static void test_periodic_keyframe(void)
{
    wire_scene sc = make_scene();
    srv_stream st;
    srv_stream_start(&st, 0, full_modes, 4);
    int16_t q[3][N * STRIDE];
    for (int k = 0; k < 3; k++) {
        fill_q(q[k], k);
    }
    srv_qhist qh = { .q = { q[0], q[1], q[2] }, .n_trees = N, .stride = STRIDE };
    wire_header h = { .tick = 2 };
    int key_only = 0, bad = 0;
    for (uint32_t seq = 1; seq <= 13; seq++) {
        snap_bufs a;
        snap_init(&a);
        CHECK(srv_stream_encode(&st, &h, seq, &sc, &qh, NET_WANT_ALL, &a.s, NULL) == 0);
        /* seq 1 starts the stream; 4, 8, 12 are the periodic ones */
        uint32_t since = seq % 4 == 0 || seq == 1 ? 0 : seq < 4 ? seq - 1 : seq % 4;
        bool want1 = since >= 1, want2 = since >= 2;
        bad += a.s.key_len == 0 || (a.s.delta1_len > 0) != want1 || (a.s.delta2_len > 0) != want2;
        key_only += a.s.delta1_len == 0 && a.s.delta2_len == 0;
    }
    CHECK(bad == 0);
    CHECK(key_only == 4);
}

/* Frames on demand: delta2 always once the stream holds two; the keyframe when wanted or
 * when the stream holds none (a start, a periodic seq), delta1 when wanted or when it
 * holds one; a frame not encoded has length 0 and the others their bytes with all wanted. */
static void test_frames_wanted(void)
{
    wire_scene sc = make_scene();
    int16_t q[3][N * STRIDE];
    for (int k = 0; k < 3; k++) {
        fill_q(q[k], k);
    }
    srv_qhist qh = { .q = { q[0], q[1], q[2] }, .n_trees = N, .stride = STRIDE };
    wire_header h = { .tick = 2 };
    for (unsigned want = 0; want <= NET_WANT_ALL; want++) {
        srv_stream st, all;
        srv_stream_start(&st, 0, full_modes, 6);
        srv_stream_start(&all, 0, full_modes, 6);
        int bad = 0;
        for (uint32_t seq = 1; seq <= 8; seq++) {
            const int held = st.held;
            snap_bufs a, b;
            snap_init(&a);
            snap_init(&b);
            CHECK(srv_stream_encode(&st, &h, seq, &sc, &qh, want, &a.s, NULL) == 0);
            CHECK(srv_stream_encode(&all, &h, seq, &sc, &qh, NET_WANT_ALL, &b.s, NULL) == 0);
            const bool key = held == 0 || seq % 6 == 0 || (want & NET_WANT_KEY);
            const bool d1 = seq % 6 && (held == 1 || (held >= 1 && (want & NET_WANT_DELTA1)));
            const bool d2 = seq % 6 && held >= 2;
            bad += (a.s.key_len > 0) != key || (a.s.delta1_len > 0) != d1 ||
                   (a.s.delta2_len > 0) != d2;
            bad += key && (a.s.key_len != b.s.key_len || memcmp(a.key, b.key, a.s.key_len));
            bad += d1 && (a.s.delta1_len != b.s.delta1_len || memcmp(a.d1, b.d1, a.s.delta1_len));
            bad += d2 && (a.s.delta2_len != b.s.delta2_len || memcmp(a.d2, b.d2, a.s.delta2_len));
        }
        CHECK(bad == 0);
    }
}

int main(void)
{
    RUN(test_shared_equals_view);
    RUN(test_frames_wanted);
    RUN(test_failure_and_skip);
    RUN(test_periodic_keyframe);
    return check_report();
}
