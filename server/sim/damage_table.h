/* A species' storm-damage table (PHYSICS.md "Storm damage"), built once from its asset:
 * the branches (a branch starts where a node forks off anything but its parent's thickest
 * child), each with its base section modulus, the bending moment per unit of each modal
 * coordinate at its base element, and its sub-tree's share of the frontal area and of the
 * leaf slots; the stem with its base moment per mode and the ForestGALES critical moments
 * M_break = (π/32) f_knot MOR d³ and M_over = C_reg · stem mass (Gardiner et al. 2000,
 * 2008; Hale et al. 2012). */
#ifndef GALE_DAMAGE_TABLE_H
#define GALE_DAMAGE_TABLE_H

#include <math.h>
#include <stdint.h>

#include "asset.h"
#include "damage_params.h"
#include "drag_law.h"
#include "err.h"

/* Thinnest branch base that breaks as a branch [m]: the EF scale's "branches 2-8 cm"
 * (Canada EF, trees) is the finest damage class above twigs, and Hugo's crowns shed their
 * twigs with the leaves; thinner twigs stay part of their branch. */
#define DAMAGE_MIN_BRANCH_D_M 0.02f

/* Modes per group of a branch's screening bound: |M_b(q)| <= Σ_g |q_g| ||M_b,g|| (the
 * triangle inequality over groups, ||.|| the spectral norm within one,
 * damage_moment_norm), one product per group and branch instead of three per mode for the
 * exact moment. Two: a tree's modes come in pairs that sway it in crossed planes at
 * nearly one frequency, whose moments at a branch no q of the pair adds in full, so a
 * pair's norm is nearly its larger moment. Wider groups sum unlike modes into one norm
 * and pass more branches for fewer products (server/SERVER.md "Storm damage: bounds by
 * mode pairs"). */
#define DAMAGE_GROUP_MODES 2u

/* Columns after the modes in every moment table: the static residual of the truncated
 * modes (PHYSICS.md "Storm damage"), the moment per unit of κ w, w = s(U) k_t |v| v the
 * tick's force vector (tree frame, [m²/s²]) and κ = w_scale; a check appends κ w to q.
 * κ = |G|, G_ik = p_i,k / ω_i² the static response of q to w, puts κ |w| on the scale of
 * |q| in a steady wind, so that |x| |M| bounds both parts alike. */
#define DAMAGE_RES_COLS 3u

/* Clusters of a species' branches: one vector of screens (DAMAGE_BOUND_LANES lanes). A
 * check screens the clusters first, each by the largest norms over capacity of its
 * branches, and bounds branch by branch only those of a cluster left open
 * (damage_branch_bounds; server/SERVER.md "Storm damage: branches screened by clusters"). */
#define DAMAGE_CLUSTERS 16u

/* Bits of a slot rank that index damage_table.rank_start: 4096 buckets, about one slot
 * each at the shipped species' 1500-5300 slots. */
#define DAMAGE_RANK_BITS 12u

/* Groups of x at most: 64 modes and the residual. */
#define DAMAGE_MAX_GROUPS ((64u + DAMAGE_RES_COLS + DAMAGE_GROUP_MODES - 1u) / DAMAGE_GROUP_MODES)

typedef struct damage_branch {
    uint32_t node;       /* first node of the branch: the end of its base element */
    int32_t up;          /* index of the branch it grows from; -1: from the stem */
    float cap_nm;        /* MOR · S, S = π r³ / 4 at the base node [N m] */
    float moment_norm;   /* damage_moment_norm over the n_cols columns: |M(x)| <= |x| ·
                            moment_norm, x = (q, κ w) */
    float area_share;    /* its sub-tree's share of the tree's ∫ D ds, 0..1 */
    float leaf_share;    /* its sub-tree's share of the leaf slots, 0..1 */
} damage_branch;

typedef struct damage_table {
    damage_params p;
    uint32_t n_modes, n_nodes;
    uint32_t n_cols;         /* n_modes + DAMAGE_RES_COLS: the length of x = (q, κ w) */
    float w_scale;           /* κ (damage_w_scale) */
    uint32_t n_branches;
    damage_branch *branch;   /* owned [n_branches], parents before children */
    float *branch_moment;    /* owned [n_branches][n_cols][3] bending moment at the base
                                element's start per unit q_i (columns < n_modes) and per
                                unit κ w_k (the static residual) [N m], tree frame */
    int32_t *node_branch;    /* owned [n_nodes] branch a node belongs to; -1: the stem */
    uint32_t n_leaves;
    const uint32_t *leaf_node; /* [n_leaves] borrowed from the asset: the node of each slot */
    uint64_t *slot_rank;     /* owned [n_leaves] wire_damage_slot_rank << 32 | slot, sorted */
    uint32_t *rank_start;    /* owned [2^DAMAGE_RANK_BITS + 1] the first index of slot_rank
                                whose rank's top DAMAGE_RANK_BITS bits reach k, and n_leaves */
    uint32_t *order;         /* owned [n_branches] branches by cap_nm / moment_norm, rising:
                                the first that cannot fail at |q| ends a check */
    float *ratio_by_order;   /* owned [n_branches] cap_nm / moment_norm of order[j], rising
                                (+inf for a branch no mode loads) */
    float *cap_by_order;     /* owned [group_stride] cap_nm of order[j] */
    float *group_norm;       /* owned [n_groups][group_stride] ||M_b,g|| (damage_moment_norm)
                                of order[j] at [g][j] (groups of DAMAGE_GROUP_MODES
                                columns of x); the clusters' lanes hold copies */
    float cluster_screen[DAMAGE_MAX_GROUPS][DAMAGE_CLUSTERS]; /* max over cluster k's
                                branches of group_norm[g][j] / their cap_nm at [g][k]
                                (FLT_MAX for a branch without capacity, zero for an empty
                                cluster): a check rules out a whole cluster at once */
    uint32_t cluster_start[DAMAGE_CLUSTERS + 1]; /* cluster k's lanes
                                [cluster_start[k], cluster_start[k + 1]) of the arrays
                                below, a whole number of DAMAGE_BOUND_LANES */
    uint32_t cluster_stride; /* their length: cluster_start[DAMAGE_CLUSTERS] (at least one
                                vector of lanes) */
    uint32_t *cluster_j;     /* owned [cluster_stride] the j (order) of each lane's branch,
                                rising within a cluster; UINT32_MAX in the padding */
    float *cluster_cap;      /* owned [cluster_stride] cap_by_order of the lane's branch;
                                +inf in the padding */
    float *cluster_norm;     /* owned [n_groups][cluster_stride] group_norm of the lane's
                                branch; zero in the padding */
    uint32_t n_groups;       /* ceil(n_cols / DAMAGE_GROUP_MODES) */
    uint32_t group_stride;   /* damage_bound_lanes(n_branches): group_norm's row length and
                                cap_by_order's length, zero and +inf past the branches */
    float stem_group[DAMAGE_MAX_GROUPS];   /* damage_moment_norm of stem_moment over group g */
    float stem_moment[64 + DAMAGE_RES_COLS][3]; /* base moment of the stem element per
                                unit x_c, as branch_moment [N m] */
    float stem_norm;         /* damage_moment_norm of stem_moment */
    double stem_d_m;         /* stem diameter at the base [m] */
    double stem_mass_kg;     /* stem volume (root to top along the thickest children) x density */
    double m_break_nm;       /* (π/32) f_knot MOR d³ */
    double m_over_nm;        /* C_reg · stem mass */
    float q_screen;          /* smallest |x| at which anything can fail at strength 1 */
    float screen_q, screen_w;/* max over branches and stem of |M| over the modes' columns
                                and over the residual's, each over the capacity: nothing
                                fails at strength 1 while |q| screen_q + κ|w| screen_w < 1 */
} damage_table;

/* Builds *t (caller-owned, arrays owned by it: damage_table_fini) for asset a whose wood
 * has Young's modulus E_pa, baked with the drag constant drag_c (C = ½ ρ_air C_D of the
 * wind basis, basis.h [kg/m³]; 0, or an asset without omega or wind_basis: no static
 * residual, the truncated modes alone), with the
 * species' damage constants p. Fails on an asset without linear modes (phi, phi_rot) or
 * with more than 64 modes, or out of memory. */
int damage_table_build(const asset *a, double E_pa, double drag_c, const damage_params *p,
                       damage_table *t, gale_err *err);
/* NULL or an empty table is a no-op. */
void damage_table_fini(damage_table *t);

/* Lanes of a branch bound's vector loop: n rounded up to a whole number of the widest
 * vectors (16 floats), so the loop has no scalar remainder. */
#define DAMAGE_BOUND_LANES 16u

static inline uint32_t damage_bound_lanes(uint32_t n)
{
    return n ? (n + DAMAGE_BOUND_LANES - 1u) / DAMAGE_BOUND_LANES * DAMAGE_BOUND_LANES
             : DAMAGE_BOUND_LANES;
}

/* How many branches of t's order have ratio_by_order[j] <= x (those whose moment can
 * reach their capacity at |x| = x times the strength), searched from hint (any value;
 * the last count of the same tree is the fast one). */
uint32_t damage_branches_within(const damage_table *t, float x, uint32_t hint);

/* The first index of t's sorted slot ranks whose rank is r or more (r in [0, 2^32]; 2^32:
 * n_leaves): from its bucket's start (rank_start), a step or two on, where a binary search
 * over all the slots waits on a dozen dependent loads. */
uint32_t damage_first_rank(const damage_table *t, uint64_t r);

/* A check's screens of x = (q, κ w) (zero past its columns up to n_groups whole groups):
 * |x_g| of each group of DAMAGE_GROUP_MODES columns into xg[n_groups]; the stem's group
 * bound Σ_g xg[g] stem_group[g], summed as a running sum over g, into *stem_bound; and
 * the clusters that may hold a branch failing at strength cap_mult, returned: bit k set
 * where cluster k's screen Σ_g xg[g] cluster_screen[g][k], times 1.0002 (for its
 * rounding), is above cap_mult (0: no branch can fail at strength cap_mult). */
uint32_t damage_screen(const damage_table *t, const float *x, float cap_mult, float *xg,
                       float *stem_bound);

/* Which of the first n_check branches in t's order, of the clusters open (bits of
 * damage_screen), may fail at strength cap_mult: branch order[j] passes where its
 * bound Σ_g xg[g] |M_b,g| >= |M(x)| [N m], times 1.0001 (for the bound's rounding), is
 * above cap_mult · cap_by_order[j]. Writes the j of each that passes, rising, to the
 * front of cand[cluster_stride] (the rest of it is scratch) and returns how many. With
 * every cluster that damage_screen leaves out, these are all the branches of the
 * prefix that pass. */
uint32_t damage_branch_bounds(const damage_table *t, const float *xg, uint32_t open,
                              uint32_t n_check, float cap_mult, uint32_t *cand);

/* The spectral norm of a moment table m[n][3] (the 3 × n matrix of its columns): the
 * least σ with |Σ_c x_c m_c| <= σ |x| for every x, rounded up [N m per unit x]. At most
 * the Frobenius norm sqrt(Σ_c |m_c|²) and down to 1/sqrt(3) of it: the modes of a tree
 * come in pairs that bend a branch in crossed planes, whose moments no x adds in full. */
float damage_moment_norm(const float (*m)[3], uint32_t n);

/* κ of DAMAGE_RES_COLS for asset a: sqrt(Σ_i |p_i|² / ω_i⁴), 1 when that is 0 or the asset
 * has no omega or wind_basis [1/(m/s)²]. */
float damage_w_scale(const asset *a);

/* The bending moment M(x) = Σ_c x_c M_c [N m] of per-column moments m[n][3] (out may be
 * NULL); returns |M|. Inline: a check sums a few columns of it per branch it bounds. */
static inline float damage_moment(const float (*m)[3], const float *x, uint32_t n, float out[3])
{
    float mx = 0.0f, my = 0.0f, mz = 0.0f;
    for (uint32_t i = 0; i < n; i++) {
        mx += x[i] * m[i][0];
        my += x[i] * m[i][1];
        mz += x[i] * m[i][2];
    }
    if (out) {
        out[0] = mx;
        out[1] = my;
        out[2] = mz;
    }
    return sqrtf(mx * mx + my * my + mz * mz);
}

/* Exact quasi-static moment at the start of the element parent(c) -> c under the load
 * the bake's basis applies (crown_load.h with the leaves' share leaf_share, 0 when the
 * asset has no leaves: C wood D w per length, C tip_m2 w at each tip) on the sub-tree from
 * c (that element included), in the sign of the modal moments:
 * M = -C (Σ_e wood D_e L_e (mid_e - r_p) + Σ_tips tip_m2 (r_tip - r_p)) × w (statics of
 * the tree, which is determinate; D_e = 2 r_e, r_e the element's mean radius). */
void damage_static_moment(const asset *a, double drag_c, double leaf_share, uint32_t c,
                          const double w[3], double out[3]);

/* Static response of the reference tree to a steady rigid-drag wind u_ms along the tree
 * frame's azimuth dir_rad: q_i = f_i / ω_i², f_i = u² (d·p_i) (Diener 2008 section 4),
 * then κ w = κ u² d in q[n_modes .. n_modes + DAMAGE_RES_COLS): x for damage_moment. */
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
