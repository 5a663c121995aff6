/* Storm damage against the straightforward sum (PHYSICS.md "Storm damage"): a stand of the
 * three shipped species driven by a gusting wind that breaks branches and fells some
 * trees, where every tick's events of damage_step must equal, in order, those of a
 * reference that screens nothing: every standing tree on its turn, its stem moment, then
 * every branch still on it summed over all of x = (q, κ w) and held against its own drawn
 * strength. The screens of damage.c are bounds; they may skip work, never a break. The
 * leaves are not stripped here (strip_max 0), so the drag a check sees is the one the
 * modal state carries. */
#include "check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake.h"
#include "damage.h"
#include "damage_table.h"
#include "hash.h"
#include "lsystem.h"
#include "modal.h"
#include "species.h"
#include "species_bake.h"

#define N_SP 3
#define PER_SP 40
#define N_TREES (N_SP * PER_SP)
#define SEED 7u

static const char *const sp_names[N_SP] = { "pine", "oak", "palm" };
static asset assets[N_SP];
static damage_table tables[N_SP];
static drag_law drags[N_SP];
static float qsteps[N_SP][64];
static double strip_max[N_SP]; /* the species' own, kept for test_threads_same */
static int baked = -1;

static int bake_all(void)
{
    if (baked >= 0) {
        return baked;
    }
    baked = 0;
    for (int k = 0; k < N_SP; k++) {
        species sp;
        int rc = bake_shipped_species(sp_names[k], &sp, &assets[k], &tables[k]);
        if (rc) {
            baked = rc;
            return rc;
        }
        drags[k] = sp.drag;
        strip_max[k] = tables[k].p.strip_max;
        tables[k].p.strip_max = 0.0; /* no stripping: see the file's comment */
        for (uint32_t i = 0; i < assets[k].n_modes; i++) {
            qsteps[k][i] = 1e-3f;
        }
    }
    return 0;
}

/* The model's draws (PHYSICS.md "Storm damage", strengths): a splitmix of (seed, a, b),
 * and its Box-Muller normal clamped to ±2. */
static double unit3(uint64_t seed, uint64_t a, uint64_t b)
{
    uint64_t s = seed ^ (a * 0x9E3779B97F4A7C15ull) ^ (b * 0xD1B54A32D192ED03ull);
    return (double)(hash64_splitmix(&s) >> 11) * (1.0 / 9007199254740992.0);
}

static double normal3(uint64_t seed, uint64_t a, uint64_t b)
{
    double u1 = unit3(seed, a, 2 * b + 1), u2 = unit3(seed, a, 2 * b + 2);
    double z = sqrt(-2.0 * log(1.0 - u1)) * cos(6.283185307179586 * u2);
    return z < -2.0 ? -2.0 : z > 2.0 ? 2.0 : z;
}

/* The reference's own record of the forest. */
static uint8_t ref_fallen[N_TREES];
static uint8_t ref_broken[N_TREES][4096];

static bool ref_gone(const damage_table *tb, uint32_t t, int32_t b)
{
    for (; b >= 0; b = tb->branch[b].up) {
        if (ref_broken[t][b]) {
            return true;
        }
    }
    return false;
}

/* The reference's events of tree t this tick, appended to ev[*n]. */
static void ref_check(const damage_sim *d, const modal *m, uint32_t t, uint8_t sp, float yaw,
                      const float *v, uint32_t tick, wire_damage *ev, int *n)
{
    const damage_table *tb = &tables[sp];
    const uint32_t nc = tb->n_cols;
    float x[64 + DAMAGE_RES_COLS] = { 0 };
    uint32_t nq = modal_get(m, t, x, NULL);
    nq = nq > tb->n_modes ? tb->n_modes : nq;
    for (uint32_t i = nq; i < tb->n_modes; i++) {
        x[i] = 0.0f;
    }
    /* the tick's force vector w = s(U) k_t |v| v in the tree frame (modal.h) */
    const float cy = cosf(yaw), sy = sinf(yaw);
    const float u = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const float sv = u * drag_law_scale(&drags[sp], u) * modal_drag_mult(m, t);
    const float w[3] = { sv * (cy * v[0] + sy * v[1]), sv * (-sy * v[0] + cy * v[1]), sv * v[2] };
    for (uint32_t k = 0; k < DAMAGE_RES_COLS; k++) {
        x[tb->n_modes + k] = tb->w_scale * w[k];
    }
    const float strength = damage_strength(d, t);
    const float mb = damage_moment((const float(*)[3])tb->stem_moment, x, nc, NULL);
    uint8_t fall = 0;
    if (mb > strength * (float)tb->m_over_nm && tb->m_over_nm <= tb->m_break_nm) {
        fall = WIRE_DAMAGE_UPROOT;
    } else if (mb > strength * (float)tb->m_break_nm) {
        fall = WIRE_DAMAGE_SNAP;
    } else if (mb > strength * (float)tb->m_over_nm) {
        fall = WIRE_DAMAGE_UPROOT;
    }
    if (fall) {
        ref_fallen[t] = fall;
        double a = atan2((double)v[1], (double)v[0]) / 6.283185307179586;
        a -= floor(a);
        ev[(*n)++] = (wire_damage){ t, WIRE_DAMAGE_WHOLE, fall,
                                    (uint8_t)((int)(a * 256.0 + 0.5) & 255), tick };
        return;
    }
    /* every branch, in the table's order (the order the events go out in) */
    for (uint32_t j = 0; j < tb->n_branches; j++) {
        const uint32_t b = tb->order[j];
        if (ref_gone(tb, t, (int32_t)b)) {
            continue;
        }
        const float(*mm)[3] = (const float(*)[3])(tb->branch_moment + (size_t)b * nc * 3);
        const float mbr = damage_moment(mm, x, nc, NULL);
        const float mult =
            strength * (float)exp(0.5 * tb->p.strength_sd * normal3(SEED, t, (uint64_t)b + 1));
        if (mbr > mult * tb->branch[b].cap_nm) {
            ref_broken[t][b] = 1;
            ev[(*n)++] = (wire_damage){ t, tb->branch[b].node, WIRE_DAMAGE_BRANCH, 0, tick };
        }
    }
}

/* 40 s of a ramp to a 42 m/s crown wind over 25 s, each tree's own gusts of ±35 % and a
 * veer of ±0.5 rad about the mean direction: the wind of every tree at tick. */
static void stand_wind(uint32_t tick, float *wind)
{
    const float ts = (float)tick / 60.0f;
    const float mean = 42.0f * (ts < 25.0f ? ts / 25.0f : 1.0f);
    for (uint32_t t = 0; t < N_TREES; t++) {
        const float g = 1.0f + 0.35f * sinf(0.9f * ts + 1.3f * (float)t) *
                                   sinf(0.23f * ts + 0.7f * (float)t);
        const float dir = 0.5f * sinf(0.11f * ts + (float)t);
        wind[3 * t] = mean * g * cosf(dir);
        wind[3 * t + 1] = mean * g * sinf(dir);
        wind[3 * t + 2] = 0.05f * mean * sinf(1.7f * ts + (float)t);
    }
}

/* The stand's trees: species in turn, each its own yaw. */
static void stand_trees(uint8_t *sp, float *yaw)
{
    for (uint32_t t = 0; t < N_TREES; t++) {
        sp[t] = (uint8_t)(t % N_SP);
        yaw[t] = 0.37f * (float)t;
    }
}

static modal *stand_modal(const uint8_t *sp, const float *yaw)
{
    modal_species ms[N_SP];
    for (int k = 0; k < N_SP; k++) {
        const asset *a = &assets[k];
        ms[k] = (modal_species){ .n_modes = a->n_modes, .omega = a->omega, .gamma = a->gamma,
                                 .wind_basis = a->wind_basis, .qstep = qsteps[k] };
    }
    gale_err err;
    return modal_create(&(modal_desc){ .n_trees = N_TREES, .n_species = N_SP, .species = ms,
                                       .tree_species = sp, .species_drag = drags,
                                       .tree_yaw_rad = yaw, .dt_s = 1.0 / 60, .n_threads = 1 },
                        &err);
}

/* The stand's damage on n_threads, each taking at least one due tree (so a small stand
 * is split too), its caller's leaf cap max_leaves. */
static damage_sim *stand_damage(const uint8_t *sp, const float *yaw, int n_threads,
                                int max_leaves)
{
    const damage_table *tp[N_SP] = { &tables[0], &tables[1], &tables[2] };
    gale_err err;
    return damage_create(&(damage_desc){ .n_trees = N_TREES, .n_species = N_SP, .table = tp,
                                         .tree_species = sp, .tree_yaw_rad = yaw, .seed = SEED,
                                         .dt_s = 1.0 / 60, .max_leaves = max_leaves,
                                         .n_threads = n_threads, .lane_min_trees = 1 },
                         &err);
}

static void events_equal_reference(int n_threads)
{
    if (bake_all()) {
        CHECK(0);
        return;
    }
    for (int k = 0; k < N_SP; k++) {
        CHECK(tables[k].n_branches <= 4096);
    }
    for (int k = 0; k < N_SP; k++) {
        tables[k].p.strip_max = 0.0; /* no stripping: see the file's comment */
    }
    memset(ref_fallen, 0, sizeof ref_fallen);
    memset(ref_broken, 0, sizeof ref_broken);
    uint8_t sp[N_TREES];
    float yaw[N_TREES];
    stand_trees(sp, yaw);
    modal *m = stand_modal(sp, yaw);
    damage_sim *d = stand_damage(sp, yaw, n_threads, 64);
    CHECK(m != NULL && d != NULL);
    if (!m || !d) {
        modal_destroy(m);
        damage_destroy(d);
        return;
    }
    static float wind[3 * N_TREES];
    static wire_damage want[N_TREES * 64];
    static leaf_seed leaves[64];
    int mismatched_ticks = 0, branches = 0, falls = 0;
    uint64_t h = 0;
    for (uint32_t tick = 0; tick < 40 * 60; tick++) {
        stand_wind(tick, wind);
        modal_tick(m, wind, NULL);
        int n_want = 0;
        uint32_t due0, due1;
        damage_due(N_TREES, tick, &due0, &due1);
        for (uint32_t t = due0; t < due1; t++) {
            if (!ref_fallen[t]) {
                ref_check(d, m, t, sp[t], yaw[t], &wind[3 * t], tick, want, &n_want);
            }
        }
        int nl = 0;
        damage_step(d, m, wind, tick, leaves, 64, &nl);
        const wire_damage *got;
        const int n_got = damage_events(d, &got);
        bool same = n_got == n_want;
        for (int i = 0; same && i < n_got; i++) {
            same = got[i].tree == want[i].tree && got[i].node == want[i].node &&
                   got[i].kind == want[i].kind && got[i].value == want[i].value &&
                   got[i].tick == want[i].tick;
        }
        if (!same && mismatched_ticks++ < 3) {
            fprintf(stderr, "  tick %u: damage_step %d events, reference %d\n", tick, n_got,
                    n_want);
        }
        for (int i = 0; i < n_want; i++) {
            branches += want[i].kind == WIRE_DAMAGE_BRANCH;
            falls += want[i].kind != WIRE_DAMAGE_BRANCH;
            uint64_t s = h ^ ((uint64_t)want[i].tree << 40 | (uint64_t)want[i].node << 8 |
                              want[i].kind) ^ ((uint64_t)want[i].tick << 20);
            h = hash64_splitmix(&s);
        }
        CHECK(nl == 0);
    }
    fprintf(stderr, "  %d thread(s), reference: %d branches broken, %d trees fallen of %d, "
                    "hash %016llx; %d ticks differ\n",
            n_threads, branches, falls, N_TREES, (unsigned long long)h, mismatched_ticks);
    CHECK(mismatched_ticks == 0);
    /* the stand exercises both paths: branches break, some trees fall, not all */
    CHECK(branches > 0);
    CHECK(falls > 0 && falls < N_TREES);
    damage_destroy(d);
    modal_destroy(m);
}

static void test_events_equal_reference(void)
{
    if (bake_all()) {
        CHECK(0);
        return;
    }
    events_equal_reference(1);
    /* three threads on uneven shares: the same events in the same order */
    events_equal_reference(3);
}

/* With stripping on and a leaf cap the stand overflows, a step on three threads gives the
 * events, the shed leaves (kept and over the cap) and the drag of one thread, tick by
 * tick (damage.c lane_run and the merge after it). */
static void test_threads_same(void)
{
    if (bake_all()) {
        CHECK(0);
        return;
    }
    for (int k = 0; k < N_SP; k++) {
        tables[k].p.strip_max = strip_max[k];
    }
    enum { CAP = 96 };
    uint8_t sp[N_TREES];
    float yaw[N_TREES];
    stand_trees(sp, yaw);
    modal *m[2] = { stand_modal(sp, yaw), stand_modal(sp, yaw) };
    damage_sim *d[2] = { stand_damage(sp, yaw, 1, CAP), stand_damage(sp, yaw, 3, CAP) };
    CHECK(m[0] && m[1] && d[0] && d[1]);
    static float wind[3 * N_TREES];
    static leaf_seed leaves[2][CAP];
    int differ = 0, events = 0, strips = 0, shed = 0, over = 0;
    for (uint32_t tick = 0; m[0] && m[1] && d[0] && d[1] && tick < 40 * 60; tick++) {
        stand_wind(tick, wind);
        int nl[2] = { 0, 0 }, lost[2];
        const wire_damage *ev[2];
        int n_ev[2];
        for (int j = 0; j < 2; j++) {
            modal_tick(m[j], wind, NULL);
            lost[j] = damage_step(d[j], m[j], wind, tick, leaves[j], CAP, &nl[j]);
            n_ev[j] = damage_events(d[j], &ev[j]);
        }
        /* field by field: wire_damage has padding */
        bool same = n_ev[0] == n_ev[1] && nl[0] == nl[1] && lost[0] == lost[1];
        for (int i = 0; same && i < n_ev[0]; i++) {
            const wire_damage *a = &ev[0][i], *b = &ev[1][i];
            same = a->tree == b->tree && a->node == b->node && a->kind == b->kind &&
                   a->value == b->value && a->tick == b->tick;
        }
        for (int i = 0; same && i < nl[0]; i++) {
            const leaf_seed *a = &leaves[0][i], *b = &leaves[1][i];
            same = a->instance == b->instance && a->slot == b->slot &&
                   a->spawn_tick == b->spawn_tick && a->variation == b->variation;
        }
        for (uint32_t t = 0; same && t < N_TREES; t++) {
            same = modal_drag_mult(m[0], t) == modal_drag_mult(m[1], t);
        }
        if (!same && differ < 3) {
            fprintf(stderr, "  tick %u: events %d / %d, leaves %d / %d, over the cap %d / %d\n",
                    tick, n_ev[0], n_ev[1], nl[0], nl[1], lost[0], lost[1]);
        }
        differ += !same;
        events += n_ev[0];
        for (int i = 0; i < n_ev[0]; i++) {
            strips += ev[0][i].kind == WIRE_DAMAGE_STRIP;
        }
        shed += nl[0];
        over += lost[0];
    }
    fprintf(stderr, "  1 and 3 threads: %d events (%d strips), %d leaves shed, %d over the "
                    "cap; %d ticks differ\n",
            events, strips, shed, over, differ);
    CHECK(differ == 0);
    /* the run strips crowns, sheds leaves past the cap and breaks things */
    CHECK(strips > 0 && shed > 0 && over > 0 && events > strips);
    for (int j = 0; j < 2; j++) {
        damage_destroy(d[j]);
        modal_destroy(m[j]);
    }
}

/* The spectral norm (damage_moment_norm) of hand tables against their closed forms: two
 * equal moments in crossed planes have norm |M| (Frobenius: sqrt(2) |M|), two along one
 * axis add in full, and a single column is its length. */
static void test_moment_norm_closed_form(void)
{
    /* a bound: at or above the closed form, and above it by at most its rounding margin
     * (1e-6 of the trace under the root, 1.5e-6 of it at most, and 1e-7) */
    const float crossed[2][3] = { { 3.0f, 0.0f, 0.0f }, { 0.0f, 3.0f, 0.0f } };
    const float along[2][3] = { { 3.0f, 0.0f, 0.0f }, { 4.0f, 0.0f, 0.0f } };
    const float one[1][3] = { { 1.0f, 2.0f, 2.0f } };
    /* [[2, 1], [0, 2]] (rows the moment's axes): σ² the larger root of λ² - 9λ + 16 */
    const float tri[2][3] = { { 2.0f, 0.0f, 0.0f }, { 1.0f, 2.0f, 0.0f } };
    const struct {
        const float (*m)[3];
        uint32_t n;
        double want;
    } cases[] = { { crossed, 2, 3.0 }, { along, 2, 5.0 }, { one, 1, 3.0 },
                  { tri, 2, sqrt((9.0 + sqrt(17.0)) / 2.0) } };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const double got = damage_moment_norm(cases[i].m, cases[i].n);
        CHECK(got >= cases[i].want);
        CHECK_NEAR(got, cases[i].want, 2e-6 * cases[i].want);
    }
    const float zero[2][3] = { { 0 } };
    CHECK(damage_moment_norm(zero, 2) == 0.0f);
}

/* Every branch bound of the shipped species against its branch's moment, for random x
 * (any x: a bound holds for all), and the branches damage_branch_bounds passes, whose
 * clusters are screened first, against each branch's own test over the whole prefix: the
 * screen may save work, never drop a branch. */
static void test_branch_bounds(void)
{
    if (bake_all()) {
        CHECK(0);
        return;
    }
    uint64_t seed = 99;
    int passed = 0, edge_hits = 0, trials = 0, bound_fail = 0, flag_fail = 0, stem_fail = 0;
    static uint32_t cand[4096 + DAMAGE_CLUSTERS * DAMAGE_BOUND_LANES];
    for (int k = 0; k < N_SP; k++) {
        const damage_table *tb = &tables[k];
        const uint32_t nc = tb->n_cols;
        CHECK(tb->n_branches <= 4096);
        const int n_draws = 200 + 2 * (int)tb->n_groups;
        for (int trial = 0; trial < n_draws && tb->n_branches <= 4096; trial++) {
            float x[64 + DAMAGE_RES_COLS + DAMAGE_GROUP_MODES] = { 0 };
            /* falling with the mode's index like a wind's response, at a scale that puts
             * the prefix's bounds about their capacities; after the first 200, x in one
             * group alone, where a cluster's screen is its largest branch's bound exactly */
            const double scale = 0.02 * (double)(trial % 200 + 1) / (double)tb->q_screen;
            const uint32_t only = trial < 200 ? UINT32_MAX : (uint32_t)(trial - 200) % tb->n_groups;
            for (uint32_t c = 0; c < nc; c++) {
                if (only != UINT32_MAX && c / DAMAGE_GROUP_MODES != only) {
                    continue;
                }
                const double u = (double)(hash64_splitmix(&seed) >> 11) / 9007199254740992.0;
                x[c] = (float)((2.0 * u - 1.0) * scale / (1.0 + 0.2 * (double)c));
            }
            float xg[DAMAGE_MAX_GROUPS] = { 0 }, sb = 0.0f;
            (void)damage_screen(tb, x, 1.0f, xg, &sb);
            /* the stem's group bound: the running sum over the groups, and a bound */
            float sb_want = xg[0] * tb->stem_group[0];
            for (uint32_t g = 1; g < tb->n_groups; g++) {
                sb_want += xg[g] * tb->stem_group[g];
            }
            stem_fail += sb != sb_want ||
                         !(sb * 1.0001f >= damage_moment((const float(*)[3])tb->stem_moment, x,
                                                          nc, NULL));
            for (uint32_t j = 0; j < tb->n_branches; j++) {
                const uint32_t b = tb->order[j];
                float bound = xg[0] * tb->group_norm[j];
                for (uint32_t g = 1; g < tb->n_groups; g++) {
                    bound += xg[g] * tb->group_norm[(size_t)g * tb->group_stride + j];
                }
                const float mom = damage_moment(
                    (const float(*)[3])(tb->branch_moment + (size_t)b * nc * 3), x, nc, NULL);
                bound_fail += !(bound * 1.0001f >= mom);
            }
            /* a fixed multiple, and one just below the largest bound over capacity, where a
             * screen too tight drops the one branch that passes */
            const uint32_t n_check = tb->n_branches - (uint32_t)trial % 17u;
            float edge = 0.0f;
            for (uint32_t j = 0; j < n_check; j++) {
                float bound = xg[0] * tb->group_norm[j];
                for (uint32_t g = 1; g < tb->n_groups; g++) {
                    bound += xg[g] * tb->group_norm[(size_t)g * tb->group_stride + j];
                }
                const float r = bound * 1.0001f / tb->cap_by_order[j];
                edge = r > edge ? r : edge;
            }
            /* and one far below, where nearly every branch passes: the prefix's end is
             * what leaves the rest out */
            const float cap_mults[3] = { 0.7f, edge * (1.0f - 1e-5f), edge * 1e-3f };
            for (int c = 0; c < 3; c++) {
                const float cap_mult = cap_mults[c];
                const uint32_t open = damage_screen(tb, x, cap_mult, xg, &sb);
                const uint32_t hits = damage_branch_bounds(tb, xg, open, n_check, cap_mult, cand);
                /* the j that pass, rising: the next one wanted is cand[at] */
                uint32_t at = 0;
                for (uint32_t j = 0; j < n_check; j++) {
                    float bound = xg[0] * tb->group_norm[j];
                    for (uint32_t g = 1; g < tb->n_groups; g++) {
                        bound += xg[g] * tb->group_norm[(size_t)g * tb->group_stride + j];
                    }
                    const bool want = bound * 1.0001f > cap_mult * tb->cap_by_order[j];
                    const bool got = at < hits && cand[at] == j;
                    flag_fail += want != got;
                    at += got;
                }
                flag_fail += at != hits;
                passed += c == 0 && hits > 0;
                edge_hits += c == 1 && hits > 0;
            }
            trials++;
        }
    }
    fprintf(stderr, "  %d draws, %d with branches past the screen at 0.7, %d at their largest "
                    "bound; %d bounds below the moment, %d branches wrong, %d stem bounds wrong\n",
            trials, passed, edge_hits, bound_fail, flag_fail, stem_fail);
    CHECK(bound_fail == 0);
    CHECK(flag_fail == 0);
    CHECK(stem_fail == 0);
    /* the draws reach both sides of the screen */
    CHECK(passed > trials / 10 && passed < trials - 100);
    CHECK(edge_hits == trials);
}

int main(void)
{
    RUN(test_moment_norm_closed_form);
    RUN(test_branch_bounds);
    RUN(test_events_equal_reference);
    RUN(test_threads_same);
    for (int k = 0; k < N_SP; k++) {
        damage_table_fini(&tables[k]);
        asset_fini(&assets[k]);
    }
    return check_report();
}
