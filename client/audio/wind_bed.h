/* The wind bed: three bands of noise whose level and centres follow the wind at the
 * listener (sound_policy.h "wind bed"): a rumble under a low-pass, a body band-pass rising
 * with the speed, and a narrow howl above it that fades in towards hurricane force and
 * wanders. Left and right are independent noises through the same filters (a wide bed). */
#ifndef GALE_WIND_BED_H
#define GALE_WIND_BED_H

#include "sound_dsp.h"

typedef struct wind_bed {
    sound_biquad f[SOUND_BANDS][2];
    uint32_t rng[2];
    float gain[SOUND_BANDS]; /* linear, what the last block ended at */
    double t_s;              /* the bed's own clock, for the howl's wander */
} wind_bed;

/* A silent bed; seed picks its noise (non-zero). */
void wind_bed_init(wind_bed *b, uint32_t seed);

/* Adds n samples at wind u_ms to l and r (the gains glide from the last block's). */
void wind_bed_render(wind_bed *b, float u_ms, float *l, float *r, int n);

/* Linear gain of band k at u_ms (the RMS each band is made to have; 0 when silent), and
 * its centre [Hz] without the howl's wander. */
float wind_bed_band_gain(int k, float u_ms);
float wind_bed_band_hz(int k, float u_ms);

#endif
