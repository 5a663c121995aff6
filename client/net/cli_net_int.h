/* What cli_net.c (the network thread) and cli_net_poll.c (the caller's thread) share:
 * the client's state, the inbox's messages and the send ring. The lock in struct cli_net
 * guards every field both threads touch (cli_net.c's opening comment). */
#ifndef GALE_CLI_NET_INT_H
#define GALE_CLI_NET_INT_H

#include "cli_net.h"

#include <libwebsockets.h>

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CLI_NET_TX_SLOTS 8
#define CLI_NET_TX_BYTES CTL_MAX_CLIENT_BYTES
#define CLI_NET_TICK_US 20000 /* the network thread's timer: pings, retries, timeouts */

enum { TAG_WS = 1, TAG_HTTP = 2 };

typedef struct cli_net_tag {
    struct cli_net *n;
    int kind;
} cli_net_tag;

typedef struct cli_net_tx {
    uint8_t buf[LWS_PRE + CLI_NET_TX_BYTES];
    size_t len;
} cli_net_tx;

/* What the network thread hands the poller, in arrival order. */
enum {
    MSG_CONNECT, /* a new connection attempt: a fresh decoder and clock */
    MSG_TEXT,    /* a control message for the handlers (welcome, wall messages) */
    MSG_BINARY,  /* a state, leaves, wind, weather, damage or BUNDLE frame */
    MSG_PONG,    /* a pong: pong.* */
    MSG_LOST,    /* the connection ended: code, data the reason */
};

typedef struct cli_net_msg {
    struct cli_net_msg *next;
    int kind;
    int code;       /* MSG_LOST */
    double recv_s;  /* local clock when its last byte arrived */
    double pong[2]; /* MSG_PONG: client and server time [s] */
    size_t len;
    uint8_t data[]; /* len bytes and a NUL */
} cli_net_msg;

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
    bool tls;           /* wss:// (https for the asset fetches) */
    char server_name[300];

    pthread_t thread;
    bool thread_on;
    atomic_int stop;
    pthread_mutex_t lock; /* everything below that both threads touch */
    pthread_cond_t cond;  /* a fetch ended */
    pthread_mutex_t log_lock;
    lws_sorted_usec_list_t tick_sul;

    /* network thread */
    uint8_t *rx; /* owned: WIRE_MAX_FRAME_BYTES (+1 for a NUL) */
    size_t rx_len, rx_cap;
    bool rx_binary, rx_overflow;
    double next_ping_s, backoff_s;
    double attempt_s; /* when the current connection attempt began (CONNECTING, HELLO) */
    uint32_t ping_id;

    /* shared (lock) */
    cli_net_msg *in_head, *in_tail; /* the inbox */
    size_t in_bytes;
    cli_net_tx tx[CLI_NET_TX_SLOTS]; /* ring of queued control messages */
    uint32_t tx_head, tx_count;
    uint64_t tx_sent; /* messages written */
    bool kill; /* close the WebSocket at the next writeable */
    bool destroying;
    cli_net_stats st;
    /* HTTP fetch: the poller asks (want_fetch), the network thread runs it */
    bool want_fetch, fetch_abort;
    bool http_open; /* the fetch's socket exists (until its WSI_DESTROY) */
    char fetch_path[512];
    uint8_t *fetch_buf; /* owned until handed to the caller */
    size_t fetch_len, fetch_cap, fetch_max;
    int fetch_status;
    bool fetch_done, fetch_complete;
    char fetch_err[160];

    /* the poller's thread */
    wire_decoder *dec; /* owned; recreated per connection */
    jitter_clock clock;

    /* the log's limit (log_lock) */
    double last_log_s;
    uint64_t suppressed_logs;
};


/* Rate-limited log line (at most one a second; the rest are counted). Any thread. */
void cli_net_log(cli_net *n, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Queues a control message (lock held); the network thread writes it. on_net: the
 * caller is the network thread (inside lws), else it is woken. */
int cli_net_queue_ctl(cli_net *n, const ctl_msg *m, bool on_net, gale_err *err);

#endif
