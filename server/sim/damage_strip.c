/* Leaf stripping by gusts: see damage_strip.h. */
#include "damage_strip.h"

#include <math.h>

float damage_strip_target(float gust_ms, float strip_max)
{
    float x = (gust_ms - DAMAGE_STRIP_START_MS) / (DAMAGE_STRIP_FULL_MS - DAMAGE_STRIP_START_MS);
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return 1.0f - strip_max * x * x * (3.0f - 2.0f * x);
}

float damage_strip_decay(float dt_s)
{
    return expf(-dt_s / DAMAGE_STRIP_TAU_S);
}

float damage_strip_step(float leaf, float gust_ms, float strip_max, float decay)
{
    float target = damage_strip_target(gust_ms, strip_max);
    if (!(leaf > target)) {
        return leaf;
    }
    return target + (leaf - target) * decay;
}
