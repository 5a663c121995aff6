/* FOREST frames: every tree's fall and leaf level at one tick, one byte a tree and five
 * more a fallen one, so the whole state of a landscape goes with a keyframe whatever the
 * storm did (as DAMAGE events it would be 14 bytes a tree and cut at WIRE_MAX_DAMAGE).
 * PROTOCOL.md "FOREST" has the byte table. */
#include <stdio.h>
#include <string.h>

#include "wire.h"
#include "wire_cursor.h"
#include "wire_int.h"

#define FOREST_FIXED_BYTES 8u /* first, count */
#define FOREST_FALL_BYTES 5u  /* azimuth, tick */

size_t wire_forest_bytes(uint32_t count, uint32_t n_fall)
{
    return WIRE_HEADER_BYTES + FOREST_FIXED_BYTES + (size_t)count + (size_t)n_fall * FOREST_FALL_BYTES;
}

/* The fall of a state byte: 0, WIRE_DAMAGE_SNAP or WIRE_DAMAGE_UPROOT when valid. */
static unsigned state_fall(uint8_t s)
{
    return s >> WIRE_FOREST_FALL_SHIFT;
}

static bool state_valid(uint8_t s)
{
    const unsigned fall = state_fall(s);
    return (s & WIRE_FOREST_LEVEL_MASK) <= WIRE_DAMAGE_LEVELS &&
           (fall == 0 || fall == WIRE_DAMAGE_SNAP || fall == WIRE_DAMAGE_UPROOT);
}

int wire_encode_forest(const wire_header *h, uint32_t first, uint32_t count, const uint8_t *state,
                       const wire_forest_fall *fall, uint32_t n_fall, uint8_t *buf, size_t cap,
                       size_t *len, gale_err *err)
{
    if (count > WIRE_MAX_TREES || first > WIRE_MAX_TREES - count) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_encode_forest: trees: expected first + count <= %u, got %u + %u",
                         WIRE_MAX_TREES, first, count);
    }
    uint32_t fallen = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (!state_valid(state[i])) {
            return gale_errf(err, GALE_E_RANGE,
                             "wire_encode_forest: state[%u]: expected level <= %u, fall 0, 2 or 3, "
                             "got 0x%02x", i, WIRE_DAMAGE_LEVELS, (unsigned)state[i]);
        }
        fallen += state_fall(state[i]) != 0;
    }
    if (fallen != n_fall) {
        return gale_errf(err, GALE_E_ARG,
                         "wire_encode_forest: fall: expected %u (the fallen trees), got %u",
                         fallen, n_fall);
    }
    const size_t want = wire_forest_bytes(count, n_fall);
    if (want > cap) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_encode_forest: buffer: expected %zu bytes, got %zu", want, cap);
    }
    wire_writer w = wire_writer_make(buf, cap);
    wire_header hh = *h;
    hh.type = WIRE_MSG_FOREST;
    hh.flags = 0;
    wire_put_header(&w, &hh);
    wire_put_u32(&w, first);
    wire_put_u32(&w, count);
    if (count) {
        memcpy(w.p, state, count); /* one byte a tree: no byte order */
        w.p += count;
    }
    for (uint32_t i = 0; i < n_fall; i++) {
        wire_put_u8(&w, fall[i].az);
        wire_put_u32(&w, fall[i].tick);
    }
    *len = (size_t)(w.p - buf);
    return 0;
}

int wire_decode_forest(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                       gale_err *err)
{
    uint32_t first = wire_get_u32(r);
    uint32_t count = wire_get_u32(r);
    if (r->bad) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: FOREST tick %u: first, count at byte %u: truncated", h->tick,
                         WIRE_HEADER_BYTES);
    }
    if (count > WIRE_MAX_TREES || first > WIRE_MAX_TREES - count) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: FOREST tick %u: count at byte %u: expected first + count <= %u, "
                         "got %u + %u", h->tick, WIRE_HEADER_BYTES + 4, WIRE_MAX_TREES, first, count);
    }
    if (count > d->max_trees) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire: FOREST tick %u: count at byte %u: expected <= %u (the decoder's "
                         "trees), got %u", h->tick, WIRE_HEADER_BYTES + 4, d->max_trees, count);
    }
    if (wire_reader_left(r) < count) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: FOREST tick %u: length: expected >= %zu bytes for %u trees, got %zu",
                         h->tick, wire_forest_bytes(count, 0), count,
                         wire_forest_bytes(0, 0) + wire_reader_left(r));
    }
    const uint8_t *state = r->p;
    uint32_t fallen = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (!state_valid(state[i])) {
            return gale_errf(err, GALE_E_FORMAT,
                             "wire: FOREST tick %u: tree %u at byte %zu: expected level <= %u and "
                             "fall 0, 2 or 3, got 0x%02x", h->tick, first + i,
                             wire_forest_bytes(i, 0), WIRE_DAMAGE_LEVELS, (unsigned)state[i]);
        }
        fallen += state_fall(state[i]) != 0;
    }
    r->p += count;
    if (wire_reader_left(r) != (size_t)fallen * FOREST_FALL_BYTES) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: FOREST tick %u: length: expected %zu bytes for %u trees, %u fallen, "
                         "got %zu", h->tick, wire_forest_bytes(count, fallen), count, fallen,
                         wire_forest_bytes(count, 0) + wire_reader_left(r));
    }
    for (uint32_t i = 0; i < fallen; i++) {
        d->forest_fall[i].az = wire_get_u8(r);
        d->forest_fall[i].tick = wire_get_u32(r);
    }
    if (count) {
        memcpy(d->forest_state, state, count);
    }
    out->forest_first = first;
    out->forest_count = count;
    out->forest_state = d->forest_state;
    out->n_forest_fall = fallen;
    out->forest_fall = d->forest_fall;
    return 0;
}

uint32_t wire_forest_events(const wire_frame *f, wire_damage *out, uint32_t cap)
{
    uint32_t n = 0, k = 0;
    if (!(f->types & (1u << WIRE_MSG_FOREST))) {
        return 0;
    }
    for (uint32_t i = 0; i < f->forest_count; i++) {
        const uint8_t s = f->forest_state[i];
        const uint32_t t = f->forest_first + i;
        const unsigned fall = state_fall(s), level = s & WIRE_FOREST_LEVEL_MASK;
        if (fall && k < f->n_forest_fall) {
            if (n < cap) {
                out[n] = (wire_damage){ t, WIRE_DAMAGE_WHOLE, (uint8_t)fall, f->forest_fall[k].az,
                                        f->forest_fall[k].tick };
            }
            n++;
            k++;
        }
        if (level < WIRE_DAMAGE_LEVELS) {
            if (n < cap) {
                out[n] = (wire_damage){ t, WIRE_DAMAGE_WHOLE, WIRE_DAMAGE_STRIP, (uint8_t)level,
                                        f->hdr.tick };
            }
            n++;
        }
    }
    return n;
}
