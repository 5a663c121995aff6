/* How the wind's load is spread over a tree (PHYSICS.md "Wind load"): the wood takes
 * C D w per length scaled by `wood`, and each tip (a node without children, where the
 * leaves grow) a point load C tip_m2 w, w the force vector of the modal force. The leaves
 * carry the share `leaf_share` of the tree's static moment about its root under a
 * horizontal wind, the wood the rest, so the base moment (the sway, the stem's load) stays
 * what C D w over the wood alone gives, while a branch's own sail, its leaves, loads it.
 * The bake's wind basis (basis.c) and the damage table's statics (damage_table.c) both
 * take the split from here. */
#ifndef GALE_CROWN_LOAD_H
#define GALE_CROWN_LOAD_H

#include <stdint.h>

typedef struct crown_load {
    double wood;     /* multiplier of C D per length on every element, 1 - leaf_share */
    double tip_m2;   /* point load of each tip per unit C and w [m²] */
    uint32_t n_tips; /* nodes without children */
} crown_load;

/* The split for the n nodes (parent[i] < i, parent[0] = -1; rest positions pos[3 n] z up
 * and radii [m]; an element's diameter is the sum of its nodes' radii) with the leaves'
 * share leaf_share in [0, 1] (0: the wood alone, tip_m2 0). A tree with no height above
 * its root or no tips gets the wood alone. */
crown_load crown_load_split(uint32_t n, const int32_t *parent, const float *pos,
                            const float *radius, double leaf_share);

/* 1 for each node without children into tip[n] (caller's). */
void crown_load_tips(uint32_t n, const int32_t *parent, uint8_t *tip);

#endif
