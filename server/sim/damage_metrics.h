/* The storm-damage rows of /metrics (server/SERVER.md "Serving"): branches broken, stems
 * snapped, trees uprooted, heals, events not streamed, and the leaf area still standing. */
#ifndef GALE_DAMAGE_METRICS_H
#define GALE_DAMAGE_METRICS_H

#include "damage.h"
#include "err.h"
#include "metric.h"

/* Adds the rows of c (borrowed for r's life) to r; fails only when r is full. */
int damage_metrics_register(damage_counts *c, metric_reg *r, gale_err *err);

#endif
