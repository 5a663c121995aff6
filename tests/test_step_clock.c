/* Tests of the fixed-step loop's schedule (server/serve/step_clock.c) on a simulated
 * clock: ticks of given work run one after the other, each starting when the last ended
 * or, when the schedule says wait, when the next is due. Checked: the warm-up tick is no
 * overrun and starts the schedule; on-time ticks start exactly a period apart; a slow
 * tick is one overrun and the ticks after it catch up back to back, back on the original
 * schedule with none skipped; a loop woken late is an overrun; one far behind restarts
 * its schedule. */
#include <stdlib.h>

#include "check.h"
#include "step_clock.h"

#define PERIOD_NS 16666666u /* 60 Hz */
#define MS 1000000u

typedef struct run {
    int ticks, overruns, restarts, waits;
    uint64_t start_ns[2000]; /* when each tick started */
    uint64_t end_ns;         /* when the last tick ended */
} run;

/* Runs n ticks from t0_ns, tick k working work_ns[k]; wake_late_ns[k] (NULL: none) is how
 * much later than due the loop wakes before tick k. */
static void simulate(run *r, uint64_t t0_ns, int n, const uint64_t *work_ns,
                     const uint64_t *wake_late_ns)
{
    step_clock c;
    step_clock_init(&c, PERIOD_NS);
    memset(r, 0, sizeof *r);
    uint64_t t = t0_ns;
    for (int k = 0; k < n; k++) {
        r->start_ns[k] = t;
        const uint64_t end = t + work_ns[k];
        const step_verdict v = step_clock_end(&c, end, work_ns[k]);
        r->ticks++;
        r->overruns += v.overrun;
        r->restarts += v.restarted;
        r->waits += v.wait;
        /* a verdict to wait always points past the end: the loop never sleeps backwards */
        CHECK(!v.wait || c.due_ns >= end);
        t = v.wait ? c.due_ns : end;
        if (k + 1 < n && wake_late_ns) {
            t += wake_late_ns[k + 1];
        }
        r->end_ns = end;
    }
}

static uint64_t work[2000], late[2000];

static void fill(uint64_t ns)
{
    for (int k = 0; k < 2000; k++) {
        work[k] = ns;
        late[k] = 0;
    }
}

static void test_warm_up_and_steady(void)
{
    static run r;
    fill(5 * MS);
    work[0] = 30 * MS; /* the warm-up: tens of ms on a large scene */
    simulate(&r, 1000 * MS, 600, work, NULL);
    CHECK(r.overruns == 0);
    CHECK(r.waits == 600);
    /* the schedule starts when the warm-up ends: tick k starts (k - 1) periods after */
    const uint64_t t1 = 1000 * MS + 30 * MS + PERIOD_NS;
    CHECK(r.start_ns[1] == t1);
    CHECK(r.start_ns[599] == t1 + 598u * (uint64_t)PERIOD_NS);
}

/* One 40 ms tick among 5 ms ones: one overrun; the next ticks run back to back (no wait)
 * until the loop is on schedule again, then every tick starts where the schedule without
 * the slow tick would have started it: none skipped, no drift. */
static void test_slow_tick_caught_up(void)
{
    static run r;
    fill(5 * MS);
    work[100] = 40 * MS;
    simulate(&r, 0, 600, work, NULL);
    CHECK(r.overruns == 1);
    CHECK(r.restarts == 0);
    CHECK(r.start_ns[101] == r.start_ns[100] + 40 * MS); /* at once, behind schedule */
    const uint64_t t1 = 5 * MS + PERIOD_NS;
    CHECK(r.start_ns[110] == t1 + 109u * (uint64_t)PERIOD_NS);
    CHECK(r.start_ns[599] == t1 + 598u * (uint64_t)PERIOD_NS);
    fprintf(stderr, "  a 40 ms tick: %d overrun, %d ticks without a wait\n", r.overruns,
            r.ticks - r.waits);
}

/* A 30 ms tick then 12 ms ones: the slow one overran; the 12 ms ones, each within its
 * period, catch up 4.7 ms a tick and are no overruns though they start late. */
static void test_catch_up_is_no_overrun(void)
{
    static run r;
    fill(12 * MS);
    work[10] = 30 * MS;
    simulate(&r, 0, 200, work, NULL);
    CHECK(r.overruns == 1);
    CHECK(r.waits == 200 - 3); /* 13.3 ms behind: 2 more ticks to catch up */
}

/* Woken 30 ms after its tick was due (a stalled machine): that tick ends 18.3 ms after
 * the next was due, more than a period behind, an overrun though its work was short.
 * Woken 20 ms late it ends 8.3 ms after: behind, caught up by the next, no overrun. */
static void test_late_wake_overruns(void)
{
    static run r;
    fill(5 * MS);
    late[50] = 30 * MS;
    simulate(&r, 0, 100, work, late);
    CHECK(r.overruns == 1);
    CHECK(r.start_ns[51] == r.start_ns[50] + 5 * MS); /* at once, behind schedule */
    late[50] = 20 * MS;
    simulate(&r, 0, 100, work, late);
    CHECK(r.overruns == 0);
    CHECK(r.start_ns[99] == 5 * MS + PERIOD_NS + 98u * (uint64_t)PERIOD_NS);
}

/* A 400 ms tick: more than STEP_CLOCK_RESTART_NS behind, the schedule restarts from its
 * end; the ticks after it wait again at once, a period apart. */
static void test_far_behind_restarts(void)
{
    static run r;
    fill(5 * MS);
    work[20] = 400 * MS;
    simulate(&r, 0, 100, work, NULL);
    CHECK(r.overruns == 1);
    CHECK(r.restarts == 1);
    const uint64_t end20 = r.start_ns[20] + 400 * MS;
    CHECK(r.start_ns[21] == end20);
    CHECK(r.start_ns[22] == end20 + PERIOD_NS);
    CHECK(r.start_ns[99] == end20 + 78u * (uint64_t)PERIOD_NS);
}

int main(void)
{
    RUN(test_warm_up_and_steady);
    RUN(test_slow_tick_caught_up);
    RUN(test_catch_up_is_no_overrun);
    RUN(test_late_wake_overruns);
    RUN(test_far_behind_restarts);
    return check_report();
}
