/* Aeolian tones (aeolian.h): each class's noise scaled to the policy's RMS (as the bed's). */
#include "aeolian.h"

void aeolian_init(aeolian *a, uint32_t seed)
{
    *a = (aeolian){ .rng = { (seed ^ 0x9e3779b9u) | 1u, (seed * 747796405u) | 1u } };
}

void aeolian_render(aeolian *a, float u_ms, const float *len_m, float *l, float *r, int n)
{
    for (int k = 0; k < SOUND_CLASSES; k++) {
        const float d = sound_class_d_m[k], db = sound_aeol_db(len_m[k], u_ms, d);
        const float hz = sound_strouhal_hz(u_ms, d);
        float g0 = a->gain[k], g1 = 0.0f;
        if (isfinite(db)) {
            const float enbw = 1.5707963f * hz / SOUND_AEOL_Q;
            g1 = sound_db_to_gain(db) * sqrtf(1.5f * (float)SOUND_RATE_HZ / enbw);
            sound_biquad_set(&a->f[k][0], SOUND_BP, hz, SOUND_AEOL_Q);
            sound_biquad_set(&a->f[k][1], SOUND_BP, hz, SOUND_AEOL_Q);
        }
        if (g0 == 0.0f && g1 == 0.0f) {
            continue;
        }
        for (int i = 0; i < n; i++) {
            float g = g0 + (g1 - g0) * (float)(i + 1) / (float)n;
            l[i] += g * sound_biquad_run(&a->f[k][0], sound_noise(&a->rng[0]));
            r[i] += g * sound_biquad_run(&a->f[k][1], sound_noise(&a->rng[1]));
        }
        a->gain[k] = g1;
    }
}
