/* A slow reader's rate steps (server/serve/net_rate.h): the keyframe-to-delta ratio counts
 * what rides only with keyframes; a reader lowered from full rate takes at most the bytes
 * a second it took there (hz / n keyframes against hz deltas), for ratios from under 2 to
 * past the snapshot rate; doubling (to the floor at least) and halving keep to 2..hz, and a
 * halving that would cost more than the full rate goes to the full rate; a reader behind
 * gets keyframes at a rate that fits the bytes a second it took. */
#include "check.h"
#include "net_rate.h"

#define HZ 30

static void test_ratio(void)
{
    net_snap p = { .key_len = 4000, .delta2_len = 800, .delta1_len = 1000 };
    CHECK(net_rate_key_bytes(&p) == 4000);
    CHECK(net_rate_delta_bytes(&p) == 800); /* delta2: what a reader at full rate takes */
    p.delta2_len = 0;
    CHECK(net_rate_delta_bytes(&p) == 1000);
    /* the FOREST (extra 5) goes only with keyframes; the leaves (extra 0) with every frame */
    p.extra_key_only = 1u << 5;
    p.extra_len[5] = 6000;
    p.extra_len[0] = 3000;
    CHECK(net_rate_key_bytes(&p) == 10000);
    p.key_len = 0; /* frames on demand: no keyframe in this snapshot */
    CHECK(net_rate_key_bytes(&p) == 0);
    CHECK_NEAR(net_rate_key_per_delta(10000, 1000), 10.0, 1e-6);
    CHECK(net_rate_key_per_delta(0, 1000) == 0.0f);
    CHECK(net_rate_key_per_delta(10000, 0) == 0.0f);
}

static void test_fewer_bytes(void)
{
    for (float r = 0.0f; r < 60.0f; r += 0.37f) {
        const int n = net_rate_lower(1, r, 1, HZ);
        CHECK(n >= 2 && n <= HZ);
        /* bytes a second with deltas of 1 byte: HZ at full rate, HZ / n * r decimated */
        if (r <= (float)HZ) {
            CHECK((double)HZ / n * (double)r <= (double)HZ * 1.000001);
        } else {
            CHECK(n == HZ); /* as low as it goes: a keyframe a second */
        }
        /* and no slower than it must: n - 1 would not be a floor */
        CHECK(n == 2 || (float)(n - 1) < r);
    }
    CHECK(net_rate_floor(0.0f, HZ) == 2);
    CHECK(net_rate_floor(7.2f, HZ) == 8);
    CHECK(net_rate_floor(7.2f, 5) == 5);
}

/* A reader that is behind: the lower rate's keyframes fit in the bytes a second it took
 * (as far as one keyframe a second allows), whatever the ratio. */
static void test_take_floor(void)
{
    const size_t key = 1100000; /* the landscape's aerial keyframe and FOREST after a storm */
    for (double take = 2e4; take < 4e7; take *= 1.37) {
        const int f = net_rate_take_floor(key, take, HZ);
        const int n = net_rate_lower(1, 0.0f, f, HZ);
        CHECK(n >= 2 && n <= HZ);
        if ((double)key <= take) {
            CHECK((double)HZ / n * (double)key <= take * 1.000001);
        } else {
            CHECK(n == HZ);
        }
        CHECK(f == 1 || (double)HZ / (f - 1) * (double)key > take); /* and no lower */
    }
    CHECK(net_rate_take_floor(key, 1.2e6, HZ) == 28);
    CHECK(net_rate_take_floor(0, 1.2e6, HZ) == 1);
    CHECK(net_rate_take_floor(key, 0.0, HZ) == 1);
    CHECK(net_rate_lower(4, 0.0f, 28, HZ) == 28);
}

static void test_steps(void)
{
    /* from a decimated rate: doubled, capped at the snapshot rate */
    CHECK(net_rate_lower(8, 7.2f, 1, HZ) == 16);
    CHECK(net_rate_lower(16, 7.2f, 1, HZ) == HZ);
    CHECK(net_rate_lower(2, 0.0f, 1, HZ) == 4);
    /* the ratio learnt since the last step raises the floor */
    CHECK(net_rate_lower(2, 7.2f, 1, HZ) == 8);
    /* halved while the half stays at the floor or above, else the full rate */
    CHECK(net_rate_raise(HZ, 7.2f, HZ) == 15);
    CHECK(net_rate_raise(16, 7.2f, HZ) == 8);
    CHECK(net_rate_raise(8, 7.2f, HZ) == 1);
    CHECK(net_rate_raise(4, 0.0f, HZ) == 2);
    CHECK(net_rate_raise(2, 0.0f, HZ) == 1);
    CHECK(net_rate_raise(3, 0.0f, HZ) == 1);
}

int main(void)
{
    RUN(test_ratio);
    RUN(test_fewer_bytes);
    RUN(test_take_floor);
    RUN(test_steps);
    return check_report();
}
