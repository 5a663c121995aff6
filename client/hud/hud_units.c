/* The numbers a visitor reads of a wind (hud.h "units"): whole mph, km/h, knots and m/s,
 * each kept inside the range NHC's Saffir-Simpson table gives the shown class in that
 * unit, so a number never contradicts the category beside it. The class is set by the
 * knots (protocol/wind_scale.h); converting to another unit and rounding on its own can
 * cross the table's edge in that unit: 96 kt is 110.5 mph, shown "110 mph" it would read
 * as Category 2 in NHC's mph column, and 136 kt, 156.5 mph, would read "157 mph",
 * Category 5. Rounded first, the value is then moved to the nearest end of its class's
 * range: by at most 1 mph, 1 km/h or 1 m/s (tests/test_hud_units.c, every 0.1 kt). */
#include "hud.h"

#include <math.h>
#include <stdio.h>

#include "lang.h"
#include "wind_scale.h"

#define MS_PER_MPH 0.44704 /* 1 mph = 1609.344 m / 3600 s */
#define KMH_PER_MS 3.6

/* NHC's table (www.nhc.noaa.gov/aboutsshws.php), lowest whole value of each class in
 * each unit, wind_scale.h numbering (tropical depression .. Category 5); the highest is
 * the next class's lowest - 1, except m/s, where NHC's rounding gives 58 to both
 * Category 3 (50-58) and 4 (58-70), and 70 to both 4 and 5 (>= 70). */
static const long class_lo[HUD_UNIT_COUNT][WIND_SCALE_SS_COUNT] = {
    [HUD_UNIT_MPH] = { 0, 39, 74, 96, 111, 130, 157 },
    [HUD_UNIT_KMH] = { 0, 63, 119, 154, 178, 209, 252 },
    [HUD_UNIT_KT] = { 0, 34, 64, 83, 96, 113, 137 },
    [HUD_UNIT_MS] = { 0, 18, 33, 43, 50, 58, 70 },
};
static const long ms_hi[WIND_SCALE_SS_COUNT] = { 17, 32, 42, 49, 58, 70, HUD_UNIT_NO_TOP };

double hud_unit_value(double ms, int unit)
{
    switch (unit) {
    case HUD_UNIT_MPH:
        return ms / MS_PER_MPH;
    case HUD_UNIT_KMH:
        return ms * KMH_PER_MS;
    case HUD_UNIT_KT:
        return ms / WIND_SCALE_MS_PER_KT;
    default:
        return ms;
    }
}

long hud_unit_round(double ms, int unit)
{
    double v = hud_unit_value(ms, unit);
    /* half up, the same as web/hud_text.js's Math.floor(v + 0.5) */
    return isfinite(v) && v > 0.0 ? (long)floor(v + 0.5) : 0;
}

int hud_unit_range(int ss_class, int unit, long *lo, long *hi)
{
    if (ss_class < 0 || ss_class >= WIND_SCALE_SS_COUNT || unit < 0 || unit >= HUD_UNIT_COUNT) {
        return -1;
    }
    *lo = class_lo[unit][ss_class];
    if (unit == HUD_UNIT_MS) {
        *hi = ms_hi[ss_class];
    } else {
        *hi = ss_class + 1 < WIND_SCALE_SS_COUNT ? class_lo[unit][ss_class + 1] - 1
                                                 : HUD_UNIT_NO_TOP;
    }
    return 0;
}

long hud_unit_sustained(double ms, int unit, int ss_class)
{
    long v = hud_unit_round(ms, unit), lo, hi;
    if (hud_unit_range(ss_class, unit, &lo, &hi) != 0) {
        return v;
    }
    return v < lo ? lo : v > hi ? hi : v;
}

int hud_format_speed(int lang, double ms, int ss_class, char *out, size_t cap)
{
    char first[48], second[48];
    long mph = ss_class >= 0 ? hud_unit_sustained(ms, HUD_UNIT_MPH, ss_class)
                             : hud_unit_round(ms, HUD_UNIT_MPH);
    long kmh = ss_class >= 0 ? hud_unit_sustained(ms, HUD_UNIT_KMH, ss_class)
                             : hud_unit_round(ms, HUD_UNIT_KMH);
    if (lang_kmh_first(lang)) {
        lang_format(first, sizeof first, lang, L_UNIT_KMH, (int)kmh);
        lang_format(second, sizeof second, lang, L_UNIT_MPH, (int)mph);
    } else {
        lang_format(first, sizeof first, lang, L_UNIT_MPH, (int)mph);
        lang_format(second, sizeof second, lang, L_UNIT_KMH, (int)kmh);
    }
    return snprintf(out, cap, "%s \xC2\xB7 %s", first, second);
}

int hud_format_speed_first(int lang, double ms, char *out, size_t cap)
{
    return lang_kmh_first(lang)
               ? lang_format(out, cap, lang, L_UNIT_KMH, (int)hud_unit_round(ms, HUD_UNIT_KMH))
               : lang_format(out, cap, lang, L_UNIT_MPH, (int)hud_unit_round(ms, HUD_UNIT_MPH));
}
