/* Fuzz target for binary frames: every input is decoded by a decoder that has first
 * seen a valid keyframe (so DELTA bodies get decoded too), then by a fresh one. A frame
 * that decodes must leave the decoder's state self-consistent (every q finite and within
 * what an int16 times the largest step can reach); nothing may crash. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static wire_decoder *dec;

/* A fixed keyframe of 3 trees, 2 species (seq 1) to sync the decoder first. */
static size_t base_keyframe(uint8_t *buf, size_t cap)
{
    static const uint8_t species[3] = { 0, 1, 0 };
    static const uint8_t nm[3] = { 4, 2, 4 };
    static const int16_t q[12] = { 100, -20, 3, 0, 5, 1, 0, 0, -7, 0, 0, 1 };
    wire_scene sc = { .n_trees = 3, .n_species = 2, .species = species };
    sc.n_modes[0] = 4;
    sc.n_modes[1] = 2;
    for (int m = 0; m < 4; m++) {
        sc.step[0][m] = 0.01f;
        sc.step[1][m] = 0.02f;
    }
    wire_state st = { 3, 4, nm, q };
    wire_header h = { .tick = 1 };
    size_t n = 0;
    if (wire_encode_keyframe(&h, 1, &sc, &st, buf, cap, &n, NULL) != 0) {
        abort();
    }
    return n;
}

/* The type in data's own header (the outer frame's, a BUNDLE's for a bundle); -1 when
 * it has none. */
static int outer_type(const uint8_t *data, size_t size)
{
    wire_reader r = wire_reader_make(data, size);
    wire_header h;
    return wire_get_header(&r, &h, NULL) == 0 ? (int)h.type : -1;
}

/* Decodes data with d and checks what it accepted. */
static void check_decode(wire_decoder *d, const uint8_t *data, size_t size)
{
    wire_frame f;
    gale_err e;
    int rc = wire_decode(d, data, size, &f, &e);
    if (rc == 0 && (f.hdr.type == WIRE_MSG_KEYFRAME || f.hdr.type == WIRE_MSG_DELTA)) {
        const wire_scene *sc = wire_decoder_scene(d);
        if (sc->n_trees > 64) {
            abort(); /* the decoder's max_trees */
        }
        float q[16];
        for (uint32_t t = 0; t < sc->n_trees; t++) {
            uint32_t n = wire_decoder_q(d, t, q, 16);
            if (n > 16) {
                abort();
            }
            for (uint32_t m = 0; m < n; m++) {
                /* |q| <= 32768 x step, and a step is a finite float */
                if (!isfinite(q[m])) {
                    abort();
                }
            }
        }
    } else if (rc == 0 && (f.types & (1u << WIRE_MSG_LEAVES)) && f.n_leaves > WIRE_MAX_LEAVES) {
        abort();
    } else if (rc == 0 && outer_type(data, size) == WIRE_MSG_WEATHER) {
        /* a decoded WEATHER frame re-encodes to the same bytes (every field was in range);
           a BUNDLE whose first frame is a WEATHER carries that header too (wire.h
           wire_frame.hdr), but its bytes are the bundle's */
        static uint8_t again[WIRE_WEATHER_MAX_BYTES];
        size_t n = 0;
        if (wire_encode_weather(&f.hdr, &f.weather, again, sizeof again, &n, NULL) != 0 ||
            n != size || memcmp(again, data, size) != 0) {
            abort();
        }
    } else if (rc != 0 && e.msg[0] == '\0') {
        abort(); /* every rejection says why */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static uint8_t kbuf[512];
    if (!dec) {
        dec = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 64, .max_modes = 16 }, NULL);
        if (!dec) {
            abort();
        }
    }
    size_t nk = base_keyframe(kbuf, sizeof kbuf);
    wire_frame f;
    if (wire_decode(dec, kbuf, nk, &f, NULL) != 0) {
        abort();
    }
    check_decode(dec, data, size);
    /* a fresh decoder: no keyframe seen, so a DELTA must be refused, a KEYFRAME taken */
    wire_decoder *fresh =
        wire_decoder_create(&(wire_decoder_desc){ .max_trees = 64, .max_modes = 16 }, NULL);
    if (!fresh) {
        abort();
    }
    check_decode(fresh, data, size);
    wire_decoder_destroy(fresh);
    return 0;
}
