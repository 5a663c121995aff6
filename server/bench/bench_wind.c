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
#include "wind.h"


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

int bench_wind(int argc, char **argv)
{
    int nx = 256, ny = 256, nz = 16, steps = 100, threads = 2, houses = 24, triad = 1;
    float dt = 1.0f / 60.0f, u10 = 20.0f;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--grid") == 0 && i + 1 < argc) {
            if (sscanf(argv[++i], "%dx%dx%d", &nx, &ny, &nz) != 3) {
                fprintf(stderr, "gale-bench wind: --grid: expected NXxNYxNZ, got %s\n", argv[i]);
                return 2;
            }
        } else if (strcmp(argv[i], "--steps") == 0 && i + 1 < argc) {
            steps = atoi(argv[++i]);
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
            return bench_usage(argv[i], "usage: gale-bench wind [--grid 256x256x16] [--steps 100] "
                                        "[--threads 2] [--houses 24] [--u10 20] [--no-triad] "
                                        "[--json]\n");
        }
    }
    if (steps < 1 || steps > 100000 || houses < 0 || houses > 10000) {
        fprintf(stderr, "gale-bench wind: --steps 1..100000, --houses 0..10000\n");
        return 2;
    }
    const float h = 2.0f;
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
                                             .obstacles = boxes, .n_obstacles = houses },
                               &err);
    free(boxes);
    if (!w) {
        fprintf(stderr, "gale-bench wind: %s\n", err.msg);
        return 1;
    }
    /* two triads: one over the step's working set (SCENE_GRID_CELL_BYTES-like 61 B per
       cell, scene.h), which on a grid that fits the last-level cache measures the cache,
       and the DRAM-sized one */
    const double cells = (double)nx * ny * nz;
    const size_t ws_bytes = (size_t)(cells * 61.0);
    double l0[3];
    loadavg(l0);
    double gbs_ws = triad ? bench_triad_sized_gb_s(threads, ws_bytes) : 0.0;
    double gbs = triad ? bench_triad_gb_s(threads) : 0.0;
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
           "\"ball_force\": [30, 10, 0], \"working_set_bytes\": %zu}, "
           "\"bytes_per_cell_model\": {\"advect\": %.1f, \"forces_bc_divergence\": %.1f, "
           "\"pressure_solve\": %.1f, \"projection\": %.1f, \"total\": %.1f}, "
           "\"triad_working_set_gb_per_s\": %.2f, \"bandwidth_fraction_working_set\": %.3f, "
           "\"loadavg_before\": [%.2f, %.2f, %.2f], \"loadavg_after\": [%.2f, %.2f, %.2f], ",
           (double)h, (double)dt, (double)u10, ws_bytes, bm.advect, bm.forces, bm.solve,
           bm.project, per_cell, gbs_ws, gbs_ws > 0.0 ? eff / gbs_ws : 0.0, l0[0], l0[1], l0[2],
           l1[0], l1[1], l1[2]);
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
