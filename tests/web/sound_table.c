/* gale-client's sound policy (client/audio/sound_policy.h, sound_caption.c) as one JSON
 * object, for tests/web/test_sound_policy_js.mjs to hold web/sound_policy.js to: every
 * number under the page's name, the laws over a range of speeds, lengths, distances and
 * bearings, the class of a range of diameters, the quiet preset's loudness, the caption
 * table and what it picks for a range of states. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sound_caption.h"
#include "sound_listener.h"
#include "sound_mix.h"
#include "sound_policy.h"

static void num(const char *name, double v)
{
    if (isfinite(v)) {
        printf("\"%s\":%.9g,", name, v);
    } else {
        printf("\"%s\":%s,", name, v > 0 ? "\"inf\"" : "\"-inf\"");
    }
}

static void floats(const char *name, const float *v, int n)
{
    printf("\"%s\":[", name);
    for (int i = 0; i < n; i++) {
        printf("%s%.9g", i ? "," : "", (double)v[i]);
    }
    printf("],");
}

/* a value in a table row: "-inf" for -INFINITY */
static void cell(double v, int last)
{
    if (isfinite(v)) {
        printf("%.9g%s", v, last ? "" : ",");
    } else {
        printf("\"%s\"%s", v > 0 ? "inf" : "-inf", last ? "" : ",");
    }
}

#define N(x) num(#x, (double)(x))

int main(int argc, char **argv)
{
    if (argc > 1) {
        printf("usage: gale-web-sound-table (prints the sound policy as JSON)\n");
        return strcmp(argv[1], "--help") == 0 ? 0 : 2;
    }
    printf("{\"numbers\":{");
    N(SOUND_RATE_HZ); N(SOUND_CHANNELS); N(SOUND_STROUHAL); N(SOUND_CLASSES);
    N(SOUND_NEEDLE_D_M); N(SOUND_NEEDLES_PER_TUFT); N(SOUND_AEOL_F_MIN_HZ);
    N(SOUND_AEOL_F_MAX_HZ); N(SOUND_AEOL_Q); N(SOUND_AEOL_DB_REF); N(SOUND_AEOL_LEN_REF_M);
    N(SOUND_AEOL_DB_PER_DECADE); N(SOUND_AEOL_DB_MAX); N(SOUND_NEAR_M); N(SOUND_REF_M);
    N(SOUND_LISTEN_Z_M); N(SOUND_U_REF_MS); N(SOUND_BED_DB_REF); N(SOUND_BED_DB_PER_DECADE);
    N(SOUND_BED_DB_MAX); N(SOUND_BED_U_MIN_MS); N(SOUND_BANDS); N(SOUND_RUMBLE_HZ);
    N(SOUND_RUMBLE_Q); N(SOUND_BODY_HZ0); N(SOUND_BODY_HZ_PER_MS); N(SOUND_BODY_Q);
    N(SOUND_HOWL_MULT); N(SOUND_HOWL_Q); N(SOUND_HOWL_WANDER); N(SOUND_HOWL_WANDER_HZ);
    N(SOUND_HOWL_U0_MS); N(SOUND_HOWL_U1_MS); N(SOUND_GUST_DEPTH); N(SOUND_GUST_HZ);
    N(SOUND_RUSTLE_HZ_PER); N(SOUND_RUSTLE_U0_MS); N(SOUND_RUSTLE_EXP); N(SOUND_RUSTLE_MAX_HZ);
    N(SOUND_RUSTLE_LEAVES_HALF); N(SOUND_RUSTLE_LAG_S); N(SOUND_RUSTLE_HP_HZ);
    N(SOUND_RUSTLE_DECAY_MS); N(SOUND_RUSTLE_DB_REF); N(SOUND_RUSTLE_DB_PER_DECADE);
    N(SOUND_EVENTS); N(SOUND_EVENT_REF_M); N(SOUND_EVENT_MAX_M); N(SOUND_VOICES);
    N(SOUND_VOLUME_DB); N(SOUND_CEILING_DBFS); N(SOUND_QUIET_VOLUME_DB);
    N(SOUND_QUIET_CEILING_DBFS); N(SOUND_QUIET_EVENT_DB); N(SOUND_VISITOR_STEP_DB);
    N(SOUND_VISITOR_MAX_DB); N(SOUND_VISITOR_MIN_DB); N(SOUND_LIMIT_LOOKAHEAD_MS);
    N(SOUND_LIMIT_RELEASE_MS); N(SOUND_CAPTION_EVENT_S); N(SOUND_CAPTION_WHISPER_MS);
    N(SOUND_CAPTION_ROAR_MS); N(SOUND_CAPTION_HOWL_MS); N(SOUND_CAPTION_RUSTLE_HZ);
    N(SOUND_CAPTION_WHISTLE_DB);
    floats("SOUND_CLASS_D_M", sound_class_d_m, SOUND_CLASSES);
    floats("SOUND_BAND_DB", sound_band_db, SOUND_BANDS);
    floats("SOUND_EVENT_DB", sound_event_db, SOUND_EVENTS);
    floats("SOUND_EVENT_S", sound_event_s, SOUND_EVENTS);
    printf("\"SOUND_BAND\":{\"RUMBLE\":%d,\"BODY\":%d,\"HOWL\":%d},", SOUND_BAND_RUMBLE,
           SOUND_BAND_BODY, SOUND_BAND_HOWL);
    printf("\"SOUND_EV\":{\"CRACK\":%d,\"SNAP\":%d,\"UPROOT\":%d}},", SOUND_EV_CRACK,
           SOUND_EV_SNAP, SOUND_EV_UPROOT);
    /* the laws by speed: u, bed_db, body_hz, howl_share, band gains, rustle_hz for two
       leaf amounts and shares, rustle_db */
    static const float speeds[] = { 0.0f, 0.3f, 0.5f, 1.5f, 2.0f, 4.5f, 8.0f, 15.0f, 18.0f,
                                    20.0f, 25.0f, 33.0f, 40.0f, 53.5f, 70.0f, 90.0f };
    printf("\"by_speed\":[");
    for (size_t i = 0; i < sizeof speeds / sizeof speeds[0]; i++) {
        const float u = speeds[i];
        printf("%s[", i ? "," : "");
        cell(u, 0);
        cell(sound_bed_db(u), 0);
        cell(sound_body_hz(u), 0);
        cell(sound_howl_share(u), 0);
        for (int k = 0; k < SOUND_BANDS; k++) {
            float db = sound_bed_db(u);
            float g = isfinite(db) ? sound_db_to_gain(db + sound_band_db[k]) : 0.0f;
            cell(k == SOUND_BAND_HOWL ? g * sound_howl_share(u) : g, 0);
        }
        cell(sound_rustle_hz(u, 500.0f, 1.0f), 0);
        cell(sound_rustle_hz(u, 8000.0f, 0.4f), 0);
        cell(sound_rustle_db(u), 1);
        printf("]");
    }
    /* aeolian: u, class, len, hz, db */
    printf("],\"aeolian\":[");
    static const float lens[] = { 0.0f, 3.0f, 100.0f, 5000.0f };
    int first = 1;
    for (size_t i = 0; i < sizeof speeds / sizeof speeds[0]; i++) {
        for (int k = 0; k < SOUND_CLASSES; k++) {
            for (size_t l = 0; l < sizeof lens / sizeof lens[0]; l++) {
                const float u = speeds[i], d = sound_class_d_m[k];
                printf("%s[", first ? "" : ",");
                first = 0;
                cell(u, 0);
                cell(k, 0);
                cell(lens[l], 0);
                cell(sound_strouhal_hz(u, d), 0);
                cell(sound_aeol_db(lens[l], u, d), 1);
                printf("]");
            }
        }
    }
    /* distances: d, near_weight, event level of each kind */
    printf("],\"by_distance\":[");
    static const float dists[] = { 0.0f, 5.0f, 10.0f, 20.0f, 40.0f, 53.7f, 119.0f, 121.0f,
                                   599.0f, 601.0f };
    for (size_t i = 0; i < sizeof dists / sizeof dists[0]; i++) {
        printf("%s[", i ? "," : "");
        cell(dists[i], 0);
        cell(sound_near_weight(dists[i]), 0);
        for (int k = 0; k < SOUND_EVENTS; k++) {
            cell(sound_event_level_db(k, dists[i]), k == SOUND_EVENTS - 1);
        }
        printf("]");
    }
    /* bearings: rel, pan, gain left, gain right */
    printf("],\"by_bearing\":[");
    for (int i = -8; i <= 8; i++) {
        float rel = (float)i * 0.4f, gl, gr, pan = sound_pan(rel);
        sound_pan_gains(pan, &gl, &gr);
        printf("%s[%.9g,%.9g,%.9g,%.9g]", i > -8 ? "," : "", (double)rel, (double)pan,
               (double)gl, (double)gr);
    }
    /* diameters: d, class */
    printf("],\"classes\":[");
    static const float diam[] = { 0.0001f, 0.0009f, 0.0015f, 0.002f, 0.005f, 0.007f, 0.012f,
                                  0.05f, 0.08f, 0.2f, 0.5f, 2.0f };
    for (size_t i = 0; i < sizeof diam / sizeof diam[0]; i++) {
        printf("%s[%.9g,%d]", i ? "," : "", (double)diam[i], sound_class_of(diam[i]));
    }
    /* loudness: volume, ceiling, quiet -> resolved */
    printf("],\"loudness\":[");
    static const float vols[][2] = { { -6, -1 }, { 0, 0 }, { -30, -20 }, { -12, -3 } };
    for (int q = 0, k = 0; q < 2; q++) {
        for (size_t i = 0; i < sizeof vols / sizeof vols[0]; i++, k++) {
            sound_mix_desc d = { .volume_db = vols[i][0], .ceiling_dbfs = vols[i][1], .quiet = q };
            float v, c;
            sound_mix_resolve(&d, &v, &c);
            printf("%s[%.9g,%.9g,%d,%.9g,%.9g]", k ? "," : "", (double)vols[i][0],
                   (double)vols[i][1], q, (double)v, (double)c);
        }
    }
    /* captions: the table, then picks: u, rustle_hz, loudest tone, event -> keys */
    printf("],\"captions\":[");
    for (int k = 0; k < SOUND_CAPS; k++) {
        printf("%s\"%s\"", k ? "," : "", sound_caption_key(k));
    }
    printf("],\"picks\":[");
    static const float states[][3] = { { 0, 0, -100 },   { 4.5f, 10, -60 }, { 9, 40, -45 },
                                       { 20, 200, -30 }, { 33, 400, -20 },  { 60, 0, -39.9f },
                                       { 7.99f, 29.9f, -40 } };
    first = 1;
    for (size_t i = 0; i < sizeof states / sizeof states[0]; i++) {
        for (int ev = -1; ev < SOUND_EVENTS; ev++) {
            int keys[4];
            int n = sound_caption_pick(states[i][0], states[i][1], states[i][2], ev, keys);
            printf("%s[%.9g,%.9g,%.9g,%d,[", first ? "" : ",", (double)states[i][0],
                   (double)states[i][1], (double)states[i][2], ev);
            first = 0;
            for (int k = 0; k < n; k++) {
                printf("%s%d", k ? "," : "", keys[k]);
            }
            printf("]]");
        }
    }
    printf("]}\n");
    return 0;
}
