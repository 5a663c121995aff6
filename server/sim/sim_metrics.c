/* The simulation's metrics: see sim_metrics.h. */
#include "sim_metrics.h"

const double sim_tick_bucket_s[SIM_TICK_BUCKETS - 1] = { 0.0005, 0.001, 0.002, 0.004,
                                                          0.008,  0.016, 0.032, 0.064 };

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
    { "gale_tick_overruns_total", NULL, "Ticks that ended after the next one was due.",
      METRIC_COUNTER, 0 },
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
    v[h + 3] = (double)atomic_load(&m->overruns);
    v[h + 4] = (double)atomic_load(&m->wind_iterations);
    v[h + 5] = atomic_load(&m->wind_residual);
    v[h + 6] = (double)atomic_load(&m->wind_unconverged);
}

uint64_t sim_metrics_tick(sim_metrics *m, uint32_t tick, const tick_stats *st)
{
    uint64_t ns = (uint64_t)(st->ms * 1e6);
    atomic_store(&m->current_tick, tick);
    atomic_fetch_add(&m->ticks, 1);
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
        atomic_store(&m->wind_iterations, st->wind_iters);
        atomic_store(&m->wind_residual, st->wind_residual);
        if (st->wind_unconverged) {
            atomic_fetch_add(&m->wind_unconverged, 1);
        }
    }
    return ns;
}

unsigned long long sim_metrics_overrun(sim_metrics *m)
{
    return atomic_fetch_add(&m->overruns, 1) + 1;
}

int sim_metrics_register(sim_metrics *m, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, sim_rows, (int)(sizeof sim_rows / sizeof sim_rows[0]), sim_fill, m,
                          err);
}
