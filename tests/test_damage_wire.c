/* DAMAGE frames (protocol/msg_damage.c, PROTOCOL.md "DAMAGE"): the exact error texts of
 * the spec's vector DAMAGE with one field broken, and the receiver's picture
 * (damage_view.c) built from events or from the whole state. */
#include "check.h"
#include "spec_vectors.h"

#include "damage_view.h"
#include "wire.h"

/* PROTOCOL.md's vector DAMAGE (tests/test_spec_vectors.c checks its bytes and values):
 * tick 123, events (tree 2 branch at node 17) and (tree 5 uprooted towards +y). */
static spec_file spec;
static uint8_t golden[64];
static size_t golden_len;

static void bad(const uint8_t *b, size_t n, const char *want)
{
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 8 }, NULL);
    wire_frame f;
    gale_err e = { 0 };
    CHECK(wire_decode(d, b, n, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, want);
    CHECK(f.damage == NULL);
    wire_decoder_destroy(d);
}

static void test_bad_frames(void)
{
    CHECK(golden_len == 51);
    uint8_t b[sizeof golden];
    memcpy(b, golden, sizeof b);
    bad(b, golden_len - 1, "wire: DAMAGE tick 123: length: expected 51 bytes for 2 events, got 50");
    memcpy(b, golden, sizeof b);
    b[20] = 2;
    bad(b, golden_len, "wire: DAMAGE tick 123: full at byte 20: expected 0 or 1, got 2");
    memcpy(b, golden, sizeof b);
    b[31] = 9;
    bad(b, golden_len, "wire: DAMAGE tick 123: event 0 kind at byte 31: expected 1..4, got 9");
    memcpy(b, golden, sizeof b);
    b[45] = WIRE_DAMAGE_BRANCH;
    bad(b, golden_len, "event 1 node at byte 41: expected a node index, got 4294967295");
    memcpy(b, golden, sizeof b);
    b[45] = WIRE_DAMAGE_STRIP;
    b[46] = 33;
    bad(b, golden_len, "event 1 value at byte 46: expected 0..32, got 33");
    memcpy(b, golden, sizeof b);
    b[21] = 0x01;
    b[22] = 0x10;
    bad(b, golden_len, "count at byte 21: expected <= 4096, got 4097");
    wire_damage big = { 0 };
    uint8_t small[30];
    size_t len;
    gale_err e;
    CHECK(wire_encode_damage(&(wire_header){ 0 }, false, &big, 1, small, sizeof small, &len,
                             &e) == GALE_E_RANGE);
}

static void test_view(void)
{
    damage_view a, b;
    CHECK(damage_view_init(&a, 8, NULL) == 0);
    CHECK(damage_view_init(&b, 8, NULL) == 0);
    wire_damage ev[4] = {
        { 3, 40, WIRE_DAMAGE_BRANCH, 0, 10 },
        { 3, 12, WIRE_DAMAGE_BRANCH, 0, 11 },
        { 1, WIRE_DAMAGE_WHOLE, WIRE_DAMAGE_STRIP, 20, 12 },
        { 6, WIRE_DAMAGE_WHOLE, WIRE_DAMAGE_SNAP, 200, 13 },
    };
    /* events one at a time, twice (idempotent), against all at once as a whole state */
    for (int r = 0; r < 2; r++) {
        for (int i = 0; i < 4; i++) {
            CHECK(damage_view_apply(&a, false, &ev[i], 1) == 0);
        }
    }
    CHECK(damage_view_apply(&b, true, ev, 4) == 0);
    CHECK(damage_view_equal(&a, &b));
    CHECK(damage_view_broken(&a, 3, 12) && damage_view_broken(&a, 3, 40));
    CHECK(!damage_view_broken(&a, 3, 13));
    CHECK(a.tree[6].fallen == WIRE_DAMAGE_SNAP && a.tree[6].fall_az == 200);
    CHECK(a.tree[1].level == 20);
    /* a whole state heals first; an unknown tree is skipped and counted */
    wire_damage out = { 9, WIRE_DAMAGE_WHOLE, WIRE_DAMAGE_UPROOT, 0, 1 };
    CHECK(damage_view_apply(&b, true, &out, 1) == 1);
    CHECK(b.n_broken == 0 && b.tree[6].fallen == 0 && b.tree[1].level == WIRE_DAMAGE_LEVELS);
    damage_view_fini(&a);
    damage_view_fini(&b);
}

static void test_leaf_rank(void)
{
    /* kept sets shrink with the level, and about level/32 of the slots stay */
    int kept16 = 0;
    for (uint32_t s = 0; s < 32000; s++) {
        bool k16 = wire_damage_leaf_kept(7, s, 16);
        CHECK(wire_damage_leaf_kept(7, s, WIRE_DAMAGE_LEVELS));
        CHECK(!wire_damage_leaf_kept(7, s, 0));
        CHECK(!k16 || wire_damage_leaf_kept(7, s, 17));
        kept16 += k16;
    }
    CHECK(kept16 > 15000 && kept16 < 17000);
}

int main(void)
{
    const spec_vector *v = spec_load(&spec, SPEC_PROTOCOL_PATH) ? NULL : spec_find(&spec, "DAMAGE");
    if (!v || v->len > sizeof golden) {
        fprintf(stderr, "test_damage_wire: %s: no vector DAMAGE %s\n", SPEC_PROTOCOL_PATH, spec.err);
        return 1;
    }
    memcpy(golden, v->bytes, v->len);
    golden_len = v->len;
    RUN(test_bad_frames);
    RUN(test_view);
    RUN(test_leaf_rank);
    return check_report();
}
