/* DAMAGE frames (protocol/msg_damage.c, PROTOCOL.md "DAMAGE"): the spec's test vector byte
 * for byte, a round trip through wire_decode, the exact error texts of bad frames, and
 * the receiver's picture (damage_view.c) built from events or from the whole state. */
#include "check.h"

#include "damage_view.h"
#include "wire.h"

/* PROTOCOL.md "Test vectors": DAMAGE, tick 123, server_time_us 2 050 000, events (tree 2
 * branch at node 17, tick 118) and (tree 5 uprooted towards azimuth 64 = +y, tick 120). */
static const uint8_t golden[] = {
    0x47, 0x41, 0x4c, 0x45, 0x01, 0x00, 0x06, 0x00, 0x7b, 0x00, 0x00, 0x00, 0xd0, 0x47,
    0x1f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x02, 0x00, 0x00, 0x00, 0x11,
    0x00, 0x00, 0x00, 0x01, 0x00, 0x76, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0xff,
    0xff, 0xff, 0xff, 0x03, 0x40, 0x78, 0x00, 0x00, 0x00,
};
static const wire_damage golden_ev[2] = {
    { .tree = 2, .node = 17, .kind = WIRE_DAMAGE_BRANCH, .value = 0, .tick = 118 },
    { .tree = 5, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_UPROOT, .value = 64, .tick = 120 },
};

static void test_vector(void)
{
    uint8_t buf[128];
    size_t len = 0;
    wire_header h = { .tick = 123, .server_time_us = 2050000 };
    CHECK(wire_encode_damage(&h, false, golden_ev, 2, buf, sizeof buf, &len, NULL) == 0);
    CHECK(len == sizeof golden);
    CHECK(memcmp(buf, golden, sizeof golden) == 0);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 8 }, NULL);
    wire_frame f;
    CHECK(wire_decode(d, golden, sizeof golden, &f, NULL) == 0);
    CHECK(f.hdr.type == WIRE_MSG_DAMAGE && f.n_damage == 2 && !f.damage_full);
    /* field by field: the struct has padding */
    CHECK(f.damage && f.damage[1].tree == golden_ev[1].tree && f.damage[1].node == golden_ev[1].node &&
          f.damage[1].kind == golden_ev[1].kind && f.damage[1].value == golden_ev[1].value &&
          f.damage[1].tick == golden_ev[1].tick);
    CHECK(f.damage && f.damage[0].node == 17 && f.damage[0].tick == 118);
    wire_decoder_destroy(d);
}

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
    uint8_t b[sizeof golden];
    memcpy(b, golden, sizeof b);
    bad(b, sizeof b - 1, "wire: DAMAGE tick 123: length: expected 51 bytes for 2 events, got 50");
    memcpy(b, golden, sizeof b);
    b[20] = 2;
    bad(b, sizeof b, "wire: DAMAGE tick 123: full at byte 20: expected 0 or 1, got 2");
    memcpy(b, golden, sizeof b);
    b[31] = 9;
    bad(b, sizeof b, "wire: DAMAGE tick 123: event 0 kind at byte 31: expected 1..4, got 9");
    memcpy(b, golden, sizeof b);
    b[45] = WIRE_DAMAGE_BRANCH;
    bad(b, sizeof b, "event 1 node at byte 41: expected a node index, got 4294967295");
    memcpy(b, golden, sizeof b);
    b[45] = WIRE_DAMAGE_STRIP;
    b[46] = 33;
    bad(b, sizeof b, "event 1 value at byte 46: expected 0..32, got 33");
    memcpy(b, golden, sizeof b);
    b[21] = 0x01;
    b[22] = 0x10;
    bad(b, sizeof b, "count at byte 21: expected <= 4096, got 4097");
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
    RUN(test_vector);
    RUN(test_bad_frames);
    RUN(test_view);
    RUN(test_leaf_rank);
    return check_report();
}
