/* The state encoders' lanes (wire.h wire_lanes) on the tick's team (sim_team.h): more
 * lanes than threads, taken as threads come free, so a thread descheduled on a busy
 * machine does not hold the frame back by a whole share; and the shares of the tick's
 * loops over the crowns. */
#ifndef GALE_SIM_LANES_H
#define GALE_SIM_LANES_H

#include "wire.h"

/* Lanes for n_threads threads (1: one lane on the caller's thread). */
wire_lanes sim_lanes(int n_threads);

/* Shares of n independent items for a loop over n_threads threads: enough that none
 * holds more than SIM_SHARE_MAX items, and a multiple of the threads, so that each
 * thread gets as many when none is held up. At least 1. */
#define SIM_SHARE_MAX 4096
int sim_shares(int n, int n_threads);

/* Share k of n items cut into `shares` (sim_shares): items [*i0, *i1), the shares' sizes
 * differing by one at most (empty only when there are fewer items than shares). */
void sim_share(int n, int shares, int k, int *i0, int *i1);

#endif
