/* The simulation's metrics (server/SERVER.md "Serving", /metrics): ticks run and their
 * time (over the run, and the last minute's quantiles), overruns of the fixed step, the
 * wind steps' time and the ticks they held up, and the wind grid's last pressure solve
 * (its iterations, relative residual, and how many solves ran out of their budget). The sim
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

/* The window of gale_tick_recent_seconds, the recent ticks' quantiles: the last this
 * many ticks (a minute at 60 Hz), so a p99 read off the page is the last minute's, not
 * the whole run's. */
#define SIM_RECENT_TICKS 3600
#define SIM_RECENT_QUANTILES 4
extern const double sim_recent_quantile[SIM_RECENT_QUANTILES];

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
    atomic_ullong wind_steps;       /* wind steps taken */
    atomic_ullong wind_step_ns_sum; /* their own wall time [ns], beside the ticks or in them */
    atomic_ullong wind_step_ns_max;
    atomic_ullong wind_waits;       /* ticks held up by a step beside them not yet done */
    atomic_ullong wind_wait_ns_sum; /* how long they waited [ns] */
    _Atomic uint32_t recent_us[SIM_RECENT_TICKS]; /* the last ticks' work [µs], a ring at
                                                     ticks % SIM_RECENT_TICKS */
} sim_metrics;

/* Counts one tick that brought the simulation to tick `tick` (tick_now after it), with
 * the stats tick_step returned. Returns the tick's work time as counted [ns]. */
uint64_t sim_metrics_tick(sim_metrics *m, uint32_t tick, const tick_stats *st);
/* Counts an overrun of the fixed step; returns the count so far. */
unsigned long long sim_metrics_overrun(sim_metrics *m);

/* Adds the simulation's rows (gale_ticks_total, the gale_tick_seconds histogram and
 * _max, the gale_tick_recent_seconds summary, gale_tick_overruns_total,
 * gale_wind_pressure_*, gale_wind_step_*) to r; m is borrowed for r's life.
 * Fails only when r is full (metric_reg_add). */
int sim_metrics_register(sim_metrics *m, metric_reg *r, gale_err *err);

#endif
