/* The tick's thread team (sim_team.h): every job of every phase runs exactly once, on as
 * many threads as asked, whatever the timing of the helpers; each calling thread has a
 * team of its own, stopped when the thread ends; sim_team_set_priority puts every thread
 * of the team at the policy (those that exist and those the team starts later) and back,
 * and where the system refuses it the error names what would allow it and no thread
 * changes. */
#include "check.h"
#include "sim_team.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#define TEAM 3

/* A phase of n jobs that each wait for all n (so each thread runs exactly one) and note
 * their thread's policy. */
typedef struct policy_job {
    pthread_barrier_t all;
    int policy[TEAM + 1], priority[TEAM + 1];
    pthread_t thread[TEAM + 1];
} policy_job;

static void note_policy(void *ctx, int k)
{
    policy_job *j = ctx;
    struct sched_param sp;
    j->thread[k] = pthread_self();
    if (!pthread_getschedparam(pthread_self(), &j->policy[k], &sp)) {
        j->priority[k] = sp.sched_priority;
    }
    pthread_barrier_wait(&j->all);
}

/* Threads of a team of n at (policy, priority); -1 where the n jobs did not run on n
 * distinct threads. */
static int count_at(int n, int policy, int priority)
{
    policy_job j;
    for (int i = 0; i < n; i++) {
        j.policy[i] = -1;
        j.priority[i] = -1;
    }
    pthread_barrier_init(&j.all, NULL, (unsigned)n);
    sim_team_run(n, n, note_policy, &j);
    pthread_barrier_destroy(&j.all);
    int k = 0;
    for (int i = 0; i < n; i++) {
        for (int h = 0; h < i; h++) {
            if (pthread_equal(j.thread[h], j.thread[i])) {
                return -1;
            }
        }
        k += j.policy[i] == policy && j.priority[i] == priority;
    }
    return k;
}

/* In a child without the privilege (no root, RLIMIT_RTPRIO 0): refused, named, unchanged. */
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

/* Jobs that count their runs, per phase context; some cost more than others, so threads
 * come free at different times. */
#define MAX_JOBS 1000
typedef struct count_job {
    _Atomic int runs[MAX_JOBS];
    _Atomic int finished; /* jobs returned */
    _Atomic unsigned sink;
} count_job;

static void count_run(void *ctx, int k)
{
    count_job *c = ctx;
    atomic_fetch_add(&c->runs[k], 1);
    unsigned x = (unsigned)k;
    for (int i = 0; i < (k % 7) * 40; i++) {
        x = x * 1664525u + 1013904223u;
    }
    atomic_fetch_add(&c->sink, x);
    atomic_fetch_add(&c->finished, 1);
}

/* Thousands of phases on teams of 1..8 threads with 0..1000 jobs, two contexts taking
 * turns (a helper late from one phase must take nothing of the next): after each, every
 * job has run exactly once, and all had returned when the phase did. Returns the phases
 * whose counts were wrong. */
static int stress(int phases)
{
    static const int threads[] = { 1, 2, 3, 8 };
    static const int jobs[] = { 0, 1, 2, 5, 64, 1000 };
    count_job *ctx[2] = { calloc(1, sizeof(count_job)), calloc(1, sizeof(count_job)) };
    int wrong = 0;
    for (int p = 0; p < phases; p++) {
        const int nt = threads[p / 7 % 4], n = jobs[p % 6];
        count_job *c = ctx[p % 2];
        for (int k = 0; k < MAX_JOBS; k++) {
            atomic_store(&c->runs[k], 0);
        }
        atomic_store(&c->finished, 0);
        sim_team_run(nt, n, count_run, c);
        int bad = atomic_load(&c->finished) != n; /* returned before a job had */
        for (int k = 0; k < MAX_JOBS; k++) {
            bad |= atomic_load(&c->runs[k]) != (k < n);
        }
        wrong += bad;
    }
    free(ctx[0]);
    free(ctx[1]);
    return wrong;
}

static void test_each_job_once(void)
{
    CHECK(stress(6000) == 0);
}

static void *stress_thread(void *arg)
{
    *(int *)arg = stress(3000);
    return NULL;
}

static void *short_stress(void *arg)
{
    *(int *)arg = stress(200);
    return NULL;
}

/* Two callers at once, each on a team of its own, and threads that use a team and end
 * (their teams stop with them: ASan's leak check sees a team left behind). */
static void test_callers(void)
{
    pthread_t a, b;
    int wrong_a = -1, wrong_b = -1;
    CHECK(!pthread_create(&a, NULL, stress_thread, &wrong_a));
    CHECK(!pthread_create(&b, NULL, stress_thread, &wrong_b));
    CHECK(!pthread_join(a, NULL) && !pthread_join(b, NULL));
    CHECK(wrong_a == 0 && wrong_b == 0);
    for (int i = 0; i < 20; i++) {
        pthread_t t;
        int wrong = -1;
        CHECK(!pthread_create(&t, NULL, short_stress, &wrong));
        CHECK(!pthread_join(t, NULL));
        CHECK(wrong == 0);
    }
}

int main(void)
{
    /* first, as a forked child gets none of the parent's helpers */
    RUN(test_refused);
    RUN(test_team_and_back);
    RUN(test_range);
    RUN(test_each_job_once);
    RUN(test_callers);
    return check_report();
}
