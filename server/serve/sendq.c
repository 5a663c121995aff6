/* Bounded per-connection send queue: see sendq.h. */
#include "sendq.h"

#include <stdlib.h>
#include <string.h>

int sendq_init(sendq *q, int cap, sendq_release_fn release, void *ctx, gale_err *err)
{
    memset(q, 0, sizeof *q);
    if (cap < 1 || cap > 65536) {
        return gale_errf(err, GALE_E_ARG, "sendq_init: cap: expected 1..65536, got %d", cap);
    }
    q->slot = calloc((size_t)cap, sizeof *q->slot);
    if (!q->slot) {
        return gale_errf(err, GALE_E_NOMEM, "sendq_init: no memory for %d slots", cap);
    }
    q->cap = cap;
    q->release = release;
    q->release_ctx = ctx;
    return GALE_OK;
}

static void release_one(sendq *q, void *item)
{
    if (q->release && item) {
        q->release(item, q->release_ctx);
    }
}

void sendq_push(sendq *q, void *item)
{
    if (q->count == q->cap) {
        /* Full: the oldest state is the least useful, drop it (newest wins). */
        release_one(q, q->slot[q->head]);
        q->head = (q->head + 1) % q->cap;
        q->count--;
        q->dropped++;
        q->drop_streak++;
    }
    q->slot[(q->head + q->count) % q->cap] = item;
    q->count++;
}

void *sendq_pop(sendq *q)
{
    if (q->count == 0) {
        return NULL;
    }
    void *item = q->slot[q->head];
    q->slot[q->head] = NULL;
    q->head = (q->head + 1) % q->cap;
    q->count--;
    q->drop_streak = 0;
    return item;
}

void sendq_clear(sendq *q)
{
    while (q->count > 0) {
        release_one(q, q->slot[q->head]);
        q->slot[q->head] = NULL;
        q->head = (q->head + 1) % q->cap;
        q->count--;
    }
}

void sendq_fini(sendq *q)
{
    if (!q || !q->slot) {
        return;
    }
    sendq_clear(q);
    free(q->slot);
    memset(q, 0, sizeof *q);
}
