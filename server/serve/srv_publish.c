/* Publishing, on the sim thread: each snapshot through the shared stream's encoder
 * (srv_stream.h), the coarse wind and leaf frames beside it, handed to net_publish and,
 * for the view streams, to the view thread (srv_views.c); the float history tests compare
 * with; the view rule's parameters a relay selects views with; the publisher's metrics. */
#include "srv_int.h"

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

/* The frames this snapshot carries of the shared stream and the view streams (a
 * net_frames_wanted_apart mask): those the connections want now, and each for SRV_WANT_HOLD
 * snapshots after it was last wanted. */
static unsigned frames_to_encode(srv *s)
{
    const unsigned want = net_frames_wanted_apart(s->net);
    unsigned out = 0;
    for (int b = 0; b < SRV_WANT_BITS; b++) {
        if (want & 1u << b) {
            s->want_hold[b] = SRV_WANT_HOLD;
        }
        if (s->want_hold[b] > 0) {
            s->want_hold[b]--;
            out |= 1u << b;
        }
    }
    return out;
}

/* The shared stream's frames of this snapshot into p: none when no connection follows it
 * (on a landscape whose viewers all send views, a whole-scene keyframe a snapshot would
 * cost the ticks their time for nobody), the stream then starting over at the next. */
static int encode_shared(srv *s, const wire_header *h, const srv_qhist *qh, unsigned want,
                         net_snap *p, gale_err *e)
{
    if (!want) {
        srv_stream_skip(&s->shared);
        p->seq = s->seq;
        p->stream = 0;
        p->key_len = p->delta1_len = p->delta2_len = 0;
        return 0;
    }
    return srv_stream_encode(&s->shared, h, s->seq, &s->wscene, qh, want, p, e);
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
    const int qi[3] = { s->cur, s->qlast[0], s->qlast[1] };
    const srv_qhist qh = { .q = { s->qbuf[qi[0]], s->qbuf[qi[1]], s->qbuf[qi[2]] },
                           .n_trees = (uint32_t)n,
                           .stride = (uint32_t)stride,
                           .lanes = &s->lanes };
    net_snap *p = net_snap_acquire(s->net);
    if (p) {
        wire_header h = { .tick = tick, .server_time_us = mono_us() };
        gale_err e;
        const unsigned want = frames_to_encode(s);
        int rc = encode_shared(s, &h, &qh, NET_WANT_SHARED(want), p, &e);
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
            srv_views_gap(s);
        } else {
            /* before net_publish bundles p */
            srv_views_post(s, &h, s->seq, NET_WANT_VIEWS(want), p, qi);
            net_publish(s->net, p);
        }
    } else {
        srv_stream_skip(&s->shared);
        srv_views_gap(s);
    }
    if (s->seq % SRV_LEAF_EVERY == 0) {
        atomic_fetch_add(&s->pubm.leaves_shed, s->n_leaves);
        s->n_leaves = 0;
    }
    s->qlast[1] = s->qlast[0];
    s->qlast[0] = s->cur;
    s->cur = srv_views_next_buffer(s);
}

srv_view_rule srv_view_rule_get(const srv *s)
{
    uint32_t max_modes = 1;
    for (uint32_t i = 0; i < s->wscene.n_species; i++) {
        max_modes = s->wscene.n_modes[i] > max_modes ? s->wscene.n_modes[i] : max_modes;
    }
    return (srv_view_rule){ .max_modes = max_modes, .n_trees = (uint32_t)s->d.sc->n_trees,
                            .tree_pos = s->tree_pos,
                            .margin_m = s->view_margin_m,
                            .cell_m = SRV_VIEW_CELL_M,
                            .lod_modes = SRV_LOD_MODES,
                            .key_every = s->key_every };
}

/* --- metrics ---------------------------------------------------------------------------- */

static const metric_row pub_rows[] = {
    { "gale_leaves_shed_total", NULL, "Leaf seeds emitted.", METRIC_COUNTER, 0 },
    { "gale_view_snapshots_total", NULL, "Snapshots encoded for per-client views.",
      METRIC_COUNTER, 0 },
    { "gale_view_encode_seconds_total", NULL, "Time spent encoding them.", METRIC_COUNTER, 6 },
    { "gale_view_snapshots_missed_total", NULL,
      "Snapshots the view streams skipped, the view thread still busy.", METRIC_COUNTER, 0 },
    { "gale_view_snapshots_idle_total", NULL,
      "View-stream snapshots not encoded: every reader a slow one, none due.", METRIC_COUNTER,
      0 },
};

static void pub_fill(void *ctx, double *v)
{
    srv_pub_counters *m = ctx;
    v[0] = (double)atomic_load(&m->leaves_shed);
    v[1] = (double)atomic_load(&m->view_snapshots);
    v[2] = (double)atomic_load(&m->view_encode_ns) * 1e-9;
    v[3] = (double)atomic_load(&m->view_missed);
    v[4] = (double)atomic_load(&m->view_idle);
}

int srv_publish_register(srv *s, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, pub_rows, (int)(sizeof pub_rows / sizeof pub_rows[0]), pub_fill,
                          &s->pubm, err);
}
