/* Leaf rustle (rustle.h). */
#include "rustle.h"

void rustle_init(rustle *s, uint32_t seed)
{
    *s = (rustle){ .rng = (seed ^ 0x85ebca6bu) | 1u };
    sound_biquad_set(&s->hp[0], SOUND_HP, SOUND_RUSTLE_HP_HZ, 0.707f);
    sound_biquad_set(&s->hp[1], SOUND_HP, SOUND_RUSTLE_HP_HZ, 0.707f);
}

void rustle_render(rustle *s, float hz, float click_gain, float *l, float *r, int n)
{
    const float p = hz / (float)SOUND_RATE_HZ;
    const float decay = expf(-1.0f / (1e-3f * SOUND_RUSTLE_DECAY_MS * (float)SOUND_RATE_HZ));
    if (p <= 0.0f && s->env[0] + s->env[1] < 1e-6f) {
        return;
    }
    for (int i = 0; i < n; i++) {
        if (sound_uniform(&s->rng) < p) {
            float a = click_gain * (0.3f + 0.7f * sound_uniform(&s->rng)), gl, gr;
            sound_pan_gains(0.8f * sound_noise(&s->rng), &gl, &gr);
            s->env[0] += a * gl;
            s->env[1] += a * gr;
            s->clicks++;
        }
        l[i] += sound_biquad_run(&s->hp[0], s->env[0] * sound_noise(&s->rng));
        r[i] += sound_biquad_run(&s->hp[1], s->env[1] * sound_noise(&s->rng));
        s->env[0] *= decay;
        s->env[1] *= decay;
    }
}
