/* Leaf rustle: clicks of high-passed noise at random instants (a Poisson process of the
 * policy's density, sound_rustle_hz), each decaying over a few milliseconds and placed at
 * random across the stereo field, as leaves all around. */
#ifndef GALE_RUSTLE_H
#define GALE_RUSTLE_H

#include "sound_dsp.h"

typedef struct rustle {
    sound_biquad hp[2];
    uint32_t rng;
    float env[2];
    uint64_t clicks; /* made so far */
} rustle;

void rustle_init(rustle *s, uint32_t seed);

/* Adds n samples of hz clicks a second, each of peak gain click_gain. */
void rustle_render(rustle *s, float hz, float click_gain, float *l, float *r, int n);

#endif
