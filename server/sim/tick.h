/* The fixed-step simulation (server/SERVER.md "Loop"): step the wind grid (every k
 * ticks), sample the wind at each tree's crown, rotate it into the tree frame, force each
 * mode with f_i = |v| v·p_i (Diener 2008 section 4) and advance each mode by the exact
 * discrete oscillator update (modal.h), quantise q into the snapshot buffer on snapshot
 * ticks, and shed leaves (leaf.h). */
#ifndef GALE_TICK_H
#define GALE_TICK_H

#include <stdbool.h>
#include <stdint.h>

#include "drag_law.h"
#include "damage.h"
#include "err.h"
#include "leaf.h"
#include "scene.h"
#include "wind.h"

/* The modal data of one species the simulation needs (borrowed from its asset). */
typedef struct tick_species {
    uint32_t n_modes;
    const float *omega;      /* [n_modes] [rad/s] */
    const float *gamma;      /* [n_modes] [1/s] */
    const float *wind_basis; /* [n_modes][3] p_i, tree frame */
    const float *qstep;      /* [n_modes] quantisation step of the snapshot (quant_steps_derive) */
    float height_m;          /* rest height: the wind is sampled at 0.7 of it */
    uint32_t n_leaves;       /* leaf slots per tree */
    drag_law drag;           /* streamlining of the crown (drag_law.h); zero: rigid, ∝ U² */
    const damage_table *damage; /* storm damage of the species (damage_table.h), borrowed;
                                   NULL: its trees take none */
} tick_species;

/* The wind grid as the tick drives it (wind.h functions on a wind_grid in the server;
 * the indirection keeps this library free of the solver, so tests can run without it). */
typedef struct tick_wind {
    void *ctx;
    void (*set_inflow)(void *ctx, const wind_inflow *in);
    int (*step)(void *ctx, float dt_s, wind_step_stats *st);
    void (*sample_many)(void *ctx, int n, const float *p, float *v);
    /* wind_coarse: the grid averaged over factor³ blocks; may be NULL */
    int (*coarse)(void *ctx, int factor, float *out, int capacity, int dims[3]);
    /* wind_add_ball: a force ball for the next step only; may be NULL (balls ignored) */
    void (*add_ball)(void *ctx, const wind_ball *b);
    /* Optional, the real grid's (a stand-in may leave them NULL: then sample_many reads
     * every crown every tick). The crowns never move and the grid changes only in a step,
     * so their stencils are made once (wind_probe_create), the grid is read there in
     * shares over the ticks between steps on the tick's threads (wind_probe_sample, points
     * [i0, i1)), and each tick adds only what follows the inflow at once
     * (wind_add_subgrid; may be NULL). Together they give sample_many's floats of the
     * grid as it stood every - 1 ticks back (tick.c sample_probe). */
    void *(*probe_create)(void *ctx, int n, const float *p);
    void (*probe_destroy)(void *probe);
    void (*probe_sample)(void *ctx, const void *probe, int i0, int i1, float *v);
    void (*add_subgrid)(void *ctx, int n, const float *p, float *v);
    /* Optional, both or neither (with the probe): wind_publish, the samplers' copy of the
     * field, and wind_set_subgrid_inflow, the inflow of the subgrid term alone. With them
     * each step is launched one step ahead of the ticks that read it, and runs on a
     * thread of its own beside the ticks between (wind_worker.h) while the samplers read
     * the copy made when the step before it was taken (tick.c step_ahead). */
    int (*publish)(void *ctx);
    void (*set_subgrid_inflow)(void *ctx, const wind_inflow *in);
    /* the pressure solve's budget and required divergence reduction (wind_get_desc), to
     * tell a solve that ran out of iterations; 0 → unknown, no solve counts as one */
    int max_iterations;
    float div_reduction;
} tick_wind;

typedef struct tick_desc {
    const scene *sc;                /* borrowed for the simulation's life */
    const tick_species *species;    /* [sc->n_species], borrowed likewise */
    const tick_wind *wind;          /* borrowed; NULL → the steady inflow profile alone */
    int max_leaves_per_tick;        /* 0 → DAMAGE_MAX_LEAVES (4096) */
} tick_desc;

typedef struct tick_stats {
    double ms;             /* wall time of this tick */
    double wind_ms;        /* of which the wind step: running it, or waiting for the one
                              beside the ticks, and copying its field */
    double wind_wait_ms;   /* of wind_ms: waiting for a step beside the ticks not yet done */
    double wind_step_ms;   /* the step taken this tick: its own wall time, beside the ticks
                              or in this one */
    bool wind_stepped;     /* the wind grid stepped this tick, or a step beside the ticks was
                              taken (the wind fields below are set, of that step) */
    int wind_iters;        /* pressure iterations of the wind step, 0 if none this tick */
    double wind_div;       /* divergence after projection */
    double wind_residual;  /* relative residual ||b - A p|| / ||b|| of the pressure solve */
    bool wind_unconverged; /* the solve used its whole budget, still above 1/div_reduction */
    double sample_ms;      /* sampling the wind at the crowns (the grid's share, or the
                              profile) */
    double modal_ms;       /* the modal update (and quantisation on snapshot ticks) */
    double leaves_ms;      /* leaf shedding */
    double damage_ms;      /* storm damage (0 without it) */
    double cpu_ms;         /* CPU time of the calling thread over the tick: ms less this is
                              the time it was off a CPU (waiting for a core, for a helper
                              thread, or for the step beside the ticks; the host's steal is
                              not counted as CPU time where the kernel accounts for it) */
    int leaves;            /* leaf seeds emitted */
    int leaves_lost;       /* shed but over the per-tick cap */
    float max_speed_ms;    /* strongest wind at a crown */
} tick_stats;

typedef struct tick_sim tick_sim;

/* Allocates the state (modal.h: q, q' per tree and mode, per-species transitions for
 * dt = 1/tick_hz); NULL on failure with err filled. */
tick_sim *tick_create(const tick_desc *d, gale_err *err);
/* NULL is a no-op. */
void tick_destroy(tick_sim *t);

/* Runs one tick. When qsnap is not NULL it receives the quantised q of every tree,
 * [n_trees][stride] (a snapshot tick). No allocation. Fails only when the wind step
 * breaks down. */
int tick_step(tick_sim *t, int16_t *qsnap, tick_stats *st, gale_err *err);

/* Sets the inflow (from the scenario: mean wind, direction, profile and this instant's
 * gust). Safe from another thread; applied at the next tick. */
void tick_set_inflow(tick_sim *t, const wind_inflow *in);

/* Force balls (the scenario's, scenario_balls) added to the grid before every wind step;
 * balls[n] borrowed until replaced. Set before the simulation runs (not thread-safe). */
void tick_set_balls(tick_sim *t, const wind_ball *balls, int n);

/* Ticks run so far (the tick number of the state tick_q shows). */
uint32_t tick_now(const tick_sim *t);
/* Number of trees and the mode count stored per tree (the maximum over species). */
int tick_n_trees(const tick_sim *t);
int tick_stride(const tick_sim *t);
/* Float q of tree `tree` into q[cap]; returns its mode count. */
int tick_get_q(const tick_sim *t, int tree, float *q, int cap);
/* The leaf seeds of the last tick. */
int tick_leaves(const tick_sim *t, const leaf_seed **out);
/* The wind velocity [m/s, world] sampled at each crown during the last tick, [n_trees][3]. */
const float *tick_crown_wind(const tick_sim *t);

/* Storm damage (damage.h); NULL when no species takes damage. Read it on the thread that
 * runs tick_step. */
const damage_sim *tick_damage(const tick_sim *t);
/* Its /metrics counters (any thread); NULL without damage. */
damage_counts *tick_damage_counts(tick_sim *t);
/* Heals the forest before the next tick (kiosk reset, scenario restart). Safe from
 * another thread. */
void tick_request_heal(tick_sim *t);
/* Heals it now (the thread that runs tick_step). */
void tick_heal(tick_sim *t);

#endif
