/* One-shots (oneshot.h), after Farnell's recipes (Designing Sound, ch. "Fire" and
 * "Creaking" for crackle and wood): a crack is a millisecond's click and a bright noise
 * burst decaying over 30 ms; a snap adds the stem's woody modes (decaying partials near
 * 180, 410 and 730 Hz) and a splintering crackle thinning out over half a second; an
 * uprooting is roots tearing (a crackle over a second) over a low thud gliding from 70 to
 * 38 Hz and a low-passed rumble of earth. Each begins with the fibres' report, a 1.5 ms
 * click of white noise at full level (its broad spectrum is what carries through a storm's
 * wind, whose power lies mostly below 2 kHz), and is shaped to peak near 1 before amp. */
#include "oneshot.h"

void oneshot_init(oneshot_pool *p, uint32_t seed)
{
    *p = (oneshot_pool){ .seed = seed | 1u };
}

void oneshot_start(oneshot_pool *p, int kind, float amp, float pan, uint64_t id)
{
    int k = 0;
    for (int i = 0; i < SOUND_VOICES; i++) {
        if (!p->v[i].on) {
            k = i;
            break;
        }
        k = p->v[i].t > p->v[k].t ? i : k; /* all on: the oldest */
    }
    oneshot_voice *v = &p->v[k];
    p->seed = p->seed * 1664525u + 1013904223u;
    *v = (oneshot_voice){ .on = true, .kind = kind, .rng = p->seed | 1u, .id = id };
    sound_pan_gains(pan, &v->gl, &v->gr);
    v->gl *= amp;
    v->gr *= amp;
    if (kind == SOUND_EV_UPROOT) {
        sound_biquad_set(&v->f[0], SOUND_LP, 300.0f, 0.707f);
        sound_biquad_set(&v->f[1], SOUND_HP, 1500.0f, 0.707f);
    } else {
        sound_biquad_set(&v->f[0], SOUND_BP, kind == SOUND_EV_CRACK ? 2500.0f : 1800.0f, 0.8f);
        sound_biquad_set(&v->f[1], SOUND_HP, 2000.0f, 0.707f);
    }
}

/* A crackle: clicks at rate hz into env, decaying over 4 ms; the high-passed noise it
 * shapes. */
static float crackle(oneshot_voice *v, float hz)
{
    if (sound_uniform(&v->rng) < hz / (float)SOUND_RATE_HZ) {
        v->env += 0.4f + 0.6f * sound_uniform(&v->rng);
    }
    float x = sound_biquad_run(&v->f[1], v->env * sound_noise(&v->rng));
    v->env *= 0.9948f; /* exp(-1 / (4 ms × 48 kHz)) */
    return x;
}

static float sample(oneshot_voice *v)
{
    const float s = (float)v->t / (float)SOUND_RATE_HZ;
    const float nz = sound_noise(&v->rng);
    const float click = s < 0.0015f ? nz : 0.0f;
    switch (v->kind) {
    case SOUND_EV_CRACK: {
        float e = s < 0.001f ? s / 0.001f : expf(-(s - 0.001f) / 0.03f);
        return click + e * 1.6f * sound_biquad_run(&v->f[0], nz);
    }
    case SOUND_EV_SNAP: {
        float e = s < 0.001f ? s / 0.001f : expf(-(s - 0.001f) / 0.05f);
        float burst = e * 1.2f * sound_biquad_run(&v->f[0], nz);
        float w = expf(-s / 0.12f) * (0.35f * sinf(6.2831853f * 180.0f * s) +
                                      0.25f * sinf(6.2831853f * 410.0f * s) +
                                      0.15f * sinf(6.2831853f * 730.0f * s));
        return click + 0.7f * burst + w + 0.4f * crackle(v, 220.0f * expf(-s / 0.2f));
    }
    default: { /* SOUND_EV_UPROOT */
        float f = 38.0f + 32.0f * expf(-s / 0.15f);
        v->phase += 6.2831853f * f / (float)SOUND_RATE_HZ;
        float e = s < 0.015f ? s / 0.015f : expf(-(s - 0.015f) / 0.35f);
        float thud = 0.7f * e * sinf(v->phase);
        float earth = 1.2f * expf(-s / 0.5f) * sound_biquad_run(&v->f[0], nz);
        return click + thud + earth + 0.35f * crackle(v, 140.0f * expf(-s / 0.5f));
    }
    }
}

void oneshot_render(oneshot_pool *p, float *l, float *r, int n)
{
    for (int k = 0; k < SOUND_VOICES; k++) {
        oneshot_voice *v = &p->v[k];
        if (!v->on) {
            continue;
        }
        const uint32_t len = (uint32_t)(sound_event_s[v->kind] * (float)SOUND_RATE_HZ);
        for (int i = 0; i < n && v->t < len; i++, v->t++) {
            float x = sample(v);
            l[i] += v->gl * x;
            r[i] += v->gr * x;
        }
        v->on = v->t < len;
    }
}

int oneshot_active(const oneshot_pool *p)
{
    int n = 0;
    for (int k = 0; k < SOUND_VOICES; k++) {
        n += p->v[k].on;
    }
    return n;
}
