/* A bounded per-connection send queue of shared, reference-counted frames (the lws
 * minimal-ws-server-ring idea, with a ring per connection): the newest frame always
 * gets in, the oldest is dropped when the ring is full, and a connection that keeps
 * losing frames without sending any is marked too slow so the server can cull it.
 * Single-threaded (the lws service thread); no allocation after sendq_init. */
#ifndef GALE_SENDQ_H
#define GALE_SENDQ_H

#include <stdint.h>

#include "err.h"

/* Called for every item the queue lets go of without handing it out (dropped or
 * left at fini), so the owner can drop its reference. */
typedef void (*sendq_release_fn)(void *item, void *ctx);

typedef struct sendq {
    void **slot;           /* owned [cap] ring storage */
    int cap;               /* capacity, >= 1 */
    int head;              /* index of the oldest item */
    int count;             /* items queued */
    uint64_t dropped;      /* items dropped to make room, over the queue's life */
    uint32_t drop_streak;  /* drops since the last pop: how far behind the consumer is */
    sendq_release_fn release;
    void *release_ctx;
} sendq;

/* Allocates a ring of cap items (1..65536). release may be NULL. */
int sendq_init(sendq *q, int cap, sendq_release_fn release, void *ctx, gale_err *err);
/* Releases every queued item and frees the ring. NULL or a zeroed queue is a no-op. */
void sendq_fini(sendq *q);
/* Appends item (the queue takes the caller's reference). When full, the oldest item is
 * released first and counted as dropped. */
void sendq_push(sendq *q, void *item);
/* Removes and returns the oldest item (the caller gets its reference), NULL if empty.
 * Resets the drop streak. */
void *sendq_pop(sendq *q);
/* Releases every queued item, counting none as dropped. */
void sendq_clear(sendq *q);

#endif
