/* Client networking (DESIGN.md "Wire", "Data flow"): one libwebsockets client context
 * holding the WebSocket to the server (hello as the chosen role, welcome, binary state
 * frames decoded as they arrive, pings for the clock, resync on a gap) and HTTP GETs of
 * assets from the same server; reconnects with backoff when the server goes away. */
#ifndef GALE_NET_H
#define GALE_NET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ctl.h"
#include "err.h"
#include "jitter.h"
#include "wire.h"

#define NET_WS_PROTOCOL "gale" /* WebSocket subprotocol requested */

enum net_state {
    NET_IDLE = 0,   /* not started */
    NET_CONNECTING, /* TCP + WebSocket handshake under way */
    NET_HELLO,      /* hello sent, waiting for welcome */
    NET_LIVE,       /* welcome received; state frames flowing */
    NET_BACKOFF,    /* connection lost or refused; waiting to retry */
};

/* What the application hears, called from inside net_poll / net_fetch (the welcome and
 * frames are borrowed for the call). Any may be NULL. */
typedef struct net_handler {
    void *user;
    /* The scene description of a (re)connection. */
    void (*on_welcome)(void *user, const ctl_welcome *w);
    /* One decoded binary frame; dec holds the decoded state (KEYFRAME/DELTA). recv_s is
     * the local clock when its last byte arrived. */
    void (*on_frame)(void *user, const wire_frame *f, const wire_decoder *dec, double recv_s);
    /* The connection ended (close code or 0 for a transport error, and why). */
    void (*on_lost)(void *user, int close_code, const char *why);
} net_handler;

typedef struct net_desc {
    const char *url;        /* ws://host:port[/path]; required */
    int role;               /* enum ctl_role */
    const char *token;      /* kiosk token; NULL = none */
    double backoff_min_s;   /* first retry delay; 0 = 0.25 s */
    double backoff_max_s;   /* cap of the doubling; 0 = 5 s */
    double ping_interval_s; /* 0 = 0.5 s */
    uint32_t max_trees;     /* decoder capacity; 0 = WIRE_MAX_TREES */
    uint32_t max_modes;     /* 0 = WIRE_MAX_MODES */
} net_desc;

typedef struct net_stats {
    int state;           /* enum net_state */
    uint64_t frames_ok;  /* binary frames decoded */
    uint64_t frames_bad; /* binary frames dropped as undecodable */
    uint64_t frames_gap; /* deltas without their base (resync asked) */
    uint64_t ctl_bad;    /* control messages that did not parse */
    uint64_t bytes_rx;
    uint32_t connects;    /* successful WebSocket handshakes */
    uint32_t attempt;     /* consecutive failed attempts (BACKOFF) */
    double retry_at_s;    /* BACKOFF: local time of the next attempt */
    int last_close;       /* close code of the last disconnect (0 transport) */
    char last_error[200]; /* why the last connection ended / was refused */
} net_stats;

typedef struct net net;

/* Parses the URL and creates the lws context; connects on the first net_poll. Allocates
 * every buffer it will use (a receive buffer of WIRE_MAX_FRAME_BYTES, the decoder). NULL
 * with err on a bad URL or no memory. */
net *net_create(const net_desc *d, const net_handler *h, gale_err *err);

/* Closes the connection and frees everything. NULL is a no-op. */
void net_destroy(net *n);

/* Services the sockets without blocking, sends pings, and (in BACKOFF) reconnects when
 * the delay has passed. now_s is the local monotonic clock (net_now). */
void net_poll(net *n, double now_s);

/* Local monotonic clock [s] (CLOCK_MONOTONIC). */
double net_now(void);

/* "host:port" of the server (owned by n). */
const char *net_server_name(const net *n);

/* Queues a kiosk wind command (GALE_E_STATE when not live, GALE_E_RANGE when invalid). */
int net_send_wind(net *n, const ctl_wind *w, gale_err *err);

/* Downloads path from the server over HTTP into *out (malloc'd, caller frees) of *len
 * bytes, servicing the WebSocket meanwhile (callbacks may fire). Blocks at most
 * timeout_s. Returns 0, GALE_E_IO (connection, HTTP status, timeout) or GALE_E_RANGE
 * (longer than max_len). Must not be called from a handler callback. */
int net_fetch(net *n, const char *path, size_t max_len, double timeout_s, uint8_t **out,
              size_t *len, gale_err *err);

net_stats net_get_stats(const net *n);

/* The server clock estimate fed by pongs and frame arrivals. */
const jitter_clock *net_clock(const net *n);

/* Drops the connection now as if the server went away (tests; the F-key "reconnect"). */
void net_drop(net *n);

#endif
