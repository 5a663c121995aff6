/* Storm look: the streamed weather (sustained wind, its direction) mapped to the sky, light,
 * fog and rain gale_render draws. Plain C, no GL: tested on its own (tests/test_storm_fx.c). */
#ifndef GALE_STORM_FX_H
#define GALE_STORM_FX_H

/* Quality of the storm look: off keeps the calm look at any wind; low draws one layer of
 * rain streaks (cheap on llvmpipe); high draws three. */
typedef enum storm_fx_quality {
    STORM_FX_OFF = 0,
    STORM_FX_LOW = 1,
    STORM_FX_HIGH = 2,
} storm_fx_quality;

/* Sustained wind [m/s] where the sky starts to darken (Beaufort 6, strong breeze) and where
 * it is darkest (Saffir-Simpson Cat 5, protocol/wind_scale.h). */
#define STORM_FX_DARK_FROM_MS 10.8f
#define STORM_FX_DARK_FULL_MS 70.0f
/* Rain streaks from tropical-storm strength (sustained >= 17.5 m/s) on. */
#define STORM_FX_RAIN_FROM_MS 17.5f
/* Spray blown off the ground from hurricane strength (Beaufort 12, 32.7 m/s: "air filled
 * with foam and spray") on. */
#define STORM_FX_SPRAY_FROM_MS 32.7f

typedef struct storm_fx {
    float intensity;  /* 0 calm .. 1 darkest */
    float sun_col[3]; /* direct light colour (common.glsl u_sun_col) */
    float sky_zenith[3], sky_horizon[3], ground_col[3];
    float fog_scale;  /* multiplies the renderer's fog distance; 1 = calm */
    float rain;       /* streak density 0 (none) .. 1 */
    int rain_layers;  /* layers of streaks drawn (0 none) */
    float spray;      /* blown spray near the horizon 0 (none) .. 1 */
    float wind_to[2]; /* horizontal wind [m/s], world x east, y north: streaks slant along it */
    /* Keeping the trees readable (the exhibit is about them): */
    float wet;           /* wet bark and leaves 0 (dry) .. 1: darker, with a sheen of the sky */
    float subject_clear; /* share of the storm's extra fog and of the rain streaks kept off
                            the camera's subject (the trees it looks at) 0 .. 1 */
} storm_fx;

/* The calm look: the sky, light and fog the renderer draws with no storm. */
void storm_fx_calm(storm_fx *fx);

/* Share of the storm's extra fog and rain kept off the camera's subject once storm_fx
 * darkens the sky (storm_fx.subject_clear). */
#define STORM_FX_SUBJECT_CLEAR 0.8f

/* The look at sustained wind sustained_ms coming from dir_from_deg (clockwise from north),
 * at quality q. Below STORM_FX_DARK_FROM_MS, or with q off, it equals storm_fx_calm. */
void storm_fx_from_weather(float sustained_ms, float dir_from_deg, storm_fx_quality q,
                           storm_fx *fx);

/* "off", "low" or "high" to *q: 0, or -1 for any other text. */
int storm_fx_quality_parse(const char *s, storm_fx_quality *q);

#endif
