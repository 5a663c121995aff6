/* The monotonic clock gale measures with: CLOCK_MONOTONIC, the base of every frame
 * header's server_time_us (PROTOCOL.md), of the tick schedule and of every duration the
 * programs and benchmarks report. One reading, four units. */
#ifndef GALE_MONO_H
#define GALE_MONO_H

#include <stdint.h>
#include <time.h>

/* Nanoseconds since an arbitrary fixed point (boot); never goes backwards. */
static inline uint64_t mono_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000ull + (uint64_t)t.tv_nsec;
}

/* Microseconds on the same clock (the wire's server_time_us unit). */
static inline uint64_t mono_us(void)
{
    return mono_ns() / 1000u;
}

/* Milliseconds on the same clock, as a double for durations. */
static inline double mono_ms(void)
{
    return (double)mono_ns() * 1e-6;
}

/* Seconds on the same clock, as a double for durations. */
static inline double mono_s(void)
{
    return (double)mono_ns() * 1e-9;
}

#endif
