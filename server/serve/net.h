/* Serving over libwebsockets on one port (protocol/PROTOCOL.md, server/SERVER.md
 * "Serving"): the gale WebSocket protocol (JSON control in, binary state out), HTTP GET
 * of baked assets by content hash, /healthz, and /metrics (a metric.h registry rendered
 * as Prometheus text). One lws service thread; the simulation thread publishes encoded
 * snapshots, each encoded once and shared by every connection through a bounded
 * per-connection queue (sendq.h), so a slow client never slows others. */
#ifndef GALE_NET_H
#define GALE_NET_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "metric.h"

typedef struct net_server net_server;
typedef struct net_shared net_shared; /* a text sent to many connections, below */

/* Client roles (hello.role). */
enum { NET_ROLE_NONE, NET_ROLE_VIEWER, NET_ROLE_KIOSK, NET_ROLE_WALL, NET_ROLE_LOAD,
       NET_ROLE_COUNT };

/* One published snapshot: the binary messages of one snapshot (sequence number seq),
 * each encoded once and shared by every connection. A connection that holds snapshots
 * seq-1 and seq-2 gets delta2 (linear prediction from both), one that holds only seq-1
 * (it was a keyframe) gets delta1, any other (late joiner, after drops, after a resync
 * request) the keyframe. Extra messages (leaf seeds, coarse wind, damage, weather, forest) follow
 * the state; one whose bit is set in extra_key_only goes only with a keyframe. Unless
 * net_desc.separate_extras, net_publish wraps each state variant and its extras into one
 * BUNDLE and clears extra_len. */
#define NET_SNAP_MAX_EXTRA 6
typedef struct net_snap {
    atomic_int refs;        /* 0 = free in the pool */
    uint32_t seq;           /* snapshot sequence number (wire.h) */
    uint32_t stream;        /* 0: the shared whole-scene stream; else a view stream (only
                               connections with net_peer.stream equal to it get it) */
    size_t cap;             /* capacity of each state buffer after LWS_PRE */
    size_t extra_cap;       /* capacity of each extra buffer after LWS_PRE */
    size_t key_len;         /* keyframe bytes (required) */
    size_t delta1_len;      /* delta against seq-1 only; 0 = none */
    size_t delta2_len;      /* delta against seq-1 and seq-2; 0 = none */
    size_t extra_len[NET_SNAP_MAX_EXTRA]; /* 0 = absent */
    unsigned extra_key_only; /* bit e set: extra e goes only to a connection that gets this
                                snapshot's keyframe (a joiner's first picture is complete) */
    uint8_t *key;           /* owned [cap], with LWS_PRE bytes of headroom before it */
    uint8_t *delta1;        /* owned [cap], likewise */
    uint8_t *delta2;        /* owned [cap], likewise */
    uint8_t *extra[NET_SNAP_MAX_EXTRA]; /* owned [extra_cap], likewise */
} net_snap;

/* A baked asset served at /assets/<hash>.gasset (bytes borrowed for the server's life). */
typedef struct net_asset {
    char hash[24];          /* 16 hex digits, lower case */
    const uint8_t *bytes;
    size_t len;
} net_asset;

/* A connection as the control handler sees it (and may change). */
typedef struct net_peer {
    uint32_t id;          /* connection id, for logs and welcome.client_id */
    const char *addr;     /* peer address */
    int role;             /* NET_ROLE_*; set it when a hello is accepted */
    bool resync;          /* set to send a keyframe next */
    uint32_t stream;      /* snapshot stream this connection follows (0 = shared); the
                             handler may change it (the first state frame of another stream
                             is always a keyframe) */
    bool shared_ok;       /* set by net: the handler may answer with reply_shared (false for
                             a relayed connection's, which needs its reply whole) */
    net_shared *reply_shared; /* handler, with shared_ok and a *reply: the reply goes on with
                                 this text, one message of *reply then it (one reference handed
                                 to net) */
} net_peer;

/* Bytes of a shared text per WebSocket fragment: what a 32 KiB send buffer (net_desc.sndbuf's
 * default) takes in one write, so lws seldom has to keep a remainder. */
#define NET_SHARED_PIECE 16384

/* net_shared: a text message's tail built once and sent to many connections (the
 * welcome's scene part, megabytes at 100,000 trees): reference-counted, and laid out in
 * NET_SHARED_PIECE pieces each with LWS_PRE bytes of headroom before it, so every
 * connection writes each piece as a fragment of its own message in place, without a copy
 * of the text of its own (SERVER.md "The welcome"). The bytes never change after
 * net_shared_create.
 *
 * Any thread: a shared text holding a copy of the len bytes at text (len >= 1), with one
 * reference for the caller; NULL when out of memory or len is 0. */
net_shared *net_shared_create(const char *text, size_t len);
/* Any thread: one more reference to t, which it returns. */
net_shared *net_shared_ref(net_shared *t);
/* Any thread: drops one reference; the last frees t. NULL is a no-op. */
void net_shared_unref(net_shared *t);
/* The text's length in bytes. */
size_t net_shared_len(const net_shared *t);
/* Copies the whole text to out[net_shared_len(t)] (a reply that cannot be shared: a
 * relayed connection's). */
void net_shared_copy(const net_shared *t, char *out);

/* What the server does with a client's control (text) message, on the lws thread.
 * Return 0 to accept; *reply may be set to a malloc'd text of *reply_len bytes that net
 * sends and frees. Return a close code (enum wire_close) to close the connection, with
 * the reason written to why[why_cap]. */
typedef int (*net_control_fn)(void *user, net_peer *peer, const char *text, size_t len,
                              char **reply, size_t *reply_len, char *why, size_t why_cap);

/* A connection being closed (any code) has its socket closed by this bound even when its
 * peer never reads the close (server/SERVER.md "Connections"). */
#define NET_CLOSE_BOUND_MS 2000
/* net_desc.stall_ms's default. */
#define NET_STALL_MS 10000

typedef struct net_desc {
    int port;                 /* 0 → 8080; -1 → an ephemeral port (tests) */
    const char *iface;        /* NULL → all interfaces; "127.0.0.1" for loopback only */
    int max_clients;          /* WebSocket connections; 0 → 2048; lowered to what the open-file
                                 limit (RLIMIT_NOFILE) leaves room for (net_get_limits) */
    int hello_timeout_ms;     /* a connection with no accepted hello this long after its
                                 upgrade is closed with 4009; 0 → 5000, < 0 → never */
    int queue_frames;         /* per-connection snapshot queue; 0 → 8 */
    int stall_ms;             /* a reader that takes nothing for this long while snapshots wait
                                 is closed with 4008 [ms]; a slower one gets fewer snapshots
                                 instead (SERVER.md "Slow readers"); 0 → NET_STALL_MS */
    int snapshot_hz;          /* snapshots published a second per stream: a slow reader gets
                                 one a second at least; 0 → 30 */
    size_t snap_cap;          /* bytes per state message (after LWS_PRE); required */
    size_t extra_cap;         /* bytes per extra message; 0 → 65536 */
    bool separate_extras;     /* true: extras go as messages of their own; false: each
                                 state frame and the extras of its snapshot travel as one
                                 BUNDLE (PROTOCOL.md "BUNDLE"), one write per client */
    size_t max_message;       /* largest control message accepted; 0 → CTL_MAX_CLIENT_BYTES */
    int sndbuf;               /* kernel send buffer per connection [bytes]; 0 → 32768,
                                 -1 → the kernel's own (bounds what a stalled client pins) */
    const net_asset *assets;  /* borrowed for the server's life */
    int n_assets;
    net_control_fn control;   /* required */
    void *control_user;
    /* called when a connection that said hello closes (releases its stream); may be NULL */
    void (*closed)(void *user, const net_peer *peer);
    int max_streams;          /* view streams published besides the shared one (sizes the
                                 snapshot pool and the hand-over queue); 0 → none */
    /* called by net_publish with every snapshot as it goes out (bundled), on the publishing
     * thread, one call at a time; NULL: none (a broker bridge, server/relay/) */
    void (*published)(void *user, const net_snap *snap);
    void *published_user;
    const metric_reg *metrics; /* the rows served at /metrics, borrowed and complete before
                                  net_run; NULL → an empty page */
    const atomic_uint *tick;  /* the simulation's tick counter, borrowed: /healthz and the
                                 connection log lines show it; NULL → 0 */
    int http_idle_s;          /* an HTTP response that could write no chunk for this long [s]
                                 is closed (the timer restarts on every chunk, so a slow
                                 reader that keeps reading completes); 0 → 10 */
    int http_sndbuf;          /* kernel send buffer of HTTP responses [bytes]; 0 → the
                                 kernel's own (autotuned, so downloads keep their speed on
                                 long links) */
    /* GET /status: the body (JSON, malloc'd, *len bytes) on the service thread; NULL → 404 */
    char *(*status)(void *user, size_t *len);
    void *status_user;
    /* rows appended to /metrics after the registry's (malloc'd Prometheus text, *len
       bytes), on the service thread; NULL → none */
    char *(*metrics_more)(void *user, size_t *len);
    void *metrics_user;
    const char *tls_cert;     /* PEM certificate chain: serve https and wss only; NULL → plain */
    const char *tls_key;      /* PEM private key of tls_cert */
} net_desc;

/* The network's counters, readable from any thread (net_metrics_register makes them
 * /metrics rows). */
typedef struct net_metrics {
    atomic_ullong snapshots;        /* shared-stream snapshots published (net_publish) */
    atomic_ullong bytes_sent;
    atomic_ullong frames_sent;
    atomic_ullong frames_dropped;
    atomic_ullong bad_messages;
    atomic_ullong laggards_closed;
    atomic_ullong connections_total;
    atomic_ullong refused;          /* closed with 4010, or at accept at the descriptor cap */
    atomic_ullong hello_timeouts;   /* closed with 4009 for saying no hello in time */
    atomic_int clients[NET_ROLE_COUNT];
    atomic_int decimated;           /* connections sent fewer snapshots than published now */
    atomic_ullong decimations;      /* times a connection's snapshot rate was lowered */
    atomic_ullong frame_waits;      /* snapshots a connection skipped, lacking its frame */
} net_metrics;

/* The connection limits net_create settled on. */
typedef struct net_limits {
    int requested;     /* net_desc.max_clients (after its default) */
    int max_clients;   /* WebSocket connections served; more get 4010 */
    int fd_cap;        /* an accepted socket with a descriptor number at or above this is
                          closed at once (the rest of the descriptors stay free so accept
                          never fails with EMFILE) */
    long nofile;       /* RLIMIT_NOFILE's soft limit when net_create ran */
} net_limits;

/* Creates the lws context and listens; NULL on failure (port in use...) with err filled.
 * Allocates the snapshot pool up front. */
net_server *net_create(const net_desc *d, gale_err *err);
/* Closes every connection and frees everything. NULL is a no-op. */
void net_destroy(net_server *s);
/* The port actually listened on. */
int net_port(const net_server *s);
/* The connection limits in force. */
net_limits net_get_limits(const net_server *s);
/* The network's counters. */
net_metrics *net_get_metrics(net_server *s);
/* Adds the network's rows (gale_snapshots_total, gale_bytes_sent_total, ...,
 * gale_clients{role=...}) to r; s is borrowed for r's life. Fails only when r is full
 * (metric_reg_add). */
int net_metrics_register(net_server *s, metric_reg *r, gale_err *err);

/* Bytes behind each state buffer of a pooled snapshot: the encoders' snap_cap plus room
 * to wrap it with every extra into a BUNDLE. */
size_t net_snap_buffer_cap(size_t snap_cap, size_t extra_cap);

/* Any thread: at the next delivery every connection follows the shared stream (0) and
 * gets a keyframe (the publisher's streams started over: a relay's server restarted). */
void net_reset_streams(net_server *s);

/* The state frames a snapshot's connections may need besides delta2 (which a connection
 * holding the two snapshots before it takes): NET_WANT_KEY when one joins, resyncs, follows
 * a new stream, lost its chain or is sent one snapshot in several (a slow reader);
 * NET_WANT_DELTA1 when one holds only the last (it took a keyframe). */
enum { NET_WANT_KEY = 1u, NET_WANT_DELTA1 = 2u, NET_WANT_ALL = 3u };
/* Simulation thread, once per snapshot: the frames wanted now by any connection (the
 * connections' standing needs as the service thread last saw them, and any asked for
 * since the last call); NET_WANT_ALL with a net_desc.published bridge (a relay's clients
 * may need any). A connection whose frame a snapshot lacks skips that snapshot and asks
 * again (SERVER.md "Frames on demand"). */
unsigned net_frames_wanted(net_server *s);
/* net_frames_wanted's frames, of the shared stream and of the view streams apart, with
 * NET_WANT_ANY while any connection follows (without it none takes even delta2), so a
 * stream nobody follows need not be encoded: the shared stream's in the low bits
 * (NET_WANT_SHARED), the view streams' shifted by NET_WANT_VIEWS_SHIFT (NET_WANT_VIEWS);
 * everything with a bridge. Call one of the two per snapshot: each takes the asks. */
#define NET_WANT_ANY 4u
#define NET_WANT_BITS 7u
#define NET_WANT_VIEWS_SHIFT 3
#define NET_WANT_SHARED(mask) ((mask) & NET_WANT_BITS)
#define NET_WANT_VIEWS(mask) (((mask) >> NET_WANT_VIEWS_SHIFT) & NET_WANT_BITS)
unsigned net_frames_wanted_apart(net_server *s);

/* A view encoder, before it encodes a snapshot of view stream `stream` (not 0): the seq
 * from which the stream's connections next take one, as the service thread last saw them
 * (SERVER.md "Slow readers": each of a slow reader's is one in n); 0 when any of them may
 * take the next, or the stream has none yet. Streams sharing a slot take the lowest. */
uint32_t net_stream_due(net_server *s, uint32_t stream);

/* Publishing threads (the simulation's, a view encoder's): a free snapshot from the pool
 * to fill (refs set to 1), or NULL when all are still in flight (counted; the caller
 * skips publishing this one). */
net_snap *net_snap_acquire(net_server *s);
/* Publishing threads: hands a filled snapshot to the service thread, which queues it on
 * every ready connection and drops the caller's reference. Wakes the service loop. */
void net_publish(net_server *s, net_snap *snap);

/* Service thread (inside net_desc.control or closed): queues text for connection conn as
 * a control reply is queued; 0, or -1 when conn is not an open WebSocket (or its queue is
 * full: it is then closed with 4012 as a reader that does not read its replies). */
int net_send_text(net_server *s, uint32_t conn, const char *text, size_t len);

/* Any thread: the notice, a control text every connection that said hello is sent once:
 * at once, and after its welcome when it joins later; a new notice replaces the last (the
 * exhibit's schedule). Copies text. */
void net_set_notice(net_server *s, const char *text, size_t len);

/* Service thread: runs lws until net_stop; then tells every client (close 1001, each
 * socket closed within NET_CLOSE_BOUND_MS whatever its peer does) and returns after they
 * are closed or grace_ms passed. */
int net_run(net_server *s, int grace_ms);
/* Any thread or a signal handler: asks net_run to finish. */
void net_stop(net_server *s);

#endif
