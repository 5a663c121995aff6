/* The tick's thread team: see sim_team.h.
 *
 * One phase is one generation g. The caller publishes its jobs, then `claim` = g << 32
 * (the next job 0), then `gen` = g. A thread takes job k by moving `claim` from (g, k) to
 * (g, k + 1), so a helper that wakes late, finding `claim` at a later generation or past
 * the last job, takes nothing. A taken job's fields are those of its generation: before
 * it rewrites them the caller closes `claim` (g + 1, UINT32_MAX), so a compare-exchange
 * that succeeds came before the rewrite and so after the reads of the fields it used. */
#include "sim_team.h"

#include <errno.h>
#include <limits.h>
#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "mono.h"

/* How long a helper spins after its last job before it sleeps, and the caller for its
 * helpers' last jobs: a tick's phases are a few microseconds to a millisecond apart, so
 * the helpers stay awake through a tick and sleep between ticks. */
#define SPIN_NS 200000u

typedef struct team team;

typedef struct helper {
    team *t;
    int id; /* 0 .. n_helpers - 1: joins a generation with helpers_wanted > id */
    uint32_t gen_at_start; /* the generation published when it was started */
    pthread_t thread;
} helper;

struct team {
    _Atomic uint64_t claim;       /* generation << 32 | next job */
    _Atomic uint32_t gen;         /* the generation published (a futex word) */
    _Atomic uint32_t done;        /* jobs of the generation returned (a futex word) */
    _Atomic uint32_t sleepers;    /* helpers asleep on gen */
    _Atomic uint32_t caller_asleep; /* the caller asleep on done (0 or 1) */
    _Atomic(sim_job_fn) fn;       /* the generation's jobs */
    _Atomic(void *) ctx;
    _Atomic uint32_t n;
    _Atomic int helpers_wanted;
    _Atomic int stop;
    int n_helpers;
    helper helper[SIM_TEAM_MAX_THREADS - 1];
};

static pthread_key_t team_key;
static pthread_once_t team_key_once = PTHREAD_ONCE_INIT;
static _Thread_local team *my_team;

static void futex_wait(_Atomic uint32_t *word, uint32_t expected)
{
    (void)syscall(SYS_futex, (uint32_t *)word, FUTEX_WAIT_PRIVATE, expected, NULL, NULL, 0);
}

static void futex_wake(_Atomic uint32_t *word, int n)
{
    (void)syscall(SYS_futex, (uint32_t *)word, FUTEX_WAKE_PRIVATE, n, NULL, NULL, 0);
}

static inline void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

/* Takes and runs jobs of generation g until none is left. */
static void take_jobs(team *t, uint32_t g)
{
    uint64_t c = atomic_load(&t->claim);
    for (;;) {
        if ((uint32_t)(c >> 32) != g) {
            return;
        }
        const uint32_t k = (uint32_t)c, n = atomic_load(&t->n);
        const sim_job_fn fn = atomic_load(&t->fn);
        void *const ctx = atomic_load(&t->ctx);
        if (k >= n) {
            return;
        }
        if (!atomic_compare_exchange_weak(&t->claim, &c, c + 1)) {
            continue;
        }
        fn(ctx, (int)k);
        if (atomic_fetch_add(&t->done, 1) + 1 == n && atomic_load(&t->caller_asleep)) {
            futex_wake(&t->done, 1);
        }
        c = atomic_load(&t->claim);
    }
}

/* Waits until *word is no longer `value` and returns what it holds: spinning for SPIN_NS
 * after the call or the last change, then asleep on the futex, counted in *asleep so the
 * writer knows to wake it. */
static uint32_t await_change(_Atomic uint32_t *word, uint32_t value, _Atomic uint32_t *asleep)
{
    const uint64_t t0 = mono_ns();
    unsigned spins = 0;
    for (;;) {
        const uint32_t now = atomic_load(word);
        if (now != value) {
            return now;
        }
        if (++spins % 64 != 0) {
            cpu_relax();
            continue;
        }
        if (mono_ns() - t0 < SPIN_NS) {
            /* a real-time thread spinning would keep a same-priority one off its core */
            sched_yield();
            continue;
        }
        atomic_fetch_add(asleep, 1);
        if (atomic_load(word) == value) {
            futex_wait(word, value);
        }
        atomic_fetch_sub(asleep, 1);
    }
}

static void *helper_main(void *arg)
{
    helper *h = arg;
    team *t = h->t;
    /* not the generation now: the caller may have published the one it was started for */
    uint32_t seen = h->gen_at_start;
    for (;;) {
        /* the stop moves the generation on too */
        seen = await_change(&t->gen, seen, &t->sleepers);
        if (atomic_load(&t->stop)) {
            return NULL;
        }
        if (h->id < atomic_load(&t->helpers_wanted)) {
            take_jobs(t, seen);
        }
    }
}

static void team_stop(void *arg)
{
    team *t = arg;
    if (!t) {
        return;
    }
    atomic_store(&t->stop, 1);
    atomic_fetch_add(&t->gen, 1);
    futex_wake(&t->gen, INT_MAX);
    for (int i = 0; i < t->n_helpers; i++) {
        pthread_join(t->helper[i].thread, NULL);
    }
    free(t);
    my_team = NULL;
}

static void make_key(void)
{
    (void)pthread_key_create(&team_key, team_stop);
}

/* The caller's team with at least `helpers` helpers where they can be started; NULL
 * where not even the team can be had. Helpers inherit the caller's policy. */
static team *team_with(int helpers)
{
    helpers = helpers > SIM_TEAM_MAX_THREADS - 1 ? SIM_TEAM_MAX_THREADS - 1 : helpers;
    team *t = my_team;
    if (!t) {
        if (pthread_once(&team_key_once, make_key)) {
            return NULL;
        }
        t = calloc(1, sizeof *t);
        if (!t) {
            return NULL;
        }
        if (pthread_setspecific(team_key, t)) {
            free(t);
            return NULL;
        }
        my_team = t;
    }
    while (t->n_helpers < helpers) {
        helper *h = &t->helper[t->n_helpers];
        h->t = t;
        h->id = t->n_helpers;
        h->gen_at_start = atomic_load(&t->gen);
        if (pthread_create(&h->thread, NULL, helper_main, h)) {
            break;
        }
        t->n_helpers++;
    }
    return t;
}

void sim_team_run(int n_threads, int n, sim_job_fn fn, void *ctx)
{
    if (n <= 0) {
        return;
    }
    team *t = n_threads > 1 && n > 1 ? team_with(n_threads - 1) : NULL;
    if (!t || t->n_helpers == 0) {
        for (int k = 0; k < n; k++) {
            fn(ctx, k);
        }
        return;
    }
    const uint32_t g = atomic_load(&t->gen) + 1;
    /* closed first: a helper that read the last generation's claim and reads this one's
     * fields fails its compare-exchange (claim is no longer what it read) */
    atomic_store(&t->claim, (uint64_t)g << 32 | UINT32_MAX);
    atomic_store(&t->fn, fn);
    atomic_store(&t->ctx, ctx);
    atomic_store(&t->n, (uint32_t)n);
    atomic_store(&t->helpers_wanted, n_threads - 1 < n - 1 ? n_threads - 1 : n - 1);
    atomic_store(&t->done, 0);
    atomic_store(&t->claim, (uint64_t)g << 32);
    atomic_store(&t->gen, g);
    if (atomic_load(&t->sleepers)) {
        futex_wake(&t->gen, INT_MAX);
    }
    take_jobs(t, g);
    /* the jobs its helpers took; a helper wakes it only with the last job's return */
    for (uint32_t d = atomic_load(&t->done); d < (uint32_t)n;
         d = await_change(&t->done, d, &t->caller_asleep)) {
    }
}

static int set_policy(pthread_t th, int priority)
{
    const struct sched_param sp = { .sched_priority = priority };
    return pthread_setschedparam(th, priority > 0 ? SCHED_FIFO : SCHED_OTHER, &sp);
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
    int rc = set_policy(pthread_self(), priority);
    team *t = !rc && n_threads > 1 ? team_with(n_threads - 1) : NULL;
    for (int i = 0; t && !rc && i < t->n_helpers; i++) {
        rc = set_policy(t->helper[i].thread, priority);
        if (rc) {
            (void)pthread_setschedparam(pthread_self(), policy_was, &was);
            for (int j = 0; j < i; j++) {
                (void)pthread_setschedparam(t->helper[j].thread, policy_was, &was);
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
