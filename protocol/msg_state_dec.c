/* The state frames' decoder: a KEYFRAME's scene, the tree set and the values, each
 * field checked, committed to the decoder's slots only once the whole frame is valid. */
#include <stdio.h>
#include <string.h>

#include "msg_state_int.h"
#include "wire_int.h"

#define FAIL(...) return gale_errf(err, GALE_E_FORMAT, __VA_ARGS__)

/* Reads k values of width w bits, LSB first: the group's ceil(k w / 8) bytes are checked
 * to be there once, then read without a check per byte. */
static void get_bits(wire_reader *r, uint32_t *z, uint32_t k, unsigned width)
{
    const size_t n_bytes = ((size_t)k * width + 7u) / 8u;
    if (r->bad || wire_reader_left(r) < n_bytes) {
        r->bad = true;
        return;
    }
    const uint8_t *p = r->p;
    const uint32_t mask = width ? (uint32_t)((1u << width) - 1u) : 0u;
    uint64_t acc = 0;
    unsigned nacc = 0;
    for (uint32_t i = 0; i < k; i++) {
        while (nacc < width) {
            acc |= (uint64_t)*p++ << nacc;
            nacc += 8;
        }
        z[i] = (uint32_t)(acc & mask);
        acc >>= width;
        nacc -= width;
    }
    r->p = p;
    /* Padding bits of the last byte must be zero (one encoding per value). */
    if (acc != 0) {
        r->bad = true;
    }
}

/* Reads the tree set into n_modes[n_trees] (0 = absent). */
static int get_set(wire_reader *r, const uint8_t *start, const char *where,
                   const wire_scene *sc, const uint8_t *prev_modes, uint32_t max_modes,
                   bool keyframe, uint8_t *n_modes, gale_err *err)
{
    size_t at = wire_offset(r, start);
    uint8_t kind = wire_get_u8(r);
    if (r->bad) {
        FAIL("%s: tree set at byte %zu: truncated", where, at);
    }
    if (kind == SET_SAME && !keyframe) {
        memcpy(n_modes, prev_modes, sc->n_trees);
        return 0;
    }
    if (kind != SET_RUNS) {
        FAIL("%s: tree set kind at byte %zu: expected %s, got %u", where, at,
             keyframe ? "1 (runs)" : "0 (same) or 1 (runs)", (unsigned)kind);
    }
    memset(n_modes, 0, sc->n_trees);
    at = wire_offset(r, start);
    uint32_t n_runs = wire_get_varint(r);
    if (r->bad) {
        FAIL("%s: run count at byte %zu: truncated or bad varint", where, at);
    }
    if (n_runs > sc->n_trees) {
        FAIL("%s: run count at byte %zu: expected <= %u trees, got %u", where, at, sc->n_trees,
             n_runs);
    }
    uint32_t pos = 0;
    uint32_t n_present = 0;
    for (uint32_t i = 0; i < n_runs; i++) {
        at = wire_offset(r, start);
        uint32_t gap = wire_get_varint(r);
        uint32_t len = wire_get_varint(r);
        if (r->bad) {
            FAIL("%s: run %u at byte %zu: truncated or bad varint", where, i, at);
        }
        if (len == 0 || (i > 0 && gap == 0)) {
            FAIL("%s: run %u at byte %zu: expected gap >= %u and length >= 1, got %u, %u",
                 where, i, at, i > 0 ? 1u : 0u, gap, len);
        }
        if (gap > sc->n_trees - pos || len > sc->n_trees - pos - gap) {
            FAIL("%s: run %u at byte %zu: expected to end <= %u trees, got %u + %u + %u", where,
                 i, at, sc->n_trees, pos, gap, len);
        }
        pos += gap;
        for (uint32_t t = pos; t < pos + len; t++) {
            n_modes[t] = 1; /* marked; the count follows */
        }
        pos += len;
        n_present += len;
    }
    at = wire_offset(r, start);
    uint8_t mk = wire_get_u8(r);
    if (r->bad) {
        FAIL("%s: mode list kind at byte %zu: truncated", where, at);
    }
    if (mk != MODES_FULL && mk != MODES_LIST) {
        FAIL("%s: mode list kind at byte %zu: expected 0 (full) or 1 (list), got %u", where, at,
             (unsigned)mk);
    }
    if (mk == MODES_LIST && wire_reader_left(r) < n_present) {
        FAIL("%s: mode list at byte %zu: truncated: expected %u bytes, got %zu", where,
             wire_offset(r, start), n_present, wire_reader_left(r));
    }
    for (uint32_t t = 0; t < sc->n_trees; t++) {
        if (!n_modes[t]) {
            continue;
        }
        uint32_t full = sc->n_modes[sc->species[t]];
        uint32_t n = full;
        if (mk == MODES_LIST) {
            at = wire_offset(r, start);
            n = wire_get_u8(r);
            if (n == 0 || n > full) {
                FAIL("%s: modes of tree %u at byte %zu: expected 1..%u, got %u", where, t, at,
                     full, n);
            }
        }
        if (n > max_modes) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: modes of tree %u: expected <= %u (decoder capacity), got %u",
                             where, t, max_modes, n);
        }
        n_modes[t] = (uint8_t)n;
    }
    return 0;
}

/* A full group of width w (exactly w bytes, no padding) with 8 more bytes readable at p:
 * value i starts at bit i w and the 8 bytes from its first byte hold it (w + 7 <= 64), so
 * each is read, predicted and range-checked on its own, one loop per predictor. Writes v
 * and q as predict (below) does; true when a value is out of range. */
static inline bool group_full(const uint8_t *p, unsigned width, int pred, const int16_t *a,
                              const int16_t *b, int32_t *v, int16_t *q)
{
    const uint32_t mask = width ? (uint32_t)((1u << width) - 1u) : 0u;
    uint32_t out = 0;
#define GROUP_VALUE(i) ((uint32_t)(load_le64(p + ((i) * width >> 3)) >> ((i) * width & 7u)) & mask)
    if (pred == PRED_ZERO) {
#pragma GCC unroll 8
        for (uint32_t i = 0; i < GROUP; i++) {
            v[i] = wire_unzigzag(GROUP_VALUE(i));
        }
    } else if (pred == PRED_PREV) {
#pragma GCC unroll 8
        for (uint32_t i = 0; i < GROUP; i++) {
            v[i] = a[i] + wire_unzigzag(GROUP_VALUE(i));
        }
    } else {
#pragma GCC unroll 8
        for (uint32_t i = 0; i < GROUP; i++) {
            v[i] = 2 * a[i] - b[i] + wire_unzigzag(GROUP_VALUE(i));
        }
    }
#undef GROUP_VALUE
    for (uint32_t i = 0; i < GROUP; i++) {
        out |= (uint32_t)(v[i] + WIRE_QMAX) > 2u * WIRE_QMAX; /* v outside -QMAX..QMAX */
        q[i] = (int16_t)v[i];
    }
    return out != 0;
}

/* Values v = prediction + residual of k modes into v and q, one loop per predictor (a and b
 * the previous two snapshots' values); true when one is out of range (q then holds it
 * truncated, for the caller to reject the frame). */
static inline bool predict(const uint32_t *z, uint32_t k, int pred, const int16_t *a,
                           const int16_t *b, int32_t *v, int16_t *q)
{
    if (pred == PRED_ZERO) {
        for (uint32_t i = 0; i < k; i++) {
            v[i] = wire_unzigzag(z[i]);
        }
    } else if (pred == PRED_PREV) {
        for (uint32_t i = 0; i < k; i++) {
            v[i] = a[i] + wire_unzigzag(z[i]);
        }
    } else {
        for (uint32_t i = 0; i < k; i++) {
            v[i] = 2 * a[i] - b[i] + wire_unzigzag(z[i]);
        }
    }
    bool out = false;
    for (uint32_t i = 0; i < k; i++) {
        out |= v[i] < -WIRE_QMAX || v[i] > WIRE_QMAX;
        q[i] = (int16_t)v[i];
    }
    return out;
}

static int get_values(wire_reader *r, const uint8_t *start, const char *where, uint32_t n_trees,
                      uint32_t stride, const uint8_t *n_modes, const int16_t *prev,
                      const int16_t *prev2, int hist, int16_t *q, gale_err *err)
{
    uint32_t z[GROUP];
    for (uint32_t t = 0; t < n_trees; t++) {
        int16_t *qt = q + (size_t)t * stride;
        uint32_t n = n_modes[t];
        memset(qt + n, 0, (stride - n) * sizeof *qt);
        for (uint32_t g0 = 0; g0 < n; g0 += GROUP) {
            uint32_t k = n - g0 < GROUP ? n - g0 : GROUP;
            size_t at = wire_offset(r, start);
            uint8_t gh = wire_get_u8(r);
            unsigned width = gh & 0x1fu;
            int pred = gh >> 5;
            if (r->bad) {
                FAIL("%s: tree %u group %u at byte %zu: truncated", where, t, g0 / GROUP, at);
            }
            if (width > MAX_WIDTH || pred > hist) {
                FAIL("%s: tree %u group %u at byte %zu: expected width <= %u and predictor <= %d, got %u, %d",
                     where, t, g0 / GROUP, at, MAX_WIDTH, hist, width, pred);
            }
            const size_t ix = (size_t)t * stride + g0;
            int32_t v[GROUP];
            bool out;
            if (k == GROUP && wire_reader_left(r) >= (size_t)width + 8u) {
                out = group_full(r->p, width, pred, prev + ix, prev2 + ix, v, qt + g0);
                r->p += width;
            } else {
                get_bits(r, z, k, width);
                if (r->bad) {
                    FAIL("%s: tree %u group %u at byte %zu: truncated or nonzero padding", where,
                         t, g0 / GROUP, at);
                }
                out = predict(z, k, pred, prev + ix, prev2 + ix, v, qt + g0);
            }
            for (uint32_t i = 0; out && i < k; i++) {
                if (v[i] < -WIRE_QMAX || v[i] > WIRE_QMAX) {
                    FAIL("%s: tree %u mode %u at byte %zu: expected |q| <= %d, got %d", where,
                         t, g0 + i, at, WIRE_QMAX, v[i]);
                }
            }
        }
    }
    return 0;
}

int wire_decode_state(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                      gale_err *err)
{
    const uint8_t *start = r->p - WIRE_HEADER_BYTES;
    const bool key = h->type == WIRE_MSG_KEYFRAME;
    char where[64];
    snprintf(where, sizeof where, "wire: %s tick %u", wire_type_name(h->type), h->tick);
    uint32_t seq = wire_get_u32(r);
    if (r->bad) {
        FAIL("%s: seq at byte %u: truncated", where, WIRE_HEADER_BYTES);
    }
    wire_slot *dst = &d->slot[d->scratch];
    const wire_slot *last = &d->slot[d->last];
    const wire_slot *before = &d->slot[d->before];
    wire_scene *sc = &d->scene[d->scene_cur];
    int hist = 0;
    if (key) {
        sc = &d->scene[1 - d->scene_cur];
        size_t at = wire_offset(r, start);
        sc->n_trees = wire_get_u32(r);
        if (r->bad) {
            FAIL("%s: n_trees at byte %zu: truncated", where, at);
        }
        if (sc->n_trees == 0 || sc->n_trees > WIRE_MAX_TREES) {
            FAIL("%s: n_trees at byte %zu: expected 1..%u, got %u", where, at, WIRE_MAX_TREES,
                 sc->n_trees);
        }
        if (sc->n_trees > d->max_trees) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: n_trees: expected <= %u (decoder capacity), got %u", where,
                             d->max_trees, sc->n_trees);
        }
        at = wire_offset(r, start);
        sc->n_species = wire_get_u8(r);
        if (r->bad || sc->n_species == 0 || sc->n_species > WIRE_MAX_SPECIES) {
            FAIL("%s: n_species at byte %zu: expected 1..%u, got %s%u", where, at,
                 WIRE_MAX_SPECIES, r->bad ? "truncated " : "", sc->n_species);
        }
        for (uint32_t s = 0; s < sc->n_species; s++) {
            at = wire_offset(r, start);
            uint8_t nm = wire_get_u8(r);
            if (r->bad || nm == 0 || nm > WIRE_MAX_MODES) {
                FAIL("%s: species %u n_modes at byte %zu: expected 1..%u, got %s%u", where, s,
                     at, WIRE_MAX_MODES, r->bad ? "truncated " : "", (unsigned)nm);
            }
            sc->n_modes[s] = nm;
            for (uint32_t m = 0; m < nm; m++) {
                at = wire_offset(r, start);
                float st = wire_get_f32(r);
                if (r->bad) {
                    FAIL("%s: species %u step %u at byte %zu: truncated", where, s, m, at);
                }
                if (!(st > 0.0f && st <= WIRE_MAX_STEP)) {
                    FAIL("%s: species %u step %u at byte %zu: expected in (0, %g], got %g",
                         where, s, m, at, (double)WIRE_MAX_STEP, (double)st);
                }
                sc->step[s][m] = st;
            }
        }
        at = wire_offset(r, start);
        if (wire_reader_left(r) < sc->n_trees) {
            FAIL("%s: species of trees at byte %zu: truncated: expected %u bytes, got %zu",
                 where, at, sc->n_trees, wire_reader_left(r));
        }
        uint8_t *species = d->species[1 - d->scene_cur];
        for (uint32_t t = 0; t < sc->n_trees; t++) {
            species[t] = wire_get_u8(r);
            if (species[t] >= sc->n_species) {
                FAIL("%s: species of tree %u at byte %zu: expected < %u, got %u", where, t,
                     at + t, sc->n_species, (unsigned)species[t]);
            }
        }
    } else {
        if (!d->synced) {
            return gale_errf(err, GALE_E_STATE,
                             "%s: seq %u: no keyframe yet: waiting for a keyframe", where, seq);
        }
        if (seq != last->seq + 1u) {
            return gale_errf(err, GALE_E_STATE,
                             "%s: seq %u: gap: expected seq %u (holding %u): waiting for a keyframe",
                             where, seq, last->seq + 1u, last->seq);
        }
        size_t at = wire_offset(r, start);
        uint8_t hb = wire_get_u8(r);
        if (r->bad) {
            FAIL("%s: history at byte %zu: truncated", where, at);
        }
        if (hb < 1 || hb > 2) {
            FAIL("%s: history at byte %zu: expected 1 or 2, got %u", where, at, (unsigned)hb);
        }
        if (hb == 2 && !d->have_before) {
            return gale_errf(err, GALE_E_STATE,
                             "%s: seq %u: predicts from seq %u which this decoder does not hold: waiting for a keyframe",
                             where, seq, seq - 2u);
        }
        hist = hb;
    }
    int rc = get_set(r, start, where, sc, last->n_modes, d->max_modes, key, dst->n_modes, err);
    if (rc) {
        return rc;
    }
    rc = get_values(r, start, where, sc->n_trees, d->max_modes, dst->n_modes, last->q,
                    before->q, hist, dst->q, err);
    if (rc) {
        return rc;
    }
    if (wire_reader_left(r) != 0) {
        FAIL("%s: length: expected %zu bytes, got %zu (trailing bytes)", where,
             wire_offset(r, start), wire_offset(r, start) + wire_reader_left(r));
    }
    /* The whole frame is valid: commit. */
    dst->seq = seq;
    int old_before = d->before;
    if (key) {
        d->scene_cur = 1 - d->scene_cur;
        d->have_before = false;
        d->scratch = d->last;
        d->last = (int)(dst - d->slot);
    } else {
        d->before = d->last;
        d->last = d->scratch;
        d->scratch = old_before;
        d->have_before = true;
    }
    d->synced = true;
    out->seq = seq;
    return 0;
}
