/* WEATHER frames: what a kiosk shows, computed on the server (the 1-minute sustained wind
 * and 3-s gust at 10 m, where it comes from, its Saffir-Simpson class and Beaufort force,
 * and during a replay the storm's name, clock, pressure, eye distance and bearing, and the
 * replay's position and speed). A self-contained frame: one decodes without any other.
 * PROTOCOL.md "WEATHER" has the byte table. */
#include <math.h>
#include <string.h>

#include "wind_scale.h"
#include "wire.h"
#include "wire_cursor.h"
#include "wire_int.h"

#define WEATHER_FIXED 55u /* body bytes before the name */

/* The first field of w outside its range, or NULL when every field is in range. */
static const char *weather_bad_field(const wire_weather *w, size_t name_len)
{
#define IN(x, lo, hi) (isfinite(x) && (x) >= (lo) && (x) <= (hi))
    if (!IN(w->sustained_ms, 0.0f, 200.0f)) {
        return "sustained_ms";
    }
    if (!IN(w->gust_ms, 0.0f, 300.0f)) {
        return "gust_ms";
    }
    if (!IN(w->dir_from_deg, 0.0f, 360.0f) || w->dir_from_deg >= 360.0f) {
        return "dir_from_deg";
    }
    if (w->ss_class >= WIND_SCALE_SS_COUNT) {
        return "ss_class";
    }
    if (w->beaufort > 12) {
        return "beaufort";
    }
    /* FINISHED, PAUSED and CLOCK describe a replay: only with STORM. Fields a flag leaves
     * unset hold their "none" value exactly, so every frame has one reading. */
    const bool storm = (w->flags & WIRE_WEATHER_STORM) != 0;
    const bool clock = (w->flags & WIRE_WEATHER_CLOCK) != 0;
    const unsigned replay_only = WIRE_WEATHER_FINISHED | WIRE_WEATHER_PAUSED | WIRE_WEATHER_CLOCK;
    if ((w->flags & ~WIRE_WEATHER_FLAGS_ALL) || (!storm && (w->flags & replay_only))) {
        return "flags";
    }
    if (storm ? w->storm_class >= WIND_SCALE_SS_COUNT : w->storm_class != 255) {
        return "storm_class";
    }
    if (!IN(w->pressure_hpa, 800.0f, 1100.0f)) {
        return "pressure_hpa";
    }
    if (storm ? !IN(w->central_hpa, 800.0f, 1100.0f) : w->central_hpa != 0.0f) {
        return "central_hpa";
    }
    if (storm ? !IN(w->distance_km, 0.0f, 20000.0f) : w->distance_km != -1.0f) {
        return "distance_km";
    }
    if (storm ? !IN(w->bearing_deg, 0.0f, 360.0f) || w->bearing_deg >= 360.0f
              : w->bearing_deg != 0.0f) {
        return "bearing_deg";
    }
    if (!clock && w->utc_min != 0) {
        return "utc_min";
    }
    if (clock ? w->utc_offset_min < -840 || w->utc_offset_min > 840 : w->utc_offset_min != 0) {
        return "utc_offset_min";
    }
    if (storm ? !IN(w->storm_min, -1e6f, 1e6f) : w->storm_min != 0.0f) {
        return "storm_min";
    }
    if (storm ? !IN(w->replay_pos_s, 0.0f, 1e9f) : w->replay_pos_s != 0.0f) {
        return "replay_pos_s";
    }
    if (storm ? !IN(w->replay_len_s, 0.0f, 1e9f) : w->replay_len_s != 0.0f) {
        return "replay_len_s";
    }
    if (storm ? !IN(w->replay_speed, 0.0f, 1e5f) : w->replay_speed != 0.0f) {
        return "replay_speed";
    }
    if (name_len > WIRE_WEATHER_NAME_MAX) {
        return "name";
    }
    for (size_t i = 0; i < name_len; i++) {
        /* text for the HUD: no control bytes (UTF-8 continuation bytes are >= 0x80) */
        unsigned char ch = (unsigned char)w->name[i];
        if (ch < 0x20 || ch == 0x7f) {
            return "name";
        }
    }
#undef IN
    return NULL;
}

int wire_encode_weather(const wire_header *h, const wire_weather *w, uint8_t *buf, size_t cap,
                        size_t *len, gale_err *err)
{
    size_t name_len = strnlen(w->name, sizeof w->name);
    const char *bad = weather_bad_field(w, name_len);
    if (bad) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_encode_weather: %s: out of range (PROTOCOL.md \"WEATHER\")", bad);
    }
    wire_writer wr = wire_writer_make(buf, cap);
    wire_header hh = *h;
    hh.type = WIRE_MSG_WEATHER;
    hh.flags = 0;
    wire_put_header(&wr, &hh);
    wire_put_f32(&wr, w->sustained_ms);
    wire_put_f32(&wr, w->gust_ms);
    wire_put_f32(&wr, w->dir_from_deg);
    wire_put_u8(&wr, w->ss_class);
    wire_put_u8(&wr, w->beaufort);
    wire_put_u8(&wr, w->flags);
    wire_put_u8(&wr, w->storm_class);
    wire_put_f32(&wr, w->pressure_hpa);
    wire_put_f32(&wr, w->central_hpa);
    wire_put_f32(&wr, w->distance_km);
    wire_put_f32(&wr, w->bearing_deg);
    wire_put_u32(&wr, w->utc_min);
    wire_put_u16(&wr, (uint16_t)w->utc_offset_min);
    wire_put_f32(&wr, w->storm_min);
    wire_put_f32(&wr, w->replay_pos_s);
    wire_put_f32(&wr, w->replay_len_s);
    wire_put_f32(&wr, w->replay_speed);
    wire_put_u8(&wr, (uint8_t)name_len);
    for (size_t i = 0; i < name_len; i++) {
        wire_put_u8(&wr, (uint8_t)w->name[i]);
    }
    if (wr.bad) {
        return gale_errf(err, GALE_E_RANGE, "wire_encode_weather: buffer: expected %zu bytes, got %zu",
                         WIRE_HEADER_BYTES + WEATHER_FIXED + name_len, cap);
    }
    *len = (size_t)(wr.p - buf);
    return 0;
}

int wire_decode_weather(wire_reader *r, const wire_header *h, wire_weather *out, gale_err *err)
{
    memset(out, 0, sizeof *out);
    wire_weather w;
    memset(&w, 0, sizeof w);
    w.sustained_ms = wire_get_f32(r);
    w.gust_ms = wire_get_f32(r);
    w.dir_from_deg = wire_get_f32(r);
    w.ss_class = wire_get_u8(r);
    w.beaufort = wire_get_u8(r);
    w.flags = wire_get_u8(r);
    w.storm_class = wire_get_u8(r);
    w.pressure_hpa = wire_get_f32(r);
    w.central_hpa = wire_get_f32(r);
    w.distance_km = wire_get_f32(r);
    w.bearing_deg = wire_get_f32(r);
    w.utc_min = wire_get_u32(r);
    w.utc_offset_min = (int16_t)wire_get_u16(r);
    w.storm_min = wire_get_f32(r);
    w.replay_pos_s = wire_get_f32(r);
    w.replay_len_s = wire_get_f32(r);
    w.replay_speed = wire_get_f32(r);
    size_t name_len = wire_get_u8(r);
    if (r->bad) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WEATHER tick %u: body at byte %u: truncated: expected %u bytes",
                         h->tick, WIRE_HEADER_BYTES, WEATHER_FIXED);
    }
    if (wire_reader_left(r) != name_len) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WEATHER tick %u: length: expected %zu bytes for a %zu-byte name, got %zu",
                         h->tick, WIRE_HEADER_BYTES + WEATHER_FIXED + name_len, name_len,
                         WIRE_HEADER_BYTES + WEATHER_FIXED + wire_reader_left(r));
    }
    if (name_len > WIRE_WEATHER_NAME_MAX) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WEATHER tick %u: name length at byte %u: expected <= %u, got %zu",
                         h->tick, WIRE_HEADER_BYTES + WEATHER_FIXED - 1, WIRE_WEATHER_NAME_MAX,
                         name_len);
    }
    memcpy(w.name, r->p, name_len);
    r->p += name_len;
    const char *bad = weather_bad_field(&w, name_len);
    if (!bad && !wire_utf8_valid((const uint8_t *)w.name, name_len)) {
        bad = "name (not UTF-8)";
    }
    if (bad) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: WEATHER tick %u: %s: out of range (PROTOCOL.md \"WEATHER\")",
                         h->tick, bad);
    }
    *out = w;
    return 0;
}

/* RFC 3629: no overlong form, no surrogate (U+D800..DFFF), nothing above U+10FFFF. */
bool wire_utf8_valid(const uint8_t *s, size_t n)
{
    for (size_t i = 0; i < n;) {
        const uint8_t c = s[i];
        size_t k;
        uint32_t cp, min;
        if (c < 0x80u) {
            i++;
            continue;
        } else if ((c & 0xe0u) == 0xc0u) {
            k = 1;
            cp = c & 0x1fu;
            min = 0x80u;
        } else if ((c & 0xf0u) == 0xe0u) {
            k = 2;
            cp = c & 0x0fu;
            min = 0x800u;
        } else if ((c & 0xf8u) == 0xf0u) {
            k = 3;
            cp = c & 0x07u;
            min = 0x10000u;
        } else {
            return false;
        }
        if (n - i <= k) {
            return false;
        }
        for (size_t j = 1; j <= k; j++) {
            if ((s[i + j] & 0xc0u) != 0x80u) {
                return false;
            }
            cp = cp << 6 | (s[i + j] & 0x3fu);
        }
        if (cp < min || cp > 0x10ffffu || (cp >= 0xd800u && cp <= 0xdfffu)) {
            return false;
        }
        i += k + 1;
    }
    return true;
}
