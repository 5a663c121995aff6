/* When a storm damage event happened on the server clock, and whether it is recent
 * enough to animate (PROTOCOL.md "DAMAGE": "a client animates a fall only when it is
 * recent"). Plain C. */
#ifndef GALE_DAMAGE_CLOCK_H
#define GALE_DAMAGE_CLOCK_H

#include <stdint.h>

#define DAMAGE_RECENT_S 3.0 /* older events show their end state: lying, gone */

/* The server time [s] of an event of tick event_tick carried by a frame of tick
 * frame_tick encoded at frame_time_us (the frame header's server_time_us), at tick_hz;
 * NaN when it is older than DAMAGE_RECENT_S. An event stamped after its frame counts as
 * the frame's instant. */
double damage_event_start_s(uint32_t frame_tick, uint64_t frame_time_us, uint32_t event_tick,
                            double tick_hz);

#endif
