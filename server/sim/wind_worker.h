/* The wind step one step ahead of the ticks that read it (server/SERVER.md "Loop"): a
 * tick launches a step (wind_worker_launch) and a later tick takes it (wind_worker_join).
 * With a thread of its own the step runs beside the ticks between, below them (at
 * SCHED_IDLE beside ticks at the fair scheduler's priority, at SCHED_OTHER beside
 * real-time ones or where the process may not leave SCHED_IDLE again), in the time they
 * leave idle, so no tick carries it; a join that finds it still running lends it the
 * joining thread's priority until it ends. Without a
 * thread of its own the join runs it. Either gives the same floats: the step's
 * inputs are the grid's at the launch, and nothing else steps or writes the grid until
 * the join. */
#ifndef GALE_WIND_WORKER_H
#define GALE_WIND_WORKER_H

#include <stdbool.h>

#include "err.h"
#include "wind.h"

typedef struct wind_worker wind_worker;

/* The step function and its context, borrowed for the worker's life; own_thread: run
 * steps on a thread of the worker's. NULL on failure with err filled (no memory, no
 * thread). */
wind_worker *wind_worker_create(int (*step)(void *ctx, float dt_s, wind_step_stats *st),
                                void *ctx, bool own_thread, gale_err *err);
/* Waits for a step in flight, then stops the thread. NULL is a no-op. */
void wind_worker_destroy(wind_worker *w);

/* Starts a step of dt_s (on the worker's thread, or due at the join). One at a time:
 * join the last first. */
void wind_worker_launch(wind_worker *w, float dt_s);
/* Whether a thread of this process may move from SCHED_IDLE back to SCHED_OTHER: root or
 * CAP_SYS_NICE, or an RLIMIT_NICE that allows nice 0 (the Debian service sets
 * LimitNICE=+0; a plain user's default of 0 does not). Where not, the step never runs at
 * SCHED_IDLE: no waiting tick could lend it a priority. */
bool wind_worker_unidle_permitted(void);

/* What a join took [ms]. */
typedef struct wind_join_times {
    double ms;      /* the call */
    double wait_ms; /* of which waiting for a step on the worker's thread not yet done */
    double step_ms; /* the step's own wall time, on the worker's thread or in the call */
} wind_join_times;

/* Waits for the step launched last (or runs it); fills *st with its stats (when not
 * NULL) and returns its return code: 0 when none was launched. *times (when not NULL):
 * what the call and the step took. */
int wind_worker_join(wind_worker *w, wind_step_stats *st, wind_join_times *times);

#endif
