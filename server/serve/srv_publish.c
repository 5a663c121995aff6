/* Publishing, on the sim thread: each snapshot through the shared stream's encoder and
 * each view stream's (srv_stream.h), the coarse wind and leaf frames beside them, handed
 * to net_publish; the float history tests compare with; the publisher's metrics. */
#include "srv_int.h"
#include "view_select.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

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
    return wire_encode_wind(h, &w, p->extra[SRV_EXTRA_WIND], p->extra_cap,
                            &p->extra_len[SRV_EXTRA_WIND], e);
}

/* One snapshot per view stream: the state encoded with the view's per-tree mode counts
 * (view_select), the extras of the shared snapshot p copied. A stream whose
 * selection is new starts with a keyframe, and every stream sends only a keyframe on the
 * periodic seqs (srv_stream_start), the shared one and the views on the same snapshots. */
static void publish_views(srv *s, const wire_header *h, const srv_qhist *qh, unsigned want,
                          const net_snap *p)
{
    uint32_t streams[SRV_MAX_VIEWS];
    ctl_view views[SRV_MAX_VIEWS];
    pthread_mutex_lock(&s->view_lock);
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        streams[k] = s->views[k].stream;
        views[k] = s->views[k].v;
    }
    pthread_mutex_unlock(&s->view_lock);
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        srv_vsel *vs = &s->vsel[k];
        if (!streams[k]) {
            vs->enc.id = 0;
            continue;
        }
        uint64_t t0 = mono_us();
        if (vs->enc.id != streams[k]) {
            view_select_grid(&s->vgrid, &views[k], s->tree_modes, s->view_margin_m,
                             SRV_LOD_MODES, vs->modes);
            srv_stream_start(&vs->enc, streams[k], vs->modes, s->key_every);
        }
        net_snap *q = net_snap_acquire(s->net);
        if (!q) {
            srv_stream_skip(&vs->enc); /* its connections see a gap and get a keyframe */
            continue;
        }
        gale_err e;
        int rc = srv_stream_encode(&vs->enc, h, p->seq, &s->wscene, qh, want, q, &e);
        for (int x = 0; x < NET_SNAP_MAX_EXTRA && !rc; x++) {
            q->extra_len[x] = p->extra_len[x];
            memcpy(q->extra[x], p->extra[x], p->extra_len[x]);
        }
        q->extra_key_only = p->extra_key_only;
        if (rc) {
            fprintf(stderr, "gale-server: snapshot %u of view stream %u not sent: %s\n", p->seq,
                    vs->enc.id, e.msg);
            atomic_fetch_sub(&q->refs, 1);
            continue;
        }
        atomic_fetch_add(&s->pubm.view_snapshots, 1);
        atomic_fetch_add(&s->pubm.view_encode_ns, (mono_us() - t0) * 1000u);
        net_publish(s->net, q);
    }
}

/* Every view stream skips this snapshot (the shared one was not published). */
static void skip_views(srv *s)
{
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        srv_stream_skip(&s->vsel[k].enc);
    }
}

/* The frames this snapshot carries besides delta2 (srv_stream_encode): those the
 * connections want now, and each for SRV_WANT_HOLD snapshots after it was last wanted. */
static unsigned frames_to_encode(srv *s)
{
    const unsigned want = net_frames_wanted(s->net);
    const unsigned bit[2] = { NET_WANT_KEY, NET_WANT_DELTA1 };
    unsigned out = 0;
    for (int b = 0; b < 2; b++) {
        if (want & bit[b]) {
            s->want_hold[b] = SRV_WANT_HOLD;
        }
        if (s->want_hold[b] > 0) {
            s->want_hold[b]--;
            out |= bit[b];
        }
    }
    return out;
}

void srv_publish(srv *s, uint32_t tick)
{
    const int n = s->d.sc->n_trees, stride = s->stride;
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
    /* qbuf[cur] was filled by tick_step (modal_tick quantised it) */
    const srv_qhist qh = { .q = { s->qbuf[s->cur], s->qbuf[(s->cur + 2) % 3],
                                  s->qbuf[(s->cur + 1) % 3] },
                           .n_trees = (uint32_t)n,
                           .stride = (uint32_t)stride,
                           .lanes = &s->lanes };
    net_snap *p = net_snap_acquire(s->net);
    if (p) {
        wire_header h = { .tick = tick, .server_time_us = mono_us() };
        gale_err e;
        const unsigned want = frames_to_encode(s);
        int rc = srv_stream_encode(&s->shared, &h, s->seq, &s->wscene, &qh, want, p, &e);
        if (!rc && s->coarse && s->seq % SRV_WIND_EVERY == 1) {
            rc = encode_wind(s, &h, p, &e);
        }
        if (!rc && s->n_leaves && s->seq % SRV_LEAF_EVERY == 0) {
            h.type = WIRE_MSG_LEAVES;
            rc = wire_encode_leaves(&h, s->leaves, s->n_leaves, p->extra[SRV_EXTRA_LEAVES],
                                    p->extra_cap, &p->extra_len[SRV_EXTRA_LEAVES], &e);
        }
        if (!rc) {
            rc = srv_damage_encode(s, &h, p, &e);
        }
        if (!rc) {
            h.type = WIRE_MSG_WEATHER;
            rc = srv_weather_encode(s, &h, p, &e);
        }
        if (rc) {
            fprintf(stderr, "gale-server: tick %u: snapshot %u not sent: %s\n", tick, s->seq,
                    e.msg);
            atomic_fetch_sub(&p->refs, 1);
            srv_stream_skip(&s->shared);
            skip_views(s);
        } else {
            publish_views(s, &h, &qh, want, p);
            net_publish(s->net, p);
        }
    } else {
        srv_stream_skip(&s->shared);
        skip_views(s);
    }
    if (s->seq % SRV_LEAF_EVERY == 0) {
        atomic_fetch_add(&s->pubm.leaves_shed, s->n_leaves);
        s->n_leaves = 0;
    }
    s->cur = (s->cur + 1) % 3;
}

/* --- metrics ---------------------------------------------------------------------------- */

static const metric_row pub_rows[] = {
    { "gale_leaves_shed_total", NULL, "Leaf seeds emitted.", METRIC_COUNTER, 0 },
    { "gale_view_snapshots_total", NULL, "Snapshots encoded for per-client views.",
      METRIC_COUNTER, 0 },
    { "gale_view_encode_seconds_total", NULL, "Time spent encoding them.", METRIC_COUNTER, 6 },
};

static void pub_fill(void *ctx, double *v)
{
    srv_pub_counters *m = ctx;
    v[0] = (double)atomic_load(&m->leaves_shed);
    v[1] = (double)atomic_load(&m->view_snapshots);
    v[2] = (double)atomic_load(&m->view_encode_ns) * 1e-9;
}

int srv_publish_register(srv *s, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, pub_rows, (int)(sizeof pub_rows / sizeof pub_rows[0]), pub_fill,
                          &s->pubm, err);
}
