/* The sound device (audio_out.h). ALSA is the library: libasound2 is on every Debian
 * desktop and console (mesa's and chromium's dependencies pull it), its "default" PCM
 * reaches PipeWire or PulseAudio through their ALSA plugins and the card without them, and
 * on a machine with neither it fails at open, which is the null device's cue. Its own
 * error printing is silenced so a headless run's log holds our one line. */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "audio_out.h"

#ifdef GALE_HAVE_ALSA
#include <alsa/asoundlib.h>
#endif

#define PERIOD_FRAMES 240u   /* 5 ms */
#define LATENCY_US 20000u    /* queued: with a period, a sound is out within 25 ms of its frame */

struct audio_out {
    sound_mix *mix;
    char name[160];
    bool live;
#ifdef GALE_HAVE_ALSA
    snd_pcm_t *pcm;
    pthread_t thread;
    volatile int stop;
    pthread_mutex_t lock;
    uint64_t written;  /* frames written to the device */
    long queued;       /* frames the device held after the last write */
    double at_s;       /* when */
    bool have_clock;
#endif
};

static double mono_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#ifdef GALE_HAVE_ALSA
static void quiet_alsa(const char *file, int line, const char *fn, int err, const char *fmt, ...)
{
    (void)file, (void)line, (void)fn, (void)err, (void)fmt;
}

/* A PCM that takes periods faster than it plays them (ALSA's null plugin, a file) would
 * let the mixer run ahead of the picture: the thread keeps at most the latency ahead of
 * the wall clock. */
static void pace(double t0_s, uint64_t frames)
{
    double ahead = (double)frames / SOUND_RATE_HZ - (mono_now_s() - t0_s) - 1e-6 * LATENCY_US;
    if (ahead > 0.0) {
        struct timespec ts = { .tv_sec = (time_t)ahead,
                               .tv_nsec = (long)((ahead - (double)(time_t)ahead) * 1e9) };
        nanosleep(&ts, NULL);
    }
}

static void *feed(void *arg)
{
    audio_out *o = arg;
    int16_t buf[PERIOD_FRAMES * SOUND_CHANNELS];
    double t0 = mono_now_s();
    uint64_t since_t0 = 0;
    while (!o->stop) {
        pace(t0, since_t0);
        sound_mix_render(o->mix, buf, PERIOD_FRAMES);
        snd_pcm_sframes_t w = snd_pcm_writei(o->pcm, buf, PERIOD_FRAMES);
        if (w < 0) {
            w = snd_pcm_recover(o->pcm, (int)w, 1); /* an underrun: start again */
            t0 = mono_now_s();
            since_t0 = 0;
            if (w < 0) {
                fprintf(stderr, "gale-client: sound: %s: %s; sound stops\n", o->name,
                        snd_strerror((int)w));
                break;
            }
            continue;
        }
        snd_pcm_sframes_t delay = 0;
        if (snd_pcm_delay(o->pcm, &delay) < 0) {
            delay = (snd_pcm_sframes_t)(LATENCY_US * (uint64_t)SOUND_RATE_HZ / 1000000u);
        }
        since_t0 += (uint64_t)w;
        pthread_mutex_lock(&o->lock);
        o->written += (uint64_t)w;
        o->queued = (long)delay;
        o->at_s = mono_now_s();
        o->have_clock = true;
        pthread_mutex_unlock(&o->lock);
    }
    return NULL;
}
#endif

audio_out *audio_out_open(sound_mix *m, const char *device, char *why, int why_cap)
{
    audio_out *o = calloc(1, sizeof *o);
    if (!o) {
        return NULL;
    }
    o->mix = m;
    snprintf(o->name, sizeof o->name, "null");
    if (why_cap > 0) {
        why[0] = '\0';
    }
#ifdef GALE_HAVE_ALSA
    const char *dev = device ? device : "default";
    snd_lib_error_set_handler(quiet_alsa);
    int rc = snd_pcm_open(&o->pcm, dev, SND_PCM_STREAM_PLAYBACK, 0);
    if (rc == 0) {
        rc = snd_pcm_set_params(o->pcm, SND_PCM_FORMAT_S16_LE, SND_PCM_ACCESS_RW_INTERLEAVED,
                                SOUND_CHANNELS, SOUND_RATE_HZ, 1, LATENCY_US);
    }
    if (rc != 0) {
        snprintf(why, (size_t)why_cap, "ALSA PCM \"%s\": %s", dev, snd_strerror(rc));
        if (o->pcm) {
            snd_pcm_close(o->pcm);
            o->pcm = NULL;
        }
        return o;
    }
    snd_pcm_info_t *info;
    snd_pcm_info_alloca(&info);
    const char *card = snd_pcm_info(o->pcm, info) == 0 ? snd_pcm_info_get_name(info) : NULL;
    snprintf(o->name, sizeof o->name, "%s%s%s", dev, card ? ": " : "", card ? card : "");
    pthread_mutex_init(&o->lock, NULL);
    if (pthread_create(&o->thread, NULL, feed, o) != 0) {
        snprintf(why, (size_t)why_cap, "%s: no thread to feed it", o->name);
        snd_pcm_close(o->pcm);
        o->pcm = NULL;
        snprintf(o->name, sizeof o->name, "null");
        return o;
    }
    o->live = true;
#else
    (void)device;
    snprintf(why, (size_t)why_cap, "built without ALSA (libasound2-dev)");
#endif
    return o;
}

void audio_out_close(audio_out *o)
{
    if (!o) {
        return;
    }
#ifdef GALE_HAVE_ALSA
    if (o->live) {
        o->stop = 1;
        pthread_join(o->thread, NULL);
        snd_pcm_drop(o->pcm);
        pthread_mutex_destroy(&o->lock);
    }
    if (o->pcm) {
        snd_pcm_close(o->pcm);
    }
#endif
    free(o);
}

bool audio_out_live(const audio_out *o)
{
    return o && o->live;
}

const char *audio_device_name(const audio_out *o)
{
    return o ? o->name : "null";
}

double audio_out_play_time_s(audio_out *o, uint64_t frame)
{
    double t = (double)NAN;
#ifdef GALE_HAVE_ALSA
    if (o && o->live) {
        pthread_mutex_lock(&o->lock);
        if (o->have_clock) {
            /* the last written frame leaves after the queue: frame leaves that much sooner
             * or later than it */
            double ahead = ((double)frame - (double)o->written) / SOUND_RATE_HZ;
            t = o->at_s + (double)o->queued / SOUND_RATE_HZ + ahead;
        }
        pthread_mutex_unlock(&o->lock);
    }
#else
    (void)o, (void)frame;
#endif
    return t;
}
