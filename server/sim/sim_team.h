/* The tick's thread team: the threads its parallel phases (the crowns' reads, the modal
 * update, leaf shedding, the damage step, the encoders' lanes) run on, and their
 * scheduling policy.
 *
 * A phase is n independent jobs taken one at a time, as threads come free, by the caller
 * and its helpers. The caller waits only for jobs a helper has taken: a helper that has
 * not woken by the time the jobs run out takes none and holds nothing up. On a virtual
 * machine a helper woken on an idle vCPU can start 4-16 ms late (the host runs the vCPU
 * again only then), so a fork-join team (OpenMP's, whose region ends when every thread
 * of the team has reached it) waited that long with its work done; here the caller does
 * the phase alone instead, at worst at one thread's speed. Helpers spin a short while
 * after a phase before they sleep, so a tick's phases after the first find them awake.
 *
 * Each calling thread has a team of its own (started on its first parallel call, grown
 * to the most threads asked for, stopped when the thread ends). Jobs must not call
 * sim_team_run themselves. */
#ifndef GALE_SIM_TEAM_H
#define GALE_SIM_TEAM_H

#include "err.h"

/* Most threads a team runs (the caller and 63 helpers). */
#define SIM_TEAM_MAX_THREADS 64

typedef void (*sim_job_fn)(void *ctx, int job);

/* Runs fn(ctx, k) for every k in [0, n) exactly once, on the calling thread and up to
 * n_threads - 1 helpers (n_threads <= 1, or n <= 1: on the caller alone); returns when
 * every job has returned. Which thread runs which job is not fixed, so jobs write
 * disjoint results. Where a helper cannot be started the caller runs what it would have. */
void sim_team_run(int n_threads, int n, sim_job_fn fn, void *ctx);

/* Puts the calling thread and the n_threads - 1 helpers of its team at SCHED_FIFO
 * `priority` [1, 99], or back to SCHED_OTHER at priority 0; helpers the team starts
 * later inherit it. Fails with err filled (naming the priority and how it could be
 * allowed) where the system does not permit it: then every thread keeps its policy.
 * Call it from the thread that runs the ticks, between ticks. */
int sim_team_set_priority(int n_threads, int priority, gale_err *err);

#endif
