/* gale-server's side of the NATS link (link.h, server/SERVER.md "Relays"): publishes every
 * snapshot of the shared stream once, and answers the relays'
 * requests (control messages and closes of relayed connections, sizes, assets and the
 * view rule a relay selects its clients' views with). */
#ifndef GALE_LINK_SERVER_H
#define GALE_LINK_SERVER_H

#include <nats/nats.h>

#include "err.h"
#include "net.h"
#include "srv.h"

typedef struct link_server link_server;

/* Connects to the NATS server(s) at url (comma-separated list), retrying in the background
 * while none answers; NULL on a bad url. */
link_server *link_server_create(const char *url, gale_err *err);
/* net_desc.published: one NATS message per shared-stream snapshot (publishing thread);
 * the view streams' snapshots stay on the server (relays encode their clients' views). */
void link_server_publish(void *user, const net_snap *p);
/* Starts answering requests for s (which must outlive the link). */
int link_server_attach(link_server *l, srv *s, gale_err *err);
/* Counters: snapshots published, publish failures (NATS down or too big). */
void link_server_counts(const link_server *l, unsigned long long *published,
                        unsigned long long *failed);
void link_server_destroy(link_server *l); /* NULL is a no-op */

/* The NATS options gale uses on both ends: reconnect forever, every 250 ms, retry the
 * first connect, buffer 8 MiB while disconnected, a dead link noticed within ~1 s.
 * name: the client name NATS shows. */
natsOptions *link_nats_options(const char *url, const char *name, gale_err *err);

#endif
