/* gale-relay: an edge (server/SERVER.md "Relays"). It takes gale-server's encoded
 * whole-scene snapshots from NATS (link.h) and serves WebSocket clients with the same
 * network layer as gale-server (net.h: handshake limits, close codes, per-connection
 * queues that pick keyframe or delta, BUNDLE, assets over HTTP from its cache); it
 * selects and encodes its clients' views itself with the server's rule (relay_views.h)
 * and forwards every other control message to the server by request/reply, applying its
 * verdict. */
#ifndef GALE_RELAY_H
#define GALE_RELAY_H

#include "err.h"

typedef struct relay relay;

typedef struct relay_desc {
    const char *nats_url; /* required: nats://HOST:PORT[,nats://...] */
    int port;             /* -1: ephemeral */
    const char *iface;    /* NULL: every interface */
    double wait_s;        /* how long to wait for gale-server's info and assets; 0 → 30 */
} relay_desc;

/* Connects, fetches the server's sizes and assets over NATS, listens. NULL with err. */
relay *relay_create(const relay_desc *d, gale_err *err);
int relay_port(const relay *r);
/* Serves until relay_stop. */
int relay_run(relay *r);
void relay_stop(relay *r); /* any thread or a signal handler */
void relay_destroy(relay *r);

#endif
