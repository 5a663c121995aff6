/* The shared falling-leaf path (Vazquez 2008 sections 3.2-4.2): the plate falls at a
 * leaf's speed and swings, the path continues smoothly through its continuity points,
 * the landing time puts the leaf on the ground, variations are deterministic per seed. */
#include <math.h>

#include "check.h"
#include "falling_path.h"

static falling_path P;

static void test_falls_and_swings(void)
{
    gale_err err = { 0 };
    CHECK(falling_path_build(&P, NULL, &err) == 0);
    /* leaves fall at roughly 0.5-3 m/s */
    CHECK(P.fall_speed > 0.5f && P.fall_speed < 3.0f);
    /* every second of the path goes down */
    uint32_t sec = (uint32_t)(1.0f / P.dt);
    for (uint32_t s = sec; s < P.n; s += sec) {
        CHECK(P.pos[s][2] < P.pos[s - sec][2]);
    }
    /* it swings: the horizontal velocity along the main swing axis changes sign */
    int flips = 0;
    float prev = 0.0f;
    for (uint32_t s = 1; s < P.n; s++) {
        float vx = P.pos[s][0] - P.pos[s - 1][0];
        if (prev * vx < 0.0f) {
            flips++;
        }
        if (vx != 0.0f) {
            prev = vx;
        }
    }
    fprintf(stderr, "fall speed %.2f m/s, %d swings, %u samples, %u continuity points\n",
            (double)P.fall_speed, flips, P.n, P.n_cont);
    CHECK(flips >= 6);
    CHECK(P.n_cont >= 1 && P.n_start >= 1);
    for (uint32_t i = 0; i < P.n_cont; i++) {
        CHECK(P.cont[i] >= 1 && P.cont[i] < P.n);
    }
}

static void test_reuse_is_continuous(void)
{
    falling_var v;
    falling_var_from_seed(&P, 77, &v);
    /* walk well past several reuses: per-step motion never jumps */
    float prev[3], q[4], pos[3];
    falling_path_eval(&P, &v, 0.0f, prev, q);
    float worst = 0.0f, h = 0.25f * P.dt;
    float span = (float)(P.n) * P.dt * 4.0f;
    for (float t = h; t < span; t += h) {
        falling_path_eval(&P, &v, t, pos, q);
        float d = sqrtf((pos[0] - prev[0]) * (pos[0] - prev[0]) +
                        (pos[1] - prev[1]) * (pos[1] - prev[1]) +
                        (pos[2] - prev[2]) * (pos[2] - prev[2]));
        worst = d > worst ? d : worst;
        memcpy(prev, pos, sizeof pos);
    }
    /* the fastest sample-to-sample motion of the path itself, scaled by the variation */
    float vmax = 0.0f;
    for (uint32_t s = 1; s < P.n; s++) {
        float dx = (P.pos[s][0] - P.pos[s - 1][0]) * v.sx, dy = (P.pos[s][1] - P.pos[s - 1][1]) * v.sy,
              dz = P.pos[s][2] - P.pos[s - 1][2];
        float d = sqrtf(dx * dx + dy * dy + dz * dz) * 0.25f;
        vmax = d > vmax ? d : vmax;
    }
    fprintf(stderr, "largest step over 4 path lengths %.4f m, path's own %.4f m\n",
            (double)worst, (double)vmax);
    CHECK(worst <= 1.5f * vmax + 1e-4f);
    /* and it keeps falling: after 4 path lengths it is 4 path drops down */
    CHECK(prev[2] < 3.5f * P.pos[P.n - 1][2]);
}

static void test_landing(void)
{
    for (uint32_t seed = 1; seed < 20; seed++) {
        falling_var v;
        falling_var_from_seed(&P, seed, &v);
        float h0 = 2.0f + (float)seed;
        float tl = falling_path_land_time(&P, &v, h0, 300.0f);
        float pos[3], q[4];
        falling_path_eval(&P, &v, tl, pos, q);
        CHECK_NEAR(h0 + pos[2], 0.0, 0.02);
        CHECK_NEAR(tl, h0 / P.fall_speed, 0.35f * h0 / P.fall_speed + 0.5f);
    }
}

static void test_variation(void)
{
    falling_var a, b, c;
    falling_var_from_seed(&P, 5, &a);
    falling_var_from_seed(&P, 5, &b);
    falling_var_from_seed(&P, 6, &c);
    CHECK(a.yaw == b.yaw && a.start == b.start && a.sx == b.sx && a.seed == b.seed);
    CHECK(a.yaw != c.yaw);
    CHECK(a.sx >= 1.0f && a.sx <= 3.0f && a.sy >= 1.0f && a.sy <= 3.0f);
}

static void test_bad_desc(void)
{
    falling_path p;
    gale_err err = { 0 };
    CHECK(falling_path_build(&p, &(falling_path_desc){ .duration_s = 100.0f }, &err) ==
          GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "duration_s");
}

int main(void)
{
    RUN(test_falls_and_swings);
    RUN(test_reuse_is_continuous);
    RUN(test_landing);
    RUN(test_variation);
    RUN(test_bad_desc);
    return check_report();
}
