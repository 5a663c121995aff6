/* The simulation's metrics (server/SERVER.md "Serving", /metrics): ticks run and their
 * time, overruns of the fixed step, and the wind grid's last pressure solve (its
 * iterations, relative residual, and how many solves ran out of their budget). The sim
 * thread writes them, any thread reads them; they become metric.h rows. */
#ifndef GALE_SIM_METRICS_H
#define GALE_SIM_METRICS_H

#include <stdatomic.h>
#include <stdint.h>

#include "err.h"
#include "metric.h"
#include "tick.h"

/* Buckets of the tick-time histogram gale_tick_seconds (upper bounds [s]: 0.5 ms doubling
 * to 64 ms, then +Inf; a 60 Hz tick has 16.7 ms). */
#define SIM_TICK_BUCKETS 9
extern const double sim_tick_bucket_s[SIM_TICK_BUCKETS - 1];

/* Caller-owned; zeroed is the start state. */
typedef struct sim_metrics {
    atomic_ullong ticks;
    atomic_ullong tick_ns_sum;      /* wall time of the ticks' work [ns] */
    atomic_ullong tick_ns_max;      /* longest tick [ns] */
    atomic_ullong tick_le[SIM_TICK_BUCKETS]; /* ticks no longer than sim_tick_bucket_s[i]
                                               (not cumulative; the last one: the rest) */
    atomic_ullong overruns;         /* ticks that ended after the next one was due */
    atomic_uint current_tick;       /* ticks run so far: the tick of the latest state */
    atomic_int wind_iterations;     /* pressure iterations of the last wind step */
    _Atomic double wind_residual;   /* ||b - A p|| / ||b|| after the last wind step's solve */
    atomic_ullong wind_unconverged; /* wind steps whose solve ran out of its budget */
} sim_metrics;

/* Counts one tick that brought the simulation to tick `tick` (tick_now after it), with
 * the stats tick_step returned. Returns the tick's work time as counted [ns]. */
uint64_t sim_metrics_tick(sim_metrics *m, uint32_t tick, const tick_stats *st);
/* Counts an overrun of the fixed step; returns the count so far. */
unsigned long long sim_metrics_overrun(sim_metrics *m);

/* Adds the simulation's rows (gale_ticks_total, gale_tick_seconds_sum/max,
 * gale_tick_overruns_total, gale_wind_pressure_*) to r; m is borrowed for r's life.
 * Fails only when r is full (metric_reg_add). */
int sim_metrics_register(sim_metrics *m, metric_reg *r, gale_err *err);

#endif
