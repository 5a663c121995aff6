/* KEYFRAME and DELTA state frames: quantised modal coordinates q of every tree in view
 * (Diener 2008 section 3). Values are coded per group of 8 modes as bit-packed zigzag
 * residuals against a chosen predictor (zero, previous snapshot, linear extrapolation of
 * the two previous); PROTOCOL.md "State frames" has the byte table.
 *
 * Private to the state codec, what its files share: the format's constants, the helpers
 * both directions or several files use, and the calls between the files. msg_state_enc.c
 * checks the states, writes each frame's fixed part and holds the encoders' entry points;
 * msg_state_lanes.c splits the values section into lanes and moves them together;
 * msg_state_rows.c codes the values of a run of trees; msg_state_dec.c decodes a frame.
 * Included by msg_state_*.c only. */
#ifndef GALE_MSG_STATE_INT_H
#define GALE_MSG_STATE_INT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "wire.h"
#include "wire_cursor.h"

#define GROUP 8u        /* modes per group; a full group of width w is exactly w bytes */
#define MAX_WIDTH 18u   /* |v - pred| <= 4 * WIRE_QMAX < 2^17, zigzag < 2^18 */

enum { PRED_ZERO = 0, PRED_PREV = 1, PRED_LINEAR = 2 };
enum { SET_SAME = 0, SET_RUNS = 1 };
enum { MODES_FULL = 0, MODES_LIST = 1 };

/* 8 bytes at p as a little-endian number. */
static inline uint64_t load_le64(const uint8_t *p)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    uint64_t v;
    memcpy(&v, p, sizeof v);
    return v;
#else
    uint64_t v = 0;
    for (unsigned i = 0; i < 8; i++) {
        v |= (uint64_t)p[i] << (8 * i);
    }
    return v;
#endif
}

/* Room past a tree's worst case the packer may overwrite with zeros (the 24 bytes a
 * group of width 17-18 is assembled in, plus the header byte before it). */
#define FAST_SLACK 32u

/* Worst-case bytes of one tree of n modes in the values section. */
static inline size_t tree_bound(uint32_t n)
{
    return (n + GROUP - 1) / GROUP + ((size_t)n * MAX_WIDTH + 7) / 8;
}

typedef wire_lane_job lane_job;

/* Values of trees [t0, t1) into the nf frames w[f] (msg_state_rows.c). */
bool state_put_values(wire_writer *const *w, const int *n_pred, int nf, const wire_scene *sc,
                      const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                      uint32_t t0, uint32_t t1);

/* The values of nf frames in lanes (msg_state_lanes.c): the layout, lanes [i0, i1) run,
 * the lanes moved together, and the three in one call. */
void state_lanes_layout(lane_job *j, wire_writer *const *w, const int *n_pred, int nf,
                        const wire_scene *sc, const wire_state *cur, const wire_state *prev,
                        const wire_state *prev2, const wire_lanes *lanes);
void state_lanes_run(lane_job *j, const wire_lanes *lanes, int i0, int i1);
int state_lanes_join(lane_job *j, wire_writer *const *w);
int state_put_lanes(wire_writer *const *w, const int *n_pred, int nf, const wire_scene *sc,
                    const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                    const wire_lanes *lanes);

#endif
