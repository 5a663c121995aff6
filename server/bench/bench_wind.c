/* gale-bench wind: milliseconds per wind step, divergence reduction and solver cycles
 * on a suburban scene (houses, log-law inflow, a jittered force ball), with the machine's
 * memory bandwidth from a STREAM triad run in the same process (bench_triad.c) and the
 * step's byte model (Oliapuram & Kumar 2010 section 2.4 reports 520 ms serial CPU and
 * 14.1 ms on a GTX 280 for 256x256x16). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mono.h"
#include "bench.h"
#include "hash.h"
#include "scenario.h"
#include "scene.h"
#include "wind.h"
#include "wind_error.h"


/* CPU time of the whole process [ms]: with the machine shared, CPU time per step over the
 * thread count estimates the step's wall time on an idle machine. */
static double bench_cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double quantile(double *v, int n, double q)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    int i = (int)ceil(q * n) - 1;
    return v[i < 0 ? 0 : i >= n ? n - 1 : i];
}

/* Bytes per cell one step moves at least, by phase, array by array (each array read or
 * written once per kernel pass, 4-byte floats; constant-coefficient rows, the vast
 * majority, read no coefficient or mask arrays: their g, diag and end cells come from a
 * per-row table), for `cycles` V-cycles. deploy/wind-cachesim.sh measures the same phases
 * in a cache simulation.
 *   advection: the three components traced in one sweep (wind_advect.c), each read once
 *   and each tmp written once: 24;
 *   forces, borders, divergence: 3 read, b written: 16;
 *   solve: first residual p, b: 8; per V-cycle on the finest level prolongation p read
 *   and written, idiag: 12; 2 red-black sweeps x 2 colour passes x (p, b read, p
 *   written): 48; residual 8; the coarser levels add about 1/7;
 *   projection: p, 3 components read and written: 28. */
typedef struct step_model {
    double advect, forces, solve, project;
} step_model;

static step_model step_bytes_per_cell(double cycles)
{
    return (step_model){ .advect = 24.0, .forces = 16.0,
                         .solve = 8.0 + cycles * (12.0 + 48.0 + 8.0) * (8.0 / 7.0),
                         .project = 28.0 };
}

/* The 1, 5 and 15 minute load averages (zeros where /proc is missing). */
static void loadavg(double l[3])
{
    l[0] = l[1] = l[2] = 0.0;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf %lf %lf", &l[0], &l[1], &l[2]) != 3) {
            l[0] = l[1] = l[2] = 0.0;
        }
        fclose(f);
    }
}

static void compare_drive(void *ctx, double t_s, wind_inflow *in, const wind_ball **balls,
                          int *n_balls)
{
    scenario *sc = ctx;
    scenario_state st;
    scenario_eval(sc, t_s, &st);
    *in = st.inflow;
    *n_balls = scenario_balls(sc, balls);
}

/* gale-bench wind --compare SCENARIO: the landscape method (a coarse grid with the
 * subgrid profile) against today's uniform 2 m grid at tree points, both driven by the
 * scenario (wind_error.h). */
static int bench_wind_compare(const char *file, int argc, char **argv)
{
    double region_m = 256.0, record_s = 60.0, spinup_s = 10.0;
    int n_points = 400, ref_nz = 8, ref_every = 4, test_nz = 2, test_every = 4, subgrid = 1;
    float ref_cell = 2.0f, test_cell = 8.0f;
    const char *houses_from = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--compare") == 0 && v) {
            i++;
        } else if (strcmp(a, "--region-m") == 0 && v) {
            region_m = atof(argv[++i]);
        } else if (strcmp(a, "--record-s") == 0 && v) {
            record_s = atof(argv[++i]);
        } else if (strcmp(a, "--spinup-s") == 0 && v) {
            spinup_s = atof(argv[++i]);
        } else if (strcmp(a, "--points") == 0 && v) {
            n_points = atoi(argv[++i]);
        } else if (strcmp(a, "--ref-nz") == 0 && v) {
            ref_nz = atoi(argv[++i]);
        } else if (strcmp(a, "--ref-every") == 0 && v) {
            ref_every = atoi(argv[++i]);
        } else if (strcmp(a, "--test-cell-m") == 0 && v) {
            test_cell = (float)atof(argv[++i]);
        } else if (strcmp(a, "--test-nz") == 0 && v) {
            test_nz = atoi(argv[++i]);
        } else if (strcmp(a, "--test-every") == 0 && v) {
            test_every = atoi(argv[++i]);
        } else if (strcmp(a, "--no-subgrid-profile") == 0) {
            subgrid = 0;
        } else if (strcmp(a, "--houses-from") == 0 && v) {
            houses_from = argv[++i];
        } else if (strcmp(a, "--json") == 0) {
            /* JSON is the only output */
        } else {
            return bench_usage(a, "usage: gale-bench wind --compare SCENARIO.json "
                                  "[--region-m 256] [--record-s 60] [--spinup-s 10] "
                                  "[--points 400] [--ref-nz 8] [--ref-every 4] "
                                  "[--test-cell-m 8] [--test-nz 2] [--test-every 4] "
                                  "[--no-subgrid-profile] [--houses-from SCENE.json] "
                                  "[--json]\n");
        }
    }
    int ref_n = (int)lround(region_m / (double)ref_cell),
        test_n = (int)lround(region_m / (double)test_cell);
    if (!(region_m >= 32.0) || !(region_m <= 4096.0) || n_points < 1 || n_points > 100000 ||
        !(record_s >= 3.0) || !(spinup_s >= 0.0) || !(test_cell >= 0.5f) || test_n < 2 ||
        test_nz < 1 || ref_nz < 1 || ref_every < 1 || test_every < 1) {
        fprintf(stderr, "gale-bench wind --compare: expected --region-m 32..4096 (at least two "
                        "test cells), --points 1..100000, --record-s >= 3, --spinup-s >= 0, "
                        "positive cells, layers and step intervals\n");
        return 2;
    }
    gale_err err = { 0 };
    /* the houses of a scene config, in both grids (points inside one are drawn again) */
    scene scn;
    memset(&scn, 0, sizeof scn);
    if (houses_from && scene_load(&scn, houses_from, &err)) {
        fprintf(stderr, "gale-bench wind --compare: %s\n", err.msg);
        return 1;
    }
    scenario *sc = scenario_load(file, &err);
    if (!sc) {
        scene_fini(&scn);
        fprintf(stderr, "gale-bench wind --compare: %s\n", err.msg);
        return 1;
    }
    /* crowns (0.7 of a 7..21 m tree) over the middle 70 %, clear of the borders' inflow */
    float *pts = malloc((size_t)n_points * 3 * sizeof *pts);
    if (!pts) {
        scenario_destroy(sc);
        scene_fini(&scn);
        return 1;
    }
    uint64_t rng = 0x5eedull;
    for (int i = 0; i < n_points; i++) {
        for (int a = 0; a < 3; a++) {
            double u = (double)(hash64_splitmix(&rng) >> 11) / 9007199254740992.0;
            pts[3 * i + a] = a < 2 ? (float)((u - 0.5) * 0.7 * region_m) : (float)(5.0 + 10.0 * u);
        }
        int inside = 0;
        for (int b = 0; b < scn.n_obstacles && !inside; b++) {
            const wind_box *x = &scn.obstacles[b];
            inside = pts[3 * i] >= x->min[0] && pts[3 * i] <= x->max[0] &&
                     pts[3 * i + 1] >= x->min[1] && pts[3 * i + 1] <= x->max[1] &&
                     pts[3 * i + 2] <= x->max[2];
        }
        i -= inside;
    }
    const float o = (float)(-0.5 * region_m);
    wind_error_desc d = {
        .ref = { .nx = ref_n, .ny = ref_n, .nz = ref_nz, .cell_m = ref_cell,
                 .origin = { o, o, 0.0f }, .threads = 1, .seed = 1,
                 .obstacles = scn.obstacles, .n_obstacles = scn.n_obstacles },
        .test = { .nx = test_n, .ny = test_n, .nz = test_nz, .cell_m = test_cell,
                  .origin = { o, o, 0.0f }, .threads = 1, .seed = 1,
                  .subgrid_profile = subgrid, .obstacles = scn.obstacles,
                  .n_obstacles = scn.n_obstacles },
        .ref_every = ref_every, .test_every = test_every, .tick_hz = 60.0,
        .spinup_s = spinup_s, .record_s = record_s, .points = pts, .n_points = n_points,
        .bin_z0_m = 4.0f, .bin_m = 2.0f, .n_bins = 6, .drive = compare_drive, .drive_ctx = sc };
    double l0[3], l1[3];
    loadavg(l0);
    wind_error_result r;
    int rc = wind_error_run(&d, &r, &err);
    loadavg(l1);
    free(pts);
    const int n_houses = scn.n_obstacles;
    scene_fini(&scn);
    if (rc) {
        scenario_destroy(sc);
        fprintf(stderr, "gale-bench wind --compare: %s\n", err.msg);
        return 1;
    }
    printf("{\"scenario\": \"%s\", \"houses\": %d, \"region_m\": %.0f, \"points\": %d, "
           "\"crown_z_m\": [5, 15], \"record_s\": %.0f, \"spinup_s\": %.0f, "
           "\"reference\": {\"grid\": [%d, %d, %d], \"cell_m\": %.1f, \"every\": %d, "
           "\"mean_ms\": %.3f, \"std_ms\": %.3f, \"gust_factor_3s\": %.3f, "
           "\"ms_per_step_median\": %.3f}, "
           "\"test\": {\"grid\": [%d, %d, %d], \"cell_m\": %.1f, \"every\": %d, "
           "\"subgrid_profile\": %s, \"mean_ms\": %.3f, \"std_ms\": %.3f, "
           "\"gust_factor_3s\": %.3f, \"ms_per_step_median\": %.3f}, ",
           scenario_name(sc), n_houses, region_m, n_points, record_s, spinup_s, ref_n, ref_n, ref_nz,
           (double)ref_cell, ref_every, r.ref.mean_ms, r.ref.std_ms, r.ref.gust3, r.ref.step_ms,
           test_n, test_n, test_nz, (double)test_cell, test_every, subgrid ? "true" : "false",
           r.test.mean_ms, r.test.std_ms, r.test.gust3, r.test.step_ms);
    printf("\"per_point\": {\"mean_rel_err\": %.4f, \"mean_rel_err_max\": %.4f, "
           "\"std_rel_err\": %.4f, \"std_rel_err_max\": %.4f, \"gust3_abs_err\": %.4f, "
           "\"gust3_abs_err_max\": %.4f, \"mean_rel_err_p90\": %.4f, \"std_rel_err_p90\": %.4f, "
           "\"gust3_abs_err_p90\": %.4f, \"speed_correlation\": %.4f}, \"profile\": [",
           r.mean_rel_err, r.mean_rel_err_max, r.std_rel_err, r.std_rel_err_max,
           r.gust3_abs_err, r.gust3_abs_err_max, r.mean_rel_err_p90, r.std_rel_err_p90,
           r.gust3_abs_err_p90, r.corr);
    for (int b = 0; b < r.n_bins; b++) {
        printf("%s{\"z_m\": [%.0f, %.0f], \"points\": %d, \"ref_ms\": %.3f, "
               "\"test_ms\": %.3f}", b ? ", " : "", (double)r.bin[b].z_lo_m,
               (double)r.bin[b].z_hi_m, r.bin[b].n, r.bin[b].ref_ms, r.bin[b].test_ms);
    }
    printf("], \"loadavg_before\": [%.2f, %.2f, %.2f], \"loadavg_after\": [%.2f, %.2f, "
           "%.2f]}\n", l0[0], l0[1], l0[2], l1[0], l1[1], l1[2]);
    scenario_destroy(sc);
    return 0;
}

int bench_wind(int argc, char **argv)
{
    for (int i = 1; i + 1 < argc; i++) {
        if (strcmp(argv[i], "--compare") == 0) {
            return bench_wind_compare(argv[i + 1], argc, argv);
        }
    }
    int nx = 256, ny = 256, nz = 16, steps = 100, threads = 2, houses = 24, triad = 1;
    float dt = 1.0f / 60.0f, u10 = 20.0f, h = 2.0f;
    int subgrid = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--grid") == 0 && i + 1 < argc) {
            if (sscanf(argv[++i], "%dx%dx%d", &nx, &ny, &nz) != 3) {
                fprintf(stderr, "gale-bench wind: --grid: expected NXxNYxNZ, got %s\n", argv[i]);
                return 2;
            }
        } else if (strcmp(argv[i], "--steps") == 0 && i + 1 < argc) {
            steps = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--cell-m") == 0 && i + 1 < argc) {
            h = (float)atof(argv[++i]);
        } else if (strcmp(argv[i], "--dt") == 0 && i + 1 < argc) {
            dt = (float)atof(argv[++i]);
        } else if (strcmp(argv[i], "--subgrid-profile") == 0) {
            subgrid = 1;
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            threads = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--houses") == 0 && i + 1 < argc) {
            houses = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--u10") == 0 && i + 1 < argc) {
            u10 = (float)atof(argv[++i]);
        } else if (strcmp(argv[i], "--no-triad") == 0) {
            triad = 0; /* under a cache simulation (deploy/wind-cachesim.sh) */
        } else if (strcmp(argv[i], "--json") == 0) {
            /* JSON is the only output */
        } else {
            return bench_usage(argv[i], "usage: gale-bench wind [--grid 256x256x16] [--cell-m 2] "
                                        "[--dt 0.01667] [--steps 100] [--threads 2] "
                                        "[--houses 24] [--u10 20] [--subgrid-profile] "
                                        "[--no-triad] [--json]\n"
                                        "       gale-bench wind --compare SCENARIO.json "
                                        "[...] (with --help: its options)\n");
        }
    }
    if (steps < 1 || steps > 100000 || houses < 0 || houses > 10000 || !(h >= 0.1f) ||
        !(h <= 50.0f) || !(dt > 0.0f) || !(dt <= 1.0f)) {
        fprintf(stderr, "gale-bench wind: --steps 1..100000, --houses 0..10000, --cell-m "
                        "0.1..50, --dt (0, 1]\n");
        return 2;
    }
    /* houses: 10 x 8 m footprints, 8 m tall, on a regular layout over the middle */
    wind_box *boxes = calloc((size_t)(houses > 0 ? houses : 1), sizeof *boxes);
    if (!boxes) {
        return 1;
    }
    int side = (int)ceil(sqrt((double)houses));
    for (int b = 0; b < houses; b++) {
        float fx = ((float)(b % side) + 1.0f) / ((float)side + 1.0f);
        float fy = ((float)(b / side) + 1.0f) / ((float)side + 1.0f);
        float cx = fx * (float)nx * h, cy = fy * (float)ny * h;
        boxes[b] = (wind_box){ .min = { cx - 5.0f, cy - 4.0f, 0.0f },
                               .max = { cx + 5.0f, cy + 4.0f, 8.0f } };
    }
    gale_err err = { 0 };
    wind_grid *w = wind_create(&(wind_desc){ .nx = nx, .ny = ny, .nz = nz, .cell_m = h,
                                             .threads = threads, .seed = 1,
                                             .subgrid_profile = subgrid,
                                             .obstacles = boxes, .n_obstacles = houses },
                               &err);
    free(boxes);
    if (!w) {
        fprintf(stderr, "gale-bench wind: %s\n", err.msg);
        return 1;
    }
    /* two triads in alternating rounds (bench.h bench_triad_pair): one over float arrays
       sized like the step's (15 a cell: about SCENE_GRID_CELL_BYTES, scene.h), which on a
       grid that fits the last-level cache measures the cache, and the DRAM-sized one */
    const double cells = (double)nx * ny * nz;
    double l0[3];
    loadavg(l0);
    bench_triads tr = { 0 };
    tr.ws_bytes = (size_t)cells * 15u * sizeof(float);
    if (triad) {
        bench_triad_pair(threads, (size_t)cells, 15, &tr);
    }
    const size_t ws_bytes = tr.ws_bytes;
    double gbs_ws = tr.ws_gb_s, gbs = tr.dram_gb_s;
    /* A working set's limit is its own triad, never less than DRAM's: a set past the
       last-level cache streams from DRAM as the DRAM triad does, so a lower working-set
       triad is the machine's contention in that round, said beside it. */
    double ws_limit = gbs_ws > gbs ? gbs_ws : gbs;
    char note[400] = "";
    if (triad && gbs_ws < gbs) {
        snprintf(note, sizeof note,
                 "working-set triad %.2f GB/s below the DRAM triad %.2f GB/s: the set (%.1f MiB) "
                 "%s the last-level cache (%.1f MiB)%s; fractions use the DRAM triad as the "
                 "working set's limit (load %.2f)",
                 gbs_ws, gbs, (double)ws_bytes / 1048576.0,
                 ws_bytes > tr.llc_bytes ? "exceeds" : "fits",
                 (double)tr.llc_bytes / 1048576.0,
                 ws_bytes > tr.llc_bytes
                     ? ", so both stream from DRAM and the gap is contention on a shared machine "
                       "or the working set's shorter sweeps (a fork per sweep, as the step's "
                       "kernels)"
                     : ", yet ran slower: other processes shared the cache and cores in those "
                       "rounds",
                 l0[0]);
    }
    wind_set_inflow(w, &(wind_inflow){ .dir_rad = 0.5f, .u10_ms = u10 });
    wind_fill_inflow(w);
    double *ms = malloc((size_t)steps * sizeof *ms);
    double *red = malloc((size_t)steps * sizeof *red);
    double *its = malloc((size_t)steps * sizeof *its);
    double phase[4] = { 0, 0, 0, 0 };
    double *cpu = malloc((size_t)steps * sizeof *cpu);
    if (!ms || !red || !its || !cpu) {
        free(cpu);
        wind_destroy(w);
        free(ms);
        free(red);
        free(its);
        return 1;
    }
    const int warm = 10;
    double worst = 1e30, its_sum = 0.0;
    int failed = 0;
    for (int s = -warm; s < steps; s++) {
        wind_ball ball = { .center = { 0.3f * (float)nx * h, 0.5f * (float)ny * h, 6.0f },
                           .radius_m = 6.0f * h, .force = { 30.0f, 10.0f, 0.0f },
                           .jitter_m = 4.0f * h };
        wind_add_ball(w, &ball);
        wind_step_stats st;
        double c0 = bench_cpu_ms();
        int rc = wind_step(w, dt, &st);
        double c1 = bench_cpu_ms();
        if (rc < 0) {
            failed++;
            continue;
        }
        if (s < 0) {
            continue;
        }
        ms[s] = st.ms;
        cpu[s] = (c1 - c0) / threads;
        red[s] = st.div_after > 0.0 ? st.div_before / st.div_after : 1e30;
        its[s] = st.iterations;
        its_sum += st.iterations;
        phase[0] += st.ms_advect;
        phase[1] += st.ms_forces;
        phase[2] += st.ms_solve;
        phase[3] += st.ms_project;
        worst = red[s] < worst ? red[s] : worst;
    }
    double div_rms = wind_divergence_rms(w);
    wind_desc d = wind_get_desc(w);
    wind_destroy(w);
    double med = quantile(ms, steps, 0.5), p95 = quantile(ms, steps, 0.95);
    double cpu_med = quantile(cpu, steps, 0.5);
    double l1[3];
    loadavg(l1);
    double red_med = quantile(red, steps, 0.5), it_med = quantile(its, steps, 0.5);
    step_model bm = step_bytes_per_cell(its_sum / steps);
    double per_cell = bm.advect + bm.forces + bm.solve + bm.project;
    double bytes = cells * per_cell;
    double eff = bytes / (med * 1e-3) / 1e9;
    printf("{\"inputs\": {\"cell_m\": %.1f, \"dt_s\": %.5f, \"u10_ms\": %.1f, "
           "\"ball_force\": [30, 10, 0], \"working_set_bytes\": %zu, \"llc_bytes\": %zu, "
           "\"subgrid_profile\": %s}, "
           "\"bytes_per_cell_model\": {\"advect\": %.1f, \"forces_bc_divergence\": %.1f, "
           "\"pressure_solve\": %.1f, \"projection\": %.1f, \"total\": %.1f}, "
           "\"triad_working_set_gb_per_s\": %.2f, \"working_set_limit_gb_per_s\": %.2f, "
           "\"working_set_note\": \"%s\", \"bandwidth_fraction_working_set\": %.3f, "
           "\"loadavg_before\": [%.2f, %.2f, %.2f], \"loadavg_after\": [%.2f, %.2f, %.2f], ",
           (double)h, (double)dt, (double)u10, ws_bytes, tr.llc_bytes, subgrid ? "true" : "false",
           bm.advect, bm.forces, bm.solve, bm.project, per_cell, gbs_ws, ws_limit, note,
           ws_limit > 0.0 ? eff / ws_limit : 0.0, l0[0], l0[1], l0[2], l1[0], l1[1], l1[2]);
    /* each phase's model bytes over its mean time, against both limits */
    const char *pname[4] = { "advect", "forces_bc_divergence", "pressure_solve", "projection" };
    const double pbytes[4] = { bm.advect, bm.forces, bm.solve, bm.project };
    printf("\"fractions\": [{\"what\": \"step\", \"gb_per_s\": %.2f, \"of_working_set_limit\": "
           "%.3f, \"of_dram_triad\": %.3f}", eff, ws_limit > 0.0 ? eff / ws_limit : 0.0,
           gbs > 0.0 ? eff / gbs : 0.0);
    for (int q = 0; q < 4; q++) {
        double pms = phase[q] / steps;
        double g = pms > 0.0 ? cells * pbytes[q] / (pms * 1e-3) / 1e9 : 0.0;
        printf(", {\"what\": \"%s\", \"gb_per_s\": %.2f, \"of_working_set_limit\": %.3f, "
               "\"of_dram_triad\": %.3f}", pname[q], g, ws_limit > 0.0 ? g / ws_limit : 0.0,
               gbs > 0.0 ? g / gbs : 0.0);
    }
    printf("], ");
    double load1 = l1[0];
    printf("\"grid\": [%d, %d, %d], \"steps\": %d, \"threads\": %d, \"houses\": %d, "
           "\"div_reduction_required\": %g, \"ms_per_step_median\": %.3f, "
           "\"ms_per_step_p95\": %.3f, \"divergence_reduction_median\": %.1f, "
           "\"divergence_reduction_min\": %.1f, \"iterations_median\": %g, "
           "\"iterations_mean\": %.2f, \"final_divergence_rms_per_s\": %.4g, "
           "\"failed_steps\": %d, \"triad_dram_gb_per_s\": %.2f, \"bytes_per_step_model\": %.0f, "
           "\"solver_effective_gb_per_s\": %.2f, \"bandwidth_fraction_dram\": %.3f, "
           "\"ms_mean_advect\": %.3f, \"ms_mean_forces_bc_divergence\": %.3f, "
           "\"ms_mean_pressure_solve\": %.3f, \"ms_mean_projection\": %.3f, "
           "\"cpu_ms_per_step_per_thread_median\": %.3f, \"loadavg_1min\": %.2f}\n",
           nx, ny, nz, steps, threads, houses, (double)d.div_reduction, med, p95, red_med, worst,
           it_med, its_sum / steps, div_rms, failed, gbs, bytes, eff, gbs > 0.0 ? eff / gbs : 0.0,
           phase[0] / steps, phase[1] / steps, phase[2] / steps, phase[3] / steps, cpu_med, load1);
    free(ms);
    free(red);
    free(its);
    free(cpu);
    return failed ? 1 : 0;
}
