/* The metric registry (metric.h): Prometheus text byte for byte (HELP and TYPE once per
 * name, labels, fixed and significant digits, NaN and infinities), growth past the
 * first buffer, its limits; and the simulation's rows (sim_metrics.h) after a tick, the
 * recent ticks' quantiles over their window alone. */
#include "check.h"
#include "metric.h"
#include "sim_metrics.h"

#include <stdlib.h>

static const metric_row rows_a[] = {
    { "a_total", NULL, "A things.", METRIC_COUNTER, 0 },
    { "b_seconds", NULL, "B time.", METRIC_GAUGE, 6 },
};

static const metric_row rows_b[] = {
    { "c", "role=\"x\"", "C by role.", METRIC_GAUGE, 0 },
    { "c", "role=\"y\"", "C by role.", METRIC_GAUGE, 0 },
    { "d", NULL, "D.", METRIC_GAUGE, -3 },
    { "e", NULL, "E.", METRIC_GAUGE, 2 },
    { "f", NULL, "F.", METRIC_GAUGE, 2 },
};

static void fill_a(void *ctx, double *v)
{
    const double *src = ctx;
    v[0] = src[0];
    v[1] = src[1];
}

static void fill_b(void *ctx, double *v)
{
    (void)ctx;
    v[0] = 3;
    v[1] = 0;
    v[2] = 1.2345e-7;
    v[3] = (double)NAN;
    v[4] = -(double)INFINITY;
}

static void test_render(void)
{
    metric_reg r;
    memset(&r, 0, sizeof r);
    double a[2] = { 12, 0.25 };
    CHECK(metric_reg_add(&r, rows_a, 2, fill_a, a, NULL) == 0);
    CHECK(metric_reg_add(&r, rows_b, 5, fill_b, NULL, NULL) == 0);
    size_t len = 0;
    char *t = metric_reg_render(&r, &len);
    const char *want = "# HELP a_total A things.\n# TYPE a_total counter\na_total 12\n"
                       "# HELP b_seconds B time.\n# TYPE b_seconds gauge\nb_seconds 0.250000\n"
                       "# HELP c C by role.\n# TYPE c gauge\nc{role=\"x\"} 3\nc{role=\"y\"} 0\n"
                       "# HELP d D.\n# TYPE d gauge\nd 1.23e-07\n"
                       "# HELP e E.\n# TYPE e gauge\ne NaN\n"
                       "# HELP f F.\n# TYPE f gauge\nf -Inf\n";
    CHECK(t && !strcmp(t, want));
    CHECK(t && len == strlen(want));
    if (t && strcmp(t, want)) {
        fprintf(stderr, "got:\n%s", t);
    }
    free(t);
    a[0] = 13; /* values are read at each render */
    t = metric_reg_render(&r, &len);
    CHECK(t && strstr(t, "\na_total 13\n"));
    free(t);
}

static const metric_row long_row[] = {
    { "a_long_metric_name_to_fill_the_page_total", NULL,
      "A help line long enough that a few hundred of them outgrow the first buffer.",
      METRIC_COUNTER, 0 },
};

static void fill_one(void *ctx, double *v)
{
    (void)ctx;
    v[0] = 1;
}

static void test_growth_and_limits(void)
{
    metric_reg r;
    memset(&r, 0, sizeof r);
    metric_row many[METRIC_MAX_ROWS];
    for (int i = 0; i < METRIC_MAX_ROWS; i++) {
        many[i] = long_row[0];
    }
    for (int k = 0; k < METRIC_MAX_TABLES; k++) {
        CHECK(metric_reg_add(&r, many, METRIC_MAX_ROWS, fill_one, NULL, NULL) == 0);
    }
    gale_err e;
    CHECK(metric_reg_add(&r, long_row, 1, fill_one, NULL, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "metric_reg_add: tables: expected <= 8, got 9");
    size_t len = 0;
    char *t = metric_reg_render(&r, &len);
    /* one family: HELP and TYPE once, then every sample */
    size_t one = strlen("a_long_metric_name_to_fill_the_page_total 1\n");
    size_t head = strlen("# HELP a_long_metric_name_to_fill_the_page_total ") +
                  strlen(long_row[0].help) + 1 +
                  strlen("# TYPE a_long_metric_name_to_fill_the_page_total counter\n");
    CHECK(t && len == head + one * METRIC_MAX_ROWS * METRIC_MAX_TABLES && len > 4096);
    CHECK(t && strlen(t) == len);
    free(t);

    memset(&r, 0, sizeof r);
    CHECK(metric_reg_add(&r, long_row, 0, fill_one, NULL, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "metric_reg_add: rows: expected 1..48, got 0");
    CHECK(metric_reg_add(&r, long_row, 1, NULL, NULL, &e) == GALE_E_ARG);
    t = metric_reg_render(&r, &len); /* empty registry: empty page */
    CHECK(t && len == 0 && !t[0]);
    free(t);
}

static void test_sim_rows(void)
{
    sim_metrics m;
    memset(&m, 0, sizeof m);
    metric_reg r;
    memset(&r, 0, sizeof r);
    CHECK(sim_metrics_register(&m, &r, NULL) == 0);
    tick_stats ts = { .ms = 2.5, .wind_stepped = true, .wind_iters = 30, .wind_residual = 0.0125,
                      .wind_unconverged = true, .wind_step_ms = 3.25, .wind_wait_ms = 0.5,
                      .wind_ms = 0.75, .sample_ms = 0.25, .modal_ms = 1.0, .leaves_ms = 0.125,
                      .damage_ms = 0.25, .cpu_ms = 1.5 };
    CHECK(sim_metrics_tick(&m, 1, &ts) == 2500000u);
    sim_metrics_publish(&m, 0.5);
    ts = (tick_stats){ .ms = 1.0 }; /* no wind step: the solver gauges keep the last one */
    CHECK(sim_metrics_tick(&m, 2, &ts) == 1000000u);
    /* a step beside the ticks done before its tick: no wait */
    ts = (tick_stats){ .ms = 4.0, .wind_stepped = true, .wind_iters = 30,
                       .wind_residual = 0.0125, .wind_step_ms = 1.0, .modal_ms = 2.0,
                       .cpu_ms = 4.0 };
    CHECK(sim_metrics_tick(&m, 3, &ts) == 4000000u);
    sim_metrics_publish(&m, 0.25);
    CHECK(sim_metrics_overrun(&m) == 1);
    CHECK(atomic_load(&m.current_tick) == 3);
    size_t len = 0;
    char *t = metric_reg_render(&r, &len);
    CHECK(t != NULL);
    if (t) {
        CHECK_STR_HAS(t, "# TYPE gale_ticks_total counter\ngale_ticks_total 3\n");
        CHECK_STR_HAS(t, "\ngale_tick_seconds_sum 0.007500\n");
        CHECK_STR_HAS(t, "# TYPE gale_tick_seconds_max gauge\ngale_tick_seconds_max 0.004000\n");
        CHECK_STR_HAS(t, "\ngale_tick_overruns_total 1\n");
        CHECK_STR_HAS(t, "# TYPE gale_wind_pressure_iterations gauge\n"
                         "gale_wind_pressure_iterations 30\n");
        CHECK_STR_HAS(t, "\ngale_wind_pressure_residual 0.0125\n");
        CHECK_STR_HAS(t, "# TYPE gale_wind_pressure_unconverged_total counter\n"
                         "gale_wind_pressure_unconverged_total 1\n");
        /* three ticks in the window: nearest ranks 2 and 3 */
        CHECK_STR_HAS(t, "# TYPE gale_tick_recent_seconds summary\n"
                         "gale_tick_recent_seconds{quantile=\"0.5\"} 0.002500\n"
                         "gale_tick_recent_seconds{quantile=\"0.9\"} 0.004000\n");
        CHECK_STR_HAS(t, "\ngale_tick_recent_seconds_sum 0.007500\n"
                         "gale_tick_recent_seconds_count 3\n");
        CHECK_STR_HAS(t, "\ngale_wind_steps_total 2\n");
        CHECK_STR_HAS(t, "\ngale_wind_step_seconds_total 0.004250\n");
        CHECK_STR_HAS(t, "\ngale_wind_step_seconds_max 0.003250\n");
        CHECK_STR_HAS(t, "\ngale_wind_step_waits_total 1\n");
        CHECK_STR_HAS(t, "\ngale_wind_step_wait_seconds_total 0.000500\n");
        /* the phases over the three ticks, publishing apart; off a CPU: 1.0 + 1.0 + 0 ms
           (the second tick's stats say no CPU time at all) */
        CHECK_STR_HAS(t, "# TYPE gale_tick_phase_seconds_total counter\n"
                         "gale_tick_phase_seconds_total{phase=\"wind\"} 0.000750\n"
                         "gale_tick_phase_seconds_total{phase=\"sample\"} 0.000250\n"
                         "gale_tick_phase_seconds_total{phase=\"modal\"} 0.003000\n"
                         "gale_tick_phase_seconds_total{phase=\"leaves\"} 0.000125\n"
                         "gale_tick_phase_seconds_total{phase=\"damage\"} 0.000250\n"
                         "gale_tick_phase_seconds_total{phase=\"publish\"} 0.000750\n");
        CHECK_STR_HAS(t, "\ngale_tick_off_cpu_seconds_total 0.002000\n");
    }
    free(t);
}

/* The overrun line's account of a tick: each phase, what no phase accounts for, the
 * publishing when there was one, and the time off a CPU. */
static void test_describe(void)
{
    const tick_stats ts = { .ms = 20.0, .wind_ms = 1.5, .wind_wait_ms = 1.25, .wind_iters = 12,
                            .sample_ms = 2.0, .modal_ms = 12.0, .leaves_ms = 0.5,
                            .damage_ms = 3.0, .cpu_ms = 8.75 };
    char buf[320];
    sim_metrics_describe(buf, sizeof buf, &ts, 2.5);
    CHECK_STR_HAS(buf, "wind 1.50 ms (of it 1.25 waiting for the step beside the ticks; 12 "
                       "pressure iterations), sample 2.00, modal 12.00, leaves 0.50, damage "
                       "3.00, other 1.00; "
                       "publishing 2.50; the sim thread off a CPU 11.25 ms of it");
    sim_metrics_describe(buf, sizeof buf, &ts, -1.0);
    CHECK(strstr(buf, "publishing") == NULL);
    CHECK_STR_HAS(buf, "other 1.00; the sim thread off a CPU 11.25 ms");
    char small[24];
    const int n = sim_metrics_describe(small, sizeof small, &ts, 2.5);
    CHECK(n > (int)sizeof small && strlen(small) == sizeof small - 1);
}

/* gale_tick_recent_seconds covers the last SIM_RECENT_TICKS ticks alone: 1400 slow ticks,
 * then 3600 of 1..3600 ms in a shuffled order, give the second set's quantiles by nearest
 * rank (the 1800th, 3240th, 3564th and 3597th smallest) and its sum, not the slow ones. */
static void test_recent_window(void)
{
    CHECK(SIM_RECENT_TICKS == 3600);
    sim_metrics *m = calloc(1, sizeof *m);
    metric_reg r;
    memset(&r, 0, sizeof r);
    CHECK(m && sim_metrics_register(m, &r, NULL) == 0);
    if (!m) {
        return;
    }
    uint32_t tick = 0;
    for (int i = 0; i < 1400; i++) {
        sim_metrics_tick(m, ++tick, &(tick_stats){ .ms = 100000.0 });
    }
    for (int i = 0; i < 3600; i++) {
        const int ms = (i * 7) % 3600 + 1; /* 7 is prime to 3600: each of 1..3600 once */
        sim_metrics_tick(m, ++tick, &(tick_stats){ .ms = ms });
    }
    size_t len = 0;
    char *t = metric_reg_render(&r, &len);
    CHECK(t != NULL);
    if (t) {
        CHECK_STR_HAS(t, "gale_tick_recent_seconds{quantile=\"0.5\"} 1.800000\n"
                         "gale_tick_recent_seconds{quantile=\"0.9\"} 3.240000\n"
                         "gale_tick_recent_seconds{quantile=\"0.99\"} 3.564000\n"
                         "gale_tick_recent_seconds{quantile=\"0.999\"} 3.597000\n"
                         "gale_tick_recent_seconds_sum 6481.800000\n"
                         "gale_tick_recent_seconds_count 3600\n");
        CHECK_STR_HAS(t, "\ngale_ticks_total 5000\n");
    }
    free(t);
    free(m);
}

int main(void)
{
    RUN(test_render);
    RUN(test_growth_and_limits);
    RUN(test_sim_rows);
    RUN(test_describe);
    RUN(test_recent_window);
    return check_report();
}
