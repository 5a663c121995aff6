/* client/audio without a server: aeolian tones at St·U/d (the FFT's peak of one diameter
 * class within 3 % of 0.2 U/d), the look-ahead limiter (no sample over its ceiling, the
 * last clamp never needed, a signal under the ceiling passed untouched but for the delay),
 * the mixer at its loudest (a Category 5 wind and sixteen snaps at 1 m under the quiet
 * preset and the default) never over the ceiling, the wind bed's level and centre following
 * the speed, the rustle's density law, what is near the listener, the captions, a WAV
 * written and read back, and the null device on a machine without one. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "aeolian.h"
#include "audio_out.h"
#include "check.h"
#include "lang.h"
#include "limiter.h"
#include "rustle.h"
#include "sound_caption.h"
#include "sound_listener.h"
#include "sound_mix.h"
#include "wav_stats.h"
#include "wav_writer.h"
#include "wind_bed.h"

/* n frames of one source rendered into an in-memory WAV */
static wav_pcm pcm_new(uint32_t n)
{
    wav_pcm w = { .s = calloc((size_t)n * 2, sizeof(int16_t)), .frames = n, .channels = 2,
                  .rate_hz = SOUND_RATE_HZ };
    return w;
}

static void put(wav_pcm *w, uint32_t at, const float *l, const float *r, int n, float gain)
{
    for (int i = 0; i < n; i++) {
        w->s[2 * (at + (uint32_t)i)] = (int16_t)lrintf(fmaxf(fminf(l[i] * gain, 1.0f), -1.0f) * 32767.0f);
        w->s[2 * (at + (uint32_t)i) + 1] = (int16_t)lrintf(fmaxf(fminf(r[i] * gain, 1.0f), -1.0f) * 32767.0f);
    }
}

/* One diameter class alone at a known speed: the spectrum peaks at 0.2 U/d. */
static void test_strouhal(void)
{
    static const struct { float u, d; } cases[] = {
        { 20.0f, 0.001f }, /* a pine needle: 4 kHz */
        { 20.0f, 0.01f },  /* a twig: 400 Hz */
        { 10.0f, 0.00316f },
        { 45.0f, 0.0316f },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        float len[SOUND_CLASSES] = { 0 };
        len[sound_class_of(cases[c].d)] = SOUND_AEOL_LEN_REF_M;
        CHECK_NEAR(sound_class_d_m[sound_class_of(cases[c].d)], cases[c].d, 1e-6);
        aeolian a;
        aeolian_init(&a, 7u);
        const uint32_t n = 2 * SOUND_RATE_HZ;
        wav_pcm w = pcm_new(n);
        float l[256], r[256];
        for (uint32_t at = 0; at < n; at += 256) {
            memset(l, 0, sizeof l);
            memset(r, 0, sizeof r);
            aeolian_render(&a, cases[c].u, len, l, r, 256);
            put(&w, at, l, r, 256, 1.0f);
        }
        wav_stats st = wav_stats_of(&w, SOUND_RATE_HZ / 4, 0);
        const double want = 0.2 * (double)cases[c].u / (double)cases[c].d;
        printf("strouhal: U %.0f m/s d %.2f mm: peak %.1f Hz, 0.2 U/d %.1f Hz (%.2f %%), "
               "rms %.1f dBFS\n", (double)cases[c].u, 1e3 * (double)cases[c].d, st.peak_hz, want,
               100.0 * (st.peak_hz - want) / want, st.rms_dbfs);
        CHECK_NEAR(st.peak_hz, want, 0.03 * want);
        /* its level is the policy's RMS within 1.5 dB */
        CHECK_NEAR(st.rms_dbfs, sound_aeol_db(SOUND_AEOL_LEN_REF_M, cases[c].u, cases[c].d), 1.5);
        wav_pcm_free(&w);
    }
    CHECK_NEAR(sound_strouhal_hz(20.0f, 0.001f), 4000.0, 1e-2);
    CHECK_NEAR(sound_strouhal_hz(20.0f, 0.01f), 400.0, 1e-3);
}

/* Any signal at any level leaves the limiter at or under its ceiling, with the final clamp
 * unused; one under the ceiling leaves as it came, len samples late. */
static void test_limiter(void)
{
    static const float ceilings[] = { -1.0f, -6.0f, -14.0f };
    for (size_t c = 0; c < sizeof ceilings / sizeof ceilings[0]; c++) {
        limiter lim;
        limiter_init(&lim, ceilings[c], SOUND_LIMIT_LOOKAHEAD_MS, SOUND_LIMIT_RELEASE_MS, SOUND_RATE_HZ);
        const float ceil = powf(10.0f, ceilings[c] / 20.0f);
        uint32_t rng = 99u;
        float peak = 0.0f;
        for (int blk = 0; blk < 2000; blk++) {
            float l[64], r[64];
            for (int i = 0; i < 64; i++) {
                const float t = (float)(blk * 64 + i) / (float)SOUND_RATE_HZ;
                /* a 12 dB-over sine, with single-sample spikes 30 dB over now and then */
                float x = 4.0f * sinf(6.2831853f * 440.0f * t);
                if (sound_uniform(&rng) < 0.002f) {
                    x = 31.6f * sound_noise(&rng);
                }
                l[i] = x;
                r[i] = -0.5f * x;
            }
            limiter_run(&lim, l, r, 64);
            for (int i = 0; i < 64; i++) {
                peak = fmaxf(peak, fmaxf(fabsf(l[i]), fabsf(r[i])));
            }
        }
        printf("limiter: ceiling %.0f dBFS: peak out %.3f dBFS, least gain %.4f, clamped %llu\n",
               (double)ceilings[c], 20.0 * log10((double)peak), (double)lim.min_gain,
               (unsigned long long)lim.clamped);
        CHECK(peak <= ceil);
        CHECK(lim.clamped == 0);
        CHECK(peak > 0.9f * ceil); /* it limits, it does not mute */
    }
    /* under the ceiling: untouched */
    limiter lim;
    limiter_init(&lim, -1.0f, SOUND_LIMIT_LOOKAHEAD_MS, SOUND_LIMIT_RELEASE_MS, SOUND_RATE_HZ);
    float in[4096], l[4096], r[4096];
    for (int i = 0; i < 4096; i++) {
        in[i] = l[i] = r[i] = 0.5f * sinf(0.05f * (float)i);
    }
    limiter_run(&lim, l, r, 4096);
    float worst = 0.0f;
    for (int i = lim.len; i < 4096; i++) {
        worst = fmaxf(worst, fabsf(l[i] - in[i - lim.len]));
    }
    CHECK(lim.len == 96);
    CHECK(worst < 1e-6f);
}

/* The mixer at its loudest: a Category 5 wind, many needles and twigs near, sixteen
 * one-shots at 1 m: no sample over the ceiling, default or quiet. */
static void test_mix_ceiling(void)
{
    for (int quiet = 0; quiet < 2; quiet++) {
        sound_mix_desc d = { .volume_db = 0.0f, .ceiling_dbfs = -3.0f, .quiet = quiet };
        sound_mix *m = sound_mix_create(&d, NULL);
        CHECK(m != NULL);
        if (!m) {
            return;
        }
        sound_scene s = { .u_ms = 75.0f, .gust = 1.4f, .leaves_w = 1e6f, .kept = 1.0f };
        for (int k = 0; k < SOUND_CLASSES; k++) {
            s.class_len_m[k] = 1e5f;
        }
        sound_mix_set_scene(m, &s);
        int16_t buf[4800 * 2];
        for (int i = 0; i < 100; i++) {
            if (i % 5 == 0) {
                for (int e = 0; e < SOUND_VOICES; e++) {
                    sound_mix_event(m, e % SOUND_EVENTS, 1.0f, 0.3f * (float)e, (uint64_t)e);
                }
            }
            sound_mix_render(m, buf, 4800);
        }
        sound_mix_state st = sound_mix_get_state(m);
        float vol, ceil_db;
        sound_mix_resolve(&d, &vol, &ceil_db);
        const int lim = (int)floorf(powf(10.0f, ceil_db / 20.0f) * 32767.0f);
        printf("mix%s: ceiling %.0f dBFS (%d): peak %d, least gain %.3f, clamped %llu\n",
               quiet ? " (quiet)" : "", (double)ceil_db, lim, st.peak, (double)st.min_gain,
               (unsigned long long)st.clamped);
        CHECK(st.peak <= lim);
        CHECK(st.peak > lim * 9 / 10);
        CHECK(st.clamped == 0);
        CHECK_NEAR(ceil_db, quiet ? SOUND_QUIET_CEILING_DBFS : -3.0f, 1e-6);
        sound_mix_destroy(m);
    }
}

/* Louder and brighter with the wind: the bed's own level and centroid. */
static void test_bed_follows_wind(void)
{
    static const float u[] = { 4.5f, 15.0f, 53.5f };
    double last_rms = -INFINITY, last_centroid = 0.0;
    for (int c = 0; c < 3; c++) {
        wind_bed b;
        wind_bed_init(&b, 5u);
        const uint32_t n = 2 * SOUND_RATE_HZ;
        wav_pcm w = pcm_new(n);
        float l[256], r[256];
        for (uint32_t at = 0; at < n; at += 256) {
            memset(l, 0, sizeof l);
            memset(r, 0, sizeof r);
            wind_bed_render(&b, u[c], l, r, 256);
            put(&w, at, l, r, 256, 1.0f);
        }
        wav_stats st = wav_stats_of(&w, SOUND_RATE_HZ / 4, 0);
        /* the bands' RMS summed in power */
        double want = 0.0;
        for (int k = 0; k < SOUND_BANDS; k++) {
            want += pow((double)wind_bed_band_gain(k, u[c]), 2.0);
        }
        printf("bed: U %.1f m/s: %.1f dBFS (bands %.1f), centroid %.0f Hz\n", (double)u[c],
               st.rms_dbfs, 10.0 * log10(want), st.centroid_hz);
        CHECK_NEAR(st.rms_dbfs, 10.0 * log10(want), 1.0);
        CHECK(st.rms_dbfs > last_rms + 6.0);
        CHECK(st.centroid_hz > last_centroid * 1.2);
        last_rms = st.rms_dbfs;
        last_centroid = st.centroid_hz;
        wav_pcm_free(&w);
    }
    CHECK(!isfinite(sound_bed_db(0.2f)));
    CHECK_NEAR(sound_bed_db(SOUND_U_REF_MS), SOUND_BED_DB_REF, 1e-5);
    CHECK_NEAR(sound_howl_share(10.0f), 0.0, 0.0);
    CHECK_NEAR(sound_howl_share(60.0f), 1.0, 0.0);
}

/* The rustle's density: up with the speed, down as the crowns are stripped, none without
 * leaves; and the clicks made match it (a Poisson count within 4 σ). */
static void test_rustle(void)
{
    CHECK(sound_rustle_hz(10.0f, 5000.0f, 1.0f) > sound_rustle_hz(5.0f, 5000.0f, 1.0f));
    CHECK_NEAR(sound_rustle_hz(10.0f, 5000.0f, 0.25f), 0.25 * (double)sound_rustle_hz(10.0f, 5000.0f, 1.0f), 1e-3);
    CHECK(sound_rustle_hz(10.0f, 0.0f, 1.0f) == 0.0f);
    CHECK(sound_rustle_hz(1.0f, 5000.0f, 1.0f) == 0.0f);
    CHECK(sound_rustle_hz(200.0f, 1e9f, 1.0f) <= SOUND_RUSTLE_MAX_HZ);
    rustle s;
    rustle_init(&s, 3u);
    const float hz = 120.0f;
    float l[480], r[480];
    for (int i = 0; i < 1000; i++) { /* 10 s */
        rustle_render(&s, hz, 0.1f, l, r, 480);
    }
    printf("rustle: %llu clicks in 10 s at %.0f a second\n", (unsigned long long)s.clicks, (double)hz);
    CHECK_NEAR((double)s.clicks, 10.0 * (double)hz, 4.0 * sqrt(10.0 * (double)hz));
}

/* A two-node asset: its segment's class and its needles; trees near count with the
 * inverse square, a fallen one not at all, a stripped one its leaves' share. */
static void test_listener(void)
{
    int32_t parent[3] = { -1, 0, 1 };
    float rest[9] = { 0, 0, 0, 0, 0, 4, 0, 0, 6 }, radius[3] = { 0.15f, 0.05f, 0.004f };
    uint32_t leaf_node[2] = { 2, 2 };
    float leaf_size[2] = { 0.1f, 0.1f };
    asset a = { .n_nodes = 3, .parent = parent, .rest = rest, .radius = radius, .n_leaves = 2,
                .leaf_node = leaf_node, .leaf_size = leaf_size, .leaf_shape = 2 };
    sound_species p;
    sound_species_profile(&a, &p);
    CHECK_NEAR(p.class_len_m[sound_class_of(0.1f)], 4.0, 1e-5);
    CHECK_NEAR(p.class_len_m[sound_class_of(0.008f)], 2.0, 1e-5);
    CHECK_NEAR(p.class_len_m[0], 2.0 * (double)SOUND_NEEDLES_PER_TUFT * 0.1, 1e-5);
    a.leaf_shape = 0;
    sound_species broad;
    sound_species_profile(&a, &broad);
    CHECK_NEAR(broad.leaves, 2.0, 0.0);
    const sound_species prof[2] = { p, broad };
    ctl_instance in[3] = { { .species = 1, .pos = { 5, 0, 0 }, .scale = 1 },
                           { .species = 1, .pos = { 0, 20, 0 }, .scale = 1 },
                           { .species = 0, .pos = { 500, 0, 0 }, .scale = 1 } };
    const float eye[2] = { 0, 0 };
    sound_scene s = { 0 };
    sound_listen(eye, in, 3, prof, 2, NULL, &s);
    CHECK_NEAR(s.leaves_w, 2.0 * (1.0 + 0.25), 1e-5);
    CHECK_NEAR(s.kept, 1.0, 0.0);
    CHECK_NEAR(s.class_len_m[sound_class_of(0.1f)], 4.0 * 1.25, 1e-5);
    damage_view_tree dt[3] = { { .level = WIRE_DAMAGE_LEVELS / 2 }, { .fallen = WIRE_DAMAGE_SNAP },
                               { .level = WIRE_DAMAGE_LEVELS } };
    damage_view dv = { .n_trees = 3, .tree = dt };
    sound_listen(eye, in, 3, prof, 2, &dv, &s);
    CHECK_NEAR(s.kept, (0.5 * 2.0) / 2.5, 1e-5);
    CHECK_NEAR(s.class_len_m[sound_class_of(0.1f)], 4.0, 1e-5);
}

static void test_captions(void)
{
    int k[4];
    char line[160];
    int n = sound_caption_pick(53.5f, 200.0f, -20.0f, SOUND_EV_SNAP, k);
    CHECK(n == 4);
    CHECK_STR_HAS(sound_caption_line(LANG_EN, k, n, line, sizeof line),
                  "[tree snaps] [wind howling] [leaves rustling] [twigs whistling]");
    n = sound_caption_pick(4.5f, 5.0f, -80.0f, -1, k);
    CHECK(n == 1 && k[0] == SOUND_CAP_WIND_WHISPERING);
    CHECK(sound_caption_pick(0.0f, 0.0f, -INFINITY, -1, k) == 0);
    for (int i = 0; i < SOUND_CAPS; i++) {
        CHECK(strncmp(sound_caption_key(i), "sound.", 6) == 0);
        CHECK(sound_caption_text(LANG_EN, i)[0] == '[' && sound_caption_text(LANG_HT, i)[0] == '[');
    }
    CHECK(sound_caption_key(SOUND_CAPS) == NULL);
}

static void test_wav_roundtrip(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/test_audio.wav", GALE_TEST_DIR);
    wav_writer w;
    CHECK(wav_writer_open(&w, path, 2, SOUND_RATE_HZ, NULL) == 0);
    int16_t s[2000];
    for (int i = 0; i < 1000; i++) {
        s[2 * i] = (int16_t)(i * 30 - 15000);
        s[2 * i + 1] = (int16_t)-i;
    }
    CHECK(wav_writer_write(&w, s, 1000, NULL) == 0);
    CHECK(wav_writer_close(&w, NULL) == 0);
    wav_pcm p;
    gale_err err = { 0 };
    CHECK(wav_pcm_load(path, &p, &err) == 0);
    CHECK(p.frames == 1000 && p.channels == 2 && p.rate_hz == SOUND_RATE_HZ);
    CHECK(p.s && memcmp(p.s, s, sizeof s) == 0);
    wav_pcm_free(&p);
    FILE *f = fopen(path, "wb");
    fputs("RIFX", f);
    fclose(f);
    CHECK(wav_pcm_load(path, &p, &err) == GALE_E_FORMAT);
    CHECK_STR_HAS(err.msg, "expected a RIFF WAVE header");
    unlink(path);
}

/* Without a sound device (CI) the null device, named so; with one, a name. */
static void test_device(void)
{
    sound_mix *m = sound_mix_create(&(sound_mix_desc){ .volume_db = -60.0f, .ceiling_dbfs = -40.0f }, NULL);
    char why[256];
    audio_out *o = audio_out_open(m, NULL, why, sizeof why);
    CHECK(o != NULL);
    printf("device: %s%s%s\n", audio_device_name(o), why[0] ? ": " : "", why);
    if (!audio_out_live(o)) {
        CHECK(strcmp(audio_device_name(o), "null") == 0);
        CHECK(why[0] != '\0');
        CHECK(isnan(audio_out_play_time_s(o, 0)));
    } else {
        CHECK(strcmp(audio_device_name(o), "null") != 0);
    }
    audio_out_close(o);
    o = audio_out_open(m, "no-such-pcm-gale", why, sizeof why);
    CHECK(o && !audio_out_live(o) && strcmp(audio_device_name(o), "null") == 0);
    audio_out_close(o);
    audio_out_close(NULL);
    sound_mix_destroy(m);
}

/* A WAV whose rate leaves the measures' windows without a whole sample (the fuzzer's 3 Hz
 * file looped for ever in the 0.1 s envelope) is refused with its rate named. */
static void test_wav_rate_refused(void)
{
    static const uint8_t hdr[44] = { 'R', 'I', 'F', 'F', 36, 0, 0, 0, 'W', 'A', 'V', 'E',
                                     'f', 'm', 't', ' ', 16, 0, 0, 0, 1, 0, 2, 0,
                                     3, 0, 0, 0, 12, 0, 0, 0, 4, 0, 16, 0,
                                     'd', 'a', 't', 'a', 0, 0, 0, 0 };
    wav_pcm w;
    gale_err e = { 0 };
    CHECK(wav_pcm_parse(hdr, sizeof hdr, "slow.wav", &w, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "slow.wav: expected 16-bit PCM of 1..8 channels at 8000..384000 Hz");
    CHECK_STR_HAS(e.msg, "3 Hz");
}

int main(void)
{
    RUN(test_strouhal);
    RUN(test_wav_rate_refused);
    RUN(test_limiter);
    RUN(test_mix_ceiling);
    RUN(test_bed_follows_wind);
    RUN(test_rustle);
    RUN(test_listener);
    RUN(test_captions);
    RUN(test_wav_roundtrip);
    RUN(test_device);
    return check_report();
}
