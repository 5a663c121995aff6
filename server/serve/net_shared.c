/* Shared texts (net.h net_shared): a text sent to many connections, laid out in pieces of
 * NET_SHARED_PIECE bytes, each after LWS_PRE bytes of headroom. lws writes a fragment's
 * frame header into the LWS_PRE bytes before its payload; with headroom of its own before
 * every piece, the headers of one connection's fragments land in gaps no other connection
 * and no reader of the text (net_shared_copy, on another thread) ever reads. */
#include "net_int.h"

#include <stdlib.h>
#include <string.h>

/* The pieces and their headroom: piece k's payload starts at data + k * stride + LWS_PRE. */
static size_t n_pieces(size_t len)
{
    return (len + NET_SHARED_PIECE - 1) / NET_SHARED_PIECE;
}

net_shared *net_shared_create(const char *text, size_t len)
{
    if (!len) {
        return NULL;
    }
    const size_t stride = LWS_PRE + NET_SHARED_PIECE;
    net_shared *t = calloc(1, sizeof *t);
    if (!t || !(t->data = malloc(n_pieces(len) * stride))) {
        free(t);
        return NULL;
    }
    for (size_t off = 0; off < len; off += NET_SHARED_PIECE) {
        size_t n = len - off < NET_SHARED_PIECE ? len - off : NET_SHARED_PIECE;
        memcpy(net_shared_piece(t, off / NET_SHARED_PIECE, NULL), text + off, n);
    }
    t->len = len;
    atomic_init(&t->refs, 1);
    return t;
}

net_shared *net_shared_ref(net_shared *t)
{
    atomic_fetch_add_explicit(&t->refs, 1, memory_order_relaxed);
    return t;
}

void net_shared_unref(net_shared *t)
{
    if (t && atomic_fetch_sub_explicit(&t->refs, 1, memory_order_acq_rel) == 1) {
        free(t->data);
        free(t);
    }
}

size_t net_shared_len(const net_shared *t)
{
    return t->len;
}

uint8_t *net_shared_piece(const net_shared *t, size_t k, size_t *len)
{
    const size_t off = k * NET_SHARED_PIECE;
    if (len) {
        *len = t->len - off < NET_SHARED_PIECE ? t->len - off : NET_SHARED_PIECE;
    }
    return t->data + k * (LWS_PRE + NET_SHARED_PIECE) + LWS_PRE;
}

void net_shared_copy(const net_shared *t, char *out)
{
    for (size_t k = 0; k < n_pieces(t->len); k++) {
        size_t n;
        const uint8_t *p = net_shared_piece(t, k, &n);
        memcpy(out + k * NET_SHARED_PIECE, p, n);
    }
}
