/* The binary wire's common parts (DESIGN.md "Wire", STYLE.md 4.6): little-endian
 * cursor, frame header, close code names, the quantisation steps of q derived from each
 * mode's displacement (Diener 2008 section 5.2 form), and the decoder object that
 * dispatches each frame to its msg_*.c body decoder. */
#include "wire.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "asset.h"
#include "wire_int.h"

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
    if (h->type < WIRE_MSG_KEYFRAME || h->type > WIRE_MSG_WIND) {
        return gale_errf(err, GALE_E_FORMAT,
                         "wire: header: message type: expected 1..4, got %u",
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
    default:
        return "unknown";
    }
}

/* ---- quantisation steps ---------------------------------------------------------- */

int wire_quant_steps(const struct asset *a, float eps, float *steps, gale_err *err)
{
    if (eps == 0.0f) {
        eps = WIRE_DEFAULT_EPS;
    }
    if (!(eps > 0.0f && eps < 1.0f)) {
        return gale_errf(err, GALE_E_ARG, "wire_quant_steps: eps: expected (0, 1), got %g",
                         (double)eps);
    }
    if (a->n_modes == 0 || a->n_modes > WIRE_MAX_MODES) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_quant_steps: %s: n_modes: expected 1..%u, got %u", a->species,
                         WIRE_MAX_MODES, a->n_modes);
    }
    if (!(a->height_m > 0.0f) || !isfinite(a->height_m)) {
        return gale_errf(err, GALE_E_RANGE,
                         "wire_quant_steps: %s: height_m: expected > 0, got %g", a->species,
                         (double)a->height_m);
    }
    const float h_m = a->height_m;
    for (uint32_t m = 0; m < a->n_modes; m++) {
        /* Largest node displacement per unit q_m. With the strong-wind form
         * u = q~ v + q~^2 w, q~ = a atan(b q), du/dq at q = 0 is a b v (Diener 2008
         * section 5.2); without the correction it is phi. */
        const float *v = a->corr_v ? a->corr_v : a->phi;
        float gain = 1.0f;
        if (a->corr_v && a->corr_a && a->corr_b) {
            gain = fabsf(a->corr_a[m] * a->corr_b[m]);
        }
        float smax = 0.0f;
        if (v) {
            const float *vm = v + (size_t)m * a->n_nodes * 3;
            for (uint32_t i = 0; i < a->n_nodes; i++) {
                float s2 = vm[3 * i] * vm[3 * i] + vm[3 * i + 1] * vm[3 * i + 1] +
                           vm[3 * i + 2] * vm[3 * i + 2];
                smax = s2 > smax ? s2 : smax;
            }
        }
        smax = sqrtf(smax) * gain;
        float step = eps * h_m;
        if (smax > 0.0f && isfinite(smax)) {
            step = eps * h_m / smax;
        }
        if (!(step > 0.0f) || !isfinite(step)) {
            return gale_errf(err, GALE_E_NUMERIC,
                             "wire_quant_steps: %s: mode %u: step: expected finite > 0, got %g",
                             a->species, m, (double)step);
        }
        steps[m] = step;
    }
    return 0;
}

/* ---- decoder object -------------------------------------------------------------- */

wire_decoder *wire_decoder_create(const wire_decoder_desc *desc, gale_err *err)
{
    wire_decoder_desc dd = desc ? *desc : (wire_decoder_desc){ 0 };
    if (dd.max_trees == 0) {
        dd.max_trees = WIRE_MAX_TREES;
    }
    if (dd.max_modes == 0) {
        dd.max_modes = WIRE_MAX_MODES;
    }
    if (dd.max_trees > WIRE_MAX_TREES || dd.max_modes > WIRE_MAX_MODES) {
        gale_errf(err, GALE_E_ARG,
                  "wire_decoder_create: capacity: expected <= %u trees, <= %u modes, got %u, %u",
                  WIRE_MAX_TREES, WIRE_MAX_MODES, dd.max_trees, dd.max_modes);
        return NULL;
    }
    wire_decoder *d = calloc(1, sizeof *d);
    if (!d) {
        goto fail;
    }
    d->max_trees = dd.max_trees;
    d->max_modes = dd.max_modes;
    for (int i = 0; i < 3; i++) {
        d->slot[i].n_modes = calloc(dd.max_trees, 1);
        d->slot[i].q = calloc((size_t)dd.max_trees * dd.max_modes, sizeof(int16_t));
        if (!d->slot[i].n_modes || !d->slot[i].q) {
            goto fail;
        }
    }
    for (int i = 0; i < 2; i++) {
        d->species[i] = calloc(dd.max_trees, 1);
        if (!d->species[i]) {
            goto fail;
        }
        d->scene[i].species = d->species[i];
    }
    d->wind = calloc((size_t)WIRE_MAX_WIND_SIDE * WIRE_MAX_WIND_SIDE * 3, 1);
    if (!d->wind) {
        goto fail;
    }
    d->last = 0;
    d->before = 1;
    d->scratch = 2;
    return d;
fail:
    wire_decoder_destroy(d);
    gale_errf(err, GALE_E_NOMEM, "wire_decoder_create: out of memory for %u trees x %u modes",
              dd.max_trees, dd.max_modes);
    return NULL;
}

void wire_decoder_destroy(wire_decoder *d)
{
    if (!d) {
        return;
    }
    for (int i = 0; i < 3; i++) {
        free(d->slot[i].n_modes);
        free(d->slot[i].q);
    }
    free(d->species[0]);
    free(d->species[1]);
    free(d->wind);
    free(d);
}

int wire_decode(wire_decoder *d, const uint8_t *buf, size_t len, wire_frame *out,
                gale_err *err)
{
    memset(out, 0, sizeof *out);
    if (len > WIRE_MAX_FRAME_BYTES) {
        return gale_errf(err, GALE_E_FORMAT, "wire: frame: length: expected <= %u, got %zu",
                         WIRE_MAX_FRAME_BYTES, len);
    }
    wire_reader r = wire_reader_make(buf, len);
    int rc = wire_get_header(&r, &out->hdr, err);
    if (rc) {
        return rc;
    }
    switch (out->hdr.type) {
    case WIRE_MSG_KEYFRAME:
    case WIRE_MSG_DELTA:
        return wire_decode_state(d, &r, &out->hdr, out, err);
    case WIRE_MSG_LEAVES:
        rc = wire_decode_leaves(&r, &out->hdr, d->leaves, &out->n_leaves, err);
        out->leaves = rc ? NULL : d->leaves;
        return rc;
    default: /* WIRE_MSG_WIND; wire_get_header checked the type */
        return wire_decode_wind(&r, &out->hdr, d->wind, &out->wind, err);
    }
}

bool wire_decoder_synced(const wire_decoder *d)
{
    return d->synced;
}

uint32_t wire_decoder_seq(const wire_decoder *d)
{
    return d->synced ? d->slot[d->last].seq : 0;
}

const wire_scene *wire_decoder_scene(const wire_decoder *d)
{
    return &d->scene[d->scene_cur];
}

wire_state wire_decoder_state(const wire_decoder *d)
{
    wire_state s = { 0 };
    if (d->synced) {
        s.n_trees = d->scene[d->scene_cur].n_trees;
        s.stride = d->max_modes;
        s.n_modes = d->slot[d->last].n_modes;
        s.q = d->slot[d->last].q;
    }
    return s;
}

uint32_t wire_decoder_q(const wire_decoder *d, uint32_t t, float *q, uint32_t max_modes)
{
    for (uint32_t m = 0; m < max_modes; m++) {
        q[m] = 0.0f;
    }
    const wire_scene *sc = &d->scene[d->scene_cur];
    if (!d->synced || t >= sc->n_trees) {
        return 0;
    }
    const wire_slot *s = &d->slot[d->last];
    uint32_t n = s->n_modes[t];
    const float *step = sc->step[sc->species[t]];
    const int16_t *qi = s->q + (size_t)t * d->max_modes;
    for (uint32_t m = 0; m < n && m < max_modes; m++) {
        q[m] = wire_dequantize(qi[m], step[m]);
    }
    return n;
}
