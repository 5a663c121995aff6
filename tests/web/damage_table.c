/* gale-client's storm damage and falling-leaf formulas as a table, one JSON object a line,
 * for tests/web/test_damage_js.mjs to hold web/damage.js and web/falling_path.js to: the
 * tip-over angle (client/motion/tip_fall.c), the break height, the event clock
 * (client/motion/damage_clock.c), the leaf slots a stripped crown keeps (protocol/wire.h), the
 * shared falling-leaf path sample by sample (client/motion/falling_path.c), and leaves' variations,
 * positions and landing times from seeds, the cut mask of broken branches
 * (client/motion/damage_cut.c) and a broken branch's tumbling fall in a steady wind
 * (client/motion/debris_path.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "damage_clock.h"
#include "damage_cut.h"
#include "debris_path.h"
#include "falling_path.h"
#include "tip_fall.h"
#include "wire.h"

static void floats(const char *name, const float *v, size_t n)
{
    printf(",\"%s\":[", name);
    for (size_t k = 0; k < n; k++) {
        printf("%s%.9g", k ? "," : "", (double)v[k]);
    }
    printf("]");
}

static void wind_steady(void *user, const float p[3], float out[3])
{
    (void)user;
    out[0] = 15.0f;
    out[1] = -4.0f + 0.1f * p[2]; /* a little shear, so the place matters */
    out[2] = 0.5f;
}

static void uints(const char *name, const uint32_t *v, size_t n)
{
    printf(",\"%s\":[", name);
    for (size_t k = 0; k < n; k++) {
        printf("%s%u", k ? "," : "", v[k]);
    }
    printf("]");
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        int help = strcmp(argv[1], "--help") == 0;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-damage-table\n"
                "  prints gale-client's damage and falling-leaf formulas (tip_fall.c,\n"
                "  damage_clock.c, wire_damage_leaf_kept, falling_path.c) for a grid of\n"
                "  inputs, one JSON object a line\n");
        return help ? 0 : 2;
    }
    static const double ts[] = { -1.0, 0.0, 0.05, 0.3, 0.7, 1.2, 2.0, 3.5, 10.0, 100.0 };
    static const double hs[] = { 0.2, 3.0, 9.5, 18.0, 30.0 };
    for (size_t i = 0; i < sizeof ts / sizeof ts[0]; i++) {
        for (size_t j = 0; j < sizeof hs / sizeof hs[0]; j++) {
            printf("{\"k\":\"tip\",\"t_s\":%.17g,\"h_m\":%.17g,\"rad\":%.17g}\n", ts[i], hs[j],
                   tip_fall_angle(ts[i], hs[j]));
        }
    }
    for (uint32_t t = 0; t < 40; t++) {
        uint32_t tree = t * 977u + (t > 30 ? 200000u : 0u);
        printf("{\"k\":\"break\",\"tree\":%u,\"m\":%.9g}\n", tree, (double)tip_fall_break_m(tree));
    }
    static const uint32_t ev[][2] = { { 1000, 1000 }, { 1000, 990 }, { 1000, 820 }, { 1000, 819 },
                                      { 1000, 1010 }, { 5, 4294967290u }, { 1000, 0 } };
    for (size_t i = 0; i < sizeof ev / sizeof ev[0]; i++) {
        double s = damage_event_start_s(ev[i][0], 16683333ull, ev[i][1], 60.0);
        char v[40] = "null"; /* NaN: too old to animate */
        if (!isnan(s)) {
            snprintf(v, sizeof v, "%.17g", s);
        }
        printf("{\"k\":\"clock\",\"frame_tick\":%u,\"event_tick\":%u,\"time_us\":16683333,"
               "\"hz\":60,\"start_s\":%s}\n",
               ev[i][0], ev[i][1], v);
    }
    printf("{\"k\":\"kept\",\"levels\":[0,1,8,20,31,32]");
    for (uint32_t tree = 0; tree < 6; tree++) {
        char name[16];
        uint32_t bits[6 * 64];
        static const uint32_t lv[6] = { 0, 1, 8, 20, 31, 32 };
        for (uint32_t l = 0; l < 6; l++) {
            for (uint32_t s = 0; s < 64; s++) {
                bits[l * 64 + s] = wire_damage_leaf_kept(tree * 131u, s * 7u, lv[l]);
            }
        }
        snprintf(name, sizeof name, "tree%u", tree * 131u);
        uints(name, bits, 6 * 64);
    }
    printf("}\n");
    static falling_path p;
    gale_err err = { 0 };
    if (falling_path_build(&p, NULL, &err) != 0) {
        fprintf(stderr, "gale-web-damage-table: %s\n", err.msg);
        return 1;
    }
    printf("{\"k\":\"path\",\"n\":%u,\"dt\":%.9g,\"fall_speed\":%.9g", p.n, (double)p.dt,
           (double)p.fall_speed);
    uints("start", p.start, p.n_start);
    uints("cont", p.cont, p.n_cont);
    floats("pos", &p.pos[0][0], 3 * (size_t)p.n);
    floats("quat", &p.quat[0][0], 4 * (size_t)p.n);
    printf("}\n");
    static const float taus[] = { 0.0f, 0.1f, 0.75f, 2.5f, 7.9f, 8.05f, 15.0f, 31.0f, 120.0f };
    for (uint32_t k = 0; k < 24; k++) {
        uint32_t seed = k * 2654435761u + 17u;
        falling_var v;
        falling_var_from_seed(&p, seed, &v);
        printf("{\"k\":\"leaf\",\"seed\":%u,\"start\":%u,\"yaw\":%.9g,\"sx\":%.9g,\"sy\":%.9g,"
               "\"vseed\":%u",
               seed, v.start, (double)v.yaw, (double)v.sx, (double)v.sy, v.seed);
        float pos[9 * 3];
        for (size_t i = 0; i < 9; i++) {
            float q[4];
            falling_path_eval(&p, &v, taus[i], &pos[3 * i], q);
        }
        floats("tau", taus, 9);
        floats("pos", pos, 27);
        const float h0 = 0.5f + 1.5f * (float)k;
        printf(",\"h0\":%.9g,\"land_s\":%.9g}\n", (double)h0,
               (double)falling_path_land_time(&p, &v, h0, 600.0f));
    }
    static const int32_t parent[12] = { -1, 0, 0, 1, 1, 2, 3, 3, 5, 6, 7, 7 };
    static const uint32_t cut[2] = { 3, 5 };
    for (int keep = 0; keep < 2; keep++) {
        uint8_t m[12];
        uint32_t mv[12];
        damage_cut_mask(parent, 12, cut, 2, keep != 0, m);
        for (int i = 0; i < 12; i++) {
            mv[i] = m[i];
        }
        printf("{\"k\":\"cut\",\"keep\":%d", keep);
        uints("mask", mv, 12);
        printf("}\n");
    }
    debris_path d;
    float r0[9];
    debris_frame_matrix(0.3f, 0.2f, 1.1f, r0);
    const float c0[3] = { 1.0f, 2.0f, 9.0f }, axis[3] = { 0.2f, 0.1f, 1.0f };
    debris_path_start(&d, 7, 33, 100.0, c0, r0, axis, 2.5f);
    static const double at[] = { 100.0, 100.5, 101.0, 102.0, 104.0, 110.0, 150.0, 152.0, 200.0 };
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
        debris_path_advance(&d, at[i], wind_steady, NULL);
        float r[9], yaw, fall, az;
        debris_path_rotation(&d, r);
        debris_frame_angles(r, &yaw, &fall, &az);
        printf("{\"k\":\"debris\",\"t_s\":%.17g,\"landed\":%d,\"done\":%d,\"sink_m\":%.9g", at[i],
               d.landed, debris_path_done(&d), (double)debris_path_sink_m(&d));
        floats("r0", r0, 9);
        floats("c", d.c, 3);
        floats("r", r, 9);
        const float ang[3] = { yaw, fall, az };
        floats("angles", ang, 3);
        printf("}\n");
    }
    return 0;
}
