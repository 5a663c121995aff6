/* The server's wind classes: names and bounds from protocol/wind_scale.h; what is the
 * server's own is the wind a kiosk's category dial holds. */
#include "saffir.h"

/* Middle of each class's knot range; 25 kt for TD and 150 kt for the open-ended
 * Category 5, speeds well inside them. */
static const double mid_kt[SAFFIR_COUNT] = { 25.0, 48.5, 73.0, 89.0, 104.0, 124.5, 150.0 };

saffir_class saffir_classify(double sustained_ms)
{
    return (saffir_class)wind_scale_ss_class(sustained_ms);
}

const char *saffir_name(saffir_class c)
{
    return wind_scale_ss_name((int)c);
}

const char *saffir_short(saffir_class c)
{
    return wind_scale_ss_abbrev((int)c);
}

double saffir_representative_ms(saffir_class c)
{
    return (c >= 0 && c < SAFFIR_COUNT) ? mid_kt[c] * SAFFIR_MS_PER_KT : -1.0;
}

double saffir_lower_ms(saffir_class c)
{
    return wind_scale_ss_lower_ms((int)c);
}

int saffir_beaufort(double ms)
{
    return wind_scale_beaufort(ms);
}

const char *saffir_beaufort_name(int b)
{
    return wind_scale_beaufort_name(b);
}
