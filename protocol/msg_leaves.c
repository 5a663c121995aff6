/* LEAVES frames: seeds of the leaves shed this tick (instance, slot, spawn tick,
 * variation seed); clients fall each along the shared precomputed path (Vazquez 2008
 * section 3). Fixed 14 bytes per leaf; PROTOCOL.md "LEAVES" has the byte table. */
#include <stdio.h>

#include "wire.h"
#include "wire_cursor.h"
#include "wire_int.h"

#define LEAF_BYTES 14u

int wire_encode_leaves(const wire_header *h, const wire_leaf *leaves, uint32_t n,
                       uint8_t *buf, size_t cap, size_t *len, gale_err *err)
{
    if (n > WIRE_MAX_LEAVES) {
        return gale_errf(err, GALE_E_RANGE, "wire_encode_leaves: count: expected <= %u, got %u",
                         WIRE_MAX_LEAVES, n);
    }
    wire_writer w = wire_writer_make(buf, cap);
    wire_header hh = *h;
    hh.type = WIRE_MSG_LEAVES;
    hh.flags = 0;
    wire_put_header(&w, &hh);
    wire_put_u16(&w, (uint16_t)n);
    for (uint32_t i = 0; i < n; i++) {
        wire_put_u32(&w, leaves[i].instance);
        wire_put_u16(&w, leaves[i].slot);
        wire_put_u32(&w, leaves[i].spawn_tick);
        wire_put_u32(&w, leaves[i].seed);
    }
    if (w.bad) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_encode_leaves: buffer: expected %u bytes, got %zu",
                         WIRE_HEADER_BYTES + 2 + n * LEAF_BYTES, cap);
    }
    *len = (size_t)(w.p - buf);
    return 0;
}

int wire_decode_leaves(wire_reader *r, const wire_header *h, wire_leaf *leaves, uint32_t *n,
                       gale_err *err)
{
    *n = 0;
    uint32_t count = wire_get_u16(r);
    if (r->bad) {
        return gale_errf(err, GALE_E_FORMAT, "wire: LEAVES tick %u: count at byte %u: truncated",
                         h->tick, WIRE_HEADER_BYTES);
    }
    if (count > WIRE_MAX_LEAVES) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: LEAVES tick %u: count at byte %u: expected <= %u, got %u",
                         h->tick, WIRE_HEADER_BYTES, WIRE_MAX_LEAVES, count);
    }
    size_t want = (size_t)count * LEAF_BYTES;
    if (wire_reader_left(r) != want) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: LEAVES tick %u: length: expected %zu bytes for %u leaves, got %zu",
                         h->tick, WIRE_HEADER_BYTES + 2 + want, count,
                         WIRE_HEADER_BYTES + 2 + wire_reader_left(r));
    }
    for (uint32_t i = 0; i < count; i++) {
        leaves[i].instance = wire_get_u32(r);
        leaves[i].slot = wire_get_u16(r);
        leaves[i].spawn_tick = wire_get_u32(r);
        leaves[i].seed = wire_get_u32(r);
    }
    *n = count;
    return 0;
}
