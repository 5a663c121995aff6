/* The wind step on its own thread: see wind_worker.h. */
#include "wind_worker.h"
#include "mono.h"

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
    double step_ms; /* the last step's wall time */
    int rc;
    wind_step_stats st;
};

static void *worker_main(void *arg)
{
    wind_worker *w = arg;
    /* SCHED_IDLE: the step takes a core only while nothing else wants it, and a tick
     * thread that wakes preempts it at once (a niced thread keeps the core to the end of
     * its slice, holding up a tick's parallel region behind it). Lowering one's own
     * policy needs no privilege; where it fails the step runs at the tick's. */
    (void)pthread_setschedparam(pthread_self(), SCHED_IDLE, &(struct sched_param){ 0 });
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
        pthread_mutex_unlock(&w->lock);
        wind_step_stats st = { 0 };
        const double t0 = mono_ms();
        const int rc = w->step(w->ctx, dt_s, &st);
        const double step_ms = mono_ms() - t0;
        pthread_mutex_lock(&w->lock);
        w->step_ms = step_ms;
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
    pthread_mutex_init(&w->lock, NULL);
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
    pthread_mutex_lock(&w->lock);
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
