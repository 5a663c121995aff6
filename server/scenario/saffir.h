/* Wind classes for the HUD: the Saffir–Simpson hurricane wind scale (1-minute sustained
 * wind at 10 m, classified in knots, NHC; REFERENCE.md "Hurricanes") and, for winds below
 * tropical-storm force, the Beaufort scale (WMO No. 8). */
#ifndef GALE_SAFFIR_H
#define GALE_SAFFIR_H

#define SAFFIR_MS_PER_KT 0.514444 /* 1 kt = 1852 m / 3600 s */

typedef enum saffir_class {
    SAFFIR_TD = 0,   /* tropical depression, ≤ 33 kt */
    SAFFIR_TS = 1,   /* tropical storm, 34–63 kt */
    SAFFIR_CAT1 = 2, /* 64–82 kt */
    SAFFIR_CAT2 = 3, /* 83–95 kt */
    SAFFIR_CAT3 = 4, /* 96–112 kt */
    SAFFIR_CAT4 = 5, /* 113–136 kt */
    SAFFIR_CAT5 = 6, /* ≥ 137 kt */
    SAFFIR_COUNT = 7
} saffir_class;

/* The class of a 1-minute sustained 10 m wind [m/s]: converted to knots, rounded to the
 * nearest knot (NHC reports whole knots), then looked up in the table. Negative or NaN
 * speeds count as 0. */
saffir_class saffir_classify(double sustained_ms);
/* "tropical depression", "tropical storm", "Category 1" ... "Category 5"; "?" out of range. */
const char *saffir_name(saffir_class c);
/* Short HUD label: "TD", "TS", "Cat 1" ... "Cat 5"; "?" out of range. */
const char *saffir_short(saffir_class c);
/* A representative sustained wind [m/s] inside the class (the middle of its knot range;
 * 150 kt for Category 5), for a kiosk that picks a category. -1 for an invalid class. */
double saffir_representative_ms(saffir_class c);
/* Lowest sustained wind [m/s] that classifies as c (0 for TD). -1 for an invalid class. */
double saffir_lower_ms(saffir_class c);

/* Beaufort number 0..12 of a 10 m mean wind [m/s] (WMO upper limits 0.2, 1.5, 3.3, 5.4,
 * 7.9, 10.7, 13.8, 17.1, 20.7, 24.4, 28.4, 32.6 m/s). */
int saffir_beaufort(double ms);
/* "calm", "light air", ... "hurricane force"; "?" out of range. */
const char *saffir_beaufort_name(int b);

#endif
