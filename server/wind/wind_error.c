/* The error of a wind grid against a reference grid at tree points: see wind_error.h. */
#include "wind_error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* One grid's running record at every point: sums for the mean and variance (double: an
 * hour of 60 Hz samples stays exact enough), and the 3-s window as a ring. */
typedef struct side_rec {
    wind_grid *g;
    int every;
    float *v;        /* [n][3] sampled this tick */
    double *sum, *sum2, *best3, *win_sum;
    float *ring;     /* [n][win] */
    double *step_ms; /* [steps] */
    int n_steps, cap_steps;
} side_rec;

static void side_free(side_rec *s)
{
    wind_destroy(s->g);
    free(s->v);
    free(s->sum);
    free(s->sum2);
    free(s->best3);
    free(s->win_sum);
    free(s->ring);
    free(s->step_ms);
}

static int side_init(side_rec *s, const wind_desc *wd, int every, int n, int win, int steps,
                     gale_err *err)
{
    memset(s, 0, sizeof *s);
    s->g = wind_create(wd, err);
    if (!s->g) {
        return err->code;
    }
    s->every = every > 0 ? every : 1;
    s->v = calloc((size_t)n * 3, sizeof *s->v);
    s->sum = calloc((size_t)n, sizeof *s->sum);
    s->sum2 = calloc((size_t)n, sizeof *s->sum2);
    s->best3 = calloc((size_t)n, sizeof *s->best3);
    s->win_sum = calloc((size_t)n, sizeof *s->win_sum);
    s->ring = calloc((size_t)n * (size_t)win, sizeof *s->ring);
    s->cap_steps = steps / s->every + 2;
    s->step_ms = calloc((size_t)s->cap_steps, sizeof *s->step_ms);
    if (!s->v || !s->sum || !s->sum2 || !s->best3 || !s->win_sum || !s->ring || !s->step_ms) {
        return gale_errf(err, GALE_E_NOMEM, "wind_error_run: no memory for %d points", n);
    }
    return GALE_OK;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* One tick of one grid: the balls, a step when due, the samples, the record. */
static int side_tick(side_rec *s, long tick, float dt, const wind_ball *balls, int nb,
                     const wind_error_desc *d, int win, long rec_tick, gale_err *err)
{
    if (tick % s->every == 0) {
        for (int b = 0; b < nb; b++) {
            wind_add_ball(s->g, &balls[b]);
        }
        wind_step_stats st;
        if (wind_step(s->g, dt * (float)s->every, &st) < 0) {
            return gale_errf(err, GALE_E_NUMERIC, "wind_error_run: tick %ld: wind step broke "
                             "down", tick);
        }
        if (s->n_steps < s->cap_steps) {
            s->step_ms[s->n_steps++] = st.ms;
        }
    }
    if (rec_tick < 0) {
        return GALE_OK;
    }
    wind_sample_many(s->g, d->n_points, d->points, s->v);
    for (int i = 0; i < d->n_points; i++) {
        double sp = hypot((double)s->v[3 * i], (double)s->v[3 * i + 1]);
        s->sum[i] += sp;
        s->sum2[i] += sp * sp;
        float *ring = s->ring + (size_t)i * (size_t)win;
        int slot = (int)(rec_tick % win);
        s->win_sum[i] += sp - (rec_tick >= win ? (double)ring[slot] : 0.0);
        ring[slot] = (float)sp;
        if (rec_tick + 1 >= win && s->win_sum[i] > s->best3[i]) {
            s->best3[i] = s->win_sum[i];
        }
    }
    return GALE_OK;
}

int wind_error_run(const wind_error_desc *d, wind_error_result *r, gale_err *err)
{
    memset(r, 0, sizeof *r);
    const double hz = d->tick_hz > 0.0 ? d->tick_hz : 60.0;
    if (!d->drive || !d->points || d->n_points < 1 || !(d->record_s >= 3.0) ||
        !(d->spinup_s >= 0.0) || d->n_bins < 0 || d->n_bins > WIND_ERROR_MAX_BINS ||
        (d->n_bins > 0 && !(d->bin_m > 0.0f))) {
        return gale_errf(err, GALE_E_ARG, "wind_error_run: expected a drive, 1 or more points, "
                         "record_s >= 3, spinup_s >= 0 and 0..%d bins of a positive height",
                         WIND_ERROR_MAX_BINS);
    }
    const int n = d->n_points;
    const int win = (int)lround(3.0 * hz);
    const long spin = lround(d->spinup_s * hz), rec = lround(d->record_s * hz);
    const float dt = (float)(1.0 / hz);
    side_rec a, b;
    memset(&b, 0, sizeof b);
    int rc = side_init(&a, &d->ref, d->ref_every, n, win, (int)(spin + rec), err);
    if (!rc) {
        rc = side_init(&b, &d->test, d->test_every, n, win, (int)(spin + rec), err);
    }
    double *cross = rc ? NULL : calloc((size_t)n, sizeof *cross);
    double *perr = rc ? NULL : calloc((size_t)n * 3u, sizeof *perr);
    if (!rc && (!cross || !perr)) {
        rc = gale_errf(err, GALE_E_NOMEM, "wind_error_run: no memory for %d points", n);
    }
    for (long t = 0; !rc && t < spin + rec; t++) {
        wind_inflow in;
        const wind_ball *balls = NULL;
        int nb = 0;
        d->drive(d->drive_ctx, (double)t / hz, &in, &balls, &nb);
        wind_set_inflow(a.g, &in);
        wind_set_inflow(b.g, &in);
        if (t == 0) {
            wind_fill_inflow(a.g);
            wind_fill_inflow(b.g);
        }
        long rt = t - spin;
        rc = side_tick(&a, t, dt, balls, nb, d, win, rt, err);
        if (!rc) {
            rc = side_tick(&b, t, dt, balls, nb, d, win, rt, err);
        }
        for (int i = 0; !rc && rt >= 0 && i < n; i++) {
            cross[i] += hypot((double)a.v[3 * i], (double)a.v[3 * i + 1]) *
                        hypot((double)b.v[3 * i], (double)b.v[3 * i + 1]);
        }
    }
    if (!rc) {
        const double nr = (double)rec;
        for (int bi = 0; bi < d->n_bins; bi++) {
            r->bin[bi].z_lo_m = d->bin_z0_m + (float)bi * d->bin_m;
            r->bin[bi].z_hi_m = r->bin[bi].z_lo_m + d->bin_m;
        }
        r->n_bins = d->n_bins;
        for (int i = 0; i < n; i++) {
            double ma = a.sum[i] / nr, mb = b.sum[i] / nr;
            double va = fmax(a.sum2[i] / nr - ma * ma, 0.0), vb = fmax(b.sum2[i] / nr - mb * mb, 0.0);
            double sa = sqrt(va), sb = sqrt(vb);
            double ga = ma > 0.0 ? a.best3[i] / win / ma : 0.0;
            double gb = mb > 0.0 ? b.best3[i] / win / mb : 0.0;
            r->ref.mean_ms += ma / n;
            r->test.mean_ms += mb / n;
            r->ref.std_ms += sa / n;
            r->test.std_ms += sb / n;
            r->ref.gust3 += ga / n;
            r->test.gust3 += gb / n;
            double em = ma > 0.0 ? fabs(mb - ma) / ma : 0.0;
            double es = sa > 0.0 ? fabs(sb - sa) / sa : 0.0;
            double eg = fabs(gb - ga);
            r->mean_rel_err += em / n;
            r->std_rel_err += es / n;
            r->gust3_abs_err += eg / n;
            r->mean_rel_err_max = fmax(r->mean_rel_err_max, em);
            r->std_rel_err_max = fmax(r->std_rel_err_max, es);
            r->gust3_abs_err_max = fmax(r->gust3_abs_err_max, eg);
            perr[i] = em;
            perr[n + i] = es;
            perr[2 * n + i] = eg;
            double cov = cross[i] / nr - ma * mb;
            r->corr += (sa > 0.0 && sb > 0.0 ? cov / (sa * sb) : 1.0) / n;
            if (d->n_bins > 0) {
                int bi = (int)floorf((d->points[3 * i + 2] - d->bin_z0_m) / d->bin_m);
                if (bi >= 0 && bi < d->n_bins) {
                    r->bin[bi].n++;
                    r->bin[bi].ref_ms += ma;
                    r->bin[bi].test_ms += mb;
                }
            }
        }
        for (int bi = 0; bi < d->n_bins; bi++) {
            if (r->bin[bi].n > 0) {
                r->bin[bi].ref_ms /= r->bin[bi].n;
                r->bin[bi].test_ms /= r->bin[bi].n;
            }
        }
        double *p90[3] = { &r->mean_rel_err_p90, &r->std_rel_err_p90, &r->gust3_abs_err_p90 };
        for (int q = 0; q < 3; q++) {
            qsort(perr + (size_t)q * (size_t)n, (size_t)n, sizeof(double), cmp_double);
            *p90[q] = perr[(size_t)q * (size_t)n + (size_t)((n - 1) * 9 / 10)];
        }
        qsort(a.step_ms, (size_t)a.n_steps, sizeof(double), cmp_double);
        qsort(b.step_ms, (size_t)b.n_steps, sizeof(double), cmp_double);
        r->ref.step_ms = a.n_steps ? a.step_ms[a.n_steps / 2] : 0.0;
        r->test.step_ms = b.n_steps ? b.step_ms[b.n_steps / 2] : 0.0;
    }
    free(cross);
    free(perr);
    side_free(&a);
    side_free(&b);
    return rc;
}
