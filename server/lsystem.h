/* Randomized bracketed L-system tree generator (Oliapuram & Kumar 2010 section 1.4):
 * seeded and deterministic; radii and lengths shrink with depth, random twist. */
#ifndef GALE_LSYSTEM_H
#define GALE_LSYSTEM_H

#include <stdint.h>

#include "err.h"
#include "skeleton.h"

typedef struct lsystem_params {
    uint64_t seed;
    int target_nodes; /* 0: as the grammar gives; > 0: refine segments to about this many */
    /* the generator's grammar parameters follow; lsystem.c documents each */
    int depth;
    double trunk_length_m;
    double trunk_radius_m;
} lsystem_params;

/* Generates a skeleton from the parameters into *out (owned by the caller, free with
 * skeleton_fini). Same parameters, same skeleton, on every machine. */
int lsystem_generate(const lsystem_params *p, skeleton *out, gale_err *err);

#endif
