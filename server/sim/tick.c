/* The fixed-step simulation: see tick.h. */
#include "tick.h"
#include "mono.h"
#include "pi_mutex.h"

#include "modal.h"
#include "sim_lanes.h"
#include "sim_team.h"
#include "wind_worker.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>


struct tick_sim {
    tick_desc d;
    float dt_s;
    int n_trees, stride;
    modal *m;               /* owned: q, q' of every tree and mode */
    float *crown;           /* owned [n_trees][3] sample points, world */
    float *vel;             /* owned [n_trees][3] sampled wind */
    uint32_t *order;        /* owned [n_trees]: the trees in the order they are sampled */
    float *crown_ordered;   /* owned [n_trees][3]: crown in that order */
    float *vel_ordered;     /* owned [n_trees][3]: the wind sampled in that order */
    void *probe;            /* owned by d.wind: the crowns' stencils in that order; NULL:
                               sample_many every tick */
    float *vel_grid;        /* owned [n_trees][3]: the grid's part at each crown (with a
                               probe), as the grid stood after a step (sample_probe) */
    float *vel_next;        /* owned [n_trees][3]: the same, of the last step, share by share */
    bool grid_read;         /* vel_grid holds a step's grid */
    wind_worker *worker;    /* owned: the steps one step ahead (with d.wind->publish and a
                               probe: step_ahead); NULL: each step on its own tick */
    bool launched;          /* the worker holds a step */
    bool step_inflow_stale; /* the inflow changed since the last step was launched */
    uint32_t *slots;        /* owned [n_trees]: leaf slots of each tree's species */
    int threads;            /* scene tick_threads */
    leaf_seed *leaves;      /* owned [max_leaves_per_tick] */
    leaf_seed *leaf_scratch;/* owned [leaf_scratch_seeds(threads, max_leaves_per_tick)] */
    int n_leaves;
    uint32_t tick;
    leaf_desc leaf;
    pthread_mutex_t lock;   /* guards inflow below */
    wind_inflow inflow;
    bool inflow_dirty;
    const wind_ball *balls; /* borrowed [n_balls] */
    int n_balls;
    damage_sim *dmg;        /* owned; NULL when no species takes damage */
    atomic_int heal;        /* a heal is due before the next tick */
};

/* Interleaves the low 16 bits of x and y (x in the even bits): the Morton code. */
static uint32_t morton2(uint32_t x, uint32_t y)
{
    uint32_t v[2] = { x & 0xffffu, y & 0xffffu };
    for (int k = 0; k < 2; k++) {
        v[k] = (v[k] | (v[k] << 8)) & 0x00ff00ffu;
        v[k] = (v[k] | (v[k] << 4)) & 0x0f0f0f0fu;
        v[k] = (v[k] | (v[k] << 2)) & 0x33333333u;
        v[k] = (v[k] | (v[k] << 1)) & 0x55555555u;
    }
    return v[0] | v[1] << 1;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* The trees in the Morton order of the wind cell their crown stands in (ties by index),
 * so consecutive samples read neighbouring cells of the grid, whatever order the scene
 * lists its trees in (a generated forest's is random). Tree ids are unchanged: the
 * samples are scattered back to scene order. Returns non-zero without memory. */
static int sample_order(tick_sim *t)
{
    const scene *sc = t->d.sc;
    const size_t n = (size_t)t->n_trees;
    uint64_t *key = malloc(n * sizeof *key);
    if (!key) {
        return GALE_E_NOMEM;
    }
    const float cell = sc->cell_m > 0.0f ? sc->cell_m : 1.0f;
    for (size_t k = 0; k < n; k++) {
        float fx = (t->crown[3 * k] - sc->origin[0]) / cell;
        float fy = (t->crown[3 * k + 1] - sc->origin[1]) / cell;
        /* outside the grid clamps to its edge cells, as the sampler does */
        uint32_t ix = fx > 0.0f ? (fx < 65535.0f ? (uint32_t)fx : 65535u) : 0u;
        uint32_t iy = fy > 0.0f ? (fy < 65535.0f ? (uint32_t)fy : 65535u) : 0u;
        key[k] = (uint64_t)morton2(ix, iy) << 32 | (uint64_t)k;
    }
    qsort(key, n, sizeof *key, cmp_u64);
    for (size_t i = 0; i < n; i++) {
        const uint32_t k = (uint32_t)key[i];
        t->order[i] = k;
        memcpy(&t->crown_ordered[3 * i], &t->crown[3 * (size_t)k], 3 * sizeof(float));
    }
    free(key);
    return 0;
}

tick_sim *tick_create(const tick_desc *d, gale_err *err)
{
    tick_sim *t = calloc(1, sizeof *t);
    if (!t) {
        gale_errf(err, GALE_E_NOMEM, "tick_create: no memory");
        return NULL;
    }
    pi_mutex_init(&t->lock);
    t->d = *d;
    const scene *sc = d->sc;
    if (!t->d.max_leaves_per_tick) {
        t->d.max_leaves_per_tick = DAMAGE_MAX_LEAVES;
    }
    t->dt_s = (float)(1.0 / sc->tick_hz);
    t->n_trees = sc->n_trees;
    modal_species ms[SCENE_MAX_SPECIES];
    drag_law drag[SCENE_MAX_SPECIES];
    for (int i = 0; i < sc->n_species; i++) {
        const tick_species *sp = &d->species[i];
        ms[i] = (modal_species){ .n_modes = sp->n_modes,
                                 .omega = sp->omega,
                                 .gamma = sp->gamma,
                                 .wind_basis = sp->wind_basis,
                                 .qstep = sp->qstep };
        drag[i] = sp->drag;
    }
    uint8_t *species = calloc((size_t)t->n_trees, 1);
    float *yaw = calloc((size_t)t->n_trees, sizeof *yaw);
    t->crown = calloc((size_t)t->n_trees * 3, sizeof *t->crown);
    t->vel = calloc((size_t)t->n_trees * 3, sizeof *t->vel);
    t->leaves = calloc((size_t)t->d.max_leaves_per_tick, sizeof *t->leaves);
    t->threads = sc->tick_threads > 1 ? sc->tick_threads : 1;
    t->order = malloc((size_t)t->n_trees * sizeof *t->order);
    t->crown_ordered = malloc((size_t)t->n_trees * 3 * sizeof(float));
    t->vel_ordered = malloc((size_t)t->n_trees * 3 * sizeof(float));
    t->slots = malloc((size_t)t->n_trees * sizeof *t->slots);
    t->leaf_scratch = t->threads > 1 ? calloc(leaf_scratch_seeds(t->threads,
                                                                 t->d.max_leaves_per_tick),
                                              sizeof *t->leaf_scratch)
                                     : NULL;
    if (!species || !yaw || !t->crown || !t->vel || !t->leaves || !t->order ||
        !t->crown_ordered || !t->vel_ordered || !t->slots ||
        (t->threads > 1 && !t->leaf_scratch)) {
        free(species);
        free(yaw);
        gale_errf(err, GALE_E_NOMEM, "tick_create: no memory for %d trees", t->n_trees);
        goto fail;
    }
    for (int k = 0; k < t->n_trees; k++) {
        const scene_tree *tr = &sc->trees[k];
        float h = d->species[tr->species].height_m * tr->scale;
        t->crown[3 * k + 0] = tr->pos[0];
        t->crown[3 * k + 1] = tr->pos[1];
        t->crown[3 * k + 2] = tr->pos[2] + 0.7f * h;
        species[k] = (uint8_t)tr->species;
        yaw[k] = tr->yaw_rad;
        t->slots[k] = d->species[tr->species].n_leaves;
    }
    if (sample_order(t)) {
        free(species);
        free(yaw);
        gale_errf(err, GALE_E_NOMEM, "tick_create: no memory for %d trees", t->n_trees);
        goto fail;
    }
    if (d->wind && d->wind->probe_create && d->wind->probe_sample && d->wind->probe_destroy) {
        /* without memory for them the crowns are sampled every tick as without a probe */
        t->vel_grid = malloc((size_t)t->n_trees * 3 * sizeof(float));
        t->vel_next = malloc((size_t)t->n_trees * 3 * sizeof(float));
        t->probe = t->vel_grid && t->vel_next
                       ? d->wind->probe_create(d->wind->ctx, t->n_trees, t->crown_ordered)
                       : NULL;
    }
    if (t->probe && d->wind->publish && d->wind->set_subgrid_inflow) {
        /* A second tick thread means a second core: the step goes beside the ticks when
         * the solver runs on one thread (a solver on several would take the tick's
         * cores). Without a thread for it the step's tick runs it; without memory for
         * the worker or the field's copy each step runs on its own tick. */
        const bool beside = t->threads > 1 && sc->wind_threads <= 1;
        t->worker = wind_worker_create(d->wind->step, d->wind->ctx, beside, NULL);
        if (!t->worker && beside) {
            t->worker = wind_worker_create(d->wind->step, d->wind->ctx, false, NULL);
        }
        if (t->worker && d->wind->publish(d->wind->ctx) != 0) {
            wind_worker_destroy(t->worker);
            t->worker = NULL;
        }
    }
    t->m = modal_create(&(modal_desc){ .n_trees = (uint32_t)t->n_trees,
                                       .n_species = (uint32_t)sc->n_species,
                                       .species = ms,
                                       .tree_species = species,
                                       .species_drag = drag,
                                       .tree_yaw_rad = yaw,
                                       .dt_s = (double)t->dt_s,
                                       .n_threads = t->threads },
                        err);
    if (t->m) {
        const damage_table *tables[SCENE_MAX_SPECIES];
        bool any = false;
        for (int i = 0; i < sc->n_species; i++) {
            tables[i] = d->species[i].damage;
            any = any || tables[i];
        }
        uint32_t *nl = any ? calloc((size_t)t->n_trees, sizeof *nl) : NULL;
        for (int k = 0; nl && k < t->n_trees; k++) {
            nl[k] = d->species[species[k]].n_leaves;
        }
        if (any && nl) {
            t->dmg = damage_create(&(damage_desc){ .n_trees = (uint32_t)t->n_trees,
                                                   .n_species = (uint32_t)sc->n_species,
                                                   .table = tables,
                                                   .tree_species = species,
                                                   .tree_yaw_rad = yaw,
                                                   .tree_leaves = nl,
                                                   .max_leaves = t->d.max_leaves_per_tick,
                                                   .seed = sc->leaf_seed ^ 0xDA3A6Eull,
                                                   .dt_s = (double)t->dt_s,
                                                   .n_threads = t->threads },
                                   err);
        } else if (any) {
            gale_errf(err, GALE_E_NOMEM, "tick_create: no memory for %d trees", t->n_trees);
        }
        free(nl);
        if (any && !t->dmg) {
            free(species);
            free(yaw);
            goto fail;
        }
    }
    free(species);
    free(yaw);
    if (!t->m) {
        goto fail;
    }
    t->stride = (int)modal_stride(t->m);
    t->leaf = (leaf_desc){ .rate_hz = sc->leaf_rate_hz,
                           .calm_ms = sc->leaf_calm_ms,
                           .ref_ms = sc->leaf_ref_ms,
                           .seed = sc->leaf_seed };
    t->inflow = (wind_inflow){ .dir_rad = sc->wind_dir_deg * 0.017453292f,
                               .u10_ms = sc->wind_u10_ms };
    t->inflow_dirty = true;
    return t;
fail:
    tick_destroy(t);
    return NULL;
}

void tick_destroy(tick_sim *t)
{
    if (!t) {
        return;
    }
    /* a step in flight still writes the grid */
    wind_worker_destroy(t->worker);
    modal_destroy(t->m);
    damage_destroy(t->dmg);
    if (t->probe) {
        t->d.wind->probe_destroy(t->probe);
    }
    free(t->vel_grid);
    free(t->vel_next);
    free(t->crown);
    free(t->vel);
    free(t->order);
    free(t->crown_ordered);
    free(t->vel_ordered);
    free(t->slots);
    free(t->leaves);
    free(t->leaf_scratch);
    pthread_mutex_destroy(&t->lock);
    free(t);
}

void tick_set_inflow(tick_sim *t, const wind_inflow *in)
{
    pthread_mutex_lock(&t->lock);
    t->inflow = *in;
    t->inflow_dirty = true;
    pthread_mutex_unlock(&t->lock);
}

void tick_set_balls(tick_sim *t, const wind_ball *balls, int n)
{
    t->balls = balls;
    t->n_balls = balls ? n : 0;
}

/* One share of a tick's read of the probe: crowns [r0, r0 + n) in the locality order. */
typedef struct probe_job {
    tick_sim *t;
    int r0, n, shares;
    float *dst;
} probe_job;

static void probe_share(void *ctx, int c)
{
    const probe_job *pj = ctx;
    tick_sim *t = pj->t;
    int a, b;
    sim_share(pj->n, pj->shares, c, &a, &b);
    a += pj->r0;
    b += pj->r0;
    t->d.wind->probe_sample(t->d.wind->ctx, t->probe, a, b, t->vel_ordered);
    for (int i = a; i < b; i++) {
        memcpy(&pj->dst[3 * (size_t)t->order[i]], &t->vel_ordered[3 * (size_t)i],
               3 * sizeof(float));
    }
}

/* One share of the crowns' wind: the grid's part plus the subgrid term. */
static void crown_share(void *ctx, int c)
{
    tick_sim *t = ctx;
    const tick_wind *wd = t->d.wind;
    int a, b;
    sim_share(t->n_trees, sim_shares(t->n_trees, t->threads), c, &a, &b);
    const size_t i0 = (size_t)a;
    const int m = b - a;
    memcpy(&t->vel[3 * i0], &t->vel_grid[3 * i0], 3 * sizeof(float) * (size_t)m);
    if (wd->add_subgrid) {
        wd->add_subgrid(wd->ctx, m, &t->crown[3 * i0], &t->vel[3 * i0]);
    }
}

/* The wind at every crown from the probe: the grid's part, then each tick the term that
 * follows the inflow. With a step every k ticks, the step's tick and each of the k - 1
 * after it read a k-th of the crowns into a second buffer, the last switching all crowns
 * to that step's grid at once: the grid's part lags the field read (the grid, or its
 * copy published by step_ahead) by k - 1 ticks (less than one step; none at k = 1), and
 * no tick carries the whole read (SERVER.md "Loop"). The
 * first tick reads the whole grid at once. Each crown is independent, so the shares over
 * the threads change no float; they are taken as threads come free, so a thread that
 * loses its core leaves the shares still to come to the other (sim_team.h). */
static void sample_probe(tick_sim *t)
{
    const int n = t->n_trees, nc = sim_shares(n, t->threads);
    const int every = t->d.sc->wind_every > 1 ? t->d.sc->wind_every : 1;
    const bool first = !t->grid_read;
    const int j = (int)(t->tick % (uint32_t)every);
    /* this tick's share of the crowns in the locality order, and where it goes */
    const int r0 = first ? 0 : (int)((int64_t)n * j / every);
    const int r1 = first ? n : (int)((int64_t)n * (j + 1) / every);
    float *const dst = first ? t->vel_grid : t->vel_next;
    const int nr = sim_shares(r1 - r0, t->threads);
    const int threads = n > SIM_SHARE_MAX ? t->threads : 1;
    probe_job pj = { .t = t, .r0 = r0, .n = r1 - r0, .shares = nr, .dst = dst };
    sim_team_run(threads, nr, probe_share, &pj);
    if (first) {
        /* both buffers: the shares still to come of this step read the same grid */
        memcpy(t->vel_next, t->vel_grid, (size_t)n * 3 * sizeof(float));
    } else if (j == every - 1) {
        t->vel_next = t->vel_grid;
        t->vel_grid = dst;
    }
    sim_team_run(threads, nc, crown_share, t);
    t->grid_read = true;
}

/* The log-law profile alone (no grid): U(z) = U10 ln(z/z0) / ln(10/z0), z clamped below
 * at zmin (defaults z0 = 0.3 m, EN 1991-1-4 terrain III, and 5 m), plus the gust. */
static void sample_profile(tick_sim *t, const wind_inflow *in)
{
    const float z0 = in->z0_m > 0 ? in->z0_m : 0.3f, zmin = in->zmin_m > 0 ? in->zmin_m : 5.0f;
    const float u10 = in->u10_ms, *gust = in->gust;
    float cx = cosf(in->dir_rad), cy = sinf(in->dir_rad), l10 = logf(10.0f / z0);
    for (int k = 0; k < t->n_trees; k++) {
        float z = t->crown[3 * k + 2] < zmin ? zmin : t->crown[3 * k + 2];
        float u = u10 * logf(z / z0) / l10;
        t->vel[3 * k + 0] = u * cx + gust[0];
        t->vel[3 * k + 1] = u * cy + gust[1];
        t->vel[3 * k + 2] = gust[2];
    }
}

/* The scenario's force balls, for the next step (wind_add_ball). */
static void add_balls(tick_sim *t)
{
    for (int b = 0; b < t->n_balls && t->d.wind->add_ball; b++) {
        t->d.wind->add_ball(t->d.wind->ctx, &t->balls[b]);
    }
}

static int step_failed(const tick_sim *t, gale_err *err)
{
    return gale_errf(err, GALE_E_NUMERIC, "tick %u: wind step broke down (non-finite field)",
                     t->tick);
}

/* A step's figures into the tick's stats. */
static void step_stats(const tick_sim *t, const wind_step_stats *ws, tick_stats *local)
{
    local->wind_stepped = true;
    local->wind_iters = ws->iterations;
    local->wind_div = ws->div_after;
    local->wind_residual = ws->residual;
    /* the solve stops at max_iterations or once the residual is within 1/div_reduction of
     * the start (wind.h wind_desc) */
    local->wind_unconverged = t->d.wind->max_iterations > 0 &&
                              ws->iterations >= t->d.wind->max_iterations &&
                              ws->residual * (double)t->d.wind->div_reduction > 1.0;
}

/* A step's tick with the steps one step ahead: the step launched on the last step's tick
 * is taken and its field published to the samplers, and the next is launched from it
 * under this tick's inflow and balls, to run beside the ticks up to the next step's tick
 * (wind_worker.h). The crowns read the published field as ever (sample_probe), so its
 * part of their wind lags the inflow one step more than a step on its own tick would:
 * 4 ticks (67 ms) at a step every 4. The first tick launches and takes a step of its
 * own first, so the crowns start on a stepped field. */
static int step_ahead(tick_sim *t, const wind_inflow *in, int every, tick_stats *local,
                      gale_err *err)
{
    const tick_wind *wd = t->d.wind;
    const float dt_s = t->dt_s * (float)every;
    if (!t->launched) {
        wd->set_inflow(wd->ctx, in);
        add_balls(t);
        wind_worker_launch(t->worker, dt_s);
        t->step_inflow_stale = false;
    }
    wind_step_stats ws = { 0 };
    wind_join_times jt = { 0 };
    const int rc = wind_worker_join(t->worker, &ws, &jt);
    t->launched = false;
    if (rc) {
        return step_failed(t, err);
    }
    step_stats(t, &ws, local);
    const double p0 = mono_ms();
    if (wd->publish(wd->ctx)) {
        return gale_errf(err, GALE_E_NOMEM, "tick %u: no memory for the wind's copy", t->tick);
    }
    if (t->step_inflow_stale) {
        wd->set_inflow(wd->ctx, in);
        t->step_inflow_stale = false;
    }
    add_balls(t);
    wind_worker_launch(t->worker, dt_s);
    t->launched = true;
    local->wind_ms = jt.ms + (mono_ms() - p0);
    local->wind_wait_ms = jt.wait_ms;
    local->wind_step_ms = jt.step_ms;
    return 0;
}

/* CPU time of the calling thread [ms]. */
static double thread_cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

int tick_step(tick_sim *t, int16_t *qsnap, tick_stats *st, gale_err *err)
{
    tick_stats local = { 0 };
    const double c0 = thread_cpu_ms();
    double t0 = mono_ms();
    const scene *sc = t->d.sc;
    wind_inflow in;
    bool dirty;
    pthread_mutex_lock(&t->lock);
    in = t->inflow;
    dirty = t->inflow_dirty;
    t->inflow_dirty = false;
    pthread_mutex_unlock(&t->lock);
    if (atomic_exchange(&t->heal, 0)) {
        tick_heal(t);
    }

    /* 1. wind */
    if (t->d.wind) {
        const tick_wind *wd = t->d.wind;
        int every = sc->wind_every > 0 ? sc->wind_every : 1;
        const bool step_tick = t->tick % (uint32_t)every == 0;
        if (t->worker) {
            if (dirty) {
                /* the subgrid term follows the inflow at once, the grid at the next launch */
                wd->set_subgrid_inflow(wd->ctx, &in);
                t->step_inflow_stale = true;
            }
            const int rc = step_tick ? step_ahead(t, &in, every, &local, err) : 0;
            if (rc) {
                return rc;
            }
        } else {
            if (dirty) {
                wd->set_inflow(wd->ctx, &in);
            }
            if (step_tick) {
                add_balls(t);
                wind_step_stats ws = { 0 };
                double w0 = mono_ms();
                const int step_rc = wd->step(wd->ctx, t->dt_s * (float)every, &ws);
                local.wind_ms = mono_ms() - w0;
                local.wind_step_ms = local.wind_ms;
                if (step_rc) {
                    return step_failed(t, err);
                }
                step_stats(t, &ws, &local);
            }
        }
        /* 2. sample the wind at every crown, in the grid's locality order */
        const double s0 = mono_ms();
        if (t->probe) {
            sample_probe(t);
        } else {
            wd->sample_many(wd->ctx, t->n_trees, t->crown_ordered, t->vel_ordered);
            for (int i = 0; i < t->n_trees; i++) {
                memcpy(&t->vel[3 * (size_t)t->order[i]], &t->vel_ordered[3 * (size_t)i],
                       3 * sizeof(float));
            }
        }
        local.sample_ms = mono_ms() - s0;
    } else {
        const double s0 = mono_ms();
        sample_profile(t, &in);
        local.sample_ms = mono_ms() - s0;
    }

    /* 3. forces and the exact modal update (modal.h), quantised on snapshot ticks */
    const double m0 = mono_ms();
    modal_tick(t->m, t->vel, qsnap);

    /* 4. leaves: the shedding rate follows the wind speed at each crown */
    const double l0 = mono_ms();
    local.modal_ms = l0 - m0;
    t->n_leaves = 0;
    local.leaves_lost += leaf_shed_trees(&t->leaf, (uint32_t)t->n_trees, t->vel, t->slots, 0,
                                         t->tick, (double)t->dt_s, t->threads, t->leaf_scratch,
                                         t->leaves, t->d.max_leaves_per_tick, &t->n_leaves,
                                         &local.max_speed_ms);
    const double d0 = mono_ms();
    local.leaves_ms = d0 - l0;
    /* 5. storm damage from the new modal state (damage.h); stripped leaves fall too */
    if (t->dmg) {
        local.leaves_lost += damage_step(t->dmg, t->m, t->vel, t->tick, t->leaves,
                                         t->d.max_leaves_per_tick, &t->n_leaves);
    }
    local.leaves = t->n_leaves;
    t->tick++;
    const double t1 = mono_ms();
    local.damage_ms = t->dmg ? t1 - d0 : 0.0;
    local.ms = t1 - t0;
    local.cpu_ms = thread_cpu_ms() - c0;
    if (st) {
        *st = local;
    }
    return GALE_OK;
}

uint32_t tick_now(const tick_sim *t)
{
    return t->tick;
}

int tick_n_trees(const tick_sim *t)
{
    return t->n_trees;
}

int tick_stride(const tick_sim *t)
{
    return t->stride;
}

int tick_get_q(const tick_sim *t, int tree, float *q, int cap)
{
    float buf[256];
    uint32_t n = modal_get(t->m, (uint32_t)tree, buf, NULL);
    int k = (int)n < cap ? (int)n : cap;
    memcpy(q, buf, sizeof(float) * (size_t)k);
    return k;
}

int tick_leaves(const tick_sim *t, const leaf_seed **out)
{
    *out = t->leaves;
    return t->n_leaves;
}

const float *tick_crown_wind(const tick_sim *t)
{
    return t->vel;
}

const damage_sim *tick_damage(const tick_sim *t)
{
    return t->dmg;
}

damage_counts *tick_damage_counts(tick_sim *t)
{
    return t->dmg ? damage_get_counts(t->dmg) : NULL;
}

void tick_request_heal(tick_sim *t)
{
    atomic_store(&t->heal, 1);
}

void tick_heal(tick_sim *t)
{
    if (t->dmg) {
        damage_heal(t->dmg, t->m);
    }
}
