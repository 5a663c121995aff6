/* The simulation's metrics: see sim_metrics.h. */
#include "sim_metrics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

const double sim_tick_bucket_s[SIM_TICK_BUCKETS - 1] = { 0.0005, 0.001, 0.002, 0.004,
                                                          0.008,  0.016, 0.032, 0.064 };
const double sim_recent_quantile[SIM_RECENT_QUANTILES] = { 0.5, 0.9, 0.99, 0.999 };

static const metric_row sim_rows[] = {
    { "gale_ticks_total", NULL, "Simulation ticks run.", METRIC_COUNTER, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.0005\"", "Wall time of the ticks' work.",
      METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.001\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.002\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.004\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.008\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.016\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.032\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"0.064\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_bucket", "le=\"+Inf\"", "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_sum", NULL, "", METRIC_HISTOGRAM, 6 },
    { "gale_tick_seconds_count", NULL, "", METRIC_HISTOGRAM, 0 },
    { "gale_tick_seconds_max", NULL, "Longest tick.", METRIC_GAUGE, 6 },
    { "gale_tick_recent_seconds", "quantile=\"0.5\"",
      "Wall time of the last 3600 ticks' work (a minute at 60 Hz).", METRIC_SUMMARY, 6 },
    { "gale_tick_recent_seconds", "quantile=\"0.9\"", "", METRIC_SUMMARY, 6 },
    { "gale_tick_recent_seconds", "quantile=\"0.99\"", "", METRIC_SUMMARY, 6 },
    { "gale_tick_recent_seconds", "quantile=\"0.999\"", "", METRIC_SUMMARY, 6 },
    { "gale_tick_recent_seconds_sum", NULL, "", METRIC_SUMMARY, 6 },
    { "gale_tick_recent_seconds_count", NULL, "", METRIC_SUMMARY, 0 },
    { "gale_tick_phase_seconds_total", "phase=\"wind\"",
      "Wall time of the ticks' work by phase: the wind step's part in the tick, sampling the "
      "wind at the crowns, the modal update, leaf shedding and storm damage (together "
      "gale_tick_seconds), and publishing each snapshot after its tick.",
      METRIC_COUNTER, 6 },
    { "gale_tick_phase_seconds_total", "phase=\"sample\"", "", METRIC_COUNTER, 6 },
    { "gale_tick_phase_seconds_total", "phase=\"modal\"", "", METRIC_COUNTER, 6 },
    { "gale_tick_phase_seconds_total", "phase=\"leaves\"", "", METRIC_COUNTER, 6 },
    { "gale_tick_phase_seconds_total", "phase=\"damage\"", "", METRIC_COUNTER, 6 },
    { "gale_tick_phase_seconds_total", "phase=\"publish\"", "", METRIC_COUNTER, 6 },
    { "gale_tick_off_cpu_seconds_total", NULL,
      "Of the ticks' work, wall time the simulation thread was off a CPU: waiting for a core "
      "(another program, or the host), for a helper thread, or for the wind step beside the "
      "ticks.",
      METRIC_COUNTER, 6 },
    { "gale_tick_overruns_total", NULL, "Ticks that ended after the next one was due.",
      METRIC_COUNTER, 0 },
    { "gale_wind_steps_total", NULL, "Wind grid steps taken.", METRIC_COUNTER, 0 },
    { "gale_wind_step_seconds_total", NULL,
      "Wall time of the wind steps, beside the ticks or in them.", METRIC_COUNTER, 6 },
    { "gale_wind_step_seconds_max", NULL, "Longest wind step.", METRIC_GAUGE, 6 },
    { "gale_wind_step_waits_total", NULL,
      "Ticks held up by a wind step beside the ticks not yet done.", METRIC_COUNTER, 0 },
    { "gale_wind_step_wait_seconds_total", NULL, "Time those ticks waited for it.",
      METRIC_COUNTER, 6 },
    { "gale_wind_pressure_iterations", NULL,
      "Pressure solver iterations of the last wind step (0 without the wind grid).",
      METRIC_GAUGE, 0 },
    { "gale_wind_pressure_residual", NULL,
      "Relative residual ||b - A p|| / ||b|| of the last wind step's pressure solve.",
      METRIC_GAUGE, -6 },
    { "gale_wind_pressure_unconverged_total", NULL,
      "Wind steps whose pressure solve ran out of its iteration budget above its tolerance.",
      METRIC_COUNTER, 0 },
};

static int cmp_u32(const void *a, const void *b)
{
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* The recent ticks' quantiles (nearest rank), sum and count [s] into v[0..5]. */
static void recent_fill(sim_metrics *m, double *v)
{
    uint32_t us[SIM_RECENT_TICKS];
    const unsigned long long ticks = atomic_load(&m->ticks);
    const int n = ticks < SIM_RECENT_TICKS ? (int)ticks : SIM_RECENT_TICKS;
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        us[i] = atomic_load_explicit(&m->recent_us[i], memory_order_relaxed);
        sum += us[i];
    }
    qsort(us, (size_t)n, sizeof us[0], cmp_u32);
    for (int q = 0; q < SIM_RECENT_QUANTILES; q++) {
        const int rank = (int)ceil(sim_recent_quantile[q] * n); /* 1-based */
        v[q] = n ? (double)us[rank > 0 ? rank - 1 : 0] * 1e-6 : (double)NAN;
    }
    v[SIM_RECENT_QUANTILES] = sum * 1e-6;
    v[SIM_RECENT_QUANTILES + 1] = n;
}

static void sim_fill(void *ctx, double *v)
{
    sim_metrics *m = ctx;
    v[0] = (double)atomic_load(&m->ticks);
    double below = 0; /* buckets are cumulative on the page */
    for (int b = 0; b < SIM_TICK_BUCKETS; b++) {
        below += (double)atomic_load(&m->tick_le[b]);
        v[1 + b] = below;
    }
    const int h = 1 + SIM_TICK_BUCKETS;
    v[h] = (double)atomic_load(&m->tick_ns_sum) * 1e-9;
    v[h + 1] = below;
    v[h + 2] = (double)atomic_load(&m->tick_ns_max) * 1e-9;
    recent_fill(m, &v[h + 3]);
    const int ph = h + 3 + SIM_RECENT_QUANTILES + 2;
    for (int k = 0; k < SIM_PHASES; k++) {
        v[ph + k] = (double)atomic_load(&m->phase_ns[k]) * 1e-9;
    }
    v[ph + SIM_PHASES] = (double)atomic_load(&m->off_cpu_ns) * 1e-9;
    const int o = ph + SIM_PHASES + 1;
    v[o] = (double)atomic_load(&m->overruns);
    v[o + 1] = (double)atomic_load(&m->wind_steps);
    v[o + 2] = (double)atomic_load(&m->wind_step_ns_sum) * 1e-9;
    v[o + 3] = (double)atomic_load(&m->wind_step_ns_max) * 1e-9;
    v[o + 4] = (double)atomic_load(&m->wind_waits);
    v[o + 5] = (double)atomic_load(&m->wind_wait_ns_sum) * 1e-9;
    v[o + 6] = (double)atomic_load(&m->wind_iterations);
    v[o + 7] = atomic_load(&m->wind_residual);
    v[o + 8] = (double)atomic_load(&m->wind_unconverged);
}

/* ms as whole nanoseconds, 0 for a negative or not-a-number time. */
static uint64_t ms_to_ns(double ms)
{
    return ms > 0.0 ? (uint64_t)(ms * 1e6) : 0u;
}

uint64_t sim_metrics_tick(sim_metrics *m, uint32_t tick, const tick_stats *st)
{
    uint64_t ns = (uint64_t)(st->ms * 1e6);
    const double phase_ms[SIM_PHASE_PUBLISH] = { st->wind_ms, st->sample_ms, st->modal_ms,
                                                 st->leaves_ms, st->damage_ms };
    for (int k = 0; k < SIM_PHASE_PUBLISH; k++) {
        atomic_fetch_add(&m->phase_ns[k], ms_to_ns(phase_ms[k]));
    }
    atomic_fetch_add(&m->off_cpu_ns, ms_to_ns(st->ms - st->cpu_ms));
    atomic_store(&m->current_tick, tick);
    const unsigned long long k = atomic_fetch_add(&m->ticks, 1);
    const double us = st->ms * 1e3 + 0.5;
    atomic_store_explicit(&m->recent_us[k % SIM_RECENT_TICKS],
                          us < 4e9 ? (uint32_t)us : UINT32_MAX, memory_order_relaxed);
    atomic_fetch_add(&m->tick_ns_sum, ns);
    int b = 0;
    while (b < SIM_TICK_BUCKETS - 1 && (double)ns * 1e-9 > sim_tick_bucket_s[b]) {
        b++;
    }
    atomic_fetch_add(&m->tick_le[b], 1);
    if (ns > atomic_load(&m->tick_ns_max)) {
        atomic_store(&m->tick_ns_max, ns);
    }
    if (st->wind_stepped) {
        const uint64_t step_ns = (uint64_t)(st->wind_step_ms * 1e6);
        atomic_fetch_add(&m->wind_steps, 1);
        atomic_fetch_add(&m->wind_step_ns_sum, step_ns);
        if (step_ns > atomic_load(&m->wind_step_ns_max)) {
            atomic_store(&m->wind_step_ns_max, step_ns);
        }
        if (st->wind_wait_ms > 0.0) {
            atomic_fetch_add(&m->wind_waits, 1);
            atomic_fetch_add(&m->wind_wait_ns_sum, (uint64_t)(st->wind_wait_ms * 1e6));
        }
        atomic_store(&m->wind_iterations, st->wind_iters);
        atomic_store(&m->wind_residual, st->wind_residual);
        if (st->wind_unconverged) {
            atomic_fetch_add(&m->wind_unconverged, 1);
        }
    }
    return ns;
}

void sim_metrics_publish(sim_metrics *m, double publish_ms)
{
    atomic_fetch_add(&m->phase_ns[SIM_PHASE_PUBLISH], ms_to_ns(publish_ms));
}

unsigned long long sim_metrics_overrun(sim_metrics *m)
{
    return atomic_fetch_add(&m->overruns, 1) + 1;
}

int sim_metrics_describe(char *buf, size_t cap, const tick_stats *st, double publish_ms)
{
    const double phases = st->wind_ms + st->sample_ms + st->modal_ms + st->leaves_ms +
                          st->damage_ms;
    const double rest = st->ms - phases, off = st->ms - st->cpu_ms;
    int n = snprintf(buf, cap,
                     "wind %.2f ms (of it %.2f waiting for the step beside the ticks; %d "
                     "pressure iterations), sample %.2f, modal %.2f, leaves %.2f, damage %.2f, "
                     "other %.2f",
                     st->wind_ms, st->wind_wait_ms, st->wind_iters, st->sample_ms, st->modal_ms,
                     st->leaves_ms,
                     st->damage_ms, rest > 0.0 ? rest : 0.0);
    if (publish_ms >= 0.0 && n >= 0 && (size_t)n < cap) {
        n += snprintf(buf + n, cap - (size_t)n, "; publishing %.2f", publish_ms);
    }
    if (n >= 0 && (size_t)n < cap) {
        n += snprintf(buf + n, cap - (size_t)n, "; the sim thread off a CPU %.2f ms of it",
                      off > 0.0 ? off : 0.0);
    }
    return n;
}

int sim_metrics_register(sim_metrics *m, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, sim_rows, (int)(sizeof sim_rows / sizeof sim_rows[0]), sim_fill, m,
                          err);
}
