/* Tests of the binary wire (protocol/wire.h): little-endian cursor, golden bytes of every
 * message type, round trips, every truncation rejected, exact error texts, quantisation
 * clamps, the step bound, and delta chains that decode to the same state as keyframes. */
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "wire.h"

static uint8_t buf[1 << 20];
static uint8_t buf2[1 << 20];

static void test_cursor(void)
{
    uint8_t b[16];
    wire_writer w = wire_writer_make(b, sizeof b);
    wire_put_u32(&w, WIRE_MAGIC);
    wire_put_u16(&w, 0xBEEF);
    wire_put_f32(&w, 1.0f);
    CHECK(!w.bad);
    CHECK(memcmp(b, "GALE", 4) == 0);
    CHECK(b[4] == 0xEF && b[5] == 0xBE);
    CHECK(b[6] == 0x00 && b[7] == 0x00 && b[8] == 0x80 && b[9] == 0x3F);
    wire_reader r = wire_reader_make(b, 10);
    CHECK(wire_get_u32(&r) == WIRE_MAGIC);
    CHECK(wire_get_u16(&r) == 0xBEEF);
    CHECK(wire_get_f32(&r) == 1.0f);
    CHECK(!r.bad);
    /* A short read sets bad, returns 0, and stays bad. */
    CHECK(wire_get_u8(&r) == 0);
    CHECK(r.bad);
    r = wire_reader_make(b, 3);
    CHECK(wire_get_u32(&r) == 0 && r.bad);
    CHECK(wire_get_u8(&r) == 0 && r.bad);
    /* Writer overflow sets bad and writes nothing. */
    w = wire_writer_make(b, 3);
    wire_put_u32(&w, 0xffffffffu);
    CHECK(w.bad && w.p == b);
    w = wire_writer_make(b, 7);
    wire_put_u64(&w, 1);
    CHECK(w.bad && w.p == b);
    /* An empty buffer may come as NULL (a zero-length frame nothing was read into). */
    r = wire_reader_make(NULL, 0);
    CHECK(wire_get_u8(&r) == 0 && r.bad);
    w = wire_writer_make(NULL, 0);
    wire_put_u8(&w, 1);
    CHECK(w.bad && w.p == NULL);
}

static void test_varint(void)
{
    const uint32_t vals[] = { 0, 1, 127, 128, 300, 16383, 16384, 0x0fffffffu, 0xffffffffu };
    for (size_t i = 0; i < sizeof vals / sizeof vals[0]; i++) {
        uint8_t b[8];
        wire_writer w = wire_writer_make(b, sizeof b);
        wire_put_varint(&w, vals[i]);
        wire_reader r = wire_reader_make(b, (size_t)(w.p - b));
        CHECK(wire_get_varint(&r) == vals[i]);
        CHECK(!r.bad && r.p == r.end);
    }
    uint8_t b300[] = { 0xAC, 0x02 };
    wire_reader r = wire_reader_make(b300, 2);
    CHECK(wire_get_varint(&r) == 300 && !r.bad);
    /* Overlong (trailing zero group), more than 32 bits, unterminated. */
    uint8_t over[] = { 0x80, 0x00 };
    r = wire_reader_make(over, 2);
    wire_get_varint(&r);
    CHECK(r.bad);
    uint8_t big[] = { 0xff, 0xff, 0xff, 0xff, 0x1f };
    r = wire_reader_make(big, 5);
    wire_get_varint(&r);
    CHECK(r.bad);
    uint8_t open[] = { 0x80, 0x80 };
    r = wire_reader_make(open, 2);
    wire_get_varint(&r);
    CHECK(r.bad);
    CHECK(wire_zigzag(0) == 0 && wire_zigzag(-1) == 1 && wire_zigzag(1) == 2);
    CHECK(wire_zigzag(-65536) == 131071 && wire_unzigzag(131071) == -65536);
    CHECK(wire_unzigzag(wire_zigzag(INT32_MIN)) == INT32_MIN);
}

static void test_quantize(void)
{
    CHECK(wire_quantize(0.0f, 1.0f) == 0);
    CHECK(wire_quantize(0.5f, 1.0f) == 1);
    CHECK(wire_quantize(-0.5f, 1.0f) == -1);
    CHECK(wire_quantize(2.49f, 1.0f) == 2);
    CHECK(wire_quantize(-2.51f, 1.0f) == -3);
    CHECK(wire_quantize(0.3f, 10.0f) == 3);
    CHECK(wire_quantize(NAN, 1.0f) == 0);
    CHECK(wire_quantize(-NAN, 1.0f) == 0);
    CHECK(wire_quantize(1e30f, 1.0f) == WIRE_QMAX);
    CHECK(wire_quantize(-1e30f, 1.0f) == -WIRE_QMAX);
    CHECK(wire_quantize(INFINITY, 1.0f) == WIRE_QMAX);
    CHECK(wire_quantize(-INFINITY, 1.0f) == -WIRE_QMAX);
    CHECK(wire_quantize(1.0f, INFINITY) == WIRE_QMAX);
    CHECK(wire_quantize(32767.4f, 1.0f) == 32767);
    CHECK(wire_quantize(40000.0f, 1.0f) == 32767);
    CHECK_NEAR(wire_dequantize(-3, 0.25f), -0.75, 0);
    CHECK(wire_wind_quantize(NAN, 1.0f) == 0);
    CHECK(wire_wind_quantize(1e30f, 0.5f) == 127);
    CHECK(wire_wind_quantize(-1e30f, 0.5f) == -127);
    CHECK(wire_wind_quantize(10.0f, 0.5f) == 20);
    CHECK(wire_wind_quantize(-10.2f, 0.5f) == -20);
}

static void test_header_golden(void)
{
    wire_header h = { .type = WIRE_MSG_LEAVES, .tick = 0x01020304u,
                      .server_time_us = 0x1122334455667788ull };
    wire_leaf lf = { .instance = 5, .slot = 0x0102, .spawn_tick = 0x01020304u, .seed = 0xdeadbeefu };
    size_t n = 0;
    gale_err e;
    CHECK(wire_encode_leaves(&h, &lf, 1, buf, sizeof buf, &n, &e) == 0);
    const uint8_t gold[] = {
        'G', 'A', 'L', 'E', 0x01, 0x00, 0x03, 0x00,                   /* magic version type flags */
        0x04, 0x03, 0x02, 0x01,                                       /* tick */
        0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11,               /* server time */
        0x01, 0x00,                                                   /* count */
        0x05, 0x00, 0x00, 0x00, 0x02, 0x01, 0x04, 0x03, 0x02, 0x01,   /* instance slot spawn */
        0xef, 0xbe, 0xad, 0xde,                                       /* seed */
    };
    CHECK(n == sizeof gold);
    CHECK(memcmp(buf, gold, sizeof gold) == 0);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 8, .max_modes = 8 }, &e);
    wire_frame f;
    CHECK(wire_decode(d, gold, sizeof gold, &f, &e) == 0);
    CHECK(f.hdr.type == WIRE_MSG_LEAVES && f.hdr.tick == 0x01020304u);
    CHECK(f.hdr.server_time_us == 0x1122334455667788ull);
    CHECK(f.n_leaves == 1 && f.leaves[0].instance == 5 && f.leaves[0].slot == 0x0102 &&
          f.leaves[0].spawn_tick == 0x01020304u && f.leaves[0].seed == 0xdeadbeefu);
    /* Every truncation is rejected. */
    for (size_t k = 0; k < sizeof gold; k++) {
        CHECK(wire_decode(d, gold, k, &f, &e) == GALE_E_FORMAT);
    }
    CHECK(wire_decode(d, gold, 0, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: header: truncated: expected 20 bytes, got 0");
    CHECK(wire_decode(d, gold, 21, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: LEAVES tick 16909060: count at byte 20: truncated");
    CHECK(wire_decode(d, gold, 30, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: LEAVES tick 16909060: length: expected 36 bytes for 1 leaves, got 30");
    uint8_t bad[sizeof gold];
    memcpy(bad, gold, sizeof gold);
    bad[0] = 'X';
    CHECK(wire_decode(d, bad, sizeof bad, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: header: bad magic: expected 0x454c4147 (\"GALE\"), got 0x454c4158");
    memcpy(bad, gold, sizeof gold);
    bad[4] = 2;
    CHECK(wire_decode(d, bad, sizeof bad, &f, &e) == GALE_E_VERSION);
    CHECK_STR_HAS(e.msg, "wire: header: protocol version: expected 1, got 2");
    memcpy(bad, gold, sizeof gold);
    bad[6] = 9;
    CHECK(wire_decode(d, bad, sizeof bad, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: header: message type: expected 1..8, got 9");
    memcpy(bad, gold, sizeof gold);
    bad[7] = 1;
    CHECK(wire_decode(d, bad, sizeof bad, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: header: flags: expected 0, got 0x01");
    memcpy(bad, gold, sizeof gold);
    bad[20] = 0xff;
    bad[21] = 0xff;
    CHECK(wire_decode(d, bad, sizeof bad, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "count at byte 20: expected <= 4096, got 65535");
    /* Trailing byte. */
    uint8_t longer[sizeof gold + 1];
    memcpy(longer, gold, sizeof gold);
    longer[sizeof gold] = 0;
    CHECK(wire_decode(d, longer, sizeof longer, &f, &e) == GALE_E_FORMAT);
    wire_leaf many[WIRE_MAX_LEAVES + 1];
    memset(many, 0, sizeof many);
    CHECK(wire_encode_leaves(&h, many, WIRE_MAX_LEAVES + 1, buf, sizeof buf, &n, &e) == GALE_E_RANGE);
    CHECK(wire_encode_leaves(&h, many, 3, buf, 40, &n, &e) == GALE_E_RANGE);
    wire_decoder_destroy(d);
}

static void test_wind_golden(void)
{
    const int8_t cells[2 * 1 * 3] = { 1, -2, 3, -128 + 1, 127, 0 };
    wire_wind w = { .x0_m = 1.0f, .y0_m = -2.0f, .z_m = 10.0f, .cell_m = 4.0f,
                    .scale_ms = 0.5f, .nx = 2, .ny = 1, .v = cells };
    wire_header h = { .tick = 2, .server_time_us = 3 };
    size_t n = 0;
    gale_err e;
    CHECK(wire_encode_wind(&h, &w, buf, sizeof buf, &n, &e) == 0);
    const uint8_t gold[] = {
        'G', 'A', 'L', 'E', 0x01, 0x00, 0x04, 0x00, 0x02, 0, 0, 0, 0x03, 0, 0, 0, 0, 0, 0, 0,
        0x00, 0x00, 0x80, 0x3f, /* x0 1.0 */
        0x00, 0x00, 0x00, 0xc0, /* y0 -2.0 */
        0x00, 0x00, 0x20, 0x41, /* z 10.0 */
        0x00, 0x00, 0x80, 0x40, /* cell 4.0 */
        0x00, 0x00, 0x00, 0x3f, /* scale 0.5 */
        0x02, 0x00, 0x01, 0x00, /* nx ny */
        0x01, 0xfe, 0x03, 0x81, 0x7f, 0x00,
    };
    CHECK(n == sizeof gold);
    CHECK(memcmp(buf, gold, sizeof gold) == 0);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 4, .max_modes = 4 }, &e);
    wire_frame f;
    CHECK(wire_decode(d, gold, sizeof gold, &f, &e) == 0);
    CHECK(f.wind.nx == 2 && f.wind.ny == 1 && f.wind.scale_ms == 0.5f && f.wind.z_m == 10.0f);
    CHECK(memcmp(f.wind.v, cells, sizeof cells) == 0);
    for (size_t k = 0; k < sizeof gold; k++) {
        CHECK(wire_decode(d, gold, k, &f, &e) == GALE_E_FORMAT);
    }
    uint8_t bad[sizeof gold];
    memcpy(bad, gold, sizeof gold);
    bad[38] = 0xc0; /* scale_ms becomes 0x7fc00000, a NaN */
    bad[39] = 0x7f;
    CHECK(wire_decode(d, bad, sizeof bad, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: WIND tick 2: geometry at byte 20: expected finite origin, cell_m > 0, scale_ms > 0, got cell_m 4, scale_ms nan");
    memcpy(bad, gold, sizeof gold);
    bad[40] = 0;
    CHECK(wire_decode(d, bad, sizeof bad, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: WIND tick 2: size at byte 40: expected 1..256 per side, got 0x1");
    w.nx = 300;
    CHECK(wire_encode_wind(&h, &w, buf, sizeof buf, &n, &e) == GALE_E_RANGE);
    wire_decoder_destroy(d);
}

/* The two-tree scene of the golden state frames. */
static uint8_t g_species[2] = { 0, 0 };
static wire_scene golden_scene(void)
{
    wire_scene sc = { .n_trees = 2, .n_species = 1, .species = g_species };
    sc.n_modes[0] = 3;
    sc.step[0][0] = 0.5f;
    sc.step[0][1] = 0.25f;
    sc.step[0][2] = 1.0f;
    return sc;
}

static void test_state_golden(void)
{
    wire_scene sc = golden_scene();
    uint8_t nm[2] = { 3, 3 };
    int16_t q1[6] = { 3, -1, 0, 0, 0, 0 };
    int16_t q2[6] = { 4, -1, 0, 0, 0, 0 };
    wire_state s1 = { .n_trees = 2, .stride = 3, .n_modes = nm, .q = q1 };
    wire_state s2 = { .n_trees = 2, .stride = 3, .n_modes = nm, .q = q2 };
    wire_header h = { .tick = 7, .server_time_us = 1000 };
    size_t n = 0;
    gale_err e;
    CHECK(wire_encode_keyframe(&h, 1, &sc, &s1, buf, sizeof buf, &n, &e) == 0);
    const uint8_t key[] = {
        'G', 'A', 'L', 'E', 0x01, 0x00, 0x01, 0x00, 0x07, 0, 0, 0, 0xe8, 0x03, 0, 0, 0, 0, 0, 0,
        0x01, 0x00, 0x00, 0x00, /* seq 1 */
        0x02, 0x00, 0x00, 0x00, /* n_trees 2 */
        0x01,                   /* n_species */
        0x03, 0x00, 0x00, 0x00, 0x3f, 0x00, 0x00, 0x80, 0x3e, 0x00, 0x00, 0x80, 0x3f,
        0x00, 0x00,             /* species of each tree */
        0x01, 0x01, 0x00, 0x02, /* runs: 1 run, gap 0, length 2 */
        0x00,                   /* modes: full */
        0x03, 0x0e, 0x00,       /* tree 0: zero predictor, width 3: 6 1 0 */
        0x00,                   /* tree 1: all zero */
    };
    CHECK(n == sizeof key);
    CHECK(memcmp(buf, key, sizeof key) == 0);
    size_t nk = n;
    CHECK(wire_encode_delta(&h, 2, &sc, &s2, &s1, NULL, buf2, sizeof buf2, &n, &e) == 0);
    const uint8_t delta[] = {
        'G', 'A', 'L', 'E', 0x01, 0x00, 0x02, 0x00, 0x07, 0, 0, 0, 0xe8, 0x03, 0, 0, 0, 0, 0, 0,
        0x02, 0x00, 0x00, 0x00, /* seq 2 */
        0x01,                   /* history: 1 snapshot */
        0x00,                   /* tree set: same */
        0x22, 0x02,             /* tree 0: previous predictor, width 2: residuals 1 0 0 */
        0x00,
    };
    CHECK(n == sizeof delta);
    CHECK(memcmp(buf2, delta, sizeof delta) == 0);

    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 4, .max_modes = 4 }, &e);
    wire_frame f;
    /* A delta before any keyframe waits. */
    CHECK(wire_decode(d, delta, sizeof delta, &f, &e) == GALE_E_STATE);
    CHECK_STR_HAS(e.msg, "wire: DELTA tick 7: seq 2: no keyframe yet: waiting for a keyframe");
    for (size_t k = 0; k < nk; k++) {
        CHECK(wire_decode(d, key, k, &f, &e) != 0);
        CHECK(!wire_decoder_synced(d));
    }
    CHECK(wire_decode(d, key, nk, &f, &e) == 0);
    CHECK(f.seq == 1 && wire_decoder_seq(d) == 1 && wire_decoder_synced(d));
    float q[4];
    CHECK(wire_decoder_q(d, 0, q, 4) == 3);
    CHECK(q[0] == 1.5f && q[1] == -0.25f && q[2] == 0.0f && q[3] == 0.0f);
    CHECK(wire_decoder_q(d, 5, q, 4) == 0);
    for (size_t k = 0; k < sizeof delta; k++) {
        CHECK(wire_decode(d, delta, k, &f, &e) == GALE_E_FORMAT);
        CHECK(wire_decoder_seq(d) == 1);
    }
    CHECK(wire_decode(d, delta, sizeof delta, &f, &e) == 0);
    CHECK(wire_decoder_seq(d) == 2);
    CHECK(wire_decoder_q(d, 0, q, 4) == 3);
    CHECK(q[0] == 2.0f && q[1] == -0.25f);
    /* The same delta again is a gap (it needs seq 1 as base). */
    CHECK(wire_decode(d, delta, sizeof delta, &f, &e) == GALE_E_STATE);
    CHECK_STR_HAS(e.msg, "wire: DELTA tick 7: seq 2: gap: expected seq 3 (holding 2): waiting for a keyframe");

    /* Exact texts of corrupt state frames. */
    uint8_t bad[64];
    CHECK(wire_decode(d, key, nk, &f, &e) == 0);
    memcpy(bad, delta, sizeof delta);
    bad[24] = 2;
    CHECK(wire_decode(d, bad, sizeof delta, &f, &e) == GALE_E_STATE);
    CHECK_STR_HAS(e.msg, "wire: DELTA tick 7: seq 2: predicts from seq 0 which this decoder does not hold");
    bad[24] = 3;
    CHECK(wire_decode(d, bad, sizeof delta, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: DELTA tick 7: history at byte 24: expected 1 or 2, got 3");
    memcpy(bad, delta, sizeof delta);
    bad[26] = 0x42; /* linear predictor with history 1 */
    CHECK(wire_decode(d, bad, sizeof delta, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: DELTA tick 7: tree 0 group 0 at byte 26: expected width <= 18 and predictor <= 1, got 2, 2");
    memcpy(bad, delta, sizeof delta);
    bad[27] = 0x42; /* padding bits set */
    CHECK(wire_decode(d, bad, sizeof delta, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: DELTA tick 7: tree 0 group 0 at byte 26: truncated or nonzero padding");
    memcpy(bad, delta, sizeof delta);
    bad[sizeof delta] = 0;
    CHECK(wire_decode(d, bad, sizeof delta + 1, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: DELTA tick 7: length: expected 29 bytes, got 30 (trailing bytes)");
    CHECK(wire_decoder_seq(d) == 1);
    memcpy(bad, key, nk);
    bad[42] = 1; /* species of tree 0 = 1 of 1 species */
    CHECK(wire_decode(d, bad, nk, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: KEYFRAME tick 7: species of tree 0 at byte 42: expected < 1, got 1");
    memcpy(bad, key, nk);
    bad[47] = 0; /* run length 0 */
    CHECK(wire_decode(d, bad, nk, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: KEYFRAME tick 7: run 0 at byte 46: expected gap >= 0 and length >= 1, got 0, 0");
    memcpy(bad, key, nk);
    bad[47] = 3; /* run past the last tree */
    CHECK(wire_decode(d, bad, nk, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: KEYFRAME tick 7: run 0 at byte 46: expected to end <= 2 trees, got 0 + 0 + 3");
    memcpy(bad, key, nk);
    bad[44] = 0; /* tree set SAME in a keyframe */
    CHECK(wire_decode(d, bad, nk, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: KEYFRAME tick 7: tree set kind at byte 44: expected 1 (runs), got 0");
    memcpy(bad, key, nk);
    bad[32] = 0xc0; /* step 0 becomes 0x7fc00000, a NaN */
    bad[33] = 0x7f;
    CHECK(wire_decode(d, bad, nk, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: KEYFRAME tick 7: species 0 step 0 at byte 30: expected in (0, 1e+30], got nan");
    memcpy(bad, key, nk);
    memcpy(bad + 30, "\x7c\x6f\xfc\x72", 4); /* step 0 = 1e31: 32767 steps would overflow */
    CHECK(wire_decode(d, bad, nk, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "wire: KEYFRAME tick 7: species 0 step 0 at byte 30: expected in (0, 1e+30], got 1e+31");
    CHECK(wire_decoder_seq(d) == 1);

    /* A decoder too small for the scene says so. */
    wire_decoder *small = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 1, .max_modes = 4 }, &e);
    CHECK(wire_decode(small, key, nk, &f, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "n_trees: expected <= 1 (decoder capacity), got 2");
    wire_decoder_destroy(small);
    /* Encoder refuses a too small buffer and q = -32768. */
    CHECK(wire_encode_keyframe(&h, 1, &sc, &s1, buf, nk - 1, &n, &e) == GALE_E_RANGE);
    q1[1] = INT16_MIN;
    CHECK(wire_encode_keyframe(&h, 1, &sc, &s1, buf, sizeof buf, &n, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "wire_encode_keyframe: cur.q[0][1]: expected >= -32767, got -32768");
    wire_decoder_destroy(d);
}

/* ---- randomised chains ------------------------------------------------------------ */

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static uint32_t rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (uint32_t)(rng >> 16);
}

#define NT 300
#define NM 40

typedef struct snap {
    uint8_t n_modes[NT];
    int16_t q[NT * NM];
} snap;

static bool same_as_decoder(const wire_decoder *d, const snap *s)
{
    wire_state st = wire_decoder_state(d);
    for (uint32_t t = 0; t < NT; t++) {
        if (st.n_modes[t] != s->n_modes[t]) {
            return false;
        }
        for (uint32_t m = 0; m < st.stride; m++) {
            int16_t want = m < s->n_modes[t] ? s->q[t * NM + m] : 0;
            if (st.q[(size_t)t * st.stride + m] != want) {
                return false;
            }
        }
    }
    return true;
}

/* A chain of deltas with smooth motion, noise, big jumps, view and LOD changes decodes
 * to exactly what a keyframe of the same snapshot decodes to; every truncation and
 * every single-byte corruption of a delta leaves the decoder unchanged or errs. */
static void test_chain(void)
{
    static uint8_t species[NT];
    wire_scene sc = { .n_trees = NT, .n_species = 3, .species = species };
    sc.n_modes[0] = 40;
    sc.n_modes[1] = 17;
    sc.n_modes[2] = 1;
    for (uint32_t s = 0; s < 3; s++) {
        for (uint32_t m = 0; m < 40; m++) {
            sc.step[s][m] = 0.001f * (float)(m + 1 + s);
        }
    }
    for (uint32_t t = 0; t < NT; t++) {
        species[t] = (uint8_t)(rnd() % 3);
    }
    static snap hist[3];
    gale_err e;
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = NT, .max_modes = NM }, &e);
    wire_decoder *k = wire_decoder_create(&(wire_decoder_desc){ .max_trees = NT, .max_modes = NM }, &e);
    CHECK(d && k);
    bool all_ok = true, all_same = true, trunc_ok = true;
    size_t bytes_delta = 0;
    for (uint32_t seq = 1; seq <= 120; seq++) {
        snap *cur = &hist[seq % 3], *prev = &hist[(seq + 2) % 3], *prev2 = &hist[(seq + 1) % 3];
        for (uint32_t t = 0; t < NT; t++) {
            uint32_t full = sc.n_modes[species[t]];
            uint32_t n = full;
            uint32_t phase = (seq / 20) % 3;
            if (phase == 1 && t % 7 == 0) {
                n = 0; /* out of view */
            } else if (phase == 2 && t % 5 == 0) {
                n = 1 + (t + seq / 20) % full; /* LOD */
            }
            cur->n_modes[t] = (uint8_t)n;
            for (uint32_t m = 0; m < NM; m++) {
                double a = 3000.0 / (m + 1) * sin(0.05 * seq * (m + 1) + t);
                int32_t v = (int32_t)a + (int32_t)(rnd() % 5) - 2;
                if (rnd() % 97 == 0) {
                    v = (int32_t)(rnd() % 65535) - 32767; /* jump */
                }
                cur->q[t * NM + m] = (int16_t)v;
            }
        }
        wire_state sc_cur = { NT, NM, cur->n_modes, cur->q };
        wire_state sc_prev = { NT, NM, prev->n_modes, prev->q };
        wire_state sc_prev2 = { NT, NM, prev2->n_modes, prev2->q };
        wire_header h = { .tick = seq * 2, .server_time_us = seq * 33333ull };
        size_t nk = 0, nd = 0;
        all_ok &= wire_encode_keyframe(&h, seq, &sc, &sc_cur, buf, sizeof buf, &nk, &e) == 0;
        all_ok &= wire_decode(k, buf, nk, &(wire_frame){ 0 }, &e) == 0;
        if (seq == 1 || seq == 60) {
            /* (Re)start the chain from a keyframe. */
            all_ok &= wire_decode(d, buf, nk, &(wire_frame){ 0 }, &e) == 0;
        } else {
            all_ok &= wire_encode_delta(&h, seq, &sc, &sc_cur, &sc_prev,
                                        (seq == 2 || seq == 61) ? NULL : &sc_prev2, buf2, sizeof buf2, &nd,
                                        &e) == 0;
            bytes_delta += nd;
            if (seq % 10 == 0) {
                for (size_t cut = 0; cut < nd; cut += 1 + nd / 50) {
                    trunc_ok &= wire_decode(d, buf2, cut, &(wire_frame){ 0 }, &e) != 0;
                    trunc_ok &= wire_decoder_seq(d) == seq - 1;
                }
            }
            wire_frame f;
            int rc = wire_decode(d, buf2, nd, &f, &e);
            if (rc) {
                fprintf(stderr, "seq %u: %s\n", seq, e.msg);
            }
            all_ok &= rc == 0;
        }
        all_same &= same_as_decoder(d, cur) && same_as_decoder(k, cur);
    }
    CHECK(all_ok);
    CHECK(all_same);
    CHECK(trunc_ok);
    CHECK(bytes_delta > 0);
    wire_decoder_destroy(d);
    wire_decoder_destroy(k);
}

/* A value out of range in a full group of 8 modes is rejected with its tree and mode, both
 * where the group is read with whole-word loads (bytes enough after it) and where it is read
 * byte by byte (the frame's last group). */
static void test_full_group_range(void)
{
    static uint8_t species[2] = { 0, 0 };
    wire_scene sc = { .n_trees = 2, .n_species = 1, .species = species };
    sc.n_modes[0] = 8;
    for (uint32_t m = 0; m < 8; m++) {
        sc.step[0][m] = 1.0f;
    }
    uint8_t nm[2] = { 8, 8 };
    int16_t q[16] = { -32767, 1, 2, 3, 4, 5, 6, 7, 1, 2, 3, 4, 5, 6, 7, -32767 };
    wire_state st = { .n_trees = 2, .stride = 8, .n_modes = nm, .q = q };
    wire_header h = { .tick = 9 };
    size_t n = 0;
    gale_err e;
    CHECK(wire_encode_keyframe(&h, 1, &sc, &st, buf, sizeof buf, &n, &e) == 0);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 2, .max_modes = 8 }, &e);
    CHECK(d != NULL);
    CHECK(wire_decode(d, buf, n, &(wire_frame){ 0 }, &e) == 0);
    /* each group: header 0x10 (zero predictor, width 16), then 16 bytes; -32767 is zigzag
     * 0xfffd, and 0xffff would be -32768 */
    size_t g0 = n - 34, g1 = n - 17;
    CHECK(buf[g0] == 0x10 && buf[g0 + 1] == 0xfd && buf[g0 + 2] == 0xff);
    CHECK(buf[g1] == 0x10 && buf[n - 2] == 0xfd && buf[n - 1] == 0xff);
    memcpy(buf2, buf, n);
    buf2[g0 + 1] = 0xff;
    CHECK(wire_decode(d, buf2, n, &(wire_frame){ 0 }, &e) == GALE_E_FORMAT);
    char want[160];
    snprintf(want, sizeof want, "wire: KEYFRAME tick 9: tree 0 mode 0 at byte %zu: expected |q| <= 32767, got -32768", g0);
    CHECK_STR_HAS(e.msg, want);
    memcpy(buf2, buf, n);
    buf2[n - 2] = 0xff;
    CHECK(wire_decode(d, buf2, n, &(wire_frame){ 0 }, &e) == GALE_E_FORMAT);
    snprintf(want, sizeof want, "wire: KEYFRAME tick 9: tree 1 mode 7 at byte %zu: expected |q| <= 32767, got -32768", g1);
    CHECK_STR_HAS(e.msg, want);
    float v[8];
    CHECK(wire_decoder_q(d, 0, v, 8) == 8 && v[0] == -32767.0f && v[7] == 7.0f);
    wire_decoder_destroy(d);
}

/* Random bytes and bit flips never crash the decoder and never leave it half-updated. */
static void test_corruption(void)
{
    wire_scene sc = golden_scene();
    uint8_t nm[2] = { 3, 2 };
    int16_t q1[6] = { 300, -100, 7, -5, 1, 0 };
    wire_state s1 = { .n_trees = 2, .stride = 3, .n_modes = nm, .q = q1 };
    wire_header h = { .tick = 1 };
    size_t n = 0;
    gale_err e;
    CHECK(wire_encode_keyframe(&h, 5, &sc, &s1, buf, sizeof buf, &n, &e) == 0);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 4, .max_modes = 4 }, &e);
    int accepted = 0;
    for (size_t i = WIRE_HEADER_BYTES; i < n; i++) {
        for (int bit = 0; bit < 8; bit++) {
            memcpy(buf2, buf, n);
            buf2[i] ^= (uint8_t)(1u << bit);
            wire_frame f;
            if (wire_decode(d, buf2, n, &f, &e) == 0) {
                accepted++;
            }
        }
    }
    CHECK(accepted > 0); /* value bits flip to other valid values */
    wire_frame empty;
    CHECK(wire_decode(d, NULL, 0, &empty, &e) != 0); /* a zero-length frame, as NULL */
    CHECK(wire_decode(d, buf, n, &(wire_frame){ 0 }, &e) == 0);
    float q[4];
    CHECK(wire_decoder_q(d, 1, q, 4) == 2);
    CHECK(q[0] == -2.5f && q[1] == 0.25f && q[2] == 0.0f);
    wire_decoder_destroy(d);
}

/* The step bound (0, 1e30] is the f32 interval: the float nearest 1e30 (bits 0x7149f2ca)
 * is in, the next float up is out; the smallest subnormal is in, +0, -0 and NaN are out.
 * PROTOCOL.md "KEYFRAME"; the test vectors are tests/test_spec_vectors.c's. */
static void test_step_bound(void)
{
    static const uint8_t species[1] = { 0 };
    wire_scene sc = { .n_trees = 1, .n_species = 1, .species = species };
    sc.n_modes[0] = 1;
    sc.step[0][0] = WIRE_MAX_STEP;
    uint8_t nm[1] = { 1 };
    int16_t q[1] = { 32767 };
    wire_state st = { 1, 1, nm, q };
    size_t len = 0;
    gale_err e;
    CHECK(wire_encode_keyframe(&(wire_header){ 0 }, 1, &sc, &st, buf, sizeof buf, &len, &e) == 0);
    /* header 20, seq 4, n_trees 4, n_species 1, n_modes 1: the step at byte 30 */
    CHECK(len > 34 && buf[30] == 0xca && buf[31] == 0xf2 && buf[32] == 0x49 && buf[33] == 0x71);
    static const struct {
        uint8_t b[4];
        bool ok;
    } steps[] = {
        { { 0xca, 0xf2, 0x49, 0x71 }, true },  /* 1e30f */
        { { 0xcb, 0xf2, 0x49, 0x71 }, false }, /* the next float */
        { { 0x01, 0x00, 0x00, 0x00 }, true },  /* the smallest subnormal */
        { { 0x00, 0x00, 0x00, 0x00 }, false },
        { { 0x00, 0x00, 0x00, 0x80 }, false }, /* -0 */
        { { 0x00, 0x00, 0xc0, 0x7f }, false }, /* NaN */
    };
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++) {
        memcpy(buf + 30, steps[i].b, 4);
        wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ 4, 4 }, NULL);
        wire_frame f;
        int rc = wire_decode(d, buf, len, &f, &e);
        CHECK((rc == 0) == steps[i].ok);
        if (!steps[i].ok) {
            CHECK_STR_HAS(e.msg, "species 0 step 0 at byte 30: expected in (0, 1e+30]");
        }
        wire_decoder_destroy(d);
    }
    sc.step[0][0] = nextafterf(WIRE_MAX_STEP, INFINITY);
    CHECK(wire_encode_keyframe(&(wire_header){ 0 }, 1, &sc, &st, buf, sizeof buf, &len, &e) ==
          GALE_E_RANGE);
}

int main(void)
{
    RUN(test_cursor);
    RUN(test_varint);
    RUN(test_quantize);
    RUN(test_header_golden);
    RUN(test_wind_golden);
    RUN(test_state_golden);
    RUN(test_chain);
    RUN(test_full_group_range);
    RUN(test_step_bound);
    RUN(test_corruption);
    return check_report();
}
