/* Aeolian tones: each diameter class near the listener sings at its Strouhal frequency
 * f = St·U/d (sound_policy.h), as noise through a narrow band-pass there, its level from
 * how much of the class is near (metres, weighted by distance) and the speed. */
#ifndef GALE_AEOLIAN_H
#define GALE_AEOLIAN_H

#include "sound_dsp.h"

typedef struct aeolian {
    sound_biquad f[SOUND_CLASSES][2];
    uint32_t rng[2];
    float gain[SOUND_CLASSES];
} aeolian;

void aeolian_init(aeolian *a, uint32_t seed);

/* Adds n samples at wind u_ms with len_m[SOUND_CLASSES] metres of each class near. */
void aeolian_render(aeolian *a, float u_ms, const float *len_m, float *l, float *r, int n);

#endif
