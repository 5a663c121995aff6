/* Tests of BUNDLE frames (PROTOCOL.md "BUNDLE"), on the spec's own vectors (read from
 * PROTOCOL.md): a bundle decoding to the same values as its frames sent apart, and every malformed container
 * (count, lengths, nesting, repeated types, trailing bytes, a bad inner frame) rejected
 * with the decoder's state unchanged. */
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "spec_vectors.h"
#include "wire.h"

static uint8_t buf[4096];

static uint8_t key[128], delta[64], leaves[64], bundle[256];
static size_t nk, nd, nl, nb;

/* PROTOCOL.md's vector name into out (tests/test_spec_vectors.c checks its bytes and
 * values); its length, 0 when the spec lacks it. */
static size_t spec_bytes(const spec_file *f, const char *name, uint8_t *out, size_t cap)
{
    const spec_vector *v = spec_find(f, name);
    if (!v || v->len > cap) {
        fprintf(stderr, "test_wire_bundle: %s: no vector %s of <= %zu bytes\n",
                SPEC_PROTOCOL_PATH, name, cap);
        return 0;
    }
    memcpy(out, v->bytes, v->len);
    return v->len;
}

static wire_decoder *keyed(void)
{
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ 8, 8 }, NULL);
    wire_frame f;
    CHECK(d && wire_decode(d, key, nk, &f, NULL) == 0 && f.types == 1u << WIRE_MSG_KEYFRAME);
    return d;
}

/* Sent apart or bundled, a client ends with the same state and the same leaves. */
static void test_same_as_apart(void)
{
    wire_decoder *a = keyed(), *b = keyed();
    wire_frame fa, fb;
    CHECK(wire_decode(a, delta, nd, &fa, NULL) == 0);
    CHECK(wire_decode(a, leaves, nl, &fa, NULL) == 0);
    CHECK(wire_decode(b, bundle, nb, &fb, NULL) == 0);
    wire_state sa = wire_decoder_state(a), sb = wire_decoder_state(b);
    CHECK(sa.n_trees == sb.n_trees && wire_decoder_seq(a) == wire_decoder_seq(b));
    CHECK(memcmp(sa.q, sb.q, sizeof(int16_t) * sa.stride * sa.n_trees) == 0);
    CHECK(fa.n_leaves == fb.n_leaves && memcmp(fa.leaves, fb.leaves, sizeof *fa.leaves) == 0);
    wire_decoder_destroy(a);
    wire_decoder_destroy(b);
}

/* A rejected bundle leaves the decoder at seq 5 (a later valid one still applies). */
static void rejects(const uint8_t *frame, size_t len, int code, const char *msg)
{
    wire_decoder *d = keyed();
    wire_frame f;
    gale_err e;
    CHECK(wire_decode(d, frame, len, &f, &e) == code);
    CHECK_STR_HAS(e.msg, msg);
    CHECK(wire_decoder_seq(d) == 5);
    CHECK(wire_decode(d, bundle, nb, &f, NULL) == 0 && wire_decoder_seq(d) == 6);
    wire_decoder_destroy(d);
}

static void test_malformed(void)
{
    uint8_t bad[512];
    memcpy(bad, bundle, nb);
    bad[20] = 0;
    rejects(bad, nb, GALE_E_FORMAT, "wire: BUNDLE tick 122: count at byte 20: expected 1..16, got 0");
    bad[20] = 17;
    rejects(bad, nb, GALE_E_FORMAT, "expected 1..16, got 17");
    bad[20] = 3;
    rejects(bad, nb, GALE_E_FORMAT, "frame 3 of 3: length: expected 20..0, got none");
    bad[20] = 1;
    rejects(bad, nb, GALE_E_FORMAT, "length: 40 trailing bytes after 1 frames");
    memcpy(bad, bundle, nb);
    bad[21] = 0x1e; /* the DELTA's length one too long */
    rejects(bad, nb, GALE_E_FORMAT, "frame 2 of 2: length: expected 20..");
    rejects(bundle, nb - 1, GALE_E_FORMAT, "frame 2 of 2: length: expected 20..35, got 36");
    rejects(bundle, 22, GALE_E_FORMAT, "frame 1 of 2: length: expected 20..1, got none");
    /* a bad inner frame: its own message, and the state stays put */
    memcpy(bad, bundle, nb);
    bad[25 + 29 + 4 + 6] = 9;
    rejects(bad, nb, GALE_E_FORMAT,
            "wire: BUNDLE tick 122: frame 2 of 2: wire: header: message type: expected 1..8, got 9");
    memcpy(bad, bundle, nb);
    bad[25 + 29 + 4 + 20] = 2; /* leaves count 2, one leaf's bytes */
    rejects(bad, nb, GALE_E_FORMAT, "frame 2 of 2: wire: LEAVES tick 123: length");
    /* a gap in the state: GALE_E_STATE as for a DELTA sent apart */
    memcpy(bad, bundle, nb);
    bad[25 + 20] = 7;
    rejects(bad, nb, GALE_E_STATE, "frame 1 of 2: ");

    /* one of each type, one state, no nesting */
    const uint8_t *two[2] = { leaves, leaves };
    size_t two_len[2] = { nl, nl }, len = nd;
    memcpy(bad, delta, nd);
    CHECK(wire_bundle_wrap(bad, sizeof bad, &len, two, two_len, 2, NULL) == 0);
    rejects(bad, len, GALE_E_FORMAT, "frame 3 of 3: type: expected one frame of each type, at "
                                     "most one state frame and no BUNDLE, got a second LEAVES");
    const uint8_t *k[1] = { key };
    len = nd;
    memcpy(bad, delta, nd);
    CHECK(wire_bundle_wrap(bad, sizeof bad, &len, k, &nk, 1, NULL) == 0);
    rejects(bad, len, GALE_E_FORMAT, "frame 2 of 2: type: expected one frame of each type, at most "
                                     "one state frame and no BUNDLE, got a second KEYFRAME");
    const uint8_t *nest[1] = { bundle };
    len = nl;
    memcpy(bad, leaves, nl);
    CHECK(wire_bundle_wrap(bad, sizeof bad, &len, nest, &nb, 1, NULL) == 0);
    rejects(bad, len, GALE_E_FORMAT, "frame 2 of 2: type: expected one frame of each type, at "
                                     "most one state frame and no BUNDLE, got BUNDLE");
    /* every truncation of the vector is rejected */
    wire_decoder *d = keyed();
    wire_frame f;
    gale_err e;
    int truncated_ok = 1;
    for (size_t cut = 0; cut < nb; cut++) {
        truncated_ok &= wire_decode(d, bundle, cut, &f, &e) == GALE_E_FORMAT &&
                        wire_decoder_seq(d) == 5;
    }
    CHECK(truncated_ok);
    wire_decoder_destroy(d);
}

static void test_wrap_limits(void)
{
    size_t len = nd;
    gale_err e;
    memcpy(buf, delta, nd);
    CHECK(wire_bundle_wrap(buf, nd + 30, &len, (const uint8_t *[]){ leaves }, &nl, 1, &e) ==
          GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "wire_bundle_wrap: buffer: expected 94 bytes, got 59");
    CHECK(len == nd && memcmp(buf, delta, nd) == 0);
    const uint8_t *many[16];
    size_t many_len[16];
    for (int i = 0; i < 16; i++) {
        many[i] = leaves;
        many_len[i] = nl;
    }
    CHECK(wire_bundle_wrap(buf, sizeof buf, &len, many, many_len, 16, &e) == GALE_E_ARG);
    CHECK_STR_HAS(e.msg, "expected a frame and <= 15 others");
}

int main(void)
{
    static spec_file spec;
    if (spec_load(&spec, SPEC_PROTOCOL_PATH)) {
        fprintf(stderr, "test_wire_bundle: %s\n", spec.err);
        return 1;
    }
    /* KEYFRAME seq 5, then the BUNDLE of DELTA seq 6 and LEAVES */
    nk = spec_bytes(&spec, "KEYFRAME", key, sizeof key);
    nd = spec_bytes(&spec, "DELTA", delta, sizeof delta);
    nl = spec_bytes(&spec, "LEAVES", leaves, sizeof leaves);
    nb = spec_bytes(&spec, "BUNDLE", bundle, sizeof bundle);
    if (nk != 59 || nd != 29 || nl != 36 || nb != 94) {
        fprintf(stderr, "test_wire_bundle: expected vectors of 59, 29, 36 and 94 bytes, got %zu, "
                        "%zu, %zu, %zu\n", nk, nd, nl, nb);
        return 1;
    }
    RUN(test_same_as_apart);
    RUN(test_malformed);
    RUN(test_wrap_limits);
    return check_report();
}
