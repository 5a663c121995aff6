/* The network module's private parts, shared by net.c (life cycle, snapshot hand-over,
 * the lws callback), net_ws.c (WebSocket connections) and net_http.c (HTTP: assets,
 * /healthz, /metrics). Everything declared here runs on the lws service thread. */
#ifndef GALE_NET_INT_H
#define GALE_NET_INT_H

#include <pthread.h>
#include <time.h>

#include <libwebsockets.h>

#include "net.h"
#include "sendq.h"

#define NET_PUB_MAX 16    /* published snapshots per stream waiting for the service thread */
/* Control messages a connection may send: a token bucket of NET_MSG_BURST messages refilled
 * at NET_MSG_PER_S a second (beyond it: close 4012). gale-client sends 2 pings a second and
 * a resync or a wind command now and then; a page reload's hello, view and ping fit the
 * burst many times over. */
#define NET_MSG_BURST 20
#define NET_MSG_PER_S 10
/* A wall tile's bucket: a wall_drawn per frame at up to CTL_WALL_MAX_RATE_HZ besides the
 * pings; the replies' queue below still bounds one that does not read its swaps. */
#define NET_WALL_MSG_BURST 64
#define NET_WALL_MSG_PER_S 250
/* Control replies queued per connection: a whole burst's replies and the error of a close,
 * so that the bucket, not this queue, bounds a client that sends faster than it reads. */
#define NET_CTL_MAX (NET_MSG_BURST + 4)
/* Descriptors kept below RLIMIT_NOFILE for what the server opens besides connections (the
 * transient accept of a connection refused at the cap, log and cache files, threads'
 * event fds), so accept never fails with EMFILE. */
#define NET_FD_RESERVE 16
/* Highest RLIMIT_NOFILE the sizing counts with (lws sizes a table by it). */
#define NET_NOFILE_MAX (1L << 20)
#define NET_HTTP_CHUNK 16384
#define NET_LOG_PER_S 20  /* rate limit of bad-input log lines */
/* A slow reader's snapshot rate (server/SERVER.md "Slow readers"): lowered (the interval
 * doubled, at most to one snapshot a second) when its queue backs up, at most once per
 * NET_RATE_DOWN_MS so a short stall costs one step; raised (halved) after it took every
 * snapshot offered for NET_RATE_UP_MS. */
#define NET_DUE_SLOTS 256
#define NET_RATE_DOWN_MS 500
#define NET_RATE_UP_MS 3000

/* A text sent to many connections (net.h): see net_shared.c for the layout. */
struct net_shared {
    atomic_int refs;
    size_t len;     /* text bytes */
    uint8_t *data;  /* owned: the pieces, each after LWS_PRE bytes of headroom */
};

/* Piece k of t (k < the pieces of t->len): its payload, LWS_PRE bytes of headroom before
 * it that a write may overwrite, and its length in *len (may be NULL). */
uint8_t *net_shared_piece(const net_shared *t, size_t k, size_t *len);

/* One queued control (text) message; data has LWS_PRE bytes of headroom. With a tail the
 * message is data then the tail's text, written as fragments: data first, then the tail
 * piece by piece (net_ws.c write_text). */
typedef struct net_text {
    uint8_t *data;     /* owned */
    size_t len;
    net_shared *tail;  /* one reference, or NULL */
    size_t tail_piece; /* the tail's next piece to write */
    bool started;      /* data went out: the message is under way, nothing else may go
                          between its fragments but a close */
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
    bool cur_key;         /* the state part of cur went out as its keyframe */
    uint32_t last_seq;    /* seq of the last state message written */
    uint32_t stream;      /* snapshot stream followed (net_peer.stream) */
    uint32_t last_stream; /* stream of the last state message written */
    int chain;            /* 0: holds nothing usable; 1: holds last_seq (a keyframe);
                             2: holds last_seq and last_seq - 1 */
    bool resync;          /* the client asked for a keyframe */
    /* the slow reader's rate (net_ws.c deliver_one) */
    int decim;            /* 1: every snapshot; n: one in n (net_desc.snapshot_hz at most) */
    size_t key_bytes;     /* its stream's last keyframe's bytes, with what rides only with
                             keyframes, and its last delta's (0: none seen), for the */
    size_t delta_bytes;   /* rate steps (net_rate.h) */
    uint64_t took_bytes;  /* bytes written since took_ns (ws_write) */
    uint64_t took_ns;     /* mono_ns the count began */
    double take_bytes_s;  /* bytes a second it took over the last whole second, 0 unknown */
    bool queued_any;      /* queued_seq and queued_stream hold the last snapshot queued */
    uint32_t queued_seq, queued_stream;
    uint64_t rate_ns;     /* mono_ns of the last rate change */
    uint64_t ahead_ns;    /* mono_ns since which every snapshot offered found nothing waiting */
    uint64_t take_ns;     /* mono_ns of the last message written, or of the last moment
                             nothing was waiting: a reader that takes nothing for
                             net_desc.stall_ms while something waits is closed (4008) */
    double tokens;        /* control messages the bucket allows now (NET_MSG_BURST at most) */
    uint64_t tokens_ns;   /* mono_ns of the last refill */
    net_text ctl[NET_CTL_MAX];
    int ctl_head, ctl_n;
    uint8_t *rx;          /* owned [max_message + 1]: reassembly of fragmented messages */
    size_t rx_len;
    bool rx_oversize;
    int close_code;       /* > 0: close at the next writeable, or hard at the close bound */
    char close_reason[100];
    /* HTTP response */
    uint8_t *http_owned;  /* owned body (healthz, metrics) or NULL */
    const uint8_t *http_body;
    size_t http_len, http_off; /* bytes of http_body to send, and sent */
    bool http_active;     /* a response is under way: HTTP_WRITEABLE sends or completes it */
    unsigned notice_gen;  /* the notice this connection was sent (net_set_notice) */
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
    net_limits lim;
    lws_sorted_usec_list_t grace_sul; /* wakes net_run's drain at its deadline */
    /* snapshot pool and the hand-over queue (mutex: sim thread <-> service thread) */
    net_snap *pool;  /* owned [n_pool] */
    int n_pool;
    pthread_mutex_t pub_lock;
    pthread_mutex_t bridge_lock; /* net_desc.published: one call at a time */
    net_snap **pub;   /* owned [pub_cap] */
    net_snap **batch; /* owned [pub_cap], service thread */
    int pub_n, pub_cap;
    atomic_int reset_streams; /* net_reset_streams asked; the service thread acts */
    /* net_frames_wanted: the connections' needs at the last delivery, and those asked
       for since the publisher's last call */
    atomic_uint want_standing, want_asked;
    /* net_stream_due: per slot (a stream's id mod NET_DUE_SLOTS) the seq from which the
       connections following its streams next take a snapshot, 0 any, at the last delivery */
    atomic_uint due_seq[NET_DUE_SLOTS];
    atomic_ullong pool_exhausted;
    atomic_ullong pub_overflow;
    /* rate limit of the bad-input log */
    time_t log_sec;
    int log_n;
    unsigned log_suppressed;
    uint8_t http_buf[LWS_PRE + NET_HTTP_CHUNK];
    /* the notice (net_set_notice): written by any thread under notice_lock */
    pthread_mutex_t notice_lock;
    char *notice;          /* owned */
    size_t notice_len;
    atomic_uint notice_gen; /* 0: none yet */
    unsigned notice_done;  /* service thread: the generation every connection was sent */
};

/* The tick counter the server lent (net_desc.tick), 0 without one. */
static inline unsigned net_tick(const net_server *s)
{
    return s->d.tick ? atomic_load(s->d.tick) : 0u;
}

/* --- net_ws.c: WebSocket connections ---------------------------------------------------- */

/* "conn 7 127.0.0.1 tick 1234: <what>" on stderr; it and net_log share a limit of
 * NET_LOG_PER_S lines a second. */
void net_conn_log(net_server *s, const net_conn *c, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* "gale-server: <what>" on stderr, rate-limited as net_conn_log. */
void net_log(net_server *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Drops one reference to a pooled snapshot (any thread). */
void net_snap_unref(net_snap *p);
/* Asks that c be closed with code/reason at its next writeable callback, after an error
 * message (ctl.h CTL_ERROR) that carries the same code and reason. */
void net_conn_close(net_server *s, net_conn *c, int code, const char *reason);
/* A new WebSocket connection on wsi: sets up c (lws zeroed it) and links it; -1 refuses
 * the connection (out of memory). */
int net_ws_established(net_server *s, net_conn *c, struct lws *wsi);
/* The connection closed: unlinks it and frees what c points to. */
void net_conn_free(net_server *s, net_conn *c);
/* Queues every snapshot the simulation published on the ready connections of its stream. */
void net_deliver_published(net_server *s);
/* SERVER_WRITEABLE: one message to c; -1 closes it. */
int net_ws_writeable(net_server *s, net_conn *c);
/* RECEIVE: a fragment of a control message, handed to net_desc.control once whole. */
int net_ws_receive(net_server *s, net_conn *c, const void *in, size_t len);
/* Sends c the notice when it said hello and has not had this one. */
void net_ws_notice(net_server *s, net_conn *c);
/* Sends every connection that said hello the notice, when it changed. */
void net_notice_deliver(net_server *s);
/* TIMER: the hello deadline (close 4009) or the close bound (the socket closed hard). */
int net_ws_timer(net_server *s, net_conn *c);

/* --- net_http.c: HTTP ------------------------------------------------------------------- */

/* LWS_CALLBACK_HTTP for uri: starts the response; nonzero closes the transaction. */
int net_http_request(net_server *s, net_conn *c, const char *uri);
/* HTTP_WRITEABLE: the next chunk of the body; nonzero closes the transaction. */
int net_http_writeable(net_server *s, net_conn *c);

#endif
