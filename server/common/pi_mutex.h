/* Mutexes shared by the ticks' real-time threads and the server's other threads (the wind
 * step beside the ticks, the network and view threads, the control messages). A tick that
 * blocks on a lock held by a thread at the fair scheduler's priority waits for as long as
 * the busy programs beside it keep that thread off a CPU: tens of milliseconds on two
 * cores shared with compilers, where the holder needed microseconds (server/SERVER.md
 * "Loop"). With priority inheritance the holder runs at the waiting tick's priority until
 * it lets go. */
#ifndef GALE_PI_MUTEX_H
#define GALE_PI_MUTEX_H

#include <pthread.h>

/* pthread_mutex_init with PTHREAD_PRIO_INHERIT; a plain mutex where the system refuses
 * the protocol (the lock works the same, without the boost). Returns pthread_mutex_init's
 * code. */
int pi_mutex_init(pthread_mutex_t *m);

#endif
