/* The server's view of the wind scales (protocol/wind_scale.h holds the one table): the
 * Saffir-Simpson class of the scenario's sustained wind, its names, the Beaufort force
 * below tropical-storm strength, and the representative wind a kiosk dials for a class. */
#ifndef GALE_SAFFIR_H
#define GALE_SAFFIR_H

#include "wind_scale.h"

#define SAFFIR_MS_PER_KT WIND_SCALE_MS_PER_KT

/* The classes of wind_scale.h, numbered as there (0 = tropical depression). */
typedef enum saffir_class {
    SAFFIR_TD = WIND_SCALE_TD,     /* tropical depression, <= 33 kt */
    SAFFIR_TS = WIND_SCALE_TS,     /* tropical storm, 34-63 kt */
    SAFFIR_CAT1 = WIND_SCALE_CAT1, /* 64-82 kt */
    SAFFIR_CAT2 = WIND_SCALE_CAT2, /* 83-95 kt */
    SAFFIR_CAT3 = WIND_SCALE_CAT3, /* 96-112 kt */
    SAFFIR_CAT4 = WIND_SCALE_CAT4, /* 113-136 kt */
    SAFFIR_CAT5 = WIND_SCALE_CAT5, /* >= 137 kt */
    SAFFIR_COUNT = WIND_SCALE_SS_COUNT
} saffir_class;

/* The class of a 1-minute sustained 10 m wind [m/s] (wind_scale_ss_class: rounded to the
 * nearest knot first). Negative or NaN speeds count as 0. */
saffir_class saffir_classify(double sustained_ms);
/* "tropical depression", "tropical storm", "Category 1" ... "Category 5"; "?" out of range. */
const char *saffir_name(saffir_class c);
/* Short label: "TD", "TS", "Cat 1" ... "Cat 5"; "?" out of range. */
const char *saffir_short(saffir_class c);
/* A representative sustained wind [m/s] inside the class (the middle of its knot range;
 * 25 kt for TD, 150 kt for the open-ended Category 5), for a kiosk that picks a
 * category. -1 for an invalid class. */
double saffir_representative_ms(saffir_class c);
/* Lowest sustained wind [m/s] that classifies as c (0 for TD). -1 for an invalid class. */
double saffir_lower_ms(saffir_class c);

/* Beaufort number 0..12 of a 10 m mean wind [m/s] (wind_scale_beaufort). */
int saffir_beaufort(double ms);
/* "calm", "light air", ... "hurricane force"; "?" out of range. */
const char *saffir_beaufort_name(int b);

#endif
