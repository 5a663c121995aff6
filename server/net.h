/* Serving over libwebsockets on one port (DESIGN.md "Wire"): the gale WebSocket
 * protocol (JSON control in, binary state out), HTTP GET of baked assets by content
 * hash, /healthz and /metrics (Prometheus text). One lws service thread; the simulation
 * thread publishes encoded snapshots, each encoded once and shared by every connection
 * through a bounded per-connection queue (sendq.h), so a slow client never slows others. */
#ifndef GALE_NET_H
#define GALE_NET_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"

typedef struct net_server net_server;

/* Client roles (hello.role). */
enum { NET_ROLE_NONE, NET_ROLE_VIEWER, NET_ROLE_KIOSK, NET_ROLE_WALL, NET_ROLE_LOAD,
       NET_ROLE_COUNT };

/* One published snapshot: the binary messages of one snapshot tick. Every message is
 * stored after LWS_PRE bytes of headroom. The keyframe is sent to a connection that
 * has not received the snapshot the delta is based on (late joiners, and after drops);
 * the others get the delta. Extra messages (leaf seeds, coarse wind) follow. */
#define NET_SNAP_MAX_EXTRA 2
typedef struct net_snap {
    atomic_int refs;        /* 0 = free in the pool */
    uint32_t tick;          /* simulation tick of the state */
    uint32_t base_tick;     /* tick the delta is relative to; meaningless if !delta_len */
    size_t cap;             /* capacity of each buffer after LWS_PRE */
    size_t key_len;         /* keyframe bytes */
    size_t delta_len;       /* delta bytes, 0 = no delta (the keyframe goes to everyone) */
    size_t extra_len[NET_SNAP_MAX_EXTRA]; /* 0 = absent */
    uint8_t *key;           /* owned [LWS_PRE + cap] */
    uint8_t *delta;         /* owned [LWS_PRE + cap] */
    uint8_t *extra[NET_SNAP_MAX_EXTRA]; /* owned [LWS_PRE + cap] */
} net_snap;

/* A baked asset served at /assets/<hash>.gasset (bytes borrowed for the server's life). */
typedef struct net_asset {
    char hash[24];          /* 16 hex digits, lower case */
    const uint8_t *bytes;
    size_t len;
} net_asset;

/* What the server does with a client's control message, answered by the owner (srv_main)
 * on the lws thread. Return 0 to accept; a reply (NUL-terminated JSON text, copied) may be
 * written to reply[reply_cap]. Return a WebSocket close code (>= 1000) to close the
 * connection, with a short reason in reply. */
typedef int (*net_control_fn)(void *user, uint32_t conn_id, int *role, const char *text,
                              size_t len, char *reply, size_t reply_cap);

typedef struct net_desc {
    int port;                 /* 0 → 8080; -1 → an ephemeral port (tests) */
    const char *iface;        /* NULL → all interfaces; "127.0.0.1" for loopback only */
    int max_clients;          /* 0 → 2048 */
    int queue_frames;         /* per-connection snapshot queue; 0 → 8 */
    int lag_limit;            /* drops in a row before a laggard is closed; 0 → 90 (3 s at 30/s) */
    size_t snap_cap;          /* bytes per snapshot message (after LWS_PRE); required */
    size_t max_message;       /* largest control message accepted; 0 → 16384 */
    const net_asset *assets;  /* borrowed for the server's life */
    int n_assets;
    net_control_fn control;   /* required */
    void *control_user;
    /* Text sent to a viewer right after its hello is accepted (the scene description);
     * borrowed for the server's life. */
    const char *scene_json;
    size_t scene_json_len;
} net_desc;

/* Counters, readable from any thread; the simulation thread writes the tick ones. */
typedef struct net_metrics {
    atomic_ullong ticks;
    atomic_ullong tick_ns_sum;
    atomic_ullong tick_ns_max;
    atomic_ullong overruns;
    atomic_ullong snapshots;
    atomic_ullong bytes_sent;
    atomic_ullong frames_sent;
    atomic_ullong frames_dropped;
    atomic_ullong bad_messages;
    atomic_ullong laggards_closed;
    atomic_ullong connections_total;
    atomic_ullong leaves_shed;
    atomic_int clients[NET_ROLE_COUNT];
    atomic_uint current_tick;
} net_metrics;

/* Creates the lws context and listens; NULL on failure (port in use...) with err filled.
 * Allocates the snapshot pool up front. */
net_server *net_create(const net_desc *d, gale_err *err);
/* Closes every connection and frees everything. NULL is a no-op. */
void net_destroy(net_server *s);
/* The port actually listened on. */
int net_port(const net_server *s);
/* Shared counters. */
net_metrics *net_get_metrics(net_server *s);

/* Simulation thread: a free snapshot from the pool to fill (refs set to 1), or NULL when
 * all are still in flight (counted; the caller skips publishing this one). */
net_snap *net_snap_acquire(net_server *s);
/* Simulation thread: hands a filled snapshot to the service thread, which queues it on
 * every ready connection and drops the caller's reference. Wakes the service loop. */
void net_publish(net_server *s, net_snap *snap);

/* Service thread: runs lws until net_stop; then tells every client (close 1001) and
 * returns after they are closed or grace_ms passed. */
int net_run(net_server *s, int grace_ms);
/* Any thread or a signal handler: asks net_run to finish. */
void net_stop(net_server *s);

#endif
