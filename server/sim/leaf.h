/* Leaf shedding on the server (Vazquez et al. 2008: leaves fall along one shared
 * precomputed path, each with its own variation): the server decides when a leaf leaves
 * its slot and streams a seed; clients fall it. The rate per slot rises with the square
 * of the wind speed above a calm threshold and is zero at or below it; draws are seeded
 * by (scene seed, tree, tick), so a run is reproducible. */
#ifndef GALE_LEAF_H
#define GALE_LEAF_H

#include <stddef.h>
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

/* Shares of the trees a thread of leaf_shed_trees: taken as threads come free, so a
 * thread late to its core holds the call up by one share, not by its whole part. */
#define LEAF_SHARES_PER_THREAD 4

/* The seeds of scratch leaf_shed_trees needs on n_threads threads at a cap of cap (0 on
 * one thread). */
size_t leaf_scratch_seeds(int n_threads, int cap);

/* The leaves of every tree for one tick: tree t has slots[t] slots (slots NULL: every
 * tree slots_all) and the wind wind[3 t..3 t + 2] [m/s] at its crown. The trees split
 * into contiguous shares (LEAF_SHARES_PER_THREAD a thread, each of 4096 trees or more)
 * drawn on n_threads threads, the first into out, the others into
 * scratch[leaf_scratch_seeds(n_threads, cap)], then merged after it in tree order under
 * the cap: the seeds, their order and the count lost are those of one thread. *max_ms
 * gets the strongest wind (may be NULL). Returns the number drawn that did not fit. */
int leaf_shed_trees(const leaf_desc *d, uint32_t n_trees, const float *wind,
                    const uint32_t *slots, uint32_t slots_all, uint32_t tick, double dt_s,
                    int n_threads, leaf_seed *scratch, leaf_seed *out, int cap, int *n,
                    float *max_ms);

#endif
