/* Weather to storm look (storm_fx.h): the calm colours are the renderer's clear day; with
 * intensity they move towards an overcast storm grey, the sun dims and the fog closes in. */
#include "storm_fx.h"

#include <math.h>
#include <string.h>

static const float calm_sun[3] = { 1.05f, 0.97f, 0.86f };
static const float calm_zenith[3] = { 0.30f, 0.50f, 0.82f };
static const float calm_horizon[3] = { 0.74f, 0.82f, 0.90f };
static const float calm_ground[3] = { 0.30f, 0.40f, 0.17f };
/* the darkest storm: a grey cloud deck, a paler horizon in rain, light through thick cloud.
 * The deck overhead stays lighter than wet foliage under it (ambient 0.55 of it), so a
 * crown seen from the street is a dark shape on a grey sky, as under a real overcast,
 * where the sky is brightest overhead (CIE standard overcast sky: zenith about three
 * times the horizon; here the rain's veil lifts the horizon). */
static const float storm_sun[3] = { 0.22f, 0.23f, 0.25f };
static const float storm_zenith[3] = { 0.30f, 0.32f, 0.35f };
static const float storm_horizon[3] = { 0.40f, 0.42f, 0.44f };
static const float storm_ground[3] = { 0.20f, 0.25f, 0.14f };
/* fog distance at full intensity: a fraction of the clear day's (heavy rain cuts visibility
 * to a few hundred metres) */
static const float storm_fog_scale = 0.18f;

void storm_fx_calm(storm_fx *fx)
{
    memset(fx, 0, sizeof *fx);
    memcpy(fx->sun_col, calm_sun, sizeof calm_sun);
    memcpy(fx->sky_zenith, calm_zenith, sizeof calm_zenith);
    memcpy(fx->sky_horizon, calm_horizon, sizeof calm_horizon);
    memcpy(fx->ground_col, calm_ground, sizeof calm_ground);
    fx->fog_scale = 1.0f;
}

static float clamp01(float x)
{
    return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
}

static void mix3(const float a[3], const float b[3], float t, float out[3])
{
    for (int k = 0; k < 3; k++) {
        out[k] = a[k] + (b[k] - a[k]) * t;
    }
}

void storm_fx_from_weather(float sustained_ms, float dir_from_deg, storm_fx_quality q, storm_fx *fx)
{
    storm_fx_calm(fx);
    if (q == STORM_FX_OFF || !(sustained_ms > STORM_FX_DARK_FROM_MS)) {
        return; /* NaN too: calm */
    }
    float x = clamp01((sustained_ms - STORM_FX_DARK_FROM_MS) /
                      (STORM_FX_DARK_FULL_MS - STORM_FX_DARK_FROM_MS));
    /* eased so a gale already reads grey and the major hurricanes keep getting darker */
    float i = sqrtf(x);
    fx->intensity = i;
    mix3(calm_sun, storm_sun, i, fx->sun_col);
    mix3(calm_zenith, storm_zenith, i, fx->sky_zenith);
    mix3(calm_horizon, storm_horizon, i, fx->sky_horizon);
    mix3(calm_ground, storm_ground, i, fx->ground_col);
    fx->fog_scale = 1.0f + (storm_fog_scale - 1.0f) * i;
    fx->wet = i;
    fx->subject_clear = STORM_FX_SUBJECT_CLEAR;
    /* where the wind goes: opposite to where it comes from */
    float to = (dir_from_deg + 180.0f) * 0.017453293f;
    float s = sustained_ms > 200.0f ? 200.0f : sustained_ms;
    fx->wind_to[0] = s * sinf(to);
    fx->wind_to[1] = s * cosf(to);
    if (sustained_ms >= STORM_FX_RAIN_FROM_MS) {
        fx->rain = 0.25f + 0.75f * clamp01((sustained_ms - STORM_FX_RAIN_FROM_MS) /
                                           (STORM_FX_DARK_FULL_MS - STORM_FX_RAIN_FROM_MS));
        fx->rain_layers = q == STORM_FX_HIGH ? 3 : 1;
    }
    if (sustained_ms >= STORM_FX_SPRAY_FROM_MS) {
        fx->spray = 0.3f + 0.7f * clamp01((sustained_ms - STORM_FX_SPRAY_FROM_MS) /
                                          (STORM_FX_DARK_FULL_MS - STORM_FX_SPRAY_FROM_MS));
    }
}

int storm_fx_quality_parse(const char *s, storm_fx_quality *q)
{
    static const char *names[] = { "off", "low", "high" };
    for (int k = 0; k < 3; k++) {
        if (s && strcmp(s, names[k]) == 0) {
            *q = (storm_fx_quality)k;
            return 0;
        }
    }
    return -1;
}
