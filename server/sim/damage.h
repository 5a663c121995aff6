/* Storm damage of every tree (PHYSICS.md "Storm damage"), deterministic per seed: leaf
 * stripping by gusts (damage_strip.h) that lowers the tree's drag, branches that break
 * where the bending stress at their base exceeds the modulus of rupture, and stems that
 * snap or trees that uproot when the base moment exceeds the ForestGALES critical moments
 * (damage_table.h), each tree with a seeded strength multiplier so a stand fails
 * progressively. Reads the modal state, writes each tree's drag multiplier into it
 * (modal_set_drag) and emits wire damage events and stripped leaves. */
#ifndef GALE_DAMAGE_H
#define GALE_DAMAGE_H

#include <stdatomic.h>
#include <stdint.h>

#include "damage_table.h"
#include "err.h"
#include "leaf.h"
#include "modal.h"
#include "wire.h"

/* Ticks between two checks of one tree's stresses: trees are checked in turn, a quarter
 * a tick (damage_due), which spreads the cost; at 60 Hz a tree is checked at 15 Hz,
 * several samples per period of the modes that load branches. */
#define DAMAGE_EVERY 4

/* The trees [*t0, *t1) of n_trees checked on `tick`: the (tick % DAMAGE_EVERY)-th of
 * DAMAGE_EVERY contiguous shares, so every tree once in DAMAGE_EVERY ticks. Contiguous,
 * not every DAMAGE_EVERY-th tree: a step then reads whole cache lines of the per-tree
 * arrays (records, wind, Σ q²) rather than a quarter of each. */
static inline void damage_due(uint32_t n_trees, uint32_t tick, uint32_t *t0, uint32_t *t1)
{
    const uint64_t k = tick % DAMAGE_EVERY; /* shares rounded up: tree 0 on tick 0 */
    *t0 = (uint32_t)(((uint64_t)n_trees * k + DAMAGE_EVERY - 1) / DAMAGE_EVERY);
    *t1 = (uint32_t)(((uint64_t)n_trees * (k + 1) + DAMAGE_EVERY - 1) / DAMAGE_EVERY);
}

/* Threads a step uses at most. A step cuts the trees due into DAMAGE_LANES_PER_THREAD
 * lanes a thread, taken as threads come free, each of at least DAMAGE_LANE_MIN_TREES
 * trees (fewer trees: fewer lanes, down to the caller's thread alone, no team to start
 * for a small forest). */
#define DAMAGE_MAX_THREADS 64
#define DAMAGE_LANES_PER_THREAD 4
#define DAMAGE_LANE_MIN_TREES 1024u
/* The default of damage_desc.max_leaves: the tick's own leaves per tick. */
#define DAMAGE_MAX_LEAVES 4096

typedef struct damage_desc {
    uint32_t n_trees;
    uint32_t n_species;
    const damage_table *const *table; /* [n_species] borrowed for the life; NULL = species
                                         takes no damage */
    const uint8_t *tree_species;      /* [n_trees] borrowed for the call */
    const float *tree_yaw_rad;        /* [n_trees] borrowed for the call; NULL = 0 */
    const uint32_t *tree_leaves;      /* [n_trees] leaf slots; NULL = none */
    uint64_t seed;                    /* per-tree strength, leaf variation */
    double dt_s;                      /* tick length [s] */
    int max_events;                   /* events kept per tick; 0 → WIRE_MAX_DAMAGE */
    int max_leaves;                   /* the most stripped leaves a step's caller takes (its
                                         cap); 0 → DAMAGE_MAX_LEAVES */
    int n_threads;                    /* threads of a step (the modal update's); 0, 1: the
                                         caller's alone */
    uint32_t lane_min_trees;          /* due trees a lane takes at least; 0 →
                                         DAMAGE_LANE_MIN_TREES */
} damage_desc;

/* Totals for /metrics (damage_metrics.h); any thread reads them. */
typedef struct damage_counts {
    atomic_ullong branches;   /* branches broken since start */
    atomic_ullong snapped;    /* stems snapped */
    atomic_ullong uprooted;   /* trees uprooted */
    atomic_ullong heals;      /* heals (kiosk reset, scenario restart) */
    atomic_ullong lost;       /* events not streamed (over the per-tick cap) */
    _Atomic double leaf_area; /* standing leaf area over the scene's intact area, 0..1 */
} damage_counts;

typedef struct damage_sim damage_sim;

/* Allocates the per-tree state (intact) and draws each tree's strength; NULL with err
 * filled on a bad desc or no memory. */
damage_sim *damage_create(const damage_desc *d, gale_err *err);
void damage_destroy(damage_sim *s); /* NULL is a no-op */

/* One tick after modal_tick: wind_world[3 t] the wind at each crown this tick. Strips
 * leaves, checks the trees due this tick, breaks what fails, sets the drag multiplier of
 * each tree that changed in m, zeroes the state of a fallen tree. Stripped leaves are
 * appended to leaves[*n_leaves..cap); returns the number that did not fit. Events and
 * leaves come in tree order whatever the threads (desc.n_threads), under the same caps,
 * while cap is at most desc.max_leaves and a thread's share of one step breaks fewer than
 * WIRE_MAX_DAMAGE + 65536 things. Does not allocate. */
int damage_step(damage_sim *s, modal *m, const float *wind_world, uint32_t tick,
                leaf_seed *leaves, int cap, int *n_leaves);

/* The events of the last damage_step (valid until the next call). */
int damage_events(const damage_sim *s, const wire_damage **out);

/* The whole damage state as events into out[cap] (fallen trees, broken branches,
 * stripped crowns, in tree order); returns the number of events the state has (more than
 * cap when it does not fit: out holds the first cap). */
uint32_t damage_state(const damage_sim *s, wire_damage *out, uint32_t cap);

/* The broken branches in the order they broke into out[cap]; returns how many there are
 * (more than cap: out holds the first cap). */
uint32_t damage_branches(const damage_sim *s, wire_damage *out, uint32_t cap);

/* Every tree's fall and level as a FOREST frame lists them (PROTOCOL.md "FOREST"): the
 * trees from the first damaged one to the last as state bytes into state[n_trees], the
 * fallen ones' azimuth and tick into fall[n_trees] (*n_fall of them), the first tree
 * listed into *first; returns how many are listed (0: the forest is intact). */
uint32_t damage_forest(const damage_sim *s, uint8_t *state, wire_forest_fall *fall,
                       uint32_t *first, uint32_t *n_fall);

/* Heals every tree: intact, full crowns, drag multiplier 1 in m. */
void damage_heal(damage_sim *s, modal *m);

/* State of tree t: 0 standing, else WIRE_DAMAGE_SNAP or WIRE_DAMAGE_UPROOT; *leaf its leaf
 * area left (0..1) and *broken its broken branches, when not NULL. */
int damage_tree(const damage_sim *s, uint32_t t, float *leaf, uint32_t *broken);
/* The drawn strength multiplier of tree t. */
float damage_strength(const damage_sim *s, uint32_t t);

damage_counts *damage_get_counts(damage_sim *s);

#endif
