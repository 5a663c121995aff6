/* The little-endian byte cursor: see wire_cursor.h. Every get checks what is left first;
 * a short read or an overflowing put sets the sticky bad flag and moves nothing. */
#include "wire_cursor.h"

#include <string.h>

/* ---- reader ---------------------------------------------------------------------- */

uint8_t wire_get_u8(wire_reader *r)
{
    if (r->bad || r->p >= r->end) {
        r->bad = true;
        return 0;
    }
    return *r->p++;
}

uint16_t wire_get_u16(wire_reader *r)
{
    if (r->bad || (size_t)(r->end - r->p) < 2) {
        r->bad = true;
        return 0;
    }
    uint16_t v = (uint16_t)(r->p[0] | (uint16_t)(r->p[1] << 8));
    r->p += 2;
    return v;
}

uint32_t wire_get_u32(wire_reader *r)
{
    if (r->bad || (size_t)(r->end - r->p) < 4) {
        r->bad = true;
        return 0;
    }
    uint32_t v = (uint32_t)r->p[0] | (uint32_t)r->p[1] << 8 | (uint32_t)r->p[2] << 16 |
                 (uint32_t)r->p[3] << 24;
    r->p += 4;
    return v;
}

uint64_t wire_get_u64(wire_reader *r)
{
    uint64_t lo = wire_get_u32(r);
    uint64_t hi = wire_get_u32(r);
    return lo | hi << 32;
}

float wire_get_f32(wire_reader *r)
{
    uint32_t u = wire_get_u32(r);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

uint32_t wire_get_varint(wire_reader *r)
{
    uint32_t v = 0;
    for (unsigned i = 0; i < 5; i++) {
        uint8_t b = wire_get_u8(r);
        if (r->bad) {
            return 0;
        }
        /* The fifth byte may carry only the top 4 bits of a 32-bit value. */
        if (i == 4 && b > 0x0f) {
            r->bad = true;
            return 0;
        }
        v |= (uint32_t)(b & 0x7fu) << (7 * i);
        if (!(b & 0x80u)) {
            /* Overlong forms (a trailing zero byte after the first) are rejected so
             * every value has one encoding. */
            if (i > 0 && b == 0) {
                r->bad = true;
                return 0;
            }
            return v;
        }
    }
    r->bad = true;
    return 0;
}

/* ---- writer ---------------------------------------------------------------------- */

void wire_put_u8(wire_writer *w, uint8_t v)
{
    if (w->bad || w->p >= w->end) {
        w->bad = true;
        return;
    }
    *w->p++ = v;
}

void wire_put_u16(wire_writer *w, uint16_t v)
{
    if (w->bad || (size_t)(w->end - w->p) < 2) {
        w->bad = true;
        return;
    }
    w->p[0] = (uint8_t)(v & 0xffu);
    w->p[1] = (uint8_t)(v >> 8);
    w->p += 2;
}

void wire_put_u32(wire_writer *w, uint32_t v)
{
    if (w->bad || (size_t)(w->end - w->p) < 4) {
        w->bad = true;
        return;
    }
    w->p[0] = (uint8_t)(v & 0xffu);
    w->p[1] = (uint8_t)(v >> 8 & 0xffu);
    w->p[2] = (uint8_t)(v >> 16 & 0xffu);
    w->p[3] = (uint8_t)(v >> 24);
    w->p += 4;
}

void wire_put_u64(wire_writer *w, uint64_t v)
{
    if (w->bad || (size_t)(w->end - w->p) < 8) {
        w->bad = true;
        return;
    }
    wire_put_u32(w, (uint32_t)(v & 0xffffffffu));
    wire_put_u32(w, (uint32_t)(v >> 32));
}

void wire_put_f32(wire_writer *w, float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    wire_put_u32(w, u);
}

void wire_put_varint(wire_writer *w, uint32_t v)
{
    while (v >= 0x80u) {
        wire_put_u8(w, (uint8_t)((v & 0x7fu) | 0x80u));
        v >>= 7;
    }
    wire_put_u8(w, (uint8_t)v);
}
