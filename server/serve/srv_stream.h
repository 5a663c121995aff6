/* The encoder of one snapshot stream (net.h net_snap.stream): each snapshot as a
 * keyframe, a delta against the stream's previous snapshot and a delta against its two
 * previous ones, as far as the stream holds them (protocol/PROTOCOL.md, server/SERVER.md
 * "Loop"). The shared whole-scene stream and every view stream are each one of these;
 * they differ only in the per-tree mode counts they encode. Sim thread. */
#ifndef GALE_SRV_STREAM_H
#define GALE_SRV_STREAM_H

#include <stdint.h>

#include "err.h"
#include "net.h"
#include "wire.h"

/* The quantised q of the last three snapshots, newest first (q[0] this snapshot, q[1]
 * the one before, q[2] the one before that), each [n_trees][stride], borrowed. */
typedef struct srv_qhist {
    const int16_t *q[3];
    uint32_t n_trees;
    uint32_t stride;
    const wire_lanes *lanes; /* the encoders' lanes (sim_lanes); NULL: one */
} srv_qhist;

/* Caller-owned; srv_stream_start sets it up. */
typedef struct srv_stream {
    uint32_t id;            /* net_snap.stream: 0 the shared stream */
    const uint8_t *n_modes; /* [n_trees] modes encoded per tree, borrowed */
    int held;               /* snapshots in a row encoded with these modes: 0, 1, 2 (or more) */
    uint32_t key_every;     /* a snapshot whose seq is a multiple of it is keyframe only; 0 never */
} srv_stream;

/* (Re)starts stream id with per-tree mode counts n_modes (borrowed while the stream
 * lasts): its next snapshot gets a keyframe only, and so does every snapshot whose seq is
 * a multiple of key_every (0: none), so that every connection on the stream gets a
 * KEYFRAME at least that often (PROTOCOL.md "Sequence and gaps"). */
void srv_stream_start(srv_stream *st, uint32_t id, const uint8_t *n_modes, uint32_t key_every);

/* Encodes snapshot seq (header h: tick and server time) of the stream into out, in one
 * pass over the snapshots (wire_encode_snapshot_lanes, on qh->lanes): delta2 when the
 * stream holds the two previous snapshots; delta1 when it holds the previous one and
 * either not the one before or want has NET_WANT_DELTA1; the keyframe when it holds
 * neither (a start, a periodic keyframe's seq) or want has NET_WANT_KEY (net_frames_wanted:
 * no connection takes a frame not wanted, SERVER.md "Frames on demand"). A frame not
 * encoded has length 0. Sets out->seq and out->stream; the stream then holds one more.
 * Fails with the wire_encode_* error in err; the stream then holds none (its clients see
 * a gap and get the next keyframe) and out's lengths mean nothing. */
int srv_stream_encode(srv_stream *st, const wire_header *h, uint32_t seq,
                      const wire_scene *scene, const srv_qhist *qh, unsigned want,
                      net_snap *out, gale_err *err);

/* The stream's snapshot was not published (no free snapshot, or another message of it
 * failed): the stream holds none. */
void srv_stream_skip(srv_stream *st);

#endif
