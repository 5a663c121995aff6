/* Storm damage of every tree: see damage.h. PHYSICS.md "Storm damage" has the model. */
#include "damage.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "big_alloc.h"
#include "damage_strip.h"
#include "hash.h"
#include "sim_team.h"

#define DAMAGE_LOG_MAX 65536u /* broken branches remembered for the whole-state frame */
#define DAMAGE_PREFETCH_TREES 8u /* trees ahead whose state lane_run asks the cache for */

typedef struct damage_tree_st {
    float strength;     /* seeded multiplier of every capacity of the tree */
    float weakest;      /* strength of its weakest branch at most: strength exp(-sd) */
    float leaf;         /* leaf area left on the crown, 0..1 */
    float area_frac;    /* ∫ D ds left after broken branches, 0..1 */
    float leaf_frac;    /* leaf slots left after broken branches, 0..1 */
    uint8_t level;      /* leaf level streamed, 0..WIRE_DAMAGE_LEVELS */
    uint8_t fallen;     /* 0, WIRE_DAMAGE_SNAP or WIRE_DAMAGE_UPROOT */
    uint8_t fall_az;    /* fall azimuth, 1/256 turns */
    uint32_t fall_tick, level_tick;
    uint32_t broken;    /* branches broken */
    uint32_t n_check;   /* branches the last check bounded: where the next one's search
                           starts */
} damage_tree_st;

/* One lane of a damage step (a contiguous share of the trees due): its scratch, and for
 * every lane after the first the events and stripped leaves of its trees, merged after
 * the first lane's in tree order (the first lane writes straight to the step's outputs). */
typedef struct damage_lane {
    float *q;                   /* owned [DAMAGE_MAX_GROUPS + 1][DAMAGE_GROUP_MODES] scratch: x */
    uint32_t *cand;             /* owned [the most cluster_stride] scratch: branches a bound
                                   passes */
    wire_damage *ev;            /* owned [cap_ev] its events this step, in tree order */
    int n_ev, cap_ev;
    leaf_seed *leaves;          /* owned [cap_leaves] its stripped leaves this step */
    int n_leaves, cap_leaves;
    int lost;                   /* its leaves over the caps this step */
} damage_lane;

struct damage_sim {
    damage_desc d;
    const damage_table **table; /* owned array of borrowed tables [n_species] */
    uint8_t *species;           /* owned [n_trees] */
    float *cos_yaw, *sin_yaw;   /* owned [n_trees] */
    damage_tree_st *tree;       /* owned [n_trees] */
    uint64_t *bits;             /* owned [n_trees][words] broken branches */
    uint32_t words;
    damage_lane *lane;          /* owned [n_lanes] */
    int n_lanes;
    int n_threads;
    wire_damage *ev;            /* owned [max_events] this tick's events */
    int n_ev;
    wire_damage *log;           /* owned [DAMAGE_LOG_MAX] broken branches, in order */
    uint32_t n_log;
    damage_counts counts;
    modal_rows rows;            /* the modal state's rows this step (damage_step) */
    float strip_decay;          /* damage_strip_decay of a tree's DAMAGE_EVERY ticks */
};

/* Uniform in [0, 1) from (seed, a, b). */
static double unit3(uint64_t seed, uint64_t a, uint64_t b)
{
    uint64_t s = seed ^ (a * 0x9E3779B97F4A7C15ull) ^ (b * 0xD1B54A32D192ED03ull);
    return (double)(hash64_splitmix(&s) >> 11) * (1.0 / 9007199254740992.0);
}

/* A standard normal deviate from (seed, a, b) (Box-Muller), clamped to ±2 so a
 * strength never strays beyond exp(±2 sd). */
static double normal3(uint64_t seed, uint64_t a, uint64_t b)
{
    double u1 = unit3(seed, a, 2 * b + 1), u2 = unit3(seed, a, 2 * b + 2);
    double z = sqrt(-2.0 * log(1.0 - u1)) * cos(6.283185307179586 * u2);
    return z < -2.0 ? -2.0 : z > 2.0 ? 2.0 : z;
}

/* Tree t as it stood before any damage, with the strength and weakest branch given. */
static void tree_reset(damage_sim *s, uint32_t t, float strength, float weakest)
{
    s->tree[t] = (damage_tree_st){ .strength = strength,
                                   .weakest = weakest,
                                   .leaf = 1.0f,
                                   .area_frac = 1.0f,
                                   .leaf_frac = 1.0f,
                                   .level = WIRE_DAMAGE_LEVELS };
    memset(s->bits + (size_t)t * s->words, 0, sizeof(uint64_t) * s->words);
}

static void tree_intact(damage_sim *s, uint32_t t)
{
    const damage_table *tb = s->table[s->species[t]];
    double sd = tb ? tb->p.strength_sd : 0.0;
    /* log-normal strength per tree (seeded): a stand fails progressively */
    const float strength = (float)exp(sd * normal3(s->d.seed, t, 0));
    tree_reset(s, t, strength, strength * expf(-(float)sd));
}

damage_sim *damage_create(const damage_desc *d, gale_err *err)
{
    if (d->n_trees == 0 || d->n_trees > WIRE_MAX_TREES || d->n_species == 0 ||
        d->n_species > WIRE_MAX_SPECIES || !d->table || !d->tree_species) {
        gale_errf(err, GALE_E_ARG, "damage_create: expected 1..%u trees of 1..%u species, got %u, %u",
                  WIRE_MAX_TREES, WIRE_MAX_SPECIES, d->n_trees, d->n_species);
        return NULL;
    }
    damage_sim *s = calloc(1, sizeof *s);
    if (!s) {
        goto nomem;
    }
    s->d = *d;
    s->strip_decay = damage_strip_decay((float)(d->dt_s * DAMAGE_EVERY));
    if (s->d.max_events <= 0) {
        s->d.max_events = (int)WIRE_MAX_DAMAGE;
    }
    uint32_t maxb = 1, maxb_lanes = DAMAGE_BOUND_LANES;
    s->table = calloc(d->n_species, sizeof *s->table);
    if (!s->table) {
        goto nomem;
    }
    for (uint32_t k = 0; k < d->n_species; k++) {
        s->table[k] = d->table[k];
        if (s->table[k] && s->table[k]->n_branches > maxb) {
            maxb = s->table[k]->n_branches;
        }
        if (s->table[k] && s->table[k]->cluster_stride > maxb_lanes) {
            maxb_lanes = s->table[k]->cluster_stride;
        }
    }
    s->words = (maxb + 63) / 64;
    s->species = malloc(d->n_trees);
    s->cos_yaw = malloc(sizeof(float) * d->n_trees);
    s->sin_yaw = malloc(sizeof(float) * d->n_trees);
    s->tree = big_alloc((size_t)d->n_trees * sizeof *s->tree);
    s->bits = calloc((size_t)d->n_trees * s->words, sizeof(uint64_t));
    s->n_threads = d->n_threads > 1 ? (d->n_threads < DAMAGE_MAX_THREADS ? d->n_threads
                                                                          : DAMAGE_MAX_THREADS)
                                    : 1;
    s->n_lanes = s->n_threads > 1 ? s->n_threads * DAMAGE_LANES_PER_THREAD : 1;
    s->lane = calloc((size_t)s->n_lanes, sizeof *s->lane);
    s->ev = calloc((size_t)s->d.max_events, sizeof *s->ev);
    s->log = calloc(DAMAGE_LOG_MAX, sizeof *s->log);
    if (!s->species || !s->cos_yaw || !s->sin_yaw || !s->tree || !s->bits || !s->lane ||
        !s->ev || !s->log) {
        goto nomem;
    }
    /* check_tree copies a state row in whole 16-float vectors and clears a fallen tree's
     * WIRE_MAX_MODES modes in this buffer */
    _Static_assert(DAMAGE_MAX_GROUPS * DAMAGE_GROUP_MODES >= WIRE_MAX_MODES,
                   "a lane's x holds a whole state row");
    for (int k = 0; k < s->n_lanes; k++) {
        damage_lane *l = &s->lane[k];
        l->q = calloc(DAMAGE_MAX_GROUPS * DAMAGE_GROUP_MODES + DAMAGE_GROUP_MODES, sizeof(float));
        l->cand = calloc((size_t)maxb_lanes, sizeof(uint32_t));
        if (k > 0) {
            /* room for every event a stream and the whole-state log can hold */
            l->cap_ev = s->d.max_events + (int)DAMAGE_LOG_MAX;
            l->cap_leaves = d->max_leaves > 0 ? d->max_leaves : DAMAGE_MAX_LEAVES;
            l->ev = calloc((size_t)l->cap_ev, sizeof *l->ev);
            l->leaves = calloc((size_t)l->cap_leaves, sizeof *l->leaves);
        }
        if (!l->q || !l->cand || (k > 0 && (!l->ev || !l->leaves))) {
            goto nomem;
        }
    }
    for (uint32_t t = 0; t < d->n_trees; t++) {
        if (d->tree_species[t] >= d->n_species) {
            gale_errf(err, GALE_E_RANGE, "damage_create: tree_species[%u]: expected < %u, got %u",
                      t, d->n_species, (unsigned)d->tree_species[t]);
            damage_destroy(s);
            return NULL;
        }
        float yaw = d->tree_yaw_rad ? d->tree_yaw_rad[t] : 0.0f;
        s->species[t] = d->tree_species[t];
        s->cos_yaw[t] = cosf(yaw);
        s->sin_yaw[t] = sinf(yaw);
        tree_intact(s, t);
    }
    atomic_store(&s->counts.leaf_area, 1.0);
    return s;
nomem:
    gale_errf(err, GALE_E_NOMEM, "damage_create: no memory for %u trees", d->n_trees);
    damage_destroy(s);
    return NULL;
}

void damage_destroy(damage_sim *s)
{
    if (!s) {
        return;
    }
    free(s->table);
    free(s->species);
    free(s->cos_yaw);
    free(s->sin_yaw);
    free(s->tree);
    free(s->bits);
    for (int k = 0; s->lane && k < s->n_lanes; k++) {
        free(s->lane[k].q);
        free(s->lane[k].cand);
        free(s->lane[k].ev);
        free(s->lane[k].leaves);
    }
    free(s->lane);
    free(s->ev);
    free(s->log);
    free(s);
}

/* An event of this step, in tree order: streamed while under the cap, and a broken branch
 * remembered for the whole-state frame. */
static void emit(damage_sim *s, const wire_damage *e)
{
    if (s->n_ev < s->d.max_events) {
        s->ev[s->n_ev++] = *e;
    } else {
        atomic_fetch_add(&s->counts.lost, 1);
    }
    if (e->kind == WIRE_DAMAGE_BRANCH) {
        if (s->n_log < DAMAGE_LOG_MAX) {
            s->log[s->n_log++] = *e;
        } else {
            atomic_fetch_add(&s->counts.lost, 1);
        }
    }
}

/* An event of lane l's trees: the first lane's straight out, a later lane's kept for the
 * merge (beyond its room, counted lost). */
static void lane_emit(damage_sim *s, damage_lane *l, uint32_t t, uint32_t node, uint8_t kind,
                      uint8_t value, uint32_t tick)
{
    const wire_damage e = { .tree = t, .node = node, .kind = kind, .value = value, .tick = tick };
    if (l == &s->lane[0]) {
        emit(s, &e);
    } else if (l->n_ev < l->cap_ev) {
        l->ev[l->n_ev++] = e;
    } else {
        atomic_fetch_add(&s->counts.lost, 1);
    }
}

static bool bit(const damage_sim *s, uint32_t t, uint32_t b)
{
    return (s->bits[(size_t)t * s->words + b / 64] >> (b % 64)) & 1u;
}

/* Branch b of tree t is gone: it or a branch it grows from broke. */
static bool gone(const damage_sim *s, const damage_table *tb, uint32_t t, int32_t b)
{
    for (; b >= 0; b = tb->branch[b].up) {
        if (bit(s, t, (uint32_t)b)) {
            return true;
        }
    }
    return false;
}

/* Drag multiplier of a standing tree: the frontal area its broken branches took, and the
 * leaves' share of the rest scaled by the leaf area left (PHYSICS.md "Storm damage"). */
static float drag_of(const damage_table *tb, const damage_tree_st *ts)
{
    float c = (float)tb->p.leaf_drag_share;
    return ts->area_frac * ((1.0f - c) + c * ts->leaf);
}

/* Area and leaf fractions left after the broken branches (top-most broken ones count). */
static void recount(const damage_sim *s, const damage_table *tb, uint32_t t, damage_tree_st *ts)
{
    float a = 1.0f, l = 1.0f;
    for (uint32_t b = 0; b < tb->n_branches; b++) {
        if (bit(s, t, b) && !gone(s, tb, t, tb->branch[b].up)) {
            a -= tb->branch[b].area_share;
            l -= tb->branch[b].leaf_share;
        }
    }
    ts->area_frac = a > 0.0f ? a : 0.0f;
    ts->leaf_frac = l > 0.0f ? l : 0.0f;
}

/* Stripped leaves of tree t going from level a to b: the slots kept at a but not at b
 * (ranks in [b, a) 32nds of the range: one or two runs of the species' sorted slot ranks),
 * on branches still there, each shed as a falling leaf. */
static int strip_leaves(const damage_sim *s, const damage_table *tb, uint32_t t, uint32_t a,
                        uint32_t b, uint32_t tick, leaf_seed *out, int cap, int *n)
{
    int lost = 0;
    const bool ts_broken = s->tree[t].broken > 0;
    const uint32_t off = wire_damage_tree_rank(t);
    /* tree rank r = slot rank + off; band [lo, hi) in tree ranks */
    const uint64_t lo = (uint64_t)b << 27, hi = (uint64_t)a << 27;
    for (int part = 0; part < 2; part++) {
        /* slot ranks [lo - off, hi - off) mod 2^32: at most two runs */
        uint64_t s0 = (lo - off) & 0xFFFFFFFFull, s1 = s0 + (hi - lo);
        uint64_t from = part == 0 ? s0 : 0, to = part == 0 ? (s1 < (1ull << 32) ? s1 : 1ull << 32)
                                                          : (s1 > (1ull << 32) ? s1 - (1ull << 32) : 0);
        if (from >= to) {
            continue;
        }
        const uint32_t i0 = damage_first_rank(tb, from), i1 = damage_first_rank(tb, to);
        for (uint32_t i = i0; i < i1; i++) {
            if (*n >= cap && !ts_broken) {
                lost += (int)(i1 - i); /* over the per-tick cap: counted, not shed */
                break;
            }
            uint32_t k = (uint32_t)tb->slot_rank[i];
            uint32_t node = tb->leaf_node[k];
            if (ts_broken && node < tb->n_nodes && gone(s, tb, t, tb->node_branch[node])) {
                continue;
            }
            if (*n >= cap) {
                lost++; /* a leaf still on the tree, over the cap */
                continue;
            }
            out[(*n)++] = (leaf_seed){ .instance = t,
                                       .slot = k,
                                       .spawn_tick = tick,
                                       .variation = (uint32_t)(unit3(s->d.seed ^ 0x5157ull, t,
                                                                     (uint64_t)k << 32 | tick) *
                                                               4294967296.0) };
        }
    }
    return lost;
}

static uint8_t azimuth(const float *v)
{
    double a = atan2((double)v[1], (double)v[0]) / 6.283185307179586;
    a -= floor(a);
    return (uint8_t)((int)(a * 256.0 + 0.5) & 255);
}

/* The force vector of tree t this tick, w = s(U) k_t |v| v in the tree frame, from the
 * factor s(U) k_t |v| modal_tick applied (modal_rows.force_scale: the same drag law, the same
 * guard on absurd samples); returns |w|². */
static inline __attribute__((always_inline)) float
    force_vector(const damage_sim *s, uint32_t t, const float *v, float w[3])
{
    float wx = v[0], wy = v[1], wz = v[2];
    if (!(wx * wx + wy * wy + wz * wz <= 1.0e6f)) {
        wx = wy = wz = 0.0f;
    }
    const float cy = s->cos_yaw[t], sy = s->sin_yaw[t];
    const float sv = s->rows.force_scale[t];
    w[0] = sv * (cy * wx + sy * wy);
    w[1] = sv * (-sy * wx + cy * wy);
    w[2] = sv * wz;
    return w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
}

/* A bound of |M(x)| for a moment table mm[n_cols] whose residual starts a group of its
 * own (n_modes a multiple of DAMAGE_GROUP_MODES): the first group's and the residual's
 * part summed, the modes' groups between them bounded by |x_g| ||M_g|| (gn[g * stride]), by the
 * triangle inequality. The first group holds the lowest modes, which carry most of a
 * moment, so this bound is close to |M(x)| where the group bound alone is not. */
static float lead_bound(const damage_table *tb, const float (*mm)[3], const float *q,
                        const float *xg, const float *gn, size_t stride)
{
    float a[3], r[3];
    damage_moment(mm, q, DAMAGE_GROUP_MODES, a);
    damage_moment(mm + tb->n_modes, q + tb->n_modes, DAMAGE_RES_COLS, r);
    float rest = 0.0f;
    for (uint32_t g = 1; g < tb->n_modes / DAMAGE_GROUP_MODES; g++) {
        rest += xg[g] * gn[g * stride];
    }
    const float x = a[0] + r[0], y = a[1] + r[1], z = a[2] + r[2];
    return sqrtf(x * x + y * y + z * z) + rest;
}

/* The stresses of standing tree t from its modal state: the stem first (a tree that
 * falls breaks nothing more), then every branch still on it. Each moment is
 * Σ_i q_i M_i + R κ w: the modes and the static residual of those left out, over
 * x = (q, κ w) (damage_table.h). */
static inline __attribute__((always_inline)) void
    check_tree(damage_sim *s, damage_lane *l, modal *m, const damage_table *tb, uint32_t t,
               const float *v, uint32_t tick)
{
    damage_tree_st *ts = &s->tree[t];
    float w[3];
    const float kw = tb->w_scale;
    const float w2 = force_vector(s, t, v, w) * kw * kw;
    /* |x| from |q| as the modal update left it (modal_rows.qnorm2): the state itself is read
     * only for a tree that might fail */
    const float qm2 = s->rows.qnorm2[t], qm = sqrtf(qm2), wn = sqrtf(w2);
    const float qn = sqrtf(qm2 + w2);
    /* the weakest branch multiplier is exp(-sd) (normal3 is clamped to ±2, halved); two
     * bounds of every moment of the tree, either below its weakest capacity ends the
     * check (1e-4 for their rounding) */
    const float lo = ts->weakest;
    if (!(qn >= lo * tb->q_screen) ||
        !((qm * tb->screen_q + wn * tb->screen_w) * 1.0001f >= lo)) {
        return;
    }
    /* q from the state's row in whole vectors (zeros past the tree's modes; what a vector
     * copies past the table's modes the residual and the pad below overwrite, or no group
     * reads), zeros past the row */
    float *q = l->q;
    const float *row = s->rows.state + (size_t)t * s->rows.stride;
    uint32_t mode = 0;
    for (; mode < tb->n_modes && mode < s->rows.pad; mode += 16) {
        memcpy(q + mode, row + mode, 16 * sizeof(float));
    }
    for (; mode < tb->n_modes; mode++) {
        q[mode] = 0.0f;
    }
    for (uint32_t k = 0; k < DAMAGE_RES_COLS; k++) {
        q[tb->n_modes + k] = kw * w[k];
    }
    const uint32_t n = tb->n_cols;
    /* x zero up to whole groups, so each group sums its squares in the order a running
     * sum over its columns would (+0 is exact) */
    for (uint32_t i = 0; i + 1 < DAMAGE_GROUP_MODES; i++) {
        q[n + i] = 0.0f; /* stores, not a call: the buffer has room past any n_cols */
    }
    /* |x_g| per group: Σ_g |x_g| ||M_g|| bounds a moment (triangle inequality over
     * groups, the spectral norm within one): the stem's (sb), and the clusters' screens.
     * Below the weakest multiplier a branch holds whatever its own strength: 1e-3 for lo's
     * single-precision exp against the draws' double one */
    const float lo_branch = 0.999f * lo;
    float xg[DAMAGE_MAX_GROUPS], sb;
    const uint32_t open = damage_screen(tb, q, lo_branch, xg, &sb);
    const float m_crit = (float)(tb->m_over_nm < tb->m_break_nm ? tb->m_over_nm : tb->m_break_nm);
    /* the stem's moment only where its bounds reach the lower critical moment: below it
     * the tree stands, whatever the moment */
    const bool res_alone = tb->n_modes > 0 && tb->n_modes % DAMAGE_GROUP_MODES == 0;
    const float(*sm)[3] = (const float(*)[3])tb->stem_moment;
    float mb = sb * 1.0001f >= ts->strength * m_crit &&
                       (!res_alone ||
                        lead_bound(tb, sm, q, xg, tb->stem_group, 1) * 1.0001f >=
                            ts->strength * m_crit)
                   ? damage_moment(sm, q, n, NULL)
                   : 0.0f;
    uint8_t fall = 0;
    if (mb > ts->strength * (float)tb->m_over_nm && tb->m_over_nm <= tb->m_break_nm) {
        fall = WIRE_DAMAGE_UPROOT;
    } else if (mb > ts->strength * (float)tb->m_break_nm) {
        fall = WIRE_DAMAGE_SNAP;
    } else if (mb > ts->strength * (float)tb->m_over_nm) {
        fall = WIRE_DAMAGE_UPROOT;
    }
    if (fall) {
        ts->fallen = fall;
        ts->fall_az = azimuth(v);
        ts->fall_tick = tick;
        lane_emit(s, l, t, WIRE_DAMAGE_WHOLE, fall, ts->fall_az, tick);
        atomic_fetch_add(fall == WIRE_DAMAGE_SNAP ? &s->counts.snapped : &s->counts.uprooted, 1);
        /* a fallen tree lies still: no force, no motion */
        memset(q, 0, sizeof(float) * WIRE_MAX_MODES);
        modal_set(m, t, q, q);
        modal_set_drag_mult(m, t, 0.0f);
        return;
    }
    bool changed = false;
    /* a branch is bounded first on its cluster's screen (open), then on its own bound
     * (Σ_g |x_g| |M_b,g| in vector lanes, 1e-4 for its rounding), then on the moment
     * itself; the draw of its own strength (a log, a cos and an exp) only for one that
     * might fail */
    if (!open) {
        return;
    }
    /* branches by rising cap / norm: from the first that cannot fail at |q| no later one
     * can fail either (a few more are bounded than the exact test needs: 1e-5) */
    const float r_max = qn / lo * 1.00001f;
    const uint32_t n_check = damage_branches_within(tb, r_max, ts->n_check);
    ts->n_check = n_check;
    /* the few the bound passes, in order */
    const uint32_t n_cand = damage_branch_bounds(tb, xg, open, n_check, lo_branch, l->cand);
    for (uint32_t c = 0; c < n_cand; c++) {
        const uint32_t j = l->cand[c];
        const uint32_t b = tb->order[j];
        const damage_branch *br = &tb->branch[b];
        const float(*mm)[3] = (const float(*)[3])(tb->branch_moment + (size_t)b * n * 3);
        /* with the residual in groups of its own, the first group and the residual summed
         * (5 columns) and the other modes bounded by their groups: tighter, at a seventh
         * of the full sum's cost */
        if (res_alone &&
            lead_bound(tb, mm, q, xg, tb->group_norm + j, tb->group_stride) * 1.0001f <=
                lo_branch * br->cap_nm) {
            continue;
        }
        const float mbr = damage_moment(mm, q, n, NULL);
        if (mbr <= lo_branch * br->cap_nm) {
            continue;
        }
        if (ts->broken && gone(s, tb, t, (int32_t)b)) {
            continue;
        }
        /* each branch its own strength about the tree's: exp(±sd) at most */
        float mult = ts->strength *
                     (float)exp(0.5 * tb->p.strength_sd * normal3(s->d.seed, t, (uint64_t)b + 1));
        if (mbr > mult * br->cap_nm) {
            s->bits[(size_t)t * s->words + b / 64] |= 1ull << (b % 64);
            ts->broken++;
            lane_emit(s, l, t, br->node, WIRE_DAMAGE_BRANCH, 0, tick);
            atomic_fetch_add(&s->counts.branches, 1);
            changed = true;
        }
    }
    if (changed) {
        recount(s, tb, t, ts);
        modal_set_drag_mult(m, t, drag_of(tb, ts));
    }
}

/* The due trees [i0, i1) of this step (tree first + i, damage_due) on lane l: stripping,
 * then stresses, each tree in turn; stripped leaves to out[*n..cap). Returns the leaves
 * over cap. Cloned for AVX-512 and AVX2 (the copies of a tree's q in whole vectors, the
 * scalar floats in the same operations: -std=c11 contracts none, so every clone decides
 * alike). */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
static int lane_run(damage_sim *s, damage_lane *l, modal *m, const float *wind_world,
                    uint32_t tick, uint32_t first, uint32_t i0, uint32_t i1, leaf_seed *out,
                    int cap, int *n)
{
    int lost = 0;
    for (uint32_t i = i0; i < i1; i++) {
        const uint32_t t = first + i;
        /* every due tree reads its own record, and about half those of a gusty day pass
         * the screen and read their state, which the modal update has long since pushed
         * out of the near caches: asked for a few trees ahead, their lines arrive while
         * the trees between are checked */
        if (i + DAMAGE_PREFETCH_TREES < i1) {
            const uint32_t ahead = t + DAMAGE_PREFETCH_TREES;
            const char *row = (const char *)(s->rows.state + (size_t)ahead * s->rows.stride);
            for (size_t at = 0; at < s->rows.pad * sizeof(float); at += 64) {
                __builtin_prefetch(row + at, 0, 3);
            }
            __builtin_prefetch(&s->tree[ahead], 1, 3);
        }
        const damage_table *tb = s->table[s->species[t]];
        damage_tree_st *ts = &s->tree[t];
        if (!tb || ts->fallen) {
            continue;
        }
        /* stripping over the ticks since this tree's last turn, then its stresses */
        const float *v = &wind_world[3 * (size_t)t];
        float sp = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (sp > DAMAGE_STRIP_START_MS && ts->leaf > 1.0f - (float)tb->p.strip_max) {
            float lf = damage_strip_step(ts->leaf, sp, (float)tb->p.strip_max, s->strip_decay);
            if (lf != ts->leaf) {
                ts->leaf = lf;
                modal_set_drag_mult(m, t, drag_of(tb, ts));
                uint32_t lv = (uint32_t)(lf * (float)WIRE_DAMAGE_LEVELS + 0.5f);
                if (lv < ts->level) {
                    lost += strip_leaves(s, tb, t, ts->level, lv, tick, out, cap, n);
                    ts->level = (uint8_t)lv;
                    ts->level_tick = tick;
                    lane_emit(s, l, t, WIRE_DAMAGE_WHOLE, WIRE_DAMAGE_STRIP, (uint8_t)lv, tick);
                }
            }
        }
        check_tree(s, l, m, tb, t, v, tick);
    }
    return lost;
}

/* One damage step's lanes. */
typedef struct step_job {
    damage_sim *s;
    modal *m;
    const float *wind_world;
    uint32_t tick, first, n_due;
    int nl;
    leaf_seed *leaves;
    int cap;
    int *n_leaves;
    int room; /* the step's room for leaves when it started */
} step_job;

static void step_lane(void *ctx, int k)
{
    const step_job *j = ctx;
    damage_lane *l = &j->s->lane[k];
    const uint32_t i0 = (uint32_t)((uint64_t)j->n_due * (uint32_t)k / (uint32_t)j->nl);
    const uint32_t i1 = (uint32_t)((uint64_t)j->n_due * (uint32_t)(k + 1) / (uint32_t)j->nl);
    if (k == 0) {
        /* the first lane writes straight to the step's outputs */
        l->lost = lane_run(j->s, l, j->m, j->wind_world, j->tick, j->first, i0, i1, j->leaves,
                           j->cap, j->n_leaves);
    } else {
        l->n_ev = 0;
        l->n_leaves = 0;
        /* of a later lane's leaves the merge keeps at most the first `room`: those past it
         * are counted lost here instead of drawn (the same leaves kept, the same count
         * lost; where the shed leaves have filled the tick's cap, as a storm's do, none is
         * drawn) */
        const int cap = l->cap_leaves < j->room ? l->cap_leaves : j->room;
        l->lost = lane_run(j->s, l, j->m, j->wind_world, j->tick, j->first, i0, i1, l->leaves,
                           cap, &l->n_leaves);
    }
}

int damage_step(damage_sim *s, modal *m, const float *wind_world, uint32_t tick,
                leaf_seed *leaves, int cap, int *n_leaves)
{
    s->n_ev = 0;
    s->rows = modal_get_rows(m);
    int lost = 0;
    uint32_t first, end;
    damage_due(s->d.n_trees, tick, &first, &end);
    const uint32_t n_due = end - first;
    /* Trees are independent: each lane takes a contiguous share of the due trees (its
     * events and leaves then follow the lanes before it), a small forest fewer lanes.
     * More lanes than threads, taken as threads come free: a thread that loses its core
     * for a while leaves its lanes still to come to the other, so the step waits for at
     * most the lane it holds rather than for its whole share. */
    const uint32_t min_trees = s->d.lane_min_trees ? s->d.lane_min_trees : DAMAGE_LANE_MIN_TREES;
    const uint32_t fit = n_due / min_trees;
    const int nl = fit >= (uint32_t)s->n_lanes ? s->n_lanes : fit > 1 ? (int)fit : 1;
    const int nt = nl < s->n_threads ? nl : s->n_threads;
    step_job j = { .s = s, .m = m, .wind_world = wind_world, .tick = tick, .first = first,
                   .n_due = n_due, .nl = nl, .leaves = leaves, .cap = cap,
                   .n_leaves = n_leaves, .room = cap > *n_leaves ? cap - *n_leaves : 0 };
    sim_team_run(nt, nl, step_lane, &j);
    for (int k = 0; k < nl; k++) {
        lost += s->lane[k].lost;
    }
    /* the later lanes' events and leaves after the first's, in tree order, under the same
     * caps as one lane would meet them */
    for (int k = 1; k < nl; k++) {
        const damage_lane *l = &s->lane[k];
        for (int e = 0; e < l->n_ev; e++) {
            emit(s, &l->ev[e]);
        }
        int room = cap - *n_leaves;
        room = room < 0 ? 0 : room;
        const int take = l->n_leaves < room ? l->n_leaves : room;
        memcpy(leaves + *n_leaves, l->leaves, sizeof *leaves * (size_t)take);
        *n_leaves += take;
        lost += l->n_leaves - take;
    }
    /* the standing leaf area for /metrics, once a second of 60 Hz ticks */
    if (tick % 60 == 0) {
        double area = 0.0;
        uint32_t counted = 0;
        for (uint32_t t = 0; t < s->d.n_trees; t++) {
            if (s->table[s->species[t]]) {
                counted++;
                area += s->tree[t].fallen ? 0.0 : (double)(s->tree[t].leaf * s->tree[t].leaf_frac);
            }
        }
        atomic_store(&s->counts.leaf_area, counted ? area / counted : 1.0);
    }
    return lost;
}

int damage_events(const damage_sim *s, const wire_damage **out)
{
    *out = s->ev;
    return s->n_ev;
}

uint32_t damage_state(const damage_sim *s, wire_damage *out, uint32_t cap)
{
    uint32_t n = 0;
    for (uint32_t t = 0; t < s->d.n_trees; t++) {
        const damage_tree_st *ts = &s->tree[t];
        if (ts->fallen) {
            if (n < cap) {
                out[n] = (wire_damage){ t, WIRE_DAMAGE_WHOLE, ts->fallen, ts->fall_az,
                                        ts->fall_tick };
            }
            n++;
        }
        if (ts->level < WIRE_DAMAGE_LEVELS) {
            if (n < cap) {
                out[n] = (wire_damage){ t, WIRE_DAMAGE_WHOLE, WIRE_DAMAGE_STRIP, ts->level,
                                        ts->level_tick };
            }
            n++;
        }
    }
    for (uint32_t i = 0; i < s->n_log; i++) {
        if (n < cap) {
            out[n] = s->log[i];
        }
        n++;
    }
    return n;
}

uint32_t damage_branches(const damage_sim *s, wire_damage *out, uint32_t cap)
{
    const uint32_t n = s->n_log < cap ? s->n_log : cap;
    memcpy(out, s->log, sizeof *out * n);
    return s->n_log;
}

uint32_t damage_forest(const damage_sim *s, uint8_t *state, wire_forest_fall *fall,
                       uint32_t *first, uint32_t *n_fall)
{
    uint32_t lo = UINT32_MAX, hi = 0;
    for (uint32_t t = 0; t < s->d.n_trees; t++) {
        const damage_tree_st *ts = &s->tree[t];
        if (ts->fallen || ts->level < WIRE_DAMAGE_LEVELS) {
            lo = lo == UINT32_MAX ? t : lo;
            hi = t;
        }
    }
    *first = 0;
    *n_fall = 0;
    if (lo == UINT32_MAX) {
        return 0;
    }
    for (uint32_t t = lo; t <= hi; t++) {
        const damage_tree_st *ts = &s->tree[t];
        state[t - lo] = (uint8_t)(ts->fallen << WIRE_FOREST_FALL_SHIFT | ts->level);
        if (ts->fallen) {
            fall[(*n_fall)++] = (wire_forest_fall){ ts->fall_az, ts->fall_tick };
        }
    }
    *first = lo;
    return hi - lo + 1;
}

void damage_heal(damage_sim *s, modal *m)
{
    /* a tree's strength is its seed's draw, the same every time: kept rather than drawn
     * again (a log, a cos and two exps a tree; the heal that drew them took 5.9 ms of one
     * tick of the 2 km scene, on the simulation thread alone) */
    for (uint32_t t = 0; t < s->d.n_trees; t++) {
        tree_reset(s, t, s->tree[t].strength, s->tree[t].weakest);
        modal_set_drag_mult(m, t, 1.0f);
    }
    s->n_log = 0;
    s->n_ev = 0;
    atomic_store(&s->counts.leaf_area, 1.0);
    atomic_fetch_add(&s->counts.heals, 1);
}

int damage_tree(const damage_sim *s, uint32_t t, float *leaf, uint32_t *broken)
{
    if (t >= s->d.n_trees) {
        return 0;
    }
    if (leaf) {
        *leaf = s->tree[t].leaf;
    }
    if (broken) {
        *broken = s->tree[t].broken;
    }
    return s->tree[t].fallen;
}

float damage_strength(const damage_sim *s, uint32_t t)
{
    return t < s->d.n_trees ? s->tree[t].strength : 0.0f;
}

damage_counts *damage_get_counts(damage_sim *s)
{
    return &s->counts;
}
