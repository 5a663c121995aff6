/* A relay's own view streams (server/SERVER.md "Relays", "Views through a relay"): each
 * distinct view of the relay's clients selected and encoded at the relay, from the
 * server's whole-scene stream, with the server's rule and encoder: view_select_grid over
 * the tree bases and margin the server sends on gale.scene (link.h), its modes past
 * lod_m, and srv_stream.h on the quantised state decoded from each shared keyframe. A
 * relayed client thus gets the frames a client of the server with the same view gets,
 * and the server encodes nothing for relayed views. */
#ifndef GALE_RELAY_VIEWS_H
#define GALE_RELAY_VIEWS_H

#include <stdint.h>

#include "ctl.h"
#include "err.h"
#include "link.h"
#include "net.h"

typedef struct relay_views relay_views;

/* Up to max_views distinct views (the server's own limit, link_info.max_streams): beyond
 * them a connection's view is ignored and it follows the shared stream, as on the server.
 * Takes ownership of sc->pos. NULL with err. */
relay_views *relay_views_create(link_scene *sc, int max_views, gale_err *err);
void relay_views_destroy(relay_views *v); /* NULL is a no-op */

/* lws thread: moves a connection from stream old to the stream of view (NULL or
 * CTL_VIEW_ALL: the shared stream 0); an equal view already followed is shared, else a
 * free slot takes it. Returns the connection's new stream. */
uint32_t relay_views_join(relay_views *v, uint32_t old, const ctl_view *view);

/* The delivery thread, after the shared snapshot p (as received: bundled or not) went to
 * net_publish: decodes its keyframe and publishes each view stream's snapshot of the
 * same seq on net, with the same extras as p. p is read, not kept. */
void relay_views_publish(relay_views *v, net_server *net, const net_snap *p);

/* The delivery thread: every view stream's next snapshot is a keyframe (the server
 * restarted: its state continues no chain). */
void relay_views_restart(relay_views *v);

/* Counters: view snapshots published, the time spent encoding them [ns], shared
 * snapshots whose keyframe did not decode. Any thread. */
void relay_views_counts(const relay_views *v, unsigned long long *snapshots,
                        unsigned long long *encode_ns, unsigned long long *bad);

#endif
