/* lws callbacks and the snapshot hand-over: see net.h. Shaped after the libwebsockets
 * v4.1.6 minimal examples (minimal-ws-server-ring: shared frames, per-connection
 * position, writeable callbacks; minimal-http-server-dynamic: headers then body in
 * HTTP_WRITEABLE). Everything here but net_snap_acquire, net_publish and net_stop runs
 * on the one lws service thread. */
#include "net.h"

#include <inttypes.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <libwebsockets.h>

#include "ctl.h"
#include "sendq.h"
#include "wire.h"

#define NET_PUB_MAX 16    /* published snapshots per stream waiting for the service thread */
#define NET_CTL_MAX 8     /* control replies queued per connection */
#define NET_HTTP_CHUNK 16384
#define NET_LOG_PER_S 20  /* rate limit of bad-input log lines */

/* One queued control (text) message; data has LWS_PRE bytes of headroom. */
typedef struct net_text {
    uint8_t *data; /* owned */
    size_t len;
} net_text;

/* Per-session data: one per WebSocket connection or HTTP transaction (lws allocates
 * and zeroes it; we free what it points to on close). */
typedef struct net_conn {
    struct net_conn *next, *prev; /* the server's list of WebSocket connections */
    struct lws *wsi;
    uint32_t id;
    char peer[64];
    bool is_ws;
    bool linked;
    int role;             /* NET_ROLE_*; NONE until the hello is accepted */
    sendq q;              /* net_snap*, one reference each */
    net_snap *cur;        /* snapshot being written, one reference */
    int cur_part;         /* 0 state, 1.. extras */
    uint32_t last_seq;    /* seq of the last state message written */
    uint32_t stream;      /* snapshot stream followed (net_peer.stream) */
    uint32_t last_stream; /* stream of the last state message written */
    int chain;            /* 0: holds nothing usable; 1: holds last_seq (a keyframe);
                             2: holds last_seq and last_seq - 1 */
    bool resync;          /* the client asked for a keyframe */
    net_text ctl[NET_CTL_MAX];
    int ctl_head, ctl_n;
    uint8_t *rx;          /* owned [max_message + 1]: reassembly of fragmented messages */
    size_t rx_len;
    bool rx_oversize;
    int close_code;       /* > 0: close at the next writeable */
    char close_reason[100];
    /* HTTP response */
    uint8_t *http_owned;  /* owned body (metrics) or NULL */
    const uint8_t *http_body;
    size_t http_len, http_off;
} net_conn;

struct net_server {
    net_desc d;
    struct lws_context *ctx;
    struct lws_vhost *vhost;
    struct lws_protocols protocols[2];
    int port;
    net_metrics m;
    atomic_int stop;
    uint32_t next_id;
    net_conn *conns; /* list head */
    int n_conns;
    /* snapshot pool and the hand-over queue (mutex: sim thread <-> service thread) */
    net_snap *pool;  /* owned [n_pool] */
    int n_pool;
    pthread_mutex_t pub_lock;
    net_snap **pub;   /* owned [pub_cap] */
    net_snap **batch; /* owned [pub_cap], service thread */
    int pub_n, pub_cap;
    atomic_ullong pool_exhausted;
    atomic_ullong pub_overflow;
    /* rate limit of the bad-input log */
    time_t log_sec;
    int log_n;
    unsigned log_suppressed;
    uint8_t http_buf[LWS_PRE + NET_HTTP_CHUNK];
};

static const char *const role_name[NET_ROLE_COUNT] = { "none", "viewer", "kiosk", "wall-tile",
                                                       "load" };

static uint64_t now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000ull + (uint64_t)t.tv_nsec;
}

/* "conn 7 127.0.0.1 tick 1234: <what>", at most NET_LOG_PER_S lines a second. */
static void conn_log(net_server *s, const net_conn *c, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void conn_log(net_server *s, const net_conn *c, const char *fmt, ...)
{
    time_t now = time(NULL);
    if (now != s->log_sec) {
        if (s->log_suppressed) {
            fprintf(stderr, "gale-server: %u more connection messages suppressed\n",
                    s->log_suppressed);
        }
        s->log_sec = now;
        s->log_n = 0;
        s->log_suppressed = 0;
    }
    if (++s->log_n > NET_LOG_PER_S) {
        s->log_suppressed++;
        return;
    }
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "gale-server: conn %" PRIu32 " %s tick %u: %s\n", c->id, c->peer,
            atomic_load(&s->m.current_tick), msg);
}

static void snap_unref(net_snap *p)
{
    atomic_fetch_sub_explicit(&p->refs, 1, memory_order_acq_rel);
}

static void snap_release_cb(void *item, void *ctx)
{
    net_server *s = ctx;
    atomic_fetch_add_explicit(&s->m.frames_dropped, 1, memory_order_relaxed);
    snap_unref(item);
}

static void conn_queue_owned(net_conn *c, uint8_t *b, size_t len);

/* Asks that c be closed with code/reason at its next writeable callback, after an error
 * message (ctl.h CTL_ERROR) that carries the same code and reason. */
static void conn_close(net_server *s, net_conn *c, int code, const char *reason)
{
    if (c->close_code) {
        return;
    }
    c->close_code = code;
    snprintf(c->close_reason, sizeof c->close_reason, "%s", reason);
    if (code != WIRE_CLOSE_GOING_AWAY) {
        conn_log(s, c, "closing %d (%s): %s", code, wire_close_name(code), reason);
    }
    ctl_msg m = { .type = CTL_ERROR };
    m.u.error.code = code;
    snprintf(m.u.error.message, sizeof m.u.error.message, "%s", reason);
    char buf[512];
    size_t n = 0;
    uint8_t *b;
    if (c->ctl_n < NET_CTL_MAX && !ctl_encode_into(&m, buf, sizeof buf, &n, NULL) &&
        (b = malloc(LWS_PRE + n))) {
        memcpy(b + LWS_PRE, buf, n);
        conn_queue_owned(c, b, n);
    }
    lws_callback_on_writable(c->wsi);
}

static void bad_input(net_server *s, net_conn *c, int code, const char *reason)
{
    atomic_fetch_add_explicit(&s->m.bad_messages, 1, memory_order_relaxed);
    conn_close(s, c, code, reason);
}

static void conn_queue_owned(net_conn *c, uint8_t *b, size_t len)
{
    c->ctl[(c->ctl_head + c->ctl_n) % NET_CTL_MAX] = (net_text){ .data = b, .len = len };
    c->ctl_n++;
}

/* Queues a text message (copied with LWS_PRE headroom). */
static int conn_queue_text(net_server *s, net_conn *c, const char *text, size_t len)
{
    if (c->ctl_n >= NET_CTL_MAX - 1) {
        /* one slot stays free for the error message a close sends */
        bad_input(s, c, WIRE_CLOSE_FULL, "control replies not read: too many requests in flight");
        return -1;
    }
    uint8_t *b = malloc(LWS_PRE + len + 1);
    if (!b) {
        conn_close(s, c, LWS_CLOSE_STATUS_UNEXPECTED_CONDITION, "server out of memory");
        return -1;
    }
    memcpy(b + LWS_PRE, text, len);
    conn_queue_owned(c, b, len);
    lws_callback_on_writable(c->wsi);
    return 0;
}

static void conn_free(net_server *s, net_conn *c)
{
    if (c->linked) {
        if (c->role != NET_ROLE_NONE && s->d.closed) {
            s->d.closed(s->d.control_user, &(net_peer){ .id = c->id, .addr = c->peer,
                                                        .role = c->role, .stream = c->stream });
        }
        if (c->prev) {
            c->prev->next = c->next;
        } else {
            s->conns = c->next;
        }
        if (c->next) {
            c->next->prev = c->prev;
        }
        c->linked = false;
        s->n_conns--;
        atomic_fetch_sub(&s->m.clients[c->role], 1);
    }
    if (c->cur) {
        snap_unref(c->cur);
        c->cur = NULL;
    }
    /* queued snapshots are released without counting them as dropped */
    c->q.release = NULL;
    for (int i = 0; i < c->q.count; i++) {
        snap_unref(c->q.slot[(c->q.head + i) % c->q.cap]);
    }
    c->q.count = 0;
    sendq_fini(&c->q);
    for (int i = 0; i < c->ctl_n; i++) {
        free(c->ctl[(c->ctl_head + i) % NET_CTL_MAX].data);
    }
    c->ctl_n = 0;
    free(c->rx);
    c->rx = NULL;
}

/* --- HTTP ----------------------------------------------------------------------------- */

static char *metrics_text(net_server *s, size_t *len)
{
    net_metrics *m = &s->m;
    size_t cap = 8192;
    char *b = malloc(cap);
    if (!b) {
        return NULL;
    }
    unsigned long long ticks = atomic_load(&m->ticks);
    int n = snprintf(
        b, cap,
        "# HELP gale_ticks_total Simulation ticks run.\n# TYPE gale_ticks_total counter\n"
        "gale_ticks_total %llu\n"
        "# HELP gale_tick_seconds_sum Wall time spent in ticks.\n"
        "# TYPE gale_tick_seconds_sum counter\ngale_tick_seconds_sum %.6f\n"
        "# HELP gale_tick_seconds_max Longest tick.\n# TYPE gale_tick_seconds_max gauge\n"
        "gale_tick_seconds_max %.6f\n"
        "# HELP gale_tick_overruns_total Ticks that ended after the next one was due.\n"
        "# TYPE gale_tick_overruns_total counter\ngale_tick_overruns_total %llu\n"
        "# HELP gale_snapshots_total Snapshots published.\n"
        "# TYPE gale_snapshots_total counter\ngale_snapshots_total %llu\n"
        "# HELP gale_leaves_shed_total Leaf seeds emitted.\n"
        "# TYPE gale_leaves_shed_total counter\ngale_leaves_shed_total %llu\n"
        "# HELP gale_bytes_sent_total WebSocket payload bytes sent.\n"
        "# TYPE gale_bytes_sent_total counter\ngale_bytes_sent_total %llu\n"
        "# HELP gale_frames_sent_total WebSocket messages sent.\n"
        "# TYPE gale_frames_sent_total counter\ngale_frames_sent_total %llu\n"
        "# HELP gale_frames_dropped_total Snapshots dropped from slow clients' queues.\n"
        "# TYPE gale_frames_dropped_total counter\ngale_frames_dropped_total %llu\n"
        "# HELP gale_snapshots_unsent_total Snapshots not published (pool or hand-over full).\n"
        "# TYPE gale_snapshots_unsent_total counter\ngale_snapshots_unsent_total %llu\n"
        "# HELP gale_bad_messages_total Client messages rejected.\n"
        "# TYPE gale_bad_messages_total counter\ngale_bad_messages_total %llu\n"
        "# HELP gale_laggards_closed_total Connections closed for falling too far behind.\n"
        "# TYPE gale_laggards_closed_total counter\ngale_laggards_closed_total %llu\n"
        "# HELP gale_connections_total WebSocket connections accepted.\n"
        "# TYPE gale_connections_total counter\ngale_connections_total %llu\n"
        "# HELP gale_view_snapshots_total Snapshots encoded for per-client views.\n"
        "# TYPE gale_view_snapshots_total counter\ngale_view_snapshots_total %llu\n"
        "# HELP gale_view_encode_seconds_sum Time spent encoding them.\n"
        "# TYPE gale_view_encode_seconds_sum counter\ngale_view_encode_seconds_sum %.6f\n"
        "# HELP gale_clients Connected WebSocket clients by role.\n# TYPE gale_clients gauge\n",
        ticks, (double)atomic_load(&m->tick_ns_sum) * 1e-9,
        (double)atomic_load(&m->tick_ns_max) * 1e-9, atomic_load(&m->overruns),
        atomic_load(&m->snapshots), atomic_load(&m->leaves_shed), atomic_load(&m->bytes_sent),
        atomic_load(&m->frames_sent), atomic_load(&m->frames_dropped),
        atomic_load(&s->pool_exhausted) + atomic_load(&s->pub_overflow),
        atomic_load(&m->bad_messages), atomic_load(&m->laggards_closed),
        atomic_load(&m->connections_total), atomic_load(&m->view_snapshots),
        (double)atomic_load(&m->view_encode_ns) * 1e-9);
    for (int r = 0; r < NET_ROLE_COUNT && n > 0 && (size_t)n < cap; r++) {
        n += snprintf(b + n, cap - (size_t)n, "gale_clients{role=\"%s\"} %d\n", role_name[r],
                      atomic_load(&m->clients[r]));
    }
    if (n < 0 || (size_t)n >= cap) {
        free(b);
        return NULL;
    }
    *len = (size_t)n;
    return b;
}

static int http_respond(net_server *s, net_conn *c, unsigned code, const char *type,
                        const uint8_t *body, size_t len)
{
    uint8_t hdr[LWS_PRE + 512], *start = hdr + LWS_PRE, *p = start, *end = hdr + sizeof hdr;
    c->http_body = body;
    c->http_len = len;
    c->http_off = 0;
    (void)s;
    if (lws_add_http_common_headers(c->wsi, code, type, (lws_filepos_t)len, &p, end) ||
        lws_finalize_write_http_header(c->wsi, start, &p, end)) {
        return 1;
    }
    lws_callback_on_writable(c->wsi);
    return 0;
}

static int http_request(net_server *s, net_conn *c, const char *uri)
{
    static const char not_found[] = "not found\n";
    static const char bad_method[] = "only GET is served\n";
    if (lws_hdr_total_length(c->wsi, WSI_TOKEN_GET_URI) <= 0) {
        return http_respond(s, c, HTTP_STATUS_METHOD_NOT_ALLOWED, "text/plain",
                            (const uint8_t *)bad_method, sizeof bad_method - 1);
    }
    if (!strcmp(uri, "/healthz")) {
        char t[128];
        int n = snprintf(t, sizeof t, "ok tick %u clients %d\n",
                         atomic_load(&s->m.current_tick), s->n_conns);
        c->http_owned = malloc((size_t)n + 1);
        if (!c->http_owned) {
            return 1;
        }
        memcpy(c->http_owned, t, (size_t)n + 1);
        return http_respond(s, c, HTTP_STATUS_OK, "text/plain", c->http_owned, (size_t)n);
    }
    if (!strcmp(uri, "/metrics")) {
        size_t len = 0;
        char *t = metrics_text(s, &len);
        if (!t) {
            return 1;
        }
        c->http_owned = (uint8_t *)t;
        return http_respond(s, c, HTTP_STATUS_OK, "text/plain; version=0.0.4", c->http_owned,
                            len);
    }
    if (!strncmp(uri, "/assets/", 8)) {
        const char *h = uri + 8;
        for (int i = 0; i < s->d.n_assets; i++) {
            const net_asset *a = &s->d.assets[i];
            size_t hl = strlen(a->hash);
            if (a->bytes && hl && !strncmp(h, a->hash, hl) &&
                (!strcmp(h + hl, ".gasset") || !h[hl])) {
                return http_respond(s, c, HTTP_STATUS_OK, "application/octet-stream", a->bytes,
                                    a->len);
            }
        }
    }
    return http_respond(s, c, HTTP_STATUS_NOT_FOUND, "text/plain", (const uint8_t *)not_found,
                        sizeof not_found - 1);
}

static int http_writeable(net_server *s, net_conn *c)
{
    size_t left = c->http_len - c->http_off;
    size_t n = left < NET_HTTP_CHUNK ? left : NET_HTTP_CHUNK;
    bool last = n == left;
    if (n) {
        memcpy(s->http_buf + LWS_PRE, c->http_body + c->http_off, n);
    }
    if (lws_write(c->wsi, s->http_buf + LWS_PRE, n,
                  last ? LWS_WRITE_HTTP_FINAL : LWS_WRITE_HTTP) != (int)n) {
        return 1;
    }
    c->http_off += n;
    if (!last) {
        lws_callback_on_writable(c->wsi);
        return 0;
    }
    free(c->http_owned);
    c->http_owned = NULL;
    return lws_http_transaction_completed(c->wsi) ? -1 : 0;
}

/* --- WebSocket ------------------------------------------------------------------------ */

static void deliver_published(net_server *s)
{
    net_snap **batch = s->batch;
    int n;
    pthread_mutex_lock(&s->pub_lock);
    n = s->pub_n;
    memcpy(batch, s->pub, sizeof batch[0] * (size_t)n);
    s->pub_n = 0;
    pthread_mutex_unlock(&s->pub_lock);
    for (int i = 0; i < n; i++) {
        net_snap *p = batch[i];
        for (net_conn *c = s->conns; c; c = c->next) {
            if (c->role == NET_ROLE_NONE || c->close_code || c->stream != p->stream) {
                continue;
            }
            atomic_fetch_add_explicit(&p->refs, 1, memory_order_relaxed);
            sendq_push(&c->q, p);
            if (c->q.drop_streak >= (uint32_t)s->d.lag_limit) {
                char why[100];
                snprintf(why, sizeof why, "too slow: %u snapshots dropped in a row",
                         c->q.drop_streak);
                atomic_fetch_add(&s->m.laggards_closed, 1);
                sendq_clear(&c->q);
                conn_close(s, c, WIRE_CLOSE_SLOW, why);
                continue;
            }
            lws_callback_on_writable(c->wsi);
        }
        snap_unref(p); /* the publisher's reference */
    }
}

static int ws_write(net_server *s, net_conn *c, uint8_t *data, size_t len,
                    enum lws_write_protocol kind)
{
    int n = lws_write(c->wsi, data, len, kind);
    if (n < (int)len) {
        return -1; /* the peer is gone: lws closes the connection */
    }
    atomic_fetch_add_explicit(&s->m.bytes_sent, len, memory_order_relaxed);
    atomic_fetch_add_explicit(&s->m.frames_sent, 1, memory_order_relaxed);
    return 0;
}

static int ws_writeable(net_server *s, net_conn *c)
{
    if (c->close_code && !c->ctl_n) {
        lws_close_reason(c->wsi, (enum lws_close_status)c->close_code,
                         (unsigned char *)c->close_reason, strlen(c->close_reason));
        return -1;
    }
    if (c->ctl_n) {
        /* Control replies first: they are few and small, and a hello's scene comes before
         * any state. */
        net_text t = c->ctl[c->ctl_head];
        c->ctl_head = (c->ctl_head + 1) % NET_CTL_MAX;
        c->ctl_n--;
        int rc = ws_write(s, c, t.data + LWS_PRE, t.len, LWS_WRITE_TEXT);
        free(t.data);
        if (rc) {
            return -1;
        }
        if (c->ctl_n || c->q.count || c->close_code) {
            lws_callback_on_writable(c->wsi);
        }
        return 0;
    }
    if (!c->cur) {
        c->cur = sendq_pop(&c->q);
        c->cur_part = 0;
        if (!c->cur) {
            return 0;
        }
    }
    net_snap *p = c->cur;
    int rc;
    if (c->cur_part == 0) {
        bool next = !c->resync && c->chain > 0 && p->seq == c->last_seq + 1u &&
                    p->stream == c->last_stream;
        if (next && c->chain >= 2 && p->delta2_len) {
            rc = ws_write(s, c, p->delta2, p->delta2_len, LWS_WRITE_BINARY);
            c->chain = 2;
        } else if (next && p->delta1_len) {
            rc = ws_write(s, c, p->delta1, p->delta1_len, LWS_WRITE_BINARY);
            c->chain = 2;
        } else {
            rc = ws_write(s, c, p->key, p->key_len, LWS_WRITE_BINARY);
            c->chain = 1;
        }
        c->resync = false;
        c->last_seq = p->seq;
        c->last_stream = p->stream;
        c->cur_part = 1;
    } else {
        int e = c->cur_part - 1;
        rc = ws_write(s, c, p->extra[e], p->extra_len[e], LWS_WRITE_BINARY);
        c->cur_part++;
    }
    if (rc) {
        return -1;
    }
    while (c->cur_part >= 1 && c->cur_part <= NET_SNAP_MAX_EXTRA &&
           !p->extra_len[c->cur_part - 1]) {
        c->cur_part++;
    }
    if (c->cur_part > NET_SNAP_MAX_EXTRA) {
        snap_unref(p);
        c->cur = NULL;
    }
    if (c->cur || c->q.count || c->ctl_n) {
        lws_callback_on_writable(c->wsi);
    }
    return 0;
}

static int ws_receive(net_server *s, net_conn *c, const void *in, size_t len)
{
    if (c->close_code) {
        return 0; /* already on its way out: ignore what follows */
    }
    if (lws_frame_is_binary(c->wsi)) {
        bad_input(s, c, WIRE_CLOSE_BINARY,
                  "binary message: only JSON text control messages are accepted");
        return 0;
    }
    if (c->rx_len + len > s->d.max_message) {
        char why[100];
        snprintf(why, sizeof why, "message too large: expected <= %zu bytes, got %zu+",
                 s->d.max_message, c->rx_len + len);
        bad_input(s, c, WIRE_CLOSE_TOO_BIG, why);
        return 0;
    }
    memcpy(c->rx + c->rx_len, in, len);
    c->rx_len += len;
    if (!lws_is_final_fragment(c->wsi) || lws_remaining_packet_payload(c->wsi)) {
        return 0;
    }
    c->rx[c->rx_len] = 0;
    char *reply = NULL, why[100];
    size_t reply_len = 0;
    why[0] = 0;
    net_peer peer = { .id = c->id, .addr = c->peer, .role = c->role, .stream = c->stream };
    int code = s->d.control(s->d.control_user, &peer, (const char *)c->rx, c->rx_len, &reply,
                            &reply_len, why, sizeof why);
    c->rx_len = 0;
    if (code) {
        free(reply);
        bad_input(s, c, code, why[0] ? why : "rejected");
        return 0;
    }
    if (peer.role != c->role && peer.role > NET_ROLE_NONE && peer.role < NET_ROLE_COUNT) {
        atomic_fetch_sub(&s->m.clients[c->role], 1);
        atomic_fetch_add(&s->m.clients[peer.role], 1);
        c->role = peer.role;
    }
    c->resync = c->resync || peer.resync;
    c->stream = peer.stream; /* a frame of another stream than the last is a keyframe */
    if (reply) {
        conn_queue_text(s, c, reply, reply_len);
        free(reply);
    }
    return 0;
}

static int net_callback(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                        size_t len)
{
    net_server *s = lws_context_user(lws_get_context(wsi));
    net_conn *c = user;

    switch (reason) {
    case LWS_CALLBACK_EVENT_WAIT_CANCELLED:
        if (!s) {
            return 0;
        }
        if (atomic_load(&s->stop)) {
            for (net_conn *k = s->conns; k; k = k->next) {
                conn_close(s, k, WIRE_CLOSE_GOING_AWAY, "server shutting down");
            }
        }
        deliver_published(s);
        return 0;

    case LWS_CALLBACK_HTTP:
        c->wsi = wsi;
        lws_get_peer_simple(wsi, c->peer, sizeof c->peer);
        return http_request(s, c, (const char *)in) ? -1 : 0;

    case LWS_CALLBACK_HTTP_WRITEABLE:
        return http_writeable(s, c) ? -1 : 0;

    case LWS_CALLBACK_CLOSED_HTTP:
        if (c) {
            free(c->http_owned);
            c->http_owned = NULL;
        }
        return 0;

    case LWS_CALLBACK_ESTABLISHED: {
        memset(c, 0, sizeof *c);
        c->wsi = wsi;
        c->id = ++s->next_id;
        c->is_ws = true;
        lws_get_peer_simple(wsi, c->peer, sizeof c->peer);
        gale_err e;
        c->rx = malloc(s->d.max_message + 1);
        if (!c->rx || sendq_init(&c->q, s->d.queue_frames, snap_release_cb, s, &e)) {
            free(c->rx);
            c->rx = NULL;
            return -1;
        }
        int fd = lws_get_socket_fd(wsi), one = 1;
        if (s->d.sndbuf > 0) {
            setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &s->d.sndbuf, sizeof s->d.sndbuf);
        }
        /* Small state frames back to back: no Nagle wait for the previous one's ACK. */
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        c->next = s->conns;
        if (s->conns) {
            s->conns->prev = c;
        }
        s->conns = c;
        c->linked = true;
        s->n_conns++;
        atomic_fetch_add(&s->m.clients[NET_ROLE_NONE], 1);
        atomic_fetch_add(&s->m.connections_total, 1);
        if (atomic_load(&s->stop)) {
            conn_close(s, c, WIRE_CLOSE_GOING_AWAY, "server shutting down");
        } else if (s->n_conns > s->d.max_clients) {
            conn_close(s, c, WIRE_CLOSE_FULL, "server full: try again later");
        }
        return 0;
    }

    case LWS_CALLBACK_CLOSED:
        conn_free(s, c);
        return 0;

    case LWS_CALLBACK_SERVER_WRITEABLE:
        return ws_writeable(s, c);

    case LWS_CALLBACK_RECEIVE:
        return ws_receive(s, c, in, len);

    case LWS_CALLBACK_WS_PEER_INITIATED_CLOSE:
        return 0;

    default:
        break;
    }
    return lws_callback_http_dummy(wsi, reason, user, in, len);
}

/* --- life cycle ----------------------------------------------------------------------- */

/* A buffer of cap bytes with LWS_PRE bytes of headroom before the returned pointer. */
static uint8_t *pre_alloc(size_t cap)
{
    uint8_t *b = malloc(LWS_PRE + cap);
    return b ? b + LWS_PRE : NULL;
}

static void pre_free(uint8_t *p)
{
    if (p) {
        free(p - LWS_PRE);
    }
}

net_server *net_create(const net_desc *desc, gale_err *err)
{
    net_server *s = calloc(1, sizeof *s);
    if (!s) {
        gale_errf(err, GALE_E_NOMEM, "net_create: no memory");
        return NULL;
    }
    s->d = *desc;
    if (!s->d.port) {
        s->d.port = 8080;
    }
    if (s->d.port < 0) {
        s->d.port = 0; /* lws: the kernel picks */
    }
    if (!s->d.max_clients) {
        s->d.max_clients = 2048;
    }
    if (!s->d.queue_frames) {
        s->d.queue_frames = 8;
    }
    if (!s->d.lag_limit) {
        s->d.lag_limit = 90;
    }
    if (!s->d.max_message) {
        s->d.max_message = CTL_MAX_CLIENT_BYTES;
    }
    if (!s->d.sndbuf) {
        s->d.sndbuf = 32768;
    }
    if (!s->d.extra_cap) {
        s->d.extra_cap = 65536;
    }
    pthread_mutex_init(&s->pub_lock, NULL);
    if (!s->d.control || !s->d.snap_cap) {
        gale_errf(err, GALE_E_ARG, "net_create: control callback and snap_cap are required");
        goto fail;
    }
    if (s->d.max_streams < 0) {
        s->d.max_streams = 0;
    }
    /* Pool: per stream every connection's queue window and the hand-over queue, and room
     * for snapshots held by connections stuck mid-write (they are culled as laggards). */
    const int streams = 1 + s->d.max_streams;
    s->n_pool = streams * (s->d.queue_frames + NET_PUB_MAX) + 48;
    s->pool = calloc((size_t)s->n_pool, sizeof *s->pool);
    s->pub_cap = streams * NET_PUB_MAX;
    s->pub = calloc((size_t)s->pub_cap, sizeof *s->pub);
    s->batch = calloc((size_t)s->pub_cap, sizeof *s->batch);
    if (!s->pool || !s->pub || !s->batch) {
        gale_errf(err, GALE_E_NOMEM, "net_create: no memory for the snapshot pool");
        goto fail;
    }
    for (int i = 0; i < s->n_pool; i++) {
        net_snap *p = &s->pool[i];
        p->cap = s->d.snap_cap;
        p->extra_cap = s->d.extra_cap;
        p->key = pre_alloc(p->cap);
        p->delta1 = pre_alloc(p->cap);
        p->delta2 = pre_alloc(p->cap);
        bool ok = p->key && p->delta1 && p->delta2;
        for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
            p->extra[e] = pre_alloc(p->extra_cap);
            ok = ok && p->extra[e];
        }
        if (!ok) {
            gale_errf(err, GALE_E_NOMEM, "net_create: no memory for %d snapshots of %zu bytes",
                      s->n_pool, p->cap);
            goto fail;
        }
    }

    s->protocols[0] = (struct lws_protocols){
        .name = "gale",
        .callback = net_callback,
        .per_session_data_size = sizeof(net_conn),
        .rx_buffer_size = 65536,
    };
    struct lws_context_creation_info info;
    memset(&info, 0, sizeof info);
    info.port = s->d.port;
    info.iface = s->d.iface;
    info.protocols = s->protocols;
    info.user = s;
    info.options = LWS_SERVER_OPTION_DISABLE_IPV6;
    info.timeout_secs = 10;
    lws_set_log_level(LLL_ERR, NULL);
    s->ctx = lws_create_context(&info);
    if (!s->ctx) {
        gale_errf(err, GALE_E_IO, "net_create: cannot listen on %s:%d (lws_create_context failed)",
                  s->d.iface ? s->d.iface : "*", s->d.port);
        goto fail;
    }
    s->vhost = lws_get_vhost_by_name(s->ctx, "default");
    s->port = s->vhost ? lws_get_vhost_listen_port(s->vhost) : s->d.port;
    return s;
fail:
    net_destroy(s);
    return NULL;
}

void net_destroy(net_server *s)
{
    if (!s) {
        return;
    }
    if (s->ctx) {
        lws_context_destroy(s->ctx); /* closes every connection: CLOSED frees their state */
    }
    for (int i = 0; i < s->pub_n; i++) {
        snap_unref(s->pub[i]);
    }
    for (int i = 0; s->pool && i < s->n_pool; i++) {
        pre_free(s->pool[i].key);
        pre_free(s->pool[i].delta1);
        pre_free(s->pool[i].delta2);
        for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
            pre_free(s->pool[i].extra[e]);
        }
    }
    free(s->pool);
    free(s->pub);
    free(s->batch);
    pthread_mutex_destroy(&s->pub_lock);
    free(s);
}

int net_port(const net_server *s)
{
    return s->port;
}

net_metrics *net_get_metrics(net_server *s)
{
    return &s->m;
}

net_snap *net_snap_acquire(net_server *s)
{
    for (int i = 0; i < s->n_pool; i++) {
        int zero = 0;
        if (atomic_compare_exchange_strong(&s->pool[i].refs, &zero, 1)) {
            net_snap *p = &s->pool[i];
            p->key_len = p->delta1_len = p->delta2_len = 0;
            p->stream = 0;
            for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
                p->extra_len[e] = 0;
            }
            return p;
        }
    }
    atomic_fetch_add(&s->pool_exhausted, 1);
    return NULL;
}

void net_publish(net_server *s, net_snap *p)
{
    pthread_mutex_lock(&s->pub_lock);
    if (s->pub_n == s->pub_cap) {
        /* The service thread is not keeping up: the oldest waiting snapshot goes. */
        snap_unref(s->pub[0]);
        memmove(s->pub, s->pub + 1, sizeof s->pub[0] * (size_t)(s->pub_cap - 1));
        s->pub_n--;
        atomic_fetch_add(&s->pub_overflow, 1);
    }
    s->pub[s->pub_n++] = p;
    pthread_mutex_unlock(&s->pub_lock);
    if (!p->stream) {
        atomic_fetch_add(&s->m.snapshots, 1); /* view streams: view_snapshots */
    }
    lws_cancel_service(s->ctx);
}

void net_stop(net_server *s)
{
    atomic_store(&s->stop, 1);
    lws_cancel_service(s->ctx);
}

int net_run(net_server *s, int grace_ms)
{
    int n = 0;
    while (n >= 0 && !atomic_load(&s->stop)) {
        n = lws_service(s->ctx, 0);
    }
    /* Tell every client why (1001 going away) and give them grace_ms to close. */
    lws_cancel_service(s->ctx);
    uint64_t until = now_ns() + (uint64_t)grace_ms * 1000000ull;
    while (n >= 0 && s->n_conns > 0 && now_ns() < until) {
        n = lws_service(s->ctx, 0);
    }
    return n < 0 ? GALE_E_IO : GALE_OK;
}
