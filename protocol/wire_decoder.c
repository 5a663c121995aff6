/* The client's decoder object (wire.h "decoder"): the last two snapshots, the scene of the
 * last keyframe, leaf and wind buffers, and wire_decode, which checks the header and hands
 * the body to its msg_*.c decoder. */
#include <stdlib.h>
#include <string.h>

#include "wire.h"
#include "wire_int.h"

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
    d->forest_state = malloc(dd.max_trees);
    d->forest_fall = malloc((size_t)dd.max_trees * sizeof *d->forest_fall);
    if (!d->wind || !d->forest_state || !d->forest_fall) {
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
    free(d->forest_state);
    free(d->forest_fall);
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
    if (out->hdr.type == WIRE_MSG_BUNDLE) {
        return wire_decode_bundle(d, &r, &out->hdr, out, err);
    }
    out->types = 1u << out->hdr.type;
    return wire_decode_body(d, &r, &out->hdr, out, err);
}

int wire_decode_body(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                     gale_err *err)
{
    int rc;
    switch (h->type) {
    case WIRE_MSG_KEYFRAME:
    case WIRE_MSG_DELTA:
        return wire_decode_state(d, r, h, out, err);
    case WIRE_MSG_LEAVES:
        rc = wire_decode_leaves(r, h, d->leaves, &out->n_leaves, err);
        out->leaves = rc ? NULL : d->leaves;
        return rc;
    case WIRE_MSG_DAMAGE:
        rc = wire_decode_damage(r, h, d->damage, &out->n_damage, &out->damage_full, err);
        out->damage = rc ? NULL : d->damage;
        return rc;
    case WIRE_MSG_WEATHER:
        return wire_decode_weather(r, h, &out->weather, err);
    case WIRE_MSG_FOREST:
        return wire_decode_forest(d, r, h, out, err);
    default: /* WIRE_MSG_WIND; wire_get_header checked the type, the callers BUNDLE */
        return wire_decode_wind(r, h, d->wind, &out->wind, err);
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
    const wire_scene *sc = &d->scene[d->scene_cur];
    if (!d->synced || t >= sc->n_trees) {
        for (uint32_t m = 0; m < max_modes; m++) {
            q[m] = 0.0f;
        }
        return 0;
    }
    const wire_slot *s = &d->slot[d->last];
    const uint32_t n = s->n_modes[t], lim = n < max_modes ? n : max_modes;
    const float *step = sc->step[sc->species[t]];
    const int16_t *qi = s->q + (size_t)t * d->max_modes;
    uint32_t m = 0;
    for (; m < lim; m++) {
        q[m] = wire_dequantize(qi[m], step[m]);
    }
    for (; m < max_modes; m++) {
        q[m] = 0.0f;
    }
    return n;
}
