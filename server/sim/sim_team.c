/* The tick's OpenMP threads' scheduling policy: see sim_team.h. */
#include "sim_team.h"

#include <errno.h>
#include <omp.h>
#include <pthread.h>
#include <sched.h>
#include <string.h>

static int set_policy(int priority)
{
    const struct sched_param sp = { .sched_priority = priority };
    return pthread_setschedparam(pthread_self(), priority > 0 ? SCHED_FIFO : SCHED_OTHER,
                                 &sp);
}

int sim_team_set_priority(int n_threads, int priority, gale_err *err)
{
    if (priority < 0 || priority > 99) {
        return gale_errf(err, GALE_E_ARG, "tick priority %d: expected 0..99", priority);
    }
    int policy_was;
    struct sched_param was;
    if (pthread_getschedparam(pthread_self(), &policy_was, &was)) {
        policy_was = SCHED_OTHER;
        was.sched_priority = 0;
    }
    /* the caller first: a refusal leaves the team as it was */
    int rc = set_policy(priority);
    if (!rc && n_threads > 1) {
        int failed = 0;
#pragma omp parallel num_threads(n_threads) reduction(max : failed)
        {
            if (omp_get_thread_num() > 0) {
                const int r = set_policy(priority);
                failed = r > failed ? r : failed;
            }
        }
        if (failed) {
            rc = failed;
            (void)pthread_setschedparam(pthread_self(), policy_was, &was);
#pragma omp parallel num_threads(n_threads)
            {
                if (omp_get_thread_num() > 0) {
                    (void)pthread_setschedparam(pthread_self(), policy_was, &was);
                }
            }
        }
    }
    if (rc == EPERM) {
        return gale_errf(err, GALE_E_STATE,
                         "tick threads at SCHED_FIFO priority %d: not permitted (it needs root, "
                         "CAP_SYS_NICE, or an RLIMIT_RTPRIO of at least %d: systemd's "
                         "LimitRTPRIO=%d with RestrictRealtime=no)",
                         priority, priority, priority);
    }
    if (rc) {
        return gale_errf(err, GALE_E_STATE, "tick threads at %s priority %d: %s",
                         priority > 0 ? "SCHED_FIFO" : "SCHED_OTHER", priority, strerror(rc));
    }
    return GALE_OK;
}
