/* The state encoders in lanes (wire_encode_keyframe_lanes, wire_encode_delta_lanes): the
 * frames of 2, 3, 7 and 16 lanes on real threads, and of lanes run in reverse order, are
 * byte for byte those of one lane, for keyframes, deltas on one and two snapshots, trees
 * out of view, LOD, species of different mode counts and groups of every width 0..16;
 * each frame decodes to the snapshot it was made from; a buffer too small for the lanes'
 * layout still gets the one-lane bytes, one byte short of the frame fails, and a bad state
 * is named as without lanes; a snapshot's three frames encoded in one pass
 * (wire_encode_snapshot_lanes) are those of the three calls, and so are they when the
 * pass runs in stages, its lanes split over two turns (wire_snapshot_begin, _run,
 * _finish); and every frame's values are those of a reference coder written value by
 * value from PROTOCOL.md, for values inside, on the edges of and past the range the
 * encoder codes in 16-bit lanes, on each of its paths (GALE_WIRE_ROWS 4, 2 and 0). */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "wire.h"

#define NT 2000
#define STRIDE 40

static uint64_t rng = 0x2545f4914f6cdd1dull;
static uint32_t rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (uint32_t)(rng >> 16);
}

/* Lanes on threads of their own, one per lane, joined before returning. */
typedef struct thread_arg {
    wire_lane_fn job;
    void *arg;
    int lane;
} thread_arg;

static void *thread_main(void *p)
{
    thread_arg *a = p;
    a->job(a->arg, a->lane);
    return NULL;
}

static void run_threads(void *ctx, int n, wire_lane_fn job, void *arg)
{
    (void)ctx;
    pthread_t th[WIRE_MAX_LANES];
    thread_arg ta[WIRE_MAX_LANES];
    for (int i = 0; i < n; i++) {
        ta[i] = (thread_arg){ job, arg, i };
        CHECK(pthread_create(&th[i], NULL, thread_main, &ta[i]) == 0);
    }
    for (int i = 0; i < n; i++) {
        pthread_join(th[i], NULL);
    }
}

/* The last lane first: a lane's bytes do not depend on the others having run. */
static void run_reverse(void *ctx, int n, wire_lane_fn job, void *arg)
{
    (void)ctx;
    for (int i = n - 1; i >= 0; i--) {
        job(arg, i);
    }
}

typedef struct snap {
    uint8_t n_modes[NT];
    int16_t q[NT * STRIDE];
} snap;

static uint8_t species[NT];
static snap hist[3];          /* cur, prev, prev2 */
static int widths_seen[19];
/* The widest group a frame holds: the zero predictor's zigzag of |q| <= WIRE_QMAX is below
 * 2^16, so a wider residual (up to 18 bits) is never the narrowest. */
#define WIDEST 16

/* Snapshot k: smooth motion from the last one with noise of a width that varies by tree,
 * some trees out of view, some at a lower LOD, a few jumping to extremes. */
static void make_snap(const wire_scene *sc, snap *s, const snap *last)
{
    for (uint32_t t = 0; t < NT; t++) {
        const uint32_t full = sc->n_modes[species[t]];
        uint32_t r = rnd() % 16;
        s->n_modes[t] = (uint8_t)(r == 0 ? 0 : r == 1 ? 1 + rnd() % full : full);
        const unsigned bits = rnd() % 17; /* residuals up to 2^16 */
        for (uint32_t m = 0; m < STRIDE; m++) {
            int32_t base = last ? last->q[t * STRIDE + m] : 0;
            int32_t noise = bits ? (int32_t)(rnd() % (1u << bits)) - (int32_t)(1u << (bits - 1)) : 0;
            int32_t v = base + noise;
            if (rnd() % 97 == 0) {
                v = rnd() % 2 ? WIRE_QMAX : -WIRE_QMAX; /* full swing: width 17-18 */
            }
            v = v > WIRE_QMAX ? WIRE_QMAX : v < -WIRE_QMAX ? -WIRE_QMAX : v;
            s->q[t * STRIDE + m] = (int16_t)v;
        }
    }
}

static wire_state state_of(const snap *s)
{
    return (wire_state){ .n_trees = NT, .stride = STRIDE, .n_modes = s->n_modes, .q = s->q };
}

/* Group widths in a frame's values, walked as the decoder does (for the coverage check). */
static void note_widths(const uint8_t *v, const uint8_t *end, const snap *s)
{
    for (uint32_t t = 0; t < NT && v < end; t++) {
        for (uint32_t g0 = 0; g0 < s->n_modes[t]; g0 += 8) {
            const uint32_t k = s->n_modes[t] - g0 < 8 ? s->n_modes[t] - g0 : 8;
            const unsigned w = *v & 0x1fu;
            widths_seen[w <= 18 ? w : 0]++;
            v += 1 + (k * w + 7) / 8;
        }
    }
}

/* Snapshot k for the reference test: most trees move within [-8192, 8191] (the fast
 * coder's 16-bit lanes), some sit on that range's edges or just past them or swing from
 * edge to edge, some jump over the whole of [-QMAX, QMAX]; whole and partial groups,
 * trees out of view. */
static void make_edge_snap(const wire_scene *sc, snap *s, const snap *last)
{
    static const int16_t edge[] = { -8193, -8192, 8191, 8192, 0, -1, 1 };
    for (uint32_t t = 0; t < NT; t++) {
        const uint32_t full = sc->n_modes[species[t]];
        const uint32_t r = rnd() % 16;
        uint32_t n = r == 0 ? 0 : r < 3 ? 1 + rnd() % full : r < 8 ? (rnd() % 5 + 1) * 8 : full;
        s->n_modes[t] = (uint8_t)(n > full ? full : n);
        const uint32_t kind = rnd() % 8;
        const unsigned bits = rnd() % 15;
        for (uint32_t m = 0; m < STRIDE; m++) {
            int32_t base = last ? last->q[t * STRIDE + m] : 0;
            int32_t noise = bits ? (int32_t)(rnd() % (1u << bits)) - (int32_t)(1u << (bits - 1)) : 0;
            int32_t v = base + noise;
            if (kind < 6) {
                v = v > 8191 ? 8191 - (int32_t)(rnd() % 64) : v < -8192 ? -8192 + (int32_t)(rnd() % 64) : v;
            } else if (kind == 6 && t % 4 < 2) {
                v = edge[rnd() % (sizeof edge / sizeof edge[0])];
            } else if (kind == 6) {
                /* a swing from L - 1 to -L and back: the linear residual 4 L - 2, which
                   wraps to -2 in 16 bits for L = 16384 */
                const int32_t lim = t % 4 == 2 ? 8192 : 16384;
                v = base >= 0 ? -lim : lim - 1;
            } else {
                v = (int32_t)(rnd() % (2u * WIRE_QMAX + 1)) - WIRE_QMAX;
            }
            s->q[t * STRIDE + m] = (int16_t)v;
        }
    }
}

/* The values section of a frame as PROTOCOL.md "State frames" defines it, value by value:
 * each tree in view, each group of up to 8 of its modes, the zigzag residuals against the
 * first n_pred predictors (zero; the previous snapshot; twice the previous less the one
 * before), history rows read as 0 past what they sent; the narrowest (the first of equal
 * widths), its header byte pred << 5 | width, then the group's residuals of that width,
 * least significant bit first, from a byte boundary. Returns the bytes written. */
static size_t ref_values(const snap *cur, const snap *prev, const snap *prev2, int n_pred,
                         uint8_t *out)
{
    size_t len = 0;
    for (uint32_t t = 0; t < NT; t++) {
        const uint32_t n = cur->n_modes[t];
        for (uint32_t g0 = 0; g0 < n; g0 += 8) {
            const uint32_t k = n - g0 < 8 ? n - g0 : 8;
            uint32_t z[3][8];
            unsigned width[3] = { 0, 0, 0 };
            for (uint32_t i = 0; i < k; i++) {
                const uint32_t m = g0 + i;
                const int32_t v = cur->q[t * STRIDE + m];
                const int32_t a = prev && m < prev->n_modes[t] ? prev->q[t * STRIDE + m] : 0;
                const int32_t b = prev2 && m < prev2->n_modes[t] ? prev2->q[t * STRIDE + m] : 0;
                const int32_t r[3] = { v, v - a, v - (2 * a - b) };
                for (int p = 0; p < 3; p++) {
                    z[p][i] = r[p] >= 0 ? 2u * (uint32_t)r[p] : 2u * (uint32_t)(-r[p]) - 1u;
                    unsigned w = 0;
                    while (w < 32 && z[p][i] >> w) {
                        w++;
                    }
                    width[p] = w > width[p] ? w : width[p];
                }
            }
            int best = 0;
            for (int p = 1; p < n_pred; p++) {
                best = width[p] < width[best] ? p : best;
            }
            const unsigned w = width[best];
            out[len++] = (uint8_t)(best << 5 | (int)w);
            const size_t nbytes = (k * w + 7) / 8;
            memset(out + len, 0, nbytes);
            for (uint32_t i = 0; i < k; i++) {
                for (unsigned bit = 0; bit < w; bit++) {
                    const size_t at = (size_t)i * w + bit;
                    out[len + at / 8] |= (uint8_t)((z[best][i] >> bit & 1u) << (at % 8));
                }
            }
            len += nbytes;
        }
    }
    return len;
}

static uint8_t one[1 << 22], many[1 << 22];

/* Encodes frame kind (0 keyframe, 1 delta on prev, 2 on prev and prev2) with lanes l. */
static int encode(int kind, const wire_scene *sc, const wire_lanes *l, uint8_t *buf, size_t cap,
                  size_t *len, gale_err *err)
{
    const wire_header h = { .tick = 77, .server_time_us = 123456789ull };
    const wire_state cur = state_of(&hist[0]), prev = state_of(&hist[1]),
                     prev2 = state_of(&hist[2]);
    return kind == 0 ? wire_encode_keyframe_lanes(&h, 9, sc, &cur, l, buf, cap, len, err)
                     : wire_encode_delta_lanes(&h, 9, sc, &cur, &prev, kind == 2 ? &prev2 : NULL,
                                               l, buf, cap, len, err);
}

/* A scene of three species of 32, 40 and 13 modes, the trees' species drawn at random. */
static wire_scene three_species(void)
{
    wire_scene sc = { .n_trees = NT, .n_species = 3, .species = species };
    const uint8_t nm[3] = { 32, 40, 13 };
    for (uint32_t s = 0; s < 3; s++) {
        sc.n_modes[s] = nm[s];
        for (uint32_t m = 0; m < nm[s]; m++) {
            sc.step[s][m] = 1e-4f * (float)(1 + m);
        }
    }
    for (uint32_t t = 0; t < NT; t++) {
        species[t] = (uint8_t)(rnd() % 3);
    }
    return sc;
}

static void test_lanes_same_bytes(void)
{
    const wire_scene sc = three_species();
    wire_decoder *dec = wire_decoder_create(&(wire_decoder_desc){ .max_trees = NT }, NULL);
    CHECK(dec != NULL);
    make_snap(&sc, &hist[2], NULL);
    make_snap(&sc, &hist[1], &hist[2]);
    int frames = 0;
    for (int round = 0; round < 6; round++) {
        make_snap(&sc, &hist[0], &hist[1]);
        if (round % 2) {
            memcpy(hist[0].n_modes, hist[1].n_modes, NT); /* the same set: SET_SAME */
        }
        for (int kind = 0; kind < 3; kind++) {
            gale_err err;
            size_t len1 = 0;
            CHECK(encode(kind, &sc, NULL, one, sizeof one, &len1, &err) == 0);
            static uint8_t ref[1 << 22];
            const size_t n_ref = ref_values(&hist[0], kind ? &hist[1] : NULL,
                                            kind == 2 ? &hist[2] : NULL, kind + 1, ref);
            CHECK(len1 > n_ref && memcmp(one + len1 - n_ref, ref, n_ref) == 0);
            note_widths(ref, ref + n_ref, &hist[0]);
            const int ns[] = { 2, 3, 7, 16 };
            for (int i = 0; i < 5; i++) {
                const wire_lanes l = i < 4 ? (wire_lanes){ ns[i], run_threads, NULL }
                                           : (wire_lanes){ 5, run_reverse, NULL };
                size_t len = 0;
                memset(many, 0xA5, len1 + 64);
                CHECK(encode(kind, &sc, &l, many, sizeof many, &len, &err) == 0);
                CHECK(len == len1);
                CHECK(memcmp(one, many, len1) == 0);
            }
            /* too small for the lanes' worst-case layout, big enough for the frame */
            const wire_lanes l2 = { 2, run_threads, NULL };
            size_t len = 0;
            CHECK(encode(kind, &sc, &l2, many, len1, &len, &err) == 0);
            CHECK(len == len1 && memcmp(one, many, len1) == 0);
            CHECK(encode(kind, &sc, &l2, many, len1 - 1, &len, &err) == GALE_E_RANGE);
            CHECK(strstr(err.msg, "too small") != NULL);
            /* the keyframe decodes to the snapshot */
            if (kind == 0) {
                wire_frame f;
                CHECK(wire_decode(dec, one, len1, &f, &err) == 0);
                const wire_state st = wire_decoder_state(dec);
                for (uint32_t t = 0; t < NT; t++) {
                    CHECK(st.n_modes[t] == hist[0].n_modes[t]);
                    for (uint32_t m = 0; m < hist[0].n_modes[t]; m++) {
                        CHECK(st.q[(size_t)t * st.stride + m] == hist[0].q[t * STRIDE + m]);
                    }
                }
            }
            frames++;
        }
        /* the three frames in one pass: the bytes of the separate calls, with and without
           lanes, holding none, one or two previous snapshots */
        for (int held = 0; held < 3; held++) {
            static uint8_t fused[3][1 << 22];
            const wire_header h = { .tick = 77, .server_time_us = 123456789ull };
            const wire_state cur = state_of(&hist[0]), prev = state_of(&hist[1]),
                             prev2 = state_of(&hist[2]);
            for (int li = 0; li < 2; li++) {
                const wire_lanes l = { 3, run_threads, NULL };
                gale_err err;
                wire_frame_out out[3];
                for (int f = 0; f < 3; f++) {
                    out[f] = (wire_frame_out){ fused[f], sizeof fused[f], 0, &err };
                }
                CHECK(wire_encode_snapshot_lanes(&h, 9, &sc, &cur, held >= 1 ? &prev : NULL,
                                                 held >= 2 ? &prev2 : NULL, li ? &l : NULL,
                                                 out) == 0);
                for (int f = 0; f <= held; f++) {
                    size_t len1 = 0;
                    CHECK(encode(f, &sc, NULL, one, sizeof one, &len1, &err) == 0);
                    CHECK(out[f].len == len1 && memcmp(one, fused[f], len1) == 0);
                }
            }
            /* only the frames wanted (a NULL buf: not written, its len 0), in every
               choice: each written one the bytes of its own call */
            for (unsigned want = 0; want < 8u; want++) {
                const wire_lanes l = { 3, run_threads, NULL };
                gale_err err;
                wire_frame_out out[3];
                for (int f = 0; f < 3; f++) {
                    memset(fused[f], 0xA5, 64);
                    out[f] = (wire_frame_out){ want >> f & 1u ? fused[f] : NULL,
                                               sizeof fused[f], 99, &err };
                }
                CHECK(wire_encode_snapshot_lanes(&h, 9, &sc, &cur, held >= 1 ? &prev : NULL,
                                                 held >= 2 ? &prev2 : NULL, &l, out) == 0);
                for (int f = 0; f <= held; f++) {
                    size_t len1 = 0;
                    CHECK(encode(f, &sc, NULL, one, sizeof one, &len1, &err) == 0);
                    if (want >> f & 1u) {
                        CHECK(out[f].len == len1 && memcmp(one, fused[f], len1) == 0);
                    } else {
                        CHECK(out[f].len == 0 && fused[f][0] == 0xA5);
                    }
                }
            }
            /* the same in stages, the lanes over two turns (the later share first), the
               header and the state descriptions gone before the lanes run */
            for (int split = 0; split < 4; split++) {
                const wire_lanes l = { 5, run_threads, NULL };
                gale_err err;
                wire_frame_out out[3];
                for (int f = 0; f < 3; f++) {
                    memset(fused[f], 0xA5, 1 << 16);
                    out[f] = (wire_frame_out){ fused[f], sizeof fused[f], 0, &err };
                }
                wire_snapshot_job job;
                struct {
                    wire_header h;
                    wire_state st[3];
                } tmp = { h, { cur, prev, prev2 } };
                wire_snapshot_begin(&job, &tmp.h, 9, &sc, &tmp.st[0],
                                    held >= 1 ? &tmp.st[1] : NULL,
                                    held >= 2 ? &tmp.st[2] : NULL, &l, out);
                memset(&tmp, 0, sizeof tmp);
                const int n = wire_snapshot_lanes(&job);
                CHECK(n == 5);
                const int k = split == 0 ? 0 : split == 1 ? 1 : split == 2 ? n / 2 : n;
                wire_snapshot_run(&job, k, n);
                wire_snapshot_run(&job, 0, k);
                CHECK(wire_snapshot_finish(&job) == 0);
                for (int f = 0; f <= held; f++) {
                    size_t len1 = 0;
                    CHECK(encode(f, &sc, NULL, one, sizeof one, &len1, &err) == 0);
                    CHECK(out[f].len == len1 && memcmp(one, fused[f], len1) == 0);
                }
            }
        }
        hist[2] = hist[1];
        hist[1] = hist[0];
    }
    wire_decoder_destroy(dec);
    CHECK(frames == 18);
    for (int w = 0; w <= WIDEST; w++) {
        if (!widths_seen[w]) {
            fprintf(stderr, "width %d never coded\n", w);
        }
        CHECK(widths_seen[w] > 0);
    }
}

/* A value below -WIRE_QMAX in cur, prev or prev2, in a whole group, a partial one, a history
 * row longer than the frame's or a tree out of view, is named as the one-lane encoder
 * names it, whichever lane finds it. */
static void test_lanes_bad_state(void)
{
    wire_scene sc = { .n_trees = NT, .n_species = 1, .species = species };
    sc.n_modes[0] = 8;
    sc.step[0][0] = 1e-3f;
    for (uint32_t m = 1; m < 8; m++) {
        sc.step[0][m] = 1e-3f;
    }
    memset(species, 0, NT);
    for (int k = 0; k < 3; k++) {
        memset(hist[k].n_modes, 8, NT);
        memset(hist[k].q, 0, sizeof hist[k].q);
    }
    /* a whole group read from the rows; a partial group (5 modes sent); a history row
       longer than the frame's (prev sends 8, cur 3); prev2's row of a tree cur does not
       send */
    const struct {
        int state, tree, mode, cur_modes;
        const char *named;
    } bad[] = { { 1, NT - 3, 5, 8, "prev.q[1997][5]" },
                { 0, NT / 2, 4, 5, "cur.q[1000][4]" },
                { 1, 700, 6, 3, "prev.q[700][6]" },
                { 2, 1500, 7, 0, "prev2.q[1500][7]" } };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        for (int j = 0; j < 3; j++) {
            memset(hist[j].n_modes, 8, NT);
            memset(hist[j].q, 0, sizeof hist[j].q);
        }
        hist[0].n_modes[bad[k].tree] = (uint8_t)bad[k].cur_modes;
        hist[bad[k].state].q[bad[k].tree * STRIDE + bad[k].mode] = -WIRE_QMAX - 1;
        gale_err e1, e2;
        size_t len;
        const wire_lanes l = { 4, run_threads, NULL };
        CHECK(encode(2, &sc, NULL, one, sizeof one, &len, &e1) == GALE_E_RANGE);
        CHECK(encode(2, &sc, &l, many, sizeof many, &len, &e2) == GALE_E_RANGE);
        CHECK(strcmp(e1.msg, e2.msg) == 0);
        CHECK(strstr(e2.msg, bad[k].named) != NULL);
        /* the three frames in one pass name it as the keyframe or a delta would */
        gale_err e3;
        static uint8_t third[1 << 22];
        wire_frame_out out[3] = { { one, sizeof one, 0, &e3 }, { many, sizeof many, 0, NULL },
                                  { third, sizeof third, 0, NULL } };
        const wire_state cur = state_of(&hist[0]), prev = state_of(&hist[1]),
                         prev2 = state_of(&hist[2]);
        const wire_header h = { .tick = 77, .server_time_us = 123456789ull };
        CHECK(wire_encode_snapshot_lanes(&h, 9, &sc, &cur, &prev, &prev2, &l, out) ==
              GALE_E_RANGE);
        CHECK(strstr(e3.msg, bad[k].named) != NULL);
        CHECK(strstr(e3.msg, bad[k].state ? "wire_encode_delta" : "wire_encode_keyframe") != NULL);
        /* and in stages, the lanes in two turns */
        gale_err e4;
        out[0].err = &e4;
        wire_snapshot_job job;
        wire_snapshot_begin(&job, &h, 9, &sc, &cur, &prev, &prev2, &l, out);
        wire_snapshot_run(&job, 2, wire_snapshot_lanes(&job));
        wire_snapshot_run(&job, 0, 2);
        CHECK(wire_snapshot_finish(&job) == GALE_E_RANGE);
        CHECK(strcmp(e3.msg, e4.msg) == 0);
        if (!strstr(e2.msg, bad[k].named)) {
            fprintf(stderr, "case %zu: %s\n", k, e2.msg);
        }
    }
}

/* Every frame's values are the reference coder's bytes, with and without lanes, alone and
 * in the one-pass snapshot, for trees whose values lie in, on the edges of and past the
 * fast coder's 16-bit range; every width 0..16 is coded. */
static void test_values_reference(void)
{
    const wire_scene sc = three_species();
    memset(widths_seen, 0, sizeof widths_seen);
    static uint8_t ref[1 << 22], fused[3][1 << 22];
    make_edge_snap(&sc, &hist[2], NULL);
    make_edge_snap(&sc, &hist[1], &hist[2]);
    for (int round = 0; round < 8; round++) {
        make_edge_snap(&sc, &hist[0], &hist[1]);
        if (round % 2) {
            memcpy(hist[0].n_modes, hist[1].n_modes, NT);
        }
        const wire_lanes l = { 3, run_threads, NULL };
        const wire_header h = { .tick = 77, .server_time_us = 123456789ull };
        const wire_state cur = state_of(&hist[0]), prev = state_of(&hist[1]),
                         prev2 = state_of(&hist[2]);
        wire_frame_out out[3];
        gale_err err;
        for (int f = 0; f < 3; f++) {
            out[f] = (wire_frame_out){ fused[f], sizeof fused[f], 0, &err };
        }
        CHECK(wire_encode_snapshot_lanes(&h, 9, &sc, &cur, &prev, &prev2, &l, out) == 0);
        for (int kind = 0; kind < 3; kind++) {
            const size_t n_ref = ref_values(&hist[0], kind ? &hist[1] : NULL,
                                            kind == 2 ? &hist[2] : NULL, kind + 1, ref);
            for (int li = 0; li < 2; li++) {
                size_t len = 0;
                CHECK(encode(kind, &sc, li ? &l : NULL, one, sizeof one, &len, &err) == 0);
                CHECK(len > n_ref && memcmp(one + len - n_ref, ref, n_ref) == 0);
            }
            CHECK(out[kind].len > n_ref &&
                  memcmp(fused[kind] + out[kind].len - n_ref, ref, n_ref) == 0);
            note_widths(ref, ref + n_ref, &hist[0]);
        }
        hist[2] = hist[1];
        hist[1] = hist[0];
    }
    for (int w = 0; w <= WIDEST; w++) {
        if (!widths_seen[w]) {
            fprintf(stderr, "width %d never coded\n", w);
        }
        CHECK(widths_seen[w] > 0);
    }
}

int main(void)
{
    RUN(test_lanes_same_bytes);
    /* each path of the encoder (msg_state_rows.c rows_groups): 16-bit lanes four and two
       groups a register, and the 32-bit pairs alone */
    static const char *const rows[] = { "4", "2", "0" };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        CHECK(setenv("GALE_WIRE_ROWS", rows[i], 1) == 0);
        fprintf(stderr, "GALE_WIRE_ROWS=%s\n", rows[i]);
        RUN(test_values_reference);
        RUN(test_lanes_bad_state);
    }
    unsetenv("GALE_WIRE_ROWS");
    return check_report();
}
