/* Client networking on libwebsockets 4.1 (shaped like its minimal-ws-client and
 * minimal-http-client examples), on a thread of its own: that thread alone services the
 * lws context (the WebSocket state machine: connect, hello, welcome, pings, backoff;
 * message reassembly; HTTP GETs of assets), so the socket is read as fast as the server
 * writes whatever the caller's frame rate, and the server never sees a slow reader in a
 * client that draws slowly. What arrives waits in an inbox, in order, until cli_net_poll
 * hands it to the handlers on the caller's thread: decoding, the decoder and the clock
 * belong to that thread. One mutex guards what both threads touch (the inbox, the send
 * ring, the stats, the fetch); the caller wakes the network thread with
 * lws_cancel_service, the one lws call safe from another thread. This file: the network
 * thread, and creating and ending it; cli_net_poll.c: the caller's side. */
#include "cli_net_int.h"
#include "mono.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

void cli_net_log(cli_net *n, const char *fmt, ...)
{
    double now = mono_s();
    pthread_mutex_lock(&n->log_lock);
    if (now - n->last_log_s < 1.0) {
        n->suppressed_logs++;
        pthread_mutex_unlock(&n->log_lock);
        return;
    }
    n->last_log_s = now;
    uint64_t suppressed = n->suppressed_logs;
    n->suppressed_logs = 0;
    pthread_mutex_unlock(&n->log_lock);
    char line[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (suppressed) {
        fprintf(stderr, "gale-client: %s (%llu similar lines suppressed)\n", line,
                (unsigned long long)suppressed);
    } else {
        fprintf(stderr, "gale-client: %s\n", line);
    }
}

/* Appends a message to the inbox (lock held). Past CLI_NET_INBOX_BYTES the oldest frames
 * go: the poller's decoder then sees a gap and asks for a keyframe, the newest state wins. */
static void inbox_put(cli_net *n, int kind, int code, double recv_s, const void *data,
                      size_t len)
{
    cli_net_msg *m = malloc(sizeof *m + len + 1);
    if (!m) {
        n->st.inbox_dropped++;
        return;
    }
    *m = (cli_net_msg){ .kind = kind, .code = code, .recv_s = recv_s, .len = len };
    if (len) {
        memcpy(m->data, data, len);
    }
    m->data[len] = 0;
    while (n->in_head && n->in_bytes + len > CLI_NET_INBOX_BYTES) {
        cli_net_msg **at = &n->in_head, *prev = NULL;
        while (*at && (*at)->kind != MSG_BINARY) {
            prev = *at;
            at = &(*at)->next;
        }
        if (!*at) {
            break;
        }
        cli_net_msg *old = *at;
        *at = old->next;
        if (n->in_tail == old) {
            n->in_tail = prev;
        }
        n->in_bytes -= old->len;
        n->st.inbox_dropped++;
        free(old);
    }
    if (n->in_tail) {
        n->in_tail->next = m;
    } else {
        n->in_head = m;
    }
    n->in_tail = m;
    n->in_bytes += len;
}

int cli_net_queue_ctl(cli_net *n, const ctl_msg *m, bool on_net, gale_err *err)
{
    if (!n->ws) {
        return gale_errf(err, GALE_E_STATE, "%s: not connected", n->server_name);
    }
    if (n->tx_count == CLI_NET_TX_SLOTS) {
        return gale_errf(err, GALE_E_STATE, "%s: send queue full (%d messages)", n->server_name,
                         CLI_NET_TX_SLOTS);
    }
    cli_net_tx *t = &n->tx[(n->tx_head + n->tx_count) % CLI_NET_TX_SLOTS];
    size_t len = 0;
    int rc = ctl_encode_into(m, (char *)t->buf + LWS_PRE, CLI_NET_TX_BYTES, &len, err);
    if (rc != 0) {
        return rc;
    }
    t->len = len;
    n->tx_count++;
    if (on_net) {
        lws_callback_on_writable(n->ws);
    } else {
        lws_cancel_service(n->ctx);
    }
    return 0;
}

/* Network thread, lock held. */
static void set_lost(cli_net *n, int code, const char *why)
{
    n->ws = NULL;
    n->tx_count = 0;
    n->kill = false;
    n->st.last_close = code;
    if (code == WIRE_CLOSE_BAD_TOKEN) {
        /* the server's error message (last_error) says which: wrong, none, or disabled */
        n->st.state = CLI_NET_REFUSED;
        if (strncmp(n->st.last_error, "server: ", 8) != 0) {
            snprintf(n->st.last_error, sizeof n->st.last_error, "%s", why);
        }
        inbox_put(n, MSG_LOST, code, mono_s(), why, strlen(why));
        return;
    }
    n->st.state = CLI_NET_BACKOFF;
    n->st.attempt++;
    snprintf(n->st.last_error, sizeof n->st.last_error, "%s", why);
    /* doubling backoff with ±20 % spread so many clients do not return in step */
    double spread = 0.8 + 0.4 * (double)(rand() % 1000) / 1000.0;
    n->st.retry_delay_s = n->backoff_s * spread;
    n->st.retry_at_s = mono_s() + n->st.retry_delay_s;
    n->backoff_s = fmin(n->backoff_s * 2.0, n->d.backoff_max_s);
    cli_net_log(n, "%s: connection lost (%s); retry %u in %.2f s", n->server_name, why,
                n->st.attempt, n->st.retry_at_s - mono_s());
    inbox_put(n, MSG_LOST, code, mono_s(), why, strlen(why));
}

/* Network thread, lock held: a whole text message. The connection's own business (the
 * welcome makes it live, an error says why it ends, a pong times the clock) is done here;
 * what the handlers want goes to the inbox. */
static void net_text(cli_net *n, const char *text, size_t len, double now)
{
    ctl_msg m;
    int close_code = 0;
    gale_err err = { 0 };
    if (ctl_decode(text, len, CTL_MAX_SERVER_BYTES, &m, &close_code, &err) != 0) {
        n->st.ctl_bad++;
        cli_net_log(n, "%s: control message dropped: %s", n->server_name, err.msg);
        return;
    }
    switch (m.type) {
    case CTL_WELCOME:
        n->st.state = CLI_NET_LIVE;
        n->st.attempt = 0;
        n->backoff_s = n->d.backoff_min_s;
        inbox_put(n, MSG_TEXT, 0, now, text, len);
        break;
    case CTL_PONG: {
        cli_net_msg *before = n->in_tail;
        inbox_put(n, MSG_PONG, 0, now, NULL, 0);
        if (n->in_tail != before) {
            n->in_tail->pong[0] = (double)m.u.pong.client_us * 1e-6;
            n->in_tail->pong[1] = (double)m.u.pong.server_us * 1e-6;
        }
        break;
    }
    case CTL_WALL_SYNC:
    case CTL_WALL_SWAP:
    case CTL_WALL_CAMERA:
    case CTL_SCHEDULE:
        inbox_put(n, MSG_TEXT, 0, now, text, len);
        break;
    case CTL_ERROR:
        snprintf(n->st.last_error, sizeof n->st.last_error, "server: %.100s (%s)",
                 m.u.error.message, wire_close_name(m.u.error.code));
        cli_net_log(n, "%s: %s", n->server_name, n->st.last_error);
        break;
    default:
        n->st.ctl_bad++;
        cli_net_log(n, "%s: unexpected control message \"%s\" dropped", n->server_name,
                    ctl_type_name(m.type) ? ctl_type_name(m.type) : "?");
        break;
    }
    ctl_msg_fini(&m);
}

static int ws_callback(cli_net *n, struct lws *wsi, enum lws_callback_reasons reason, void *in,
                       size_t len)
{
    /* A socket this client gave up on (set_lost, or an attempt past its timeout) may still
     * report its end later: it must not end the connection that replaced it. Only an
     * attempt that connect_ws has not yet seen returned (n->ws NULL while CONNECTING) is
     * current besides n->ws. */
    bool current = wsi == n->ws || (!n->ws && n->st.state == CLI_NET_CONNECTING);
    if (reason == LWS_CALLBACK_WSI_DESTROY && wsi == n->ws) {
        /* lws frees a socket that fails in its handshake without CONNECTION_ERROR or
         * CLIENT_CLOSED: n->ws must not outlive it (the connect timeout would touch it) */
        n->ws = NULL;
        if (!n->destroying && (n->st.state == CLI_NET_CONNECTING || n->st.state == CLI_NET_HELLO ||
                               n->st.state == CLI_NET_LIVE)) {
            set_lost(n, n->st.last_close, "closed during the handshake");
        }
        return 0;
    }
    if (!current) {
        return reason == LWS_CALLBACK_CLIENT_WRITEABLE ? -1 : 0;
    }
    switch (reason) {
    case LWS_CALLBACK_CLIENT_CONNECTION_ERROR: {
        char why[160];
        snprintf(why, sizeof why, "connect: %s", in ? (const char *)in : "error");
        if (n->st.state == CLI_NET_CONNECTING) {
            set_lost(n, 0, why);
        }
        return 0;
    }
    case LWS_CALLBACK_CLIENT_ESTABLISHED: {
        n->ws = wsi;
        n->st.connects++;
        n->st.state = CLI_NET_HELLO;
        n->tx_count = 0;
        ctl_msg m = { .type = CTL_HELLO };
        m.u.hello.protocol = WIRE_PROTOCOL_VERSION;
        m.u.hello.role = n->d.role;
        m.u.hello.view.kind = CTL_VIEW_ALL;
        if (n->d.token) {
            snprintf(m.u.hello.token, sizeof m.u.hello.token, "%s", n->d.token);
        }
        gale_err err = { 0 };
        if (cli_net_queue_ctl(n, &m, true, &err) != 0) {
            cli_net_log(n, "%s: hello: %s", n->server_name, err.msg);
            return -1;
        }
        n->next_ping_s = mono_s();
        return 0;
    }
    case LWS_CALLBACK_CLIENT_RECEIVE: {
        if (lws_is_first_fragment(wsi)) {
            n->rx_len = 0;
            n->rx_overflow = false;
            n->rx_binary = lws_frame_is_binary(wsi) != 0;
        }
        n->st.bytes_rx += len;
        if (!n->rx_overflow && len <= n->rx_cap - n->rx_len) {
            memcpy(n->rx + n->rx_len, in, len);
            n->rx_len += len;
        } else {
            n->rx_overflow = true;
        }
        if (!lws_is_final_fragment(wsi) || lws_remaining_packet_payload(wsi) != 0) {
            return 0;
        }
        if (n->rx_overflow) {
            n->st.frames_bad++;
            cli_net_log(n, "%s: message over %zu bytes dropped", n->server_name, n->rx_cap);
        } else if (n->rx_binary) {
            inbox_put(n, MSG_BINARY, 0, mono_s(), n->rx, n->rx_len);
        } else {
            n->rx[n->rx_len] = '\0';
            net_text(n, (const char *)n->rx, n->rx_len, mono_s());
        }
        n->rx_len = 0;
        return 0;
    }
    case LWS_CALLBACK_CLIENT_WRITEABLE:
        if (n->kill) {
            return -1;
        }
        if (n->tx_count > 0) {
            cli_net_tx *t = &n->tx[n->tx_head];
            int w = lws_write(wsi, t->buf + LWS_PRE, t->len, LWS_WRITE_TEXT);
            if (w < (int)t->len) {
                cli_net_log(n, "%s: write failed", n->server_name);
                return -1;
            }
            n->tx_head = (n->tx_head + 1) % CLI_NET_TX_SLOTS;
            n->tx_count--;
            n->tx_sent++;
            if (n->tx_count > 0) {
                lws_callback_on_writable(wsi);
            }
        }
        return 0;
    case LWS_CALLBACK_WS_PEER_INITIATED_CLOSE:
        if (len >= 2) {
            const uint8_t *p = in;
            n->st.last_close = (p[0] << 8) | p[1];
        }
        return 0;
    case LWS_CALLBACK_CLIENT_CLOSED: {
        char why[160];
        if (n->st.last_close) {
            snprintf(why, sizeof why, "closed, code %d %s", n->st.last_close,
                     wire_close_name(n->st.last_close));
        } else {
            snprintf(why, sizeof why, "closed");
        }
        if (n->st.state != CLI_NET_BACKOFF && n->st.state != CLI_NET_IDLE && !n->destroying) {
            set_lost(n, n->st.last_close, why);
        }
        return 0;
    }
    default:
        return 0;
    }
}

static int http_callback(cli_net *n, struct lws *wsi, enum lws_callback_reasons reason, void *in,
                         size_t len)
{
    switch (reason) {
    case LWS_CALLBACK_CLIENT_CONNECTION_ERROR:
        if (!n->fetch_err[0]) { /* keep the reason we closed it for (an HTTP status) */
            snprintf(n->fetch_err, sizeof n->fetch_err, "connect: %s",
                     in ? (const char *)in : "error");
        }
        n->fetch_done = true;
        n->http = NULL;
        return 0;
    case LWS_CALLBACK_ESTABLISHED_CLIENT_HTTP:
        n->fetch_status = (int)lws_http_client_http_response(wsi);
        if (n->fetch_status != 200) {
            snprintf(n->fetch_err, sizeof n->fetch_err, "HTTP status %d", n->fetch_status);
            n->fetch_done = true;
            return -1;
        }
        return 0;
    case LWS_CALLBACK_RECEIVE_CLIENT_HTTP_READ:
        if (len > n->fetch_max - n->fetch_len) {
            snprintf(n->fetch_err, sizeof n->fetch_err, "body over %zu bytes", n->fetch_max);
            n->fetch_done = true;
            return -1;
        }
        if (n->fetch_len + len > n->fetch_cap) {
            size_t cap = n->fetch_cap ? n->fetch_cap : 65536;
            while (cap < n->fetch_len + len) {
                cap *= 2;
            }
            uint8_t *b = realloc(n->fetch_buf, cap);
            if (!b) {
                snprintf(n->fetch_err, sizeof n->fetch_err, "no memory for %zu bytes", cap);
                n->fetch_done = true;
                return -1;
            }
            n->fetch_buf = b;
            n->fetch_cap = cap;
        }
        memcpy(n->fetch_buf + n->fetch_len, in, len);
        n->fetch_len += len;
        return 0;
    case LWS_CALLBACK_RECEIVE_CLIENT_HTTP: {
        char buffer[LWS_PRE + 16384];
        char *px = buffer + LWS_PRE;
        int lenx = (int)sizeof buffer - LWS_PRE;
        if (lws_http_client_read(wsi, &px, &lenx) < 0) {
            return -1;
        }
        return 0;
    }
    case LWS_CALLBACK_COMPLETED_CLIENT_HTTP:
        n->fetch_complete = true;
        n->fetch_done = true;
        n->http = NULL;
        return -1; /* body complete: close rather than keep the connection alive */
    case LWS_CALLBACK_CLOSED_CLIENT_HTTP:
    case LWS_CALLBACK_WSI_DESTROY:
        if (!n->fetch_complete && !n->fetch_err[0]) {
            snprintf(n->fetch_err, sizeof n->fetch_err, "connection closed after %zu bytes",
                     n->fetch_len);
        }
        n->fetch_done = true;
        n->http = NULL;
        n->http_open = reason != LWS_CALLBACK_WSI_DESTROY && n->http_open;
        return 0;
    default:
        return 0;
    }
}


/* Network thread, lock held: a new connection attempt. */
static void connect_ws(cli_net *n)
{
    inbox_put(n, MSG_CONNECT, 0, mono_s(), NULL, 0); /* the next keyframe starts anew */
    n->st.last_close = 0;
    n->st.state = CLI_NET_CONNECTING;
    n->attempt_s = mono_s();
    struct lws_client_connect_info i;
    memset(&i, 0, sizeof i);
    i.context = n->ctx;
    i.address = n->host;
    i.port = n->port;
    i.path = n->path;
    i.host = n->host;
    i.origin = n->host;
    i.protocol = CLI_NET_WS_PROTOCOL;
    i.local_protocol_name = CLI_NET_WS_PROTOCOL;
    i.opaque_user_data = &n->ws_tag;
    i.ssl_connection = n->tls ? LCCSCF_USE_SSL : 0;
    n->ws = lws_client_connect_via_info(&i);
    if (!n->ws) {
        if (n->st.state == CLI_NET_CONNECTING) {
            set_lost(n, 0, "connect failed");
        }
    }
}

/* Network thread, lock held: the fetch the poller asked for. */
static void start_fetch(cli_net *n)
{
    n->want_fetch = false;
    struct lws_client_connect_info i;
    memset(&i, 0, sizeof i);
    i.context = n->ctx;
    i.address = n->host;
    i.port = n->port;
    i.path = n->fetch_path;
    i.host = n->host;
    i.origin = n->host;
    i.method = "GET";
    i.protocol = CLI_NET_WS_PROTOCOL;
    i.local_protocol_name = CLI_NET_WS_PROTOCOL;
    i.opaque_user_data = &n->http_tag;
    i.ssl_connection = n->tls ? LCCSCF_USE_SSL : 0;
    n->http_open = true;
    n->http = lws_client_connect_via_info(&i);
    if (!n->http) {
        n->http_open = false;
        if (!n->fetch_done) {
            snprintf(n->fetch_err, sizeof n->fetch_err, "connect failed");
            n->fetch_done = true;
        }
    }
    pthread_cond_broadcast(&n->cond);
}

/* Network thread, lock held: timers (connect timeout, retry, ping) and the poller's
 * requests (messages to write, a drop, a fetch or its abort). */
static void net_work(cli_net *n)
{
    const double now = mono_s();
    if ((n->st.state == CLI_NET_CONNECTING || n->st.state == CLI_NET_HELLO) &&
        now - n->attempt_s > CLI_NET_CONNECT_TIMEOUT_S) {
        /* a handshake or hello that never finishes: drop that socket, try anew */
        struct lws *stale = n->ws;
        char why[96];
        snprintf(why, sizeof why, "no %s within %.0f s",
                 n->st.state == CLI_NET_HELLO ? "welcome" : "connection",
                 CLI_NET_CONNECT_TIMEOUT_S);
        set_lost(n, 0, why);
        if (stale) {
            lws_set_timeout(stale, PENDING_TIMEOUT_CLOSE_ACK, LWS_TO_KILL_ASYNC);
        }
    }
    if (n->st.state == CLI_NET_IDLE ||
        (n->st.state == CLI_NET_BACKOFF && now >= n->st.retry_at_s)) {
        connect_ws(n);
    }
    if ((n->st.state == CLI_NET_LIVE || n->st.state == CLI_NET_HELLO) && n->ws &&
        now >= n->next_ping_s) {
        ctl_msg m = { .type = CTL_PING };
        m.u.ping.id = ++n->ping_id;
        m.u.ping.client_us = (uint64_t)(mono_s() * 1e6);
        cli_net_queue_ctl(n, &m, true, NULL);
        n->next_ping_s = now + n->d.ping_interval_s;
    }
    if (n->ws && (n->tx_count || n->kill)) {
        lws_callback_on_writable(n->ws);
    }
    if (n->want_fetch) {
        start_fetch(n);
    }
    if (n->fetch_abort) {
        n->fetch_abort = false;
        if (n->http) {
            lws_set_timeout(n->http, PENDING_TIMEOUT_CLOSE_ACK, LWS_TO_KILL_ASYNC);
        }
    }
}

static void tick_cb(lws_sorted_usec_list_t *sul)
{
    cli_net *n = lws_container_of(sul, cli_net, tick_sul);
    pthread_mutex_lock(&n->lock);
    net_work(n);
    pthread_mutex_unlock(&n->lock);
    lws_sul_schedule(n->ctx, 0, &n->tick_sul, tick_cb, CLI_NET_TICK_US);
}

static int cli_net_callback(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                        size_t len)
{
    if (reason == LWS_CALLBACK_EVENT_WAIT_CANCELLED) {
        cli_net *n = lws_context_user(lws_get_context(wsi));
        if (n) {
            pthread_mutex_lock(&n->lock);
            net_work(n);
            pthread_mutex_unlock(&n->lock);
        }
        return 0;
    }
    cli_net_tag *tag = wsi ? lws_get_opaque_user_data(wsi) : NULL;
    int rc;
    if (tag && tag->kind == TAG_WS) {
        pthread_mutex_lock(&tag->n->lock);
        rc = ws_callback(tag->n, wsi, reason, in, len);
        pthread_mutex_unlock(&tag->n->lock);
        return rc;
    }
    if (tag && tag->kind == TAG_HTTP) {
        pthread_mutex_lock(&tag->n->lock);
        rc = http_callback(tag->n, wsi, reason, in, len);
        pthread_cond_broadcast(&tag->n->cond);
        pthread_mutex_unlock(&tag->n->lock);
        return rc;
    }
    return lws_callback_http_dummy(wsi, reason, user, in, len);
}

static const struct lws_protocols cli_net_protocols[] = {
    { CLI_NET_WS_PROTOCOL, cli_net_callback, 0, 65536, 0, NULL, 0 },
    { NULL, NULL, 0, 0, 0, NULL, 0 },
};

static void *net_main(void *arg)
{
    cli_net *n = arg;
    lws_sul_schedule(n->ctx, 0, &n->tick_sul, tick_cb, 1);
    while (!atomic_load(&n->stop)) {
        if (lws_service(n->ctx, 0) < 0) {
            break;
        }
    }
    return NULL;
}

cli_net *cli_net_create(const cli_net_desc *d, const cli_net_handler *h, gale_err *err)
{
    if (!d->url) {
        gale_errf(err, GALE_E_ARG, "--url: required (ws://HOST:PORT)");
        return NULL;
    }
    cli_net *n = calloc(1, sizeof *n);
    if (!n) {
        gale_errf(err, GALE_E_NOMEM, "net: no memory");
        return NULL;
    }
    /* recursive: lws may call back into the thread's handlers from inside net_work */
    pthread_mutexattr_t ma;
    pthread_mutexattr_init(&ma);
    pthread_mutexattr_settype(&ma, PTHREAD_MUTEX_RECURSIVE);
    pthread_mutex_init(&n->lock, &ma);
    pthread_mutexattr_destroy(&ma);
    pthread_mutex_init(&n->log_lock, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&n->cond, &ca);
    pthread_condattr_destroy(&ca);
    n->d = *d;
    if (h) {
        n->h = *h;
    }
    if (n->d.backoff_min_s <= 0) {
        n->d.backoff_min_s = 0.25;
    }
    if (n->d.backoff_max_s <= 0) {
        n->d.backoff_max_s = 5.0;
    }
    if (n->d.ping_interval_s <= 0) {
        n->d.ping_interval_s = 0.5;
    }
    n->backoff_s = n->d.backoff_min_s;
    n->ws_tag = (cli_net_tag){ n, TAG_WS };
    n->http_tag = (cli_net_tag){ n, TAG_HTTP };
    jitter_clock_init(&n->clock);

    const char *prot = NULL, *ads = NULL, *path = NULL;
    if (strlen(d->url) >= sizeof n->url) {
        gale_errf(err, GALE_E_ARG, "--url: longer than %zu bytes", sizeof n->url - 1);
        goto fail;
    }
    snprintf(n->url, sizeof n->url, "%s", d->url);
    n->tls = strncmp(d->url, "wss://", 6) == 0;
    if ((strncmp(d->url, "ws://", 5) != 0 && !n->tls) ||
        lws_parse_uri(n->url, &prot, &ads, &n->port, &path) != 0 || !ads[0]) {
        gale_errf(err, GALE_E_ARG, "--url \"%s\": expected ws://HOST:PORT[/PATH] or "
                  "wss://HOST:PORT[/PATH]", d->url);
        goto fail;
    }
    if (n->port <= 0 || n->port > 65535 || !strstr(d->url + (n->tls ? 6 : 5), ":")) {
        gale_errf(err, GALE_E_ARG, "--url \"%s\": expected a port 1..65535", d->url);
        goto fail;
    }
    snprintf(n->host, sizeof n->host, "%s", ads);
    snprintf(n->path, sizeof n->path, "/%s", path ? path : "");
    snprintf(n->server_name, sizeof n->server_name, "%s:%d", n->host, n->port);

    n->rx_cap = WIRE_MAX_FRAME_BYTES;
    n->rx = malloc(n->rx_cap + 1);
    n->dec = wire_decoder_create(
        &(wire_decoder_desc){ .max_trees = d->max_trees, .max_modes = d->max_modes }, err);
    if (!n->rx || !n->dec) {
        if (!n->rx) {
            gale_errf(err, GALE_E_NOMEM, "net: no memory for the receive buffer");
        }
        goto fail;
    }

    lws_set_log_level(LLL_ERR, NULL); /* our own lines say what went wrong */
    struct lws_context_creation_info info;
    memset(&info, 0, sizeof info);
    info.port = CONTEXT_PORT_NO_LISTEN;
    info.protocols = cli_net_protocols;
    info.fd_limit_per_thread = 1 + 1 + 2;
    info.user = n;
    if (n->tls) {
        /* the server's certificate is checked against these (host name included) */
        const char *ca_file = d->tls_ca ? d->tls_ca : CLI_NET_SYSTEM_CA;
        if (access(ca_file, R_OK) != 0) {
            gale_errf(err, GALE_E_IO, "--tls-ca %s: cannot read: %s", ca_file,
                      strerror(errno));
            goto fail;
        }
        info.options |= LWS_SERVER_OPTION_DO_SSL_GLOBAL_INIT;
        info.client_ssl_ca_filepath = ca_file;
    }
    n->ctx = lws_create_context(&info);
    if (!n->ctx) {
        gale_errf(err, GALE_E_STATE, "net: libwebsockets context creation failed%s",
                  n->tls ? " (TLS: is the --tls-ca file PEM?)" : "");
        goto fail;
    }
    n->st.state = CLI_NET_IDLE;
    if (pthread_create(&n->thread, NULL, net_main, n) != 0) {
        gale_errf(err, GALE_E_STATE, "net: cannot start the network thread");
        goto fail;
    }
    n->thread_on = true;
    return n;
fail:
    cli_net_destroy(n);
    return NULL;
}

void cli_net_destroy(cli_net *n)
{
    if (!n) {
        return;
    }
    if (n->thread_on) {
        atomic_store(&n->stop, 1);
        lws_cancel_service(n->ctx);
        pthread_join(n->thread, NULL);
    }
    if (n->ctx) {
        n->destroying = true; /* closing callbacks neither log nor call the handler */
        lws_context_destroy(n->ctx);
    }
    while (n->in_head) {
        cli_net_msg *m = n->in_head;
        n->in_head = m->next;
        free(m);
    }
    wire_decoder_destroy(n->dec);
    free(n->rx);
    free(n->fetch_buf);
    pthread_cond_destroy(&n->cond);
    pthread_mutex_destroy(&n->lock);
    pthread_mutex_destroy(&n->log_lock);
    free(n);
}

const char *cli_net_server_name(const cli_net *n)
{
    return n->server_name;
}
