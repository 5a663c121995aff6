/* Metrics as rows for a Prometheus text page (exposition format 0.0.4): a registry of
 * row tables, each filled by its owner when the page is rendered, so whoever serves the
 * page knows names, help and types but not what any value means. */
#ifndef GALE_METRIC_H
#define GALE_METRIC_H

#include <stddef.h>

#include "err.h"

#define METRIC_MAX_TABLES 8  /* owners in one registry (simulation, network, publisher...) */
#define METRIC_MAX_ROWS 48   /* rows of one table (one fill call writes them all) */

/* METRIC_HISTOGRAM: a row of a histogram family, named <family>_bucket (with an le label,
 * cumulative), <family>_sum or <family>_count; METRIC_SUMMARY: a row of a summary family,
 * named <family> (with a quantile label), <family>_sum or <family>_count. HELP and TYPE
 * are written once for the family. */
typedef enum metric_type {
    METRIC_COUNTER,
    METRIC_GAUGE,
    METRIC_HISTOGRAM,
    METRIC_SUMMARY
} metric_type;

/* One sample. Rows of one name must follow each other: the first of them carries the
 * HELP and TYPE lines for all. */
typedef struct metric_row {
    const char *name;  /* [a-zA-Z_:][a-zA-Z0-9_:]*, e.g. "gale_ticks_total" */
    const char *label; /* NULL, or the label set written inside the braces: role="viewer" */
    const char *help;  /* one line, no newline */
    metric_type type;
    int digits;        /* >= 0: digits after the decimal point (0 for counts, 6 for
                          seconds); < 0: -digits significant digits, for values that span
                          decades (a solver residual) */
} metric_row;

/* Writes the current value of row i of the table into v[i] for every row; called on the
 * thread that renders, so it reads what other threads write atomically. */
typedef void (*metric_fill_fn)(void *ctx, double *v);

typedef struct metric_table {
    const metric_row *rows; /* borrowed [n_rows] */
    int n_rows;
    metric_fill_fn fill;
    void *ctx;              /* borrowed, passed to fill */
} metric_table;

/* Caller-owned; zero it before the first metric_reg_add. Complete it before it is
 * rendered from another thread (the registry itself takes no lock). */
typedef struct metric_reg {
    metric_table t[METRIC_MAX_TABLES];
    int n;
} metric_reg;

/* Appends a table of n_rows rows (1..METRIC_MAX_ROWS) filled by fill(ctx, v); rows and
 * ctx are borrowed for the registry's life. Fails with GALE_E_RANGE when the registry
 * is full or n_rows is out of range, GALE_E_ARG without rows or fill. */
int metric_reg_add(metric_reg *r, const metric_row *rows, int n_rows, metric_fill_fn fill,
                   void *ctx, gale_err *err);

/* The page: every table filled and written in the order added. Returns a malloc'd,
 * NUL-terminated text of *len bytes (the caller frees it), or NULL without memory. */
char *metric_reg_render(const metric_reg *r, size_t *len);

#endif
