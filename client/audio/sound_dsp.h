/* The few signal blocks the sound wing is made of, inline: a xorshift noise source (each
 * voice its own seed, so a run's sound is the same for the same frames), RBJ biquads
 * (R. Bristow-Johnson, "Cookbook formulae for audio EQ biquad filter coefficients":
 * low-pass, high-pass and the constant 0 dB peak band-pass) and a one-pole smoother. */
#ifndef GALE_SOUND_DSP_H
#define GALE_SOUND_DSP_H

#include <math.h>
#include <stdint.h>

#include "sound_policy.h"

/* Uniform in [-1, 1). s: the state, never 0. */
static inline float sound_noise(uint32_t *s)
{
    uint32_t x = *s;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *s = x;
    return (float)(int32_t)x * (1.0f / 2147483648.0f);
}

/* Uniform in [0, 1). */
static inline float sound_uniform(uint32_t *s)
{
    return 0.5f * (sound_noise(s) + 1.0f);
}

typedef struct sound_biquad {
    float b0, b1, b2, a1, a2; /* normalised by a0 */
    float x1, x2, y1, y2;
} sound_biquad;

enum { SOUND_LP = 0, SOUND_HP = 1, SOUND_BP = 2 };

/* Coefficients of kind (SOUND_LP, SOUND_HP, SOUND_BP) at f_hz and q; the state is kept so a
 * moving centre does not click. f_hz is held below 0.45 of the rate. */
static inline void sound_biquad_set(sound_biquad *b, int kind, float f_hz, float q)
{
    float f = fminf(fmaxf(f_hz, 5.0f), 0.45f * (float)SOUND_RATE_HZ);
    float w = 6.2831853f * f / (float)SOUND_RATE_HZ, cw = cosf(w), al = sinf(w) / (2.0f * q);
    float a0 = 1.0f + al, b0, b1, b2;
    if (kind == SOUND_LP) {
        b0 = b2 = 0.5f * (1.0f - cw);
        b1 = 1.0f - cw;
    } else if (kind == SOUND_HP) {
        b0 = b2 = 0.5f * (1.0f + cw);
        b1 = -(1.0f + cw);
    } else {
        b0 = al;
        b1 = 0.0f;
        b2 = -al;
    }
    b->b0 = b0 / a0;
    b->b1 = b1 / a0;
    b->b2 = b2 / a0;
    b->a1 = -2.0f * cw / a0;
    b->a2 = (1.0f - al) / a0;
}

static inline float sound_biquad_run(sound_biquad *b, float x)
{
    float y = b->b0 * x + b->b1 * b->x1 + b->b2 * b->x2 - b->a1 * b->y1 - b->a2 * b->y2;
    b->x2 = b->x1;
    b->x1 = x;
    b->y2 = b->y1;
    b->y1 = y;
    return y;
}

/* One-pole step of cur towards target over time constant tau_s, for dt_s. */
static inline float sound_smooth(float cur, float target, float tau_s, float dt_s)
{
    return target + (cur - target) * expf(-dt_s / tau_s);
}

#endif
