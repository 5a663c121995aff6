/* The Saffir-Simpson and Beaufort tables: see wind_scale.h. Each class is one row, so its
 * bounds and its names cannot drift apart. */
#include "wind_scale.h"

#include <math.h>

typedef struct ss_row {
    int lower_kt;       /* lowest whole knot of the class (NHC) */
    const char *name;   /* running text */
    const char *title;  /* a line of its own */
    const char *abbrev; /* short label */
} ss_row;

static const ss_row ss_table[WIND_SCALE_SS_COUNT] = {
    { 0, "tropical depression", "Tropical depression", "TD" },
    { 34, "tropical storm", "Tropical storm", "TS" },
    { 64, "Category 1", "Category 1 hurricane", "Cat 1" },
    { 83, "Category 2", "Category 2 hurricane", "Cat 2" },
    { 96, "Category 3", "Category 3 hurricane", "Cat 3" },
    { 113, "Category 4", "Category 4 hurricane", "Cat 4" },
    { 137, "Category 5", "Category 5 hurricane", "Cat 5" },
};

typedef struct bft_row {
    int upper_dms;     /* WMO upper limit [0.1 m/s]; force 12 has none */
    const char *name;  /* running text */
    const char *title; /* a line of its own */
} bft_row;

#define BFT_FORCES 13

static const bft_row bft_table[BFT_FORCES] = {
    { 2, "calm", "Calm" },
    { 15, "light air", "Light air" },
    { 33, "light breeze", "Light breeze" },
    { 54, "gentle breeze", "Gentle breeze" },
    { 79, "moderate breeze", "Moderate breeze" },
    { 107, "fresh breeze", "Fresh breeze" },
    { 138, "strong breeze", "Strong breeze" },
    { 171, "near gale", "Near gale" },
    { 207, "gale", "Gale" },
    { 244, "strong gale", "Strong gale" },
    { 284, "storm", "Storm" },
    { 326, "violent storm", "Violent storm" },
    { 0, "hurricane force", "Hurricane force" },
};

static int ss_valid(int c)
{
    return c >= 0 && c < WIND_SCALE_SS_COUNT;
}

int wind_scale_ss_class(double sustained_ms)
{
    if (!(sustained_ms > 0.0)) {
        return WIND_SCALE_TD;
    }
    double kt = floor(sustained_ms / WIND_SCALE_MS_PER_KT + 0.5);
    int c = WIND_SCALE_TD;
    for (int i = 1; i < WIND_SCALE_SS_COUNT; i++) {
        if (kt >= ss_table[i].lower_kt) {
            c = i;
        }
    }
    return c;
}

double wind_scale_ss_lower_ms(int c)
{
    if (!ss_valid(c)) {
        return -1.0;
    }
    /* rounding to the nearest knot: half a knot below the class's first whole knot */
    return c == WIND_SCALE_TD ? 0.0 : (ss_table[c].lower_kt - 0.5) * WIND_SCALE_MS_PER_KT;
}

const char *wind_scale_ss_name(int c)
{
    return ss_valid(c) ? ss_table[c].name : "?";
}

const char *wind_scale_ss_title(int c)
{
    return ss_valid(c) ? ss_table[c].title : "?";
}

const char *wind_scale_ss_abbrev(int c)
{
    return ss_valid(c) ? ss_table[c].abbrev : "?";
}

int wind_scale_beaufort(double ms)
{
    if (!(ms > 0.0)) {
        return 0;
    }
    /* Past the last limit by far: force 12 without converting a huge value to int. */
    if (ms > 1000.0) {
        return BFT_FORCES - 1;
    }
    /* the WMO limits are given to 0.1 m/s: a speed belongs to the first force whose
     * upper limit it does not exceed after rounding to 0.1 m/s */
    int dms = (int)floor(ms * 10.0 + 0.5);
    for (int b = 0; b < BFT_FORCES - 1; b++) {
        if (dms <= bft_table[b].upper_dms) {
            return b;
        }
    }
    return BFT_FORCES - 1;
}

double wind_scale_beaufort_lower_ms(int b)
{
    if (b < 0 || b >= BFT_FORCES) {
        return -1.0;
    }
    return b == 0 ? 0.0 : (bft_table[b - 1].upper_dms + 0.5) * 0.1;
}

const char *wind_scale_beaufort_name(int b)
{
    return b >= 0 && b < BFT_FORCES ? bft_table[b].name : "?";
}

const char *wind_scale_beaufort_title(int b)
{
    return b >= 0 && b < BFT_FORCES ? bft_table[b].title : "?";
}
