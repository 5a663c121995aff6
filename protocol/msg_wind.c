/* WIND frames: a coarse horizontal slice of the wind field (Oliapuram & Kumar section 2)
 * for leaf drift and the HUD: nx x ny cells, three int8 components scaled by scale_ms.
 * PROTOCOL.md "WIND" has the byte table. */
#include <math.h>
#include <string.h>

#include "wire.h"
#include "wire_cursor.h"
#include "wire_int.h"

#define WIND_FIXED 24u /* bytes before the cells */

int8_t wire_wind_quantize(float v_ms, float scale_ms)
{
    float s = v_ms / scale_ms;
    s = s == s ? s : 0.0f;
    s = s > 127.0f ? 127.0f : s;
    s = s < -127.0f ? -127.0f : s;
    return (int8_t)(int32_t)(s + (s < 0.0f ? -0.5f : 0.5f));
}

static bool wind_ok(float x0, float y0, float z, float cell, float scale)
{
    return isfinite(x0) && isfinite(y0) && isfinite(z) && isfinite(cell) && cell > 0.0f &&
           isfinite(scale) && scale > 0.0f;
}

int wire_encode_wind(const wire_header *h, const wire_wind *wind, uint8_t *buf, size_t cap,
                     size_t *len, gale_err *err)
{
    if (wind->nx == 0 || wind->ny == 0 || wind->nx > WIRE_MAX_WIND_SIDE ||
        wind->ny > WIRE_MAX_WIND_SIDE) {
        return gale_errf(err, GALE_E_RANGE, "wire_encode_wind: size: expected 1..%u per side, got %ux%u",
                         WIRE_MAX_WIND_SIDE, (unsigned)wind->nx, (unsigned)wind->ny);
    }
    if (!wind_ok(wind->x0_m, wind->y0_m, wind->z_m, wind->cell_m, wind->scale_ms)) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_encode_wind: geometry: expected finite origin, cell_m > 0, scale_ms > 0, got cell_m %g, scale_ms %g",
                         (double)wind->cell_m, (double)wind->scale_ms);
    }
    wire_writer w = wire_writer_make(buf, cap);
    wire_header hh = *h;
    hh.type = WIRE_MSG_WIND;
    hh.flags = 0;
    wire_put_header(&w, &hh);
    wire_put_f32(&w, wind->x0_m);
    wire_put_f32(&w, wind->y0_m);
    wire_put_f32(&w, wind->z_m);
    wire_put_f32(&w, wind->cell_m);
    wire_put_f32(&w, wind->scale_ms);
    wire_put_u16(&w, wind->nx);
    wire_put_u16(&w, wind->ny);
    size_t cells = (size_t)wind->nx * wind->ny * 3;
    if (!w.bad && (size_t)(w.end - w.p) >= cells) {
        memcpy(w.p, wind->v, cells); /* int8 bytes: no byte order */
        w.p += cells;
    } else {
        w.bad = true;
    }
    if (w.bad) {
        return gale_errf(err, GALE_E_RANGE, "wire_encode_wind: buffer: expected %zu bytes, got %zu",
                         WIRE_HEADER_BYTES + WIND_FIXED + cells, cap);
    }
    *len = (size_t)(w.p - buf);
    return 0;
}

int wire_decode_wind(wire_reader *r, const wire_header *h, int8_t *v, wire_wind *out,
                     gale_err *err)
{
    memset(out, 0, sizeof *out);
    wire_wind wd = { 0 };
    wd.x0_m = wire_get_f32(r);
    wd.y0_m = wire_get_f32(r);
    wd.z_m = wire_get_f32(r);
    wd.cell_m = wire_get_f32(r);
    wd.scale_ms = wire_get_f32(r);
    wd.nx = wire_get_u16(r);
    wd.ny = wire_get_u16(r);
    if (r->bad) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WIND tick %u: slice header at byte %u: truncated: expected %u bytes",
                         h->tick, WIRE_HEADER_BYTES, WIND_FIXED);
    }
    if (!wind_ok(wd.x0_m, wd.y0_m, wd.z_m, wd.cell_m, wd.scale_ms)) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WIND tick %u: geometry at byte %u: expected finite origin, cell_m > 0, scale_ms > 0, got cell_m %g, scale_ms %g",
                         h->tick, WIRE_HEADER_BYTES, (double)wd.cell_m, (double)wd.scale_ms);
    }
    if (wd.nx == 0 || wd.ny == 0 || wd.nx > WIRE_MAX_WIND_SIDE || wd.ny > WIRE_MAX_WIND_SIDE) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WIND tick %u: size at byte %u: expected 1..%u per side, got %ux%u",
                         h->tick, WIRE_HEADER_BYTES + 20, WIRE_MAX_WIND_SIDE, (unsigned)wd.nx,
                         (unsigned)wd.ny);
    }
    size_t cells = (size_t)wd.nx * wd.ny * 3;
    if (wire_reader_left(r) != cells) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WIND tick %u: length: expected %zu bytes for %ux%u cells, got %zu",
                         h->tick, WIRE_HEADER_BYTES + WIND_FIXED + cells, (unsigned)wd.nx,
                         (unsigned)wd.ny, WIRE_HEADER_BYTES + WIND_FIXED + wire_reader_left(r));
    }
    memcpy(v, r->p, cells);
    r->p += cells;
    wd.v = v;
    *out = wd;
    return 0;
}
