/* Storm damage event times: see damage_clock.h. */
#include "damage_clock.h"

#include <math.h>

double damage_event_start_s(uint32_t frame_tick, uint64_t frame_time_us, uint32_t event_tick,
                            double tick_hz)
{
    double hz = tick_hz > 0.0 ? tick_hz : 60.0;
    /* ticks wrap at 2^32: the signed difference is the age */
    double age_s = (double)(int32_t)(frame_tick - event_tick) / hz;
    age_s = age_s > 0.0 ? age_s : 0.0;
    return age_s <= DAMAGE_RECENT_S ? (double)frame_time_us * 1e-6 - age_s : (double)NAN;
}
