/* The machine's memory bandwidth for gale-bench: a STREAM triad (McCalpin) run in the
 * same process as the figure it scales, so a benchmark reports its speed as a fraction
 * of what this machine's memory can move, comparable across machines. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "bench.h"
#include "big_alloc.h"
#include "mono.h"

double bench_triad_gb_s(int threads)
{
    return bench_triad_sized_gb_s(threads, (size_t)3 << 27); /* 3 x 128 MiB */
}

int bench_triad_open(bench_triad *t, int threads, size_t bytes)
{
    const size_t n = bytes / 24 > 1024 ? bytes / 24 : 1024;
    /* on the pages the tick's streamed arrays get (big_alloc): huge ones where the kernel
     * grants them, which move a triad faster than small ones */
    *t = (bench_triad){ .a = big_alloc(n * sizeof(double)), .b = big_alloc(n * sizeof(double)),
                        .c = big_alloc(n * sizeof(double)), .n = n, .threads = threads };
    if (!t->a || !t->b || !t->c) {
        bench_triad_close(t);
        return -1;
    }
    const long nl = (long)n;
    double *a = t->a, *b = t->b, *c = t->c;
    /* values written by the same threads and schedule as the timed loop (big_alloc's
     * zeroing placed the pages from one thread, as it places the tick's arrays) */
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long i = 0; i < nl; i++) {
        a[i] = 0.0;
        b[i] = 1.0;
        c[i] = 2.0;
    }
    return 0;
}

double bench_triad_burst(bench_triad *t, int reps)
{
    if (!t->a) {
        return 0.0;
    }
    const long nl = (long)t->n;
    double *a = t->a, *b = t->b, *c = t->c;
    /* each timed pass sweeps about 256 MiB (at least once), so a small, cache-resident
       triad is timed over milliseconds, not microseconds */
    const int sweeps = (int)((((size_t)1 << 28) + 24 * t->n - 1) / (24 * t->n));
    double best = 1e30;
    for (int rep = 0; rep < reps; rep++) {
        double t0 = mono_ms();
        for (int sw = 0; sw < sweeps; sw++) {
#pragma omp parallel for schedule(static) num_threads(t->threads)
            for (long i = 0; i < nl; i++) {
                a[i] = b[i] + 3.0 * c[i];
            }
        }
        double ms = (mono_ms() - t0) / sweeps;
        best = ms < best ? ms : best;
    }
    return a[t->n / 2] == 7.0 ? 24.0 * (double)t->n / (best * 1e-3) / 1e9 : 0.0;
}

void bench_triad_close(bench_triad *t)
{
    free(t->a);
    free(t->b);
    free(t->c);
    *t = (bench_triad){ 0 };
}

double bench_triad_sized_gb_s(int threads, size_t bytes)
{
    bench_triad t;
    if (bench_triad_open(&t, threads, bytes) != 0) {
        return 0.0;
    }
    const double gbs = bench_triad_burst(&t, 5);
    bench_triad_close(&t);
    return gbs;
}

/* The last-level cache: /sys first (some virtual machines' sysconf reports another
 * figure than the cache the guest sees, e.g. 320 MiB for a 32 MiB L3), then sysconf. */
static size_t llc_bytes(void)
{
    FILE *f = fopen("/sys/devices/system/cpu/cpu0/cache/index3/size", "r");
    unsigned long kib = 0;
    if (f) {
        if (fscanf(f, "%luK", &kib) != 1) {
            kib = 0;
        }
        fclose(f);
    }
    if (kib > 0) {
        return (size_t)kib * 1024u;
    }
    long v = 0;
#ifdef _SC_LEVEL3_CACHE_SIZE
    v = sysconf(_SC_LEVEL3_CACHE_SIZE);
#endif
    return v > 0 ? (size_t)v : 0;
}

/* One pass over the working set: every triple of arrays, a fork per sweep. */
static void ws_pass(float **arr, int triples, long n, int threads, float s)
{
    for (int t = 0; t < triples; t++) {
        float *a = arr[3 * t], *b = arr[3 * t + 1], *c = arr[3 * t + 2];
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long i = 0; i < n; i++) {
            a[i] = b[i] + s * c[i];
        }
    }
}

void bench_triad_pair(int threads, size_t cells, int arrays, bench_triads *out)
{
    out->ws_gb_s = out->dram_gb_s = 0.0;
    out->llc_bytes = llc_bytes();
    const int triples = arrays / 3 > 0 ? arrays / 3 : 1;
    const long n = (long)(cells > 1024 ? cells : 1024);
    out->ws_bytes = (size_t)triples * 3u * (size_t)n * sizeof(float);
    const long nd = (long)(((size_t)3 << 27) / 24);
    float **arr = calloc((size_t)triples * 3u, sizeof *arr);
    double *da = malloc((size_t)nd * sizeof *da), *db = malloc((size_t)nd * sizeof *db),
           *dc = malloc((size_t)nd * sizeof *dc);
    int ok = arr && da && db && dc;
    for (int k = 0; ok && k < 3 * triples; k++) {
        ok = (arr[k] = malloc((size_t)n * sizeof(float))) != NULL;
    }
    if (ok) {
        for (int k = 0; k < 3 * triples; k++) {
            float *a = arr[k];
            const float v = (float)(k % 3);
#pragma omp parallel for schedule(static) num_threads(threads)
            for (long i = 0; i < n; i++) {
                a[i] = v;
            }
        }
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long i = 0; i < nd; i++) {
            da[i] = 0.0;
            db[i] = 1.0;
            dc[i] = 2.0;
        }
        ws_pass(arr, triples, n, threads, 0.5f);
        /* at least 64 MiB a timed working-set round, so a cache-sized set is timed over
           milliseconds */
        const size_t pass_bytes = (size_t)triples * 12u * (size_t)n;
        const int passes = (int)((((size_t)1 << 26) + pass_bytes - 1) / pass_bytes);
        double best_ws = 1e30, best_d = 1e30;
        for (int round = 0; round < 7; round++) {
            double t0 = mono_ms();
            for (int p = 0; p < passes; p++) {
                ws_pass(arr, triples, n, threads, 0.5f);
            }
            double t1 = mono_ms();
#pragma omp parallel for schedule(static) num_threads(threads)
            for (long i = 0; i < nd; i++) {
                da[i] = db[i] + 3.0 * dc[i];
            }
            double t2 = mono_ms();
            best_ws = (t1 - t0) / passes < best_ws ? (t1 - t0) / passes : best_ws;
            best_d = t2 - t1 < best_d ? t2 - t1 : best_d;
        }
        out->ws_gb_s = (double)pass_bytes / (best_ws * 1e-3) / 1e9;
        out->dram_gb_s = da[nd / 2] == 7.0 ? 24.0 * (double)nd / (best_d * 1e-3) / 1e9 : 0.0;
    }
    for (int k = 0; arr && k < 3 * triples; k++) {
        free(arr[k]);
    }
    free(arr);
    free(da);
    free(db);
    free(dc);
}
