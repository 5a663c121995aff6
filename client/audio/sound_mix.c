/* The mixer (sound_mix.h): blocks of SOUND_BLOCK frames; the scene's speed glides into the
 * bed (0.3 s) and lags into the rustle (SOUND_RUSTLE_LAG_S), the gusts swing it over a
 * smooth random curve, and the master gain glides to a visitor's step. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>

#include "aeolian.h"
#include "err.h"
#include "limiter.h"
#include "oneshot.h"
#include "rustle.h"
#include "sound_mix.h"
#include "wind_bed.h"

#define SOUND_BLOCK 64
#define STARTED_RING 64

struct sound_mix {
    pthread_mutex_t lock;
    sound_mix_desc d;
    float volume_db, ceiling_dbfs, visitor_db, gain; /* gain: the master now, linear */
    sound_scene scene;
    bool have_scene;
    float u_s, u_rustle;           /* the glided and lagged speeds */
    float gust_a, gust_b, gust_t;  /* the gust curve: from a to b, t in [0, 1) */
    uint32_t rng;
    wind_bed bed;
    aeolian aeol;
    rustle rus;
    oneshot_pool shots;
    limiter lim;
    uint64_t frames;
    struct { uint64_t id, frame; } started[STARTED_RING];
    uint32_t started_head, started_tail;
    int peak;
    sound_mix_state st;
};

void sound_mix_resolve(const sound_mix_desc *d, float *volume_db, float *ceiling_dbfs)
{
    *volume_db = d->quiet ? fminf(d->volume_db, SOUND_QUIET_VOLUME_DB) : d->volume_db;
    *ceiling_dbfs = fminf(d->quiet ? fminf(d->ceiling_dbfs, SOUND_QUIET_CEILING_DBFS)
                                   : d->ceiling_dbfs, 0.0f);
}

sound_mix *sound_mix_create(const sound_mix_desc *d, gale_err *err)
{
    sound_mix *m = calloc(1, sizeof *m);
    if (!m) {
        gale_errf(err, GALE_E_NOMEM, "sound: no memory for the mixer");
        return NULL;
    }
    pthread_mutex_init(&m->lock, NULL);
    m->d = *d;
    sound_mix_resolve(d, &m->volume_db, &m->ceiling_dbfs);
    m->gain = sound_db_to_gain(m->volume_db);
    uint32_t seed = d->seed ? d->seed : 0x6a1e5eedu;
    m->rng = seed | 1u;
    wind_bed_init(&m->bed, seed);
    aeolian_init(&m->aeol, seed + 1u);
    rustle_init(&m->rus, seed + 2u);
    oneshot_init(&m->shots, seed + 3u);
    limiter_init(&m->lim, m->ceiling_dbfs, SOUND_LIMIT_LOOKAHEAD_MS, SOUND_LIMIT_RELEASE_MS,
                 SOUND_RATE_HZ);
    m->scene.gust = 1.0f;
    m->scene.kept = 1.0f;
    return m;
}

void sound_mix_destroy(sound_mix *m)
{
    if (m) {
        pthread_mutex_destroy(&m->lock);
        free(m);
    }
}

void sound_mix_set_scene(sound_mix *m, const sound_scene *s)
{
    pthread_mutex_lock(&m->lock);
    m->scene = *s;
    if (!m->have_scene) {
        m->u_s = m->u_rustle = s->u_ms; /* the first scene starts there, not from calm */
        m->have_scene = true;
    }
    pthread_mutex_unlock(&m->lock);
}

float sound_mix_event(sound_mix *m, int kind, float dist_m, float rel_rad, uint64_t id)
{
    float db = sound_event_level_db(kind, dist_m);
    if (!isfinite(db)) {
        return db;
    }
    pthread_mutex_lock(&m->lock);
    float at = db + (m->d.quiet ? SOUND_QUIET_EVENT_DB : 0.0f);
    oneshot_start(&m->shots, kind, sound_db_to_gain(at), sound_pan(rel_rad), id);
    /* it sounds from the next frame rendered */
    uint32_t next = (m->started_tail + 1u) % STARTED_RING;
    if (next != m->started_head) {
        m->started[m->started_tail].id = id;
        m->started[m->started_tail].frame = UINT64_MAX; /* set at the render */
        m->started_tail = next;
    }
    pthread_mutex_unlock(&m->lock);
    return db;
}

bool sound_mix_take_started(sound_mix *m, uint64_t *id, uint64_t *first_frame)
{
    pthread_mutex_lock(&m->lock);
    bool got = m->started_head != m->started_tail && m->started[m->started_head].frame != UINT64_MAX;
    if (got) {
        *id = m->started[m->started_head].id;
        *first_frame = m->started[m->started_head].frame;
        m->started_head = (m->started_head + 1u) % STARTED_RING;
    }
    pthread_mutex_unlock(&m->lock);
    return got;
}

/* The gust curve: a new random point every 1/SOUND_GUST_HZ s, cosine-eased between. */
static float gust_swing(sound_mix *m, float dt_s)
{
    m->gust_t += dt_s * SOUND_GUST_HZ;
    while (m->gust_t >= 1.0f) {
        m->gust_t -= 1.0f;
        m->gust_a = m->gust_b;
        m->gust_b = 0.5f * (sound_noise(&m->rng) + 1.0f);
    }
    float e = 0.5f - 0.5f * cosf(3.14159265f * m->gust_t);
    return m->gust_a + (m->gust_b - m->gust_a) * e;
}

static void block(sound_mix *m, int16_t *out, int n)
{
    float l[SOUND_BLOCK] = { 0 }, r[SOUND_BLOCK] = { 0 };
    const float dt = (float)n / (float)SOUND_RATE_HZ;
    const sound_scene *s = &m->scene;
    m->u_s = sound_smooth(m->u_s, s->u_ms, 0.3f, dt);
    m->u_rustle = sound_smooth(m->u_rustle, s->u_ms, SOUND_RUSTLE_LAG_S, dt);
    const float swing = 1.0f + SOUND_GUST_DEPTH * fmaxf(s->gust - 1.0f, 0.0f) * gust_swing(m, dt);
    const float u = m->u_s * swing, ur = m->u_rustle * swing;
    wind_bed_render(&m->bed, u, l, r, n);
    aeolian_render(&m->aeol, u, s->class_len_m, l, r, n);
    const float rhz = sound_rustle_hz(ur, s->leaves_w, s->kept);
    rustle_render(&m->rus, rhz, sound_db_to_gain(sound_rustle_db(ur)), l, r, n);
    oneshot_render(&m->shots, l, r, n);
    const float g1 = sound_db_to_gain(m->volume_db + m->visitor_db), g0 = m->gain;
    for (int i = 0; i < n; i++) {
        float g = g0 + (g1 - g0) * (float)(i + 1) / (float)n;
        l[i] *= g;
        r[i] *= g;
    }
    m->gain = g1;
    limiter_run(&m->lim, l, r, n);
    /* the ceiling in integers: no sample past floor(ceiling × 32767) */
    const float lim = floorf(m->lim.ceiling * 32767.0f);
    for (int i = 0; i < n; i++) {
        int a = (int)lrintf(fminf(fmaxf(l[i] * 32767.0f, -lim), lim));
        int b = (int)lrintf(fminf(fmaxf(r[i] * 32767.0f, -lim), lim));
        out[2 * i] = (int16_t)a;
        out[2 * i + 1] = (int16_t)b;
        int p = abs(a) > abs(b) ? abs(a) : abs(b);
        m->peak = p > m->peak ? p : m->peak;
    }
    m->st.u_eff_ms = u;
    m->st.rustle_u_ms = ur;
    m->st.rustle_hz = rhz;
}

void sound_mix_render(sound_mix *m, int16_t *out, uint32_t n)
{
    pthread_mutex_lock(&m->lock);
    /* events started since the last render begin with this one's first frame */
    for (uint32_t k = m->started_head; k != m->started_tail; k = (k + 1u) % STARTED_RING) {
        if (m->started[k].frame == UINT64_MAX) {
            m->started[k].frame = m->frames;
        }
    }
    for (uint32_t done = 0; done < n;) {
        int k = n - done > SOUND_BLOCK ? SOUND_BLOCK : (int)(n - done);
        block(m, out + 2 * done, k);
        done += (uint32_t)k;
    }
    m->frames += n;
    pthread_mutex_unlock(&m->lock);
}

void sound_mix_visitor_step(sound_mix *m, int dir)
{
    pthread_mutex_lock(&m->lock);
    float v = m->visitor_db + (dir > 0 ? SOUND_VISITOR_STEP_DB : -SOUND_VISITOR_STEP_DB);
    m->visitor_db = fminf(fmaxf(v, SOUND_VISITOR_MIN_DB), SOUND_VISITOR_MAX_DB);
    pthread_mutex_unlock(&m->lock);
}

void sound_mix_visitor_reset(sound_mix *m)
{
    pthread_mutex_lock(&m->lock);
    m->visitor_db = 0.0f;
    pthread_mutex_unlock(&m->lock);
}

sound_mix_state sound_mix_get_state(sound_mix *m)
{
    pthread_mutex_lock(&m->lock);
    sound_mix_state st = m->st;
    const float u = st.u_eff_ms;
    st.loudest_tone_db = -INFINITY;
    for (int k = 0; k < SOUND_BANDS; k++) {
        st.band_gain[k] = wind_bed_band_gain(k, u);
    }
    st.body_hz = wind_bed_band_hz(SOUND_BAND_BODY, u);
    st.howl_hz = wind_bed_band_hz(SOUND_BAND_HOWL, u);
    for (int k = 0; k < SOUND_CLASSES; k++) {
        st.tone_hz[k] = sound_strouhal_hz(u, sound_class_d_m[k]);
        st.tone_db[k] = sound_aeol_db(m->scene.class_len_m[k], u, sound_class_d_m[k]);
        st.loudest_tone_db = fmaxf(st.loudest_tone_db, st.tone_db[k]);
    }
    st.volume_db = m->volume_db + m->visitor_db;
    st.visitor_db = m->visitor_db;
    st.ceiling_dbfs = m->ceiling_dbfs;
    st.voices = oneshot_active(&m->shots);
    st.frames = m->frames;
    st.clamped = m->lim.clamped;
    st.min_gain = m->lim.min_gain;
    st.peak = m->peak;
    pthread_mutex_unlock(&m->lock);
    return st;
}
