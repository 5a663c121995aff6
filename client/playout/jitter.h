/* Client jitter buffer and clock: decoded q snapshots held by server time (protocol/
 * PROTOCOL.md "Frame header"), played out a fixed delay behind the server so every wall
 * tile shows the same instant, with q interpolated C1-smoothly between snapshots (cubic
 * Hermite, tangents from the parabola through neighbouring snapshots, exact for quadratic
 * motion). */
#ifndef GALE_JITTER_H
#define GALE_JITTER_H

#include <stdbool.h>
#include <stdint.h>

#include "err.h"

#define JITTER_MAX_CAPACITY 256

typedef struct jitter_desc {
    uint32_t n_values;      /* floats per snapshot (trees × modes); required, > 0 */
    uint32_t capacity;      /* snapshots held; 0 = 32, at most JITTER_MAX_CAPACITY */
    double playout_delay_s; /* render this far behind server time; 0 = 0.1 s */
} jitter_desc;

/* Why a snapshot was not taken (jitter_insert's non-negative result). */
enum {
    JITTER_INSERTED = 0,
    JITTER_DUPLICATE = 1, /* same tick already held */
    JITTER_LATE = 2,      /* older than what playout has already passed */
};

typedef struct jitter_stats {
    uint64_t inserted;
    uint64_t duplicates;
    uint64_t late;         /* arrived after playout passed their time */
    uint64_t out_of_order; /* arrived before a newer tick but still in time */
    uint64_t evicted;      /* dropped to make room (capacity) */
    uint64_t underruns;    /* samples past the newest snapshot (held the newest) */
} jitter_stats;

/* Where a sample fell. */
typedef struct jitter_sample_info {
    uint64_t tick0, tick1; /* the snapshots bracketing the render time */
    float s;               /* 0..1 between them */
    bool underrun;         /* render time past the newest snapshot: held it */
    bool before_first;     /* render time before the oldest snapshot: held it */
} jitter_sample_info;

typedef struct jitter jitter;

/* Creates a buffer for snapshots of d->n_values floats; all storage is allocated here,
 * none later. Returns NULL (and fills err) on a bad desc or no memory. */
jitter *jitter_create(const jitter_desc *d, gale_err *err);

/* Frees j. NULL is a no-op. */
void jitter_destroy(jitter *j);

/* The resolved desc (defaults applied). */
jitter_desc jitter_get_desc(const jitter *j);

/* Copies one decoded snapshot (q[n_values], borrowed) taken at server tick `tick` and
 * server time t_s. Snapshots may arrive out of order; the buffer keeps them sorted by
 * tick. Returns JITTER_INSERTED, JITTER_DUPLICATE or JITTER_LATE (not taken, counted),
 * or GALE_E_RANGE for a non-finite time or a time that disagrees with tick order. When
 * full, the oldest snapshot is evicted. */
int jitter_insert(jitter *j, uint64_t tick, double t_s, const float *q, gale_err *err);

/* Writes q at server time render_t_s into out[n_values]: cubic Hermite between the two
 * bracketing snapshots (C1 across snapshots, no steps at any display rate); before the
 * first or after the newest snapshot it holds that snapshot. Returns 0, or GALE_E_STATE
 * when the buffer is empty (out untouched). Marks times before render_t_s as passed, so
 * later arrivals for them count as late; past the newest snapshot (an underrun, which holds
 * it) only the newest's time is passed: the times after it were never shown, and a
 * snapshot of one of them that arrives is taken, else a client behind its stream (a wall
 * tile drawing a frame more than its delay ahead, a loaded machine) would refuse every
 * snapshot and show the one it held until the stream got ahead again. info may be NULL. */
int jitter_sample(jitter *j, double render_t_s, float *out, jitter_sample_info *info);

/* Drops every snapshot and the passed-time mark (after a reconnect); stats are kept. */
void jitter_reset(jitter *j);

/* Number of snapshots held, and the server-time span they cover. */
uint32_t jitter_count(const jitter *j);
double jitter_newest_time(const jitter *j); /* -inf when empty */
double jitter_oldest_time(const jitter *j); /* +inf when empty */
jitter_stats jitter_get_stats(const jitter *j);

/* Render time for a local clock reading: server time estimate minus the playout delay. */
double jitter_render_time(const jitter *j, double server_now_s);

/* Server clock estimate from ping/pong (NTP-style): each exchange gives
 * offset = t_server − (t_sent + t_recv)/2 with error at most rtt/2; the estimate uses the
 * sample of least round trip among the last JITTER_CLOCK_WINDOW, which bounds the error
 * by that sample's rtt/2. Before any pong, snapshot arrivals give an upper bound
 * (t_server − t_recv = offset − one-way delay; its maximum is the best). */
#define JITTER_CLOCK_WINDOW 16

typedef struct jitter_clock {
    double offset_s[JITTER_CLOCK_WINDOW]; /* server − local, per pong */
    double rtt_s[JITTER_CLOCK_WINDOW];
    uint32_t n, next;   /* samples held, ring position */
    double arrival_max; /* max(t_server − t_recv) over snapshots; -inf if none */
    bool have_arrival;
} jitter_clock;

/* Zeroes c (no samples). */
void jitter_clock_init(jitter_clock *c);

/* One ping sent at local t_sent_s, answered with server time t_server_s, received at local
 * t_recv_s. Ignored if t_recv_s < t_sent_s or any value is not finite. */
void jitter_clock_pong(jitter_clock *c, double t_sent_s, double t_server_s, double t_recv_s);

/* A snapshot stamped t_server_s arrived at local t_recv_s. */
void jitter_clock_arrival(jitter_clock *c, double t_server_s, double t_recv_s);

/* Server time now for local time local_s; false if nothing is known yet (then returns
 * local_s unchanged in *server_s). */
bool jitter_clock_server_time(const jitter_clock *c, double local_s, double *server_s);

/* Round trip of the sample in use [s]; negative when no pong has arrived. */
double jitter_clock_rtt(const jitter_clock *c);

#endif
