/* A species' storm-damage table (PHYSICS.md "Storm damage"), built once from its asset:
 * the branches (a branch starts where a node forks off anything but its parent's thickest
 * child), each with its base section modulus, the bending moment per unit of each modal
 * coordinate at its base element, and its sub-tree's share of the frontal area and of the
 * leaf slots; the stem with its base moment per mode and the ForestGALES critical moments
 * M_break = (π/32) f_knot MOR d³ and M_over = C_reg · stem mass (Gardiner et al. 2000,
 * 2008; Hale et al. 2012). */
#ifndef GALE_DAMAGE_TABLE_H
#define GALE_DAMAGE_TABLE_H

#include <stdint.h>

#include "asset.h"
#include "damage_params.h"
#include "drag_law.h"
#include "err.h"

/* Thinnest branch base that breaks as a branch [m]: the EF scale's "branches 2-8 cm"
 * (Canada EF, trees) is the finest damage class above twigs, and Hugo's crowns shed their
 * twigs with the leaves; thinner twigs stay part of their branch. */
#define DAMAGE_MIN_BRANCH_D_M 0.02f

/* Modes per group of a branch's screening bound: |M_b(q)| <= Σ_g |q_g| |M_b,g| (the
 * triangle inequality over groups, Cauchy-Schwarz within one), one product per group
 * and branch instead of three per mode for the exact moment. */
#define DAMAGE_GROUP_MODES 4u

typedef struct damage_branch {
    uint32_t node;       /* first node of the branch: the end of its base element */
    int32_t up;          /* index of the branch it grows from; -1: from the stem */
    float cap_nm;        /* MOR · S, S = π r³ / 4 at the base node [N m] */
    float moment_norm;   /* sqrt(Σ_i |M_i|²): |M(q)| <= |q| · moment_norm */
    float area_share;    /* its sub-tree's share of the tree's ∫ D ds, 0..1 */
    float leaf_share;    /* its sub-tree's share of the leaf slots, 0..1 */
} damage_branch;

typedef struct damage_table {
    damage_params p;
    uint32_t n_modes, n_nodes;
    uint32_t n_branches;
    damage_branch *branch;   /* owned [n_branches], parents before children */
    float *branch_moment;    /* owned [n_branches][n_modes][3] bending moment per unit q at
                                the base element's start [N m], tree frame */
    int32_t *node_branch;    /* owned [n_nodes] branch a node belongs to; -1: the stem */
    uint32_t n_leaves;
    const uint32_t *leaf_node; /* [n_leaves] borrowed from the asset: the node of each slot */
    uint64_t *slot_rank;     /* owned [n_leaves] wire_damage_slot_rank << 32 | slot, sorted */
    uint32_t *order;         /* owned [n_branches] branches by cap_nm / moment_norm, rising:
                                the first that cannot fail at |q| ends a check */
    float *ratio_by_order;   /* owned [n_branches] cap_nm / moment_norm of order[j], rising
                                (+inf for a branch no mode loads) */
    float *cap_by_order;     /* owned [n_branches] cap_nm of order[j] */
    float *group_norm;       /* owned [n_groups][n_branches] |M_b,g| of order[j] at [g][j]:
                                a check bounds the branches it needs, a prefix of the order,
                                group by group in vector lanes */
    uint32_t n_groups;       /* ceil(n_modes / DAMAGE_GROUP_MODES) */
    float stem_moment[64][3];/* base moment of the stem element per unit q_i [N m] */
    float stem_norm;         /* sqrt(Σ_i |stem_moment_i|²) */
    double stem_d_m;         /* stem diameter at the base [m] */
    double stem_mass_kg;     /* stem volume (root to top along the thickest children) x density */
    double m_break_nm;       /* (π/32) f_knot MOR d³ */
    double m_over_nm;        /* C_reg · stem mass */
    float q_screen;          /* smallest |q| at which anything can fail at strength 1 */
} damage_table;

/* Builds *t (caller-owned, arrays owned by it: damage_table_fini) for asset a whose wood
 * has Young's modulus E_pa, with the species' damage constants p. Fails on an asset
 * without linear modes (phi, phi_rot) or with more than 64 modes, or out of memory. */
int damage_table_build(const asset *a, double E_pa, const damage_params *p, damage_table *t,
                       gale_err *err);
/* NULL or an empty table is a no-op. */
void damage_table_fini(damage_table *t);

/* Upper bounds of the bending moments of the first n_check branches in t's order at modal
 * state q[n]: out[j] >= |M(q)| of branch order[j] [N m] (DAMAGE_GROUP_MODES). */
void damage_branch_bounds(const damage_table *t, const float *q, uint32_t n, uint32_t n_check,
                          float *out);

/* The bending moment M(q) = Σ_i q_i M_i [N m] of per-mode moments m[n][3]; returns |M|. */
float damage_moment(const float (*m)[3], const float *q, uint32_t n, float out[3]);

/* Static response of the reference tree to a steady wind u_ms along the tree frame's
 * azimuth dir_rad: q_i = f_i / ω_i², f_i = u² (d·p_i) (Diener 2008 section 4). */
void damage_static_q(const asset *a, double u_ms, double dir_rad, float *q);

/* Steady crown wind [m/s] at which the reference tree (strength 1) snaps, at which it
 * uproots and at which its first branch breaks (branch_ms may be NULL), the weakest
 * azimuth of 16. Static moments grow as u² s(u), s the streamlining of drag_law.h (d NULL
 * or rigid: s = 1), so u solves u² s(u) = M_crit / M(1 m/s) (damage_speed_for). */
void damage_critical_speeds(const asset *a, const damage_table *t, const drag_law *d,
                            double *snap_ms, double *uproot_ms, double *branch_ms);

/* The speed u with u² s(u) = ratio under drag law d (NULL: rigid, u = sqrt(ratio));
 * INFINITY for a ratio that is not finite and positive. */
double damage_speed_for(const drag_law *d, double ratio);

#endif
