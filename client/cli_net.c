/* Client networking on libwebsockets 4.1 (shaped like its minimal-ws-client and
 * minimal-http-client examples): the WebSocket state machine (connect, hello, welcome,
 * frames, pings, resync, backoff), message reassembly into one preallocated buffer, and
 * blocking HTTP GETs of assets over the same context. */
#include "cli_net.h"
#include "asset_cache.h"
#include "mono.h"

#include <libwebsockets.h>

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CLI_NET_TX_SLOTS 8
#define CLI_NET_TX_BYTES CTL_MAX_CLIENT_BYTES

enum { TAG_WS = 1, TAG_HTTP = 2 };

typedef struct cli_net_tag {
    struct cli_net *n;
    int kind;
} cli_net_tag;

typedef struct cli_net_tx {
    uint8_t buf[LWS_PRE + CLI_NET_TX_BYTES];
    size_t len;
} cli_net_tx;

struct cli_net {
    cli_net_desc d;
    cli_net_handler h;
    struct lws_context *ctx;
    struct lws *ws;   /* the WebSocket, NULL when none */
    struct lws *http; /* the HTTP fetch under way, NULL when none */
    cli_net_tag ws_tag, http_tag;
    char url[512]; /* parsed in place by lws_parse_uri */
    char host[256];
    char path[256];
    int port;
    char server_name[300];

    wire_decoder *dec; /* owned; recreated per connection */
    uint8_t *rx;       /* owned: WIRE_MAX_FRAME_BYTES (+1 for a NUL) */
    size_t rx_len, rx_cap;
    bool rx_binary, rx_overflow;

    cli_net_tx tx[CLI_NET_TX_SLOTS]; /* ring of queued control messages */
    uint32_t tx_head, tx_count;
    uint64_t tx_sent; /* messages written */
    bool kill; /* close the WebSocket at the next writeable */
    bool destroying;

    jitter_clock clock;
    double next_ping_s, backoff_s;
    double attempt_s; /* when the current connection attempt began (CONNECTING, HELLO) */
    uint32_t ping_id;
    double last_log_s;
    uint64_t suppressed_logs;
    cli_net_stats st;

    /* HTTP fetch */
    uint8_t *fetch_buf; /* owned until handed to the caller */
    size_t fetch_len, fetch_cap, fetch_max;
    int fetch_status;
    bool fetch_done, fetch_complete;
    char fetch_err[160];
};

/* Rate-limited log line (at most one a second; the rest are counted). */
static void cli_net_log(cli_net *n, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void cli_net_log(cli_net *n, const char *fmt, ...)
{
    double now = mono_s();
    if (now - n->last_log_s < 1.0) {
        n->suppressed_logs++;
        return;
    }
    n->last_log_s = now;
    char line[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (n->suppressed_logs) {
        fprintf(stderr, "gale-client: %s (%llu similar lines suppressed)\n", line,
                (unsigned long long)n->suppressed_logs);
        n->suppressed_logs = 0;
    } else {
        fprintf(stderr, "gale-client: %s\n", line);
    }
}

static int queue_ctl(cli_net *n, const ctl_msg *m, gale_err *err)
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
    lws_callback_on_writable(n->ws);
    return 0;
}

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
        if (n->h.on_lost) {
            n->h.on_lost(n->h.user, code, why);
        }
        return;
    }
    n->st.state = CLI_NET_BACKOFF;
    n->st.attempt++;
    snprintf(n->st.last_error, sizeof n->st.last_error, "%s", why);
    /* doubling backoff with ±20 % spread so many clients do not return in step */
    double spread = 0.8 + 0.4 * (double)(rand() % 1000) / 1000.0;
    n->st.retry_at_s = mono_s() + n->backoff_s * spread;
    n->backoff_s = fmin(n->backoff_s * 2.0, n->d.backoff_max_s);
    cli_net_log(n, "%s: connection lost (%s); retry %u in %.2f s", n->server_name, why,
                n->st.attempt, n->st.retry_at_s - mono_s());
    if (n->h.on_lost) {
        n->h.on_lost(n->h.user, code, why);
    }
}

static void handle_text(cli_net *n, const char *text, size_t len)
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
        if (n->h.on_welcome) {
            n->h.on_welcome(n->h.user, &m.u.welcome);
        }
        break;
    case CTL_PONG:
        jitter_clock_pong(&n->clock, (double)m.u.pong.client_us * 1e-6,
                          (double)m.u.pong.server_us * 1e-6, mono_s());
        break;
    case CTL_WALL_SYNC:
    case CTL_WALL_SWAP:
    case CTL_WALL_CAMERA:
        if (n->h.on_wall) {
            n->h.on_wall(n->h.user, &m);
        }
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

static void handle_binary(cli_net *n, const uint8_t *buf, size_t len, double now)
{
    wire_frame f;
    gale_err err = { 0 };
    int rc = wire_decode(n->dec, buf, len, &f, &err);
    if (rc == GALE_E_STATE) {
        /* a delta whose base we lack: ask for a keyframe (once per gap) */
        n->st.frames_gap++;
        ctl_msg m = { .type = CTL_RESYNC };
        m.u.resync_seq = wire_decoder_seq(n->dec);
        queue_ctl(n, &m, NULL);
        cli_net_log(n, "%s: %s; keyframe requested", n->server_name, err.msg);
        return;
    }
    if (rc != 0) {
        n->st.frames_bad++;
        cli_net_log(n, "%s: frame of %zu bytes dropped: %s", n->server_name, len, err.msg);
        return;
    }
    n->st.frames_ok++;
    if (f.hdr.type == WIRE_MSG_KEYFRAME || f.hdr.type == WIRE_MSG_DELTA) {
        jitter_clock_arrival(&n->clock, (double)f.hdr.server_time_us * 1e-6, now);
    }
    if (n->h.on_frame) {
        n->h.on_frame(n->h.user, &f, n->dec, now);
    }
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
        if (queue_ctl(n, &m, &err) != 0) {
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
            handle_binary(n, n->rx, n->rx_len, mono_s());
        } else {
            n->rx[n->rx_len] = '\0';
            handle_text(n, (const char *)n->rx, n->rx_len);
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
        if (!n->fetch_complete && !n->fetch_err[0]) {
            snprintf(n->fetch_err, sizeof n->fetch_err, "connection closed after %zu bytes",
                     n->fetch_len);
        }
        n->fetch_done = true;
        n->http = NULL;
        return 0;
    default:
        return 0;
    }
}

static int cli_net_callback(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                        size_t len)
{
    cli_net_tag *tag = wsi ? lws_get_opaque_user_data(wsi) : NULL;
    if (tag && tag->kind == TAG_WS) {
        return ws_callback(tag->n, wsi, reason, in, len);
    }
    if (tag && tag->kind == TAG_HTTP) {
        return http_callback(tag->n, wsi, reason, in, len);
    }
    return lws_callback_http_dummy(wsi, reason, user, in, len);
}

static const struct lws_protocols cli_net_protocols[] = {
    { CLI_NET_WS_PROTOCOL, cli_net_callback, 0, 65536, 0, NULL, 0 },
    { NULL, NULL, 0, 0, 0, NULL, 0 },
};

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
    if (strncmp(d->url, "ws://", 5) != 0 ||
        lws_parse_uri(n->url, &prot, &ads, &n->port, &path) != 0 || !ads[0]) {
        gale_errf(err, GALE_E_ARG, "--url \"%s\": expected ws://HOST:PORT[/PATH]", d->url);
        goto fail;
    }
    if (n->port <= 0 || n->port > 65535 || !strstr(d->url + 5, ":")) {
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
    n->ctx = lws_create_context(&info);
    if (!n->ctx) {
        gale_errf(err, GALE_E_STATE, "net: libwebsockets context creation failed");
        goto fail;
    }
    n->st.state = CLI_NET_IDLE;
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
    if (n->ctx) {
        n->destroying = true; /* closing callbacks neither log nor call the handler */
        lws_context_destroy(n->ctx);
    }
    wire_decoder_destroy(n->dec);
    free(n->rx);
    free(n->fetch_buf);
    free(n);
}

const char *cli_net_server_name(const cli_net *n)
{
    return n->server_name;
}

static void connect_ws(cli_net *n)
{
    /* a fresh decoder: the next keyframe starts the new stream */
    gale_err err = { 0 };
    wire_decoder *dec = wire_decoder_create(
        &(wire_decoder_desc){ .max_trees = n->d.max_trees, .max_modes = n->d.max_modes }, &err);
    if (dec) {
        wire_decoder_destroy(n->dec);
        n->dec = dec;
    }
    jitter_clock_init(&n->clock);
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
    n->ws = lws_client_connect_via_info(&i);
    if (!n->ws) {
        if (n->st.state == CLI_NET_CONNECTING) {
            set_lost(n, 0, "connect failed");
        }
    }
}

void cli_net_poll(cli_net *n, double now_s)
{
    if ((n->st.state == CLI_NET_CONNECTING || n->st.state == CLI_NET_HELLO) &&
        now_s - n->attempt_s > CLI_NET_CONNECT_TIMEOUT_S) {
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
        (n->st.state == CLI_NET_BACKOFF && now_s >= n->st.retry_at_s)) {
        connect_ws(n);
    }
    if ((n->st.state == CLI_NET_LIVE || n->st.state == CLI_NET_HELLO) && n->ws &&
        now_s >= n->next_ping_s) {
        ctl_msg m = { .type = CTL_PING };
        m.u.ping.id = ++n->ping_id;
        m.u.ping.client_us = (uint64_t)(mono_s() * 1e6);
        queue_ctl(n, &m, NULL);
        n->next_ping_s = now_s + n->d.ping_interval_s;
    }
    /* -1: do what is pending, never wait. One call handles one batch of socket events;
     * a frame that took long to draw (llvmpipe) leaves several snapshots waiting, so drain
     * until a pass brings nothing new, bounded so a flood cannot stall drawing. A pass
     * that opened the connection or wrote a message counts as new: the hello queued on
     * ESTABLISHED goes out on the next pass's WRITEABLE, in this poll, not a frame later
     * (a slow frame would let the server's hello timeout close the socket, 4009). */
    for (int pass = 0; pass < 64; pass++) {
        uint64_t before = n->st.frames_ok + n->st.frames_bad + n->st.ctl_bad + n->tx_sent +
                          n->st.connects;
        lws_service(n->ctx, -1);
        if (n->st.frames_ok + n->st.frames_bad + n->st.ctl_bad + n->tx_sent + n->st.connects ==
            before) {
            break;
        }
    }
}

int cli_net_send_wall(cli_net *n, const ctl_msg *m, gale_err *err)
{
    if (n->st.state != CLI_NET_LIVE) {
        return gale_errf(err, GALE_E_STATE, "%s: %s: not connected", n->server_name,
                         ctl_type_name(m->type) ? ctl_type_name(m->type) : "wall message");
    }
    return queue_ctl(n, m, err);
}

int cli_net_send_wind(cli_net *n, const ctl_wind *w, gale_err *err)
{
    if (n->st.state != CLI_NET_LIVE) {
        return gale_errf(err, GALE_E_STATE, "%s: wind command: not connected", n->server_name);
    }
    ctl_msg m = { .type = CTL_WIND };
    m.u.wind = *w;
    return queue_ctl(n, &m, err);
}

int cli_net_send_ctl(cli_net *n, const ctl_msg *m, char *text, size_t cap, gale_err *err)
{
    if (n->st.state != CLI_NET_LIVE) {
        return gale_errf(err, GALE_E_STATE, "%s: %s: not connected", n->server_name,
                         ctl_type_name(m->type) ? ctl_type_name(m->type) : "control message");
    }
    int rc = queue_ctl(n, m, err);
    if (rc == 0 && text && cap > 0) {
        const cli_net_tx *t = &n->tx[(n->tx_head + n->tx_count - 1) % CLI_NET_TX_SLOTS];
        size_t k = t->len < cap - 1 ? t->len : cap - 1;
        memcpy(text, t->buf + LWS_PRE, k);
        text[k] = '\0';
    }
    return rc;
}

int cli_net_fetch(cli_net *n, const char *path, size_t max_len, double timeout_s, uint8_t **out,
              size_t *len, gale_err *err)
{
    *out = NULL;
    *len = 0;
    if (n->http) {
        return gale_errf(err, GALE_E_STATE, "%s%s: a fetch is already under way", n->server_name,
                         path);
    }
    n->fetch_len = 0;
    n->fetch_max = max_len;
    n->fetch_status = 0;
    n->fetch_done = false;
    n->fetch_complete = false;
    n->fetch_err[0] = '\0';
    struct lws_client_connect_info i;
    memset(&i, 0, sizeof i);
    i.context = n->ctx;
    i.address = n->host;
    i.port = n->port;
    i.path = path;
    i.host = n->host;
    i.origin = n->host;
    i.method = "GET";
    i.protocol = CLI_NET_WS_PROTOCOL;
    i.local_protocol_name = CLI_NET_WS_PROTOCOL;
    i.opaque_user_data = &n->http_tag;
    n->http = lws_client_connect_via_info(&i);
    if (!n->http && !n->fetch_done) {
        return gale_errf(err, GALE_E_IO, "http://%s%s: connect failed", n->server_name, path);
    }
    const double deadline = mono_s() + timeout_s;
    while (!n->fetch_done && mono_s() < deadline) {
        lws_service(n->ctx, -1);
        if (!n->fetch_done) {
            usleep(500);
        }
    }
    if (!n->fetch_done) {
        if (n->http) {
            lws_set_timeout(n->http, PENDING_TIMEOUT_CLOSE_ACK, LWS_TO_KILL_ASYNC);
        }
        return gale_errf(err, GALE_E_IO, "http://%s%s: timed out after %.1f s (%zu bytes)",
                         n->server_name, path, timeout_s, n->fetch_len);
    }
    if (!n->fetch_complete || n->fetch_err[0]) {
        int code = strstr(n->fetch_err, "body over") ? GALE_E_RANGE : GALE_E_IO;
        return gale_errf(err, code, "http://%s%s: %s", n->server_name, path,
                         n->fetch_err[0] ? n->fetch_err : "incomplete");
    }
    *out = n->fetch_buf ? n->fetch_buf : malloc(1);
    *len = n->fetch_len;
    n->fetch_buf = NULL;
    n->fetch_cap = 0;
    n->fetch_len = 0;
    return *out ? 0 : gale_errf(err, GALE_E_NOMEM, "cli_net_fetch: no memory");
}

int cli_net_fetch_asset(cli_net *n, const char *path, const char *hash_hex, size_t max_len,
                        double timeout_s, uint8_t **out, size_t *len, gale_err *err)
{
    int rc = cli_net_fetch(n, path, max_len, timeout_s, out, len, err);
    if (rc) {
        return rc;
    }
    char what[400];
    snprintf(what, sizeof what, "http://%s%s", n->server_name, path);
    rc = asset_cache_verify(hash_hex, *out, *len, what, err);
    if (rc) {
        free(*out);
        *out = NULL;
        *len = 0;
    }
    return rc;
}

cli_net_stats cli_net_get_stats(const cli_net *n)
{
    return n->st;
}

const jitter_clock *cli_net_clock(const cli_net *n)
{
    return &n->clock;
}

void cli_net_drop(cli_net *n)
{
    if (n->ws) {
        n->kill = true;
        lws_callback_on_writable(n->ws);
    }
}
