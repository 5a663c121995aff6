/* The simulation's metrics (server/SERVER.md "Serving", /metrics): ticks run and their
 * time (over the run, and the last minute's quantiles), overruns of the fixed step, the
 * wind steps' time and the ticks they held up, and the wind grid's last pressure solve
 * (its iterations, relative residual, and how many solves ran out of their budget). The sim
 * thread writes them, any thread reads them; they become metric.h rows. */
#ifndef GALE_SIM_METRICS_H
#define GALE_SIM_METRICS_H

#include <stdatomic.h>
#include <stddef.h>
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

/* The phases of a tick's work gale_tick_phase_seconds_total counts: the first five are
 * tick_step's (tick_stats), which gale_tick_seconds counts whole; publishing the snapshot
 * follows the tick on snapshot ticks (sim_metrics_publish). */
enum {
    SIM_PHASE_WIND,
    SIM_PHASE_SAMPLE,
    SIM_PHASE_MODAL,
    SIM_PHASE_LEAVES,
    SIM_PHASE_DAMAGE,
    SIM_PHASE_PUBLISH,
    SIM_PHASES
};

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
    atomic_ullong phase_ns[SIM_PHASES]; /* wall time of each phase [ns] */
    atomic_ullong off_cpu_ns;       /* of the ticks' work, time the sim thread was off a CPU */
    _Atomic uint32_t recent_us[SIM_RECENT_TICKS]; /* the last ticks' work [µs], a ring at
                                                     ticks % SIM_RECENT_TICKS */
} sim_metrics;

/* Counts one tick that brought the simulation to tick `tick` (tick_now after it), with
 * the stats tick_step returned. Returns the tick's work time as counted [ns]. */
uint64_t sim_metrics_tick(sim_metrics *m, uint32_t tick, const tick_stats *st);
/* Counts the publishing of a snapshot after its tick, publish_ms of it. */
void sim_metrics_publish(sim_metrics *m, double publish_ms);
/* Counts an overrun of the fixed step; returns the count so far. */
unsigned long long sim_metrics_overrun(sim_metrics *m);

/* Where a tick's time went, for the overrun's log line: each phase of st (the wind's
 * with its pressure iterations, and publishing,
 * publish_ms; negative: none this tick), the work no phase accounts for, and how long the
 * sim thread was off a CPU, into buf (always terminated). Returns snprintf's count. */
int sim_metrics_describe(char *buf, size_t cap, const tick_stats *st, double publish_ms);

/* Adds the simulation's rows (gale_ticks_total, the gale_tick_seconds histogram and
 * _max, the gale_tick_recent_seconds summary, gale_tick_phase_seconds_total by phase,
 * gale_tick_off_cpu_seconds_total, gale_tick_overruns_total,
 * gale_wind_pressure_*, gale_wind_step_*) to r; m is borrowed for r's life.
 * Fails only when r is full (metric_reg_add). */
int sim_metrics_register(sim_metrics *m, metric_reg *r, gale_err *err);

#endif
