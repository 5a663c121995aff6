/* A small in-process server for the loopback tests: two synthetic species (6 modes
 * each, analytic frequencies), 120 trees, log-law wind, ephemeral port on 127.0.0.1,
 * served on its own thread. Header-only (static), one per test program. */
#ifndef GALE_SERVER_FIXTURE_H
#define GALE_SERVER_FIXTURE_H

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "mono.h"
#include "srv.h"

#define N_TREES 120
#define N_MODES 6

static float omega[2][N_MODES], gamma_[2][N_MODES], basis[2][N_MODES * 3], qstep[2][N_MODES];
static const uint8_t asset_bytes[] = "not a real asset, served verbatim by hash";
static srv *S;
static pthread_t S_thread;
static scene SC;
static double FIXTURE_KEYFRAME_S; /* srv_desc.keyframe_s; 0 = the server's default */
static int FIXTURE_SNDBUF = 16384; /* srv_desc.sndbuf: bytes a stalled reader pins in the kernel */

static void *serve(void *arg)
{
    (void)arg;
    srv_run(S);
    return NULL;
}

static int start_server(void)
{
    char cfg[1024];
    snprintf(cfg, sizeof cfg,
             "{\"name\": \"test\", \"tick_hz\": 60, \"snapshot_hz\": 30,"
             " \"kiosk_token\": \"sesame\","
             " \"species\": [{\"name\": \"a\", \"file\": \"a.json\"}, {\"name\": \"b\", \"file\": \"b.json\"}],"
             " \"forest\": [{\"species\": \"a\", \"count\": %d, \"area_min\": [-40, -40],"
             " \"area_max\": [40, 40], \"min_spacing_m\": 2, \"seed\": 3},"
             " {\"species\": \"b\", \"count\": %d, \"area_min\": [-40, -40],"
             " \"area_max\": [40, 40], \"min_spacing_m\": 2, \"seed\": 4}],"
             " \"wind\": {\"solver\": false, \"u10_ms\": 14, \"dir_deg\": 30}}",
             N_TREES / 2, N_TREES / 2);
    gale_err e;
    if (scene_parse(&SC, "test.json", cfg, strlen(cfg), NULL, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    static srv_species sp[2];
    for (int s = 0; s < 2; s++) {
        for (int m = 0; m < N_MODES; m++) {
            omega[s][m] = (float)(2 * M_PI * (0.4 + 0.37 * m + 0.1 * s));
            gamma_[s][m] = 0.1f * omega[s][m];
            basis[s][3 * m] = 0.02f / (float)(m + 1);
            basis[s][3 * m + 1] = 0.01f * (float)(s + 1);
            basis[s][3 * m + 2] = 0.0f;
            qstep[s][m] = 1e-4f;
        }
        sp[s] = (srv_species){ .modal = { .n_modes = N_MODES, .omega = omega[s], .gamma = gamma_[s],
                                          .wind_basis = basis[s], .height_m = 12, .n_leaves = 400 },
                               .qstep = qstep[s],
                               .asset_bytes = s == 0 ? asset_bytes : NULL,
                               .asset_len = sizeof asset_bytes - 1 };
        snprintf(sp[s].hash, sizeof sp[s].hash, "%016x", 0xabc0 + s);
    }
    S = srv_create(&(srv_desc){ .sc = &SC, .species = sp, .port = -1, .iface = "127.0.0.1",
                                .queue_frames = 4, .stall_ms = 2000, .sndbuf = FIXTURE_SNDBUF,
                                .quiet = 1, .history = 120,
                                .keyframe_s = FIXTURE_KEYFRAME_S },
                   &e);
    if (!S) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    return pthread_create(&S_thread, NULL, serve, NULL);
}

/* Stops the server thread and frees everything. */
static inline void stop_server(void)
{
    srv_stop(S);
    pthread_join(S_thread, NULL);
    srv_destroy(S);
    scene_fini(&SC);
}

#endif
