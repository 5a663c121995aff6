/* gale-client's sound (client/audio, CLIENT.md "Sound"): the wind at the camera and what
 * grows near it into the mixer each frame, the storm's snaps, uproots and broken branches
 * started at the frame that shows them (placed in stereo by their bearing from the view,
 * softer with distance) with a log line of the frame's time and the sound's, the caption
 * line, the visitor's volume step and its reset on idle, and the output: the device (or
 * the null device), or headless the WAV of --audio-out, 1/60 s of sound a frame (1/HZ
 * with --max-fps), so a run's sound follows its frames and not the machine's speed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "audio_out.h"
#include "client.h"
#include "mono.h"
#include "sound_caption.h"
#include "sound_listener.h"
#include "sound_mix.h"
#include "wav_writer.h"

#define PENDING_MAX 64
#define LOGGED_MAX 64

typedef struct pending_event {
    uint32_t tree;
    int kind;      /* SOUND_EV_* */
    double t0_s;   /* server time its picture begins */
} pending_event;

/* An event started in the mixer, until its first sample is rendered and logged. */
typedef struct fired_event {
    uint64_t id;
    double frame_s;        /* the audio clock at the frame that shows it */
    double frame_server_s; /* the server time that frame shows */
    uint32_t tree;
    int kind;
    float dist_m, rel_rad, db;
    uint64_t frame_no;
} fired_event;

typedef struct client_audio {
    sound_mix *mix;   /* owned */
    audio_out *out;   /* owned: the device, or NULL headless */
    wav_writer wav;
    bool wav_open;
    sound_species prof[RENDER_MAX_SPECIES]; /* by render id */
    bool have_prof[RENDER_MAX_SPECIES];
    sound_species by_welcome[CLIENT_MAX_SPECIES];
    pending_event pend[PENDING_MAX];
    int n_pend;
    fired_event fired[LOGGED_MAX];
    int n_fired;
    uint64_t next_id, frames;
    double frame_period_s, owed_frames;
    double listen_at_s;   /* audio clock of the last scan of the trees near */
    sound_scene scene;
    int last_event;       /* the caption's one-shot */
    double last_event_s;  /* when it sounded (the audio clock) */
    double clock_s;       /* the audio clock: WAV time headless, CLOCK_MONOTONIC live */
    uint64_t played, too_far, dropped, max_gap_us;
    char caption[160];
} client_audio;

int client_audio_start(client *c)
{
    const client_args *a = &c->a;
    if (a->sound_off || (a->headless && !a->audio_out && !a->audio_device)) {
        return 0; /* headless runs are silent unless asked for the WAV or a device */
    }
    gale_err err = { 0 };
    client_audio *x = calloc(1, sizeof *x);
    sound_mix_desc d = { .volume_db = a->volume_db, .ceiling_dbfs = a->volume_max_dbfs,
                         .quiet = a->quiet };
    if (!x || !(x->mix = sound_mix_create(&d, &err))) {
        fprintf(stderr, "gale-client: sound: %s\n", x ? err.msg : "no memory");
        free(x);
        return -1;
    }
    float vol, ceil;
    sound_mix_resolve(&d, &vol, &ceil);
    x->scene = (sound_scene){ .gust = 1.0f, .kept = 1.0f };
    x->last_event = -1;
    x->listen_at_s = -1.0;
    x->frame_period_s = 1.0 / (a->max_fps > 0.0 ? a->max_fps : 60.0);
    c->aud = x;
    if (a->audio_out) {
        if (wav_writer_open(&x->wav, a->audio_out, SOUND_CHANNELS, SOUND_RATE_HZ, &err) != 0) {
            fprintf(stderr, "gale-client: --audio-out: %s\n", err.msg);
            return -1;
        }
        x->wav_open = true;
        fprintf(stderr, "gale-client: sound to %s (48 kHz 16-bit stereo, %.4f s a frame), "
                        "volume %.1f dB, ceiling %.1f dBFS%s\n",
                a->audio_out, x->frame_period_s, (double)vol, (double)ceil,
                a->quiet ? " (quiet)" : "");
        return 0;
    }
    char why[256];
    x->out = audio_out_open(x->mix, a->audio_device, why, sizeof why);
    if (!x->out) {
        fprintf(stderr, "gale-client: sound: no memory for the device\n");
        return -1;
    }
    if (audio_out_live(x->out)) {
        fprintf(stderr, "gale-client: sound on %s, volume %.1f dB, ceiling %.1f dBFS%s\n",
                audio_device_name(x->out), (double)vol, (double)ceil, a->quiet ? " (quiet)" : "");
    } else {
        fprintf(stderr, "gale-client: sound: no output device (%s): the null device, "
                        "captions only\n", why);
    }
    return 0;
}

const char *client_audio_device_name(const client *c)
{
    return c->aud ? audio_device_name(c->aud->out) : "null";
}

void client_audio_species(client *c, int render_id, const asset *a)
{
    if (c->aud && render_id >= 0 && render_id < (int)RENDER_MAX_SPECIES) {
        sound_species_profile(a, &c->aud->prof[render_id]);
        c->aud->have_prof[render_id] = true;
    }
}

void client_audio_event(client *c, uint32_t tree, int wire_kind, double t0_s)
{
    client_audio *x = c->aud;
    if (!x || isnan(t0_s)) {
        return; /* an old event shows its end, and makes no sound */
    }
    int kind = wire_kind == WIRE_DAMAGE_SNAP     ? SOUND_EV_SNAP
               : wire_kind == WIRE_DAMAGE_UPROOT ? SOUND_EV_UPROOT
               : wire_kind == WIRE_DAMAGE_BRANCH ? SOUND_EV_CRACK
                                                 : -1;
    if (kind < 0) {
        return;
    }
    if (x->n_pend == PENDING_MAX) {
        x->dropped++;
        return;
    }
    x->pend[x->n_pend++] = (pending_event){ .tree = tree, .kind = kind, .t0_s = t0_s };
}

void client_audio_volume(client *c, int dir)
{
    if (c->aud) {
        sound_mix_visitor_step(c->aud->mix, dir);
        sound_mix_state st = sound_mix_get_state(c->aud->mix);
        fprintf(stderr, "gale-client: sound: volume %.1f dB (visitor %+.0f dB)\n",
                (double)st.volume_db, (double)st.visitor_db);
    }
}

void client_audio_idle(client *c)
{
    if (c->aud) {
        sound_mix_visitor_reset(c->aud->mix);
        fprintf(stderr, "gale-client: sound: kiosk idle, volume back to the default\n");
    }
}

/* The wind at the listener: the streamed grid at the camera's ground point, at
 * SOUND_LISTEN_Z_M, else the weather's sustained wind; the weather's gust factor. */
static void listener_wind(client *c, const float eye[3], sound_scene *s)
{
    float u = c->have_wx ? c->wx.sustained_ms : 0.0f;
    if (c->have_wind && c->r) {
        const float p[3] = { eye[0], eye[1], SOUND_LISTEN_Z_M };
        float w[3];
        render_wind_sample(c->r, p, w);
        u = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    s->u_ms = isfinite(u) ? u : 0.0f;
    s->gust = c->have_wx && c->wx.sustained_ms > 0.5f
                  ? fmaxf(c->wx.gust_ms / c->wx.sustained_ms, 1.0f)
                  : 1.0f;
}

static void fire_due(client *c, client_audio *x, double render_t, const float eye[3])
{
    float f[3];
    camera_forward(&c->cam, f);
    const float look = atan2f(f[1], f[0]);
    int kept = 0;
    for (int i = 0; i < x->n_pend; i++) {
        pending_event *e = &x->pend[i];
        if (e->t0_s > render_t) {
            x->pend[kept++] = *e; /* not in the picture yet */
            continue;
        }
        if (e->tree >= c->w.n_instances) {
            continue;
        }
        const float *p = c->w_instances[e->tree].pos;
        /* heard from the stem's middle, about 5 m up */
        float d[3] = { p[0] - eye[0], p[1] - eye[1], p[2] + 5.0f - eye[2] };
        float dist = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        float rel = atan2f(d[1], d[0]) - look;
        rel = atan2f(sinf(rel), cosf(rel));
        uint64_t id = ++x->next_id;
        float db = sound_mix_event(x->mix, e->kind, dist, rel, id);
        if (!isfinite(db)) {
            x->too_far++;
            continue;
        }
        if (x->n_fired < LOGGED_MAX) {
            x->fired[x->n_fired++] = (fired_event){
                .id = id, .frame_s = x->clock_s, .frame_server_s = render_t, .tree = e->tree,
                .kind = e->kind, .dist_m = dist, .rel_rad = rel, .db = db, .frame_no = x->frames };
        }
        x->last_event = e->kind;
        x->last_event_s = x->clock_s;
        x->played++;
    }
    x->n_pend = kept;
}

static const char *const ev_name[SOUND_EVENTS] = { "crack", "snap", "uproot" };

/* A line per event whose sound has begun: the frame's time and the sound's, on one clock. */
static void log_started(client_audio *x)
{
    uint64_t id, first;
    while (sound_mix_take_started(x->mix, &id, &first)) {
        for (int i = 0; i < x->n_fired; i++) {
            if (x->fired[i].id != id) {
                continue;
            }
            double sound_s = x->out ? audio_out_play_time_s(x->out, first)
                                    : (double)first / SOUND_RATE_HZ;
            double gap_ms = 1e3 * (sound_s - x->fired[i].frame_s);
            if (isfinite(gap_ms) && fabs(gap_ms) * 1e3 > (double)x->max_gap_us) {
                x->max_gap_us = (uint64_t)(fabs(gap_ms) * 1e3);
            }
            fprintf(stderr,
                    "gale-client: sound %s tree %u dist_m %.1f bearing_deg %.0f level_db %.1f "
                    "frame %llu server_s %.4f frame_s %.4f sound_s %.4f gap_ms %.1f (%s clock)\n",
                    ev_name[x->fired[i].kind], x->fired[i].tree, (double)x->fired[i].dist_m,
                    (double)x->fired[i].rel_rad * 57.29578, (double)x->fired[i].db,
                    (unsigned long long)x->fired[i].frame_no, x->fired[i].frame_server_s,
                    x->fired[i].frame_s, sound_s, gap_ms, x->out ? "monotonic" : "wav");
            x->fired[i] = x->fired[--x->n_fired];
            break;
        }
    }
}

/* Headless: the frame's share of sound into the WAV. */
static void write_frame(client *c, client_audio *x)
{
    x->owed_frames += x->frame_period_s * SOUND_RATE_HZ;
    uint32_t n = (uint32_t)x->owed_frames;
    x->owed_frames -= n;
    int16_t buf[2048 * SOUND_CHANNELS];
    gale_err err = { 0 };
    while (n > 0) {
        uint32_t k = n > 2048 ? 2048 : n;
        sound_mix_render(x->mix, buf, k);
        if (x->wav_open && wav_writer_write(&x->wav, buf, k, &err) != 0) {
            fprintf(stderr, "gale-client: --audio-out %s: %s; no more sound written\n",
                    c->a.audio_out, err.msg);
            wav_writer_close(&x->wav, NULL);
            x->wav_open = false;
        }
        n -= k;
    }
}

void client_audio_frame(client *c, double render_t, double now_mono)
{
    client_audio *x = c->aud;
    if (!x) {
        return;
    }
    /* on a device, the frame's time is now, its picture finished and about to be presented
       (its start, now_mono, is a software renderer's whole frame earlier) */
    (void)now_mono;
    x->clock_s = x->out ? mono_s() : (double)sound_mix_get_state(x->mix).frames / SOUND_RATE_HZ;
    float eye[3];
    camera_eye(&c->cam, eye);
    listener_wind(c, eye, &x->scene);
    /* the trees near, four times a second of the audio clock */
    if (c->scene_ready && (x->listen_at_s < 0.0 || x->clock_s - x->listen_at_s >= 0.25 ||
                           x->clock_s < x->listen_at_s)) {
        for (uint32_t s = 0; s < c->w.n_species && s < CLIENT_MAX_SPECIES; s++) {
            int id = c->species_id[s];
            x->by_welcome[s] = id >= 0 && id < (int)RENDER_MAX_SPECIES && x->have_prof[id]
                                   ? x->prof[id] : (sound_species){ 0 };
        }
        sound_listen(eye, c->w_instances, c->w.n_instances, x->by_welcome,
                     c->w.n_species < CLIENT_MAX_SPECIES ? c->w.n_species : CLIENT_MAX_SPECIES,
                     c->dmg.tree ? &c->dmg : NULL, &x->scene);
        x->listen_at_s = x->clock_s;
    }
    sound_mix_set_scene(x->mix, &x->scene);
    fire_due(c, x, render_t, eye);
    if (!x->out) {
        write_frame(c, x);
    }
    log_started(x);
    x->frames++;
    /* the caption line: the one-shot of the last few seconds, the wind, leaves, twigs */
    const sound_scene *s = &x->scene;
    float loud = -INFINITY;
    for (int k = 0; k < SOUND_CLASSES; k++) {
        loud = fmaxf(loud, sound_aeol_db(s->class_len_m[k], s->u_ms, sound_class_d_m[k]));
    }
    int ev = x->last_event >= 0 && x->clock_s - x->last_event_s < (double)SOUND_CAPTION_EVENT_S
                 ? x->last_event : -1;
    int keys[4];
    int n = sound_caption_pick(s->u_ms, sound_rustle_hz(s->u_ms, s->leaves_w, s->kept), loud,
                               ev, keys);
    sound_caption_line(c->lang, keys, n, x->caption, sizeof x->caption);
}

const char *client_audio_caption(const client *c)
{
    return c->aud && c->aud->caption[0] ? c->aud->caption : NULL;
}

void client_audio_stop(client *c)
{
    client_audio *x = c->aud;
    if (!x) {
        return;
    }
    char device[160];
    snprintf(device, sizeof device, "%s", audio_device_name(x->out)); /* o's, freed below */
    audio_out_close(x->out); /* the thread stops before the mixer goes */
    sound_mix_state st = sound_mix_get_state(x->mix);
    gale_err err = { 0 };
    if (x->wav_open && wav_writer_close(&x->wav, &err) != 0) {
        fprintf(stderr, "gale-client: --audio-out: %s\n", err.msg);
    }
    fprintf(stderr,
            "gale-client: sound: %llu frames (%.2f s), peak %d of %d (%.2f dBFS), limiter "
            "least gain %.3f, clamped %llu; events played %llu, too far %llu, dropped %llu, "
            "largest gap %.1f ms; device %s\n",
            (unsigned long long)st.frames, (double)st.frames / SOUND_RATE_HZ, st.peak,
            (int)floorf(sound_db_to_gain(st.ceiling_dbfs) * 32767.0f),
            st.peak > 0 ? 20.0 * log10((double)st.peak / 32767.0) : -(double)INFINITY,
            (double)st.min_gain, (unsigned long long)st.clamped, (unsigned long long)x->played,
            (unsigned long long)x->too_far, (unsigned long long)x->dropped,
            (double)x->max_gap_us * 1e-3, device);
    sound_mix_destroy(x->mix);
    free(x);
    c->aud = NULL;
}
