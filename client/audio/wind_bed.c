/* The wind bed (wind_bed.h). Each band's noise is scaled so its RMS is the policy's level:
 * white noise uniform on [-1, 1) has variance 1/3, and a second-order low-pass or 0 dB
 * band-pass passes an equivalent noise bandwidth of π/2 · f/Q of the rate's half. */
#include "wind_bed.h"

static const int band_kind[SOUND_BANDS] = { SOUND_LP, SOUND_BP, SOUND_BP };
static const float band_q[SOUND_BANDS] = { SOUND_RUMBLE_Q, SOUND_BODY_Q, SOUND_HOWL_Q };

void wind_bed_init(wind_bed *b, uint32_t seed)
{
    *b = (wind_bed){ .rng = { seed | 1u, (seed * 2654435761u) | 1u } };
}

float wind_bed_band_hz(int k, float u_ms)
{
    return k == SOUND_BAND_RUMBLE ? SOUND_RUMBLE_HZ
           : k == SOUND_BAND_BODY ? sound_body_hz(u_ms)
                                  : SOUND_HOWL_MULT * sound_body_hz(u_ms);
}

float wind_bed_band_gain(int k, float u_ms)
{
    float db = sound_bed_db(u_ms);
    if (!isfinite(db)) {
        return 0.0f;
    }
    float g = sound_db_to_gain(db + sound_band_db[k]);
    return k == SOUND_BAND_HOWL ? g * sound_howl_share(u_ms) : g;
}

/* Scale that gives unit RMS out of a filter of centre f_hz and q fed uniform noise. */
static float unit_rms(int kind, float f_hz, float q)
{
    float enbw = 1.5707963f * f_hz / (kind == SOUND_LP ? 1.0f : q);
    return sqrtf(3.0f * 0.5f * (float)SOUND_RATE_HZ / enbw);
}

void wind_bed_render(wind_bed *b, float u_ms, float *l, float *r, int n)
{
    float wander = 1.0f + SOUND_HOWL_WANDER * sinf(6.2831853f * SOUND_HOWL_WANDER_HZ * (float)b->t_s);
    for (int k = 0; k < SOUND_BANDS; k++) {
        float hz = wind_bed_band_hz(k, u_ms) * (k == SOUND_BAND_HOWL ? wander : 1.0f);
        sound_biquad_set(&b->f[k][0], band_kind[k], hz, band_q[k]);
        sound_biquad_set(&b->f[k][1], band_kind[k], hz, band_q[k]);
        float g0 = b->gain[k], g1 = wind_bed_band_gain(k, u_ms) * unit_rms(band_kind[k], hz, band_q[k]);
        if (g0 == 0.0f && g1 == 0.0f) {
            continue;
        }
        for (int i = 0; i < n; i++) {
            float g = g0 + (g1 - g0) * (float)(i + 1) / (float)n;
            l[i] += g * sound_biquad_run(&b->f[k][0], sound_noise(&b->rng[0]));
            r[i] += g * sound_biquad_run(&b->f[k][1], sound_noise(&b->rng[1]));
        }
        b->gain[k] = g1;
    }
    b->t_s += (double)n / SOUND_RATE_HZ;
}
