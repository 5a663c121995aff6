/* The fixed-step loop's schedule (server/SERVER.md "Loop"): when the next tick is due, and
 * whether the tick that just ended overran. A tick is never skipped, so simulated time
 * stays exact: a late loop runs its ticks back to back until it is on schedule again, and
 * one more than STEP_CLOCK_RESTART_NS behind starts the schedule again from now. The first
 * tick warms up (first wind step, threads started, state touched): the schedule starts
 * when it ends, and it is no overrun. Times are CLOCK_MONOTONIC nanoseconds. */
#ifndef GALE_STEP_CLOCK_H
#define GALE_STEP_CLOCK_H

#include <stdbool.h>
#include <stdint.h>

/* A loop this far behind gives up catching up and restarts its schedule from now. */
#define STEP_CLOCK_RESTART_NS 250000000LL

typedef struct step_clock {
    uint64_t period_ns;
    uint64_t due_ns; /* when the next tick is due; set by the first step_clock_end */
    bool warm;       /* the warm-up tick has ended */
} step_clock;

typedef struct step_verdict {
    bool overrun;    /* the tick's work took longer than a period, or it ended more than a
                        period after the next tick was due: count and log it */
    bool restarted;  /* the schedule was more than STEP_CLOCK_RESTART_NS behind */
    bool wait;       /* the loop is on schedule: wait until due_ns before the next tick */
    int64_t late_ns; /* how long after the next tick was due this one ended (<= 0: early) */
} step_verdict;

void step_clock_init(step_clock *c, uint64_t period_ns);

/* The tick that ended at now_ns after work_ns of work: advances the schedule by one
 * period and says what the loop does next. */
step_verdict step_clock_end(step_clock *c, uint64_t now_ns, uint64_t work_ns);

#endif
