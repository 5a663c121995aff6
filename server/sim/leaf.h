/* Leaf shedding on the server (Vazquez et al. 2008: leaves fall along one shared
 * precomputed path, each with its own variation): the server decides when a leaf leaves
 * its slot and streams a seed; clients fall it. The rate per slot rises with the square
 * of the wind speed above a calm threshold and is zero at or below it; draws are seeded
 * by (scene seed, tree, tick), so a run is reproducible. */
#ifndef GALE_LEAF_H
#define GALE_LEAF_H

#include <stdint.h>

typedef struct leaf_desc {
    float rate_hz;   /* sheds per slot per second at ref_ms; 0 → no shedding */
    float calm_ms;   /* no shedding at or below this wind speed [m/s] */
    float ref_ms;    /* reference speed [m/s], > calm_ms */
    uint64_t seed;
} leaf_desc;

/* One shed leaf, as streamed to clients. */
typedef struct leaf_seed {
    uint32_t instance;   /* tree index in the scene */
    uint32_t slot;       /* leaf slot of that tree's species */
    uint32_t spawn_tick; /* tick it left the tree */
    uint32_t variation;  /* per-leaf variation seed (rotation, scale, start point) */
} leaf_seed;

/* Shedding rate per slot [1/s] at wind speed speed_ms:
 * rate_hz ((speed - calm) / (ref - calm))², zero at or below calm. */
double leaf_rate(const leaf_desc *d, double speed_ms);

/* Draws the leaves tree `instance` (n_slots slots, wind speed speed_ms at its crown)
 * sheds during tick `tick` of length dt_s: a Poisson count (mean capped at 32 per tree
 * per tick), written to out[0..cap) starting at out[*n], *n advanced. Returns the number
 * drawn that did not fit (the caller counts them). */
int leaf_shed(const leaf_desc *d, uint32_t instance, uint32_t n_slots, double speed_ms,
              uint32_t tick, double dt_s, leaf_seed *out, int cap, int *n);

#endif
