/* Batch modal state of every tree (Diener 2008 sections 3-4): per tree and mode the
 * damped oscillator (q, q'), driven by f_i = |v| v.p_i with v the wind in the tree's
 * frame, advanced by the exact discrete update (server/oscillator.h), then quantised
 * into the snapshot buffer the wire encoder reads (protocol/wire.h). */
#ifndef GALE_MODAL_H
#define GALE_MODAL_H

#include <stddef.h>
#include <stdint.h>

#include "drag_law.h"
#include "err.h"

/* One species' modal data (borrowed for modal_create only; copied). */
typedef struct modal_species {
    uint32_t n_modes;          /* 1..WIRE_MAX_MODES */
    const float *omega;        /* [n_modes] [rad/s] > 0 */
    const float *gamma;        /* [n_modes] [1/s] >= 0 */
    const float *wind_basis;   /* [n_modes][3] p_i, tree frame */
    const float *qstep;        /* [n_modes] quantisation step (quant_steps_derive) > 0 */
} modal_species;

typedef struct modal_desc {
    uint32_t n_trees;             /* 1..WIRE_MAX_TREES */
    uint32_t n_species;           /* 1..WIRE_MAX_SPECIES */
    const modal_species *species; /* [n_species] borrowed for the call */
    const uint8_t *tree_species;  /* [n_trees] index into species, borrowed for the call */
    const drag_law *species_drag; /* [n_species] streamlining, borrowed for the call; NULL:
                                   * rigid drag, f ∝ U², for every species */
    const float *tree_yaw_rad;    /* [n_trees] rotation about z, tree -> world; NULL = 0 */
    double dt_s;                  /* tick length [s]; 0 = 1/60 */
    int n_threads;                /* worker threads for modal_tick; 0 = 2, 1 = none */
} modal_desc;

typedef struct modal modal;

/* Allocates the state (all q, q' zero) for d; NULL with err filled on bad desc or
 * no memory. Threads, if any, are started here and live until modal_destroy. */
modal *modal_create(const modal_desc *d, gale_err *err);
void modal_destroy(modal *m); /* NULL is a no-op */

/* Snapshot buffer stride: int16 per tree (the largest species' mode count). */
uint32_t modal_stride(const modal *m);
uint32_t modal_n_trees(const modal *m);
/* Modes of tree t's species. */
uint32_t modal_tree_modes(const modal *m, uint32_t t);

/* One tick: wind_world[3 t + k] is the wind sampled at tree t (world frame, [m/s]);
 * each tree's modes advance by one dt under f_i = s(|v|) k_t |v| v.p_i (v rotated into the tree
 * frame by -yaw; s the species' drag_law_scale, k_t the tree's drag factor), and qsnap[t * stride + i] receives the quantised q (when qsnap is not
 * NULL; entries beyond a tree's modes are written 0). Does not allocate. */
void modal_tick(modal *m, const float *wind_world, int16_t *qsnap);

/* Float state of tree t: q[n] and qdot[n] for n = its modes (either may be NULL);
 * returns n. */
uint32_t modal_get(const modal *m, uint32_t t, float *q, float *qdot);
/* Tree t's drag factor (default 1): every modal force of the tree is multiplied by it,
 * e.g. by the leaf area and branches a storm has left (damage.h). Ignored for t out of range or a negative or
 * non-finite value. */
void modal_set_drag_mult(modal *m, uint32_t t, float mult);
float modal_drag_mult(const modal *m, uint32_t t); /* 0 for t out of range */

/* Sets tree t's state (tests, restore). */
void modal_set(modal *m, uint32_t t, const float *q, const float *qdot);

/* Read-only views of every tree's state and of what the last modal_tick kept per tree,
 * for a reader that goes over many trees (damage.c) without a call for each: tree t's q
 * is state[t * stride .. + pad) (its modes, then zeros up to pad, a whole number of
 * 16-float vectors), qnorm2[t] its Σ_i q_i² after the last modal_tick (0 before any;
 * modal_set leaves it), and force_scale[t] the factor s(|v|) k_t |v| of its force
 * vector w = s k_t |v| v that tick (0 before any, and for a sample the tick treated as
 * calm air). They stay valid until modal_destroy; modal_tick and modal_set change what
 * they show. */
typedef struct modal_rows {
    const float *state;
    size_t stride;
    uint32_t pad;
    const float *qnorm2, *force_scale;
} modal_rows;
modal_rows modal_get_rows(const modal *m);

#endif
