/* A relay's view streams: see relay_views.h. The server's shared stream carries a
 * keyframe in every snapshot it publishes on NATS (net_frames_wanted: NET_WANT_ALL with a
 * bridge), so the relay decodes that and needs no delta chain of its own: the three last
 * states it keeps are what the view streams' deltas are taken against, exactly as the
 * server's view thread keeps them (srv_views.c). */
#include "relay_views.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mono.h"
#include "pi_mutex.h"
#include "srv_stream.h"
#include "view_select.h"
#include "wire.h"
#include "wire_cursor.h"

/* One distinct view and the connections following it (lws thread, under lock). */
typedef struct relay_slot {
    ctl_view v;
    uint32_t stream; /* 0: free */
    int users;
} relay_slot;

/* The delivery thread's encoder for one slot. */
typedef struct relay_enc {
    srv_stream enc;
    uint8_t *modes; /* owned [n_trees]: the slot's view selected */
} relay_enc;

struct relay_views {
    link_scene sc; /* pos owned */
    view_grid grid;
    int max_views;
    pthread_mutex_t lock;
    relay_slot *slot; /* owned [max_views] */
    uint32_t next_stream;
    /* delivery thread */
    relay_enc *enc;    /* owned [max_views] */
    ctl_view *views;   /* owned [max_views]: the slots' views, copied per snapshot */
    uint32_t *streams; /* owned [max_views] */
    wire_decoder *dec; /* owned */
    int16_t *q[3];     /* owned [n_trees * stride] each: the last three states, a ring */
    uint32_t stride;
    int cur;           /* q[cur] holds seq last_seq */
    uint32_t last_seq; /* 0: no chain (start, a snapshot missed, a restart) */
    atomic_ullong snapshots, encode_ns, bad;
};

relay_views *relay_views_create(link_scene *sc, int max_views, gale_err *err)
{
    relay_views *v = calloc(1, sizeof *v);
    if (!v) {
        free(sc->pos);
        sc->pos = NULL;
        gale_errf(err, GALE_E_NOMEM, "relay views: no memory");
        return NULL;
    }
    v->sc = *sc;
    sc->pos = NULL;
    v->max_views = max_views > 0 ? max_views : 0;
    pi_mutex_init(&v->lock);
    const size_t n = v->sc.n_trees ? v->sc.n_trees : 1;
    const size_t k = v->max_views ? (size_t)v->max_views : 1;
    v->slot = calloc(k, sizeof *v->slot);
    v->enc = calloc(k, sizeof *v->enc);
    v->views = calloc(k, sizeof *v->views);
    v->streams = calloc(k, sizeof *v->streams);
    v->dec = wire_decoder_create(
        &(wire_decoder_desc){ .max_trees = (uint32_t)n, .max_modes = v->sc.max_modes }, err);
    if (!v->slot || !v->enc || !v->views || !v->streams || !v->dec) {
        goto fail;
    }
    v->stride = wire_decoder_state(v->dec).stride;
    if (!v->stride) {
        v->stride = v->sc.max_modes;
    }
    for (int i = 0; i < 3; i++) {
        v->q[i] = calloc(n * v->stride, sizeof(int16_t));
        if (!v->q[i]) {
            goto fail;
        }
    }
    for (int i = 0; i < v->max_views; i++) {
        v->enc[i].modes = calloc(n, 1);
        if (!v->enc[i].modes) {
            goto fail;
        }
    }
    if (view_grid_build(&v->grid, v->sc.n_trees, v->sc.pos, v->sc.cell_m, err)) {
        relay_views_destroy(v);
        return NULL;
    }
    return v;
fail:
    gale_errf(err, GALE_E_NOMEM, "relay views: no memory for %u trees and %d views", v->sc.n_trees,
              v->max_views);
    relay_views_destroy(v);
    return NULL;
}

void relay_views_destroy(relay_views *v)
{
    if (!v) {
        return;
    }
    for (int i = 0; v->enc && i < v->max_views; i++) {
        free(v->enc[i].modes);
    }
    for (int i = 0; i < 3; i++) {
        free(v->q[i]);
    }
    wire_decoder_destroy(v->dec);
    view_grid_fini(&v->grid);
    free(v->slot);
    free(v->enc);
    free(v->views);
    free(v->streams);
    free(v->sc.pos);
    pthread_mutex_destroy(&v->lock);
    free(v);
}

/* As the server's view_join (srv_control.c), on the relay's own slots. */
uint32_t relay_views_join(relay_views *v, uint32_t old, const ctl_view *view)
{
    uint32_t stream = 0;
    pthread_mutex_lock(&v->lock);
    for (int k = 0; k < v->max_views && old; k++) {
        relay_slot *w = &v->slot[k];
        if (w->stream == old && --w->users <= 0) {
            w->stream = 0;
            w->users = 0;
        }
    }
    if (view && view->kind != CTL_VIEW_ALL) {
        int free_slot = -1;
        for (int k = 0; k < v->max_views && !stream; k++) {
            relay_slot *w = &v->slot[k];
            if (w->stream && !memcmp(&w->v, view, sizeof *view)) {
                w->users++;
                stream = w->stream;
            } else if (!w->stream && free_slot < 0) {
                free_slot = k;
            }
        }
        if (!stream && free_slot >= 0) {
            v->slot[free_slot] = (relay_slot){ .v = *view, .stream = ++v->next_stream, .users = 1 };
            stream = v->slot[free_slot].stream;
        }
    }
    pthread_mutex_unlock(&v->lock);
    return stream;
}

void relay_views_restart(relay_views *v)
{
    v->last_seq = 0;
}

/* The frames a BUNDLE carries after its first (the state frame: PROTOCOL.md "BUNDLE"),
 * pointers into b. Returns the count; 0 for a frame that is not a BUNDLE. */
static uint32_t bundle_extras(const uint8_t *b, size_t len, const uint8_t **more, size_t *more_len)
{
    if (len < WIRE_HEADER_BYTES + 1 || b[6] != WIRE_MSG_BUNDLE) {
        return 0;
    }
    wire_reader r = wire_reader_make(b + WIRE_HEADER_BYTES, len - WIRE_HEADER_BYTES);
    const uint32_t count = wire_get_u8(&r);
    uint32_t n = 0;
    for (uint32_t i = 0; i < count && i < WIRE_MAX_BUNDLE; i++) {
        const size_t flen = wire_get_u32(&r);
        if (r.bad || flen > wire_reader_left(&r)) {
            return 0; /* not reached: the relay decoded this bundle's keyframe already */
        }
        if (i > 0) {
            more[n] = r.p;
            more_len[n++] = flen;
        }
        r.p += flen;
    }
    return n;
}

/* The view snapshot q gets the shared snapshot p's extras as p carries them: inside each
 * variant's BUNDLE (wrapped the same way), or apart. */
static int copy_extras(net_snap *q, const net_snap *p, gale_err *e)
{
    const uint8_t *km[WIRE_MAX_BUNDLE], *dm[WIRE_MAX_BUNDLE];
    size_t kl[WIRE_MAX_BUNDLE], dl[WIRE_MAX_BUNDLE];
    const uint32_t nk = bundle_extras(p->key, p->key_len, km, kl);
    uint32_t nd = 0;
    if (p->delta2_len) {
        nd = bundle_extras(p->delta2, p->delta2_len, dm, dl);
    } else if (p->delta1_len) {
        nd = bundle_extras(p->delta1, p->delta1_len, dm, dl);
    }
    const size_t cap = net_snap_buffer_cap(q->cap, q->extra_cap);
    uint8_t *buf[3] = { q->key, q->delta1, q->delta2 };
    size_t *len[3] = { &q->key_len, &q->delta1_len, &q->delta2_len };
    for (int i = 0; i < 3; i++) {
        const uint32_t n = i == 0 ? nk : nd;
        if (n && *len[i] &&
            wire_bundle_wrap(buf[i], cap, len[i], i == 0 ? km : dm, i == 0 ? kl : dl, n, e)) {
            return -1;
        }
    }
    for (int x = 0; x < NET_SNAP_MAX_EXTRA; x++) {
        q->extra_len[x] = p->extra_len[x];
        memcpy(q->extra[x], p->extra[x], p->extra_len[x]);
    }
    q->extra_key_only = p->extra_key_only;
    return 0;
}

void relay_views_publish(relay_views *v, net_server *net, const net_snap *p)
{
    uint32_t n_streams = 0;
    pthread_mutex_lock(&v->lock);
    for (int k = 0; k < v->max_views; k++) {
        v->streams[k] = v->slot[k].stream;
        v->views[k] = v->slot[k].v;
        n_streams += v->streams[k] != 0;
    }
    pthread_mutex_unlock(&v->lock);
    if (!n_streams) {
        v->last_seq = 0; /* no view to encode: no keyframe decoded (a view's stream starts
                            with a keyframe of its own) */
        return;
    }
    wire_frame f;
    gale_err e = { 0 };
    int rc = wire_decode(v->dec, p->key, p->key_len, &f, &e);
    if (rc || !(f.types & (1u << WIRE_MSG_KEYFRAME))) {
        if (atomic_fetch_add(&v->bad, 1) < 5) {
            fprintf(stderr, "gale-relay: snapshot %u: no keyframe to select views from%s%s\n",
                    p->seq, rc ? ": " : "", rc ? e.msg : "");
        }
        v->last_seq = 0;
        return;
    }
    const wire_state st = wire_decoder_state(v->dec);
    if (st.n_trees != v->sc.n_trees || st.stride != v->stride) {
        if (atomic_fetch_add(&v->bad, 1) < 5) {
            fprintf(stderr,
                    "gale-relay: snapshot %u: %u trees, the scene has %u: views not "
                    "selected (restart the relay after the server's scene changes)\n",
                    p->seq, st.n_trees, v->sc.n_trees);
        }
        v->last_seq = 0;
        return;
    }
    const bool chain = v->last_seq && p->seq == v->last_seq + 1u;
    const int qi[3] = { (v->cur + 1) % 3, v->cur, (v->cur + 2) % 3 };
    memcpy(v->q[qi[0]], st.q, (size_t)st.n_trees * st.stride * sizeof(int16_t));
    v->cur = qi[0];
    v->last_seq = p->seq;
    /* a shared snapshot without a delta (a start, a periodic keyframe) says nothing of the
       extras a delta carries: the views send their keyframe alone too */
    const bool restart = !chain || (!p->delta1_len && !p->delta2_len);
    const srv_qhist qh = { .q = { v->q[qi[0]], v->q[qi[1]], v->q[qi[2]] },
                           .n_trees = st.n_trees,
                           .stride = st.stride,
                           .lanes = NULL };
    const wire_scene *scene = wire_decoder_scene(v->dec);
    const unsigned want = net_frames_wanted(net);
    for (int k = 0; k < v->max_views; k++) {
        relay_enc *re = &v->enc[k];
        if (!v->streams[k]) {
            re->enc.id = 0;
            continue;
        }
        const uint64_t t0 = mono_us();
        if (re->enc.id != v->streams[k]) {
            view_select_grid(&v->grid, &v->views[k], st.n_modes, v->sc.margin_m, v->sc.lod_modes,
                             re->modes);
            srv_stream_start(&re->enc, v->streams[k], re->modes, v->sc.key_every);
        }
        if (restart) {
            srv_stream_skip(&re->enc);
        }
        /* as the server's view thread: a stream whose readers are all slow ones, none due,
           is not encoded, and its next snapshot is the keyframe such a reader takes */
        const uint32_t due = net_stream_due(net, v->streams[k]);
        if (due && (int32_t)(p->seq - due) < 0) {
            srv_stream_skip(&re->enc);
            continue;
        }
        net_snap *q = net_snap_acquire(net);
        if (!q) {
            srv_stream_skip(&re->enc); /* its connections see a gap and get a keyframe */
            continue;
        }
        rc = srv_stream_encode(&re->enc, &f.hdr, p->seq, scene, &qh, want, q, &e);
        if (!rc) {
            rc = copy_extras(q, p, &e);
        }
        if (rc) {
            fprintf(stderr, "gale-relay: snapshot %u of view stream %u not sent: %s\n", p->seq,
                    re->enc.id, e.msg);
            srv_stream_skip(&re->enc);
            atomic_fetch_sub(&q->refs, 1);
            continue;
        }
        atomic_fetch_add(&v->snapshots, 1);
        atomic_fetch_add(&v->encode_ns, (mono_us() - t0) * 1000u);
        net_publish(net, q);
    }
}

void relay_views_counts(const relay_views *v, unsigned long long *snapshots,
                        unsigned long long *encode_ns, unsigned long long *bad)
{
    *snapshots = atomic_load(&v->snapshots);
    *encode_ns = atomic_load(&v->encode_ns);
    *bad = atomic_load(&v->bad);
}
