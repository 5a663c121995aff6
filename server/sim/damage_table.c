/* The storm-damage table of one species: see damage_table.h. Moments come from the
 * linear modes of the asset: the end moment of an Euler-Bernoulli element from its end
 * displacements and rotations, plus the static residual of the modes left out, from the
 * statics of the tree (PHYSICS.md "Storm damage"). */
#include "damage_table.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "crown_load.h"
#include "modal_static.h"
#include "wire.h"

#define PI 3.14159265358979323846

static void sub3(const float *a, const float *b, double o[3])
{
    for (int k = 0; k < 3; k++) {
        o[k] = (double)a[k] - (double)b[k];
    }
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The bending moment at the start of element p -> c in mode i: for a cubic Hermite beam,
 * M_start = (EI/L) (4 θ_p + 2 θ_c - 6 ψ) in each bending plane, with θ the end rotations
 * about the axes across the element and ψ = e × (u_c - u_p)⊥ / L the chord rotation (the
 * element stiffness of Diener 2008 appendix, row of the start rotation). I is the
 * element's, of its mean radius, as the bake's frame elements have it. */
static void element_moment(const asset *a, double E_pa, uint32_t i, uint32_t p, uint32_t c,
                           float out[3])
{
    const uint32_t n = a->n_nodes;
    double e[3], d[3], tp[3], tc[3];
    sub3(&a->rest[3 * c], &a->rest[3 * p], e);
    double L = sqrt(dot3(e, e));
    if (!(L > 0.0)) {
        out[0] = out[1] = out[2] = 0.0f;
        return;
    }
    for (int k = 0; k < 3; k++) {
        e[k] /= L;
    }
    const float *ph = a->phi + (size_t)i * n * 3, *pr = a->phi_rot + (size_t)i * n * 3;
    sub3(&ph[3 * c], &ph[3 * p], d);
    for (int k = 0; k < 3; k++) {
        tp[k] = pr[3 * p + k];
        tc[k] = pr[3 * c + k];
    }
    double de = dot3(d, e), pe = dot3(tp, e), ce = dot3(tc, e);
    double dp[3], psi[3], m[3];
    for (int k = 0; k < 3; k++) {
        dp[k] = d[k] - de * e[k];
        tp[k] -= pe * e[k];
        tc[k] -= ce * e[k];
    }
    psi[0] = (e[1] * dp[2] - e[2] * dp[1]) / L;
    psi[1] = (e[2] * dp[0] - e[0] * dp[2]) / L;
    psi[2] = (e[0] * dp[1] - e[1] * dp[0]) / L;
    double r = 0.5 * ((double)a->radius[p] + (double)a->radius[c]);
    double EI = E_pa * PI * r * r * r * r / 4.0;
    for (int k = 0; k < 3; k++) {
        m[k] = EI / L * (4.0 * tp[k] + 2.0 * tc[k] - 6.0 * psi[k]);
        out[k] = (float)m[k];
    }
}

uint32_t damage_first_rank(const damage_table *t, uint64_t r)
{
    if (r >= 1ull << 32) {
        return t->n_leaves;
    }
    /* every rank of bucket k lies in [k, k + 1) << (32 - bits): the answer lies between
     * the bucket's start and the next one's */
    const uint32_t k = (uint32_t)(r >> (32u - DAMAGE_RANK_BITS));
    uint32_t i = t->rank_start[k];
    const uint32_t end = t->rank_start[k + 1];
    while (i < end && (t->slot_rank[i] >> 32) < r) {
        i++;
    }
    return i;
}

/* Galloping out from hint: a tree's |x| moves little between two of its checks, so the
 * count is found in a step or two where a bisection of the whole array waits on eight or
 * nine loads in a row. */
uint32_t damage_branches_within(const damage_table *t, float x, uint32_t hint)
{
    const float *r = t->ratio_by_order;
    const uint32_t n = t->n_branches;
    uint32_t lo, hi, step = 1; /* the count lies in [lo, hi] */
    if (hint > n) {
        hint = n;
    }
    if (hint > 0 && !(r[hint - 1] <= x)) {
        hi = hint - 1;
        while (hi >= step && !(r[hi - step] <= x)) {
            hi -= step;
            step *= 2;
        }
        lo = hi >= step ? hi - step + 1 : 0;
    } else {
        lo = hint;
        while (lo + step <= n && r[lo + step - 1] <= x) {
            lo += step;
            step *= 2;
        }
        hi = lo + step - 1 < n ? lo + step - 1 : n;
    }
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo + 1) / 2;
        if (r[mid - 1] <= x) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    return lo;
}

/* Sixteen lanes of bounds, one vector of the widest (GCC vectors: the clones below split
 * it into halves or quarters where the target's vectors are narrower). */
typedef float bound_v __attribute__((vector_size(DAMAGE_BOUND_LANES * sizeof(float))));
/* The same at any float's alignment, for the loads. */
typedef float bound_v_u
    __attribute__((vector_size(DAMAGE_BOUND_LANES * sizeof(float)), aligned(4), may_alias));
typedef int32_t bound_mask __attribute__((vector_size(DAMAGE_BOUND_LANES * sizeof(float))));

/* Through a pointer, not by value: a vector this wide returned from a function would have
 * a different ABI in each clone. */
#define bound_load(p) (*(const bound_v_u *)(const void *)(p))

/* The group norms (lanes over the groups, omp simd: the stride-2 loads become shuffles
 * and the square roots one instruction for 16 groups; each lane adds its group's squares
 * in column order, so the clones round alike; damage_table.c builds with
 * -fno-math-errno: a root of a sum of squares sets no errno), then the stem's bound as a
 * running sum (a scalar chain beside the clusters' vector ones, so neither waits on the
 * other), and the clusters' screens, the first of two levels each a vector of sixteen
 * lanes whose sums stay in a register over the groups (-std=c11: no contraction, so the
 * clones round alike): the clusters against their screens, which rules out most of the
 * branches at the cost of one branch each; then (damage_branch_bounds) the branches of
 * each cluster left, against their own capacities. A cluster's screen is the largest
 * |M_b,g| / cap_b of its branches, so Σ_g x_g screen_g bounds every branch's bound over
 * its capacity; 2e-4 covers the quotient's and the sums' rounding, so a cluster ruled out
 * holds no branch that its own test would pass. A branch's own bound sums its groups in
 * the order the test of one branch would. */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
uint32_t damage_screen(const damage_table *t, const float *x, float cap_mult, float *xg,
                       float *stem_bound)
{
    _Static_assert(DAMAGE_CLUSTERS == DAMAGE_BOUND_LANES, "one vector of cluster screens");
    const uint32_t ng = t->n_groups;
#pragma omp simd
    for (uint32_t g = 0; g < ng; g++) {
        const float *p = x + (size_t)g * DAMAGE_GROUP_MODES;
        float acc = p[0] * p[0];
        for (uint32_t i = 1; i < DAMAGE_GROUP_MODES; i++) {
            acc += p[i] * p[i];
        }
        xg[g] = sqrtf(acc);
    }
    /* the clusters' sums in two chains, the even groups' and the odd ones' (the screen's
     * 2e-4 covers their rounding as it does one chain's) */
    bound_v even = xg[0] * bound_load(t->cluster_screen[0]), odd = { 0 };
    float sb = xg[0] * t->stem_group[0];
    uint32_t g = 1;
    for (; g + 1 < ng; g += 2) {
        odd += xg[g] * bound_load(t->cluster_screen[g]);
        even += xg[g + 1] * bound_load(t->cluster_screen[g + 1]);
        sb += xg[g] * t->stem_group[g];
        sb += xg[g + 1] * t->stem_group[g + 1];
    }
    if (g < ng) {
        odd += xg[g] * bound_load(t->cluster_screen[g]);
        sb += xg[g] * t->stem_group[g];
    }
    *stem_bound = sb;
    const bound_mask open = (even + odd) * 1.0002f > cap_mult;
    uint32_t bits = 0;
    for (uint32_t k = 0; k < DAMAGE_CLUSTERS; k++) {
        bits |= ((uint32_t)open[k] & 1u) << k;
    }
    return bits;
}

__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
uint32_t damage_branch_bounds(const damage_table *t, const float *xg, uint32_t open,
                              uint32_t n_check, float cap_mult, uint32_t *cand)
{
    const uint32_t ng = t->n_groups;
    const size_t stride = t->cluster_stride;
    uint32_t n_cand = 0;
    for (uint32_t k = 0; k < DAMAGE_CLUSTERS; k++) {
        if (!(open >> k & 1u)) {
            continue;
        }
        for (uint32_t i0 = t->cluster_start[k]; i0 < t->cluster_start[k + 1];
             i0 += DAMAGE_BOUND_LANES) {
            bound_v m = xg[0] * bound_load(t->cluster_norm + i0);
            for (uint32_t g = 1; g < ng; g++) {
                m += xg[g] * bound_load(t->cluster_norm + g * stride + i0);
            }
            const bound_v cap = cap_mult * bound_load(t->cluster_cap + i0);
            const bound_mask p = m * 1.0001f > cap;
            /* the lanes that pass and lie in the prefix, appended: each lane written, the
             * count moved by its flag (the count stays below the lanes read, so every
             * write lies within cand[cluster_stride]) */
            for (uint32_t l = 0; l < DAMAGE_BOUND_LANES; l++) {
                const uint32_t j = t->cluster_j[i0 + l];
                cand[n_cand] = j;
                n_cand += (uint32_t)(p[l] & 1) & (j < n_check);
            }
        }
    }
    /* rising j, as one pass over the order would find them: a branch of a cluster after
     * its parent's is then tested after it (insertion: there are few) */
    for (uint32_t a = 1; a < n_cand; a++) {
        const uint32_t j = cand[a];
        uint32_t b = a;
        for (; b > 0 && cand[b - 1] > j; b--) {
            cand[b] = cand[b - 1];
        }
        cand[b] = j;
    }
    return n_cand;
}

float damage_moment_norm(const float (*m)[3], uint32_t n)
{
    /* σ_max² is the largest eigenvalue of the 3×3 Gram matrix G = Σ_c M_c M_cᵀ, in closed
     * form (the trigonometric solution of its characteristic cubic) */
    double g[3][3] = { { 0 } };
    for (uint32_t i = 0; i < n; i++) {
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++) {
                g[r][c] += (double)m[i][r] * (double)m[i][c];
            }
        }
    }
    const double tr = g[0][0] + g[1][1] + g[2][2];
    const double off = g[0][1] * g[0][1] + g[0][2] * g[0][2] + g[1][2] * g[1][2];
    double lmax;
    if (!(tr > 0.0)) {
        return 0.0f;
    }
    if (off == 0.0) {
        lmax = fmax(g[0][0], fmax(g[1][1], g[2][2]));
    } else {
        const double q = tr / 3.0;
        const double a = g[0][0] - q, b = g[1][1] - q, c = g[2][2] - q;
        const double p = sqrt((a * a + b * b + c * c + 2.0 * off) / 6.0);
        /* det((G - q I) / p) / 2, within [-1, 1] but for rounding */
        const double det = a * (b * c - g[1][2] * g[1][2]) -
                           g[0][1] * (g[0][1] * c - g[1][2] * g[0][2]) +
                           g[0][2] * (g[0][1] * g[1][2] - b * g[0][2]);
        double r = det / (2.0 * p * p * p);
        r = r < -1.0 ? -1.0 : r > 1.0 ? 1.0 : r;
        lmax = q + 2.0 * p * cos(acos(r) / 3.0);
    }
    /* the closed form's rounding (acos near ±1 loses digits) is far below 1e-6 of the trace,
     * which keeps the result a bound */
    return (float)(sqrt(lmax + 1e-6 * tr) * (1.0 + 1e-7));
}

/* Raises t's screen_q, screen_w by a moment table m[n_cols] against its capacity. */
static void screen(damage_table *t, const float (*m)[3], float cap_nm)
{
    if (!(cap_nm > 0.0f)) {
        return;
    }
    const float a = damage_moment_norm(m, t->n_modes) / cap_nm;
    const float r = damage_moment_norm(m + t->n_modes, DAMAGE_RES_COLS) / cap_nm;
    t->screen_q = a > t->screen_q ? a : t->screen_q;
    t->screen_w = r > t->screen_w ? r : t->screen_w;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* cap / norm of a branch: the |q| below which it cannot fail at strength 1 */
static double ratio(const damage_branch *b)
{
    return b->moment_norm > 0.0f ? (double)b->cap_nm / (double)b->moment_norm : 1e300;
}

static const damage_table *sort_branches; /* qsort has no context argument */

static int cmp_ratio(const void *a, const void *b)
{
    double x = ratio(&sort_branches->branch[*(const uint32_t *)a]);
    double y = ratio(&sort_branches->branch[*(const uint32_t *)b]);
    return (x > y) - (x < y);
}

void damage_static_moment(const asset *a, double drag_c, double leaf_share, uint32_t c,
                          const double w[3], double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    if (c == 0 || c >= a->n_nodes) {
        return;
    }
    const float *rp = &a->rest[3 * (uint32_t)a->parent[c]];
    const uint32_t n = a->n_nodes;
    /* the load as the bake's basis spreads it (bake.c: the leaves' share at the tips) */
    const crown_load cl = crown_load_split(n, a->parent, a->rest, a->radius,
                                           a->n_leaves ? leaf_share : 0.0);
    /* Σ_e wood D_e L_e (mid_e - r_p) + Σ_tips tip_m2 (r_tip - r_p) over the elements whose
     * end node lies in the sub-tree of c: parent[i] < i, so a node is in it when its
     * parent is (or it is c) */
    uint8_t *in = calloc(n, 1), *tip = malloc(n);
    if (!in || !tip) {
        free(in);
        free(tip);
        return;
    }
    crown_load_tips(n, a->parent, tip);
    double arm[3] = { 0, 0, 0 };
    in[c] = 1;
    for (uint32_t i = c; i < n; i++) {
        if (i > c && !in[a->parent[i]]) {
            continue;
        }
        in[i] = 1;
        const uint32_t q = (uint32_t)a->parent[i];
        double e[3];
        sub3(&a->rest[3 * i], &a->rest[3 * q], e);
        const double dl = cl.wood * ((double)a->radius[i] + (double)a->radius[q]) *
                          sqrt(dot3(e, e));
        const double pt = tip[i] ? cl.tip_m2 : 0.0;
        for (int k = 0; k < 3; k++) {
            arm[k] += dl * (0.5 * ((double)a->rest[3 * i + k] + (double)a->rest[3 * q + k]) -
                            (double)rp[k]) +
                      pt * ((double)a->rest[3 * i + k] - (double)rp[k]);
        }
    }
    free(in);
    free(tip);
    /* the modal moments' sign: element_moment gives minus the load's moment about r_p */
    out[0] = -drag_c * (arm[1] * w[2] - arm[2] * w[1]);
    out[1] = -drag_c * (arm[2] * w[0] - arm[0] * w[2]);
    out[2] = -drag_c * (arm[0] * w[1] - arm[1] * w[0]);
}

float damage_w_scale(const asset *a)
{
    double s = 0.0;
    for (uint32_t i = 0; a->omega && a->wind_basis && i < a->n_modes; i++) {
        for (int k = 0; k < 3; k++) {
            const double g = modal_static_gain(a->omega, a->wind_basis, i, k);
            s += g * g;
        }
    }
    return s > 0.0 ? (float)sqrt(s) : 1.0f;
}

/* The static residual of element parent(c) -> c into m[n_modes .. n_cols): column k the
 * exact static moment of a unit w_k less the modes' static share Σ_i M_i p_i,k / ω_i²
 * (mode-acceleration correction; the modes' static response is q_i = w·p_i / ω_i²), per
 * unit κ w_k. */
static void residual(const asset *a, double drag_c, double leaf_share, uint32_t c,
                     float (*m)[3])
{
    const uint32_t nm = a->n_modes;
    const double kappa = (double)damage_w_scale(a);
    for (uint32_t k = 0; k < DAMAGE_RES_COLS; k++) {
        double w[3] = { 0, 0, 0 }, ex[3];
        w[k] = 1.0;
        if (!(drag_c > 0.0) || !a->omega || !a->wind_basis) {
            m[nm + k][0] = m[nm + k][1] = m[nm + k][2] = 0.0f;
            continue;
        }
        damage_static_moment(a, drag_c, leaf_share, c, w, ex);
        for (uint32_t i = 0; i < nm; i++) {
            const double f = modal_static_gain(a->omega, a->wind_basis, i, (int)k);
            for (int j = 0; j < 3; j++) {
                ex[j] -= (double)m[i][j] * f;
            }
        }
        for (int j = 0; j < 3; j++) {
            m[nm + k][j] = (float)(ex[j] / kappa);
        }
    }
}

/* Branch j's group norms over its capacity (0 for a branch without capacity: it only
 * places the branch; its screen is FLT_MAX, as in damage_branch_bounds). */
static float per_capacity(const damage_table *t, uint32_t g, uint32_t j)
{
    const float cap = t->cap_by_order[j], gn = t->group_norm[(size_t)g * t->group_stride + j];
    return cap > 0.0f ? gn / cap : 0.0f;
}

/* L1 distance of branch j's norms over capacity from a centre [n_groups]. */
static double cluster_distance(const damage_table *t, uint32_t j, const double *centre)
{
    double d = 0.0;
    for (uint32_t g = 0; g < t->n_groups; g++) {
        d += fabs((double)per_capacity(t, g, j) - centre[g]);
    }
    return d;
}

/* The branches in DAMAGE_CLUSTERS clusters of like norms over capacity (Lloyd's rounds:
 * each branch to the centre nearest in the L1 distance, each centre its branches' mean;
 * from centres at evenly spaced branches of the order, until no branch moves or for 64
 * rounds: the same clusters on every machine), each cluster's screen the largest
 * norm over capacity of its branches per group, and its branches in lanes of their own.
 * A branch's bound is large against its capacity in a few groups (those of the modes that
 * bend it, and the residual); branches alike in which share a cluster, so a cluster's
 * screen is near each of its branches' bounds, where the largest over all branches, per
 * group, sums the worst of unlike branches. */
static int build_clusters(damage_table *t)
{
    const uint32_t nb = t->n_branches, ng = t->n_groups;
    uint8_t *of = calloc(nb ? nb : 1, 1);
    double(*centre)[DAMAGE_MAX_GROUPS] = calloc(DAMAGE_CLUSTERS, sizeof *centre);
    if (!of || !centre) {
        free(of);
        free(centre);
        return GALE_E_NOMEM;
    }
    for (uint32_t k = 0; k < DAMAGE_CLUSTERS && nb > 0; k++) {
        const uint32_t j = (uint32_t)((uint64_t)k * nb / DAMAGE_CLUSTERS);
        for (uint32_t g = 0; g < ng; g++) {
            centre[k][g] = (double)per_capacity(t, g, j);
        }
    }
    for (int round = 0; round < 64; round++) {
        bool moved = round == 0;
        for (uint32_t j = 0; j < nb; j++) {
            uint32_t best = 0;
            double best_d = cluster_distance(t, j, centre[0]);
            for (uint32_t k = 1; k < DAMAGE_CLUSTERS; k++) {
                const double d = cluster_distance(t, j, centre[k]);
                if (d < best_d) {
                    best_d = d;
                    best = k;
                }
            }
            moved = moved || of[j] != best;
            of[j] = (uint8_t)best;
        }
        if (!moved) {
            break;
        }
        uint32_t count[DAMAGE_CLUSTERS] = { 0 };
        double sum[DAMAGE_CLUSTERS][DAMAGE_MAX_GROUPS] = { { 0 } };
        for (uint32_t j = 0; j < nb; j++) {
            count[of[j]]++;
            for (uint32_t g = 0; g < ng; g++) {
                sum[of[j]][g] += (double)per_capacity(t, g, j);
            }
        }
        for (uint32_t k = 0; k < DAMAGE_CLUSTERS; k++) {
            for (uint32_t g = 0; g < ng && count[k] > 0; g++) {
                centre[k][g] = sum[k][g] / (double)count[k];
            }
        }
    }
    free(centre);
    /* each cluster's branches in rising j, padded to whole vectors of lanes */
    uint32_t at = 0;
    for (uint32_t k = 0; k < DAMAGE_CLUSTERS; k++) {
        t->cluster_start[k] = at;
        uint32_t n = 0;
        for (uint32_t j = 0; j < nb; j++) {
            n += of[j] == k;
        }
        at += n ? damage_bound_lanes(n) : 0;
    }
    t->cluster_start[DAMAGE_CLUSTERS] = at;
    t->cluster_stride = at ? at : DAMAGE_BOUND_LANES;
    t->cluster_j = malloc(sizeof(uint32_t) * t->cluster_stride);
    t->cluster_cap = malloc(sizeof(float) * t->cluster_stride);
    t->cluster_norm = calloc((size_t)ng * t->cluster_stride, sizeof(float));
    if (!t->cluster_j || !t->cluster_cap || !t->cluster_norm) {
        free(of);
        return GALE_E_NOMEM;
    }
    for (uint32_t i = 0; i < t->cluster_stride; i++) {
        t->cluster_j[i] = UINT32_MAX; /* padding: past any prefix, no capacity reached */
        t->cluster_cap[i] = INFINITY;
    }
    memset(t->cluster_screen, 0, sizeof t->cluster_screen);
    uint32_t fill[DAMAGE_CLUSTERS];
    memcpy(fill, t->cluster_start, sizeof fill);
    for (uint32_t j = 0; j < nb; j++) {
        const uint32_t k = of[j], i = fill[k]++;
        t->cluster_j[i] = j;
        t->cluster_cap[i] = t->cap_by_order[j];
        for (uint32_t g = 0; g < ng; g++) {
            const float gn = t->group_norm[(size_t)g * t->group_stride + j];
            t->cluster_norm[(size_t)g * t->cluster_stride + i] = gn;
            /* a branch without capacity keeps its cluster open wherever its moment is not
             * zero: the largest float, not +inf, whose product with an |x_g| of 0 would be
             * NaN and close the cluster */
            const float cap = t->cap_by_order[j];
            const float per_cap = cap > 0.0f ? gn / cap : gn > 0.0f ? FLT_MAX : 0.0f;
            float *cs = &t->cluster_screen[g][k];
            *cs = per_cap > *cs ? per_cap : *cs;
        }
    }
    free(of);
    return 0;
}

int damage_table_build(const asset *a, double E_pa, double drag_c, const damage_params *p,
                       damage_table *t, gale_err *err)
{
    memset(t, 0, sizeof *t);
    const uint32_t n = a->n_nodes, nm = a->n_modes;
    if (!a->phi || !a->phi_rot || n < 2 || nm == 0 || nm > 64 || a->parent[0] != -1) {
        return gale_errf(err, GALE_E_ARG,
                         "damage_table_build: %s: expected a rooted asset with linear modes "
                         "(1..64), got %u nodes, %u modes",
                         a->species, n, nm);
    }
    t->p = *p;
    t->n_modes = nm;
    t->n_cols = nm + DAMAGE_RES_COLS;
    t->w_scale = damage_w_scale(a);
    t->n_nodes = n;
    t->n_leaves = a->n_leaves;
    t->leaf_node = a->leaf_node;
    /* children: the thickest child of a node continues its branch, any other starts one */
    int32_t *main_child = malloc(sizeof(int32_t) * n);
    int32_t *nkids = calloc(n, sizeof(int32_t));
    double *area = calloc(n, sizeof(double));   /* ∫ D ds of the sub-tree from node i */
    double *leaves = calloc(n, sizeof(double)); /* leaf slots in it */
    t->node_branch = malloc(sizeof(int32_t) * n);
    t->branch = malloc(sizeof(damage_branch) * n);
    if (!main_child || !nkids || !area || !leaves || !t->node_branch || !t->branch) {
        free(main_child);
        free(nkids);
        free(area);
        free(leaves);
        damage_table_fini(t);
        return gale_errf(err, GALE_E_NOMEM, "damage_table_build: no memory for %u nodes", n);
    }
    for (uint32_t i = 0; i < n; i++) {
        main_child[i] = -1;
    }
    for (uint32_t i = 1; i < n; i++) {
        uint32_t q = (uint32_t)a->parent[i];
        nkids[q]++;
        if (main_child[q] < 0 || a->radius[i] > a->radius[main_child[q]]) {
            main_child[q] = (int32_t)i;
        }
        double e[3];
        sub3(&a->rest[3 * i], &a->rest[3 * q], e);
        area[i] = (double)(a->radius[i] + a->radius[q]) * sqrt(dot3(e, e));
    }
    for (uint32_t l = 0; l < a->n_leaves; l++) {
        if (a->leaf_node[l] < n) {
            leaves[a->leaf_node[l]] += 1.0;
        }
    }
    /* sub-tree sums: children come after their parent (parent[i] < i) */
    for (uint32_t i = n - 1; i >= 1; i--) {
        area[a->parent[i]] += area[i];
        leaves[a->parent[i]] += leaves[i];
    }
    const double area_all = area[0] > 0.0 ? area[0] : 1.0;
    const double leaves_all = leaves[0] > 0.0 ? leaves[0] : 1.0;
    /* branches in node order, so a branch's parent branch comes first */
    t->node_branch[0] = -1;
    uint32_t nb = 0;
    for (uint32_t i = 1; i < n; i++) {
        uint32_t q = (uint32_t)a->parent[i];
        int32_t up = t->node_branch[q];
        /* twigs thinner than DAMAGE_MIN_BRANCH_D_M go with the leaves (stripping) */
        if (main_child[q] == (int32_t)i || 2.0f * a->radius[i] < DAMAGE_MIN_BRANCH_D_M) {
            t->node_branch[i] = up;
            continue;
        }
        damage_branch *b = &t->branch[nb];
        double r = a->radius[i];
        b->node = i;
        b->up = up;
        b->cap_nm = (float)(p->mor_pa * PI * r * r * r / 4.0);
        b->area_share = (float)(area[i] / area_all);
        b->leaf_share = (float)(leaves[i] / leaves_all);
        t->node_branch[i] = (int32_t)nb;
        nb++;
    }
    t->n_branches = nb;
    free(nkids);
    free(area);
    free(leaves);
    const uint32_t nc = t->n_cols;
    t->branch_moment = malloc(sizeof(float) * 3 * nc * (nb ? nb : 1));
    if (!t->branch_moment) {
        free(main_child);
        damage_table_fini(t);
        return gale_errf(err, GALE_E_NOMEM, "damage_table_build: no memory for %u branches", nb);
    }
    float qs = INFINITY;
    for (uint32_t b = 0; b < nb; b++) {
        uint32_t c = t->branch[b].node, q = (uint32_t)a->parent[c];
        float(*m)[3] = (float(*)[3])(t->branch_moment + (size_t)b * nc * 3);
        for (uint32_t i = 0; i < nm; i++) {
            element_moment(a, E_pa, i, q, c, m[i]);
        }
        residual(a, drag_c, p->leaf_drag_share, c, m);
        t->branch[b].moment_norm = damage_moment_norm((const float(*)[3])m, nc);
        if (t->branch[b].moment_norm > 0.0f) {
            float s = t->branch[b].cap_nm / t->branch[b].moment_norm;
            qs = s < qs ? s : qs;
        }
        screen(t, (const float(*)[3])m, t->branch[b].cap_nm);
    }
    /* the stem: root to top along the thickest children */
    const uint32_t s1 = (uint32_t)main_child[0];
    double mass = 0.0;
    for (int32_t i = main_child[0]; i >= 0; i = main_child[i]) {
        uint32_t q = (uint32_t)a->parent[i];
        double e[3], r = 0.5 * ((double)a->radius[i] + (double)a->radius[q]);
        sub3(&a->rest[3 * i], &a->rest[3 * q], e);
        mass += PI * r * r * sqrt(dot3(e, e));
    }
    free(main_child);
    for (uint32_t i = 0; i < nm; i++) {
        element_moment(a, E_pa, i, 0, s1, t->stem_moment[i]);
    }
    residual(a, drag_c, p->leaf_drag_share, s1, t->stem_moment);
    t->stem_norm = damage_moment_norm((const float(*)[3])t->stem_moment, nc);
    t->stem_d_m = 2.0 * (double)a->radius[0];
    t->stem_mass_kg = mass * p->stem_density_kg_m3;
    /* Gardiner et al. 2000 / Hale et al. 2012 (ForestGALES) */
    t->m_break_nm = PI / 32.0 * p->f_knot * p->mor_pa * t->stem_d_m * t->stem_d_m * t->stem_d_m;
    t->m_over_nm = p->c_reg_nm_kg * t->stem_mass_kg;
    if (t->stem_norm > 0.0f) {
        double m = t->m_break_nm < t->m_over_nm ? t->m_break_nm : t->m_over_nm;
        float s = (float)(m / (double)t->stem_norm);
        qs = s < qs ? s : qs;
        screen(t, (const float(*)[3])t->stem_moment, (float)m);
    }
    t->q_screen = qs;
    t->order = malloc(sizeof(uint32_t) * (nb ? nb : 1));
    t->slot_rank = malloc(sizeof(uint64_t) * (a->n_leaves ? a->n_leaves : 1));
    t->rank_start = malloc(sizeof(uint32_t) * ((1u << DAMAGE_RANK_BITS) + 1u));
    if (!t->order || !t->slot_rank || !t->rank_start) {
        damage_table_fini(t);
        return gale_errf(err, GALE_E_NOMEM, "damage_table_build: no memory for %u leaves",
                         a->n_leaves);
    }
    for (uint32_t k = 0; k < a->n_leaves; k++) {
        t->slot_rank[k] = (uint64_t)wire_damage_slot_rank(k) << 32 | k;
    }
    qsort(t->slot_rank, a->n_leaves, sizeof(uint64_t), cmp_u64);
    for (uint32_t k = 0, i = 0; k <= 1u << DAMAGE_RANK_BITS; k++) {
        while (i < a->n_leaves && (t->slot_rank[i] >> (64u - DAMAGE_RANK_BITS)) < k) {
            i++;
        }
        t->rank_start[k] = i;
    }
    for (uint32_t b = 0; b < nb; b++) {
        t->order[b] = b;
    }
    sort_branches = t;
    qsort(t->order, nb, sizeof(uint32_t), cmp_ratio);
    sort_branches = NULL;
    t->n_groups = (nc + DAMAGE_GROUP_MODES - 1) / DAMAGE_GROUP_MODES;
    for (uint32_t g = 0; g < t->n_groups; g++) {
        const uint32_t i0 = g * DAMAGE_GROUP_MODES;
        const uint32_t k = nc - i0 < DAMAGE_GROUP_MODES ? nc - i0 : DAMAGE_GROUP_MODES;
        t->stem_group[g] = damage_moment_norm((const float(*)[3])t->stem_moment + i0, k);
    }
    t->group_stride = damage_bound_lanes(nb);
    t->ratio_by_order = malloc(sizeof(float) * (nb ? nb : 1));
    t->cap_by_order = malloc(sizeof(float) * t->group_stride);
    t->group_norm = calloc((size_t)t->n_groups * t->group_stride, sizeof(float));
    if (!t->ratio_by_order || !t->cap_by_order || !t->group_norm) {
        damage_table_fini(t);
        return gale_errf(err, GALE_E_NOMEM, "damage_table_build: no memory for %u branches", nb);
    }
    for (uint32_t j = nb; j < t->group_stride; j++) {
        t->cap_by_order[j] = INFINITY; /* the lanes past the last branch: no capacity reached */
    }
    for (uint32_t j = 0; j < nb; j++) {
        const damage_branch *b = &t->branch[t->order[j]];
        t->ratio_by_order[j] = b->moment_norm > 0.0f ? b->cap_nm / b->moment_norm : INFINITY;
        t->cap_by_order[j] = b->cap_nm;
        const float(*m)[3] = (const float(*)[3])(t->branch_moment + (size_t)t->order[j] * nc * 3);
        for (uint32_t g = 0; g < t->n_groups; g++) {
            const uint32_t i0 = g * DAMAGE_GROUP_MODES;
            const uint32_t k = nc - i0 < DAMAGE_GROUP_MODES ? nc - i0 : DAMAGE_GROUP_MODES;
            t->group_norm[(size_t)g * t->group_stride + j] = damage_moment_norm(m + i0, k);
        }
    }
    if (build_clusters(t)) {
        damage_table_fini(t);
        return gale_errf(err, GALE_E_NOMEM, "damage_table_build: no memory for %u branches", nb);
    }
    return GALE_OK;
}

void damage_table_fini(damage_table *t)
{
    if (!t) {
        return;
    }
    free(t->branch);
    free(t->branch_moment);
    free(t->node_branch);
    free(t->order);
    free(t->ratio_by_order);
    free(t->cap_by_order);
    free(t->group_norm);
    free(t->cluster_j);
    free(t->cluster_cap);
    free(t->cluster_norm);
    free(t->slot_rank);
    free(t->rank_start);
    memset(t, 0, sizeof *t);
}

void damage_static_q(const asset *a, double u_ms, double dir_rad, float *q)
{
    const double vx = u_ms * cos(dir_rad), vy = u_ms * sin(dir_rad);
    for (uint32_t i = 0; i < a->n_modes; i++) {
        q[i] = (float)(u_ms * (vx * modal_static_gain(a->omega, a->wind_basis, i, 0) +
                               vy * modal_static_gain(a->omega, a->wind_basis, i, 1)));
    }
    const double kappa = (double)damage_w_scale(a);
    q[a->n_modes] = (float)(kappa * u_ms * vx);
    q[a->n_modes + 1] = (float)(kappa * u_ms * vy);
    q[a->n_modes + 2] = 0.0f;
}

double damage_speed_for(const drag_law *d, double ratio)
{
    if (!(ratio > 0.0) || !isfinite(ratio)) {
        return (double)INFINITY;
    }
    const double rigid = sqrt(ratio);
    if (!d || drag_law_scale(d, (float)rigid) == 1.0f) {
        return rigid; /* below U_0 the crown is rigid; streamlining only raises u */
    }
    /* u² s(u) grows monotonically (2 + B > 0), so bisect between the rigid answer and a
     * bound that doubles until it holds */
    double lo = rigid, hi = 2.0 * rigid;
    while (hi * hi * (double)drag_law_scale(d, (float)hi) < ratio && hi < 1e9) {
        lo = hi;
        hi *= 2.0;
    }
    for (int it = 0; it < 100 && hi - lo > 1e-9 * hi; it++) {
        const double mid = 0.5 * (lo + hi);
        if (mid * mid * (double)drag_law_scale(d, (float)mid) < ratio) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

void damage_critical_speeds(const asset *a, const damage_table *t, const drag_law *d,
                            double *snap_ms, double *uproot_ms, double *branch_ms)
{
    float q[64 + DAMAGE_RES_COLS];
    double worst = 0.0, bmin = INFINITY;
    for (int k = 0; k < 16; k++) {
        damage_static_q(a, 1.0, 2.0 * PI * k / 16.0, q);
        double m = (double)damage_moment((const float(*)[3])t->stem_moment, q, t->n_cols, NULL);
        worst = m > worst ? m : worst;
        for (uint32_t b = 0; b < t->n_branches; b++) {
            const float(*mm)[3] = (const float(*)[3])(t->branch_moment + (size_t)b * t->n_cols * 3);
            double mb = (double)damage_moment(mm, q, t->n_cols, NULL);
            double u = mb > 0.0 ? damage_speed_for(d, (double)t->branch[b].cap_nm / mb)
                                : (double)INFINITY;
            bmin = u < bmin ? u : bmin;
        }
    }
    *snap_ms = worst > 0.0 ? damage_speed_for(d, t->m_break_nm / worst) : (double)INFINITY;
    *uproot_ms = worst > 0.0 ? damage_speed_for(d, t->m_over_nm / worst) : (double)INFINITY;
    if (branch_ms) {
        *branch_ms = bmin;
    }
}
