/* The mixer: the wind bed, the aeolian tones, the leaf rustle and the one-shots summed,
 * times the operator's volume (and a visitor's step on it), through the look-ahead limiter
 * at the operator's ceiling, to 16-bit stereo at SOUND_RATE_HZ. The frame loop sets the
 * scene and starts events; a device thread (audio_out.h) or the headless frame loop
 * renders. Every call takes the mixer's lock, so the two may be different threads. */
#ifndef GALE_SOUND_MIX_H
#define GALE_SOUND_MIX_H

#include <stdbool.h>
#include <stdint.h>

#include "err.h"
#include "sound_policy.h"

/* What the listener hears the wind from: its speed at the camera, the gusts, what grows
 * near (sound_listener.h) and what the storm left of it. */
typedef struct sound_scene {
    float u_ms;                          /* wind at the listener [m/s] */
    float gust;                          /* gust / sustained, ≥ 1 (1: none known) */
    float class_len_m[SOUND_CLASSES];    /* metres of each diameter class, weighted */
    float leaves_w;                      /* leaves near, weighted */
    float kept;                          /* the share of leaf area their crowns keep */
} sound_scene;

typedef struct sound_mix_desc {
    float volume_db;    /* master gain [dB] */
    float ceiling_dbfs; /* the limiter's ceiling [dBFS], ≤ 0 */
    bool quiet;         /* the quiet preset: its volume and ceiling where lower, and
                           one-shots SOUND_QUIET_EVENT_DB down */
    uint32_t seed;      /* the noises' seed (0: a fixed one) */
} sound_mix_desc;

/* What the mixer plays now, for captions, logs and tests. */
typedef struct sound_mix_state {
    float u_eff_ms;                     /* the listener's speed with the gust's swing */
    float rustle_u_ms;                  /* the rustle's lagged speed */
    float band_gain[SOUND_BANDS];       /* linear RMS of each bed band */
    float body_hz, howl_hz;
    float tone_hz[SOUND_CLASSES];
    float tone_db[SOUND_CLASSES];       /* -INFINITY: silent */
    float loudest_tone_db;
    float rustle_hz;
    float volume_db;                    /* the master gain now, visitor's step included */
    float visitor_db;
    float ceiling_dbfs;
    int voices;
    uint64_t frames;                    /* frames rendered */
    uint64_t clamped;                   /* samples the limiter's last clamp changed */
    float min_gain;                     /* the limiter's least gain so far */
    int peak;                           /* largest |sample| written */
} sound_mix_state;

typedef struct sound_mix sound_mix;

/* Allocates a mixer (sound_mix_destroy frees it). NULL with err set. */
sound_mix *sound_mix_create(const sound_mix_desc *d, gale_err *err);
void sound_mix_destroy(sound_mix *m);

/* The scene from now on (the gains glide to it over a block). */
void sound_mix_set_scene(sound_mix *m, const sound_scene *s);

/* A one-shot of kind (SOUND_EV_*) dist_m away at bearing rel_rad from where the camera
 * looks (counter-clockwise positive): starts with the next rendered sample. id is the
 * caller's (sound_mix_take_started gives it back with that sample's index). Returns its
 * peak level [dBFS before the volume], -INFINITY when it is too far to play. */
float sound_mix_event(sound_mix *m, int kind, float dist_m, float rel_rad, uint64_t id);

/* One event started since the last call: its id and the index of its first sample.
 * False when none. */
bool sound_mix_take_started(sound_mix *m, uint64_t *id, uint64_t *first_frame);

/* Renders n frames of interleaved 16-bit stereo into out. */
void sound_mix_render(sound_mix *m, int16_t *out, uint32_t n);

/* A visitor's step (+1 louder, −1 softer) of SOUND_VISITOR_STEP_DB, within the policy's
 * range; reset to the operator's default (kiosk idle). */
void sound_mix_visitor_step(sound_mix *m, int dir);
void sound_mix_visitor_reset(sound_mix *m);

sound_mix_state sound_mix_get_state(sound_mix *m);

/* The operator's volume and ceiling after the quiet preset. */
void sound_mix_resolve(const sound_mix_desc *d, float *volume_db, float *ceiling_dbfs);

#endif
