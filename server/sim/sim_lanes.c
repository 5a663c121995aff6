/* The encoders' lanes and the tick's shares on the tick's team: see sim_lanes.h. */
#include "sim_lanes.h"
#include "sim_team.h"

#include <stdint.h>

/* Lanes per thread: 4 shares each balance a thread that loses its core for part of the
 * frame at the cost of one more move of a share's bytes (a memmove, ~0.1 ns a byte). */
#define LANES_PER_THREAD 4

static void run_team(void *ctx, int n, wire_lane_fn job, void *arg)
{
    sim_team_run((int)(intptr_t)ctx, n, job, arg);
}

wire_lanes sim_lanes(int n_threads)
{
    if (n_threads <= 1) {
        return (wire_lanes){ .n = 1 };
    }
    int n = n_threads * LANES_PER_THREAD;
    n = n > (int)WIRE_MAX_LANES ? (int)WIRE_MAX_LANES : n;
    return (wire_lanes){ .n = n, .run = run_team, .ctx = (void *)(intptr_t)n_threads };
}

int sim_shares(int n, int n_threads)
{
    const int threads = n_threads > 1 ? n_threads : 1;
    const int by_size = n > 0 ? (n + SIM_SHARE_MAX - 1) / SIM_SHARE_MAX : 1;
    return (by_size + threads - 1) / threads * threads;
}

void sim_share(int n, int shares, int k, int *i0, int *i1)
{
    *i0 = (int)((int64_t)n * k / shares);
    *i1 = (int)((int64_t)n * (k + 1) / shares);
}
