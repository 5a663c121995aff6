/* Metric registry and its Prometheus text rendering: see metric.h. */
#include "metric.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A growing text buffer; bad once an allocation failed. */
typedef struct metric_buf {
    char *b;
    size_t n, cap;
    int bad;
} metric_buf;

static void buf_printf(metric_buf *m, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void buf_printf(metric_buf *m, const char *fmt, ...)
{
    for (int pass = 0; pass < 2 && !m->bad; pass++) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(m->b + m->n, m->cap - m->n, fmt, ap);
        va_end(ap);
        if (k < 0) {
            m->bad = 1;
            return;
        }
        if ((size_t)k < m->cap - m->n) {
            m->n += (size_t)k;
            return;
        }
        size_t cap = m->cap * 2 > m->n + (size_t)k + 1 ? m->cap * 2 : m->n + (size_t)k + 1;
        char *b = realloc(m->b, cap);
        if (!b) {
            m->bad = 1;
            return;
        }
        m->b = b;
        m->cap = cap;
    }
}

/* Prometheus writes non-finite values as NaN, +Inf, -Inf. */
static void put_value(metric_buf *m, double v, int digits)
{
    if (isnan(v)) {
        buf_printf(m, "NaN\n");
    } else if (isinf(v)) {
        buf_printf(m, "%sInf\n", v > 0 ? "+" : "-");
    } else if (digits < 0) {
        buf_printf(m, "%.*g\n", -digits, v);
    } else {
        buf_printf(m, "%.*f\n", digits, v);
    }
}

static int has_suffix(const char *s, const char *suffix)
{
    const size_t n = strlen(s), k = strlen(suffix);
    return n > k && strcmp(s + n - k, suffix) == 0;
}

int metric_reg_add(metric_reg *r, const metric_row *rows, int n_rows, metric_fill_fn fill,
                   void *ctx, gale_err *err)
{
    if (!rows || !fill) {
        return gale_errf(err, GALE_E_ARG, "metric_reg_add: rows and fill are required");
    }
    if (n_rows < 1 || n_rows > METRIC_MAX_ROWS) {
        return gale_errf(err, GALE_E_RANGE, "metric_reg_add: rows: expected 1..%d, got %d",
                         METRIC_MAX_ROWS, n_rows);
    }
    if (r->n >= METRIC_MAX_TABLES) {
        return gale_errf(err, GALE_E_RANGE, "metric_reg_add: tables: expected <= %d, got %d",
                         METRIC_MAX_TABLES, r->n + 1);
    }
    r->t[r->n++] = (metric_table){ .rows = rows, .n_rows = n_rows, .fill = fill, .ctx = ctx };
    return GALE_OK;
}

char *metric_reg_render(const metric_reg *r, size_t *len)
{
    metric_buf m = { .cap = 4096 };
    m.b = malloc(m.cap);
    if (!m.b) {
        return NULL;
    }
    m.b[0] = 0;
    const char *family = NULL;
    char family_buf[128];
    for (int k = 0; k < r->n; k++) {
        const metric_table *t = &r->t[k];
        double v[METRIC_MAX_ROWS] = { 0 };
        t->fill(t->ctx, v);
        for (int i = 0; i < t->n_rows; i++) {
            const metric_row *row = &t->rows[i];
            /* a histogram's family is its rows' name less _bucket, _sum or _count; a
               summary's, less _sum or _count (its quantiles carry the family's name) */
            size_t flen = strlen(row->name);
            if (row->type == METRIC_HISTOGRAM) {
                const char *u = strrchr(row->name, '_');
                flen = u ? (size_t)(u - row->name) : flen;
            } else if (row->type == METRIC_SUMMARY) {
                flen -= has_suffix(row->name, "_sum")     ? 4
                        : has_suffix(row->name, "_count") ? 6
                                                          : 0;
            }
            if (!family || strlen(family) != flen || strncmp(family, row->name, flen)) {
                buf_printf(&m, "# HELP %.*s %s\n# TYPE %.*s %s\n", (int)flen, row->name,
                           row->help, (int)flen, row->name,
                           row->type == METRIC_COUNTER     ? "counter"
                           : row->type == METRIC_GAUGE     ? "gauge"
                           : row->type == METRIC_HISTOGRAM ? "histogram"
                                                           : "summary");
                snprintf(family_buf, sizeof family_buf, "%.*s", (int)flen, row->name);
                family = family_buf;
            }
            if (row->label) {
                buf_printf(&m, "%s{%s} ", row->name, row->label);
            } else {
                buf_printf(&m, "%s ", row->name);
            }
            put_value(&m, v[i], row->digits);
        }
    }
    if (m.bad) {
        free(m.b);
        return NULL;
    }
    *len = m.n;
    return m.b;
}
