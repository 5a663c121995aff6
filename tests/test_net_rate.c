/* A slow reader's rate steps (server/serve/net_rate.h): the keyframe-to-delta ratio counts
 * what rides only with keyframes; a reader lowered from full rate takes at most the bytes
 * a second it took there (hz / n keyframes against hz deltas), for ratios from under 2 to
 * past the snapshot rate; doubling and halving keep to 2..hz, and a halving that would
 * cost more than the full rate goes to the full rate. */
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
        const int n = net_rate_lower(1, r, HZ);
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

static void test_steps(void)
{
    /* from a decimated rate: doubled, capped at the snapshot rate */
    CHECK(net_rate_lower(8, 7.2f, HZ) == 16);
    CHECK(net_rate_lower(16, 7.2f, HZ) == HZ);
    CHECK(net_rate_lower(2, 0.0f, HZ) == 4);
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
    RUN(test_steps);
    return check_report();
}
