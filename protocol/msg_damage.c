/* DAMAGE frames: storm damage as events (a branch broke off, a stem snapped, a tree was
 * uprooted, a crown's leaf level fell) or, after a keyframe, as the whole damage state, so
 * a late joiner sees the same broken forest. Fixed 14 bytes per event; PROTOCOL.md
 * "DAMAGE" has the byte table. */
#include <stdio.h>

#include "wire.h"
#include "wire_cursor.h"
#include "wire_int.h"

#define DAMAGE_EVENT_BYTES 14u

int wire_encode_damage(const wire_header *h, bool full, const wire_damage *ev, uint32_t n,
                       uint8_t *buf, size_t cap, size_t *len, gale_err *err)
{
    if (n > WIRE_MAX_DAMAGE) {
        return gale_errf(err, GALE_E_RANGE, "wire_encode_damage: count: expected <= %u, got %u",
                         WIRE_MAX_DAMAGE, n);
    }
    wire_writer w = wire_writer_make(buf, cap);
    wire_header hh = *h;
    hh.type = WIRE_MSG_DAMAGE;
    hh.flags = 0;
    wire_put_header(&w, &hh);
    wire_put_u8(&w, full ? 1 : 0);
    wire_put_u16(&w, (uint16_t)n);
    for (uint32_t i = 0; i < n; i++) {
        wire_put_u32(&w, ev[i].tree);
        wire_put_u32(&w, ev[i].node);
        wire_put_u8(&w, ev[i].kind);
        wire_put_u8(&w, ev[i].value);
        wire_put_u32(&w, ev[i].tick);
    }
    if (w.bad) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_encode_damage: buffer: expected %u bytes, got %zu",
                         WIRE_HEADER_BYTES + 3 + n * DAMAGE_EVENT_BYTES, cap);
    }
    *len = (size_t)(w.p - buf);
    return 0;
}

int wire_decode_damage(wire_reader *r, const wire_header *h, wire_damage *ev, uint32_t *n,
                       bool *full, gale_err *err)
{
    *n = 0;
    *full = false;
    uint32_t f = wire_get_u8(r);
    uint32_t count = wire_get_u16(r);
    if (r->bad) {
        return gale_errf(err, GALE_E_FORMAT, "wire: DAMAGE tick %u: full, count at byte %u: truncated",
                         h->tick, WIRE_HEADER_BYTES);
    }
    if (f > 1) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: DAMAGE tick %u: full at byte %u: expected 0 or 1, got %u", h->tick,
                         WIRE_HEADER_BYTES, f);
    }
    if (count > WIRE_MAX_DAMAGE) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: DAMAGE tick %u: count at byte %u: expected <= %u, got %u",
                         h->tick, WIRE_HEADER_BYTES + 1, WIRE_MAX_DAMAGE, count);
    }
    size_t want = (size_t)count * DAMAGE_EVENT_BYTES;
    if (wire_reader_left(r) != want) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: DAMAGE tick %u: length: expected %zu bytes for %u events, got %zu",
                         h->tick, WIRE_HEADER_BYTES + 3 + want, count,
                         WIRE_HEADER_BYTES + 3 + wire_reader_left(r));
    }
    for (uint32_t i = 0; i < count; i++) {
        wire_damage e;
        e.tree = wire_get_u32(r);
        e.node = wire_get_u32(r);
        e.kind = wire_get_u8(r);
        e.value = wire_get_u8(r);
        e.tick = wire_get_u32(r);
        size_t at = WIRE_HEADER_BYTES + 3 + (size_t)i * DAMAGE_EVENT_BYTES;
        bool whole = e.kind != WIRE_DAMAGE_BRANCH;
        if (e.kind < WIRE_DAMAGE_BRANCH || e.kind > WIRE_DAMAGE_STRIP) {
            return gale_errf(err, GALE_E_FORMAT,
                             "wire: DAMAGE tick %u: event %u kind at byte %zu: expected 1..4, got %u",
                             h->tick, i, at + 8, (unsigned)e.kind);
        }
        if (whole != (e.node == WIRE_DAMAGE_WHOLE)) {
            return gale_errf(err, GALE_E_FORMAT,
                             "wire: DAMAGE tick %u: event %u node at byte %zu: expected %s, got %u",
                             h->tick, i, at + 4,
                             whole ? "0xffffffff (whole tree)" : "a node index", e.node);
        }
        if ((e.kind == WIRE_DAMAGE_STRIP && e.value > WIRE_DAMAGE_LEVELS) ||
            (e.kind == WIRE_DAMAGE_BRANCH && e.value != 0)) {
            return gale_errf(err, GALE_E_FORMAT,
                             "wire: DAMAGE tick %u: event %u value at byte %zu: expected %s, got %u",
                             h->tick, i, at + 9, e.kind == WIRE_DAMAGE_STRIP ? "0..32" : "0",
                             (unsigned)e.value);
        }
        ev[i] = e;
    }
    *n = count;
    *full = f == 1;
    return 0;
}
