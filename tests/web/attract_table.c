/* gale-client's attract mode over a fixed scene, one JSON object a line, for
 * tests/web/test_attract_js.mjs to hold web/attract.js to: the camera tour's orbit at
 * times through every stop (client/kiosk/camera_preset.c), and the idle clock's answers to a
 * sequence of ticks and touches (client/kiosk/attract.c). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "attract.h"
#include "camera_preset.h"

#define N_TREES 23

int main(int argc, char **argv)
{
    if (argc > 1) {
        bool help = strcmp(argv[1], "--help") == 0;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-attract-table\n"
                "  prints the scene (\"scene\"), the attract tour's camera at times through\n"
                "  its stops (\"tour\") and the idle clock's answers (\"clock\"), JSON lines\n");
        return help ? 0 : 2;
    }
    ctl_species sp[3] = { { .name = "pine" }, { .name = "sabal_palm" }, { .name = "live_oak" } };
    ctl_instance inst[N_TREES];
    printf("{\"scene\":{\"species\":[\"pine\",\"sabal_palm\",\"live_oak\"],\"instances\":[");
    for (int i = 0; i < N_TREES; i++) {
        /* a scattered planting, off the origin */
        inst[i] = (ctl_instance){ .species = (uint32_t)(i % 3),
                                  .pos = { 12.0f + 31.0f * sinf(1.7f * (float)i),
                                           -5.0f + 27.0f * cosf(2.3f * (float)i),
                                           0.1f * (float)(i % 4) },
                                  .scale = 1.0f };
        printf("%s[%u,%.9g,%.9g,%.9g,0,1]", i ? "," : "", inst[i].species,
               (double)inst[i].pos[0], (double)inst[i].pos[1], (double)inst[i].pos[2]);
    }
    printf("]}}\n");
    static const double times[] = { 0.0, 7.5, 19.99, 20.0, 33.0, 45.5, 61.0, 79.9, 80.0, 95.0, 163.0 };
    for (size_t k = 0; k < sizeof times / sizeof times[0]; k++) {
        camera c;
        camera_preset_tour(&c, times[k], inst, N_TREES, sp, 3);
        printf("{\"tour\":{\"t_s\":%.9g,\"target\":[%.9g,%.9g,%.9g],\"distance\":%.9g,"
               "\"yaw\":%.9g,\"pitch\":%.9g}}\n",
               times[k], (double)c.target[0], (double)c.target[1], (double)c.target[2],
               (double)c.distance, (double)c.yaw, (double)c.pitch);
    }
    /* the idle clock: 5 s idle, ticks and touches in time order */
    attract a;
    attract_init(&a, 5.0, 0.0);
    static const struct { char op; double t; } seq[] = {
        { 't', 1.0 }, { 't', 4.9 }, { 't', 5.0 }, { 't', 6.0 }, { 'i', 7.0 }, { 't', 11.0 },
        { 't', 12.0 }, { 'i', 12.5 }, { 'i', 13.0 }, { 't', 17.9 }, { 't', 18.0 },
    };
    for (size_t k = 0; k < sizeof seq / sizeof seq[0]; k++) {
        bool r = seq[k].op == 't' ? attract_tick(&a, seq[k].t) : attract_input(&a, seq[k].t);
        printf("{\"clock\":{\"idle_s\":5,\"op\":\"%s\",\"t_s\":%.9g,\"result\":%s,\"active\":%s,"
               "\"card\":%d,\"card_later\":%d}}\n",
               seq[k].op == 't' ? "tick" : "input", seq[k].t, r ? "true" : "false",
               a.active ? "true" : "false", attract_card(&a, seq[k].t),
               attract_card(&a, seq[k].t + 1.5 * ATTRACT_CARD_S));
    }
    return 0;
}
