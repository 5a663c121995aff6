/* What labels every binary frame and connection end: the 20-byte frame header (written
 * and checked here), message type names for errors, close code names. PROTOCOL.md
 * "Frame header" and "Errors and close codes". */
#include "wire.h"
#include "wire_int.h"

/* ---- header ---------------------------------------------------------------------- */

const char *wire_type_name(unsigned type)
{
    switch (type) {
    case WIRE_MSG_KEYFRAME:
        return "KEYFRAME";
    case WIRE_MSG_DELTA:
        return "DELTA";
    case WIRE_MSG_LEAVES:
        return "LEAVES";
    case WIRE_MSG_WIND:
        return "WIND";
    case WIRE_MSG_WEATHER:
        return "WEATHER";
    case WIRE_MSG_BUNDLE:
        return "BUNDLE";
    case WIRE_MSG_DAMAGE:
        return "DAMAGE";
    case WIRE_MSG_FOREST:
        return "FOREST";
    default:
        return "?";
    }
}

void wire_put_header(wire_writer *w, const wire_header *h)
{
    wire_put_u32(w, WIRE_MAGIC);
    wire_put_u16(w, WIRE_PROTOCOL_VERSION);
    wire_put_u8(w, h->type);
    wire_put_u8(w, h->flags);
    wire_put_u32(w, h->tick);
    wire_put_u64(w, h->server_time_us);
}

int wire_get_header(wire_reader *r, wire_header *h, gale_err *err)
{
    size_t have = wire_reader_left(r);
    h->magic = wire_get_u32(r);
    h->version = wire_get_u16(r);
    h->type = wire_get_u8(r);
    h->flags = wire_get_u8(r);
    h->tick = wire_get_u32(r);
    h->server_time_us = wire_get_u64(r);
    if (r->bad) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: header: truncated: expected %u bytes, got %zu",
                         WIRE_HEADER_BYTES, have);
    }
    if (h->magic != WIRE_MAGIC) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: header: bad magic: expected 0x%08x (\"GALE\"), got 0x%08x",
                         WIRE_MAGIC, h->magic);
    }
    if (h->version != WIRE_PROTOCOL_VERSION) {
        return gale_errf(err, GALE_E_VERSION,
                         "wire: header: protocol version: expected %d, got %u",
                         WIRE_PROTOCOL_VERSION, (unsigned)h->version);
    }
    if (h->type < WIRE_MSG_KEYFRAME || h->type > WIRE_MSG_FOREST) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: header: message type: expected 1..8, got %u",
                         (unsigned)h->type);
    }
    if (h->flags != 0) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: header: flags: expected 0, got 0x%02x", (unsigned)h->flags);
    }
    return 0;
}

const char *wire_close_name(int code)
{
    switch (code) {
    case WIRE_CLOSE_NORMAL:
        return "normal";
    case WIRE_CLOSE_GOING_AWAY:
        return "going-away";
    case WIRE_CLOSE_BAD_JSON:
        return "bad-json";
    case WIRE_CLOSE_UNKNOWN_TYPE:
        return "unknown-type";
    case WIRE_CLOSE_BAD_FIELD:
        return "bad-field";
    case WIRE_CLOSE_VERSION:
        return "version";
    case WIRE_CLOSE_TOO_BIG:
        return "too-big";
    case WIRE_CLOSE_BINARY:
        return "binary";
    case WIRE_CLOSE_FORBIDDEN:
        return "forbidden";
    case WIRE_CLOSE_BAD_TOKEN:
        return "bad-token";
    case WIRE_CLOSE_SLOW:
        return "slow";
    case WIRE_CLOSE_ORDER:
        return "order";
    case WIRE_CLOSE_FULL:
        return "full";
    case WIRE_CLOSE_BAD_FRAME:
        return "bad-frame";
    case WIRE_CLOSE_RATE:
        return "too-many";
    default:
        return "unknown";
    }
}
