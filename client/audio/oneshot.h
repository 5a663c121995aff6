/* One-shots: a branch's crack, a stem's snap, an uprooting's tearing and thud, each a
 * voice placed in stereo (sound_pan_gains) at the level its distance gives
 * (sound_event_level_db). A pool of SOUND_VOICES; a new one takes the oldest's place. */
#ifndef GALE_ONESHOT_H
#define GALE_ONESHOT_H

#include <stdbool.h>

#include "sound_dsp.h"

typedef struct oneshot_voice {
    bool on;
    int kind;           /* SOUND_EV_* */
    uint32_t t;         /* samples since it began */
    float gl, gr;       /* gains into left and right */
    uint32_t rng;
    sound_biquad f[2];
    float env, phase;
    uint64_t id;        /* the caller's */
} oneshot_voice;

typedef struct oneshot_pool {
    oneshot_voice v[SOUND_VOICES];
    uint32_t seed;
} oneshot_pool;

void oneshot_init(oneshot_pool *p, uint32_t seed);

/* Starts kind at peak gain amp (linear) and pan (−1..1), with the caller's id. */
void oneshot_start(oneshot_pool *p, int kind, float amp, float pan, uint64_t id);

/* Adds n samples of every voice sounding to l and r; voices past their length end. */
void oneshot_render(oneshot_pool *p, float *l, float *r, int n);

/* Voices sounding. */
int oneshot_active(const oneshot_pool *p);

#endif
