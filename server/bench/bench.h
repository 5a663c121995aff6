/* The subcommands of gale-bench (one per bench_<name>.c) and what they share. */
#ifndef GALE_BENCH_H
#define GALE_BENCH_H

#include <stddef.h>

int bench_bake(int argc, char **argv);
int bench_wind(int argc, char **argv);
int bench_modal(int argc, char **argv);
int bench_wire(int argc, char **argv);
int bench_views(int argc, char **argv);
int bench_ef(int argc, char **argv);

/* The machine's memory bandwidth [GB/s]: a STREAM triad a = b + 3 c over three arrays of
 * 2^24 doubles (384 MiB, far past the caches) on `threads` threads, best of 5, on the
 * pages the tick's streamed arrays get (big_alloc: huge where the kernel grants them),
 * counted as 24 bytes per element (STREAM's convention: write-allocate traffic not
 * counted, so a benchmark's byte model leaves it out too). Allocates and frees its
 * arrays; 0 when they cannot be allocated. */
double bench_triad_gb_s(int threads);

/* The same triad over three arrays of bytes / 3 in all (at least 24 KiB): sized like a
 * benchmark's working set it measures what the caches holding that set deliver. */
double bench_triad_sized_gb_s(int threads, size_t bytes);

/* The same triad kept open between measurements, so that a benchmark reads the machine's
 * bandwidth in bursts among its own work, at the moments it runs (a guest's memory speed
 * drifts from minute to minute): bench_triad_open allocates and writes the arrays (bytes
 * in all; -1 when out of memory), bench_triad_burst times `reps` passes and returns the
 * best in GB/s (0 for a closed triad), bench_triad_close frees them. */
typedef struct bench_triad {
    double *a, *b, *c;
    size_t n;
    int threads;
} bench_triad;
int bench_triad_open(bench_triad *t, int threads, size_t bytes);
double bench_triad_burst(bench_triad *t, int reps);
void bench_triad_close(bench_triad *t);

/* The wind step's own triad beside the DRAM one, measured in alternating rounds (so a
 * busy moment of a shared machine hits both alike), best round of each:
 *   ws: float arrays sized like the step's (`arrays` arrays of `cells` floats, swept in
 *   triples a = b + s c, one parallel region per sweep as the step's kernels fork, on its
 *   `threads` threads, first touched by them and warmed by one untimed pass);
 *   dram: a 384 MiB double triad like bench_triad_gb_s's, on the same threads and on
 *   small pages, as the wind's arrays are.
 * llc_bytes: the last-level cache (sysconf, else /sys; 0 unknown). 12 bytes counted per
 * float triad element, 24 per double one (STREAM's convention). */
typedef struct bench_triads {
    double ws_gb_s, dram_gb_s;
    size_t ws_bytes, llc_bytes;
} bench_triads;
void bench_triad_pair(int threads, size_t cells, int arrays, bench_triads *out);

/* Answers an argument a subcommand does not take: "--help"/"-h" print usage on stdout and
 * give exit status 0, anything else prints it on stderr and gives 2. */
int bench_usage(const char *arg, const char *usage);

#endif
