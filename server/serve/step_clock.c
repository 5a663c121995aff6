/* The fixed-step loop's schedule (step_clock.h). */
#include "step_clock.h"

void step_clock_init(step_clock *c, uint64_t period_ns)
{
    *c = (step_clock){ .period_ns = period_ns };
}

step_verdict step_clock_end(step_clock *c, uint64_t now_ns, uint64_t work_ns)
{
    step_verdict v = { 0 };
    if (!c->warm) {
        c->due_ns = now_ns;
    }
    /* the next tick is due one period after this one was */
    c->due_ns += c->period_ns;
    v.late_ns = (int64_t)(now_ns - c->due_ns);
    const int64_t period = (int64_t)c->period_ns;
    if (c->warm && (v.late_ns > period || work_ns > c->period_ns)) {
        v.overrun = true;
        if (v.late_ns > STEP_CLOCK_RESTART_NS) {
            c->due_ns = now_ns;
            v.restarted = true;
        }
    }
    c->warm = true;
    v.wait = v.late_ns <= 0;
    return v;
}
