/* The state encoders' lanes (wire.h wire_lanes) on the simulation's OpenMP threads: more
 * lanes than threads, taken as threads come free, so a thread descheduled on a busy
 * machine does not hold the frame back by a whole share. */
#ifndef GALE_SIM_LANES_H
#define GALE_SIM_LANES_H

#include "wire.h"

/* Lanes for n_threads threads (1: one lane on the caller's thread). */
wire_lanes sim_lanes(int n_threads);

#endif
