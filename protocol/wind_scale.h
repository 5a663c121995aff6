/* The wind scales a person reads a speed by, one table for server and client: the
 * Saffir-Simpson hurricane wind scale (NHC, 1-minute sustained wind at 10 m, classified in
 * whole knots) and, below tropical-storm force, the Beaufort
 * scale (WMO No. 8, 10 m mean wind, limits in tenths of m/s). */
#ifndef GALE_WIND_SCALE_H
#define GALE_WIND_SCALE_H

#define WIND_SCALE_MS_PER_KT 0.514444 /* 1 kt = 1852 m / 3600 s */

/* Saffir-Simpson classes, numbered from 0 upwards with the wind: a hurricane's category
 * number is its class - 1 (WIND_SCALE_CAT3 - 1 == 3). The HUD counts the same classes
 * from tropical storm = 0 (client/hud/hud.h hud_saffir_simpson). */
enum wind_scale_ss {
    WIND_SCALE_TD = 0,   /* tropical depression, <= 33 kt */
    WIND_SCALE_TS = 1,   /* tropical storm, 34-63 kt */
    WIND_SCALE_CAT1 = 2, /* 64-82 kt */
    WIND_SCALE_CAT2 = 3, /* 83-95 kt */
    WIND_SCALE_CAT3 = 4, /* 96-112 kt */
    WIND_SCALE_CAT4 = 5, /* 113-136 kt */
    WIND_SCALE_CAT5 = 6, /* >= 137 kt */
    WIND_SCALE_SS_COUNT = 7
};

/* Class of a 1-minute sustained 10 m wind [m/s]: converted to knots and rounded to the
 * nearest knot (NHC reports whole knots), then looked up. Negative or NaN:
 * WIND_SCALE_TD. */
int wind_scale_ss_class(double sustained_ms);
/* Lowest sustained wind [m/s] that classifies as c: half a knot below its first whole
 * knot (0 for TD); -1 for a class outside [0, WIND_SCALE_SS_COUNT). */
double wind_scale_ss_lower_ms(int c);
/* Names of class c, "?" outside [0, WIND_SCALE_SS_COUNT); static strings. name: as in
 * running text ("tropical depression", "Category 3"); title: as a line of its own
 * ("Tropical depression", "Category 3 hurricane"); abbrev: a short label ("TD", "Cat 3"). */
const char *wind_scale_ss_name(int c);
const char *wind_scale_ss_title(int c);
const char *wind_scale_ss_abbrev(int c);

/* Beaufort force 0..12 of a 10 m mean wind [m/s]: rounded to 0.1 m/s, the first force
 * whose WMO upper limit (0.2, 1.5, 3.3, 5.4, 7.9, 10.7, 13.8, 17.1, 20.7, 24.4, 28.4,
 * 32.6 m/s for forces 0..11) it does not exceed, 12 above. Negative or NaN: 0. */
int wind_scale_beaufort(double ms);
/* Lowest 10 m mean wind [m/s] of force b: half a tenth above force b - 1's upper limit
 * (the rounding to 0.1 m/s above; 0 for force 0); -1 for b outside 0..12. */
double wind_scale_beaufort_lower_ms(int b);
/* Names of force b, "?" outside 0..12; static strings. name: running text ("strong
 * breeze"); title: a line of its own ("Strong breeze"). */
const char *wind_scale_beaufort_name(int b);
const char *wind_scale_beaufort_title(int b);

#endif
