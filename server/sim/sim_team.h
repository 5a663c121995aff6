/* The tick's OpenMP threads' scheduling policy. A tick's parallel phases (the modal
 * update, the damage step) wait for their slowest thread, so a thread that loses its core
 * for one scheduler tick (4 ms at HZ 250) doubles the phase: under the kernel's fair
 * scheduler even a SCHED_IDLE task (the wind step beside the ticks, or anything else on
 * the machine) is given the core now and then. At a real-time priority the tick's threads
 * take their core whenever they run, and leave it when they wait (the server's OpenMP
 * threads wait passively), so the fair tasks keep every moment between the ticks. */
#ifndef GALE_SIM_TEAM_H
#define GALE_SIM_TEAM_H

#include "err.h"

/* Puts the calling thread and the n_threads − 1 OpenMP threads of its parallel regions
 * at SCHED_FIFO `priority` [1, 99], or back to SCHED_OTHER at priority 0; threads the
 * team starts later inherit it. Fails with err filled (naming the priority and how it
 * could be allowed) where the system does not permit it: then every thread keeps its
 * policy. Call it from the thread that runs the ticks, between ticks. */
int sim_team_set_priority(int n_threads, int priority, gale_err *err);

#endif
