/* The wind step on its own thread: see wind_worker.h. */
#include "wind_worker.h"
#include "mono.h"
#include "pi_mutex.h"

#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdlib.h>


struct wind_worker {
    int (*step)(void *ctx, float dt_s, wind_step_stats *st);
    void *ctx;
    bool own_thread;
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t cond;
    bool due;     /* a step was launched and not yet taken by the thread */
    bool running; /* launched and not yet done */
    bool quit;
    float dt_s;
    bool tick_rt;   /* the launching thread ran at a real-time policy */
    bool idle_ok;   /* a thread of this process may leave SCHED_IDLE again */
    bool lent;      /* a join lent the step in flight its priority */
    double step_ms; /* the last step's wall time */
    int rc;
    wind_step_stats st;
};

static bool rt_policy(int policy)
{
    return policy == SCHED_FIFO || policy == SCHED_RR;
}

/* wind_worker_unidle_permitted's trial, on a thread of its own, which may be left at
 * SCHED_IDLE. */
static void *try_unidle(void *arg)
{
    bool *ok = arg;
    *ok = pthread_setschedparam(pthread_self(), SCHED_IDLE, &(struct sched_param){ 0 }) == 0 &&
          pthread_setschedparam(pthread_self(), SCHED_OTHER, &(struct sched_param){ 0 }) == 0;
    return NULL;
}

bool wind_worker_unidle_permitted(void)
{
    bool ok = false;
    pthread_t th;
    if (pthread_create(&th, NULL, try_unidle, &ok) == 0) {
        pthread_join(th, NULL);
    }
    return ok;
}

/* The step's own policy, set as each step starts, under the lock, unless a join lent it
 * a priority already:
 * - beside ticks at the fair scheduler's priority, SCHED_IDLE: the step takes a core only
 *   while nothing else wants it, and a tick thread that wakes preempts it at once (a
 *   niced thread keeps the core to the end of its slice, holding up a tick's parallel
 *   region behind it);
 * - beside ticks at a real-time priority, SCHED_OTHER: a waking tick thread preempts it
 *   at once all the same, and it takes its fair share beside other programs. At
 *   SCHED_IDLE any busy program starves it: two clients decoding the 2 km scene on the
 *   server's 2 cores held 290 of 897 steps past their tick, 26 ms each (SERVER.md "The
 *   2 km scene beside its clients");
 * - SCHED_OTHER too where the process may not leave SCHED_IDLE again: a waiting tick
 *   could not lend it its priority, and beside a busy program every step's tick would
 *   wait for a step that gets almost no CPU (the town block ran at an eighth of real time
 *   so).
 * Where the change is refused the step keeps the policy it has. */
static void step_policy(const wind_worker *w)
{
    const bool idle = !w->tick_rt && w->idle_ok;
    (void)pthread_setschedparam(pthread_self(), idle ? SCHED_IDLE : SCHED_OTHER,
                                &(struct sched_param){ 0 });
}

static void *worker_main(void *arg)
{
    wind_worker *w = arg;
    pthread_mutex_lock(&w->lock);
    for (;;) {
        while (!w->due && !w->quit) {
            pthread_cond_wait(&w->cond, &w->lock);
        }
        if (!w->due) {
            break;
        }
        w->due = false;
        const float dt_s = w->dt_s;
        if (!w->lent) { /* a join may have lent it a priority before it began */
            step_policy(w);
        }
        pthread_mutex_unlock(&w->lock);
        wind_step_stats st = { 0 };
        const double t0 = mono_ms();
        const int rc = w->step(w->ctx, dt_s, &st);
        const double step_ms = mono_ms() - t0;
        pthread_mutex_lock(&w->lock);
        w->step_ms = step_ms;
        w->lent = false;
        w->st = st;
        w->rc = rc;
        w->running = false;
        pthread_cond_broadcast(&w->cond);
    }
    pthread_mutex_unlock(&w->lock);
    return NULL;
}

wind_worker *wind_worker_create(int (*step)(void *ctx, float dt_s, wind_step_stats *st),
                                void *ctx, bool own_thread, gale_err *err)
{
    wind_worker *w = calloc(1, sizeof *w);
    if (!w) {
        gale_errf(err, GALE_E_NOMEM, "wind_worker_create: no memory");
        return NULL;
    }
    w->step = step;
    w->ctx = ctx;
    w->own_thread = own_thread;
    w->idle_ok = own_thread && wind_worker_unidle_permitted();
    pi_mutex_init(&w->lock);
    pthread_cond_init(&w->cond, NULL);
    if (own_thread && pthread_create(&w->thread, NULL, worker_main, w)) {
        pthread_cond_destroy(&w->cond);
        pthread_mutex_destroy(&w->lock);
        free(w);
        gale_errf(err, GALE_E_NOMEM, "wind_worker_create: no thread");
        return NULL;
    }
    if (own_thread) {
        (void)pthread_setname_np(w->thread, "gale-wind");
    }
    return w;
}

void wind_worker_destroy(wind_worker *w)
{
    if (!w) {
        return;
    }
    pthread_mutex_lock(&w->lock);
    w->quit = true;
    pthread_cond_broadcast(&w->cond);
    pthread_mutex_unlock(&w->lock);
    if (w->own_thread) {
        pthread_join(w->thread, NULL);
    }
    pthread_cond_destroy(&w->cond);
    pthread_mutex_destroy(&w->lock);
    free(w);
}

void wind_worker_launch(wind_worker *w, float dt_s)
{
    int policy = SCHED_OTHER;
    struct sched_param sp;
    const bool rt = pthread_getschedparam(pthread_self(), &policy, &sp) == 0 && rt_policy(policy);
    pthread_mutex_lock(&w->lock);
    w->tick_rt = rt;
    w->dt_s = dt_s;
    w->due = true;
    w->running = true;
    if (w->own_thread) {
        pthread_cond_broadcast(&w->cond);
    }
    pthread_mutex_unlock(&w->lock);
}

int wind_worker_join(wind_worker *w, wind_step_stats *st, wind_join_times *times)
{
    const double t0 = mono_ms();
    if (!w->own_thread && w->due) {
        w->due = false;
        w->st = (wind_step_stats){ 0 };
        w->rc = w->step(w->ctx, w->dt_s, &w->st);
        w->step_ms = mono_ms() - t0;
        w->running = false;
    }
    pthread_mutex_lock(&w->lock);
    double wait_ms = 0.0;
    if (w->running) {
        /* The tick waits on the step: the step takes the waiting thread's policy and
         * priority until it ends (priority inheritance), so no program between them in
         * priority holds the tick up longer than the rest of the step takes; where that
         * is refused it waits as it is. */
        int policy;
        struct sched_param sp;
        if (w->own_thread && pthread_getschedparam(pthread_self(), &policy, &sp) == 0 &&
            pthread_setschedparam(w->thread, policy, &sp) == 0) {
            w->lent = true;
        }
        const double w0 = mono_ms();
        while (w->running) {
            pthread_cond_wait(&w->cond, &w->lock);
        }
        wait_ms = mono_ms() - w0;
    }
    const int rc = w->rc;
    if (st) {
        *st = w->st;
    }
    if (times) {
        times->step_ms = w->step_ms;
        times->wait_ms = wait_ms;
    }
    w->rc = 0;
    w->st = (wind_step_stats){ 0 };
    w->step_ms = 0.0;
    pthread_mutex_unlock(&w->lock);
    if (times) {
        times->ms = mono_ms() - t0;
    }
    return rc;
}
