/* The clients' sound policy: every number the wind's sound is made of and the laws that
 * turn the wind at the listener, what grows near it and the storm's damage into levels,
 * frequencies and densities. The page holds the same numbers and laws
 * (web/sound_policy.js); tests/web/test_sound_policy_js.mjs holds the two to each other
 * through tests/web/sound_table.c.
 *
 * Sources: aeolian tones at f = St·U/d, St ≈ 0.2 for a circular cylinder over
 * 300 < Re < 2e5 (the Strouhal number's plateau; a 1 mm pine needle at 20 m/s sings near
 * 4 kHz, a 1 cm twig near 400 Hz). Procedural wind as band-passed noise whose level and
 * centre follow the speed, with leaf crackle whose density grows with the speed and lags
 * the gusts (A. Farnell, Designing Sound, MIT Press 2010, ch. 41 "Wind"). Survivors of
 * Andrew describe a whisper, then a howl, then breaking glass and snapping trees (Landsea
 * et al. 2004): the captions follow that order. Levels are dBFS before the operator's
 * volume; the limiter's ceiling is the operator's (sound_mix.h). */
#ifndef GALE_SOUND_POLICY_H
#define GALE_SOUND_POLICY_H

#include <math.h>

#define SOUND_RATE_HZ 48000
#define SOUND_CHANNELS 2

/* ---- aeolian tones ---- */
#define SOUND_STROUHAL 0.2f
/* Diameter classes [m], a factor √10 apart: needles, fine twigs, twigs, small branches,
 * limbs, stems. A node's segment (asset radius × 2) goes to the nearest class on a log
 * scale; a needle tuft (ASSET leaf_shape 2) counts SOUND_NEEDLES_PER_TUFT needles of
 * SOUND_NEEDLE_D_M, each its blade length long. Broad leaves and palm leaflets flutter
 * rather than sing: they feed the rustle. */
#define SOUND_CLASSES 6
static const float sound_class_d_m[SOUND_CLASSES] = { 0.001f, 0.00316f, 0.01f,
                                                      0.0316f, 0.1f,     0.316f };
#define SOUND_NEEDLE_D_M 0.001f
#define SOUND_NEEDLES_PER_TUFT 12.0f
/* A tone outside these is not made (below: felt, not heard; above: past most speakers). */
#define SOUND_AEOL_F_MIN_HZ 40.0f
#define SOUND_AEOL_F_MAX_HZ 12000.0f
/* Each class is noise through a band-pass of this Q at its Strouhal frequency: the many
 * elements of a class in gusty air sing over a band, not one line. */
#define SOUND_AEOL_Q 12.0f
/* A class's level [dBFS]: SOUND_AEOL_DB_REF for SOUND_AEOL_LEN_REF_M metres of it at
 * SOUND_REF_M and SOUND_U_REF_MS, +10 dB per decade of length, +SOUND_AEOL_DB_PER_DECADE
 * per decade of speed (a dipole's power goes as U⁶, 60 dB a decade; 40 keeps a breeze
 * audible under a storm's ceiling), at most SOUND_AEOL_DB_MAX. */
#define SOUND_AEOL_DB_REF (-30.0f)
#define SOUND_AEOL_LEN_REF_M 100.0f
#define SOUND_AEOL_DB_PER_DECADE 40.0f
#define SOUND_AEOL_DB_MAX (-14.0f)

/* ---- what is near the listener ---- */
/* Trees past SOUND_NEAR_M of the camera are not heard apart from the bed; nearer ones count
 * with the inverse square of their distance, flat within SOUND_REF_M. */
#define SOUND_NEAR_M 120.0f
#define SOUND_REF_M 10.0f
/* The listener's wind [m/s] is taken at this height above the camera's ground point. */
#define SOUND_LISTEN_Z_M 10.0f
#define SOUND_U_REF_MS 20.0f

/* ---- wind bed: three bands of noise ---- */
/* Level of the bed [dBFS]: SOUND_BED_DB_REF at SOUND_U_REF_MS, SOUND_BED_DB_PER_DECADE per
 * decade of speed, at most SOUND_BED_DB_MAX; silent below SOUND_BED_U_MIN_MS. Each band
 * adds its offset. */
#define SOUND_BED_DB_REF (-22.0f)
#define SOUND_BED_DB_PER_DECADE 24.0f
#define SOUND_BED_DB_MAX (-8.0f)
#define SOUND_BED_U_MIN_MS 0.5f
enum { SOUND_BAND_RUMBLE = 0, SOUND_BAND_BODY = 1, SOUND_BAND_HOWL = 2, SOUND_BANDS = 3 };
static const float sound_band_db[SOUND_BANDS] = { -2.0f, -4.0f, -8.0f };
/* Rumble: a low-pass at its corner. Body: a band-pass whose centre rises with the speed.
 * Howl: a narrow band-pass at a multiple of the body's centre, wandering ±SOUND_HOWL_WANDER
 * at SOUND_HOWL_WANDER_HZ, faded in from SOUND_HOWL_U0_MS to SOUND_HOWL_U1_MS. */
#define SOUND_RUMBLE_HZ 110.0f
#define SOUND_RUMBLE_Q 0.707f
#define SOUND_BODY_HZ0 180.0f
#define SOUND_BODY_HZ_PER_MS 22.0f
#define SOUND_BODY_Q 0.9f
#define SOUND_HOWL_MULT 2.2f
#define SOUND_HOWL_Q 7.0f
#define SOUND_HOWL_WANDER 0.12f
#define SOUND_HOWL_WANDER_HZ 0.23f
#define SOUND_HOWL_U0_MS 18.0f
#define SOUND_HOWL_U1_MS 40.0f
/* Gusts: the listener's speed swings by SOUND_GUST_DEPTH of the gust's excess
 * (gust/sustained − 1) over a slow random curve of SOUND_GUST_HZ. */
#define SOUND_GUST_DEPTH 0.6f
#define SOUND_GUST_HZ 0.25f

/* ---- leaf rustle ---- */
/* Clicks a second: SOUND_RUSTLE_HZ_PER × max(U − SOUND_RUSTLE_U0_MS, 0)^SOUND_RUSTLE_EXP,
 * at most SOUND_RUSTLE_MAX_HZ, × the leaves near (saturating: n / (n + HALF)) × the share
 * their crowns keep (a stripped crown rustles less); U lags the gusts by SOUND_RUSTLE_LAG_S.
 * A click: noise high-passed at SOUND_RUSTLE_HP_HZ decaying over SOUND_RUSTLE_DECAY_MS, its
 * level SOUND_RUSTLE_DB_REF at U_REF + SOUND_RUSTLE_DB_PER_DECADE a decade. */
#define SOUND_RUSTLE_HZ_PER 8.0f
#define SOUND_RUSTLE_U0_MS 1.5f
#define SOUND_RUSTLE_EXP 1.5f
#define SOUND_RUSTLE_MAX_HZ 400.0f
#define SOUND_RUSTLE_LEAVES_HALF 2000.0f
#define SOUND_RUSTLE_LAG_S 0.6f
#define SOUND_RUSTLE_HP_HZ 2500.0f
#define SOUND_RUSTLE_DECAY_MS 6.0f
#define SOUND_RUSTLE_DB_REF (-22.0f)
#define SOUND_RUSTLE_DB_PER_DECADE 20.0f

/* ---- one-shots ---- */
enum { SOUND_EV_CRACK = 0, SOUND_EV_SNAP = 1, SOUND_EV_UPROOT = 2, SOUND_EVENTS = 3 };
/* Peak level of each at SOUND_EVENT_REF_M [dBFS], falling 6 dB a doubling past it
 * (a point source), and how long each rings [s]. */
static const float sound_event_db[SOUND_EVENTS] = { -6.0f, 0.0f, -2.0f };
static const float sound_event_s[SOUND_EVENTS] = { 0.18f, 0.9f, 1.4f };
#define SOUND_EVENT_REF_M 20.0f
#define SOUND_EVENT_MAX_M 600.0f /* further ones are not played */
#define SOUND_VOICES 16

/* ---- loudness the operator sets ---- */
/* The master gain [dB] and the limiter's ceiling [dBFS]: defaults, the quiet preset
 * (sensory-friendly hours: everything 14 dB down, the ceiling at −14 dBFS, one-shots a
 * further 6 dB down), and what a visitor may add to the default (reset on kiosk idle). */
#define SOUND_VOLUME_DB (-6.0f)
#define SOUND_CEILING_DBFS (-1.0f)
#define SOUND_QUIET_VOLUME_DB (-20.0f)
#define SOUND_QUIET_CEILING_DBFS (-14.0f)
#define SOUND_QUIET_EVENT_DB (-6.0f)
#define SOUND_VISITOR_STEP_DB 3.0f
#define SOUND_VISITOR_MAX_DB 9.0f
#define SOUND_VISITOR_MIN_DB (-30.0f)
/* The limiter: look-ahead SOUND_LIMIT_LOOKAHEAD_MS (min-hold then a box of that length,
 * so the gain is down before the peak arrives), release SOUND_LIMIT_RELEASE_MS. */
#define SOUND_LIMIT_LOOKAHEAD_MS 2.0f
#define SOUND_LIMIT_RELEASE_MS 80.0f

/* ---- captions ---- */
/* A one-shot's caption shows this long; the wind's by its speed at the listener. */
#define SOUND_CAPTION_EVENT_S 3.0f
#define SOUND_CAPTION_WHISPER_MS 8.0f  /* below: whispering */
#define SOUND_CAPTION_ROAR_MS 20.0f    /* from: roaring */
#define SOUND_CAPTION_HOWL_MS 33.0f    /* from (hurricane force): howling */
#define SOUND_CAPTION_RUSTLE_HZ 30.0f  /* clicks a second from which leaves are named */
#define SOUND_CAPTION_WHISTLE_DB (-40.0f) /* a twig class this loud is named */

/* ---- the laws ---- */

static inline float sound_db_to_gain(float db)
{
    return powf(10.0f, db / 20.0f);
}

/* Aeolian frequency [Hz] of diameter d_m in wind u_ms. */
static inline float sound_strouhal_hz(float u_ms, float d_m)
{
    return SOUND_STROUHAL * u_ms / d_m;
}

/* The bed's level [dBFS] at u_ms (before each band's offset); -INFINITY when silent. */
static inline float sound_bed_db(float u_ms)
{
    if (!(u_ms >= SOUND_BED_U_MIN_MS)) {
        return -INFINITY;
    }
    float db = SOUND_BED_DB_REF + SOUND_BED_DB_PER_DECADE * log10f(u_ms / SOUND_U_REF_MS);
    return fminf(db, SOUND_BED_DB_MAX);
}

/* The body band's centre [Hz] at u_ms; the howl's is SOUND_HOWL_MULT times it. */
static inline float sound_body_hz(float u_ms)
{
    return SOUND_BODY_HZ0 + SOUND_BODY_HZ_PER_MS * fmaxf(u_ms, 0.0f);
}

/* The howl's share (0..1) of its band's level at u_ms: a smoothstep between U0 and U1. */
static inline float sound_howl_share(float u_ms)
{
    float x = (u_ms - SOUND_HOWL_U0_MS) / (SOUND_HOWL_U1_MS - SOUND_HOWL_U0_MS);
    x = fminf(fmaxf(x, 0.0f), 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

/* Level [dBFS] of a class with len_m metres (already weighted by distance) at u_ms;
 * -INFINITY for none, or a tone outside the heard band. */
static inline float sound_aeol_db(float len_m, float u_ms, float d_m)
{
    float f = sound_strouhal_hz(u_ms, d_m);
    if (!(len_m > 0.0f) || !(u_ms >= SOUND_BED_U_MIN_MS) || f < SOUND_AEOL_F_MIN_HZ ||
        f > SOUND_AEOL_F_MAX_HZ) {
        return -INFINITY;
    }
    float db = SOUND_AEOL_DB_REF + 10.0f * log10f(len_m / SOUND_AEOL_LEN_REF_M) +
               SOUND_AEOL_DB_PER_DECADE * log10f(u_ms / SOUND_U_REF_MS);
    return fminf(db, SOUND_AEOL_DB_MAX);
}

/* Weight of something d_m from the listener: 1 within SOUND_REF_M, the inverse square past
 * it, 0 past SOUND_NEAR_M. */
static inline float sound_near_weight(float d_m)
{
    if (!(d_m <= SOUND_NEAR_M)) {
        return 0.0f;
    }
    float r = fmaxf(d_m, SOUND_REF_M) / SOUND_REF_M;
    return 1.0f / (r * r);
}

/* Rustle clicks a second at (lagged) u_ms with leaves_w distance-weighted leaves near and
 * kept (0..1) the share of leaf area their crowns keep. */
static inline float sound_rustle_hz(float u_ms, float leaves_w, float kept)
{
    float x = fmaxf(u_ms - SOUND_RUSTLE_U0_MS, 0.0f);
    float hz = fminf(SOUND_RUSTLE_HZ_PER * powf(x, SOUND_RUSTLE_EXP), SOUND_RUSTLE_MAX_HZ);
    float near = leaves_w > 0.0f ? leaves_w / (leaves_w + SOUND_RUSTLE_LEAVES_HALF) : 0.0f;
    return hz * near * fminf(fmaxf(kept, 0.0f), 1.0f);
}

/* A rustle click's level [dBFS] at u_ms. */
static inline float sound_rustle_db(float u_ms)
{
    return SOUND_RUSTLE_DB_REF +
           SOUND_RUSTLE_DB_PER_DECADE * log10f(fmaxf(u_ms, 0.1f) / SOUND_U_REF_MS);
}

/* A one-shot of kind k at dist_m: its peak level [dBFS] (-INFINITY past the farthest). */
static inline float sound_event_level_db(int k, float dist_m)
{
    if (k < 0 || k >= SOUND_EVENTS || !(dist_m <= SOUND_EVENT_MAX_M)) {
        return -INFINITY;
    }
    return sound_event_db[k] - 20.0f * log10f(fmaxf(dist_m, SOUND_EVENT_REF_M) / SOUND_EVENT_REF_M);
}

/* Pan (−1 left .. +1 right) of a source at bearing rel_rad from where the camera looks
 * (counter-clockwise positive, so a source to the left has rel > 0): −sin(rel); the two
 * channels' gains are equal-power, cos and sin of (pan + 1) π/4. */
static inline float sound_pan(float rel_rad)
{
    return -sinf(rel_rad);
}
static inline void sound_pan_gains(float pan, float *gl, float *gr)
{
    float a = (fminf(fmaxf(pan, -1.0f), 1.0f) + 1.0f) * 0.78539816f;
    *gl = cosf(a);
    *gr = sinf(a);
}

#endif
