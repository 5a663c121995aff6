/* A fallen tree tipping over: see tip_fall.h. */
#include "tip_fall.h"

#include <math.h>

#include "hash.h"

static double omega(double height_m)
{
    return sqrt(1.5 * TIP_FALL_G_MS2 / (height_m > 0.5 ? height_m : 0.5));
}

double tip_fall_angle(double t_s, double height_m)
{
    if (!(t_s > 0.0)) {
        return 0.0;
    }
    double e = omega(height_m) * t_s;
    if (e > 40.0) {
        return TIP_FALL_LYING_RAD; /* long lying; e^40 stays finite but means nothing */
    }
    double th = 4.0 * atan(tan(0.25 * TIP_FALL_LEAN0_RAD) * exp(e));
    return th < TIP_FALL_LYING_RAD ? th : TIP_FALL_LYING_RAD;
}

double tip_fall_duration_s(double height_m)
{
    /* the closed form solved for t at the lying angle */
    return log(tan(0.25 * TIP_FALL_LYING_RAD) / tan(0.25 * TIP_FALL_LEAN0_RAD)) / omega(height_m);
}


float tip_fall_break_m(uint32_t tree)
{
    const float u = (float)(hash_mix32(tree * 2246822519u + 374761393u) >> 8) * (1.0f / 16777216.0f);
    return TIP_FALL_BREAK_MIN_M + TIP_FALL_BREAK_SPAN_M * u;
}
