/* gale-relay's edge: see relay.h. Three threads: lws (net_run: clients, their views kept
 * here and every other control message forwarded synchronously to the server), the NATS
 * library's delivery thread (the shared stream's snapshots into the net pool, and the
 * view streams encoded from them, relay_views.h: the publisher net.h expects), and
 * main. */
#include "relay.h"

#include <nats/nats.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hash.h"
#include "link.h"
#include "link_server.h"
#include "mono.h"
#include "net.h"
#include "relay_views.h"
#include "wire.h"
#include "wire_cursor.h"

struct relay {
    relay_desc d;
    metric_reg reg; /* /metrics: the relay's rows and its network's */
    natsConnection *nc;
    natsSubscription *snaps;
    net_server *net;
    relay_views *views; /* the clients' views, selected here */
    link_info info;
    net_asset assets[64];
    uint8_t *bytes[64];
    atomic_uint tick;              /* of the last snapshot relayed: /healthz */
    atomic_int closing;
    /* NATS delivery thread: the server's epoch and the offset that keeps every relayed
     * connection's seq increasing across server restarts (PROTOCOL.md "Sequence and gaps") */
    uint64_t epoch;
    uint32_t seq_offset, last_seq;            /* relay_destroy began: snapshots are dropped */
    atomic_ullong snaps_in, snaps_bad, snaps_unsent;
};

/* Sends the control message to the server and applies its verdict to p (role, resync). */
static int relay_forward(relay *r, net_peer *p, const char *text, size_t len, char **reply,
                         size_t *reply_len, char *why, size_t why_cap)
{
    link_ctl c = { .peer = *p, .text = text, .text_len = len };
    c.peer.stream = 0; /* the relay's streams are not the server's */
    uint8_t *req;
    size_t req_len;
    gale_err e;
    if (link_ctl_encode(&c, &req, &req_len, &e)) {
        snprintf(why, why_cap, "relay: %s", e.msg);
        return WIRE_CLOSE_GOING_AWAY;
    }
    natsMsg *m = NULL;
    natsStatus st = natsConnection_Request(&m, r->nc, LINK_SUBJ_CTL, req, (int)req_len,
                                           LINK_CTL_TIMEOUT_MS);
    free(req);
    if (st != NATS_OK) {
        snprintf(why, why_cap, "relay: the server did not answer: %s", natsStatus_GetText(st));
        return WIRE_CLOSE_GOING_AWAY;
    }
    link_ctl v;
    char addr[64], vwhy[256];
    int rc = link_ctl_decode((const uint8_t *)natsMsg_GetData(m), (size_t)natsMsg_GetDataLength(m),
                             &v, addr, sizeof addr, vwhy, sizeof vwhy, &e);
    if (rc) {
        natsMsg_Destroy(m);
        snprintf(why, why_cap, "relay: %s", e.msg);
        return WIRE_CLOSE_GOING_AWAY;
    }
    p->role = v.peer.role;
    p->resync = v.peer.resync;
    if (v.text_len) {
        *reply = malloc(v.text_len);
        if (*reply) {
            memcpy(*reply, v.text, v.text_len);
            *reply_len = v.text_len;
        }
    }
    natsMsg_Destroy(m);
    if (v.rc) {
        snprintf(why, why_cap, "%s", vwhy);
    }
    return v.rc;
}

/* A client's control message. A view is the relay's own business (its streams are
 * encoded here): a `view` after hello is taken without asking the server, and a hello's
 * view is kept here while the hello, without it, goes to the server for the welcome and
 * the token check. Everything else, and anything that does not decode (so the client
 * gets the server's own close code and reason), goes to the server as it came. The
 * server's verdict sets role and resync; the stream is the relay's. */
static int relay_control(void *user, net_peer *p, const char *text, size_t len, char **reply,
                         size_t *reply_len, char *why, size_t why_cap)
{
    relay *r = user;
    ctl_msg m;
    ctl_view hello_view = { .kind = CTL_VIEW_ALL };
    char *hello_text = NULL;
    gale_err e;
    if (ctl_decode(text, len, CTL_MAX_CLIENT_BYTES, &m, NULL, &e) == 0) {
        if (m.type == CTL_VIEW && p->role != NET_ROLE_NONE) {
            /* the new stream's first frame is a keyframe (net.c: a stream change breaks
               the delta chain) */
            p->stream = relay_views_join(r->views, p->stream, &m.u.view);
            ctl_msg_fini(&m);
            return 0;
        }
        if (m.type == CTL_HELLO && m.u.hello.view.kind != CTL_VIEW_ALL) {
            hello_view = m.u.hello.view;
            m.u.hello.view = (ctl_view){ .kind = CTL_VIEW_ALL };
            size_t n;
            if (ctl_encode(&m, &hello_text, &n, &e) == 0) {
                text = hello_text;
                len = n;
            } else {
                hello_view.kind = CTL_VIEW_ALL; /* not reached: it decoded */
            }
        }
        ctl_msg_fini(&m);
    }
    const int role_before = p->role;
    int rc = relay_forward(r, p, text, len, reply, reply_len, why, why_cap);
    free(hello_text);
    if (!rc && role_before == NET_ROLE_NONE && p->role != NET_ROLE_NONE) {
        p->stream = relay_views_join(r->views, p->stream, &hello_view);
    }
    return rc;
}

static void relay_closed(void *user, const net_peer *p)
{
    relay *r = user;
    relay_views_join(r->views, p->stream, NULL);
    link_ctl c = { .peer = *p };
    c.peer.stream = 0; /* the server keeps no stream of a relayed connection */
    uint8_t *b;
    size_t n;
    if (link_ctl_encode(&c, &b, &n, NULL) == 0) {
        natsConnection_Publish(r->nc, LINK_SUBJ_CLOSED, b, (int)n);
        free(b);
    }
}

/* Writes seq into a state frame (plain or the first frame of a BUNDLE): byte 20, after
 * the header (PROTOCOL.md "KEYFRAME", "BUNDLE"). */
static void put_seq(uint8_t *f, size_t len, uint32_t seq)
{
    size_t at = len > 6 && f[6] == WIRE_MSG_BUNDLE ? 25u + WIRE_HEADER_BYTES : WIRE_HEADER_BYTES;
    if (len >= at + 4) {
        wire_writer w = wire_writer_make(f + at, 4);
        wire_put_u32(&w, seq);
    }
}

/* A restarted server counts seq from 1 again: the relay goes on from where it was, and
 * its view streams start over with a keyframe (the views are the relay's: its
 * connections keep them). */
static void renumber(relay *r, net_snap *p, uint64_t epoch)
{
    if (epoch != r->epoch) {
        if (r->epoch) {
            r->seq_offset = r->last_seq + 1u - p->seq;
            relay_views_restart(r->views);
            fprintf(stderr, "gale-relay: the server restarted: seq %u goes on as %u\n", p->seq,
                    p->seq + r->seq_offset);
        }
        r->epoch = epoch;
    }
    if (!r->seq_offset) {
        r->last_seq = p->seq > r->last_seq ? p->seq : r->last_seq;
        return;
    }
    p->seq += r->seq_offset;
    put_seq(p->key, p->key_len, p->seq);
    put_seq(p->delta1, p->delta1_len, p->seq);
    put_seq(p->delta2, p->delta2_len, p->seq);
    r->last_seq = p->seq > r->last_seq ? p->seq : r->last_seq;
}

static void on_snap(natsConnection *nc, natsSubscription *sub, natsMsg *msg, void *user)
{
    (void)nc;
    (void)sub;
    relay *r = user;
    net_snap *p = atomic_load(&r->closing) ? NULL : net_snap_acquire(r->net);
    if (!p) {
        atomic_fetch_add(&r->snaps_unsent, 1);
        natsMsg_Destroy(msg);
        return;
    }
    gale_err e;
    uint64_t epoch;
    if (link_snap_decode((const uint8_t *)natsMsg_GetData(msg), (size_t)natsMsg_GetDataLength(msg),
                         p, &epoch, &e)) {
        if (atomic_fetch_add(&r->snaps_bad, 1) < 5) {
            fprintf(stderr, "gale-relay: %s: %s\n", natsMsg_GetSubject(msg), e.msg);
        }
        atomic_fetch_sub(&p->refs, 1);
        natsMsg_Destroy(msg);
        return;
    }
    natsMsg_Destroy(msg);
    renumber(r, p, epoch);
    if (p->key_len >= WIRE_HEADER_BYTES) {
        wire_reader rd = wire_reader_make(p->key + 8, 4); /* header: tick at byte 8 */
        atomic_store(&r->tick, wire_get_u32(&rd));
    }
    atomic_fetch_add(&r->snaps_in, 1);
    atomic_fetch_add(&p->refs, 1); /* read on below while the clients are sent it */
    net_publish(r->net, p);
    relay_views_publish(r->views, r->net, p);
    atomic_fetch_sub(&p->refs, 1);
}

/* The server's sizes and every asset, over NATS; retries until d.wait_s runs out. */
static int fetch(relay *r, gale_err *err)
{
    const double until = mono_s() + r->d.wait_s;
    natsMsg *m = NULL;
    natsStatus st;
    while ((st = natsConnection_Request(&m, r->nc, LINK_SUBJ_INFO, "", 0, 1000)) != NATS_OK) {
        if (mono_s() > until) {
            return gale_errf(err, GALE_E_IO, "no gale-server answered on NATS %s within %.0f s: %s",
                             r->d.nats_url, r->d.wait_s, natsStatus_GetText(st));
        }
        nats_Sleep(200);
    }
    int rc = link_info_decode((const uint8_t *)natsMsg_GetData(m), (size_t)natsMsg_GetDataLength(m),
                              &r->info, err);
    natsMsg_Destroy(m);
    if (rc) {
        return rc;
    }
    for (uint32_t i = 0; i < r->info.n_assets; i++) {
        net_asset *a = &r->assets[i];
        *a = r->info.assets[i];
        r->bytes[i] = malloc(a->len ? a->len : 1);
        if (!r->bytes[i]) {
            return gale_errf(err, GALE_E_NOMEM, "asset %s: no memory for %zu bytes", a->hash,
                             a->len);
        }
        size_t off = 0;
        while (off < a->len) {
            uint8_t q[32] = { 0 };
            memcpy(q, a->hash, strlen(a->hash));
            wire_writer w = wire_writer_make(q + 24, 8);
            wire_put_u64(&w, off);
            st = natsConnection_Request(&m, r->nc, LINK_SUBJ_ASSET, q, sizeof q, 5000);
            if (st != NATS_OK || natsMsg_GetDataLength(m) <= 0 ||
                off + (size_t)natsMsg_GetDataLength(m) > a->len) {
                natsMsg_Destroy(st == NATS_OK ? m : NULL);
                return gale_errf(err, GALE_E_IO, "asset %s: at byte %zu of %zu: %s", a->hash, off,
                                 a->len, st != NATS_OK ? natsStatus_GetText(st) : "bad chunk");
            }
            memcpy(r->bytes[i] + off, natsMsg_GetData(m), (size_t)natsMsg_GetDataLength(m));
            off += (size_t)natsMsg_GetDataLength(m);
            natsMsg_Destroy(m);
        }
        char got[24];
        snprintf(got, sizeof got, "%016llx", (unsigned long long)hash64(r->bytes[i], a->len));
        if (strcmp(got, a->hash)) {
            return gale_errf(err, GALE_E_FORMAT, "asset: expected hash %s, got %s", a->hash, got);
        }
        a->bytes = r->bytes[i];
    }
    return 0;
}

/* The view rule (gale.scene, link.h), in chunks, into r->views. */
static int fetch_scene(relay *r, gale_err *err)
{
    uint8_t *buf = NULL;
    size_t off = 0, total = 0;
    do {
        uint8_t q[8];
        wire_writer w = wire_writer_make(q, sizeof q);
        wire_put_u64(&w, off);
        natsMsg *m = NULL;
        natsStatus st = natsConnection_Request(&m, r->nc, LINK_SUBJ_SCENE, q, sizeof q, 5000);
        const size_t got = st == NATS_OK ? (size_t)natsMsg_GetDataLength(m) : 0;
        const uint8_t *d = st == NATS_OK ? (const uint8_t *)natsMsg_GetData(m) : NULL;
        if (st == NATS_OK && off == 0) {
            total = (size_t)link_scene_total(d, got);
            buf = total >= got && total <= (size_t)1 << 32 ? malloc(total) : NULL;
        }
        if (st != NATS_OK || !got || !buf || off + got > total) {
            natsMsg_Destroy(st == NATS_OK ? m : NULL);
            free(buf);
            return gale_errf(err, GALE_E_IO, "%s: at byte %zu of %zu: %s", LINK_SUBJ_SCENE, off,
                             total, st != NATS_OK ? natsStatus_GetText(st) : "bad chunk");
        }
        memcpy(buf + off, d, got);
        off += got;
        natsMsg_Destroy(m);
    } while (off < total);
    link_scene sc;
    int rc = link_scene_decode(buf, total, &sc, err);
    free(buf);
    if (rc) {
        return rc;
    }
    r->views = relay_views_create(&sc, (int)r->info.max_streams, err);
    return r->views ? 0 : GALE_E_NOMEM;
}

static const metric_row relay_rows[] = {
    { "gale_relay_snapshots_total", NULL, "Snapshots taken from NATS and relayed.",
      METRIC_COUNTER, 0 },
    { "gale_relay_snapshots_bad_total", NULL, "NATS snapshot messages that did not decode.",
      METRIC_COUNTER, 0 },
    { "gale_relay_snapshots_unsent_total", NULL,
      "Snapshots dropped for want of a free pool snapshot.", METRIC_COUNTER, 0 },
    { "gale_relay_view_snapshots_total", NULL,
      "Snapshots encoded here for the clients' views.", METRIC_COUNTER, 0 },
    { "gale_relay_view_encode_seconds_total", NULL, "Time spent encoding them.",
      METRIC_COUNTER, 6 },
    { "gale_relay_view_keyframes_bad_total", NULL,
      "Shared snapshots whose keyframe the view selection could not decode.", METRIC_COUNTER,
      0 },
};

static void relay_fill(void *ctx, double *v)
{
    relay *r = ctx;
    v[0] = (double)atomic_load(&r->snaps_in);
    v[1] = (double)atomic_load(&r->snaps_bad);
    v[2] = (double)atomic_load(&r->snaps_unsent);
    unsigned long long n, ns, bad;
    relay_views_counts(r->views, &n, &ns, &bad);
    v[3] = (double)n;
    v[4] = (double)ns * 1e-9;
    v[5] = (double)bad;
}

relay *relay_create(const relay_desc *d, gale_err *err)
{
    relay *r = calloc(1, sizeof *r);
    if (!r) {
        gale_errf(err, GALE_E_NOMEM, "relay: no memory");
        return NULL;
    }
    r->d = *d;
    if (r->d.wait_s <= 0) {
        r->d.wait_s = 30;
    }
    natsOptions *o = link_nats_options(d->nats_url, "gale-relay", err);
    if (!o) {
        free(r);
        return NULL;
    }
    natsStatus st = natsConnection_Connect(&r->nc, o);
    natsOptions_Destroy(o);
    if (st != NATS_OK && st != NATS_NOT_YET_CONNECTED) {
        gale_errf(err, GALE_E_IO, "--nats %s: %s", d->nats_url, natsStatus_GetText(st));
        relay_destroy(r);
        return NULL;
    }
    if (fetch(r, err) || fetch_scene(r, err)) {
        relay_destroy(r);
        return NULL;
    }
    r->net = net_create(&(net_desc){ .port = d->port,
                                     .iface = d->iface,
                                     .snap_cap = r->info.snap_cap,
                                     .extra_cap = r->info.extra_cap,
                                     /* the server bundled already (or, with --no-bundle,
                                        chose not to): its clients' frames, unchanged */
                                     .separate_extras = true,
                                     .assets = r->assets,
                                     .n_assets = (int)r->info.n_assets,
                                     .control = relay_control,
                                     .control_user = r,
                                     .closed = relay_closed,
                                     .max_streams = (int)r->info.max_streams,
                                     .metrics = &r->reg,
                                     .tick = &r->tick },
                        err);
    const int n_rows = (int)(sizeof relay_rows / sizeof relay_rows[0]);
    if (!r->net || metric_reg_add(&r->reg, relay_rows, n_rows, relay_fill, r, err) ||
        net_metrics_register(r->net, &r->reg, err)) {
        relay_destroy(r);
        return NULL;
    }
    /* the shared stream only: the relay encodes its clients' views itself */
    st = natsConnection_Subscribe(&r->snaps, r->nc, LINK_SUBJ_SNAP ".0", on_snap, r);
    if (st == NATS_OK) {
        /* a relay that falls this far behind drops snapshots (its clients see a gap and get
         * a keyframe) rather than grow; nats-server cuts a consumer slower than that */
        st = natsSubscription_SetPendingLimits(r->snaps, 64, 64 << 20);
    }
    if (st != NATS_OK) {
        gale_errf(err, GALE_E_IO, "nats: subscribe %s.0: %s", LINK_SUBJ_SNAP,
                  natsStatus_GetText(st));
        relay_destroy(r);
        return NULL;
    }
    return r;
}

int relay_port(const relay *r)
{
    return net_port(r->net);
}

int relay_run(relay *r)
{
    return net_run(r->net, 2000);
}

void relay_stop(relay *r)
{
    net_stop(r->net);
}

void relay_destroy(relay *r)
{
    if (!r) {
        return;
    }
    atomic_store(&r->closing, 1);
    if (r->snaps) {
        natsSubscription_Unsubscribe(r->snaps);
        natsSubscription_Destroy(r->snaps);
    }
    natsConnection_Close(r->nc); /* joins the delivery thread before net goes */
    net_destroy(r->net);
    relay_views_destroy(r->views);
    natsConnection_Destroy(r->nc);
    for (int i = 0; i < 64; i++) {
        free(r->bytes[i]);
    }
    free(r);
}
