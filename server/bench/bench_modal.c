/* gale-bench modal: the per-tick cost of the batch modal update (server/sim/modal.c) for
 * many trees: wind sampled at each tree from the real wind field (wind_sample_many on a
 * grid of scene-scale cells, 2 m by default, over the trees' 2 km square, stepped by the
 * real solver every few ticks under a gusty inflow so the field evolves), forces
 * f_i = |v| v.p_i in the tree frame, exact update, quantisation into the snapshot buffer,
 * leaf shedding at each tree's wind speed (leaf.c) and the snapshot's DELTA encoding
 * (wire_encode_delta): all timed as the tick. Prints JSON; medians over the ticks, with
 * the tick's byte model, the memory floor it implies and the machine's triad bandwidth
 * measured in the same run (bench_triad.c). The wind step itself is timed apart (and in
 * gale-bench wind). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mono.h"
#include "bench.h"
#include "bake.h"
#include "damage.h"
#include "leaf.h"
#include "lsystem.h"
#include "modal.h"
#include "wind.h"
#include "wire.h"


/* CPU time of the whole process (all threads) [ms]: on a loaded machine the wall time
 * counts other programs' turns, the CPU time only this one's work (and spinning). */
static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Orders tree positions (x, y, z) by their 16 m column: row y first, then x. */
static int cmp_cell(const void *a, const void *b)
{
    const float *p = a, *q = b;
    long ka = (long)(p[1] / 16.0f) * 4096 + (long)(p[0] / 16.0f);
    long kb = (long)(q[1] / 16.0f) * 4096 + (long)(q[0] / 16.0f);
    if (ka != kb) {
        return (ka > kb) - (ka < kb);
    }
    return (p[0] > q[0]) - (p[0] < q[0]); /* ties by x: the order is fully defined */
}

/* Bytes one tick moves per tree at least, array by array (each read or written once per
 * pass; the species constants, the wind grid and the padding lanes' coefficients are a
 * few MB at most and stay in cache, so they are not counted; write-allocate is not
 * counted, as in the triad). modal.c keeps each tree's q and q' as 2 x pad floats, pad
 * the modes rounded up to its 16-lane groups (MODE_PAD):
 *   sampling (wind_sample_many): position 12 read, wind 12 written;
 *   update (modal_tick): wind 12, cos/sin of the yaw 8, species index 1 and the state
 *   8 pad read; the state 8 pad written, and with a snapshot the int16 row 2 modes. */
typedef struct modal_bytes {
    double read, written; /* per tree per tick */
} modal_bytes;

static modal_bytes modal_tree_bytes(int n_modes, bool sample, bool snapshot)
{
    const double pad = (double)((n_modes + 15) / 16 * 16);
    modal_bytes b = { 12.0 + 8.0 + 1.0 + 8.0 * pad, 8.0 * pad };
    if (snapshot) {
        b.written += 2.0 * n_modes;
    }
    if (sample) {
        b.read += 12.0;
        b.written += 12.0;
    }
    return b;
}

static double pct(double *v, int n, double p)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    int i = (int)(p * (n - 1) + 0.5);
    return v[i];
}

/* What --damage adds: the shipped oak baked at the bench's mode count, its damage
 * table for every species, the damage state of every tree. */
typedef struct damage_bench {
    asset a;
    damage_table t;
    damage_sim *sim;
    leaf_seed leaves[4096];
} damage_bench;

static int damage_bench_init(damage_bench *b, modal *m, int n_trees, int n_modes,
                             int n_species, const uint8_t *ts, const float *yaw, gale_err *err)
{
    (void)m;
    memset(b, 0, sizeof *b);
    species sp;
    skeleton sk;
    memset(&sk, 0, sizeof sk);
    int rc = species_load(GALE_SOURCE_DIR "/configs/species/oak.json", &sp, err);
    rc = rc ? rc : lsystem_generate(&sp.gen, &sk, err);
    rc = rc ? rc : bake_run(&sk, &sp, &(bake_desc){ .n_modes = n_modes }, &b->a, NULL, err);
    rc = rc ? rc : damage_table_build(&b->a, sp.E_pa, &sp.damage, &b->t, err);
    skeleton_fini(&sk);
    if (rc) {
        return rc;
    }
    const damage_table *tables[WIRE_MAX_SPECIES];
    for (int k = 0; k < n_species; k++) {
        tables[k] = &b->t;
    }
    b->sim = damage_create(&(damage_desc){ .n_trees = (uint32_t)n_trees,
                                           .n_species = (uint32_t)n_species,
                                           .table = tables,
                                           .tree_species = ts,
                                           .tree_yaw_rad = yaw,
                                           .seed = 1,
                                           .dt_s = 1.0 / 60 },
                           err);
    return b->sim ? 0 : GALE_E_NOMEM;
}

static void damage_bench_fini(damage_bench *b)
{
    damage_destroy(b->sim);
    damage_table_fini(&b->t);
    asset_fini(&b->a);
}


int bench_modal(int argc, char **argv)
{
    int n_trees = 100000, n_modes = 32, ticks = 300, n_species = 3, threads = 2, every = 4;
    float cell_m = 2.0f;
    bool json = false, damage = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--trees") == 0 && i + 1 < argc) {
            n_trees = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--modes") == 0 && i + 1 < argc) {
            n_modes = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--ticks") == 0 && i + 1 < argc) {
            ticks = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--species") == 0 && i + 1 < argc) {
            n_species = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            threads = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--cell-m") == 0 && i + 1 < argc) {
            cell_m = (float)atof(argv[++i]);
        } else if (strcmp(argv[i], "--wind-every") == 0 && i + 1 < argc) {
            every = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if (strcmp(argv[i], "--damage") == 0) {
            damage = true;
        } else {
            return bench_usage(argv[i], "usage: gale-bench modal [--trees N] [--modes M] [--species S] "
                                        "[--ticks K] [--threads T] [--cell-m 2] [--wind-every 4] "
                                        "[--damage] [--json]\n");
        }
    }
    if (n_trees < 1 || n_trees > (int)WIRE_MAX_TREES || n_modes < 1 ||
        n_modes > (int)WIRE_MAX_MODES || ticks < 10 || n_species < 1 ||
        n_species > (int)WIRE_MAX_SPECIES || threads < 1 || threads > 64 ||
        !(cell_m >= 1.0f && cell_m <= 64.0f) || every < 1 || every > 1000) {
        fprintf(stderr, "gale-bench modal: --trees 1..%u, --modes 1..%u, --species 1..%u, "
                        "--ticks >= 10, --threads 1..64, --cell-m 1..64, --wind-every 1..1000\n",
                WIRE_MAX_TREES, WIRE_MAX_MODES, WIRE_MAX_SPECIES);
        return 2;
    }
    uint64_t s = 12345;
#define RND() ((s = s * 6364136223846793005ull + 1442695040888963407ull), (float)(s >> 40) / 16777216.0f)
    float *omega = malloc(sizeof(float) * (size_t)n_species * (size_t)n_modes);
    float *gamma = malloc(sizeof(float) * (size_t)n_species * (size_t)n_modes);
    float *p = malloc(sizeof(float) * 3 * (size_t)n_species * (size_t)n_modes);
    float *step = malloc(sizeof(float) * (size_t)n_species * (size_t)n_modes);
    modal_species *sp = calloc((size_t)n_species, sizeof *sp);
    uint8_t *ts = malloc((size_t)n_trees);
    float *yaw = malloc(sizeof(float) * (size_t)n_trees);
    float *pos = malloc(sizeof(float) * 3 * (size_t)n_trees);
    float *wind = malloc(sizeof(float) * 3 * (size_t)n_trees);
    int16_t *snap = malloc(sizeof(int16_t) * (size_t)n_trees * (size_t)n_modes);
    double *t_sample = malloc(sizeof(double) * (size_t)ticks);
    double *t_modal = malloc(sizeof(double) * (size_t)ticks);
    double *t_total = malloc(sizeof(double) * (size_t)ticks);
    double *t_cpu = malloc(sizeof(double) * (size_t)ticks);
    double *t_nosnap = malloc(sizeof(double) * (size_t)ticks);
    double *t_leaf = malloc(sizeof(double) * (size_t)ticks);
    double *t_enc = malloc(sizeof(double) * (size_t)ticks);
    double *t_wind = malloc(sizeof(double) * (size_t)ticks);
    int16_t *prev = calloc((size_t)n_trees * (size_t)n_modes, sizeof(int16_t));
    uint8_t *nm = malloc((size_t)n_trees);
    const size_t enc_cap = wire_state_bound((uint32_t)n_trees, (uint32_t)n_modes,
                                            (uint32_t)n_species);
    uint8_t *enc = malloc(enc_cap);
    enum { LEAF_CAP = 65536 };
    leaf_seed *leaves = malloc(LEAF_CAP * sizeof *leaves);
    if (!omega || !gamma || !p || !step || !sp || !ts || !yaw || !pos || !wind ||
        !snap || !t_sample || !t_modal || !t_total || !t_cpu || !t_nosnap || !t_leaf ||
        !t_enc || !t_wind || !prev || !nm || !enc || !leaves) {
        fprintf(stderr, "gale-bench modal: out of memory\n");
        return 1;
    }
    for (int k = 0; k < n_species; k++) {
        for (int i = 0; i < n_modes; i++) {
            int j = k * n_modes + i;
            /* First modes 0.3-2 Hz rising to tens of Hz (PHYSICS.md "Modes"). */
            omega[j] = 6.2831853f * (0.3f + 0.7f * (float)i * (float)i / 4.0f + RND());
            gamma[j] = 0.1f + 1e-3f * omega[j] * omega[j] * 0.01f;
            for (int c = 0; c < 3; c++) {
                p[3 * j + c] = 0.01f * (RND() - 0.5f);
            }
            step[j] = 1e-4f;
        }
        sp[k] = (modal_species){ (uint32_t)n_modes, omega + k * n_modes, gamma + k * n_modes,
                                 p + 3 * k * n_modes, step + k * n_modes };
    }
    const float side = 2000.0f;
    for (int t = 0; t < n_trees; t++) {
        ts[t] = (uint8_t)(t % n_species);
        yaw[t] = 6.2831853f * RND();
        pos[3 * t] = side * RND();
        pos[3 * t + 1] = side * RND();
        pos[3 * t + 2] = 5.0f + 10.0f * RND();
    }
    /* Trees are static: stored once in the order of the 16 m wind cells they stand in
     * (rows of y, then x), as a scene loader would keep them, so consecutive samples
     * read neighbouring grid lines instead of missing the cache at random. */
    qsort(pos, (size_t)n_trees, 3 * sizeof(float), cmp_cell);
    gale_err err;
    modal *m = modal_create(&(modal_desc){ .n_trees = (uint32_t)n_trees,
                                           .n_species = (uint32_t)n_species, .species = sp,
                                           .tree_species = ts, .tree_yaw_rad = yaw,
                                           .dt_s = 1.0 / 60, .n_threads = threads },
                            &err);
    if (!m) {
        fprintf(stderr, "gale-bench modal: %s\n", err.msg);
        return 1;
    }
    /* cells of cell_m over the 2 km square the trees stand in, 8 cells deep (at 2 m the
       16 m the crowns reach; the grid is capped at the scene's 2^24 cells) */
    const int gxy = (int)ceilf(side / cell_m);
    const int gz = 8;
    if ((double)gxy * gxy * gz > (double)(1 << 24)) {
        fprintf(stderr, "gale-bench modal: --cell-m %g: %d x %d x %d cells, expected at most "
                        "2^24\n", (double)cell_m, gxy, gxy, gz);
        return 2;
    }
    wind_grid *wg = wind_create(&(wind_desc){ .nx = gxy, .ny = gxy, .nz = gz, .cell_m = cell_m,
                                              .threads = threads, .seed = 7 },
                                &err);
    if (!wg) {
        fprintf(stderr, "gale-bench modal: wind: %s\n", err.msg);
        return 1;
    }
    wind_set_inflow(wg, &(wind_inflow){ .dir_rad = 0.3f, .u10_ms = 25.0f });
    wind_fill_inflow(wg);
    for (int k = 0; k < 3; k++) {
        wind_set_inflow(wg, &(wind_inflow){ .dir_rad = 0.3f, .u10_ms = 25.0f,
                                            .gust = { 5.0f * (RND() - 0.5f), 5.0f * (RND() - 0.5f), 0 } });
        if (wind_step(wg, 1.0f / 60, NULL) != 0) {
            fprintf(stderr, "gale-bench modal: wind step failed\n");
            return 1;
        }
    }
    /* the snapshot as the server encodes it: every tree, all its modes, 1e-4 steps */
    wire_scene wsc = { .n_trees = (uint32_t)n_trees, .n_species = (uint32_t)n_species,
                       .species = ts };
    for (int k = 0; k < n_species; k++) {
        wsc.n_modes[k] = (uint8_t)n_modes;
        for (int i = 0; i < n_modes; i++) {
            wsc.step[k][i] = 1e-4f;
        }
    }
    memset(nm, n_modes, (size_t)n_trees);
    const wire_state cur_st = { (uint32_t)n_trees, (uint32_t)n_modes, nm, snap };
    const wire_state prev_st = { (uint32_t)n_trees, (uint32_t)n_modes, nm, prev };
    const leaf_desc ld = { .rate_hz = 0.002f, .calm_ms = 3.0f, .ref_ms = 20.0f, .seed = 11 };
    const uint32_t slots = 1500; /* leaf slots per tree: the shipped species' 1500-5300 */
    long n_shed = 0, enc_bytes = 0;
    /* --damage: storm damage after each update (damage.h), every species with the damage
     * table of the shipped oak */
    damage_bench db;
    if (damage && damage_bench_init(&db, m, n_trees, n_modes, n_species, ts, yaw, &err)) {
        fprintf(stderr, "gale-bench modal: --damage: %s\n", err.msg);
        return 1;
    }
    /* measured here, between the set-up and the ticks, on the threads the ticks use */
    double gbs = bench_triad_gb_s(threads);
    for (int k = -20; k < ticks; k++) { /* 20 warm-up ticks */
        double tw = 0.0;
        if ((k + 20) % every == 0) { /* the field evolves as the scene's grid would */
            wind_set_inflow(wg, &(wind_inflow){ .dir_rad = 0.3f, .u10_ms = 25.0f,
                                                .gust = { 5.0f * (RND() - 0.5f),
                                                          5.0f * (RND() - 0.5f), 0 } });
            double w0 = mono_ms();
            if (wind_step(wg, (float)every / 60.0f, NULL) != 0) {
                fprintf(stderr, "gale-bench modal: wind step failed\n");
                return 1;
            }
            tw = mono_ms() - w0;
        }
        memcpy(prev, snap, sizeof(int16_t) * (size_t)n_trees * (size_t)n_modes);
        double c0 = cpu_ms();
        double t0 = mono_ms();
        wind_sample_many(wg, n_trees, pos, wind);
        double t1 = mono_ms();
        modal_tick(m, wind, snap);
        if (damage) {
            int nd = 0;
            damage_step(db.sim, m, wind, (uint32_t)(k + 20), db.leaves, 4096, &nd);
        }
        double t2 = mono_ms();
        int nl = 0;
        for (int t = 0; t < n_trees; t++) {
            const float *v = &wind[3 * t];
            double sp_ms = sqrt((double)(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            leaf_shed(&ld, (uint32_t)t, slots, sp_ms, (uint32_t)(k + 20), 1.0 / 60, leaves,
                      LEAF_CAP, &nl);
        }
        double t2l = mono_ms();
        size_t len = 0;
        wire_header hdr = { .tick = (uint32_t)(k + 20) };
        if (wire_encode_delta(&hdr, (uint32_t)(k + 21), &wsc, &cur_st, &prev_st, NULL, enc,
                              enc_cap, &len, &err) != 0) {
            fprintf(stderr, "gale-bench modal: encode: %s\n", err.msg);
            return 1;
        }
        double t2e = mono_ms();
        double c1 = cpu_ms();
        /* A tick between snapshots: the same update without quantisation. */
        double t3s = mono_ms();
        modal_tick(m, wind, NULL);
        double t3 = mono_ms();
        if (k >= 0) {
            t_sample[k] = t1 - t0;
            t_modal[k] = t2 - t1;
            t_leaf[k] = t2l - t2;
            t_enc[k] = t2e - t2l;
            t_wind[k] = tw;
            n_shed += nl;
            enc_bytes += (long)len;
            t_total[k] = t2e - t0;
            t_cpu[k] = c1 - c0;
            t_nosnap[k] = t3 - t3s;
        }
    }
    long check = 0;
    for (int i = 0; i < n_trees * n_modes; i += 97) {
        check += snap[i];
    }
    double med_s = pct(t_sample, ticks, 0.5), med_m = pct(t_modal, ticks, 0.5);
    double med_t = pct(t_total, ticks, 0.5), p95_t = pct(t_total, ticks, 0.95);
    double max_t = t_total[ticks - 1];
    double med_cpu = pct(t_cpu, ticks, 0.5), med_ns = pct(t_nosnap, ticks, 0.5);
    double med_l = pct(t_leaf, ticks, 0.5), med_e = pct(t_enc, ticks, 0.5);
    double wind_sum = 0.0;
    for (int k = 0; k < ticks; k++) {
        wind_sum += t_wind[k];
    }
    double load[3] = { 0 };
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) {
            load[0] = -1;
        }
        fclose(la);
    }
    /* the tick (sampling, update, quantisation) and the update between snapshots */
    const modal_bytes tb = modal_tree_bytes(n_modes, true, true);
    const modal_bytes ub = modal_tree_bytes(n_modes, false, false);
    /* the DELTA written and the previous snapshot read by the encoder come on top */
    const double enc_per_tick = (double)enc_bytes / ticks;
    const double tick_bytes = (tb.read + tb.written + 2.0 * n_modes) * n_trees + enc_per_tick;
    const double upd_bytes = (ub.read + ub.written) * n_trees;
    const double tick_gbs = med_t > 0.0 ? tick_bytes / (med_t * 1e-3) / 1e9 : 0.0;
    const double upd_gbs = med_ns > 0.0 ? upd_bytes / (med_ns * 1e-3) / 1e9 : 0.0;
    const double frac = gbs > 0.0 ? tick_gbs / gbs : 0.0;
    const double upd_frac = gbs > 0.0 ? upd_gbs / gbs : 0.0;
    if (json) {
        printf("{\"bench\":\"modal\",\"trees\":%d,\"modes\":%d,\"species\":%d,\"threads\":%d,"
               "\"ticks\":%d,\"damage\":%s,\"sample_ms_median\":%.3f,\"update_quantise_ms_median\":%.3f,"
               "\"tick_ms_median\":%.3f,\"tick_ms_p95\":%.3f,\"tick_ms_max\":%.3f,"
               "\"ns_per_tree_mode\":%.3f,\"cpu_ms_per_tick_median\":%.3f,"
               "\"update_only_ms_median\":%.3f,\"loadavg_1min\":%.2f,\"target_ms\":3.0,"
               "\"machine_gb_per_s\":%.2f,\"bytes_per_tree_read\":%.0f,"
               "\"bytes_per_tree_written\":%.0f,\"bytes_per_tick_model\":%.0f,"
               "\"tick_effective_gb_per_s\":%.2f,\"bandwidth_fraction\":%.3f,"
               "\"update_only_bytes_per_tree\":%.0f,\"update_only_effective_gb_per_s\":%.2f,"
               "\"update_only_bandwidth_fraction\":%.3f,\"checksum\":%ld,"
               "\"inputs\":{\"cell_m\":%.1f,\"grid\":[%d,%d,%d],\"wind_every_ticks\":%d,"
               "\"leaf_slots_per_tree\":%u,\"side_m\":%.0f},\"leaf_shed_ms_median\":%.3f,"
               "\"encode_ms_median\":%.3f,\"encoded_bytes_per_tick\":%.0f,"
               "\"leaves_shed_per_tick\":%.1f,\"wind_step_ms_mean\":%.1f,"
               "\"memory_floor_ms\":%.3f,\"loadavg\":[%.2f,%.2f,%.2f]}\n",
               n_trees, n_modes, n_species, threads, ticks, damage ? "true" : "false", med_s,
               med_m, med_t, p95_t, max_t, med_t * 1e6 / ((double)n_trees * n_modes), med_cpu, med_ns, load[0], gbs,
               tb.read, tb.written, tick_bytes, tick_gbs, frac, ub.read + ub.written, upd_gbs,
               upd_frac, check, (double)cell_m, gxy, gxy, gz, every, slots, (double)side, med_l,
               med_e, enc_per_tick, (double)n_shed / ticks, wind_sum / ((ticks + every - 1) / every),
               gbs > 0.0 ? tick_bytes / (gbs * 1e9) * 1e3 : 0.0, load[0], load[1], load[2]);
    } else {
        printf("modal: %d trees x %d modes, %d threads: tick median %.3f ms (sample %.3f, "
               "update+quantise %.3f), p95 %.3f, max %.3f\n"
               "modal: %.0f + %.0f bytes per tree read + written: %.2f GB/s, %.3f of the "
               "machine's triad %.2f GB/s (update alone %.3f)\n",
               n_trees, n_modes, threads, med_t, med_s, med_m, p95_t, max_t, tb.read,
               tb.written, tick_gbs, frac, gbs, upd_frac);
    }
    if (damage) {
        damage_bench_fini(&db);
    }
    modal_destroy(m);
    free(omega);
    free(gamma);
    free(p);
    free(step);
    free(sp);
    free(ts);
    free(yaw);
    free(pos);
    free(wind);
    wind_destroy(wg);
    free(snap);
    free(t_sample);
    free(t_modal);
    free(t_total);
    free(t_cpu);
    free(t_nosnap);
    free(t_leaf);
    free(t_enc);
    free(t_wind);
    free(prev);
    free(nm);
    free(enc);
    free(leaves);
    return 0;
}
