/* A slow reader's rate steps (SERVER.md "Slow readers", net_ws.c deliver_one): one
 * snapshot in n of those published, each then the snapshot's KEYFRAME with what rides only
 * with keyframes (the whole damage state). A keyframe is several deltas' worth, so a rate
 * just below the full one would send more bytes, not fewer; the steps never go there.
 * Pure functions. */
#ifndef GALE_NET_RATE_H
#define GALE_NET_RATE_H

#include "net.h"

/* The bytes of p's keyframe and of its extras that go only with it; 0 when p has no
 * keyframe (frames on demand: a stream whose every reader holds the last snapshots). */
size_t net_rate_key_bytes(const net_snap *p);

/* The bytes of p's delta (delta2's, else delta1's); 0 when p has none. */
size_t net_rate_delta_bytes(const net_snap *p);

/* A stream's keyframe-to-delta ratio from the last of each a reader saw (a stream's
 * snapshot often carries only one of them); 0 while either is unknown. */
float net_rate_key_per_delta(size_t key_bytes, size_t delta_bytes);

/* The fewest snapshots in one a decimated reader may take: one in n costs key/n bytes a
 * snapshot against a delta's at full rate, so n >= key_per_delta (rounded up); at least 2,
 * at most hz (the snapshot rate). key_per_delta 0 (unknown): 2. */
int net_rate_floor(float key_per_delta, int hz);

/* The fewest snapshots in one that a reader which took take_bytes_s bytes a second (over
 * the last second, while behind) can take, each a keyframe of key_bytes: n >=
 * key_bytes * hz / take_bytes_s, rounded up; at most hz; 1 when either is unknown (0). */
int net_rate_take_floor(size_t key_bytes, double take_bytes_s, int hz);

/* The rate after a reader at one in decim fell behind: doubled, at least net_rate_floor
 * (the ratio may have grown since) and take_floor (net_rate_take_floor), at most hz. */
int net_rate_lower(int decim, float key_per_delta, int take_floor, int hz);

/* The rate after a reader at one in decim kept up: halved, or full rate (1) where the
 * half is below net_rate_floor. */
int net_rate_raise(int decim, float key_per_delta, int hz);

#endif
