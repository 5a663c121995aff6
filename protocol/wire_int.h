/* Private to the wire module: the decoder's storage and the per-message body decoders
 * that wire_decode dispatches to. Included by wire_decoder.c and msg_*.c only; it
 * includes wire.h, which includes wire_cursor.h (one way: nothing below includes it). */
#ifndef GALE_WIRE_INT_H
#define GALE_WIRE_INT_H

#include "wire.h"

/* One decoded snapshot slot: n_modes per tree and q tree-major with stride max_modes. */
typedef struct wire_slot {
    uint8_t *n_modes; /* owned: [max_trees] */
    int16_t *q;       /* owned: [max_trees * max_modes] */
    uint32_t seq;
} wire_slot;

struct wire_decoder {
    uint32_t max_trees, max_modes;
    /* Three rotating slots: last (seq), before (seq - 1, when have_before), and a scratch
     * that a frame is decoded into and that becomes last only when the frame is valid. */
    wire_slot slot[3];
    int last, before, scratch; /* indices into slot */
    bool synced;               /* a keyframe was decoded; last is valid */
    bool have_before;          /* before holds seq(last) - 1 */
    /* Scenes of the last keyframe and a scratch one (swapped on a valid keyframe). */
    wire_scene scene[2];
    uint8_t *species[2]; /* owned: [max_trees] each, the scenes' species arrays */
    int scene_cur;
    wire_leaf leaves[WIRE_MAX_LEAVES];
    int8_t *wind;        /* owned: [WIRE_MAX_WIND_SIDE^2 * 3] */
    wire_damage damage[WIRE_MAX_DAMAGE];
    uint8_t *forest_state;          /* owned: [max_trees] */
    wire_forest_fall *forest_fall;  /* owned: [max_trees] */
};

/* Body decoders (after the header). Return 0 or GALE_E_*; leave the decoder's visible
 * state untouched on failure. */
int wire_decode_state(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                      gale_err *err);
int wire_decode_leaves(wire_reader *r, const wire_header *h, wire_leaf *leaves,
                       uint32_t *n, gale_err *err);
int wire_decode_damage(wire_reader *r, const wire_header *h, wire_damage *ev, uint32_t *n,
                       bool *full, gale_err *err);
int wire_decode_forest(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                       gale_err *err);
int wire_decode_wind(wire_reader *r, const wire_header *h, int8_t *v, wire_wind *out,
                     gale_err *err);

/* The body (after the header h) of one frame of any type but BUNDLE, into out's fields
 * for that type; out is not cleared, so a BUNDLE's frames accumulate in one wire_frame. */
int wire_decode_body(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                     gale_err *err);
/* A BUNDLE's body (msg_bundle.c): checks the container, then decodes each inner frame with
 * wire_decode_body, the state frame last. */
int wire_decode_bundle(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                       gale_err *err);
int wire_decode_weather(wire_reader *r, const wire_header *h, wire_weather *out,
                        gale_err *err);

/* Short message type name for errors ("KEYFRAME", ...). */
const char *wire_type_name(unsigned type);

#endif
