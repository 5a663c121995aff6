/* sim_team_set_priority: every thread of the tick's OpenMP team takes the policy (the
 * threads that exist and those the team starts later), and back; where the system
 * refuses it, the error names what would allow it and no thread changes. */
#include "check.h"
#include "sim_team.h"

#include <omp.h>
#include <pthread.h>
#include <sched.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#define TEAM 3

/* Policy and priority of each thread of a team of n (the caller first). */
static void team_policies(int n, int *policy, int *priority)
{
    for (int i = 0; i < n; i++) {
        policy[i] = -1;
        priority[i] = -1;
    }
#pragma omp parallel num_threads(n)
    {
        const int i = omp_get_thread_num();
        struct sched_param sp;
        if (i < n && !pthread_getschedparam(pthread_self(), &policy[i], &sp)) {
            priority[i] = sp.sched_priority;
        }
    }
}

static int count_at(int n, int policy, int priority)
{
    int p[TEAM + 1], q[TEAM + 1], k = 0;
    team_policies(n, p, q);
    for (int i = 0; i < n; i++) {
        k += p[i] == policy && q[i] == priority;
    }
    return k;
}

/* In a child without the privilege (no root, RLIMIT_RTPRIO 0): refused, named, unchanged.
 * Run before this process starts any OpenMP thread, as a forked child gets none. */
static void test_refused(void)
{
    const pid_t pid = fork();
    if (pid == 0) {
        int bad = 0;
        const struct rlimit none = { 0, 0 };
        if (setrlimit(RLIMIT_RTPRIO, &none) || (getuid() == 0 && setuid(65534))) {
            _exit(3);
        }
        gale_err e = { 0 };
        const int rc = sim_team_set_priority(TEAM, 1, &e);
        bad |= rc != GALE_E_STATE;
        bad |= !strstr(e.msg, "SCHED_FIFO priority 1: not permitted");
        bad |= !strstr(e.msg, "LimitRTPRIO=1");
        bad |= count_at(TEAM, SCHED_OTHER, 0) != TEAM;
        if (bad) {
            fprintf(stderr, "refused: rc %d, \"%s\"\n", rc, e.msg);
        }
        _exit(bad ? 1 : 0);
    }
    int status = -1;
    CHECK(pid > 0 && waitpid(pid, &status, 0) == pid);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

static void test_team_and_back(void)
{
    /* the team exists before the call: the call must reach its threads */
    CHECK(count_at(TEAM, SCHED_OTHER, 0) == TEAM);
    gale_err e = { 0 };
    const int rc = sim_team_set_priority(TEAM, 1, &e);
    if (rc) {
        /* an unprivileged run: the refusal is test_refused's */
        CHECK(rc == GALE_E_STATE);
        CHECK_STR_HAS(e.msg, "LimitRTPRIO=1");
        CHECK(count_at(TEAM, SCHED_OTHER, 0) == TEAM);
        fprintf(stderr, "  (not permitted here: the team's policy is not exercised)\n");
        return;
    }
    CHECK(count_at(TEAM, SCHED_FIFO, 1) == TEAM);
    /* a thread the team starts later inherits the caller's */
    CHECK(count_at(TEAM + 1, SCHED_FIFO, 1) == TEAM + 1);
    CHECK(sim_team_set_priority(TEAM + 1, 0, &e) == GALE_OK);
    CHECK(count_at(TEAM + 1, SCHED_OTHER, 0) == TEAM + 1);
}

static void test_range(void)
{
    gale_err e = { 0 };
    CHECK(sim_team_set_priority(TEAM, 100, &e) == GALE_E_ARG);
    CHECK_STR_HAS(e.msg, "tick priority 100: expected 0..99");
    CHECK(sim_team_set_priority(TEAM, -1, &e) == GALE_E_ARG);
}

int main(void)
{
    RUN(test_refused);
    RUN(test_team_and_back);
    RUN(test_range);
    return check_report();
}
