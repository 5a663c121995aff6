/* gale-bench views: the server's cost of per-client views on a scene's trees (by default
 * the 2 km landscape, configs/scenes/landscape-2km.json: 100,000 trees). N distinct
 * frustum views, street, roof and aerial in turn (view_kinds.h) at seeded places over the
 * scene, with lod_m (SERVER.md "Views and LOD"), each a stream encoded by the server's encoder
 * (srv_stream_encode, on the tick's lanes) for every snapshot of a run, as the server
 * encodes them after a tick. Per view: the selection when the view changes (view_select,
 * the rule tree by tree, and view_select_grid, the server's), the encode of each
 * snapshot (delta2 in the steady state, a keyframe on the periodic seqs), and the view's
 * bytes; the sum over the views as a fraction of the snapshot period. The q of every
 * tree is synthetic (a sine per mode, a phase per tree), so bytes are indicative only;
 * the live server's are in SERVER.md. Prints JSON. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "mono.h"
#include "scene.h"
#include "sim_lanes.h"
#include "srv_stream.h"
#include "view_kinds.h"
#include "view_select.h"

#define SRV_LOD_MODES_BENCH 4 /* the server's SRV_LOD_MODES */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Percentile p in [0, 1] of v[n] (sorts v). */
static double pct(double *v, size_t n, double p)
{
    if (!n) {
        return 0.0;
    }
    qsort(v, n, sizeof *v, cmp_double);
    size_t k = (size_t)(p * (double)(n - 1) + 0.5);
    return v[k < n ? k : n - 1];
}

/* Snapshot seq's q: per mode m a sine of 0.3 + 0.1 m Hz and amplitude 400 / (1 + m)
 * steps, a phase per tree, at 30 snapshots a second. */
static void fill_q(int16_t *q, uint32_t n, uint32_t stride, uint32_t seq)
{
    enum { TURN = 4096 }; /* a sine table of one turn: the run's q costs little */
    static int16_t table[TURN];
    if (!table[TURN / 4]) {
        for (int i = 0; i < TURN; i++) {
            table[i] = (int16_t)lrint(400.0 * sin(2.0 * 3.14159265358979 * i / TURN));
        }
    }
    for (uint32_t m = 0; m < stride; m++) {
        /* (0.3 + 0.1 m) Hz at 30 snapshots a second, in table steps a snapshot */
        const uint32_t step = (uint32_t)lrint((0.3 + 0.1 * m) / 30.0 * TURN);
        for (uint32_t t = 0; t < n; t++) {
            const uint32_t at = (seq * step + t * 2531u) % TURN; /* a phase per tree */
            q[(size_t)t * stride + m] = (int16_t)(table[at] / (int)(1 + m));
        }
    }
}

int bench_views(int argc, char **argv)
{
    const char *config = "configs/scenes/landscape-2km.json";
    int n_views = 20, n_snaps = 150, threads = 2;
    float lod_m = 120.0f, margin_m = 25.0f, cell_m = 32.0f;
    bool json_only = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
            config = argv[++i];
        } else if (strcmp(argv[i], "--views") == 0 && i + 1 < argc) {
            n_views = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--snapshots") == 0 && i + 1 < argc) {
            n_snaps = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            threads = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--lod-m") == 0 && i + 1 < argc) {
            lod_m = strtof(argv[++i], NULL);
        } else if (strcmp(argv[i], "--margin-m") == 0 && i + 1 < argc) {
            margin_m = strtof(argv[++i], NULL);
        } else if (strcmp(argv[i], "--cell-m") == 0 && i + 1 < argc) {
            cell_m = strtof(argv[++i], NULL);
        } else if (strcmp(argv[i], "--json") == 0) {
            json_only = true;
        } else {
            return bench_usage(argv[i],
                               "usage: gale-bench views [--config SCENE] [--views N] "
                               "[--snapshots K] [--threads T] [--lod-m 120] [--margin-m 25] "
                               "[--cell-m 32] [--json]\n"
                               "  --config    the scene (default "
                               "configs/scenes/landscape-2km.json)\n"
                               "  --margin-m  the scene's tallest tree [m] (the server's "
                               "view margin)\n"
                               "  --cell-m    the selection grid's cells [m]\n");
        }
    }
    if (n_views < 1 || n_views > 1024 || n_snaps < 10 || threads < 1 || threads > 64 ||
        !(lod_m >= 0.0f) || !(margin_m >= 0.0f) || !(cell_m > 0.0f)) {
        fprintf(stderr, "gale-bench views: --views 1..1024, --snapshots >= 10, --threads "
                        "1..64, --lod-m >= 0, --margin-m >= 0, --cell-m > 0\n");
        return 2;
    }
    scene sc;
    gale_err err;
    if (scene_load(&sc, config, &err)) {
        fprintf(stderr, "gale-bench views: %s\n", err.msg);
        return 1;
    }
    const uint32_t n = (uint32_t)sc.n_trees;
    uint32_t stride = 1;
    wire_scene ws = { .n_trees = n, .n_species = (uint32_t)sc.n_species };
    for (int s = 0; s < sc.n_species; s++) {
        ws.n_modes[s] = (uint8_t)sc.species[s].modes;
        stride = (uint32_t)sc.species[s].modes > stride ? (uint32_t)sc.species[s].modes : stride;
        for (int m = 0; m < sc.species[s].modes; m++) {
            ws.step[s][m] = 1e-3f;
        }
    }
    uint8_t *species = malloc(n ? n : 1), *full = malloc(n ? n : 1);
    float *pos = malloc(sizeof(float) * 3 * (n ? n : 1));
    int16_t *q[3];
    for (int k = 0; k < 3; k++) {
        q[k] = malloc(sizeof(int16_t) * stride * (n ? n : 1));
    }
    uint8_t **modes = calloc((size_t)n_views, sizeof *modes);
    srv_stream *st = calloc((size_t)n_views, sizeof *st);
    const size_t cap = wire_state_bound(n, stride, ws.n_species);
    net_snap out = { .cap = cap, .key = malloc(cap), .delta1 = malloc(cap),
                     .delta2 = malloc(cap) };
    const size_t n_samples = (size_t)n_views * (size_t)n_snaps;
    double *enc_us = malloc(sizeof(double) * n_samples);
    double *sel_ref_us = malloc(sizeof(double) * (size_t)n_views);
    double *sel_grid_us = malloc(sizeof(double) * (size_t)n_views);
    double *key_us = malloc(sizeof(double) * (size_t)n_views);
    double *snap_sum_us = malloc(sizeof(double) * (size_t)n_snaps);
    double *trees_in = malloc(sizeof(double) * (size_t)n_views);
    double *kind_us[3]; /* encode times by kind of view: street, roof, aerial */
    size_t kind_n[3] = { 0, 0, 0 };
    double kind_in[3] = { 0, 0, 0 };
    for (int k = 0; k < 3; k++) {
        kind_us[k] = malloc(sizeof(double) * n_samples);
    }
    int rc = 1;
    if (!species || !full || !pos || !q[0] || !q[1] || !q[2] || !modes || !st || !out.key ||
        !out.delta1 || !out.delta2 || !enc_us || !sel_ref_us || !sel_grid_us || !key_us ||
        !snap_sum_us || !trees_in || !kind_us[0] || !kind_us[1] || !kind_us[2]) {
        fprintf(stderr, "gale-bench views: out of memory\n");
        goto done;
    }
    float half_m = 1.0f;
    for (uint32_t t = 0; t < n; t++) {
        species[t] = (uint8_t)sc.trees[t].species;
        full[t] = ws.n_modes[species[t]];
        for (int a = 0; a < 3; a++) {
            pos[3 * t + a] = sc.trees[t].pos[a];
        }
        half_m = fmaxf(half_m, fmaxf(fabsf(pos[3 * t]), fabsf(pos[3 * t + 1])));
    }
    ws.species = species;
    view_grid grid;
    const uint64_t g0 = mono_us();
    if (view_grid_build(&grid, n, pos, cell_m, &err)) {
        fprintf(stderr, "gale-bench views: %s\n", err.msg);
        goto done;
    }
    const double grid_build_ms = (double)(mono_us() - g0) * 1e-3;
    const wire_lanes lanes = sim_lanes(threads);
    const uint32_t key_every = 150; /* 5 s at 30 snapshots a second (SRV_KEYFRAME_S) */
    uint64_t rng = 0x6a09e667f3bcc909ull;
    double sel_bytes = 0.0, mism = 0.0;
    for (int k = 0; k < n_views; k++) {
        modes[k] = malloc(n ? n : 1);
        uint8_t *ref = malloc(n ? n : 1);
        if (!modes[k] || !ref) {
            free(ref);
            fprintf(stderr, "gale-bench views: out of memory\n");
            goto done_grid;
        }
        const ctl_view v = view_kind_make(k % VIEW_KINDS, &rng, 0.9 * (double)half_m, lod_m);
        /* best of 3 each: the selection runs once per view change, not per snapshot */
        sel_ref_us[k] = sel_grid_us[k] = 1e30;
        for (int r = 0; r < 3; r++) {
            uint64_t t0 = mono_us();
            view_select(&v, n, pos, full, margin_m, SRV_LOD_MODES_BENCH, ref);
            uint64_t t1 = mono_us();
            view_select_grid(&grid, &v, full, margin_m, SRV_LOD_MODES_BENCH, modes[k]);
            uint64_t t2 = mono_us();
            sel_ref_us[k] = fmin(sel_ref_us[k], (double)(t1 - t0));
            sel_grid_us[k] = fmin(sel_grid_us[k], (double)(t2 - t1));
        }
        mism += memcmp(ref, modes[k], n) != 0;
        free(ref);
        uint32_t in = 0;
        for (uint32_t t = 0; t < n; t++) {
            in += modes[k][t] != 0;
            sel_bytes += modes[k][t];
        }
        trees_in[k] = in;
        kind_in[k % 3] += in / ((n_views - k % 3 + 2) / 3);
        srv_stream_start(&st[k], (uint32_t)k + 1, modes[k], key_every);
    }
    /* the run: 2 snapshots to fill the history, then n_snaps timed */
    double bytes_delta = 0.0, bytes_key = 0.0;
    size_t n_delta = 0, n_key = 0, ns = 0;
    int ki = 0;
    for (int s = -2; s < n_snaps; s++) {
        const uint32_t seq = (uint32_t)(s + 3);
        fill_q(q[seq % 3], n, stride, seq);
        const srv_qhist qh = { .q = { q[seq % 3], q[(seq + 2) % 3], q[(seq + 1) % 3] },
                               .n_trees = n, .stride = stride, .lanes = &lanes };
        const wire_header h = { .tick = 2 * seq, .server_time_us = mono_us() };
        double sum = 0.0;
        for (int k = 0; k < n_views; k++) {
            uint64_t t0 = mono_us();
            if (srv_stream_encode(&st[k], &h, seq, &ws, &qh, 0, &out, &err)) {
                fprintf(stderr, "gale-bench views: view %d: %s\n", k, err.msg);
                goto done_grid;
            }
            const double us = (double)(mono_us() - t0);
            if (s < 0) {
                if (s == -2) {
                    key_us[ki++] = us; /* a stream's first snapshot: the keyframe */
                }
                continue;
            }
            enc_us[ns++] = us;
            kind_us[k % 3][kind_n[k % 3]++] = us;
            sum += us;
            if (out.delta2_len) {
                bytes_delta += (double)out.delta2_len;
                n_delta++;
            } else {
                bytes_key += (double)out.key_len;
                n_key++;
            }
        }
        if (s >= 0) {
            snap_sum_us[s] = sum;
        }
    }
    const double period_us = 1e6 / (sc.snapshot_hz > 0 ? sc.snapshot_hz : 30.0);
    const double mean_in = pct(trees_in, (size_t)n_views, 0.5);
    const double ref_med = pct(sel_ref_us, (size_t)n_views, 0.5),
                 ref_p99 = pct(sel_ref_us, (size_t)n_views, 0.99);
    const double grid_med = pct(sel_grid_us, (size_t)n_views, 0.5),
                 grid_p99 = pct(sel_grid_us, (size_t)n_views, 0.99);
    const double key_med = pct(key_us, (size_t)n_views, 0.5);
    const double enc_med = pct(enc_us, ns, 0.5), enc_p99 = pct(enc_us, ns, 0.99);
    const double sum_med = pct(snap_sum_us, (size_t)n_snaps, 0.5),
                 sum_p99 = pct(snap_sum_us, (size_t)n_snaps, 0.99);
    (void)json_only;
    double kind_med[3];
    for (int k = 0; k < 3; k++) {
        kind_med[k] = pct(kind_us[k], kind_n[k], 0.5);
    }
    printf("{\"bench\":\"views\",\"config\":\"%s\",\"trees\":%u,\"views\":%d,\"snapshots\":%d,"
           "\"threads\":%d,\"lod_m\":%g,\"margin_m\":%g,\"cell_m\":%g,\"grid_cells\":%u,"
           "\"grid_build_ms\":%.2f,\"trees_in_view_median\":%.0f,"
           "\"modes_per_view_mean\":%.0f,\"grid_mismatches\":%.0f,"
           "\"select_ref_us\":{\"median\":%.1f,\"p99\":%.1f},"
           "\"select_grid_us\":{\"median\":%.1f,\"p99\":%.1f},"
           "\"encode_key_us_median\":%.1f,"
           "\"encode_us_per_view_snapshot\":{\"median\":%.1f,\"p99\":%.1f},"
           "\"encode_us_per_snapshot_all_views\":{\"median\":%.1f,\"p99\":%.1f},"
           "\"snapshot_period_fraction\":{\"median\":%.4f,\"p99\":%.4f},"
           "\"bytes_per_view_snapshot\":{\"delta2\":%.0f,\"keyframe\":%.0f},"
           "\"by_kind\":{\"street\":{\"trees_in_view\":%.0f,\"encode_us_median\":%.1f},"
           "\"roof\":{\"trees_in_view\":%.0f,\"encode_us_median\":%.1f},"
           "\"aerial\":{\"trees_in_view\":%.0f,\"encode_us_median\":%.1f}}}\n",
           config, n, n_views, n_snaps, threads, (double)lod_m, (double)margin_m,
           (double)grid.cell_m, grid.nx * grid.ny, grid_build_ms, mean_in,
           sel_bytes / n_views, mism, ref_med, ref_p99, grid_med, grid_p99, key_med, enc_med,
           enc_p99, sum_med, sum_p99, sum_med / period_us, sum_p99 / period_us,
           n_delta ? bytes_delta / (double)n_delta : 0.0,
           n_key ? bytes_key / (double)n_key : 0.0, kind_in[0], kind_med[0], kind_in[1],
           kind_med[1], kind_in[2], kind_med[2]);
    rc = mism > 0.0;
done_grid:
    view_grid_fini(&grid);
done:
    for (int k = 0; modes && k < n_views; k++) {
        free(modes[k]);
    }
    free(modes);
    free(st);
    free(out.key);
    free(out.delta1);
    free(out.delta2);
    free(enc_us);
    free(sel_ref_us);
    free(sel_grid_us);
    free(key_us);
    free(snap_sum_us);
    free(trees_in);
    for (int k = 0; k < 3; k++) {
        free(kind_us[k]);
    }
    for (int k = 0; k < 3; k++) {
        free(q[k]);
    }
    free(species);
    free(full);
    free(pos);
    scene_fini(&sc);
    return rc;
}
