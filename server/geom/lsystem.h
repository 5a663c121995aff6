/* Randomized bracketed L-system tree generator (Oliapuram & Kumar 2010 section 1.4):
 * seeded and deterministic; radii and lengths shrink with depth, random twist. */
#ifndef GALE_LSYSTEM_H
#define GALE_LSYSTEM_H

#include <stdint.h>

#include "err.h"
#include "skeleton.h"

/* How a stem spawns its children, the rule F = G [R1 F] ... [Rk F] [F] of section 1.4
 * spread along the stem: `whorls` attachment points in [start, end] of its length with
 * `per_whorl` children each, plus `tip_children` at its end (and one continuation [F]
 * when tip_continue). Every child stem is again grown by a rule, one level deeper. */
typedef struct lsystem_rule {
    int whorls;              /* lateral attachment points along the stem, 0..64 */
    int per_whorl;           /* children per whorl, evenly around the axis, 0..16 */
    double start, end;       /* fraction of the stem carrying the whorls, 0 <= start <= end <= 1 */
    double angle_deg;        /* lateral branching angle from the parent axis [deg] */
    int tip_children;        /* angled children at the stem tip, 0..32 */
    double tip_angle_deg;    /* their angle from the parent axis [deg] */
    int tip_continue;        /* 1: one more tip child continues the axis ([F]) */
    double continue_ratio;   /* its length / parent length */
    double angle_jitter_deg; /* uniform random spread of every branching angle [deg] */
    double length_ratio;     /* child length / parent length (at the first whorl, and tip) */
    double length_top;       /* multiplier of length_ratio at the last whorl (conifers < 1) */
    double length_jitter;    /* relative uniform spread of child lengths, 0..0.9 */
    double radius_ratio;     /* child base radius / parent radius where it attaches */
    double taper;            /* child tip radius / its base radius, (0, 1] */
    double bend_deg;         /* total bend of a child stem toward +z (> 0) or -z (< 0) [deg] */
    double prune_prob;       /* probability that a child is not grown, 0..1 */
} lsystem_rule;

typedef struct lsystem_params {
    uint64_t seed;
    int target_nodes; /* 0: as the grammar gives; > 0: refine segments to about this many */
    /* the generator's grammar parameters follow; lsystem.c documents each */
    int depth;               /* recursion levels below the trunk, 0..10 */
    double trunk_length_m;   /* arc length of the trunk stem [m] */
    double trunk_radius_m;   /* trunk radius at the root [m] */
    double trunk_taper;      /* trunk tip radius / root radius, (0, 1] */
    double trunk_bend_deg;   /* total curve of the trunk toward a random side [deg] */
    double segment_m;        /* element length the stems are cut into [m]; 0: trunk / 10 */
    double twist_deg;        /* azimuth step between successive whorls (phyllotaxis) [deg] */
    double twist_jitter_deg; /* random extra rotation about the axis per whorl [deg] */
    double wobble_deg;       /* random deviation of a stem's direction along its length [deg] */
    double tip_radius_m;     /* thinnest stem radius [m], 0..1; 0: 2 mm */
    double pipe_exponent;    /* 0: radii as the rules give; 1.5..4: the pipe model (da Vinci)
                              * r^e >= sum of r_child^e raises every radius to carry its
                              * children */
    lsystem_rule trunk;      /* how the trunk spawns the first branches */
    lsystem_rule branch;     /* how every deeper stem spawns its children */
    char where[160];         /* first word of every failure: the species file these came
                              * from (species_parse sets it); "" reads "lsystem" */
} lsystem_params;

/* A parameter set that gives a plain broadleaf tree; species files start from it. */
lsystem_params lsystem_params_default(void);

/* Generates a skeleton from the parameters into *out (owned by the caller, free with
 * skeleton_fini). Same parameters, same skeleton, on every machine. Nodes come
 * parents-first, root at the origin, z up, metres; order[] holds the branch order.
 * With target_nodes > 0 the segment length (never below 2% of the trunk length) and,
 * when that cannot reach the target, the depth are adjusted. A bad parameter, or a
 * grammar that grows past 200 000 stems or 1 000 000 nodes, fails with GALE_E_RANGE
 * before anything that size is allocated; every message reads "where: generator.KEY:
 * ..." with KEY the species-file key to change (the fields are named as those keys). */
int lsystem_generate(const lsystem_params *p, skeleton *out, gale_err *err);

#endif
