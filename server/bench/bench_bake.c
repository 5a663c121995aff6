/* gale-bench bake: wall time and peak memory of the whole bake (frame model, modes, wind
 * basis, correction, mesh) for synthetic trees of 300 to 10,000 nodes at 32 modes. Each
 * size runs in its own child process so its peak RSS is its own. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench.h"
#include "bake.h"
#include "bake_tree.h"
#include "species.h"

typedef struct bench_row {
    int nodes;
    double seconds[3]; /* three runs */
    double eigen_s, corr_s, mesh_s;
    int solves;
    double max_rss_mb;
    double cpu_s;      /* user + system CPU of the child per bake (3 bakes + one tree) */
    int ok;
} bench_row;

static double median3(const double *x)
{
    double a = x[0], b = x[1], c = x[2];
    if (a > b) {
        double t = a;
        a = b, b = t;
    }
    if (b > c) {
        b = c;
    }
    return a > b ? a : b;
}

/* In the child: bake the tree three times, report the figures over the pipe. */
static void child(int n, int modes, int fd)
{
    bench_row r;
    memset(&r, 0, sizeof r);
    r.nodes = n;
    skeleton s;
    species sp;
    gale_err err;
    species_default(&sp);
    if (bake_tree_generate(n, 42, &s, &err) == GALE_OK) {
        r.ok = 1;
        for (int k = 0; k < 3 && r.ok; k++) {
            asset a;
            bake_report rep;
            bake_desc d = { .n_modes = modes };
            if (bake_run(&s, &sp, &d, &a, &rep, &err) != GALE_OK) {
                fprintf(stderr, "bench bake: %d nodes: %s\n", n, err.msg);
                r.ok = 0;
                break;
            }
            r.seconds[k] = rep.seconds;
            r.eigen_s = rep.seconds_eigen, r.corr_s = rep.seconds_correction;
            r.mesh_s = rep.seconds_mesh, r.solves = rep.eigen_solves;
            asset_fini(&a);
        }
        skeleton_fini(&s);
    }
    if (write(fd, &r, sizeof r) != (ssize_t)sizeof r) {
        _exit(1);
    }
    _exit(0);
}


int bench_bake(int argc, char **argv)
{
    int json = 0, modes = 32;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (strcmp(argv[i], "--modes") == 0 && i + 1 < argc) {
            modes = atoi(argv[++i]);
        } else {
            return bench_usage(argv[i],
                               "usage: gale-bench bake [--json] [--modes N]\n"
                               "  bake wall time (median of 3) and peak RSS per tree size, synthetic trees\n"
                               "  of 300, 1000, 3500, 10000 nodes, 32 modes by default\n");
        }
    }
    const int sizes[4] = { 300, 1000, 3500, 10000 };
    bench_row rows[4];
    for (int k = 0; k < 4; k++) {
        int fds[2];
        memset(&rows[k], 0, sizeof rows[k]);
        rows[k].nodes = sizes[k];
        if (pipe(fds) != 0) {
            return 1;
        }
        fflush(NULL);
        pid_t pid = fork();
        if (pid == 0) {
            close(fds[0]);
            child(sizes[k], modes, fds[1]);
        }
        close(fds[1]);
        bench_row r;
        const ssize_t got = read(fds[0], &r, sizeof r);
        close(fds[0]);
        int st = 0;
        struct rusage ru;
        if (wait4(pid, &st, 0, &ru) == pid && got == (ssize_t)sizeof r) {
            rows[k] = r;
            rows[k].max_rss_mb = (double)ru.ru_maxrss / 1024.0;
            rows[k].cpu_s = ((double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
                             (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec) /
                            3.0;
        }
    }
    /* wall times mean little on a shared machine without the load they ran under */
    double load[1] = { -1.0 };
    if (getloadavg(load, 1) != 1) {
        load[0] = -1.0;
    }
    if (json) {
        printf("{\n  \"bench\": \"bake\",\n  \"modes\": %d,\n  \"trees\": \"synthetic "
               "(bake_tree_generate, seed 42)\",\n  \"load_average_1min\": %.2f,\n"
               "  \"sizes\": [\n",
               modes, load[0]);
        for (int k = 0; k < 4; k++) {
            const bench_row *r = &rows[k];
            printf("    { \"nodes\": %d, \"ok\": %s, \"seconds\": %.4f, \"seconds_runs\": [%.4f, "
                   "%.4f, %.4f], \"eigen_seconds\": %.4f, \"correction_seconds\": %.4f, "
                   "\"mesh_seconds\": %.4f, \"cpu_seconds\": %.4f, \"solves\": %d, \"peak_rss_mb\": %.1f }%s\n",
                   r->nodes, r->ok ? "true" : "false", median3(r->seconds), r->seconds[0],
                   r->seconds[1], r->seconds[2], r->eigen_s, r->corr_s, r->mesh_s, r->cpu_s, r->solves,
                   r->max_rss_mb, k < 3 ? "," : "");
        }
        const double s1 = median3(rows[0].seconds), s4 = median3(rows[3].seconds);
        printf("  ],\n  \"seconds_per_1000_nodes\": [%.4f, %.4f, %.4f, %.4f],\n"
               "  \"growth_10000_over_300\": %.2f\n}\n",
               1000 * s1 / 300, 1000 * median3(rows[1].seconds) / 1000,
               1000 * median3(rows[2].seconds) / 3500, 1000 * s4 / 10000, s4 / (s1 > 0 ? s1 : 1));
    } else {
        printf("%8s %10s %10s %10s %10s %8s %12s\n", "nodes", "bake [s]", "eigen [s]", "corr [s]",
               "cpu [s]", "solves", "peak RSS MB");
        printf("(load average %.2f)\n", load[0]);
        for (int k = 0; k < 4; k++) {
            const bench_row *r = &rows[k];
            printf("%8d %10.4f %10.4f %10.4f %10.4f %8d %12.1f%s\n", r->nodes, median3(r->seconds),
                   r->eigen_s, r->corr_s, r->cpu_s, r->solves, r->max_rss_mb,
                   r->ok ? "" : "  FAILED");
        }
    }
    for (int k = 0; k < 4; k++) {
        if (!rows[k].ok) {
            return 1;
        }
    }
    return 0;
}
