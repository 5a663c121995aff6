/* The network module's life cycle and its one lws callback: see net.h. Creates the lws
 * context and the snapshot pool, hands published snapshots from the simulation thread to
 * the service thread, and routes each callback to net_ws.c or net_http.c. Everything but
 * net_snap_acquire, net_publish and net_stop runs on the one lws service thread. */
#include "mono.h"
#include "pi_mutex.h"
#include "net_int.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sys/resource.h>

#include "ctl.h"
#include "metric.h"
#include "wire.h"

static int net_callback(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                        size_t len)
{
    net_server *s = lws_context_user(lws_get_context(wsi));
    net_conn *c = user;

    switch (reason) {
    case LWS_CALLBACK_FILTER_NETWORK_CONNECTION:
        /* in: the accepted descriptor (user is lws' accept record, not a net_conn). The
         * kernel hands out the lowest free number, so one at or above the cap means the
         * descriptors below are all taken: refuse it now and keep the rest free. */
        if (s && (int)(lws_intptr_t)in >= s->lim.fd_cap) {
            atomic_fetch_add(&s->m.refused, 1);
            net_log(s, "connection refused at accept: descriptor %d, cap %d (RLIMIT_NOFILE %ld)",
                    (int)(lws_intptr_t)in, s->lim.fd_cap, s->lim.nofile);
            return 1;
        }
        return 0;

    case LWS_CALLBACK_TIMER:
        return net_ws_timer(s, c);

    case LWS_CALLBACK_EVENT_WAIT_CANCELLED:
        if (!s) {
            return 0;
        }
        if (atomic_load(&s->stop)) {
            for (net_conn *k = s->conns; k; k = k->next) {
                net_conn_close(s, k, WIRE_CLOSE_GOING_AWAY, "server shutting down");
            }
        }
        net_deliver_published(s);
        net_notice_deliver(s);
        return 0;

    case LWS_CALLBACK_HTTP:
        c->wsi = wsi;
        lws_get_peer_simple(wsi, c->peer, sizeof c->peer);
        return net_http_request(s, c, (const char *)in) ? -1 : 0;

    case LWS_CALLBACK_HTTP_WRITEABLE:
        return net_http_writeable(s, c) ? -1 : 0;

    case LWS_CALLBACK_HTTP_BODY_COMPLETION:
        return 0; /* a request body is discarded; net_http_writeable completes the reply */

    case LWS_CALLBACK_CLOSED_HTTP:
        if (c) {
            free(c->http_owned);
            c->http_owned = NULL;
        }
        return 0;

    case LWS_CALLBACK_ESTABLISHED:
        return net_ws_established(s, c, wsi);

    case LWS_CALLBACK_CLOSED:
        net_conn_free(s, c);
        return 0;

    case LWS_CALLBACK_SERVER_WRITEABLE:
        return net_ws_writeable(s, c);

    case LWS_CALLBACK_RECEIVE:
        return net_ws_receive(s, c, in, len);

    case LWS_CALLBACK_WS_PEER_INITIATED_CLOSE:
        return 0;

    default:
        break;
    }
    return lws_callback_http_dummy(wsi, reason, user, in, len);
}

/* --- metrics ---------------------------------------------------------------------------- */

/* The network's rows for /metrics; the gale_clients rows follow enum NET_ROLE_*. */
static const metric_row net_rows[] = {
    { "gale_snapshots_total", NULL, "Snapshots published.", METRIC_COUNTER, 0 },
    { "gale_bytes_sent_total", NULL, "WebSocket payload bytes sent.", METRIC_COUNTER, 0 },
    { "gale_frames_sent_total", NULL, "WebSocket messages sent.", METRIC_COUNTER, 0 },
    { "gale_frames_dropped_total", NULL, "Snapshots dropped from slow clients' queues.",
      METRIC_COUNTER, 0 },
    { "gale_snapshots_unsent_total", NULL, "Snapshots not published (pool or hand-over full).",
      METRIC_COUNTER, 0 },
    { "gale_bad_messages_total", NULL, "Client messages rejected.", METRIC_COUNTER, 0 },
    { "gale_laggards_closed_total", NULL, "Connections closed for taking nothing too long.",
      METRIC_COUNTER, 0 },
    { "gale_connections_total", NULL, "WebSocket connections accepted.", METRIC_COUNTER, 0 },
    { "gale_connections_refused_total", NULL,
      "Connections refused at the connection or descriptor limit.", METRIC_COUNTER, 0 },
    { "gale_hello_timeouts_total", NULL, "Connections closed for sending no hello in time.",
      METRIC_COUNTER, 0 },
    { "gale_clients", "role=\"none\"", "Connected WebSocket clients by role.", METRIC_GAUGE, 0 },
    { "gale_clients", "role=\"viewer\"", "Connected WebSocket clients by role.", METRIC_GAUGE, 0 },
    { "gale_clients", "role=\"kiosk\"", "Connected WebSocket clients by role.", METRIC_GAUGE, 0 },
    { "gale_clients", "role=\"wall-tile\"", "Connected WebSocket clients by role.", METRIC_GAUGE,
      0 },
    { "gale_clients", "role=\"load\"", "Connected WebSocket clients by role.", METRIC_GAUGE, 0 },
    { "gale_readers_decimated", NULL, "Connections sent fewer snapshots than published now.",
      METRIC_GAUGE, 0 },
    { "gale_decimations_total", NULL, "Times a slow reader's snapshot rate was lowered.",
      METRIC_COUNTER, 0 },
    { "gale_frame_waits_total", NULL,
      "Snapshots a connection skipped as they lacked the state frame it needed (encoded on "
      "demand).",
      METRIC_COUNTER, 0 },
};
#define NET_N_ROWS ((int)(sizeof net_rows / sizeof net_rows[0]))
_Static_assert(NET_N_ROWS == 13 + NET_ROLE_COUNT, "one gale_clients row per role");

static void net_fill(void *ctx, double *v)
{
    net_server *s = ctx;
    net_metrics *m = &s->m;
    v[0] = (double)atomic_load(&m->snapshots);
    v[1] = (double)atomic_load(&m->bytes_sent);
    v[2] = (double)atomic_load(&m->frames_sent);
    v[3] = (double)atomic_load(&m->frames_dropped);
    v[4] = (double)(atomic_load(&s->pool_exhausted) + atomic_load(&s->pub_overflow));
    v[5] = (double)atomic_load(&m->bad_messages);
    v[6] = (double)atomic_load(&m->laggards_closed);
    v[7] = (double)atomic_load(&m->connections_total);
    v[8] = (double)atomic_load(&m->refused);
    v[9] = (double)atomic_load(&m->hello_timeouts);
    for (int r = 0; r < NET_ROLE_COUNT; r++) {
        v[10 + r] = (double)atomic_load(&m->clients[r]);
    }
    v[10 + NET_ROLE_COUNT] = (double)atomic_load(&m->decimated);
    v[11 + NET_ROLE_COUNT] = (double)atomic_load(&m->decimations);
    v[12 + NET_ROLE_COUNT] = (double)atomic_load(&m->frame_waits);
}

int net_metrics_register(net_server *s, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, net_rows, NET_N_ROWS, net_fill, s, err);
}

/* --- limits ---------------------------------------------------------------------------- */

/* Descriptors open in this process now (Linux /proc/self/fd), -1 when unknown. */
static int open_fds(void)
{
    DIR *d = opendir("/proc/self/fd");
    if (!d) {
        return -1;
    }
    int n = 0;
    for (struct dirent *e; (e = readdir(d));) {
        n += e->d_name[0] != '.';
    }
    closedir(d);
    return n - 1; /* the directory's own descriptor */
}

/* Sizes the limits from RLIMIT_NOFILE once the context (and its listen socket) exists:
 * accepted sockets get descriptors below fd_cap; of the sockets that leaves room for,
 * 7/8 may be WebSocket connections, the rest HTTP (/healthz answers at the limit) and
 * upgrades refused with 4010. */
static void size_limits(net_server *s)
{
    struct rlimit rl;
    long nofile = 1024;
    if (!getrlimit(RLIMIT_NOFILE, &rl)) {
        nofile = rl.rlim_cur == RLIM_INFINITY || rl.rlim_cur > (rlim_t)NET_NOFILE_MAX
                     ? NET_NOFILE_MAX
                     : (long)rl.rlim_cur;
    }
    net_limits *l = &s->lim;
    l->nofile = nofile;
    l->requested = s->d.max_clients;
    l->fd_cap = (int)(nofile - NET_FD_RESERVE);
    int open = open_fds();
    int sockets = l->fd_cap - (open < 0 ? NET_FD_RESERVE : open);
    int ws = sockets - sockets / 8;
    l->max_clients = s->d.max_clients < ws ? s->d.max_clients : ws;
    if (l->max_clients < 1) {
        l->max_clients = 1;
    }
    if (l->fd_cap < 1) {
        l->fd_cap = 1;
    }
}

/* --- life cycle ------------------------------------------------------------------------- */

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

/* --- BUNDLE: a state frame and its extras in one message (PROTOCOL.md "BUNDLE") ------- */

size_t net_snap_buffer_cap(size_t snap_cap, size_t extra_cap)
{
    return snap_cap + WIRE_HEADER_BYTES + 1u + 4u * (1u + NET_SNAP_MAX_EXTRA) +
           NET_SNAP_MAX_EXTRA * extra_cap;
}

static size_t net_bundle_cap(const net_server *s)
{
    return net_snap_buffer_cap(s->d.snap_cap, s->d.extra_cap);
}

/* Sim thread, once per published snapshot (not per client): each state variant becomes a
 * BUNDLE of itself and the extras (a key-only extra only in the keyframe's); the extras
 * are then not sent on their own. */
static void net_bundle(net_server *s, net_snap *p)
{
    uint8_t *buf[3] = { p->key, p->delta1, p->delta2 };
    size_t *len[3] = { &p->key_len, &p->delta1_len, &p->delta2_len };
    for (int v = 0; v < 3; v++) {
        const uint8_t *more[NET_SNAP_MAX_EXTRA];
        size_t more_len[NET_SNAP_MAX_EXTRA];
        uint32_t n = 0;
        for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
            const bool key_only = (p->extra_key_only >> e) & 1u;
            if (!p->extra_len[e] || (key_only && v != 0)) {
                continue;
            }
            /* a bundle holds one frame of each type: in the keyframe's, a key-only extra
             * stands for any other of its type (the whole damage state holds the events) */
            bool shadowed = false;
            for (int k = 0; k < NET_SNAP_MAX_EXTRA && v == 0 && !key_only; k++) {
                shadowed = shadowed || (k != e && ((p->extra_key_only >> k) & 1u) &&
                                        p->extra_len[k] > 6 && p->extra_len[e] > 6 &&
                                        p->extra[k][6] == p->extra[e][6]);
            }
            if (!shadowed) {
                more[n] = p->extra[e];
                more_len[n++] = p->extra_len[e];
            }
        }
        gale_err e;
        if (n && *len[v] &&
            wire_bundle_wrap(buf[v], net_bundle_cap(s), len[v], more, more_len, n, &e)) {
            fprintf(stderr, "gale-server: snapshot %u: extras sent apart: %s\n", p->seq, e.msg);
            return; /* not reached: net_bundle_cap holds the largest state and every extra */
        }
    }
    for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
        p->extra_len[e] = 0;
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
    if (!s->d.hello_timeout_ms) {
        s->d.hello_timeout_ms = 5000;
    }
    if (!s->d.queue_frames) {
        s->d.queue_frames = 8;
    }
    if (s->d.stall_ms <= 0) {
        s->d.stall_ms = NET_STALL_MS;
    }
    if (s->d.snapshot_hz <= 0) {
        s->d.snapshot_hz = 30;
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
    pi_mutex_init(&s->pub_lock);
    pi_mutex_init(&s->bridge_lock);
    pi_mutex_init(&s->notice_lock);
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
        p->key = pre_alloc(net_bundle_cap(s));
        p->delta1 = pre_alloc(net_bundle_cap(s));
        p->delta2 = pre_alloc(net_bundle_cap(s));
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
    if (s->d.tls_cert) {
        /* https and wss only on this port (OpenSSL, as Debian builds lws): a handshake
         * that fails, or plain HTTP, ends that connection alone */
        info.options |= LWS_SERVER_OPTION_DO_SSL_GLOBAL_INIT;
        info.ssl_cert_filepath = s->d.tls_cert;
        info.ssl_private_key_filepath = s->d.tls_key;
    }
    lws_set_log_level(LLL_ERR, NULL);
    s->ctx = lws_create_context(&info);
    if (!s->ctx) {
        if (s->d.tls_cert) {
            gale_errf(err, GALE_E_IO, "net_create: cannot listen on %s:%d with TLS (certificate "
                      "%s, key %s: lws_create_context failed; check both files are PEM, "
                      "readable and match, and the port is free)",
                      s->d.iface ? s->d.iface : "*", s->d.port, s->d.tls_cert, s->d.tls_key);
        } else {
            gale_errf(err, GALE_E_IO, "net_create: cannot listen on %s:%d (lws_create_context "
                      "failed)", s->d.iface ? s->d.iface : "*", s->d.port);
        }
        goto fail;
    }
    s->vhost = lws_get_vhost_by_name(s->ctx, "default");
    s->port = s->vhost ? lws_get_vhost_listen_port(s->vhost) : s->d.port;
    size_limits(s);
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
        net_snap_unref(s->pub[i]);
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
    pthread_mutex_destroy(&s->bridge_lock);
    pthread_mutex_destroy(&s->notice_lock);
    free(s->notice);
    free(s);
}

int net_port(const net_server *s)
{
    return s->port;
}

net_limits net_get_limits(const net_server *s)
{
    return s->lim;
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
            p->extra_key_only = 0;
            for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
                p->extra_len[e] = 0;
            }
            return p;
        }
    }
    atomic_fetch_add(&s->pool_exhausted, 1);
    return NULL;
}

unsigned net_frames_wanted(net_server *s)
{
    if (s->d.published) {
        return NET_WANT_ALL;
    }
    const unsigned m = net_frames_wanted_apart(s);
    return (NET_WANT_SHARED(m) | NET_WANT_VIEWS(m)) & NET_WANT_ALL;
}

unsigned net_frames_wanted_apart(net_server *s)
{
    if (s->d.published) {
        return NET_WANT_BITS | NET_WANT_BITS << NET_WANT_VIEWS_SHIFT;
    }
    return atomic_load(&s->want_standing) | atomic_exchange(&s->want_asked, 0u);
}

uint32_t net_stream_due(net_server *s, uint32_t stream)
{
    return s->d.published ? 0u : atomic_load(&s->due_seq[stream % NET_DUE_SLOTS]);
}

void net_publish(net_server *s, net_snap *p)
{
    if (!s->d.separate_extras) {
        net_bundle(s, p);
    }
    if (s->d.published) {
        pthread_mutex_lock(&s->bridge_lock);
        s->d.published(s->d.published_user, p);
        pthread_mutex_unlock(&s->bridge_lock);
    }
    pthread_mutex_lock(&s->pub_lock);
    if (s->pub_n == s->pub_cap) {
        /* The service thread is not keeping up: the oldest waiting snapshot goes. */
        net_snap_unref(s->pub[0]);
        memmove(s->pub, s->pub + 1, sizeof s->pub[0] * (size_t)(s->pub_cap - 1));
        s->pub_n--;
        atomic_fetch_add(&s->pub_overflow, 1);
    }
    s->pub[s->pub_n++] = p;
    pthread_mutex_unlock(&s->pub_lock);
    if (!p->stream) {
        atomic_fetch_add(&s->m.snapshots, 1); /* view streams are counted by their encoder */
    }
    lws_cancel_service(s->ctx);
}

void net_reset_streams(net_server *s)
{
    atomic_store(&s->reset_streams, 1);
    lws_cancel_service(s->ctx);
}

void net_set_notice(net_server *s, const char *text, size_t len)
{
    char *t = malloc(len + 1);
    if (!t) {
        return; /* the last notice stands */
    }
    memcpy(t, text, len);
    t[len] = 0;
    pthread_mutex_lock(&s->notice_lock);
    free(s->notice);
    s->notice = t;
    s->notice_len = len;
    atomic_fetch_add(&s->notice_gen, 1);
    pthread_mutex_unlock(&s->notice_lock);
    lws_cancel_service(s->ctx);
}

void net_stop(net_server *s)
{
    atomic_store(&s->stop, 1);
    lws_cancel_service(s->ctx);
}

/* The drain's grace timer: nothing to do but wake lws_service. */
static void grace_wake(lws_sorted_usec_list_t *sul)
{
    (void)sul;
}

int net_run(net_server *s, int grace_ms)
{
    int n = 0;
    while (n >= 0 && !atomic_load(&s->stop)) {
        n = lws_service(s->ctx, 0);
    }
    /* Tell every client why (1001 going away) and give them grace_ms to close; the close
     * bound ends each within NET_CLOSE_BOUND_MS. lws_service waits for its next event or
     * timer: the last close (net_conn_free) and the grace timer wake it. */
    lws_cancel_service(s->ctx);
    uint64_t until = mono_ns() + (uint64_t)grace_ms * 1000000ull;
    lws_sul_schedule(s->ctx, 0, &s->grace_sul, grace_wake, (lws_usec_t)grace_ms * 1000);
    while (n >= 0 && s->n_conns > 0 && mono_ns() < until) {
        n = lws_service(s->ctx, 0);
    }
    lws_sul_cancel(&s->grace_sul);
    return n < 0 ? GALE_E_IO : GALE_OK;
}
