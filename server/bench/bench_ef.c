/* gale-bench ef: the storm damage model (server/sim/damage*.c) against the Enhanced Fujita
 * scale's tree indicators (PHYSICS.md "Damage against the EF scale"). The shipped species
 * (pine, oak, palm), a stand of --trees of each at 32 modes as the server bakes them, in
 * the tick without a wind grid (the steady profile at each crown plus the gust vector, as
 * tick.c samples it), under a 10 m mean wind that ramps from --from to --to at --rate m/s
 * per second, with the scenarios' gust process (gust.h, I_u = 1/ln(10/0.3), L_u = 50 m;
 * --no-gust: the mean alone). At the first branch broken, the first tree uprooted, the
 * first snapped, and when half a species' trees are down, it records the 10 m wind as a
 * weather report names it: the 1-minute sustained wind (the mean of the last 60 s) and the
 * 3-s gust the gust process produced (the highest 3-s mean of the 10 m speed, mean plus
 * gust vector, of the last 60 s: weather_gust.h, the figure WEATHER sends), beside
 * 1.3 × sustained (NOAA AOML's open-terrain factor for the peak 3-s gust). Prints JSON. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake.h"
#include "bench.h"
#include "damage.h"
#include "damage_table.h"
#include "gust.h"
#include "lsystem.h"
#include "mono.h"
#include "species.h"
#include "tick.h"
#include "weather_gust.h"
#include "wire.h"

#define EF_SP       3
#define EF_MAX_TREE 256
#define MPH_PER_MS  2.2369363 /* 1 / 0.44704 */

static const char *const ef_names[EF_SP] = { "pine", "oak", "palm" };
/* the EF scale's indicator for the species' wood (DI 27 hardwood, DI 28 softwood) */
static const char *const ef_di[EF_SP] = { "DI 28 softwood", "DI 27 hardwood", "none (DI 27 shown)" };

/* The 10 m wind at an event. */
typedef struct ef_wind {
    bool seen;
    double t_s, mean_ms, sustained_ms, gust3_ms;
} ef_wind;

typedef struct ef_species {
    ef_wind branch, uproot, snap, half;
    int fallen, snapped, uprooted, branches;
} ef_species;

static const char ef_usage[] =
    "usage: gale-bench ef [--trees N] [--rate R] [--from U0] [--to U1] [--seed S] [--no-gust]\n"
    "  The shipped pine, oak and palm (N of each, default 12) under a 10 m mean wind ramping\n"
    "  from U0 (10) to U1 (90) m/s at R m/s per second (0.05), gusts from the scenarios'\n"
    "  gust process (seed S, 42; --no-gust: none). Prints JSON: per species the 10 m\n"
    "  1-minute sustained wind and 3-s gust (m/s and mph) at the first branch broken, the\n"
    "  first uproot, the first snap and half the trees down, with the EF scale's figures.\n";

/* Bakes the shipped species `name` at 32 modes with its damage table. */
static int ef_bake(const char *name, species *sp, asset *a, damage_table *t, gale_err *err)
{
    char path[512];
    snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, name);
    skeleton sk = { 0 };
    int rc = species_load(path, sp, err);
    rc = rc ? rc : lsystem_generate(&sp->gen, &sk, err);
    rc = rc ? rc : bake_run(&sk, sp, &(bake_desc){ .n_modes = 32 }, a, NULL, err);
    rc = rc ? rc : damage_table_build(a, sp->E_pa, sp->drag_c, &sp->damage, t, err);
    skeleton_fini(&sk);
    return rc;
}

static void ef_print_wind(const char *key, const ef_wind *w, bool comma)
{
    if (!w->seen) {
        printf("\"%s\":null%s", key, comma ? "," : "");
        return;
    }
    printf("\"%s\":{\"t_s\":%.1f,\"mean_ms\":%.2f,\"sustained_ms\":%.2f,\"sustained_mph\":%.1f,"
           "\"gust3s_ms\":%.2f,\"gust3s_mph\":%.1f,\"gust_factor\":%.3f,"
           "\"sustained_x1.3_mph\":%.1f}%s",
           key, w->t_s, w->mean_ms, w->sustained_ms, w->sustained_ms * MPH_PER_MS, w->gust3_ms,
           w->gust3_ms * MPH_PER_MS, w->sustained_ms > 0.0 ? w->gust3_ms / w->sustained_ms : 0.0,
           1.3 * w->sustained_ms * MPH_PER_MS, comma ? "," : "");
}

int bench_ef(int argc, char **argv)
{
    int per = 12;
    double rate = 0.05, u0 = 10.0, u1 = 90.0;
    unsigned long long seed = 42;
    bool gusts = true;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--no-gust")) {
            gusts = false;
            continue;
        }
        if (!v || a[0] != '-' || a[1] != '-') {
            return bench_usage(a, ef_usage);
        }
        char *end = NULL;
        double x = strtod(v, &end);
        if (!end || *end || !isfinite(x)) {
            fprintf(stderr, "gale-bench ef: %s: expected a number, got '%s'\n", a, v);
            return 2;
        }
        if (!strcmp(a, "--trees") && x >= 1 && x * EF_SP <= EF_MAX_TREE && x == floor(x)) {
            per = (int)x;
        } else if (!strcmp(a, "--rate") && x > 0.0 && x <= 10.0) {
            rate = x;
        } else if (!strcmp(a, "--from") && x >= 0.0 && x < 200.0) {
            u0 = x;
        } else if (!strcmp(a, "--to") && x > 0.0 && x <= 200.0) {
            u1 = x;
        } else if (!strcmp(a, "--seed") && x >= 0.0 && x == floor(x)) {
            seed = (unsigned long long)x;
        } else {
            fprintf(stderr,
                    "gale-bench ef: %s: expected --trees 1..%d, --rate (0, 10], --from [0, 200), "
                    "--to (0, 200] or --seed >= 0, got %s\n",
                    a, EF_MAX_TREE / EF_SP, v);
            return 2;
        }
        i++;
    }
    if (!(u1 > u0)) {
        fprintf(stderr, "gale-bench ef: --to: expected more than --from (%g), got %g\n", u0, u1);
        return 2;
    }

    static species sp[EF_SP];
    static asset as[EF_SP];
    static damage_table tab[EF_SP];
    static float qstep[EF_SP][64];
    tick_species tsp[EF_SP];
    gale_err err = { 0 };
    int rc = 0;
    for (int k = 0; k < EF_SP && !rc; k++) {
        rc = ef_bake(ef_names[k], &sp[k], &as[k], &tab[k], &err);
        if (rc) {
            fprintf(stderr, "gale-bench ef: %s: %s\n", ef_names[k], err.msg);
            break;
        }
        for (uint32_t i = 0; i < as[k].n_modes && i < 64; i++) {
            qstep[k][i] = 1e-3f;
        }
        tsp[k] = (tick_species){ .n_modes = as[k].n_modes, .omega = as[k].omega,
                                 .gamma = as[k].gamma, .wind_basis = as[k].wind_basis,
                                 .qstep = qstep[k], .height_m = as[k].height_m,
                                 .n_leaves = as[k].n_leaves, .drag = sp[k].drag,
                                 .damage = &tab[k] };
    }
    static scene_tree trees[EF_MAX_TREE];
    scene sc;
    memset(&sc, 0, sizeof sc);
    sc.tick_hz = 60;
    sc.snapshot_hz = 30;
    sc.n_species = EF_SP;
    sc.leaf_seed = (uint64_t)seed;
    sc.n_trees = EF_SP * per;
    for (int i = 0; i < sc.n_trees; i++) {
        /* yaws spread over the turn: each tree meets the wind from its own azimuth */
        trees[i] = (scene_tree){ .species = i % EF_SP, .pos = { 20.0f * (float)i, 0, 0 },
                                 .yaw_rad = 0.3f * (float)i, .scale = 1 };
    }
    sc.trees = trees;
    tick_sim *t = rc ? NULL : tick_create(&(tick_desc){ .sc = &sc, .species = tsp }, &err);
    if (!rc && !t) {
        fprintf(stderr, "gale-bench ef: %s\n", err.msg);
        rc = 1;
    }

    ef_species res[EF_SP];
    memset(res, 0, sizeof res);
    bool down[EF_MAX_TREE] = { false };
    const gust_desc gd = gust_desc_resolve(&(gust_desc){ .seed = seed, .z0_m = 0.3 });
    gust g;
    gust_init(&g, &gd);
    weather_gust wg;
    weather_gust_init(&wg);
    /* the 1-minute sustained wind: the mean of the last 60 one-second means */
    double sec_sum = 0.0, sec_mean[60] = { 0 };
    int sec_n = 0, n_secs = 0;
    const double dt = 1.0 / 60.0, wall0 = mono_s();
    const long n_ticks = rc ? 0 : (long)ceil((u1 - u0) / rate / dt);
    long ticks = 0;
    double mean = u0, sustained = u0, gust3 = u0;
    for (long n = 0; n < n_ticks; n++, ticks++) {
        const double ts = (double)n * dt;
        mean = u0 + rate * ts;
        double gv[3] = { 0.0, 0.0, 0.0 };
        if (gusts) {
            gust_step(&g, dt, mean, gv);
        }
        /* the wind blows toward +x (from the west): along = x, across = y */
        tick_set_inflow(t, &(wind_inflow){ .dir_rad = 0.0f, .u10_ms = (float)mean,
                                           .z0_m = 0.3f, .zmin_m = 5.0f,
                                           .gust = { (float)gv[0], (float)gv[1], (float)gv[2] } });
        if (tick_step(t, NULL, NULL, &err) != 0) {
            fprintf(stderr, "gale-bench ef: tick: %s\n", err.msg);
            rc = 1;
            break;
        }
        const double u10 = sqrt((mean + gv[0]) * (mean + gv[0]) + gv[1] * gv[1] + gv[2] * gv[2]);
        weather_gust_add(&wg, ts, (float)u10);
        sec_sum += mean;
        if (++sec_n == 60) {
            sec_mean[n_secs % 60] = sec_sum / 60.0;
            n_secs++;
            sec_sum = 0.0;
            sec_n = 0;
        }
        int have = n_secs < 60 ? n_secs : 60;
        double s = 0.0;
        for (int i = 0; i < have; i++) {
            s += sec_mean[i];
        }
        sustained = have > 0 ? s / have : mean;
        gust3 = weather_gust_ms(&wg, (float)sustained);
        const ef_wind now = { true, ts, mean, sustained, gust3 };
        const wire_damage *ev;
        int ne = damage_events(tick_damage(t), &ev);
        for (int e = 0; e < ne; e++) {
            int k = (int)(ev[e].tree % EF_SP);
            ef_species *r = &res[k];
            if (ev[e].kind == WIRE_DAMAGE_BRANCH) {
                r->branches++;
                if (!r->branch.seen) {
                    r->branch = now;
                }
            } else if (ev[e].kind == WIRE_DAMAGE_SNAP || ev[e].kind == WIRE_DAMAGE_UPROOT) {
                bool snap = ev[e].kind == WIRE_DAMAGE_SNAP;
                ef_wind *first = snap ? &r->snap : &r->uproot;
                if (!first->seen) {
                    *first = now;
                }
                r->snapped += snap;
                r->uprooted += !snap;
                if (ev[e].tree < EF_MAX_TREE && !down[ev[e].tree]) {
                    down[ev[e].tree] = true;
                    if (++r->fallen * 2 >= per && !r->half.seen) {
                        r->half = now;
                    }
                }
            }
        }
    }
    const double wall = mono_s() - wall0;
    double load[3] = { 0, 0, 0 };
    if (getloadavg(load, 3) < 0) {
        load[0] = -1.0;
    }
    if (!rc) {
        printf("{\"bench\":\"ef\",\"trees_per_species\":%d,\"rate_ms_per_s\":%g,\"from_ms\":%g,"
               "\"to_ms\":%g,\"seed\":%llu,\"gusts\":%s,\"gust_intensity\":%.4f,"
               "\"gust_length_m\":%g,\"ticks\":%ld,\"wall_s\":%.1f,\"load1\":%.2f,",
               per, rate, u0, u1, seed, gusts ? "true" : "false", gd.intensity, gd.length_m,
               ticks, wall, load[0]);
        printf("\"gust_source\":\"%s\",", gusts ? "the gust process's peak 3-s mean of the 10 m "
                                                  "speed over the last 60 s"
                                                : "none: the mean alone");
        printf("\"ef_mph\":{\"small_limbs\":48,\"uproot_hardwood\":91,\"uproot_softwood\":87,"
               "\"snap_hardwood\":110,\"snap_softwood\":104},\"species\":[");
        for (int k = 0; k < EF_SP; k++) {
            const ef_species *r = &res[k];
            printf("{\"name\":\"%s\",\"ef_indicator\":\"%s\",\"trees\":%d,\"fallen\":%d,"
                   "\"snapped\":%d,\"uprooted\":%d,\"branches\":%d,",
                   ef_names[k], ef_di[k], per, r->fallen, r->snapped, r->uprooted, r->branches);
            ef_print_wind("first_branch", &r->branch, true);
            ef_print_wind("first_uproot", &r->uproot, true);
            ef_print_wind("first_snap", &r->snap, true);
            ef_print_wind("half_down", &r->half, false);
            printf("}%s", k + 1 < EF_SP ? "," : "");
        }
        printf("]}\n");
    }
    tick_destroy(t);
    for (int k = 0; k < EF_SP; k++) {
        damage_table_fini(&tab[k]);
        asset_fini(&as[k]);
    }
    return rc ? 1 : 0;
}
