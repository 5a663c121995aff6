/* A seeded synthetic tree of an exact node count (trunk, branches spawned along each
 * branch with shrinking length and radius and a random twist), for benchmarks and tests
 * of the bake where the node count must be chosen freely. */
#ifndef GALE_BAKE_TREE_H
#define GALE_BAKE_TREE_H

#include <stdint.h>

#include "err.h"
#include "skeleton.h"

/* Fills *s (caller frees with skeleton_fini) with an n-node tree (n >= 2), 10 m tall,
 * trunk radius 0.25 m at the base, parents before children. Same (n, seed), same tree. */
int bake_tree_generate(int n, uint64_t seed, skeleton *s, gale_err *err);

#endif
