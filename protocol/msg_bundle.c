/* BUNDLE frames: one WebSocket message carrying several self-contained frames of the same
 * snapshot (the state frame and the leaves, wind ... that go with it), so a client costs
 * one write per snapshot (PROTOCOL.md "BUNDLE"). The container knows no inner type: each
 * inner frame is a whole frame with its own header, decoded by wire_decode's per-type
 * dispatch (wire_decode_body). */
#include <stdio.h>
#include <string.h>

#include "wire.h"
#include "wire_cursor.h"
#include "wire_int.h"

/* Bytes before the first inner frame: header, count, the first length. */
#define BUNDLE_PREFIX_BYTES (WIRE_HEADER_BYTES + 1u + 4u)

static void put_u32_at(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) {
        p[i] = (uint8_t)(v >> (8 * i));
    }
}

int wire_bundle_wrap(uint8_t *buf, size_t cap, size_t *len, const uint8_t *const *more,
                     const size_t *more_len, uint32_t n_more, gale_err *err)
{
    const size_t first = *len;
    size_t total = BUNDLE_PREFIX_BYTES + first;
    for (uint32_t i = 0; i < n_more; i++) {
        total += 4u + more_len[i];
    }
    if (first < WIRE_HEADER_BYTES || 1u + n_more > WIRE_MAX_BUNDLE) {
        return gale_errf(err, GALE_E_ARG,
                         "wire_bundle_wrap: expected a frame and <= %u others, got %zu bytes and %u",
                         WIRE_MAX_BUNDLE - 1u, first, n_more);
    }
    if (total > cap || total > WIRE_MAX_FRAME_BYTES) {
        return gale_errf(err, GALE_E_RANGE, "wire_bundle_wrap: buffer: expected %zu bytes, got %zu",
                         total, cap < WIRE_MAX_FRAME_BYTES ? cap : (size_t)WIRE_MAX_FRAME_BYTES);
    }
    memmove(buf + BUNDLE_PREFIX_BYTES, buf, first);
    /* the bundle is labelled with the first frame's tick and server time (bytes 8..19) */
    memcpy(buf, buf + BUNDLE_PREFIX_BYTES, WIRE_HEADER_BYTES);
    buf[6] = WIRE_MSG_BUNDLE;
    buf[7] = 0;
    buf[WIRE_HEADER_BYTES] = (uint8_t)(1u + n_more);
    put_u32_at(buf + WIRE_HEADER_BYTES + 1u, (uint32_t)first);
    size_t at = BUNDLE_PREFIX_BYTES + first;
    for (uint32_t i = 0; i < n_more; i++) {
        put_u32_at(buf + at, (uint32_t)more_len[i]);
        memcpy(buf + at + 4u, more[i], more_len[i]);
        at += 4u + more_len[i];
    }
    *len = at;
    return 0;
}

static bool is_state(unsigned type)
{
    return type == WIRE_MSG_KEYFRAME || type == WIRE_MSG_DELTA;
}

int wire_decode_bundle(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                       gale_err *err)
{
    const uint8_t *at[WIRE_MAX_BUNDLE];
    uint32_t at_len[WIRE_MAX_BUNDLE];
    wire_header ih[WIRE_MAX_BUNDLE];
    uint32_t n = wire_get_u8(r);
    if (r->bad || n == 0 || n > WIRE_MAX_BUNDLE) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: BUNDLE tick %u: count at byte %u: expected 1..%u, got %s%u",
                         h->tick, WIRE_HEADER_BYTES, WIRE_MAX_BUNDLE, r->bad ? "none " : "",
                         r->bad ? 0u : n);
    }
    /* The container is checked whole before any inner frame is decoded. */
    uint32_t types = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t len = wire_get_u32(r);
        if (r->bad || len < WIRE_HEADER_BYTES || len > wire_reader_left(r)) {
            return gale_errf(err, GALE_E_FORMAT,
                             "wire: BUNDLE tick %u: frame %u of %u: length: expected %u..%zu, got %s%u",
                             h->tick, i + 1u, n, WIRE_HEADER_BYTES, wire_reader_left(r),
                             r->bad ? "none " : "", r->bad ? 0u : len);
        }
        at[i] = r->p;
        at_len[i] = len;
        r->p += len;
        wire_reader ir = wire_reader_make(at[i], len);
        gale_err e;
        if (wire_get_header(&ir, &ih[i], &e)) {
            return gale_errf(err, e.code, "wire: BUNDLE tick %u: frame %u of %u: %s", h->tick,
                             i + 1u, n, e.msg);
        }
        const unsigned t = ih[i].type;
        const bool dup = ((types >> t) & 1u) || (is_state(t) && (types & ((1u << WIRE_MSG_KEYFRAME) |
                                                                        (1u << WIRE_MSG_DELTA))));
        if (t == WIRE_MSG_BUNDLE || dup) {
            return gale_errf(err, GALE_E_FORMAT,
                             "wire: BUNDLE tick %u: frame %u of %u: type: expected one frame "
                             "of each type, at most one state frame and no BUNDLE, got %s%s",
                             h->tick, i + 1u, n, dup ? "a second " : "", wire_type_name(t));
        }
        types |= 1u << t;
    }
    if (wire_reader_left(r) != 0) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: BUNDLE tick %u: length: %zu trailing bytes after %u frames",
                         h->tick, wire_reader_left(r), n);
    }
    /* The state frame last: a bundle that fails anywhere leaves the snapshots untouched. */
    int state = -1;
    for (uint32_t pass = 0; pass < 2; pass++) {
        for (uint32_t i = 0; i < n; i++) {
            if (is_state(ih[i].type) != (pass == 1)) {
                continue;
            }
            wire_reader ir = wire_reader_make(at[i] + WIRE_HEADER_BYTES,
                                              at_len[i] - WIRE_HEADER_BYTES);
            gale_err e;
            int rc = wire_decode_body(d, &ir, &ih[i], out, &e);
            if (rc) {
                return gale_errf(err, rc, "wire: BUNDLE tick %u: frame %u of %u: %s", h->tick,
                                 i + 1u, n, e.msg);
            }
            state = pass == 1 ? (int)i : state;
        }
    }
    out->hdr = state >= 0 ? ih[state] : ih[0];
    out->types = types;
    return 0;
}
