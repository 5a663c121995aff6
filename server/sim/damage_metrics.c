/* The storm-damage rows of /metrics: see damage_metrics.h. */
#include "damage_metrics.h"

static const metric_row damage_rows[] = {
    { "gale_branches_broken_total", NULL, "Branches broken off by the wind.", METRIC_COUNTER, 0 },
    { "gale_trees_snapped_total", NULL, "Trees whose stem snapped.", METRIC_COUNTER, 0 },
    { "gale_trees_uprooted_total", NULL, "Trees uprooted.", METRIC_COUNTER, 0 },
    { "gale_damage_heals_total", NULL, "Heals of the forest (reset, scenario restart).",
      METRIC_COUNTER, 0 },
    { "gale_damage_events_lost_total", NULL, "Damage events over the per-tick or log cap.",
      METRIC_COUNTER, 0 },
    { "gale_leaf_area_remaining_ratio", NULL,
      "Standing leaf area over the intact forest's (0..1).", METRIC_GAUGE, 4 },
};

static void damage_fill(void *ctx, double *v)
{
    damage_counts *c = ctx;
    v[0] = (double)atomic_load(&c->branches);
    v[1] = (double)atomic_load(&c->snapped);
    v[2] = (double)atomic_load(&c->uprooted);
    v[3] = (double)atomic_load(&c->heals);
    v[4] = (double)atomic_load(&c->lost);
    v[5] = atomic_load(&c->leaf_area);
}

int damage_metrics_register(damage_counts *c, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, damage_rows, (int)(sizeof damage_rows / sizeof damage_rows[0]),
                          damage_fill, c, err);
}
