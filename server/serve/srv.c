/* The running server: see srv.h. The simulation thread owns the tick state; the lws
 * thread owns the connections; they meet in net_publish (snapshots), the scenario lock
 * (kiosk commands) and a few atomics (metrics). */
#include "srv.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ctl.h"
#include "view_select.h"
#include "wire.h"

#define SRV_MAX_VIEWS 4  /* distinct client views encoded per snapshot; beyond them a
                            connection's view is ignored (it gets the whole scene) */
#define SRV_LOD_MODES 4  /* modes sent for trees beyond a view's lod_m */

/* One distinct view and the connections following it (lws thread, under view_lock). */
typedef struct srv_view {
    ctl_view v;
    uint32_t stream; /* 0 = slot free */
    int users;
} srv_view;

/* The sim thread's selection for one view slot. */
typedef struct srv_vsel {
    uint32_t stream; /* stream the modes below were selected for; 0 none */
    uint8_t *modes;  /* owned [n_trees]: ctl_view_select of the slot's view */
    int held;        /* snapshots of this stream published with these modes: 0, 1, 2+ */
} srv_vsel;

struct srv {
    srv_desc d;
    net_server *net;
    net_asset assets[SCENE_MAX_SPECIES];
    tick_sim *tick;
    tick_species ts[SCENE_MAX_SPECIES]; /* what the tick borrows */
    pthread_t thread;
    atomic_int stop;
    pthread_mutex_t scen_lock;   /* scenario: evaluated by the sim thread, dialled by kiosks */
    scenario *scen;
    /* snapshot encoding (sim thread only) */
    wire_scene wscene;
    uint8_t *tree_species;       /* owned [n_trees] */
    uint8_t *tree_modes;         /* owned [n_trees] */
    int16_t *qbuf[3];            /* owned [n_trees * stride]: current, previous, before */
    int cur;                     /* index of the current buffer in qbuf */
    int held;                    /* snapshots in qbuf history: 0, 1, 2+ */
    uint32_t seq;
    int ticks_per_snap;
    wire_leaf *leaves;           /* owned [WIRE_MAX_LEAVES] gathered since the last snapshot */
    uint32_t n_leaves;
    /* welcome template (lws thread) */
    ctl_species *wspecies;       /* owned [n_species] */
    ctl_instance *winst;         /* owned [n_trees] */
    /* float history for tests */
    pthread_mutex_t hist_lock;
    float *hist;                 /* owned [history][n_trees * stride] */
    uint32_t *hist_seq;          /* owned [history] */
    int stride;
    /* coarse wind slices (sim thread): a WIND frame every SRV_WIND_EVERY snapshots */
    float *coarse;               /* owned [coarse_cap] */
    int coarse_cap;
    int8_t *slice;               /* owned [WIRE_MAX_WIND_SIDE² × 3] */
    /* per-client views: up to SRV_MAX_VIEWS distinct views, each its own snapshot stream
     * (net.h net_snap.stream), encoded once per snapshot and shared by its connections */
    pthread_mutex_t view_lock;   /* guards views (lws thread joins/leaves, sim thread reads) */
    srv_view views[SRV_MAX_VIEWS];
    uint32_t next_stream;
    srv_vsel vsel[SRV_MAX_VIEWS]; /* sim thread: selection of each slot's stream */
    float *tree_pos;             /* owned [n_trees * 3] tree bases for ctl_view_select */
    float view_margin_m;         /* a tree counts as in view within this of the region */
    /* overrun log rate limit (sim thread) */
    time_t olog_sec;
    int olog_n;
};

#define SRV_WIND_EVERY 15  /* snapshots between coarse wind slices (2 per second at 30/s) */
#define SRV_WIND_FACTOR 4  /* grid cells per coarse cell along each axis */
#define SRV_LEAF_EVERY 3   /* snapshots between leaf frames (10 per second at 30/s): leaves
                              carry their spawn tick, so batching them costs no accuracy
                              and saves a WebSocket message per client per snapshot */

static uint64_t mono_us(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000ull + (uint64_t)t.tv_nsec / 1000u;
}

/* --- control messages (lws thread) ----------------------------------------------------- */

static int welcome(srv *s, const net_peer *p, int ctl_role, char **reply, size_t *len, char *why,
                   size_t why_cap)
{
    ctl_msg m = { .type = CTL_WELCOME };
    ctl_welcome *w = &m.u.welcome;
    w->protocol = WIRE_PROTOCOL_VERSION;
    w->client_id = p->id;
    w->role = ctl_role;
    w->tick_hz = (float)s->d.sc->tick_hz;
    w->snapshot_hz = (float)(s->d.sc->tick_hz / s->ticks_per_snap);
    w->server_us = mono_us();
    w->tick = atomic_load(&net_get_metrics(s->net)->current_tick);
    w->n_species = (uint32_t)s->d.sc->n_species;
    w->species = s->wspecies;
    w->n_instances = (uint32_t)s->d.sc->n_trees;
    w->instances = s->winst;
    /* The houses: every scene obstacle fits the wire. */
    _Static_assert(SCENE_MAX_OBSTACLES <= WIRE_MAX_OBSTACLES, "scene obstacles exceed the wire");
    const scene *sc = s->d.sc;
    w->obstacles = sc->n_obstacles > 0 ? calloc((size_t)sc->n_obstacles, sizeof *w->obstacles)
                                       : NULL;
    if (sc->n_obstacles > 0 && !w->obstacles) {
        snprintf(why, why_cap, "cannot encode the welcome: out of memory");
        return WIRE_CLOSE_BAD_FIELD;
    }
    w->n_obstacles = (uint32_t)sc->n_obstacles;
    for (int i = 0; i < sc->n_obstacles; i++) {
        memcpy(w->obstacles[i].min, sc->obstacles[i].min, sizeof w->obstacles[i].min);
        memcpy(w->obstacles[i].max, sc->obstacles[i].max, sizeof w->obstacles[i].max);
    }
    gale_err e;
    int rc = ctl_encode(&m, reply, len, &e);
    free(w->obstacles);
    if (rc) {
        snprintf(why, why_cap, "cannot encode the welcome: %s", e.msg);
        return WIRE_CLOSE_BAD_FIELD;
    }
    return 0;
}

/* Moves a connection from stream `old` to the stream of view v (lws thread): an equal view
 * already encoded is shared, else a free slot takes it. Returns the new stream, 0 for the
 * shared whole-scene stream (v covers everything, or all SRV_MAX_VIEWS slots are taken). */
static uint32_t view_join(srv *s, uint32_t old, const ctl_view *v)
{
    uint32_t stream = 0;
    pthread_mutex_lock(&s->view_lock);
    for (int k = 0; k < SRV_MAX_VIEWS && old; k++) {
        srv_view *w = &s->views[k];
        if (w->stream == old && --w->users <= 0) {
            w->stream = 0;
            w->users = 0;
        }
    }
    if (v && v->kind != CTL_VIEW_ALL) {
        int free_slot = -1;
        for (int k = 0; k < SRV_MAX_VIEWS && !stream; k++) {
            srv_view *w = &s->views[k];
            if (w->stream && !memcmp(&w->v, v, sizeof *v)) {
                w->users++;
                stream = w->stream;
            } else if (!w->stream && free_slot < 0) {
                free_slot = k;
            }
        }
        if (!stream && free_slot >= 0) {
            s->views[free_slot] = (srv_view){ .v = *v, .stream = ++s->next_stream, .users = 1 };
            stream = s->views[free_slot].stream;
        }
    }
    pthread_mutex_unlock(&s->view_lock);
    return stream;
}

static void on_closed(void *user, const net_peer *p)
{
    if (p->stream) {
        view_join(user, p->stream, NULL);
    }
}

static int on_control(void *user, net_peer *p, const char *text, size_t len, char **reply,
                      size_t *reply_len, char *why, size_t why_cap)
{
    srv *s = user;
    ctl_msg m;
    int code = WIRE_CLOSE_BAD_JSON;
    gale_err e;
    if (ctl_decode(text, len, CTL_MAX_CLIENT_BYTES, &m, &code, &e)) {
        snprintf(why, why_cap, "%s", e.msg);
        return code ? code : WIRE_CLOSE_BAD_JSON;
    }
    int rc = 0;
    if (!ctl_from_client(m.type)) {
        snprintf(why, why_cap, "type: %s is a server message", ctl_type_name(m.type));
        rc = WIRE_CLOSE_UNKNOWN_TYPE;
    } else if (m.type == CTL_HELLO) {
        const ctl_hello *h = &m.u.hello;
        if (p->role != NET_ROLE_NONE) {
            snprintf(why, why_cap, "hello: a second hello on one connection");
            rc = WIRE_CLOSE_ORDER;
        } else if (h->protocol != WIRE_PROTOCOL_VERSION) {
            snprintf(why, why_cap, "hello.protocol: expected %d, got %d", WIRE_PROTOCOL_VERSION,
                     h->protocol);
            rc = WIRE_CLOSE_VERSION;
        } else if (h->role == CTL_ROLE_KIOSK &&
                   (!s->d.sc->kiosk_token[0] || strcmp(h->token, s->d.sc->kiosk_token))) {
            snprintf(why, why_cap, "hello.token: wrong kiosk token");
            rc = WIRE_CLOSE_BAD_TOKEN;
        } else {
            rc = welcome(s, p, h->role, reply, reply_len, why, why_cap);
            if (!rc) {
                p->role = h->role + 1; /* NET_ROLE_* follows ctl_role, shifted by NONE */
                p->resync = true;
                p->stream = view_join(s, p->stream, &h->view);
            }
        }
    } else if (p->role == NET_ROLE_NONE) {
        snprintf(why, why_cap, "%s before hello", ctl_type_name(m.type));
        rc = WIRE_CLOSE_ORDER;
    } else if (m.type == CTL_WIND) {
        const ctl_wind *w = &m.u.wind;
        if (p->role != NET_ROLE_KIOSK) {
            snprintf(why, why_cap, "wind: only a kiosk may steer the wind (this is a %s)",
                     ctl_role_name(p->role - 1));
            rc = WIRE_CLOSE_FORBIDDEN;
        } else if (strcmp(w->token, s->d.sc->kiosk_token)) {
            snprintf(why, why_cap, "wind.token: wrong kiosk token");
            rc = WIRE_CLOSE_BAD_TOKEN;
        } else if (w->has_gust) {
            /* The scenario's gust process has no override (scenario.h dials hold the
             * sustained wind and its direction only): say so rather than ignore it. */
            snprintf(why, why_cap, "wind.gust: not supported (the scenario sets the "
                                   "turbulence); send speed_ms and dir_deg only");
            rc = WIRE_CLOSE_BAD_FIELD;
        } else if (s->scen) {
            pthread_mutex_lock(&s->scen_lock);
            if (w->has_speed) {
                /* the scenario's dial holds a sustained wind in [0, 90] m/s */
                scenario_set_dial(s->scen, w->speed_ms > 90.0f ? 90.0 : (double)w->speed_ms, NULL);
            }
            if (w->has_dir) {
                /* ctl: toward, from +x counter-clockwise; scenario: from, clockwise from
                 * north. Coming from θ + 180° (math) is bearing 90° − (θ + 180°). */
                double from = fmod(270.0 - (double)w->dir_deg + 720.0, 360.0);
                scenario_set_direction(s->scen, from, NULL);
            }
            if (w->has_scenario && !w->scenario[0]) {
                scenario_clear_override(s->scen);
            }
            pthread_mutex_unlock(&s->scen_lock);
        } else if (w->has_speed || w->has_dir) {
            const scene *sc = s->d.sc;
            wind_inflow in = { .dir_rad = (w->has_dir ? w->dir_deg : sc->wind_dir_deg) *
                                          0.017453292f,
                               .u10_ms = w->has_speed ? w->speed_ms : sc->wind_u10_ms };
            tick_set_inflow(s->tick, &in);
        }
    } else if (m.type == CTL_RESYNC) {
        p->resync = true;
    } else if (m.type == CTL_VIEW) {
        /* the new stream's first frame is a keyframe (net.c: a stream change breaks the
         * delta chain) */
        p->stream = view_join(s, p->stream, &m.u.view);
    } else if (m.type == CTL_PING) {
        ctl_msg pong = { .type = CTL_PONG };
        pong.u.pong.id = m.u.ping.id;
        pong.u.pong.client_us = m.u.ping.client_us;
        pong.u.pong.server_us = mono_us();
        pong.u.pong.tick = atomic_load(&net_get_metrics(s->net)->current_tick);
        if (ctl_encode(&pong, reply, reply_len, &e)) {
            snprintf(why, why_cap, "pong: %s", e.msg);
            rc = WIRE_CLOSE_BAD_FIELD;
        }
    }
    ctl_msg_fini(&m);
    return rc;
}

/* --- simulation thread ------------------------------------------------------------------ */

/* The lowest layer of the grid averaged over SRV_WIND_FACTOR³ blocks, as a WIND frame
 * (clients drift falling leaves with it). */
static int encode_wind(srv *s, wire_header *h, net_snap *p, gale_err *e)
{
    int dims[3];
    const scene *sc = s->d.sc;
    if (s->d.wind->coarse(s->d.wind->ctx, SRV_WIND_FACTOR, s->coarse, s->coarse_cap, dims) < 0 ||
        dims[0] > (int)WIRE_MAX_WIND_SIDE || dims[1] > (int)WIRE_MAX_WIND_SIDE) {
        return gale_errf(e, GALE_E_RANGE, "coarse wind: the grid does not fit a slice");
    }
    float vmax = 0.05f;
    const int cells = dims[0] * dims[1];
    for (int i = 0; i < 3 * cells; i++) {
        float a = fabsf(s->coarse[i]);
        vmax = a > vmax && isfinite(a) ? a : vmax;
    }
    wire_wind w = { .x0_m = sc->origin[0], .y0_m = sc->origin[1],
                    .z_m = sc->origin[2] + 0.5f * (float)SRV_WIND_FACTOR * sc->cell_m,
                    .cell_m = (float)SRV_WIND_FACTOR * sc->cell_m, .scale_ms = vmax / 127.0f,
                    .nx = (uint16_t)dims[0], .ny = (uint16_t)dims[1], .v = s->slice };
    if (sc->grid[2] < SRV_WIND_FACTOR) {
        w.z_m = sc->origin[2] + 0.5f * (float)sc->grid[2] * sc->cell_m;
    }
    for (int i = 0; i < 3 * cells; i++) {
        s->slice[i] = wire_wind_quantize(s->coarse[i], w.scale_ms);
    }
    h->type = WIRE_MSG_WIND;
    return wire_encode_wind(h, &w, p->extra[1], p->extra_cap, &p->extra_len[1], e);
}

/* One snapshot per view stream: the state re-encoded with the view's per-tree mode
 * counts (ctl_view_select), the extras of the shared snapshot p copied. A stream whose
 * selection is new starts with a keyframe (no delta is encoded until it holds one). */
static void publish_views(srv *s, const wire_header *h0, const net_snap *p)
{
    uint32_t streams[SRV_MAX_VIEWS];
    ctl_view views[SRV_MAX_VIEWS];
    pthread_mutex_lock(&s->view_lock);
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        streams[k] = s->views[k].stream;
        views[k] = s->views[k].v;
    }
    pthread_mutex_unlock(&s->view_lock);
    const uint32_t n = (uint32_t)s->d.sc->n_trees;
    net_metrics *mt = net_get_metrics(s->net);
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        srv_vsel *vs = &s->vsel[k];
        if (!streams[k]) {
            vs->stream = 0;
            continue;
        }
        uint64_t t0 = mono_us();
        if (vs->stream != streams[k]) {
            view_select(&views[k], n, s->tree_pos, s->tree_modes, s->view_margin_m,
                        SRV_LOD_MODES, vs->modes);
            vs->stream = streams[k];
            vs->held = 0;
        }
        net_snap *q = net_snap_acquire(s->net);
        if (!q) {
            vs->held = 0; /* its connections see a gap and get the next keyframe */
            continue;
        }
        q->seq = p->seq;
        q->stream = vs->stream;
        wire_header h = *h0;
        wire_state ws = { .n_trees = n, .stride = (uint32_t)s->stride, .n_modes = vs->modes,
                          .q = s->qbuf[s->cur] };
        wire_state prev = ws, prev2 = ws;
        prev.q = s->qbuf[(s->cur + 2) % 3];
        prev2.q = s->qbuf[(s->cur + 1) % 3];
        const int held = vs->held < s->held ? vs->held : s->held;
        gale_err e;
        int rc = wire_encode_keyframe(&h, p->seq, &s->wscene, &ws, q->key, q->cap, &q->key_len,
                                      &e);
        if (!rc && held >= 1) {
            rc = wire_encode_delta(&h, p->seq, &s->wscene, &ws, &prev, NULL, q->delta1, q->cap,
                                   &q->delta1_len, &e);
        }
        if (!rc && held >= 2) {
            rc = wire_encode_delta(&h, p->seq, &s->wscene, &ws, &prev, &prev2, q->delta2, q->cap,
                                   &q->delta2_len, &e);
        }
        for (int x = 0; x < NET_SNAP_MAX_EXTRA && !rc; x++) {
            q->extra_len[x] = p->extra_len[x];
            memcpy(q->extra[x], p->extra[x], p->extra_len[x]);
        }
        if (rc) {
            fprintf(stderr, "gale-server: snapshot %u of view stream %u not sent: %s\n", p->seq,
                    vs->stream, e.msg);
            atomic_fetch_sub(&q->refs, 1);
            vs->held = 0;
            continue;
        }
        vs->held = vs->held < 2 ? vs->held + 1 : 2;
        atomic_fetch_add(&mt->view_snapshots, 1);
        atomic_fetch_add(&mt->view_encode_ns, (mono_us() - t0) * 1000u);
        net_publish(s->net, q);
    }
}

static void publish(srv *s, uint32_t tick)
{
    const int n = s->d.sc->n_trees, stride = s->stride;
    int16_t *cur = s->qbuf[s->cur]; /* filled by tick_step (modal_tick quantised it) */
    s->seq++;
    if (s->hist) {
        int k = (int)(s->seq % (uint32_t)s->d.history);
        pthread_mutex_lock(&s->hist_lock);
        float *h = s->hist + (size_t)k * (size_t)n * (size_t)stride;
        for (int t = 0; t < n; t++) {
            tick_get_q(s->tick, t, h + (size_t)t * (size_t)stride, stride);
        }
        s->hist_seq[k] = s->seq;
        pthread_mutex_unlock(&s->hist_lock);
    }
    net_metrics *mt = net_get_metrics(s->net);
    net_snap *p = net_snap_acquire(s->net);
    if (p) {
        wire_header h = { .tick = tick, .server_time_us = mono_us() };
        wire_state ws = { .n_trees = (uint32_t)n, .stride = (uint32_t)stride,
                          .n_modes = s->tree_modes, .q = cur };
        wire_state prev = ws, prev2 = ws;
        prev.q = s->qbuf[(s->cur + 2) % 3];
        prev2.q = s->qbuf[(s->cur + 1) % 3];
        gale_err e;
        p->seq = s->seq;
        int rc = wire_encode_keyframe(&h, s->seq, &s->wscene, &ws, p->key, p->cap,
                                      &p->key_len, &e);
        if (!rc && s->held >= 1) {
            rc = wire_encode_delta(&h, s->seq, &s->wscene, &ws, &prev, NULL,
                                   p->delta1, p->cap, &p->delta1_len, &e);
        }
        if (!rc && s->held >= 2) {
            rc = wire_encode_delta(&h, s->seq, &s->wscene, &ws, &prev, &prev2,
                                   p->delta2, p->cap, &p->delta2_len, &e);
        }
        if (!rc && s->coarse && s->seq % SRV_WIND_EVERY == 1) {
            rc = encode_wind(s, &h, p, &e);
        }
        if (!rc && s->n_leaves && s->seq % SRV_LEAF_EVERY == 0) {
            h.type = WIRE_MSG_LEAVES;
            rc = wire_encode_leaves(&h, s->leaves, s->n_leaves, p->extra[0],
                                    p->extra_cap, &p->extra_len[0], &e);
        }
        if (rc) {
            fprintf(stderr, "gale-server: tick %u: snapshot %u not sent: %s\n", tick, s->seq,
                    e.msg);
            atomic_fetch_sub(&p->refs, 1);
        } else {
            publish_views(s, &h, p);
            net_publish(s->net, p);
        }
    }
    if (s->seq % SRV_LEAF_EVERY == 0) {
        atomic_fetch_add(&mt->leaves_shed, s->n_leaves);
        s->n_leaves = 0;
    }
    s->held = s->held < 2 ? s->held + 1 : 2;
    s->cur = (s->cur + 1) % 3;
}

static void *sim_main(void *arg)
{
    srv *s = arg;
    net_metrics *mt = net_get_metrics(s->net);
    const double dt = 1.0 / s->d.sc->tick_hz;
    const uint64_t period_ns = (uint64_t)(dt * 1e9);
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    while (!atomic_load(&s->stop)) {
        uint32_t tick = tick_now(s->tick);
        if (s->scen) {
            scenario_state st;
            pthread_mutex_lock(&s->scen_lock);
            scenario_eval(s->scen, tick * dt, &st);
            pthread_mutex_unlock(&s->scen_lock);
            tick_set_inflow(s->tick, &st.inflow);
        }
        tick_stats ts;
        gale_err e;
        bool snap = (tick + 1) % (uint32_t)s->ticks_per_snap == 0;
        if (tick_step(s->tick, snap ? s->qbuf[s->cur] : NULL, &ts, &e)) {
            fprintf(stderr, "gale-server: %s: stopping the simulation\n", e.msg);
            net_stop(s->net);
            break;
        }
        const leaf_seed *ls;
        int nl = tick_leaves(s->tick, &ls);
        for (int i = 0; i < nl && s->n_leaves < WIRE_MAX_LEAVES; i++) {
            s->leaves[s->n_leaves++] = (wire_leaf){ .instance = ls[i].instance,
                                                    .slot = (uint16_t)ls[i].slot,
                                                    .spawn_tick = ls[i].spawn_tick,
                                                    .seed = ls[i].variation };
        }
        if (snap) {
            publish(s, tick + 1);
        }
        uint64_t ns = 0;
        struct timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        ns = (uint64_t)(ts.ms * 1e6);
        atomic_store(&mt->current_tick, tick + 1);
        atomic_fetch_add(&mt->ticks, 1);
        atomic_fetch_add(&mt->tick_ns_sum, ns);
        if (ns > atomic_load(&mt->tick_ns_max)) {
            atomic_store(&mt->tick_ns_max, ns);
        }
        /* the next tick is due one period after this one was */
        next.tv_nsec += (long)period_ns;
        while (next.tv_nsec >= 1000000000L) {
            next.tv_nsec -= 1000000000L;
            next.tv_sec++;
        }
        int64_t late_ns = (int64_t)(now.tv_sec - next.tv_sec) * 1000000000LL +
                          (now.tv_nsec - next.tv_nsec);
        if (late_ns > (int64_t)period_ns || ns > period_ns) {
            /* Overrun: the tick's work took longer than a period, or the loop fell a whole
             * period behind. The tick is still run (ticks are never skipped, simulated
             * time stays exact); the loop catches up back to back, and a schedule more
             * than 0.25 s behind restarts from now. */
            unsigned long long k = atomic_fetch_add(&mt->overruns, 1) + 1;
            time_t sec = time(NULL);
            if (sec != s->olog_sec) {
                s->olog_sec = sec;
                s->olog_n = 0;
            }
            if (s->olog_n++ < 5) {
                fprintf(stderr,
                        "gale-server: tick %u overran: work %.2f ms (wind %.2f ms, %d pressure "
                        "iterations) of a %.2f ms budget, finished %.2f ms after the next tick "
                        "was due; %llu overruns\n",
                        tick, ts.ms, ts.wind_ms, ts.wind_iters, dt * 1e3, (double)late_ns * 1e-6,
                        k);
            }
            if (late_ns > 250000000LL) {
                next = now;
            }
        }
        if (late_ns <= 0) {
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
        }
    }
    return NULL;
}

/* --- life cycle ------------------------------------------------------------------------ */

srv *srv_create(const srv_desc *d, gale_err *err)
{
    srv *s = calloc(1, sizeof *s);
    if (!s) {
        gale_errf(err, GALE_E_NOMEM, "srv_create: no memory");
        return NULL;
    }
    s->d = *d;
    s->scen = d->scen;
    pthread_mutex_init(&s->scen_lock, NULL);
    pthread_mutex_init(&s->hist_lock, NULL);
    pthread_mutex_init(&s->view_lock, NULL);
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
    if (s->scen) {
        const wind_ball *balls;
        int nb = scenario_balls(s->scen, &balls);
        tick_set_balls(s->tick, balls, nb);
    }
    s->ticks_per_snap = (int)lround(sc->tick_hz / sc->snapshot_hz);
    if (s->ticks_per_snap < 1) {
        s->ticks_per_snap = 1;
    }
    /* wire scene: species per tree, modes and steps per species */
    s->tree_species = calloc((size_t)n, 1);
    s->tree_modes = calloc((size_t)n, 1);
    for (int k = 0; k < 3; k++) {
        s->qbuf[k] = calloc((size_t)n * (size_t)s->stride, sizeof(int16_t));
    }
    s->leaves = calloc(WIRE_MAX_LEAVES, sizeof *s->leaves);
    s->wspecies = calloc((size_t)sc->n_species, sizeof *s->wspecies);
    s->winst = calloc((size_t)n, sizeof *s->winst);
    s->tree_pos = calloc((size_t)n * 3, sizeof *s->tree_pos);
    bool vsel_ok = true;
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        s->vsel[k].modes = calloc((size_t)n > 0 ? (size_t)n : 1, 1);
        vsel_ok = vsel_ok && s->vsel[k].modes;
    }
    if (!vsel_ok || !s->tree_pos || !s->tree_species || !s->tree_modes || !s->qbuf[0] || !s->qbuf[1] || !s->qbuf[2] ||
        !s->leaves || !s->wspecies || !s->winst) {
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
    s->net = net_create(&(net_desc){ .port = d->port,
                                     .iface = d->iface,
                                     .max_clients = d->max_clients,
                                     .queue_frames = d->queue_frames,
                                     .lag_limit = d->lag_limit,
                                     .sndbuf = d->sndbuf,
                                     .snap_cap = cap,
                                     .extra_cap = extra,
                                     .assets = s->assets,
                                     .n_assets = sc->n_species,
                                     .control = on_control,
                                     .control_user = s,
                                     .closed = on_closed,
                                     .max_streams = SRV_MAX_VIEWS },
                        err);
    if (!s->net) {
        goto fail;
    }
    if (!d->quiet) {
        fprintf(stderr,
                "gale-server: scene %s: %d trees, %d species, %d obstacles, %d modes max; tick "
                "%g Hz, snapshot every %d ticks; wind %s; port %d\n",
                sc->name, n, sc->n_species, sc->n_obstacles, s->stride, sc->tick_hz,
                s->ticks_per_snap, d->wind ? "grid" : "log-law profile", net_port(s->net));
    }
    return s;
fail:
    srv_destroy(s);
    return NULL;
}

int srv_run(srv *s)
{
    if (pthread_create(&s->thread, NULL, sim_main, s)) {
        fprintf(stderr, "gale-server: cannot start the simulation thread\n");
        return GALE_E_STATE;
    }
    int rc = net_run(s->net, 1000);
    atomic_store(&s->stop, 1);
    pthread_join(s->thread, NULL);
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
    net_destroy(s->net);
    tick_destroy(s->tick);
    free(s->tree_species);
    free(s->tree_modes);
    for (int k = 0; k < 3; k++) {
        free(s->qbuf[k]);
    }
    free(s->leaves);
    free(s->wspecies);
    free(s->winst);
    free(s->hist);
    free(s->hist_seq);
    free(s->coarse);
    free(s->slice);
    free(s->tree_pos);
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        free(s->vsel[k].modes);
    }
    pthread_mutex_destroy(&s->scen_lock);
    pthread_mutex_destroy(&s->view_lock);
    pthread_mutex_destroy(&s->hist_lock);
    free(s);
}

int srv_port(const srv *s)
{
    return net_port(s->net);
}

net_metrics *srv_metrics(srv *s)
{
    return net_get_metrics(s->net);
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
