/* Saffir–Simpson and Beaufort classes of a 10 m wind: see saffir.h and REFERENCE.md
 * "Hurricanes" (the NHC table in knots). */
#include "saffir.h"

#include <math.h>

/* Lowest whole knot of each class (NHC): TD 0, TS 34, Cat 1 64, 2 83, 3 96, 4 113, 5 137. */
static const int lower_kt[SAFFIR_COUNT] = { 0, 34, 64, 83, 96, 113, 137 };
/* Middle of each class's knot range; 150 kt for the open-ended Category 5. */
static const double mid_kt[SAFFIR_COUNT] = { 25.0, 48.5, 73.0, 89.0, 104.0, 124.5, 150.0 };
static const char *const names[SAFFIR_COUNT] = {
    "tropical depression", "tropical storm", "Category 1", "Category 2",
    "Category 3",          "Category 4",     "Category 5",
};
static const char *const shorts[SAFFIR_COUNT] = { "TD",    "TS",    "Cat 1", "Cat 2",
                                                  "Cat 3", "Cat 4", "Cat 5" };

saffir_class saffir_classify(double sustained_ms)
{
    if (!(sustained_ms > 0.0)) {
        return SAFFIR_TD;
    }
    double kt = floor(sustained_ms / SAFFIR_MS_PER_KT + 0.5);
    saffir_class c = SAFFIR_TD;
    for (int i = 1; i < SAFFIR_COUNT; i++) {
        if (kt >= lower_kt[i]) {
            c = (saffir_class)i;
        }
    }
    return c;
}

const char *saffir_name(saffir_class c)
{
    return (c >= 0 && c < SAFFIR_COUNT) ? names[c] : "?";
}

const char *saffir_short(saffir_class c)
{
    return (c >= 0 && c < SAFFIR_COUNT) ? shorts[c] : "?";
}

double saffir_representative_ms(saffir_class c)
{
    return (c >= 0 && c < SAFFIR_COUNT) ? mid_kt[c] * SAFFIR_MS_PER_KT : -1.0;
}

double saffir_lower_ms(saffir_class c)
{
    /* rounding to the nearest knot: half a knot below the class's first whole knot */
    if (c < 0 || c >= SAFFIR_COUNT) {
        return -1.0;
    }
    return c == SAFFIR_TD ? 0.0 : (lower_kt[c] - 0.5) * SAFFIR_MS_PER_KT;
}

/* WMO No. 8 Beaufort upper limits [m/s] of forces 0..11; force 12 above the last. */
static const double beaufort_upper[12] = { 0.2,  1.5,  3.3,  5.4,  7.9,  10.7,
                                           13.8, 17.1, 20.7, 24.4, 28.4, 32.6 };
static const char *const beaufort_names[13] = {
    "calm",         "light air",     "light breeze",    "gentle breeze", "moderate breeze",
    "fresh breeze", "strong breeze", "near gale",       "gale",          "strong gale",
    "storm",        "violent storm", "hurricane force",
};

int saffir_beaufort(double ms)
{
    if (!(ms > 0.0)) {
        return 0;
    }
    /* the WMO limits are given to 0.1 m/s: a speed belongs to the first force whose
     * upper limit it does not exceed after rounding to 0.1 m/s */
    double r = floor(ms * 10.0 + 0.5) / 10.0;
    for (int b = 0; b < 12; b++) {
        if (r <= beaufort_upper[b] + 1e-9) {
            return b;
        }
    }
    return 12;
}

const char *saffir_beaufort_name(int b)
{
    return (b >= 0 && b <= 12) ? beaufort_names[b] : "?";
}
