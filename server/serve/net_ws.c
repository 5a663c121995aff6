/* WebSocket connections: per-connection state, control replies and close, the hand-over
 * of published snapshots to each connection's queue, and the writeable/receive callbacks
 * (see net.h; shaped after lws minimal-ws-server-ring). Runs on the lws service thread. */
#include "mono.h"
#include "net_int.h"
#include "net_rate.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include "ctl.h"
#include "wire.h"

/* The shared limit of the connection log: true when one more line may go out this second. */
static bool log_allowed(net_server *s)
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
        return false;
    }
    return true;
}

void net_conn_log(net_server *s, const net_conn *c, const char *fmt, ...)
{
    if (!log_allowed(s)) {
        return;
    }
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "gale-server: conn %" PRIu32 " %s tick %u: %s\n", c->id, c->peer,
            net_tick(s), msg);
}

void net_log(net_server *s, const char *fmt, ...)
{
    if (!log_allowed(s)) {
        return;
    }
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "gale-server: %s\n", msg);
}

void net_snap_unref(net_snap *p)
{
    atomic_fetch_sub_explicit(&p->refs, 1, memory_order_acq_rel);
}

static void snap_release_cb(void *item, void *ctx)
{
    net_server *s = ctx;
    atomic_fetch_add_explicit(&s->m.frames_dropped, 1, memory_order_relaxed);
    net_snap_unref(item);
}

static void conn_queue_owned(net_conn *c, uint8_t *b, size_t len);

/* Want bits (net.h NET_WANT_*) of a connection following stream, where the publisher
 * reads them: the shared stream's in the low bits, the view streams' above. */
static unsigned want_of(uint32_t stream, unsigned bits)
{
    return stream ? bits << NET_WANT_VIEWS_SHIFT : bits;
}

void net_conn_close(net_server *s, net_conn *c, int code, const char *reason)
{
    if (c->close_code) {
        return;
    }
    c->close_code = code;
    snprintf(c->close_reason, sizeof c->close_reason, "%s", reason);
    if (code != WIRE_CLOSE_GOING_AWAY) {
        net_conn_log(s, c, "closing %d (%s): %s", code, wire_close_name(code), reason);
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
    /* A peer that never reads never makes the socket writeable: the close bound ends it
     * anyway (net_ws_timer), so it holds its descriptor and slot no longer than that. */
    lws_set_timer_usecs(c->wsi, (lws_usec_t)NET_CLOSE_BOUND_MS * 1000);
}

static void bad_input(net_server *s, net_conn *c, int code, const char *reason)
{
    atomic_fetch_add_explicit(&s->m.bad_messages, 1, memory_order_relaxed);
    net_conn_close(s, c, code, reason);
}

static void conn_queue_owned(net_conn *c, uint8_t *b, size_t len)
{
    c->ctl[(c->ctl_head + c->ctl_n) % NET_CTL_MAX] = (net_text){ .data = b, .len = len };
    c->ctl_n++;
}

/* Queues a text message (copied with LWS_PRE headroom), continued by tail when it is not
 * NULL (the caller's reference to it is taken, also on failure). */
static int conn_queue_text(net_server *s, net_conn *c, const char *text, size_t len,
                           net_shared *tail)
{
    if (c->ctl_n >= NET_CTL_MAX - 1) {
        net_shared_unref(tail);
        /* one slot stays free for the error message a close sends */
        char why[100];
        snprintf(why, sizeof why, "too many messages: replies not read, expected <= %d in flight",
                 NET_CTL_MAX - 1);
        bad_input(s, c, WIRE_CLOSE_RATE, why);
        return -1;
    }
    uint8_t *b = malloc(LWS_PRE + len + 1);
    if (!b) {
        net_shared_unref(tail);
        net_conn_close(s, c, LWS_CLOSE_STATUS_UNEXPECTED_CONDITION, "server out of memory");
        return -1;
    }
    memcpy(b + LWS_PRE, text, len);
    conn_queue_owned(c, b, len);
    c->ctl[(c->ctl_head + c->ctl_n - 1) % NET_CTL_MAX].tail = tail;
    lws_callback_on_writable(c->wsi);
    return 0;
}

int net_send_text(net_server *s, uint32_t conn, const char *text, size_t len)
{
    for (net_conn *c = s->conns; c; c = c->next) {
        if (c->id == conn) {
            return c->close_code ? -1 : conn_queue_text(s, c, text, len, NULL);
        }
    }
    return -1;
}

void net_ws_notice(net_server *s, net_conn *c)
{
    const unsigned gen = atomic_load(&s->notice_gen);
    if (!gen || c->notice_gen == gen || c->role == NET_ROLE_NONE || c->close_code) {
        return;
    }
    pthread_mutex_lock(&s->notice_lock);
    char *t = malloc(s->notice_len + 1);
    size_t n = s->notice_len;
    if (t) {
        memcpy(t, s->notice, n);
    }
    c->notice_gen = atomic_load(&s->notice_gen);
    pthread_mutex_unlock(&s->notice_lock);
    if (t) {
        conn_queue_text(s, c, t, n, NULL);
        free(t);
    }
}

void net_notice_deliver(net_server *s)
{
    const unsigned gen = atomic_load(&s->notice_gen);
    if (gen == s->notice_done) {
        return;
    }
    s->notice_done = gen;
    for (net_conn *c = s->conns; c; c = c->next) {
        net_ws_notice(s, c);
    }
}

void net_conn_free(net_server *s, net_conn *c)
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
        if (c->decim > 1) {
            atomic_fetch_sub(&s->m.decimated, 1);
        }
        atomic_fetch_sub(&s->m.clients[c->role], 1);
        if (atomic_load(&s->stop) && !s->n_conns) {
            lws_cancel_service(s->ctx); /* the drain is done: wake net_run */
        }
    }
    if (c->cur) {
        net_snap_unref(c->cur);
        c->cur = NULL;
    }
    /* queued snapshots are released without counting them as dropped */
    c->q.release = NULL;
    for (int i = 0; i < c->q.count; i++) {
        net_snap_unref(c->q.slot[(c->q.head + i) % c->q.cap]);
    }
    c->q.count = 0;
    sendq_fini(&c->q);
    for (int i = 0; i < c->ctl_n; i++) {
        net_text *t = &c->ctl[(c->ctl_head + i) % NET_CTL_MAX];
        free(t->data);
        net_shared_unref(t->tail);
    }
    c->ctl_n = 0;
    free(c->rx);
    c->rx = NULL;
}

int net_ws_established(net_server *s, net_conn *c, struct lws *wsi)
{
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
    c->tokens = NET_MSG_BURST;
    c->tokens_ns = mono_ns();
    c->decim = 1;
    c->rate_ns = c->ahead_ns = c->take_ns = c->tokens_ns;
    if (s->d.hello_timeout_ms > 0) {
        lws_set_timer_usecs(wsi, (lws_usec_t)s->d.hello_timeout_ms * 1000);
    }
    if (atomic_load(&s->stop)) {
        net_conn_close(s, c, WIRE_CLOSE_GOING_AWAY, "server shutting down");
    } else if (s->n_conns > s->lim.max_clients) {
        atomic_fetch_add(&s->m.refused, 1);
        char why[100];
        snprintf(why, sizeof why, "server full: %d connections, try again later",
                 s->lim.max_clients);
        net_conn_close(s, c, WIRE_CLOSE_FULL, why);
    }
    return 0;
}

/* Sets c's snapshot rate to one in decim, keeping the decimated gauge. */
static void set_rate(net_server *s, net_conn *c, int decim, uint64_t now)
{
    if ((c->decim > 1) != (decim > 1)) {
        atomic_fetch_add(&s->m.decimated, decim > 1 ? 1 : -1);
    }
    c->decim = decim;
    c->rate_ns = now;
    c->ahead_ns = now;
}

/* Offers snapshot p to c (server/SERVER.md "Slow readers"). A decimated reader takes one
 * snapshot in c->decim; what it skips it never sees, so each one it gets follows a gap
 * and goes out as its KEYFRAME (net_ws_writeable sends a delta only on the very next seq):
 * no delta ever refers to a snapshot the reader lacks. The backlog at each offer steers
 * the rate: a full queue (at full rate) or a snapshot still waiting from the interval
 * before (decimated) lowers it; nothing waiting for NET_RATE_UP_MS raises it. Only a
 * reader that takes nothing at all for stall_ms is closed. */
static void deliver_one(net_server *s, net_conn *c, net_snap *p, uint64_t now)
{
    if (c->decim > 1 && c->queued_any && c->queued_stream == p->stream &&
        p->seq - c->queued_seq < (uint32_t)c->decim) {
        return; /* not its turn */
    }
    if (c->decim > 1 && !p->key_len) {
        atomic_fetch_or(&s->want_asked, want_of(p->stream, NET_WANT_KEY));
        return; /* its turn comes with the next keyframe */
    }
    const int waiting = c->q.count + (c->cur != NULL);
    if (!waiting) {
        c->take_ns = now; /* idle, not stalled */
    } else if (now > c->take_ns && now - c->take_ns > (uint64_t)s->d.stall_ms * 1000000u) {
        char why[100];
        snprintf(why, sizeof why, "too slow: took nothing for %.1f s",
                 (double)(now - c->take_ns) * 1e-9);
        atomic_fetch_add(&s->m.laggards_closed, 1);
        sendq_clear(&c->q);
        net_conn_close(s, c, WIRE_CLOSE_SLOW, why);
        return;
    }
    /* (another stream's sizes, a view's after the whole scene's, stand in until its own
       are seen: a reader that falls behind as it changes streams has a ratio at once) */
    c->key_bytes = net_rate_key_bytes(p) ? net_rate_key_bytes(p) : c->key_bytes;
    c->delta_bytes = net_rate_delta_bytes(p) ? net_rate_delta_bytes(p) : c->delta_bytes;
    const float key_per_delta = net_rate_key_per_delta(c->key_bytes, c->delta_bytes);
    if (!c->took_ns || now - c->took_ns >= 1000000000ull) {
        c->take_bytes_s = c->took_ns ? (double)c->took_bytes * 1e9 / (double)(now - c->took_ns)
                                     : 0.0;
        c->took_bytes = 0;
        c->took_ns = now;
    }
    const bool behind = c->decim > 1 ? waiting >= 2 : c->q.count == c->q.cap;
    if (behind) {
        c->ahead_ns = now;
        if (c->decim < s->d.snapshot_hz && now - c->rate_ns >= NET_RATE_DOWN_MS * 1000000ull) {
            const int d = net_rate_lower(c->decim, key_per_delta,
                                         net_rate_take_floor(c->key_bytes, c->take_bytes_s,
                                                             s->d.snapshot_hz),
                                         s->d.snapshot_hz);
            set_rate(s, c, d, now);
            atomic_fetch_add(&s->m.decimations, 1);
            net_conn_log(s, c,
                         "slow reader: %.3g snapshots a second (one in %d; a keyframe %.3g "
                         "deltas, %.0f kB; it took %.0f kB/s)",
                         (double)s->d.snapshot_hz / d, d, (double)key_per_delta,
                         (double)c->key_bytes * 1e-3, c->take_bytes_s * 1e-3);
        }
        if (c->decim > 1) {
            sendq_clear(&c->q); /* newest wins: what waits is older than a whole interval */
        }
    } else if (waiting) {
        c->ahead_ns = now;
    } else if (c->decim > 1 && now - c->ahead_ns >= NET_RATE_UP_MS * 1000000ull &&
               now - c->rate_ns >= NET_RATE_UP_MS * 1000000ull) {
        set_rate(s, c, net_rate_raise(c->decim, key_per_delta, s->d.snapshot_hz), now);
        net_conn_log(s, c, "reader keeps up: %.3g snapshots a second (one in %d)",
                     (double)s->d.snapshot_hz / c->decim, c->decim);
    }
    atomic_fetch_add_explicit(&p->refs, 1, memory_order_relaxed);
    sendq_push(&c->q, p);
    c->queued_any = true;
    c->queued_seq = p->seq;
    c->queued_stream = p->stream;
    lws_callback_on_writable(c->wsi);
}

void net_deliver_published(net_server *s)
{
    net_snap **batch = s->batch;
    int n;
    if (atomic_exchange(&s->reset_streams, 0)) {
        for (net_conn *c = s->conns; c; c = c->next) {
            c->stream = 0;
            c->resync = true;
        }
    }
    pthread_mutex_lock(&s->pub_lock);
    n = s->pub_n;
    memcpy(batch, s->pub, sizeof batch[0] * (size_t)n);
    s->pub_n = 0;
    pthread_mutex_unlock(&s->pub_lock);
    const uint64_t now = mono_ns();
    for (int i = 0; i < n; i++) {
        net_snap *p = batch[i];
        for (net_conn *c = s->conns; c; c = c->next) {
            if (c->role != NET_ROLE_NONE && !c->close_code && c->stream == p->stream) {
                deliver_one(s, c, p, now);
            }
        }
        net_snap_unref(p); /* the publisher's reference */
    }
    /* what the connections will need of the next snapshots (net_frames_wanted), and from
       which seq each view stream's followers take one (net_stream_due: UINT32_MAX none) */
    unsigned want = 0;
    uint32_t due[NET_DUE_SLOTS];
    memset(due, 0xff, sizeof due);
    for (net_conn *c = s->conns; c; c = c->next) {
        if (c->role == NET_ROLE_NONE || c->close_code) {
            continue;
        }
        /* a slow reader takes its next at queued_seq + decim (deliver_one) */
        const bool waits = c->decim > 1 && c->queued_any && c->queued_stream == c->stream;
        const uint32_t next = waits ? c->queued_seq + (uint32_t)c->decim : 0u;
        uint32_t *d = &due[c->stream % NET_DUE_SLOTS];
        if (*d != 0 && (next == 0 || *d == UINT32_MAX || (int32_t)(next - *d) < 0)) {
            *d = next;
        }
        want |= want_of(c->stream, NET_WANT_ANY);
        /* a slow reader of a view stream needs no standing keyframe: its stream is not
           encoded until its turn (net_stream_due), so that snapshot is one */
        if ((c->decim > 1 && !c->stream) || c->resync || c->chain == 0 ||
            c->stream != c->last_stream) {
            want |= want_of(c->stream, NET_WANT_KEY);
        } else if (c->chain == 1 && c->decim == 1) {
            want |= want_of(c->stream, NET_WANT_DELTA1);
        }
    }
    atomic_store(&s->want_standing, want);
    for (int k = 0; k < NET_DUE_SLOTS; k++) {
        atomic_store_explicit(&s->due_seq[k], due[k] == UINT32_MAX ? 0u : due[k],
                              memory_order_relaxed);
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
    c->take_ns = mono_ns();
    c->took_bytes += len;
    return 0;
}

/* Writes text message t, or with a tail its next fragment (its own part first, then the
 * tail's pieces in place: net_shared.c); *done when its last fragment went out. */
static int write_text(net_server *s, net_conn *c, net_text *t, bool *done)
{
    if (!t->tail) {
        *done = true;
        return ws_write(s, c, t->data + LWS_PRE, t->len, LWS_WRITE_TEXT);
    }
    *done = false;
    if (!t->started && t->len) {
        t->started = true;
        return ws_write(s, c, t->data + LWS_PRE, t->len,
                        (enum lws_write_protocol)(LWS_WRITE_TEXT | LWS_WRITE_NO_FIN));
    }
    const int first = t->started ? LWS_WRITE_CONTINUATION : LWS_WRITE_TEXT;
    t->started = true;
    size_t n;
    uint8_t *piece = net_shared_piece(t->tail, t->tail_piece++, &n);
    *done = t->tail_piece * NET_SHARED_PIECE >= t->tail->len;
    return ws_write(s, c, piece, n,
                    (enum lws_write_protocol)(first | (*done ? 0 : LWS_WRITE_NO_FIN)));
}

/* Drops c's oldest queued text message. */
static void text_pop(net_conn *c)
{
    net_text *t = &c->ctl[c->ctl_head];
    free(t->data);
    net_shared_unref(t->tail);
    *t = (net_text){ 0 };
    c->ctl_head = (c->ctl_head + 1) % NET_CTL_MAX;
    c->ctl_n--;
}

int net_ws_writeable(net_server *s, net_conn *c)
{
    /* Closing, the megabytes of a welcome not yet begun are not worth the wait: the error
     * message and the close go first. */
    while (c->close_code && c->ctl_n && c->ctl[c->ctl_head].tail &&
           !c->ctl[c->ctl_head].started) {
        text_pop(c);
    }
    /* A close frame may go between the fragments of a message (RFC 6455 5.4), an error
     * message may not: a connection closed in the middle of one gets the close alone. */
    if (c->close_code && (!c->ctl_n || c->ctl[c->ctl_head].started)) {
        lws_close_reason(c->wsi, (enum lws_close_status)c->close_code,
                         (unsigned char *)c->close_reason, strlen(c->close_reason));
        return -1;
    }
    if (c->ctl_n) {
        /* Control replies first: they are few, and a hello's scene comes before any
         * state. A welcome goes out a piece per writeable, so other connections' writes
         * take turns with it. */
        net_text *t = &c->ctl[c->ctl_head];
        bool done = false;
        int rc = write_text(s, c, t, &done);
        if (done || rc) {
            text_pop(c);
        }
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
        c->cur_key = false;
        bool next =
            !c->resync && c->chain > 0 && p->seq == c->last_seq + 1u && p->stream == c->last_stream;
        if (next && c->chain >= 2 && p->delta2_len) {
            rc = ws_write(s, c, p->delta2, p->delta2_len, LWS_WRITE_BINARY);
            c->chain = 2;
        } else if (next && p->delta1_len) {
            rc = ws_write(s, c, p->delta1, p->delta1_len, LWS_WRITE_BINARY);
            c->chain = 2;
        } else if (p->key_len) {
            rc = ws_write(s, c, p->key, p->key_len, LWS_WRITE_BINARY);
            c->chain = 1;
            c->cur_key = true;
            /* its next snapshot's */
            atomic_fetch_or(&s->want_asked, want_of(p->stream, NET_WANT_DELTA1));
        } else {
            /* encoded without the frame this connection needs (frames are encoded on
               demand, net_frames_wanted): skipped, and the next one asked to carry it */
            atomic_fetch_or(&s->want_asked, want_of(p->stream, NET_WANT_KEY));
            atomic_fetch_add_explicit(&s->m.frame_waits, 1, memory_order_relaxed);
            net_snap_unref(p);
            c->cur = NULL;
            c->take_ns = mono_ns(); /* the reader is not the one waiting */
            if (c->q.count || c->ctl_n || c->close_code) {
                lws_callback_on_writable(c->wsi);
            }
            return 0;
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
    /* the key extra (the whole damage state) goes only with a keyframe */
    while (c->cur_part >= 1 && c->cur_part <= NET_SNAP_MAX_EXTRA &&
           (!p->extra_len[c->cur_part - 1] ||
            ((p->extra_key_only >> (c->cur_part - 1)) & 1u && !c->cur_key))) {
        c->cur_part++;
    }
    if (c->cur_part > NET_SNAP_MAX_EXTRA) {
        net_snap_unref(p);
        c->cur = NULL;
    }
    if (c->cur || c->q.count || c->ctl_n) {
        lws_callback_on_writable(c->wsi);
    }
    return 0;
}

int net_ws_receive(net_server *s, net_conn *c, const void *in, size_t len)
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
    uint64_t now = mono_ns();
    /* a wall tile reports every frame it draws (PROTOCOL.md "Wall groups") */
    const bool wall = c->role == NET_ROLE_WALL;
    const double per_s = wall ? NET_WALL_MSG_PER_S : NET_MSG_PER_S;
    const double burst = wall ? NET_WALL_MSG_BURST : NET_MSG_BURST;
    c->tokens += (double)(now - c->tokens_ns) * 1e-9 * per_s;
    c->tokens = c->tokens < burst ? c->tokens : burst;
    c->tokens_ns = now;
    if (c->tokens < 1.0) {
        char why[100];
        snprintf(why, sizeof why,
                 "too many messages: expected <= %d a second after a burst of %d",
                 wall ? NET_WALL_MSG_PER_S : NET_MSG_PER_S,
                 wall ? NET_WALL_MSG_BURST : NET_MSG_BURST);
        bad_input(s, c, WIRE_CLOSE_RATE, why);
        return 0;
    }
    c->tokens -= 1.0;
    char *reply = NULL, why[100];
    size_t reply_len = 0;
    why[0] = 0;
    net_peer peer = { .id = c->id, .addr = c->peer, .role = c->role, .stream = c->stream,
                      .shared_ok = true };
    int code = s->d.control(s->d.control_user, &peer, (const char *)c->rx, c->rx_len, &reply,
                            &reply_len, why, sizeof why);
    c->rx_len = 0;
    if (code) {
        free(reply);
        net_shared_unref(peer.reply_shared);
        bad_input(s, c, code, why[0] ? why : "rejected");
        return 0;
    }
    if (peer.role != c->role && peer.role > NET_ROLE_NONE && peer.role < NET_ROLE_COUNT) {
        atomic_fetch_sub(&s->m.clients[c->role], 1);
        atomic_fetch_add(&s->m.clients[peer.role], 1);
        c->role = peer.role;
    }
    if (peer.role != NET_ROLE_NONE && (!c->queued_any || peer.resync || peer.stream != c->stream)) {
        /* for the very next snapshot */
        atomic_fetch_or(&s->want_asked, want_of(peer.stream, NET_WANT_KEY | NET_WANT_ANY));
    }
    c->resync = c->resync || peer.resync;
    c->stream = peer.stream; /* a frame of another stream than the last is a keyframe */
    if (reply) {
        conn_queue_text(s, c, reply, reply_len, peer.reply_shared);
        free(reply);
    } else {
        net_shared_unref(peer.reply_shared); /* a tail without its message: nothing to send */
    }
    net_ws_notice(s, c); /* a joiner's first after its welcome */
    return 0;
}

int net_ws_timer(net_server *s, net_conn *c)
{
    if (!c || !c->is_ws || !c->linked) {
        return 0;
    }
    if (c->close_code) {
        /* The close bound passed and the peer has not taken the close: drop the socket
         * without the rest of the handshake. */
        lws_set_timeout(c->wsi, PENDING_TIMEOUT_CLOSE_SEND, LWS_TO_KILL_ASYNC);
        return 0;
    }
    if (c->role == NET_ROLE_NONE) {
        atomic_fetch_add(&s->m.hello_timeouts, 1);
        char why[100];
        snprintf(why, sizeof why, "hello: expected within %d ms of the upgrade, got none",
                 s->d.hello_timeout_ms);
        net_conn_close(s, c, WIRE_CLOSE_ORDER, why);
    }
    return 0;
}
