/* The machine's memory bandwidth for gale-bench: a STREAM triad (McCalpin) run in the
 * same process as the figure it scales, so a benchmark reports its speed as a fraction
 * of what this machine's memory can move, comparable across machines. */
#include <stddef.h>
#include <stdlib.h>

#include "bench.h"
#include "mono.h"

double bench_triad_gb_s(int threads)
{
    return bench_triad_sized_gb_s(threads, (size_t)3 << 27); /* 3 x 128 MiB */
}

double bench_triad_sized_gb_s(int threads, size_t bytes)
{
    const size_t n = bytes / 24 > 1024 ? bytes / 24 : 1024;
    double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
    if (!a || !b || !c) {
        free(a);
        free(b);
        free(c);
        return 0.0;
    }
    const long nl = (long)n;
    /* first touch by the same threads and schedule as the timed loop: each page sits
     * where the thread that sweeps it runs */
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long i = 0; i < nl; i++) {
        a[i] = 0.0;
        b[i] = 1.0;
        c[i] = 2.0;
    }
    /* each timed pass sweeps about 256 MiB (at least once), so a small, cache-resident
       triad is timed over milliseconds, not microseconds */
    const int sweeps = (int)((((size_t)1 << 28) + 24 * n - 1) / (24 * n));
    double best = 1e30;
    for (int rep = 0; rep < 5; rep++) {
        double t0 = mono_ms();
        for (int sw = 0; sw < sweeps; sw++) {
#pragma omp parallel for schedule(static) num_threads(threads)
            for (long i = 0; i < nl; i++) {
                a[i] = b[i] + 3.0 * c[i];
            }
        }
        double t = (mono_ms() - t0) / sweeps;
        best = t < best ? t : best;
    }
    double check = a[n / 2];
    free(a);
    free(b);
    free(c);
    return check == 7.0 ? 24.0 * (double)n / (best * 1e-3) / 1e9 : 0.0;
}
