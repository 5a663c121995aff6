/* Storm damage on screen without a GL context: the cut mask on a hand-made skeleton hides
 * exactly the descendants of each broken node (and a debris piece keeps exactly them), the
 * per-tree range of a sorted broken list, the tip-over closed form against a fine RK4 of
 * θ'' = (3g / 2L) sin θ, and a debris piece: deterministic per (tree, node), downwind,
 * landed, lying flat, then gone; tree_frame's angles round-trip; only recent events
 * animate (a late joiner's old events give NaN: the end state at once). */
#include <math.h>
#include <string.h>

#include "check.h"
#include "damage_clock.h"
#include "damage_cut.h"
#include "debris_path.h"
#include "tip_fall.h"

/* Breadth-first numbering like an asset (ASSET.md "Node numbering"):
 *            0
 *         /  |  \
 *        1   2   3
 *       / \   \   \
 *      4   5   6   7
 *     / \       \
 *    8   9       10
 *         \
 *          11
 */
static const int32_t PARENT[12] = { -1, 0, 0, 0, 1, 1, 2, 3, 4, 4, 6, 9 };

/* the reference: is a a descendant of b (or b itself)? walks up from a */
static int descends(int a, int b)
{
    for (int j = a; j >= 0; j = PARENT[j]) {
        if (j == b) {
            return 1;
        }
    }
    return 0;
}

static void test_mask_is_descendants(void)
{
    uint8_t m[12];
    for (uint32_t b = 0; b < 12; b++) {
        damage_cut_mask(PARENT, 12, &b, 1, false, m);
        int wrong = 0;
        for (int i = 0; i < 12; i++) {
            wrong += m[i] != !descends(i, (int)b);
        }
        CHECK(wrong == 0);
        damage_cut_mask(PARENT, 12, &b, 1, true, m);
        for (int i = 0; i < 12; i++) {
            wrong += m[i] != descends(i, (int)b);
        }
        CHECK(wrong == 0);
    }
    /* two breaks, one inside the other's sub-tree, and one out of range */
    const uint32_t cut[3] = { 4, 9, 99 };
    damage_cut_mask(PARENT, 12, cut, 3, false, m);
    const uint8_t want[12] = { 1, 1, 1, 1, 0, 1, 1, 1, 0, 0, 1, 0 };
    CHECK(memcmp(m, want, 12) == 0);
    /* node 1 broken: 1, 4, 5, 8, 9, 11 gone; its sibling 2's sub-tree (2, 6, 10) stays */
    const uint32_t one = 1;
    damage_cut_mask(PARENT, 12, &one, 1, false, m);
    const uint8_t want1[12] = { 1, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
    CHECK(memcmp(m, want1, 12) == 0);
    /* nothing broken: everything drawn */
    damage_cut_mask(PARENT, 12, NULL, 0, false, m);
    int all = 0;
    for (int i = 0; i < 12; i++) {
        all += m[i];
    }
    CHECK(all == 12);
}

static void test_tree_range(void)
{
    const uint64_t keys[6] = { (0ull << 32) | 5, (2ull << 32) | 1, (2ull << 32) | 7,
                               (2ull << 32) | 0xFFFFFFFFull, (3ull << 32) | 2, (9ull << 32) | 4 };
    uint32_t first = 99;
    CHECK(damage_cut_tree_range(keys, 6, 2, &first) == 3 && first == 1);
    CHECK(damage_cut_tree_range(keys, 6, 0, &first) == 1 && first == 0);
    CHECK(damage_cut_tree_range(keys, 6, 1, &first) == 0 && first == 1);
    CHECK(damage_cut_tree_range(keys, 6, 9, &first) == 1 && first == 5);
    CHECK(damage_cut_tree_range(keys, 6, 10, &first) == 0 && first == 6);
    CHECK(damage_cut_tree_range(keys, 0, 0, &first) == 0 && first == 0);
}

/* θ'' = (3g / 2L) sin θ from θ0 with the closed form's starting speed 2ω sin(θ0 / 2),
 * classical RK4 at 0.1 ms: an independent solution of the pole equation */
static double rk4_angle(double t_end, double height_m)
{
    const double w2 = 1.5 * TIP_FALL_G_MS2 / height_m;
    const int n = (int)ceil(t_end / 1e-4);
    const double h = t_end / n;
    double th = TIP_FALL_LEAN0_RAD, om = 2.0 * sqrt(w2) * sin(0.5 * TIP_FALL_LEAN0_RAD);
    for (int s = 0; s < n; s++) {
        double k1t = om, k1o = w2 * sin(th);
        double k2t = om + 0.5 * h * k1o, k2o = w2 * sin(th + 0.5 * h * k1t);
        double k3t = om + 0.5 * h * k2o, k3o = w2 * sin(th + 0.5 * h * k2t);
        double k4t = om + h * k3o, k4o = w2 * sin(th + h * k3t);
        th += h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
        om += h / 6.0 * (k1o + 2.0 * k2o + 2.0 * k3o + k4o);
    }
    return th;
}

static void test_tip_fall(void)
{
    const double heights[2] = { 20.0, 11.0 };
    for (int k = 0; k < 2; k++) {
        double L = heights[k], dur = tip_fall_duration_s(L);
        CHECK(dur > 2.0 && dur < 6.0); /* "over a few seconds" for a 11..20 m stem */
        const double frac[4] = { 0.25, 0.5, 0.8, 0.97 };
        for (int i = 0; i < 4; i++) {
            double t = frac[i] * dur;
            CHECK_NEAR(tip_fall_angle(t, L), rk4_angle(t, L), 1e-6);
        }
        CHECK_NEAR(tip_fall_angle(dur, L), TIP_FALL_LYING_RAD, 1e-9);
        CHECK_NEAR(tip_fall_angle(dur + 1.0, L), TIP_FALL_LYING_RAD, 0);
        CHECK_NEAR(tip_fall_angle(1e9, L), TIP_FALL_LYING_RAD, 0);
        CHECK_NEAR(tip_fall_angle(-1.0, L), 0.0, 0);
        /* monotone: it never rises again */
        double prev = 0.0;
        int back = 0;
        for (double t = 0.0; t < dur + 0.5; t += 0.01) {
            double a = tip_fall_angle(t, L);
            back += a < prev;
            prev = a;
        }
        CHECK(back == 0);
    }
    /* a taller stem takes longer (ω = sqrt(3g / 2L)) */
    CHECK(tip_fall_duration_s(20.0) > tip_fall_duration_s(11.0));
}

static void wind_east(void *user, const float p[3], float out[3])
{
    const float *u = user;
    /* stronger aloft, as the streamed field is */
    float f = p[2] > 0.0f ? 0.6f + 0.04f * p[2] : 0.6f;
    out[0] = u[0] * f;
    out[1] = u[1] * f;
    out[2] = 0.0f;
}

static void start(debris_path *p, uint32_t tree, uint32_t node)
{
    const float c0[3] = { 3.0f, -2.0f, 11.0f }, axis[3] = { 0.3f, 0.1f, 1.0f };
    float r0[9];
    debris_frame_matrix(0.4f, 0.0f, 0.0f, r0);
    debris_path_start(p, tree, node, 100.0, c0, r0, axis, 2.5f);
}

static void test_debris_path(void)
{
    float u[3] = { 40.0f, 0.0f, 0.0f };
    debris_path a, b, c;
    start(&a, 7, 42);
    start(&b, 7, 42);
    start(&c, 8, 42);
    /* the same piece advanced in different frame steps lands on the same state */
    for (double t = 100.0; t < 120.0; t += 1.0 / 60.0) {
        debris_path_advance(&a, t, wind_east, u);
    }
    for (double t = 100.0; t < 120.0; t += 1.0 / 23.0) {
        debris_path_advance(&b, t, wind_east, u);
    }
    debris_path_advance(&a, 120.0, wind_east, u);
    debris_path_advance(&b, 120.0, wind_east, u);
    debris_path_advance(&c, 120.0, wind_east, u);
    CHECK(a.landed && b.landed && c.landed);
    CHECK(memcmp(a.c, b.c, sizeof a.c) == 0 && a.land_s == b.land_s);
    float ra[9], rb[9], rc[9];
    debris_path_rotation(&a, ra);
    debris_path_rotation(&b, rb);
    debris_path_rotation(&c, rc);
    CHECK(memcmp(ra, rb, sizeof ra) == 0);
    /* another piece falls another way (its own spin and drag) */
    CHECK(memcmp(ra, rc, sizeof ra) != 0);
    /* it fell within a few seconds, carried downwind, and rests on the ground */
    CHECK(a.land_s - a.t0_s > 0.8 && a.land_s - a.t0_s < 5.0);
    CHECK(a.c[0] > 3.0f + 5.0f && fabsf(a.c[1] + 2.0f) < 1e-3f);
    CHECK_NEAR(a.c[2], a.lie_z_m, 1e-6);
    /* lying flat: its main axis horizontal once settled */
    float ax[3];
    for (int k = 0; k < 3; k++) {
        ax[k] = ra[k] * a.rest_axis[0] + ra[3 + k] * a.rest_axis[1] + ra[6 + k] * a.rest_axis[2];
    }
    CHECK_NEAR(ax[2], 0.0, 1e-4);
    CHECK_NEAR(debris_path_sink_m(&a), 0.0, 0);
    CHECK(!debris_path_done(&a));
    /* in calm air it drops straight down in about sqrt(2 h / g) and a bit more (drag) */
    float calm[3] = { 0.0f, 0.0f, 0.0f };
    debris_path d;
    start(&d, 1, 2);
    debris_path_advance(&d, 110.0, wind_east, calm);
    CHECK(d.landed && fabsf(d.c[0] - 3.0f) < 1e-4f);
    double fall_s = d.land_s - d.t0_s, free_s = sqrt(2.0 * (11.0 - (double)d.lie_z_m) / 9.81);
    CHECK(fall_s >= free_s - 0.01 && fall_s < 2.0 * free_s);
    CHECK(d.c[2] == d.lie_z_m);
    /* then it sinks away and is gone: debris stays bounded */
    debris_path_advance(&a, a.land_s + DEBRIS_LIE_S + 0.5 * DEBRIS_SINK_S, wind_east, u);
    CHECK(debris_path_sink_m(&a) > 0.0f && !debris_path_done(&a));
    debris_path_advance(&a, a.land_s + DEBRIS_LIE_S + DEBRIS_SINK_S, wind_east, u);
    CHECK(debris_path_done(&a));
}

static void test_frame_angles(void)
{
    int bad = 0;
    for (int i = 0; i < 200; i++) {
        float yaw = -3.0f + 0.03f * (float)i, fall = 0.01f + 0.0155f * (float)i,
              az = 2.9f - 0.029f * (float)i;
        float r[9], r2[9], y2, f2, a2;
        debris_frame_matrix(yaw, fall, az, r);
        debris_frame_angles(r, &y2, &f2, &a2);
        debris_frame_matrix(y2, f2, a2, r2);
        for (int k = 0; k < 9; k++) {
            bad += fabsf(r[k] - r2[k]) > 2e-4f;
        }
        bad += f2 < 0.0f || f2 > 3.1416f;
    }
    CHECK(bad == 0);
    /* tipped 90° towards +x: the tree's +z points along +x */
    float r[9];
    debris_frame_matrix(0.0f, 1.5707963f, 0.0f, r);
    CHECK_NEAR(r[6], 1.0, 1e-6);
    CHECK_NEAR(r[8], 0.0, 1e-6);
}

static void test_event_clock(void)
{
    /* a frame of tick 6000 encoded at 100 s, 60 Hz ticks */
    CHECK_NEAR(damage_event_start_s(6000, 100000000u, 6000, 60.0), 100.0, 1e-9);
    CHECK_NEAR(damage_event_start_s(6000, 100000000u, 5940, 60.0), 99.0, 1e-9);
    CHECK_NEAR(damage_event_start_s(6000, 100000000u, 6000 - 180, 60.0), 97.0, 1e-9);
    CHECK(isnan(damage_event_start_s(6000, 100000000u, 6000 - 181, 60.0)));
    /* the whole state a late joiner gets: every old event shows its end state */
    CHECK(isnan(damage_event_start_s(6000, 100000000u, 60, 60.0)));
    /* stamped after its frame: the frame's instant; across the tick wrap: its age */
    CHECK_NEAR(damage_event_start_s(6000, 100000000u, 6010, 60.0), 100.0, 1e-9);
    CHECK_NEAR(damage_event_start_s(30, 100000000u, 0xFFFFFFFFu - 29, 60.0), 99.0, 1e-9);
    /* no rate known: 60 Hz */
    CHECK_NEAR(damage_event_start_s(6000, 100000000u, 5940, 0.0), 99.0, 1e-9);
}

int main(void)
{
    RUN(test_mask_is_descendants);
    RUN(test_tree_range);
    RUN(test_tip_fall);
    RUN(test_debris_path);
    RUN(test_frame_angles);
    RUN(test_event_clock);
    return check_report();
}
