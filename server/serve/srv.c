/* The server's life cycle: see srv.h. srv_create builds the simulation, the wire scene,
 * the welcome template and the network, and wires the metrics of each into /metrics;
 * srv_run runs the simulation thread (srv_loop.c) beside the lws service loop. The sim
 * thread owns the tick state, the lws thread the connections; they meet in net_publish
 * (snapshots), the scenario lock (kiosk commands), the view lock and a few atomics. */
#include "srv_int.h"
#include "big_alloc.h"
#include "pi_mutex.h"
#include "sim_lanes.h"
#include "damage_metrics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* gale_build_info: the running build, by label (Prometheus's convention: the value is 1). */
#define STR_(x) #x
#define STR(x) STR_(x)
static const metric_row build_rows[] = {
    { "gale_build_info", "version=\"" GALE_VERSION "\",protocol=\"" STR(WIRE_PROTOCOL_VERSION) "\"",
      "The gale build serving.", METRIC_GAUGE, 0 },
};

static void build_fill(void *ctx, double *v)
{
    (void)ctx;
    v[0] = 1;
}

srv *srv_create(const srv_desc *d, gale_err *err)
{
    srv *s = calloc(1, sizeof *s);
    if (!s) {
        gale_errf(err, GALE_E_NOMEM, "srv_create: no memory");
        return NULL;
    }
    s->d = *d;
    /* opened here, before the server listens, so its descriptor is among the process's
       from the start; none: overrun lines say nothing of the host */
    (void)host_steal_open(&s->steal, mono_s());
    if (s->d.kiosk_idle_s == 0) {
        s->d.kiosk_idle_s = SRV_KIOSK_IDLE_S;
    }
    pi_mutex_init(&s->scen_lock);
    pi_mutex_init(&s->hist_lock);
    pi_mutex_init(&s->view_lock);
    pi_mutex_init(&s->ctl_lock);
    pi_mutex_init(&s->vlock);
    pthread_cond_init(&s->vpost, NULL);
    pthread_cond_init(&s->vdone, NULL);
    kiosk_gate_init(&s->kgate);
    s->walls = wall_groups_create(srv_wall_send, s);
    if (!s->walls) {
        gale_errf(err, GALE_E_NOMEM, "srv_create: no memory");
        goto fail;
    }
    const scene *sc = d->sc;
    const int n = sc->n_trees;
    tick_species *ts = s->ts;
    for (int i = 0; i < sc->n_species; i++) {
        ts[i] = d->species[i].modal;
        ts[i].qstep = d->species[i].qstep;
        if (ts[i].n_modes > WIRE_MAX_MODES) {
            gale_errf(err, GALE_E_RANGE, "srv_create: species %s: expected <= %u modes, got %u",
                      sc->species[i].name, WIRE_MAX_MODES, ts[i].n_modes);
            goto fail;
        }
    }
    s->tick = tick_create(&(tick_desc){ .sc = sc, .species = ts, .wind = d->wind }, err);
    if (!s->tick) {
        goto fail;
    }
    s->stride = tick_stride(s->tick);
    s->lanes = sim_lanes(sc->tick_threads);
    s->vlanes = sim_lanes(sc->tick_threads); /* the view thread's own team */
    weather_gust_init(&s->wx_gust);
    s->man_inflow = (wind_inflow){ .dir_rad = sc->wind_dir_deg * 0.017453292f,
                                   .u10_ms = sc->wind_u10_ms };
    if (srv_scenarios_init(s, err)) {
        goto fail;
    }
    s->ticks_per_snap = (int)lround(sc->tick_hz / sc->snapshot_hz);
    if (s->ticks_per_snap < 1) {
        s->ticks_per_snap = 1;
    }
    double key_snaps = (d->keyframe_s > 0 ? d->keyframe_s : SRV_KEYFRAME_S) * sc->tick_hz /
                       s->ticks_per_snap;
    s->key_every = key_snaps < 1 ? 1u : key_snaps > 1e9 ? 1000000000u : (uint32_t)lround(key_snaps);
    /* wire scene: species per tree, modes and steps per species */
    s->tree_species = calloc((size_t)n, 1);
    s->tree_modes = calloc((size_t)n, 1);
    bool qbuf_ok = true;
    for (int k = 0; k < SRV_QBUFS; k++) {
        /* written now (big_alloc), not left to calloc's lazy zero pages: the first
         * snapshot ticks would fault them in (6.4 MB each at 100 000 trees, ~10 ms a
         * tick) */
        s->qbuf[k] = big_alloc((size_t)n * (size_t)s->stride * sizeof(int16_t));
        qbuf_ok = qbuf_ok && s->qbuf[k];
    }
    s->cur = 0; /* and the snapshots before the first are none: any two others */
    s->qlast[0] = 1;
    s->qlast[1] = 2;
    s->leaves = calloc(WIRE_MAX_LEAVES, sizeof *s->leaves);
    s->dmg_ev = calloc(WIRE_MAX_DAMAGE, sizeof *s->dmg_ev);
    s->dmg_state = calloc(WIRE_MAX_DAMAGE, sizeof *s->dmg_state);
    s->forest_state = malloc(n > 0 ? (size_t)n : 1);
    s->forest_fall = malloc((n > 0 ? (size_t)n : 1) * sizeof *s->forest_fall);
    s->wspecies = calloc((size_t)sc->n_species, sizeof *s->wspecies);
    s->winst = calloc((size_t)n, sizeof *s->winst);
    s->tree_pos = calloc((size_t)n * 3, sizeof *s->tree_pos);
    bool vsel_ok = true;
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        s->vsel[k].modes = calloc((size_t)n > 0 ? (size_t)n : 1, 1);
        vsel_ok = vsel_ok && s->vsel[k].modes;
    }
    if (!vsel_ok || !s->tree_pos || !s->tree_species || !s->tree_modes || !qbuf_ok ||
        !s->leaves || !s->wspecies || !s->winst || !s->dmg_ev || !s->dmg_state ||
        !s->forest_state || !s->forest_fall) {
        gale_errf(err, GALE_E_NOMEM, "srv_create: no memory for %d trees", n);
        goto fail;
    }
    s->wscene.n_trees = (uint32_t)n;
    s->wscene.n_species = (uint32_t)sc->n_species;
    s->wscene.species = s->tree_species;
    for (int i = 0; i < sc->n_species; i++) {
        const srv_species *sp = &d->species[i];
        s->wscene.n_modes[i] = (uint8_t)sp->modal.n_modes;
        for (uint32_t m = 0; m < sp->modal.n_modes; m++) {
            if (!(sp->qstep[m] > 0) || !isfinite(sp->qstep[m])) {
                gale_errf(err, GALE_E_RANGE,
                          "srv_create: species %s mode %u: quantisation step: expected > 0, "
                          "got %g",
                          sc->species[i].name, m, (double)sp->qstep[m]);
                goto fail;
            }
            s->wscene.step[i][m] = sp->qstep[m];
        }
        ctl_species *w = &s->wspecies[i];
        snprintf(w->name, sizeof w->name, "%s", sc->species[i].name);
        snprintf(w->hash, sizeof w->hash, "%s", sp->hash);
        snprintf(w->url, sizeof w->url, "/assets/%s.gasset", sp->hash[0] ? sp->hash : "none");
        w->n_modes = sp->modal.n_modes;
        snprintf(s->assets[i].hash, sizeof s->assets[i].hash, "%s", sp->hash);
        s->assets[i].bytes = sp->asset_bytes;
        s->assets[i].len = sp->asset_bytes ? sp->asset_len : 0;
    }
    for (int t = 0; t < n; t++) {
        const scene_tree *tr = &sc->trees[t];
        s->tree_species[t] = (uint8_t)tr->species;
        s->tree_modes[t] = (uint8_t)d->species[tr->species].modal.n_modes;
        for (int a = 0; a < 3; a++) {
            s->tree_pos[3 * t + a] = tr->pos[a];
        }
        /* margin: the tallest tree's height, so a crown leaning into the view counts */
        float hgt = d->species[tr->species].modal.height_m * tr->scale;
        s->view_margin_m = hgt > s->view_margin_m ? hgt : s->view_margin_m;
        s->winst[t] = (ctl_instance){ .species = (uint32_t)tr->species,
                                      .pos = { tr->pos[0], tr->pos[1], tr->pos[2] },
                                      .yaw_rad = tr->yaw_rad,
                                      .scale = tr->scale };
    }
    if (view_grid_build(&s->vgrid, (uint32_t)n, s->tree_pos, SRV_VIEW_CELL_M, err)) {
        goto fail;
    }
    srv_stream_start(&s->shared, 0, s->tree_modes, s->key_every);
    /* built now, so the first hellos are answered as fast as the later ones */
    if (srv_welcome_build(s, err)) {
        goto fail;
    }
    if (d->history > 0) {
        s->hist = calloc((size_t)d->history * (size_t)n * (size_t)s->stride, sizeof(float));
        s->hist_seq = calloc((size_t)d->history, sizeof *s->hist_seq);
        if (!s->hist || !s->hist_seq) {
            gale_errf(err, GALE_E_NOMEM, "srv_create: no memory for the history");
            goto fail;
        }
    }
    if (d->wind && d->wind->coarse && sc->grid_on) {
        int cd[3];
        for (int a = 0; a < 3; a++) {
            int f = SRV_WIND_FACTOR < sc->grid[a] ? SRV_WIND_FACTOR : sc->grid[a];
            cd[a] = (sc->grid[a] + f - 1) / f;
        }
        s->coarse_cap = 3 * cd[0] * cd[1] * cd[2];
        s->coarse = calloc((size_t)s->coarse_cap, sizeof *s->coarse);
        s->slice = calloc((size_t)WIRE_MAX_WIND_SIDE * WIRE_MAX_WIND_SIDE * 3, 1);
        if (!s->coarse || !s->slice) {
            gale_errf(err, GALE_E_NOMEM, "srv_create: no memory for the coarse wind");
            goto fail;
        }
    }
    size_t cap = wire_state_bound((uint32_t)n, (uint32_t)s->stride, (uint32_t)sc->n_species);
    size_t extra = WIRE_HEADER_BYTES + 64 + (size_t)WIRE_MAX_LEAVES * 16;
    if (s->coarse && extra < WIRE_HEADER_BYTES + 64 + (size_t)s->coarse_cap) {
        extra = WIRE_HEADER_BYTES + 64 + (size_t)s->coarse_cap; /* one layer ≤ all layers */
    }
    if (extra < wire_forest_bytes((uint32_t)n, (uint32_t)n)) {
        extra = wire_forest_bytes((uint32_t)n, (uint32_t)n); /* every tree fallen */
    }
    s->snap_cap = cap;
    s->extra_cap = extra;
    for (int i = 0; i < SRV_VJOBS; i++) {
        for (int x = 0; x < NET_SNAP_MAX_EXTRA; x++) {
            s->vjob[i].extra[x] = malloc(extra);
            if (!s->vjob[i].extra[x]) {
                gale_errf(err, GALE_E_NOMEM, "srv_create: no memory for the view thread");
                goto fail;
            }
        }
    }
    s->ops = srv_ops_create(&(srv_ops_desc){ .hours = d->hours,
                                             .state_file = d->state_file,
                                             .idle_s = s->d.kiosk_idle_s > 0 ? s->d.kiosk_idle_s
                                                                             : SRV_KIOSK_IDLE_S,
                                             .quiet = d->quiet },
                            err);
    if (!s->ops) {
        goto fail;
    }
    s->net = net_create(&(net_desc){ .port = d->port,
                                     .iface = d->iface,
                                     .max_clients = d->max_clients,
                                     .hello_timeout_ms = d->hello_timeout_ms,
                                     .queue_frames = d->queue_frames,
                                     .stall_ms = d->stall_ms,
                                     .snapshot_hz = (int)lround(sc->snapshot_hz),
                                     .sndbuf = d->sndbuf,
                                     .snap_cap = cap,
                                     .extra_cap = extra,
                                     .separate_extras = d->separate_extras,
                                     .published = d->published,
                                     .published_user = d->published_user,
                                     .assets = s->assets,
                                     .n_assets = sc->n_species,
                                     .control = srv_control_serial,
                                     .control_user = s,
                                     .closed = srv_closed_serial,
                                     .max_streams = SRV_MAX_VIEWS,
                                     .metrics = &s->reg,
                                     .tick = &s->simm.current_tick,
                                     .status = srv_ops_status,
                                     .status_user = s->ops,
                                     .metrics_more = srv_ops_metrics,
                                     .metrics_user = s->ops,
                                     .tls_cert = d->tls_cert,
                                     .tls_key = d->tls_key },
                        err);
    if (!s->net) {
        goto fail;
    }
    /* /metrics: the simulation's rows, the network's, the publisher's, the kiosk gate's */
    if (metric_reg_add(&s->reg, build_rows, 1, build_fill, NULL, err) ||
        sim_metrics_register(&s->simm, &s->reg, err) ||
        net_metrics_register(s->net, &s->reg, err) || srv_publish_register(s, &s->reg, err) ||
        kiosk_gate_register(&s->kgate, &s->reg, err) ||
        wall_groups_register(s->walls, &s->reg, err) ||
        srv_weather_register(s, &s->reg, err)) {
        goto fail;
    }
    /* storm damage rows (damage_metrics.h), when any species takes damage */
    if (tick_damage_counts(s->tick) &&
        damage_metrics_register(tick_damage_counts(s->tick), &s->reg, err)) {
        goto fail;
    }
    if (!d->quiet) {
        fprintf(stderr,
                "gale-server: scene %s: %d trees, %d species, %d obstacles, %d modes max; tick "
                "%g Hz, snapshot every %d ticks; wind %s; port %d; welcome %zu bytes, built "
                "in %.0f ms\n",
                sc->name, n, sc->n_species, sc->n_obstacles, s->stride, sc->tick_hz,
                s->ticks_per_snap, d->wind ? "grid" : "log-law profile", net_port(s->net),
                net_shared_len(s->wbody), s->wbuild_ms);
    }
    return s;
fail:
    srv_destroy(s);
    return NULL;
}

int srv_run(srv *s)
{
    gale_err e;
    if (srv_views_start(s, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return GALE_E_STATE;
    }
    if (srv_ops_start(s->ops, s->net, &s->simm.current_tick, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        srv_views_stop(s);
        return GALE_E_STATE;
    }
    if (pthread_create(&s->thread, NULL, srv_loop, s)) {
        fprintf(stderr, "gale-server: cannot start the simulation thread\n");
        srv_ops_stop(s->ops);
        srv_views_stop(s);
        return GALE_E_STATE;
    }
    /* the close bound ends every connection; the grace is a backstop behind it */
    int rc = net_run(s->net, NET_CLOSE_BOUND_MS + 500);
    atomic_store(&s->stop, 1);
    pthread_join(s->thread, NULL);
    srv_views_stop(s);
    srv_ops_stop(s->ops); /* the usage counters' last write */
    return rc;
}

void srv_stop(srv *s)
{
    atomic_store(&s->stop, 1);
    net_stop(s->net);
}

void srv_destroy(srv *s)
{
    if (!s) {
        return;
    }
    srv_views_stop(s);
    net_destroy(s->net);
    srv_ops_destroy(s->ops);
    host_steal_close(&s->steal);
    wall_groups_destroy(s->walls);
    tick_destroy(s->tick);
    free(s->tree_species);
    free(s->tree_modes);
    for (int k = 0; k < SRV_QBUFS; k++) {
        free(s->qbuf[k]);
    }
    free(s->leaves);
    free(s->dmg_ev);
    free(s->dmg_state);
    free(s->forest_state);
    free(s->forest_fall);
    srv_welcome_fini(s);
    free(s->wspecies);
    free(s->winst);
    free(s->wscen);
    free(s->hist);
    free(s->hist_seq);
    free(s->coarse);
    free(s->slice);
    view_grid_fini(&s->vgrid);
    free(s->tree_pos);
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        free(s->vsel[k].modes);
    }
    pthread_mutex_destroy(&s->scen_lock);
    pthread_mutex_destroy(&s->view_lock);
    pthread_mutex_destroy(&s->hist_lock);
    pthread_mutex_destroy(&s->ctl_lock);
    for (int i = 0; i < SRV_VJOBS; i++) {
        for (int x = 0; x < NET_SNAP_MAX_EXTRA; x++) {
            free(s->vjob[i].extra[x]);
        }
    }
    pthread_mutex_destroy(&s->vlock);
    pthread_cond_destroy(&s->vpost);
    pthread_cond_destroy(&s->vdone);
    free(s);
}

int srv_port(const srv *s)
{
    return net_port(s->net);
}

net_limits srv_net_limits(const srv *s)
{
    return net_get_limits(s->net);
}

net_metrics *srv_metrics(srv *s)
{
    return net_get_metrics(s->net);
}

sim_metrics *srv_sim_metrics(srv *s)
{
    return &s->simm;
}

srv_pub_counters *srv_pub_metrics(srv *s)
{
    return &s->pubm;
}

int srv_history_q(srv *s, uint32_t seq, int t, float *q, int cap)
{
    if (!s->hist || t < 0 || t >= s->d.sc->n_trees || seq == 0) {
        return -1;
    }
    int k = (int)(seq % (uint32_t)s->d.history), n = -1;
    pthread_mutex_lock(&s->hist_lock);
    if (s->hist_seq[k] == seq) {
        n = s->tree_modes[t] < cap ? s->tree_modes[t] : cap;
        memcpy(q, s->hist + ((size_t)k * (size_t)s->d.sc->n_trees + (size_t)t) * (size_t)s->stride,
               sizeof(float) * (size_t)n);
    }
    pthread_mutex_unlock(&s->hist_lock);
    return n;
}

float srv_qstep(const srv *s, int t, int m)
{
    return s->d.species[s->tree_species[t]].qstep[m];
}
