/* Client networking (protocol/PROTOCOL.md): one libwebsockets client context, serviced
 * on a thread of its own, holding the WebSocket to the server (hello as the chosen role,
 * welcome, pings for the clock, resync on a gap) and HTTP GETs of assets from the same
 * server; reconnects with backoff when the server goes away. The thread reads the socket
 * as fast as the server writes, whatever the caller's frame rate (a software renderer at
 * a frame a second is no slow reader to the server); cli_net_poll decodes what arrived
 * since the last call, every message in order, and hands it to the handlers. */
#ifndef GALE_CLI_NET_H
#define GALE_CLI_NET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ctl.h"
#include "err.h"
#include "jitter.h"
#include "wire.h"

#define CLI_NET_WS_PROTOCOL "gale" /* WebSocket subprotocol requested */

enum cli_net_state {
    CLI_NET_IDLE = 0,   /* not started */
    CLI_NET_CONNECTING, /* TCP + WebSocket handshake under way */
    CLI_NET_HELLO,      /* hello sent, waiting for welcome */
    CLI_NET_LIVE,       /* welcome received; state frames flowing */
    CLI_NET_BACKOFF,    /* connection lost or refused; waiting to retry */
    CLI_NET_REFUSED,    /* the server refused the kiosk token (close 4007): an operator's
                           error that retrying cannot mend; no further attempts */
};

/* A connection that has not finished its handshake (CONNECTING) or got no welcome
 * (HELLO) this long after it began is abandoned and retried [s]. */
#define CLI_NET_CONNECT_TIMEOUT_S 10.0

/* Bytes of received messages held for cli_net_poll; past it the oldest frames are
 * dropped (counted in inbox_dropped; the decoder then asks for a keyframe): 2 minutes of
 * the town block's stream at 30 snapshots a second. */
#define CLI_NET_INBOX_BYTES (64u << 20)

/* What the application hears, called from inside cli_net_poll on its caller's thread (the
 * welcome and frames are borrowed for the call). Any may be NULL. */
typedef struct cli_net_handler {
    void *user;
    /* The scene description of a (re)connection. */
    void (*on_welcome)(void *user, const ctl_welcome *w);
    /* One decoded binary frame; dec holds the decoded state (KEYFRAME/DELTA). recv_s is
     * the local clock when its last byte arrived. */
    void (*on_frame)(void *user, const wire_frame *f, const wire_decoder *dec, double recv_s);
    /* The connection ended (close code or 0 for a transport error, and why). */
    void (*on_lost)(void *user, int close_code, const char *why);
    /* A display-wall message from the server (wall_sync, wall_swap, wall_camera), or the
     * exhibit's schedule (open or closed; every role gets it). */
    void (*on_wall)(void *user, const ctl_msg *m);
} cli_net_handler;

/* The system's trusted certificates (Debian's ca-certificates bundle). */
#define CLI_NET_SYSTEM_CA "/etc/ssl/certs/ca-certificates.crt"

typedef struct cli_net_desc {
    const char *url;        /* ws://host:port[/path], or wss:// for TLS; required */
    const char *tls_ca;     /* wss: PEM file of the certificates to trust (a self-signed
                               server's own); NULL = the system's (CLI_NET_SYSTEM_CA) */
    int role;               /* enum ctl_role */
    const char *token;      /* kiosk token; NULL = none */
    double backoff_min_s;   /* first retry delay; 0 = 0.25 s */
    double backoff_max_s;   /* cap of the doubling; 0 = 5 s */
    double ping_interval_s; /* 0 = 0.5 s */
    uint32_t max_trees;     /* decoder capacity; 0 = WIRE_MAX_TREES */
    uint32_t max_modes;     /* 0 = WIRE_MAX_MODES */
} cli_net_desc;

typedef struct cli_net_stats {
    int state;           /* enum cli_net_state */
    uint64_t frames_ok;  /* binary frames decoded */
    uint64_t frames_bad; /* binary frames dropped as undecodable */
    uint64_t frames_gap; /* deltas without their base (resync asked) */
    uint64_t ctl_bad;    /* control messages that did not parse */
    uint64_t bytes_rx;
    uint64_t inbox_dropped; /* frames dropped unread past CLI_NET_INBOX_BYTES */
    uint32_t connects;    /* successful WebSocket handshakes */
    uint32_t attempt;     /* consecutive failed attempts (BACKOFF) */
    double retry_at_s;    /* BACKOFF: local time of the next attempt */
    double retry_delay_s; /* BACKOFF: the delay the last failed attempt set [s] */
    int last_close;       /* close code of the last disconnect (0 transport) */
    char last_error[200]; /* why the last connection ended / was refused */
} cli_net_stats;

typedef struct cli_net cli_net;

/* Parses the URL, creates the lws context and starts the network thread, which connects
 * at once. Allocates a receive buffer of WIRE_MAX_FRAME_BYTES and the decoder; each
 * message received is copied once into the inbox. NULL with err on a bad URL, no memory
 * or no thread. */
cli_net *cli_net_create(const cli_net_desc *d, const cli_net_handler *h, gale_err *err);

/* Stops the network thread, closes the connection and frees everything. NULL is a no-op. */
void cli_net_destroy(cli_net *n);

/* Decodes every message the network thread received since the last call, in order, and
 * calls the handlers (a new connection's decoder and clock start afresh; a delta without
 * its base asks for a keyframe). Never blocks on the network: the thread sends pings,
 * reconnects after its backoff and reads the socket meanwhile. */
void cli_net_poll(cli_net *n);

/* "host:port" of the server (owned by n). */
const char *cli_net_server_name(const cli_net *n);

/* Queues a display-wall message (wall_join, wall_drawn, wall_camera): GALE_E_STATE when
 * not live or the send queue is full, GALE_E_RANGE when invalid. */
int cli_net_send_wall(cli_net *n, const ctl_msg *m, gale_err *err);
/* Queues a kiosk wind command (GALE_E_STATE when not live, GALE_E_RANGE when invalid). */
int cli_net_send_wind(cli_net *n, const ctl_wind *w, gale_err *err);
/* Queues any client control message (a kiosk's wind or reset); the same errors. When
 * text is not NULL it gets the JSON sent (cap bytes, cut to fit), for the kiosk's log. */
int cli_net_send_ctl(cli_net *n, const ctl_msg *m, char *text, size_t cap, gale_err *err);

/* Downloads path from the server over HTTP into *out (malloc'd, caller frees) of *len
 * bytes on the network thread, which keeps reading the WebSocket meanwhile (no handler
 * runs: what arrives waits for cli_net_poll). Blocks at most timeout_s (and up to 2 s
 * more for an abandoned socket to close). Returns 0, GALE_E_IO (connection, HTTP status, timeout) or GALE_E_RANGE
 * (longer than max_len). Must not be called from a handler callback. */
int cli_net_fetch(cli_net *n, const char *path, size_t max_len, double timeout_s, uint8_t **out,
              size_t *len, gale_err *err);

/* cli_net_fetch of an asset, then its bytes checked against hash_hex, the species' hash
 * in the welcome (asset_cache_verify): on a mismatch GALE_E_CHECKSUM ("http://HOST/PATH:
 * content hash H, expected E (the welcome's): refused"), the bytes freed and *out NULL, so
 * nothing unverified reaches the decoder or the cache. Other failures as cli_net_fetch. */
int cli_net_fetch_asset(cli_net *n, const char *path, const char *hash_hex, size_t max_len,
                        double timeout_s, uint8_t **out, size_t *len, gale_err *err);

cli_net_stats cli_net_get_stats(const cli_net *n);

/* The server clock estimate fed by pongs and frame arrivals (as cli_net_poll hands them
 * on, each with the time it arrived); the poller's thread only. */
const jitter_clock *cli_net_clock(const cli_net *n);

/* Drops the connection now as if the server went away (tests; the F-key "reconnect"). */
void cli_net_drop(cli_net *n);

#endif
