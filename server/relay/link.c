/* The byte layouts of link.h's messages. */
#include "link.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wire_cursor.h"
#include "wire_limits.h"

size_t link_snap_size(const net_snap *p)
{
    size_t n = 8 + 4 + 4 + 4 * 3 + 1 + 4 * NET_SNAP_MAX_EXTRA + p->key_len + p->delta1_len +
               p->delta2_len;
    for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
        n += p->extra_len[e];
    }
    return n;
}

void link_snap_encode(const net_snap *p, uint64_t epoch, uint8_t *buf)
{
    wire_writer w = wire_writer_make(buf, link_snap_size(p));
    wire_put_u64(&w, epoch);
    wire_put_u32(&w, p->seq);
    wire_put_u32(&w, p->stream);
    wire_put_u32(&w, (uint32_t)p->key_len);
    wire_put_u32(&w, (uint32_t)p->delta1_len);
    wire_put_u32(&w, (uint32_t)p->delta2_len);
    wire_put_u8(&w, NET_SNAP_MAX_EXTRA);
    for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
        wire_put_u32(&w, (uint32_t)p->extra_len[e]);
    }
    uint8_t *at = w.p;
    memcpy(at, p->key, p->key_len);
    at += p->key_len;
    memcpy(at, p->delta1, p->delta1_len);
    at += p->delta1_len;
    memcpy(at, p->delta2, p->delta2_len);
    at += p->delta2_len;
    for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
        memcpy(at, p->extra[e], p->extra_len[e]);
        at += p->extra_len[e];
    }
}

int link_snap_decode(const uint8_t *buf, size_t len, net_snap *p, uint64_t *epoch,
                     gale_err *err)
{
    wire_reader r = wire_reader_make(buf, len);
    *epoch = wire_get_u64(&r);
    p->seq = wire_get_u32(&r);
    p->stream = wire_get_u32(&r);
    size_t lens[3 + NET_SNAP_MAX_EXTRA] = { 0 };
    for (int i = 0; i < 3; i++) {
        lens[i] = wire_get_u32(&r);
    }
    uint32_t n_extra = wire_get_u8(&r);
    if (r.bad || n_extra != NET_SNAP_MAX_EXTRA) {
        return gale_errf(err, GALE_E_FORMAT, "link: snapshot: header: expected %d extras, got %s%u",
                         NET_SNAP_MAX_EXTRA, r.bad ? "a truncated header " : "", n_extra);
    }
    for (uint32_t e = 0; e < n_extra; e++) {
        lens[3 + e] = wire_get_u32(&r);
    }
    size_t want = 0;
    for (int i = 0; i < 3 + NET_SNAP_MAX_EXTRA; i++) {
        size_t cap = i < 3 ? net_snap_buffer_cap(p->cap, p->extra_cap) : p->extra_cap;
        if (lens[i] > cap) {
            return gale_errf(err, GALE_E_RANGE,
                             "link: snapshot %u: part %d: expected <= %zu bytes, got %zu", p->seq,
                             i, cap, lens[i]);
        }
        want += lens[i];
    }
    if (r.bad || wire_reader_left(&r) != want || !lens[0]) {
        return gale_errf(err, GALE_E_FORMAT,
                         "link: snapshot %u: length: expected %zu bytes of frames, got %zu", p->seq,
                         want, r.bad ? 0 : wire_reader_left(&r));
    }
    uint8_t *dst[3 + NET_SNAP_MAX_EXTRA] = { p->key, p->delta1, p->delta2 };
    size_t *dlen[3 + NET_SNAP_MAX_EXTRA] = { &p->key_len, &p->delta1_len, &p->delta2_len };
    for (int e = 0; e < NET_SNAP_MAX_EXTRA; e++) {
        dst[3 + e] = p->extra[e];
        dlen[3 + e] = &p->extra_len[e];
    }
    const uint8_t *at = r.p;
    for (int i = 0; i < 3 + NET_SNAP_MAX_EXTRA; i++) {
        memcpy(dst[i], at, lens[i]);
        *dlen[i] = lens[i];
        at += lens[i];
    }
    return 0;
}

static void put_str(wire_writer *w, const char *s, size_t n)
{
    wire_put_u32(w, (uint32_t)n);
    for (size_t i = 0; i < n && !w->bad; i++) {
        wire_put_u8(w, (uint8_t)s[i]);
    }
}

static const char *get_str(wire_reader *r, size_t *n)
{
    *n = wire_get_u32(r);
    if (r->bad || *n > wire_reader_left(r)) {
        r->bad = true;
        *n = 0;
        return NULL;
    }
    const char *s = (const char *)r->p;
    r->p += *n;
    return s;
}

int link_ctl_encode(const link_ctl *c, uint8_t **out, size_t *len, gale_err *err)
{
    const char *addr = c->peer.addr ? c->peer.addr : "";
    const char *why = c->why ? c->why : "";
    size_t n = 4 * 5 + 1 + 4 * 3 + strlen(addr) + strlen(why) + c->text_len;
    *out = malloc(n);
    if (!*out) {
        return gale_errf(err, GALE_E_NOMEM, "link: control: no memory for %zu bytes", n);
    }
    wire_writer w = wire_writer_make(*out, n);
    wire_put_u32(&w, c->peer.id);
    wire_put_u32(&w, (uint32_t)c->peer.role);
    wire_put_u8(&w, c->peer.resync);
    wire_put_u32(&w, c->peer.stream);
    wire_put_u32(&w, (uint32_t)c->rc);
    put_str(&w, addr, strlen(addr));
    put_str(&w, why, strlen(why));
    put_str(&w, c->text ? c->text : "", c->text ? c->text_len : 0);
    *len = (size_t)(w.p - *out);
    return 0;
}

int link_ctl_decode(const uint8_t *buf, size_t len, link_ctl *c, char *addr_buf, size_t addr_cap,
                    char *why_buf, size_t why_cap, gale_err *err)
{
    wire_reader r = wire_reader_make(buf, len);
    memset(c, 0, sizeof *c);
    c->peer.id = wire_get_u32(&r);
    c->peer.role = (int)wire_get_u32(&r);
    c->peer.resync = wire_get_u8(&r) != 0;
    c->peer.stream = wire_get_u32(&r);
    c->rc = (int)wire_get_u32(&r);
    size_t na, nw, nt;
    const char *a = get_str(&r, &na);
    const char *w = get_str(&r, &nw);
    c->text = get_str(&r, &nt);
    c->text_len = nt;
    if (r.bad || wire_reader_left(&r) || c->peer.role < 0 || c->peer.role >= NET_ROLE_COUNT) {
        return gale_errf(err, GALE_E_FORMAT, "link: control: malformed message of %zu bytes", len);
    }
    snprintf(addr_buf, addr_cap, "%.*s", (int)na, a ? a : "");
    snprintf(why_buf, why_cap, "%.*s", (int)nw, w ? w : "");
    c->peer.addr = addr_buf;
    c->why = why_buf;
    return 0;
}

int link_info_encode(const link_info *in, uint8_t *buf, size_t cap, size_t *len)
{
    wire_writer w = wire_writer_make(buf, cap);
    wire_put_u64(&w, in->snap_cap);
    wire_put_u64(&w, in->extra_cap);
    wire_put_u32(&w, in->max_streams);
    wire_put_u32(&w, in->n_assets);
    for (uint32_t i = 0; i < in->n_assets; i++) {
        for (size_t k = 0; k < sizeof in->assets[i].hash; k++) {
            wire_put_u8(&w, (uint8_t)in->assets[i].hash[k]);
        }
        wire_put_u64(&w, in->assets[i].len);
    }
    *len = (size_t)(w.p - buf);
    return w.bad ? GALE_E_RANGE : 0;
}

int link_info_decode(const uint8_t *buf, size_t len, link_info *out, gale_err *err)
{
    wire_reader r = wire_reader_make(buf, len);
    memset(out, 0, sizeof *out);
    out->snap_cap = wire_get_u64(&r);
    out->extra_cap = wire_get_u64(&r);
    out->max_streams = wire_get_u32(&r);
    out->n_assets = wire_get_u32(&r);
    if (r.bad || out->n_assets > 64 || out->snap_cap > WIRE_MAX_FRAME_BYTES ||
        out->extra_cap > WIRE_MAX_FRAME_BYTES || out->max_streams > 64) {
        return gale_errf(err, GALE_E_FORMAT, "link: info: malformed message of %zu bytes", len);
    }
    for (uint32_t i = 0; i < out->n_assets; i++) {
        for (size_t k = 0; k < sizeof out->assets[i].hash; k++) {
            out->assets[i].hash[k] = (char)wire_get_u8(&r);
        }
        out->assets[i].hash[sizeof out->assets[i].hash - 1] = '\0';
        out->assets[i].len = (size_t)wire_get_u64(&r);
    }
    if (r.bad || wire_reader_left(&r)) {
        return gale_errf(err, GALE_E_FORMAT, "link: info: malformed message of %zu bytes", len);
    }
    return 0;
}

size_t link_scene_size(uint32_t n_trees)
{
    return 8 + 4 * 4 + 4 * 2 + (size_t)n_trees * 12;
}

void link_scene_encode(const link_scene *sc, uint8_t *buf)
{
    const size_t n = link_scene_size(sc->n_trees);
    wire_writer w = wire_writer_make(buf, n);
    wire_put_u64(&w, n);
    wire_put_u32(&w, sc->n_trees);
    wire_put_u32(&w, sc->lod_modes);
    wire_put_u32(&w, sc->key_every);
    wire_put_u32(&w, sc->max_modes);
    wire_put_f32(&w, sc->margin_m);
    wire_put_f32(&w, sc->cell_m);
    for (size_t i = 0; i < 3 * (size_t)sc->n_trees; i++) {
        wire_put_f32(&w, sc->pos[i]);
    }
}

uint64_t link_scene_total(const uint8_t *buf, size_t len)
{
    wire_reader r = wire_reader_make(buf, len);
    uint64_t n = wire_get_u64(&r);
    return r.bad ? 0 : n;
}

int link_scene_decode(const uint8_t *buf, size_t len, link_scene *sc, gale_err *err)
{
    wire_reader r = wire_reader_make(buf, len);
    memset(sc, 0, sizeof *sc);
    uint64_t total = wire_get_u64(&r);
    sc->n_trees = wire_get_u32(&r);
    sc->lod_modes = wire_get_u32(&r);
    sc->key_every = wire_get_u32(&r);
    sc->max_modes = wire_get_u32(&r);
    sc->margin_m = wire_get_f32(&r);
    sc->cell_m = wire_get_f32(&r);
    if (r.bad || total != len || sc->n_trees > WIRE_MAX_TREES ||
        len != link_scene_size(sc->n_trees) || sc->lod_modes < 1 ||
        sc->lod_modes > WIRE_MAX_MODES ||
        sc->max_modes < 1 || sc->max_modes > WIRE_MAX_MODES || !(sc->margin_m >= 0.0f) ||
        !(sc->cell_m > 0.0f)) {
        return gale_errf(err, GALE_E_FORMAT,
                         "link: scene: malformed message of %zu bytes (%u trees)", len,
                         sc->n_trees);
    }
    sc->pos = malloc(sc->n_trees ? (size_t)sc->n_trees * 12 : 1);
    if (!sc->pos) {
        return gale_errf(err, GALE_E_NOMEM, "link: scene: no memory for %u trees", sc->n_trees);
    }
    for (size_t i = 0; i < 3 * (size_t)sc->n_trees; i++) {
        sc->pos[i] = wire_get_f32(&r);
    }
    return 0;
}
