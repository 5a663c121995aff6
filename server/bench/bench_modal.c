/* gale-bench modal: the per-tick cost of the batch modal update (server/sim/modal.c) for
 * many trees: wind sampled at each tree from the real wind field (as the server's tick
 * does: the grid read at each tree's stencil, wind_probe_sample, on the tick's threads in
 * shares over the ticks between wind steps, switched over on the last, server/sim/tick.c;
 * on a
 * grid of scene-scale cells, 2 m by default, over the trees' 2 km square, stepped by the
 * real solver every few ticks under a gusty inflow so the field evolves), forces
 * f_i = |v| v.p_i in the tree frame, exact update, quantisation into the snapshot buffer,
 * leaf shedding at each tree's wind speed (leaf_shed_trees), storm damage with --damage
 * (damage_step, the stripped leaves in the room the shed ones leave under the server's
 * cap, as tick.c orders them) and the snapshot's DELTA encoding
 * (wire_encode_delta_lanes), all on the tick's threads: all timed as the tick.
 * Prints JSON; medians over the ticks, with
 * the tick's byte model, the memory floor it implies and the machine's triad bandwidth
 * measured in the same run, before and after the ticks (bench_triad.c). The wind step
 * itself is timed apart (and in gale-bench wind). --damage both runs the tick twice on each tick's wind, without and
 * with storm damage (damage.h) on separate states, alternating which goes first, and
 * prints both and their ratio (SERVER.md "Storm damage on the tick"). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mono.h"
#include "bench.h"
#include "bake.h"
#include "big_alloc.h"
#include "damage.h"
#include "leaf.h"
#include "lsystem.h"
#include "modal.h"
#include "quant_steps.h"
#include "sim_lanes.h"
#include "sim_team.h"
#include "species.h"
#include "wind.h"
#include "wire.h"


/* CPU time of the whole process (all threads) [ms]: on a loaded machine the wall time
 * counts other programs' turns, the CPU time only this one's work (and spinning). */
static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Orders tree positions (x, y, z) by their 16 m column: row y first, then x. */
static int cmp_cell(const void *a, const void *b)
{
    const float *p = a, *q = b;
    long ka = (long)(p[1] / 16.0f) * 4096 + (long)(p[0] / 16.0f);
    long kb = (long)(q[1] / 16.0f) * 4096 + (long)(q[0] / 16.0f);
    if (ka != kb) {
        return (ka > kb) - (ka < kb);
    }
    return (p[0] > q[0]) - (p[0] < q[0]); /* ties by x: the order is fully defined */
}

/* Bytes one tick moves per tree at least, array by array (each read or written once per
 * pass; the species constants and the padding lanes' coefficients are a few kB and stay
 * in cache, so they are not counted; write-allocate is not counted, as in the triad).
 * The grid lines the sampling reads are counted apart, per tick (wind_probe_lines): a
 * 2 m grid over 2 km is ~100 MB, larger than the caches and rewritten by every step.
 * modal.c keeps each tree's q and q' as 2 x pad floats, pad the modes rounded up to its
 * 16-lane groups (MODE_PAD):
 *   sampling (wind_probe_sample, each tree once in `every` ticks): the stencil 48 read, wind 12
 *   written, amortised over the ticks (the grid's lines apart, as above);
 *   update (modal_tick): wind 12, cos/sin of the yaw 8, species index 1 and the state
 *   8 pad read; the state 8 pad written, and with a snapshot the int16 row 2 modes. */
typedef struct modal_bytes {
    double read, written; /* per tree per tick */
} modal_bytes;

static modal_bytes modal_tree_bytes(int n_modes, int sample_every, bool snapshot)
{
    const double pad = (double)((n_modes + 15) / 16 * 16);
    modal_bytes b = { 12.0 + 8.0 + 1.0 + 8.0 * pad, 8.0 * pad };
    if (snapshot) {
        b.written += 2.0 * n_modes;
    }
    if (sample_every > 0) {
        b.read += 48.0 / sample_every;
        b.written += 12.0 / sample_every;
    }
    return b;
}

/* The tick's bytes at least: the trees' (tb), the previous snapshot the encoder reads (2
 * bytes a mode), the DELTA it writes (enc_per_tick) and the grid's lines (grid_bytes). */
static double tick_model_bytes(const modal_bytes *tb, int n_trees, int n_modes,
                               double enc_per_tick, double grid_bytes)
{
    return (tb->read + tb->written + 2.0 * n_modes) * n_trees + enc_per_tick + grid_bytes;
}

static double pct(double *v, int n, double p)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    int i = (int)(p * (n - 1) + 0.5);
    return v[i];
}

/* The oak as --damage drives it: baked at the bench's mode count, its quantisation steps,
 * streamlining and damage table, for every species, so the wind loads the trees as the
 * server's would and a Cat 4 breaks branches and trees. */
typedef struct damage_oak {
    asset a;
    float qstep[WIRE_MAX_MODES];
    drag_law drag;
    damage_table t;
} damage_oak;

static int damage_oak_init(damage_oak *o, int n_modes, gale_err *err)
{
    memset(o, 0, sizeof *o);
    species sp;
    skeleton sk;
    memset(&sk, 0, sizeof sk);
    int rc = species_load(GALE_SOURCE_DIR "/configs/species/oak.json", &sp, err);
    rc = rc ? rc : lsystem_generate(&sp.gen, &sk, err);
    rc = rc ? rc : bake_run(&sk, &sp, &(bake_desc){ .n_modes = n_modes }, &o->a, NULL, err);
    rc = rc ? rc : quant_steps_derive(&o->a, 0, o->qstep, err);
    rc = rc ? rc : damage_table_build(&o->a, sp.E_pa, sp.drag_c, &sp.damage, &o->t, err);
    o->drag = sp.drag;
    skeleton_fini(&sk);
    return rc;
}

static void damage_oak_fini(damage_oak *o)
{
    damage_table_fini(&o->t);
    asset_fini(&o->a);
}

/* One simulation the bench times: A (no damage) or B (damage each tick), each
 * with its own state, snapshot buffers and encoder output, driven by the same wind. */
typedef struct variant {
    bool damage;
    modal *m;
    damage_sim *sim;
    int16_t *snap, *prev;
    uint8_t *enc;
    leaf_seed *leaves, *leaf_scratch; /* [LEAF_CAP], [leaf_scratch_seeds(threads, LEAF_CAP)] */
    double *t_total, *t_cpu, *t_sample, *t_modal, *t_damage, *t_leaf, *t_enc, *t_nosnap;
    bool *read; /* [ticks]: the tick read the grid (a share of the trees) */
    long n_shed, enc_bytes;
} variant;

/* The leaves a tick keeps, shed and stripped together, as the server's tick keeps them
 * (tick_desc.max_leaves_per_tick's default) */
enum { LEAF_CAP = DAMAGE_MAX_LEAVES };

static int variant_init(variant *v, bool damage, const modal_desc *md, int n_modes, int ticks,
                        size_t enc_cap, const damage_oak *oak, gale_err *err)
{
    memset(v, 0, sizeof *v);
    v->damage = damage;
    const size_t n = md->n_trees, nt = (size_t)ticks;
    v->m = modal_create(md, err);
    if (!v->m) {
        return GALE_E_NOMEM;
    }
    if (damage) {
        const damage_table *tables[WIRE_MAX_SPECIES];
        for (uint32_t k = 0; k < md->n_species; k++) {
            tables[k] = &oak->t;
        }
        v->sim = damage_create(&(damage_desc){ .n_trees = md->n_trees,
                                               .n_species = md->n_species,
                                               .table = tables,
                                               .tree_species = md->tree_species,
                                               .tree_yaw_rad = md->tree_yaw_rad,
                                               .seed = 1,
                                               .dt_s = 1.0 / 60,
                                               .max_leaves = LEAF_CAP,
                                               .n_threads = md->n_threads },
                               err);
        if (!v->sim) {
            return GALE_E_NOMEM;
        }
    }
    v->snap = big_alloc(n * (size_t)n_modes * sizeof(int16_t));
    v->prev = big_alloc(n * (size_t)n_modes * sizeof(int16_t));
    v->enc = malloc(enc_cap);
    v->leaves = malloc(LEAF_CAP * sizeof *v->leaves);
    const size_t scratch_seeds = leaf_scratch_seeds(md->n_threads, LEAF_CAP);
    v->leaf_scratch = malloc((scratch_seeds > 0 ? scratch_seeds : 1) * sizeof *v->leaf_scratch);
    double **t[] = { &v->t_total, &v->t_cpu, &v->t_sample, &v->t_modal,
                     &v->t_damage, &v->t_leaf, &v->t_enc, &v->t_nosnap };
    v->read = calloc(nt, sizeof *v->read);
    bool ok = v->snap && v->prev && v->enc && v->leaves && v->leaf_scratch && v->read;
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        *t[i] = calloc(nt, sizeof(double));
        ok = ok && *t[i];
    }
    if (!ok) {
        gale_errf(err, GALE_E_NOMEM, "no memory for %zu trees", n);
        return GALE_E_NOMEM;
    }
    return 0;
}

static void variant_fini(variant *v)
{
    damage_destroy(v->sim);
    modal_destroy(v->m);
    free(v->snap);
    free(v->prev);
    free(v->enc);
    free(v->leaves);
    free(v->leaf_scratch);
    free(v->read);
    double *t[] = { v->t_total, v->t_cpu, v->t_sample, v->t_modal,
                    v->t_damage, v->t_leaf, v->t_enc, v->t_nosnap };
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        free(t[i]);
    }
}

/* What one tick of a variant needs from the run. */
typedef struct tick_in {
    wind_grid *wg;
    const wind_probe *probe; /* the trees' stencils */
    int n_trees;
    const float *pos;
    float *wind;      /* the trees' wind the ticks use */
    float *wind_next; /* the last step's, read share by share */
    const wire_scene *wsc;
    const uint8_t *nm;
    int n_modes;
    size_t enc_cap;
    const leaf_desc *ld;
    uint32_t slots;
    int threads;
    wire_lanes lanes; /* the encoder's, on the tick's threads */
} tick_in;

/* The grid at trees [i0, i1) into dst, in shares over the tick's threads
 * (server/sim/tick.c). */
typedef struct grid_job {
    const tick_in *in;
    int i0, n, shares;
    float *dst;
} grid_job;

static void grid_share(void *ctx, int c)
{
    const grid_job *g = ctx;
    int a, b;
    sim_share(g->n, g->shares, c, &a, &b);
    wind_probe_sample(g->in->wg, g->in->probe, g->i0 + a, g->i0 + b, g->dst);
}

static void sample_grid(const tick_in *in, int i0, int i1, float *dst)
{
    grid_job g = { .in = in, .i0 = i0, .n = i1 - i0, .shares = sim_shares(i1 - i0, in->threads),
                   .dst = dst };
    sim_team_run(i1 - i0 > SIM_SHARE_MAX ? in->threads : 1, g.shares, grid_share, &g);
}

/* Tick k (k < 0: warm-up, not recorded) of v: sampling (the grid at trees [r0, r1) into
 * dst), update, leaf shedding, damage, DELTA encoding, timed as the tick; then an update
 * without quantisation. */
static int variant_tick(variant *v, const tick_in *in, int k, int r0, int r1, float *dst,
                        gale_err *err)
{
    const bool read_grid = r1 > r0;
    const size_t n = (size_t)in->n_trees;
    /* the last snapshot becomes the previous one and the update writes over the one before
     * it, as the server turns its snapshot buffers (server/serve/srv_int.h qbuf): no copy,
     * which would bring both into the cache ahead of the tick */
    int16_t *const older = v->prev;
    v->prev = v->snap;
    v->snap = older;
    double c0 = cpu_ms();
    double t0 = mono_ms();
    if (read_grid) {
        sample_grid(in, r0, r1, dst);
    }
    double t1 = mono_ms();
    modal_tick(v->m, in->wind, v->snap);
    double t1d = mono_ms();
    /* leaves shed, then storm damage with the room they leave (server/sim/tick.c) */
    int nl = 0;
    const int shed_lost = leaf_shed_trees(in->ld, (uint32_t)n, in->wind, NULL, in->slots,
                                          (uint32_t)(k + 20), 1.0 / 60, in->threads,
                                          v->leaf_scratch, v->leaves, LEAF_CAP, &nl, NULL);
    const int n_shed = nl + shed_lost;
    double t2 = mono_ms();
    if (v->sim) {
        damage_step(v->sim, v->m, in->wind, (uint32_t)(k + 20), v->leaves, LEAF_CAP, &nl);
    }
    double t2l = mono_ms();
    size_t len = 0;
    wire_header hdr = { .tick = (uint32_t)(k + 20) };
    const wire_state cur_st = { (uint32_t)n, (uint32_t)in->n_modes, in->nm, v->snap };
    const wire_state prev_st = { (uint32_t)n, (uint32_t)in->n_modes, in->nm, v->prev };
    if (wire_encode_delta_lanes(&hdr, (uint32_t)(k + 21), in->wsc, &cur_st, &prev_st, NULL,
                                &in->lanes, v->enc, in->enc_cap, &len, err) != 0) {
        return GALE_E_RANGE;
    }
    double t2e = mono_ms();
    double c1 = cpu_ms();
    /* A tick between snapshots: the same update without quantisation. */
    double t3s = mono_ms();
    modal_tick(v->m, in->wind, NULL);
    double t3 = mono_ms();
    if (k >= 0) {
        v->t_sample[k] = t1 - t0;
        v->read[k] = read_grid;
        v->t_modal[k] = (t1d - t1) + (t2l - t2);
        v->t_damage[k] = t2l - t2;
        v->t_leaf[k] = t2 - t1d;
        v->t_enc[k] = t2e - t2l;
        v->n_shed += n_shed;
        v->enc_bytes += (long)len;
        v->t_total[k] = t2e - t0;
        v->t_cpu[k] = c1 - c0;
        v->t_nosnap[k] = t3 - t3s;
    }
    return 0;
}

/* Median of v[n] without reordering it. */
static double median_of(const double *v, int n, double *scratch)
{
    memcpy(scratch, v, sizeof(double) * (size_t)n);
    return pct(scratch, n, 0.5);
}

/* The bytes a damage step reads at least: each due tree's q row and its wind (its record
 * and the species' tables left out, so the floor stays a floor). */
static double damage_model_bytes(int n_trees, int n_modes)
{
    return (double)n_trees / DAMAGE_EVERY * (4.0 * n_modes + 12.0);
}

/* Prints the figures of variant v as JSON members (no braces). */
static void print_variant(const variant *v, int ticks, int n_trees, int n_modes,
                          const modal_bytes *tb, double grid_bytes, double gbs, double *scratch)
{
    double med_t = median_of(v->t_total, ticks, scratch);
    double p95_t = (memcpy(scratch, v->t_total, sizeof(double) * (size_t)ticks),
                    pct(scratch, ticks, 0.95));
    double p99_t = (memcpy(scratch, v->t_total, sizeof(double) * (size_t)ticks),
                    pct(scratch, ticks, 0.99));
    double enc_per_tick = (double)v->enc_bytes / ticks;
    double tick_bytes = tick_model_bytes(tb, n_trees, n_modes, enc_per_tick, grid_bytes) +
                        (v->damage ? damage_model_bytes(n_trees, n_modes) : 0.0);
    double tick_gbs = med_t > 0.0 ? tick_bytes / (med_t * 1e-3) / 1e9 : 0.0;
    double floor_ms = gbs > 0.0 ? tick_bytes / (gbs * 1e9) * 1e3 : 0.0;
    printf("\"damage\":%s,\"tick_ms_median\":%.3f,\"tick_ms_p95\":%.3f,\"tick_ms_p99\":%.3f,"
           "\"cpu_ms_per_tick_median\":%.3f,\"sample_ms_median\":%.3f,"
           "\"update_quantise_ms_median\":%.3f,\"damage_ms_median\":%.3f,"
           "\"leaf_shed_ms_median\":%.3f,\"encode_ms_median\":%.3f,"
           "\"update_only_ms_median\":%.3f,\"ns_per_tree_mode\":%.3f,"
           "\"bandwidth_fraction\":%.3f,\"memory_floor_ms\":%.3f,\"tick_over_floor\":%.2f,"
           "\"leaves_shed_per_tick\":%.1f",
           v->damage ? "true" : "false", med_t, p95_t, p99_t, median_of(v->t_cpu, ticks, scratch),
           median_of(v->t_sample, ticks, scratch), median_of(v->t_modal, ticks, scratch),
           median_of(v->t_damage, ticks, scratch), median_of(v->t_leaf, ticks, scratch),
           median_of(v->t_enc, ticks, scratch), median_of(v->t_nosnap, ticks, scratch),
           med_t * 1e6 / ((double)n_trees * n_modes), gbs > 0.0 ? tick_gbs / gbs : 0.0,
           floor_ms, floor_ms > 0.0 ? med_t / floor_ms : 0.0, (double)v->n_shed / ticks);
    if (v->sim) {
        damage_counts *c = damage_get_counts(v->sim);
        printf(",\"branches_broken\":%llu,\"trees_snapped\":%llu,\"trees_uprooted\":%llu,"
               "\"leaf_area_left\":%.3f",
               (unsigned long long)atomic_load(&c->branches),
               (unsigned long long)atomic_load(&c->snapped),
               (unsigned long long)atomic_load(&c->uprooted), atomic_load(&c->leaf_area));
    }
}

int bench_modal(int argc, char **argv)
{
    int n_trees = 100000, n_modes = 32, ticks = 300, n_species = 3, threads = 2, every = 4;
    float cell_m = 2.0f, u10_ms = 25.0f;
    bool json = false;
    /* --damage: off (A only), on (B only), both (A and B alternating, tick by tick) */
    enum { DMG_OFF, DMG_ON, DMG_BOTH } dmg = DMG_OFF;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--trees") == 0 && i + 1 < argc) {
            n_trees = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--modes") == 0 && i + 1 < argc) {
            n_modes = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--ticks") == 0 && i + 1 < argc) {
            ticks = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--species") == 0 && i + 1 < argc) {
            n_species = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            threads = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--cell-m") == 0 && i + 1 < argc) {
            cell_m = (float)atof(argv[++i]);
        } else if (strcmp(argv[i], "--wind-every") == 0 && i + 1 < argc) {
            every = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--u10") == 0 && i + 1 < argc) {
            u10_ms = (float)atof(argv[++i]);
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if (strcmp(argv[i], "--damage") == 0) {
            const char *w = i + 1 < argc ? argv[i + 1] : "";
            if (strcmp(w, "off") == 0 || strcmp(w, "on") == 0 || strcmp(w, "both") == 0) {
                i++;
                dmg = w[1] == 'f' ? DMG_OFF : w[1] == 'n' ? DMG_ON : DMG_BOTH;
            } else {
                dmg = DMG_ON;
            }
        } else {
            return bench_usage(argv[i], "usage: gale-bench modal [--trees N] [--modes M] [--species S] "
                                        "[--ticks K] [--threads T] [--cell-m 2] [--wind-every 4] "
                                        "[--u10 25] [--damage [off|on|both]] [--json]\n"
                                        "  --u10 MS       mean inflow at 10 m [m/s] (Cat 4: 62)\n"
                                        "  --damage       storm damage each tick (after the leaves), every "
                                        "species the shipped oak\n"
                                        "                 (its modes, drag and damage table); both: "
                                        "the tick with and\n"
                                        "                 without it on the same wind, alternating, "
                                        "and their ratio\n");
        }
    }
    if (n_trees < 1 || n_trees > (int)WIRE_MAX_TREES || n_modes < 1 ||
        n_modes > (int)WIRE_MAX_MODES || ticks < 10 || n_species < 1 ||
        n_species > (int)WIRE_MAX_SPECIES || threads < 1 || threads > 64 ||
        !(cell_m >= 1.0f && cell_m <= 64.0f) || every < 1 || every > 1000 ||
        !(u10_ms >= 0.0f && u10_ms <= 100.0f)) {
        fprintf(stderr, "gale-bench modal: --trees 1..%u, --modes 1..%u, --species 1..%u, "
                        "--ticks >= 10, --threads 1..64, --cell-m 1..64, --wind-every 1..1000, "
                        "--u10 0..100\n",
                WIRE_MAX_TREES, WIRE_MAX_MODES, WIRE_MAX_SPECIES);
        return 2;
    }
    uint64_t s = 12345;
#define RND() ((s = s * 6364136223846793005ull + 1442695040888963407ull), (float)(s >> 40) / 16777216.0f)
    float *omega = malloc(sizeof(float) * (size_t)n_species * (size_t)n_modes);
    float *gamma = malloc(sizeof(float) * (size_t)n_species * (size_t)n_modes);
    float *p = malloc(sizeof(float) * 3 * (size_t)n_species * (size_t)n_modes);
    float *step = malloc(sizeof(float) * (size_t)n_species * (size_t)n_modes);
    modal_species *sp = calloc((size_t)n_species, sizeof *sp);
    drag_law *sp_drag = calloc((size_t)n_species, sizeof *sp_drag);
    uint8_t *ts = malloc((size_t)n_trees);
    float *yaw = malloc(sizeof(float) * (size_t)n_trees);
    float *pos = malloc(sizeof(float) * 3 * (size_t)n_trees);
    float *wind = malloc(sizeof(float) * 3 * (size_t)n_trees);
    float *wind_next = malloc(sizeof(float) * 3 * (size_t)n_trees);
    double *t_wind = calloc((size_t)ticks, sizeof(double));
    double *scratch = malloc(sizeof(double) * (size_t)ticks);
    double *ratio = malloc(sizeof(double) * (size_t)ticks);
    uint8_t *nm = malloc((size_t)n_trees);
    const size_t enc_cap = wire_state_bound((uint32_t)n_trees, (uint32_t)n_modes,
                                            (uint32_t)n_species);
    if (!omega || !gamma || !p || !step || !sp || !sp_drag || !ts || !yaw || !pos || !wind || !wind_next ||
        !t_wind || !scratch || !ratio || !nm) {
        fprintf(stderr, "gale-bench modal: out of memory\n");
        return 1;
    }
    gale_err err;
    damage_oak oak;
    const bool with_oak = dmg != DMG_OFF;
    if (with_oak && damage_oak_init(&oak, n_modes, &err)) {
        fprintf(stderr, "gale-bench modal: --damage: oak: %s\n", err.msg);
        return 1;
    }
    for (int k = 0; k < n_species; k++) {
        for (int i = 0; i < n_modes; i++) {
            int j = k * n_modes + i;
            /* First modes 0.3-2 Hz rising to tens of Hz (PHYSICS.md "Modes"). */
            omega[j] = 6.2831853f * (0.3f + 0.7f * (float)i * (float)i / 4.0f + RND());
            gamma[j] = 0.1f + 1e-3f * omega[j] * omega[j] * 0.01f;
            for (int c = 0; c < 3; c++) {
                p[3 * j + c] = 0.01f * (RND() - 0.5f);
            }
            step[j] = 1e-4f;
        }
        sp[k] = (modal_species){ (uint32_t)n_modes, omega + k * n_modes, gamma + k * n_modes,
                                 p + 3 * k * n_modes, step + k * n_modes };
        /* the shipped species' streamlining in turn (configs/species: oak -0.85, palm and
           pine -0.75 from 10 m/s, held above 25), so the force scale costs what it costs
           the server's trees */
        sp_drag[k] = (drag_law){ .vogel_b = k % 3 == 0 ? -0.85f : -0.75f, .u0_ms = 10.0f,
                                 .fit_max_ms = 25.0f, .hold_above_fit = 1 };
        if (with_oak) {
            sp[k] = (modal_species){ (uint32_t)n_modes, oak.a.omega, oak.a.gamma,
                                     oak.a.wind_basis, oak.qstep };
            sp_drag[k] = oak.drag;
        }
    }
    const float side = 2000.0f;
    for (int t = 0; t < n_trees; t++) {
        ts[t] = (uint8_t)(t % n_species);
        yaw[t] = 6.2831853f * RND();
        pos[3 * t] = side * RND();
        pos[3 * t + 1] = side * RND();
        pos[3 * t + 2] = 5.0f + 10.0f * RND();
    }
    /* Trees are static: stored once in the order of the 16 m wind cells they stand in
     * (rows of y, then x), as a scene loader would keep them, so consecutive samples
     * read neighbouring grid lines instead of missing the cache at random. */
    qsort(pos, (size_t)n_trees, 3 * sizeof(float), cmp_cell);
    const modal_desc md = { .n_trees = (uint32_t)n_trees, .n_species = (uint32_t)n_species,
                            .species = sp, .tree_species = ts, .tree_yaw_rad = yaw,
                            .species_drag = sp_drag,
                            .dt_s = 1.0 / 60, .n_threads = threads };
    variant var[2];
    int n_var = 0;
    if (dmg != DMG_ON) {
        if (variant_init(&var[n_var++], false, &md, n_modes, ticks, enc_cap, &oak, &err)) {
            fprintf(stderr, "gale-bench modal: %s\n", err.msg);
            return 1;
        }
    }
    if (dmg != DMG_OFF) {
        if (variant_init(&var[n_var++], true, &md, n_modes, ticks, enc_cap, &oak, &err)) {
            fprintf(stderr, "gale-bench modal: --damage: %s\n", err.msg);
            return 1;
        }
    }
    /* cells of cell_m over the 2 km square the trees stand in, 8 cells deep (at 2 m the
       16 m the crowns reach; the grid is capped at the scene's 2^24 cells) */
    const int gxy = (int)ceilf(side / cell_m);
    const int gz = 8;
    if ((double)gxy * gxy * gz > (double)(1 << 24)) {
        fprintf(stderr, "gale-bench modal: --cell-m %g: %d x %d x %d cells, expected at most "
                        "2^24\n", (double)cell_m, gxy, gxy, gz);
        return 2;
    }
    wind_grid *wg = wind_create(&(wind_desc){ .nx = gxy, .ny = gxy, .nz = gz, .cell_m = cell_m,
                                              .threads = threads, .seed = 7 },
                                &err);
    if (!wg) {
        fprintf(stderr, "gale-bench modal: wind: %s\n", err.msg);
        return 1;
    }
    /* gusts of ±10 % of the mean (±2.5 m/s at the default 25 m/s) */
    const float gust_ms = 0.2f * u10_ms;
    wind_set_inflow(wg, &(wind_inflow){ .dir_rad = 0.3f, .u10_ms = u10_ms });
    wind_fill_inflow(wg);
    for (int k = 0; k < 3; k++) {
        wind_set_inflow(wg, &(wind_inflow){ .dir_rad = 0.3f, .u10_ms = u10_ms,
                                            .gust = { gust_ms * (RND() - 0.5f),
                                                      gust_ms * (RND() - 0.5f), 0 } });
        if (wind_step(wg, 1.0f / 60, NULL) != 0) {
            fprintf(stderr, "gale-bench modal: wind step failed\n");
            return 1;
        }
    }
    /* the snapshot as the server encodes it: every tree, all its modes, 1e-4 steps */
    wire_scene wsc = { .n_trees = (uint32_t)n_trees, .n_species = (uint32_t)n_species,
                       .species = ts };
    for (int k = 0; k < n_species; k++) {
        wsc.n_modes[k] = (uint8_t)n_modes;
        for (int i = 0; i < n_modes; i++) {
            wsc.step[k][i] = with_oak ? oak.qstep[i] : 1e-4f;
        }
    }
    memset(nm, n_modes, (size_t)n_trees);
    const leaf_desc ld = { .rate_hz = 0.002f, .calm_ms = 3.0f, .ref_ms = 20.0f, .seed = 11 };
    wind_probe *probe = wind_probe_create(wg, n_trees, pos, &err);
    if (!probe) {
        fprintf(stderr, "gale-bench modal: %s\n", err.msg);
        return 1;
    }
    /* the grid lines each tick's share of the trees reads (the shares of the tick loop
       below), averaged over the shares: the grid's bytes a tick moves at least */
    double grid_bytes = 0.0;
    for (int phase = 0; phase < every; phase++) {
        size_t lines = 0;
        if (wind_probe_lines(wg, probe, (int)((int64_t)n_trees * phase / every),
                             (int)((int64_t)n_trees * (phase + 1) / every), &lines, &err)) {
            fprintf(stderr, "gale-bench modal: %s\n", err.msg);
            return 1;
        }
        grid_bytes += 64.0 * (double)lines / every;
    }
    tick_in in = { .wg = wg, .probe = probe, .n_trees = n_trees, .pos = pos, .wind = wind,
                         .wind_next = wind_next, .wsc = &wsc,
                         .nm = nm, .n_modes = n_modes, .enc_cap = enc_cap, .ld = &ld,
                         .slots = 1500 /* leaf slots per tree: the shipped species' 1500-5300 */,
                         .threads = threads, .lanes = sim_lanes(threads) };
    /* With the oak, every tree starts at its static pose under the wind at its crown
     * (damage_static_q, streamlined as modal_tick drives it), so the ticks time a stand
     * swaying about its mean, not the overshoot of a load switched on at once (which
     * would throw the whole stand over in the first second of a Cat 4). */
    if (with_oak) {
        float q0[WIRE_MAX_MODES + DAMAGE_RES_COLS] = { 0 }, qd0[WIRE_MAX_MODES] = { 0 };
        sample_grid(&in, 0, n_trees, in.wind);
        for (int t = 0; t < n_trees; t++) {
            const float *w = &wind[3 * t];
            double u = sqrt((double)(w[0] * w[0] + w[1] * w[1]));
            double az = atan2((double)w[1], (double)w[0]) - (double)yaw[t];
            damage_static_q(&oak.a, u, az, q0);
            const float k = drag_law_scale(&oak.drag, (float)u);
            for (int i = 0; i < n_modes; i++) {
                q0[i] *= k;
            }
            for (int j = 0; j < n_var; j++) {
                modal_set(var[j].m, (uint32_t)t, q0, qd0);
            }
        }
    }
    /* The machine's bandwidth on the threads the ticks use: a guest's memory speed drifts
     * from minute to minute (one run read 51 GB/s where the runs beside it read 34-36; on
     * huge pages readings of 34-39 and 55-67 alternate within a minute), so a reading
     * before the ticks can be another machine's than the ticks ran on. Read on either side
     * of the ticks, and in 8 bursts among them (a triad kept open, 3 passes a burst,
     * between two ticks): the floor is taken from the bursts' median, and their spread is
     * said beside it when it passes 10 %. */
    const double gbs_before = bench_triad_gb_s(threads);
    enum { BURSTS_MAX = 16 };
    double bursts[BURSTS_MAX];
    int n_bursts = 0;
    const int burst_every = ticks >= 8 ? ticks / 8 : 1;
    bench_triad during;
    const bool during_ok = bench_triad_open(&during, threads, (size_t)3 << 27) == 0;
    for (int k = -20; k < ticks; k++) { /* 20 warm-up ticks */
        double tw = 0.0;
        const bool stepped = (k + 20) % every == 0;
        if (stepped) { /* the field evolves as the scene's grid would */
            wind_set_inflow(wg, &(wind_inflow){ .dir_rad = 0.3f, .u10_ms = u10_ms,
                                                .gust = { gust_ms * (RND() - 0.5f),
                                                          gust_ms * (RND() - 0.5f), 0 } });
            double w0 = mono_ms();
            if (wind_step(wg, (float)every / 60.0f, NULL) != 0) {
                fprintf(stderr, "gale-bench modal: wind step failed\n");
                return 1;
            }
            tw = mono_ms() - w0;
        }
        /* the grid read as the server's tick reads it: whole on the first tick, else an
         * every-th of the trees on the step's tick and on each of the every - 1 after it
         * into the next buffer, switched on the last */
        const int phase = (k + 20) % every;
        int r0 = 0, r1 = n_trees;
        float *dst = in.wind;
        if (k > -20) {
            r0 = (int)((int64_t)n_trees * phase / every);
            r1 = (int)((int64_t)n_trees * (phase + 1) / every);
            dst = in.wind_next;
        }
        /* A then B on even ticks, B then A on odd: neither always runs on warm caches or
         * in the same share of another program's turn */
        for (int j = 0; j < n_var; j++) {
            variant *v = &var[(k & 1) && n_var == 2 ? 1 - j : j];
            /* with two variants the second reads the grid too: the same work, timed */
            if (variant_tick(v, &in, k, r0, r1, dst, &err)) {
                fprintf(stderr, "gale-bench modal: encode: %s\n", err.msg);
                return 1;
            }
        }
        if (k == -20) {
            memcpy(in.wind_next, in.wind, sizeof(float) * 3 * (size_t)n_trees);
        }
        if (dst == in.wind_next && phase == every - 1) {
            in.wind_next = in.wind;
            in.wind = dst;
        }
        if (k >= 0) {
            t_wind[k] = tw;
        }
        if (k >= 0 && during_ok && k % burst_every == burst_every - 1 && n_bursts < BURSTS_MAX) {
            bursts[n_bursts++] = bench_triad_burst(&during, 3);
        }
    }
    bench_triad_close(&during);
    /* the tick's arrays on huge pages, as the kernel granted them (big_alloc) */
    const long long huge_bytes = big_alloc_huge_bytes();
    const double gbs_after = bench_triad_gb_s(threads);
    double burst_lo = 0.0, burst_med = 0.0, burst_hi = 0.0;
    if (n_bursts > 0) {
        qsort(bursts, (size_t)n_bursts, sizeof *bursts, cmp_double);
        burst_lo = bursts[0];
        burst_hi = bursts[n_bursts - 1];
        burst_med = n_bursts % 2 ? bursts[n_bursts / 2]
                                 : 0.5 * (bursts[n_bursts / 2 - 1] + bursts[n_bursts / 2]);
    }
    /* without bursts (no memory for them), the mean of the readings either side */
    const double gbs = burst_med > 0.0 ? burst_med
                       : gbs_before > 0.0 && gbs_after > 0.0 ? 0.5 * (gbs_before + gbs_after)
                                                             : 0.0;
    if (burst_med > 0.0 && burst_hi - burst_lo > 0.1 * burst_med) {
        fprintf(stderr,
                "gale-bench modal: the machine's triad read %.2f to %.2f GB/s in %d bursts "
                "among the ticks (%.2f before them, %.2f after): the memory floor (from the "
                "bursts' median, %.2f) is uncertain by %.0f %%\n",
                burst_lo, burst_hi, n_bursts, gbs_before, gbs_after, gbs,
                50.0 * (burst_hi - burst_lo) / gbs);
    } else if (burst_med <= 0.0 && gbs > 0.0 && fabs(gbs_after - gbs_before) > 0.1 * gbs) {
        fprintf(stderr,
                "gale-bench modal: the machine's triad moved from %.2f GB/s before the ticks "
                "to %.2f after: the memory floor (from their mean, %.2f) is uncertain by "
                "%.0f %%\n",
                gbs_before, gbs_after, gbs, 50.0 * fabs(gbs_after - gbs_before) / gbs);
    }
    double wind_sum = 0.0;
    for (int k = 0; k < ticks; k++) {
        wind_sum += t_wind[k];
    }
    double load[3] = { 0 };
    FILE *la = fopen("/proc/loadavg", "r");
    if (la) {
        if (fscanf(la, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) {
            load[0] = -1;
        }
        fclose(la);
    }
    /* the tick (sampling, update, quantisation) and the update between snapshots */
    const modal_bytes tb = modal_tree_bytes(n_modes, every, true);
    const modal_bytes ub = modal_tree_bytes(n_modes, 0, false);
    if (n_var == 2) {
        /* B over A tick by tick (the same wind, run back to back), and of the medians */
        for (int k = 0; k < ticks; k++) {
            ratio[k] = var[0].t_total[k] > 0.0 ? var[1].t_total[k] / var[0].t_total[k] : 0.0;
        }
        double crit_snap = 0.0, crit_up = 0.0, crit_b = 0.0;
        damage_critical_speeds(&oak.a, &oak.t, &oak.drag, &crit_snap, &crit_up, &crit_b);
        double r_med = pct(ratio, ticks, 0.5), r_p95 = pct(ratio, ticks, 0.95);
        double a_med = median_of(var[0].t_total, ticks, scratch);
        double b_med = median_of(var[1].t_total, ticks, scratch);
        double a_cpu = median_of(var[0].t_cpu, ticks, scratch);
        double b_cpu = median_of(var[1].t_cpu, ticks, scratch);
        if (json) {
            printf("{\"bench\":\"modal\",\"damage\":\"both\",\"trees\":%d,\"modes\":%d,"
                   "\"species\":%d,\"threads\":%d,\"ticks\":%d,\"u10_ms\":%.1f,"
                   "\"modal_species\":\"configs/species/oak.json baked\","
                   "\"oak_branches\":%u,\"oak_critical_mean_ms\":{\"first_branch\":%.1f,\"snap\":%.1f,"
                   "\"uproot\":%.1f},\"machine_gb_per_s\":%.2f,\"machine_gb_per_s_before\":%.2f,"
                   "\"machine_gb_per_s_after\":%.2f,\"machine_gb_per_s_during\":{\"bursts\":%d,"
                   "\"min\":%.2f,\"median\":%.2f,\"max\":%.2f},\"huge_page_bytes\":%lld,\"off\":{",
                   n_trees, n_modes, n_species, threads, ticks, (double)u10_ms, oak.t.n_branches, crit_b,
                   crit_snap, crit_up, gbs, gbs_before, gbs_after, n_bursts, burst_lo, burst_med,
                   burst_hi, huge_bytes);
            print_variant(&var[0], ticks, n_trees, n_modes, &tb, grid_bytes, gbs, scratch);
            printf("},\"on\":{");
            print_variant(&var[1], ticks, n_trees, n_modes, &tb, grid_bytes, gbs, scratch);
            printf("},\"on_over_off_tick_ms_median\":%.3f,\"on_over_off_per_tick_median\":%.3f,"
                   "\"on_over_off_per_tick_p95\":%.3f,\"on_over_off_cpu_ms_median\":%.3f,"
                   "\"target_ratio\":1.10,\"wind_step_ms_mean\":%.1f,"
                   "\"loadavg\":[%.2f,%.2f,%.2f]}\n",
                   a_med > 0.0 ? b_med / a_med : 0.0, r_med, r_p95,
                   a_cpu > 0.0 ? b_cpu / a_cpu : 0.0,
                   wind_sum / ((ticks + every - 1) / every), load[0], load[1], load[2]);
        } else {
            printf("modal: %d trees x %d modes at %.0f m/s: tick median %.3f ms without damage, "
                   "%.3f with (ratio %.3f, per tick %.3f, p95 %.3f), load %.2f\n",
                   n_trees, n_modes, (double)u10_ms, a_med, b_med,
                   a_med > 0.0 ? b_med / a_med : 0.0, r_med, r_p95, load[0]);
        }
    } else {
        const variant *v = &var[0];
        double med_t = median_of(v->t_total, ticks, scratch);
        double p95_t = (memcpy(scratch, v->t_total, sizeof(double) * (size_t)ticks),
                        pct(scratch, ticks, 0.95));
        double max_t = 0.0;
        for (int k = 0; k < ticks; k++) {
            max_t = v->t_total[k] > max_t ? v->t_total[k] : max_t;
        }
        double med_s = median_of(v->t_sample, ticks, scratch);
        double p99_t = (memcpy(scratch, v->t_total, sizeof(double) * (size_t)ticks),
                        pct(scratch, ticks, 0.99));
        /* the ticks that read a share of the grid and the others (none since the grid is
           read on every tick), apart */
        double *rd = malloc(sizeof(double) * 2 * (size_t)ticks);
        int n_rd = 0, n_other = 0;
        for (int k = 0; rd && k < ticks; k++) {
            if (v->read[k]) {
                rd[ticks + n_rd++] = v->t_sample[k];
                rd[n_rd - 1] = v->t_total[k];
            } else {
                n_other++;
            }
        }
        double rd_tick = 0.0, rd_sample = 0.0, other_tick = 0.0;
        if (rd && n_rd > 0) {
            rd_tick = pct(rd, n_rd, 0.5);
            rd_sample = pct(rd + ticks, n_rd, 0.5);
        }
        if (rd && n_other > 0) {
            int j = 0;
            for (int k = 0; k < ticks; k++) {
                if (!v->read[k]) {
                    rd[j++] = v->t_total[k];
                }
            }
            other_tick = pct(rd, n_other, 0.5);
        }
        free(rd);
        double med_m = median_of(v->t_modal, ticks, scratch);
        double med_cpu = median_of(v->t_cpu, ticks, scratch);
        double med_ns = median_of(v->t_nosnap, ticks, scratch);
        double med_l = median_of(v->t_leaf, ticks, scratch);
        double med_e = median_of(v->t_enc, ticks, scratch);
        long check = 0;
        for (int i = 0; i < n_trees * n_modes; i += 97) {
            check += v->snap[i];
        }
        const double enc_per_tick = (double)v->enc_bytes / ticks;
        const double tick_bytes = tick_model_bytes(&tb, n_trees, n_modes, enc_per_tick, grid_bytes);
        const double upd_bytes = (ub.read + ub.written) * n_trees;
        const double tick_gbs = med_t > 0.0 ? tick_bytes / (med_t * 1e-3) / 1e9 : 0.0;
        const double upd_gbs = med_ns > 0.0 ? upd_bytes / (med_ns * 1e-3) / 1e9 : 0.0;
        const double frac = gbs > 0.0 ? tick_gbs / gbs : 0.0;
        const double upd_frac = gbs > 0.0 ? upd_gbs / gbs : 0.0;
        if (json) {
            printf("{\"bench\":\"modal\",\"trees\":%d,\"modes\":%d,\"species\":%d,\"threads\":%d,"
                   "\"ticks\":%d,\"damage\":%s,\"u10_ms\":%.1f,\"sample_ms_median\":%.3f,"
                   "\"update_quantise_ms_median\":%.3f,"
                   "\"tick_ms_median\":%.3f,\"tick_ms_p95\":%.3f,\"tick_ms_max\":%.3f,"
                   "\"ns_per_tree_mode\":%.3f,\"cpu_ms_per_tick_median\":%.3f,"
                   "\"update_only_ms_median\":%.3f,\"loadavg_1min\":%.2f,\"target_ms\":3.0,"
                   "\"machine_gb_per_s\":%.2f,\"machine_gb_per_s_before\":%.2f,"
                   "\"machine_gb_per_s_after\":%.2f,\"machine_gb_per_s_during\":{\"bursts\":%d,"
                   "\"min\":%.2f,\"median\":%.2f,\"max\":%.2f},\"huge_page_bytes\":%lld,"
                   "\"bytes_per_tree_read\":%.0f,"
                   "\"bytes_per_tree_written\":%.0f,\"bytes_per_tick_model\":%.0f,"
                   "\"tick_effective_gb_per_s\":%.2f,\"bandwidth_fraction\":%.3f,"
                   "\"update_only_bytes_per_tree\":%.0f,\"update_only_effective_gb_per_s\":%.2f,"
                   "\"update_only_bandwidth_fraction\":%.3f,\"checksum\":%ld,"
                   "\"inputs\":{\"cell_m\":%.1f,\"grid\":[%d,%d,%d],\"wind_every_ticks\":%d,"
                   "\"leaf_slots_per_tree\":%u,\"side_m\":%.0f,\"encode_lanes\":%d},"
                   "\"leaf_shed_ms_median\":%.3f,"
                   "\"encode_ms_median\":%.3f,\"encoded_bytes_per_tick\":%.0f,"
                   "\"leaves_shed_per_tick\":%.1f,\"wind_step_ms_mean\":%.1f,"
                   "\"memory_floor_ms\":%.3f,\"tick_over_floor\":%.2f,\"tick_ms_p99\":%.3f,"
                   "\"grid_line_bytes_per_tick\":%.0f,\"memory_floor_ms_without_grid\":%.3f,"
                   "\"grid_read\":{\"ticks\":%d,\"tick_ms_median\":%.3f,\"sample_ms_median\":%.3f},"
                   "\"no_grid_read\":{\"ticks\":%d,\"tick_ms_median\":%.3f},"
                   "\"loadavg\":[%.2f,%.2f,%.2f]}\n",
                   n_trees, n_modes, n_species, threads, ticks, v->damage ? "true" : "false",
                   (double)u10_ms, med_s, med_m, med_t, p95_t, max_t,
                   med_t * 1e6 / ((double)n_trees * n_modes), med_cpu, med_ns, load[0], gbs,
                   gbs_before, gbs_after, n_bursts, burst_lo, burst_med, burst_hi, huge_bytes,
                   tb.read, tb.written, tick_bytes, tick_gbs, frac,
                   ub.read + ub.written,
                   upd_gbs, upd_frac, check, (double)cell_m, gxy, gxy, gz, every, in.slots,
                   (double)side, in.lanes.n > 1 ? in.lanes.n : 1, med_l, med_e, enc_per_tick, (double)v->n_shed / ticks,
                   wind_sum / ((ticks + every - 1) / every),
                   gbs > 0.0 ? tick_bytes / (gbs * 1e9) * 1e3 : 0.0,
                   gbs > 0.0 && tick_bytes > 0.0 ? med_t / (tick_bytes / (gbs * 1e9) * 1e3) : 0.0,
                   p99_t, grid_bytes,
                   gbs > 0.0 ? (tick_bytes - grid_bytes) / (gbs * 1e9) * 1e3 : 0.0, n_rd,
                   rd_tick, rd_sample, n_other, other_tick, load[0], load[1], load[2]);
        } else {
            printf("modal: %d trees x %d modes, %d threads: tick median %.3f ms (sample %.3f, "
                   "update+quantise %.3f), p95 %.3f, max %.3f\n"
                   "modal: %.0f + %.0f bytes per tree read + written: %.2f GB/s, %.3f of the "
                   "machine's triad %.2f GB/s (update alone %.3f)\n",
                   n_trees, n_modes, threads, med_t, med_s, med_m, p95_t, max_t, tb.read,
                   tb.written, tick_gbs, frac, gbs, upd_frac);
        }
    }
    for (int j = 0; j < n_var; j++) {
        variant_fini(&var[j]);
    }
    if (with_oak) {
        damage_oak_fini(&oak);
    }
    free(omega);
    free(gamma);
    free(p);
    free(step);
    free(sp);
    free(sp_drag);
    free(ts);
    free(yaw);
    free(pos);
    free(wind);
    free(wind_next);
    wind_probe_destroy(probe);
    wind_destroy(wg);
    free(t_wind);
    free(scratch);
    free(ratio);
    free(nm);
    return 0;
}
