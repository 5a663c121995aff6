/* storm_fx: calm is the renderer's clear day exactly, the look darkens and the fog closes in
 * monotonically with the sustained wind, Cat 4 is darker and foggier than Cat 1, rain starts
 * at tropical-storm strength, and the quality names parse. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "storm_fx.h"

static float luma(const float c[3])
{
    return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
}

static void test_calm_is_clear_day(void)
{
    storm_fx calm, fx;
    storm_fx_calm(&calm);
    CHECK(calm.fog_scale == 1.0f && calm.rain == 0.0f && calm.rain_layers == 0);
    CHECK(calm.sky_zenith[0] == 0.30f && calm.sky_zenith[1] == 0.50f &&
          calm.sky_zenith[2] == 0.82f);
    CHECK(calm.sun_col[0] == 1.05f && calm.ground_col[1] == 0.40f);
    float calm_ms[] = { 0.0f, 3.0f, 8.0f, STORM_FX_DARK_FROM_MS, NAN };
    for (size_t k = 0; k < sizeof calm_ms / sizeof calm_ms[0]; k++) {
        storm_fx_from_weather(calm_ms[k], 270.0f, STORM_FX_HIGH, &fx);
        CHECK(memcmp(&fx, &calm, sizeof fx) == 0);
    }
    /* off keeps the clear day at any wind */
    storm_fx_from_weather(65.0f, 90.0f, STORM_FX_OFF, &fx);
    CHECK(memcmp(&fx, &calm, sizeof fx) == 0);
}

static void test_monotone(void)
{
    storm_fx prev;
    storm_fx_from_weather(0.0f, 0.0f, STORM_FX_LOW, &prev);
    for (float v = 0.5f; v <= 90.0f; v += 0.5f) {
        storm_fx fx;
        storm_fx_from_weather(v, 0.0f, STORM_FX_LOW, &fx);
        CHECK(fx.intensity >= prev.intensity);
        CHECK(luma(fx.sky_zenith) <= luma(prev.sky_zenith));
        CHECK(luma(fx.sky_horizon) <= luma(prev.sky_horizon));
        CHECK(luma(fx.sun_col) <= luma(prev.sun_col));
        CHECK(fx.fog_scale <= prev.fog_scale && fx.fog_scale > 0.0f);
        CHECK(fx.rain >= prev.rain && fx.rain <= 1.0f);
        CHECK(fx.spray >= prev.spray && fx.spray <= 1.0f);
        CHECK(fx.wet >= prev.wet && fx.wet <= 1.0f);
        /* the subject kept clear whenever the storm look is on */
        CHECK(fx.subject_clear == (fx.intensity > 0.0f ? STORM_FX_SUBJECT_CLEAR : 0.0f));
        prev = fx;
    }
}

static void test_cat4_darker_than_cat1(void)
{
    storm_fx c1, c4;
    storm_fx_from_weather(38.0f, 90.0f, STORM_FX_LOW, &c1); /* Cat 1: 33-42 m/s */
    storm_fx_from_weather(62.0f, 90.0f, STORM_FX_LOW, &c4); /* Cat 4: 58-70 m/s */
    CHECK(luma(c4.sky_zenith) < luma(c1.sky_zenith) - 0.01f);
    CHECK(luma(c4.sun_col) < luma(c1.sun_col) - 0.05f);
    CHECK(c4.fog_scale < c1.fog_scale - 0.05f);
    CHECK(c4.rain > c1.rain);
    CHECK(c1.spray > 0.0f && c4.spray > c1.spray);
    CHECK(c4.wet > c1.wet && c1.wet > 0.0f);
}

/* Crowns darker than the sky behind them from Category 3 on: a leaf facing straight up,
 * lit as common.glsl light() lights it (ambient 0.55 x the zenith, the sun at most fully
 * on it, the wet albedo 1 - 0.3 wet), of the brightest demo leaf colour (palm, 0.30 0.52
 * 0.16 x 1.18, render_demo.c and leaf.frag's variation), stays under 0.8 of the sky's
 * zenith luma: the deck is a light ground for dark crowns, not the other way round. */
static void test_crowns_darker_than_sky(void)
{
    const float leaf[3] = { 0.30f * 1.18f, 0.52f * 1.18f, 0.16f * 1.18f };
    for (float v = 50.0f; v <= 90.0f; v += 1.0f) { /* Category 3 and above */
        storm_fx fx;
        storm_fx_from_weather(v, 0.0f, STORM_FX_HIGH, &fx);
        float lit[3];
        for (int k = 0; k < 3; k++) {
            lit[k] = leaf[k] * (1.0f - 0.3f * fx.wet) * (0.55f * fx.sky_zenith[k] + fx.sun_col[k]);
        }
        CHECK(luma(lit) < 0.8f * luma(fx.sky_zenith));
    }
}

static void test_rain_threshold_and_wind(void)
{
    storm_fx fx;
    storm_fx_from_weather(17.4f, 0.0f, STORM_FX_HIGH, &fx);
    CHECK(fx.intensity > 0.0f && fx.rain == 0.0f && fx.rain_layers == 0);
    storm_fx_from_weather(STORM_FX_RAIN_FROM_MS, 0.0f, STORM_FX_HIGH, &fx);
    CHECK(fx.rain > 0.0f && fx.rain_layers == 3 && fx.spray == 0.0f);
    storm_fx_from_weather(30.0f, 0.0f, STORM_FX_LOW, &fx);
    CHECK(fx.rain_layers == 1);
    /* from the north: it blows towards -y */
    CHECK_NEAR(fx.wind_to[0], 0.0f, 1e-3);
    CHECK_NEAR(fx.wind_to[1], -30.0f, 1e-3);
    /* from the east: towards -x */
    storm_fx_from_weather(30.0f, 90.0f, STORM_FX_LOW, &fx);
    CHECK_NEAR(fx.wind_to[0], -30.0f, 1e-3);
    CHECK_NEAR(fx.wind_to[1], 0.0f, 1e-3);
}

static void test_quality_parse(void)
{
    storm_fx_quality q = STORM_FX_LOW;
    CHECK(storm_fx_quality_parse("off", &q) == 0 && q == STORM_FX_OFF);
    CHECK(storm_fx_quality_parse("high", &q) == 0 && q == STORM_FX_HIGH);
    CHECK(storm_fx_quality_parse("low", &q) == 0 && q == STORM_FX_LOW);
    CHECK(storm_fx_quality_parse("medium", &q) == -1 && q == STORM_FX_LOW);
    CHECK(storm_fx_quality_parse(NULL, &q) == -1);
}

int main(void)
{
    RUN(test_calm_is_clear_day);
    RUN(test_monotone);
    RUN(test_cat4_darker_than_cat1);
    RUN(test_crowns_darker_than_sky);
    RUN(test_rain_threshold_and_wind);
    RUN(test_quality_parse);
    return check_report();
}
