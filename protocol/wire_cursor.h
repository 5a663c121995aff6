/* The little-endian byte cursor every binary frame is read and written with, byte by
 * byte as PROTOCOL.md requires: a reader and a writer with a sticky bad flag, fixed-width
 * and LEB128 varint fields, zigzag signs. Knows no message; the msg_*.c codecs and the
 * decoder build on it. */
#ifndef GALE_WIRE_CURSOR_H
#define GALE_WIRE_CURSOR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Reader: a cursor with a sticky bad flag; any short read sets bad and returns 0. Check
 * bad once before acting on what was read. */
typedef struct wire_reader {
    const uint8_t *p, *end;
    bool bad;
} wire_reader;

/* Writer: same for output; an overflowing put sets bad and writes nothing. */
typedef struct wire_writer {
    uint8_t *p, *end;
    bool bad;
} wire_writer;

/* An empty buffer may come as NULL: no offset is added to it (NULL + 0 is undefined). */
static inline wire_reader wire_reader_make(const uint8_t *buf, size_t len)
{
    wire_reader r = { buf, buf ? buf + len : buf, false };
    return r;
}

static inline wire_writer wire_writer_make(uint8_t *buf, size_t cap)
{
    wire_writer w = { buf, buf ? buf + cap : buf, false };
    return w;
}

static inline size_t wire_reader_left(const wire_reader *r)
{
    return (size_t)(r->end - r->p);
}

uint8_t wire_get_u8(wire_reader *r);
uint16_t wire_get_u16(wire_reader *r);
uint32_t wire_get_u32(wire_reader *r);
uint64_t wire_get_u64(wire_reader *r);
float wire_get_f32(wire_reader *r);
/* LEB128 unsigned varint, at most 5 bytes for 32 bits; overlong or >32-bit sets bad. */
uint32_t wire_get_varint(wire_reader *r);

void wire_put_u8(wire_writer *w, uint8_t v);
void wire_put_u16(wire_writer *w, uint16_t v);
void wire_put_u32(wire_writer *w, uint32_t v);
void wire_put_u64(wire_writer *w, uint64_t v);
void wire_put_f32(wire_writer *w, float v);
void wire_put_varint(wire_writer *w, uint32_t v);

static inline uint32_t wire_zigzag(int32_t v)
{
    return ((uint32_t)v << 1) ^ (uint32_t)(v >> 31);
}

static inline int32_t wire_unzigzag(uint32_t v)
{
    return (int32_t)(v >> 1) ^ -(int32_t)(v & 1u);
}

/* Byte offset of the cursor from the frame start, for messages. */
static inline size_t wire_offset(const wire_reader *r, const uint8_t *start)
{
    return (size_t)(r->p - start);
}

#endif
