/* WEATHER frames (protocol/msg_weather.c, PROTOCOL.md "WEATHER") and the server's 3-s gust
 * (server/serve/weather_gust.c): the PROTOCOL.md vector WEATHER (read from the spec)
 * decodes field for field; every field out of its range, and every field a clear flag
 * governs holding other than its "none" value, is refused on both sides with its name;
 * truncated and padded frames are refused; the gust is the peak 3-s mean of the last
 * 60 s and never undercuts the sustained wind. */
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "spec_vectors.h"
#include "weather_gust.h"
#include "wire.h"

/* Andrew near landfall: the PROTOCOL.md vector WEATHER's values. */
static wire_weather andrew(void)
{
    wire_weather w = { .sustained_ms = 50.0f,
                       .gust_ms = 62.5f,
                       .dir_from_deg = 45.0f,
                       .ss_class = 4,
                       .beaufort = 12,
                       .flags = WIRE_WEATHER_STORM | WIRE_WEATHER_CLOCK,
                       .storm_class = 5,
                       .pressure_hpa = 950.0f,
                       .central_hpa = 922.0f,
                       .distance_km = 20.0f,
                       .bearing_deg = 90.0f,
                       .utc_min = 11910785u, /* 1992-08-24 09:05Z */
                       .utc_offset_min = -240,
                       .storm_min = -10.0f,
                       .replay_pos_s = 180.0f,
                       .replay_len_s = 402.0f,
                       .replay_speed = 50.0f };
    snprintf(w.name, sizeof w.name, "Andrew 1992");
    return w;
}

static spec_file spec;

/* The PROTOCOL.md vector WEATHER (tests/test_spec_vectors.c checks its bytes and values)
 * into out; its length. */
static size_t vector(uint8_t *out, size_t cap)
{
    const spec_vector *v = spec_find(&spec, "WEATHER");
    CHECK(v != NULL && v->len <= cap);
    if (!v || v->len > cap) {
        return 0;
    }
    memcpy(out, v->bytes, v->len);
    return v->len;
}

/* Truncated and padded frames are refused. */
static void test_length(void)
{
    uint8_t want[256];
    size_t wn = vector(want, sizeof want);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 4, .max_modes = 4 }, NULL);
    CHECK(d != NULL && wn == 20 + 55 + 11);
    wire_frame f;
    gale_err e = { 0 };
    CHECK(wire_decode(d, want, wn, &f, &e) == 0);
    wire_weather w = andrew();
    CHECK(memcmp(&f.weather, &w, sizeof w) == 0);
    /* truncated by one byte, and one byte too many */
    CHECK(wire_decode(d, want, wn - 1, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "WEATHER tick 120: length");
    uint8_t big[300];
    memcpy(big, want, wn);
    big[wn] = 'x';
    CHECK(wire_decode(d, big, wn + 1, &f, &e) == GALE_E_FORMAT);
    CHECK(wire_decode(d, want, 40, &f, &e) == GALE_E_FORMAT);
    CHECK_STR_HAS(e.msg, "truncated");
    wire_decoder_destroy(d);
}

/* Each field broken in turn: the encoder refuses it by name, and a frame carrying it
 * (written with the check bypassed by patching the bytes) is refused by the decoder. */
static void test_ranges(void)
{
    struct {
        const char *field;
        size_t off; /* body offset of the field */
        uint8_t bytes[4];
        int n;
    } bad[] = {
        { "sustained_ms", 0, { 0x00, 0x00, 0xc0, 0x7f }, 4 }, /* NaN */
        { "gust_ms", 4, { 0x00, 0x00, 0x80, 0xbf }, 4 },      /* -1 */
        { "dir_from_deg", 8, { 0x00, 0x00, 0xb4, 0x43 }, 4 }, /* 360 */
        { "ss_class", 12, { 7 }, 1 },
        { "beaufort", 13, { 13 }, 1 },
        { "flags", 14, { 0x29 }, 1 },
        { "storm_class", 15, { 9 }, 1 },
        { "pressure_hpa", 16, { 0, 0, 0, 0 }, 4 },
        { "central_hpa", 20, { 0, 0, 0, 0 }, 4 },
        { "distance_km", 24, { 0x00, 0x00, 0x80, 0xbf }, 4 },
        { "bearing_deg", 28, { 0x00, 0x00, 0x80, 0xbf }, 4 },
        { "utc_offset_min", 36, { 0x00, 0x04 }, 2 },          /* 1024 */
        { "replay_pos_s", 42, { 0x00, 0x00, 0x80, 0xbf }, 4 },
        { "replay_speed", 50, { 0x00, 0x00, 0x80, 0x7f }, 4 }, /* +inf */
        { "name", 55, { 0x07 }, 1 },                           /* a control byte */
    };
    uint8_t good[256];
    size_t n = vector(good, sizeof good);
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 4, .max_modes = 4 }, NULL);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        uint8_t b[256];
        memcpy(b, good, n);
        memcpy(b + 20 + bad[i].off, bad[i].bytes, (size_t)bad[i].n);
        wire_frame f;
        gale_err e = { 0 };
        CHECK(wire_decode(d, b, n, &f, &e) == GALE_E_FORMAT);
        CHECK_STR_HAS(e.msg, bad[i].field);
        if (!strstr(e.msg, bad[i].field)) {
            fprintf(stderr, "  (breaking %s)\n", bad[i].field);
        }
    }
    wire_decoder_destroy(d);
    wire_weather w = andrew();
    uint8_t buf[WIRE_WEATHER_MAX_BYTES];
    size_t len;
    gale_err e = { 0 };
    CHECK(wire_encode_weather(&(wire_header){ 0 }, &w, buf, sizeof buf, &len, &e) == 0);
    CHECK(wire_encode_weather(&(wire_header){ 0 }, &w, buf, 30, &len, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "buffer");
}

/* A flag left clear: the fields it governs hold their one "none" value (PROTOCOL.md
 * "WEATHER"); any other is refused by the encoder and, patched into the bytes, by the
 * decoder, naming the field. */
static void test_none_values(void)
{
    wire_weather w = andrew();
    w.flags = 0;
    w.storm_class = 255;
    w.central_hpa = 0.0f;
    w.distance_km = -1.0f;
    w.bearing_deg = 0.0f;
    w.utc_min = 0;
    w.utc_offset_min = 0;
    w.storm_min = w.replay_pos_s = w.replay_len_s = w.replay_speed = 0.0f;
    uint8_t good[WIRE_WEATHER_MAX_BYTES];
    size_t n = 0;
    gale_err e = { 0 };
    CHECK(wire_encode_weather(&(wire_header){ 0 }, &w, good, sizeof good, &n, &e) == 0);
    struct {
        const char *field;
        size_t off; /* body offset */
        uint8_t bytes[4];
        int n;
    } bad[] = {
        { "flags", 14, { WIRE_WEATHER_FINISHED }, 1 },
        { "flags", 14, { WIRE_WEATHER_CLOCK }, 1 },
        { "flags", 14, { WIRE_WEATHER_PAUSED | WIRE_WEATHER_DIAL }, 1 },
        { "storm_class", 15, { 3 }, 1 },
        { "bearing_deg", 28, { 0x00, 0x00, 0xb4, 0x42 }, 4 }, /* 90 */
        { "utc_min", 32, { 0x81, 0xbe, 0xb5, 0x00 }, 4 },
        { "utc_offset_min", 36, { 0x10, 0xff }, 2 },
        { "storm_min", 38, { 0x00, 0x00, 0x20, 0xc1 }, 4 },
        { "replay_pos_s", 42, { 0x00, 0x00, 0x80, 0x3f }, 4 },
        { "replay_len_s", 46, { 0x00, 0x00, 0x80, 0x3f }, 4 },
        { "replay_speed", 50, { 0x00, 0x00, 0x80, 0x3f }, 4 },
    };
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ .max_trees = 4, .max_modes = 4 }, NULL);
    wire_frame f;
    CHECK(wire_decode(d, good, n, &f, &e) == 0);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        uint8_t b[WIRE_WEATHER_MAX_BYTES];
        memcpy(b, good, n);
        memcpy(b + 20 + bad[i].off, bad[i].bytes, (size_t)bad[i].n);
        CHECK(wire_decode(d, b, n, &f, &e) == GALE_E_FORMAT);
        CHECK_STR_HAS(e.msg, bad[i].field);
        /* the same value refused by the encoder */
        wire_weather x;
        CHECK(wire_decode(d, good, n, &f, &e) == 0);
        x = f.weather;
        uint8_t *body = b + 20;
        x.flags = body[14];
        x.storm_class = body[15];
        memcpy(&x.bearing_deg, body + 28, 4);
        memcpy(&x.utc_min, body + 32, 4);
        memcpy(&x.utc_offset_min, body + 36, 2);
        memcpy(&x.storm_min, body + 38, 4);
        memcpy(&x.replay_pos_s, body + 42, 4);
        memcpy(&x.replay_len_s, body + 46, 4);
        memcpy(&x.replay_speed, body + 50, 4);
        uint8_t out[WIRE_WEATHER_MAX_BYTES];
        size_t len;
        CHECK(wire_encode_weather(&(wire_header){ 0 }, &x, out, sizeof out, &len, &e) == GALE_E_RANGE);
        CHECK_STR_HAS(e.msg, bad[i].field);
    }
    /* with STORM, storm_class 255 is refused */
    w = andrew();
    w.storm_class = 255;
    CHECK(wire_encode_weather(&(wire_header){ 0 }, &w, good, sizeof good, &n, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "storm_class");
    wire_decoder_destroy(d);
}

static void test_gust(void)
{
    weather_gust g;
    weather_gust_init(&g);
    CHECK_NEAR(weather_gust_ms(&g, 20.0f), 20.0, 0.0);
    /* 20 m/s at 60 Hz with one 3-s burst of 30 m/s at t = 10..13 s */
    for (int k = 0; k < 60 * 30; k++) {
        double t = k / 60.0;
        weather_gust_add(&g, t, t >= 10.0 && t < 13.0 ? 30.0f : 20.0f);
    }
    CHECK_NEAR(weather_gust_ms(&g, 20.0f), 30.0, 1e-4);
    /* a shorter window (a replay's 60 storm seconds): the newest mean closed second 28;
       the burst's seconds 10..12 make the whole mean of second 12 (17th newest) and part
       of those of 13 (16th, 26.7) and 14 (15th); the last 14 hold none of it */
    CHECK_NEAR(weather_gust_ms_last(&g, 20.0f, 17), 30.0, 1e-4);
    CHECK_NEAR(weather_gust_ms_last(&g, 20.0f, 16), 80.0 / 3.0, 1e-4);
    CHECK_NEAR(weather_gust_ms_last(&g, 20.0f, 14), 20.0, 1e-4);
    CHECK_NEAR(weather_gust_ms_last(&g, 20.0f, 1000), 30.0, 1e-4); /* clamped to 60 */
    /* a 1-s burst counts a third */
    weather_gust_init(&g);
    for (int k = 0; k < 60 * 30; k++) {
        double t = k / 60.0;
        weather_gust_add(&g, t, t >= 10.0 && t < 11.0 ? 50.0f : 20.0f);
    }
    CHECK_NEAR(weather_gust_ms(&g, 20.0f), 30.0, 1e-4);
    /* the burst leaves the window 60 s later */
    for (int k = 60 * 30; k < 60 * 80; k++) {
        weather_gust_add(&g, k / 60.0, 20.0f);
    }
    CHECK_NEAR(weather_gust_ms(&g, 20.0f), 20.0, 1e-4);
    /* never below the floor (the sustained wind) */
    CHECK_NEAR(weather_gust_ms(&g, 25.0f), 25.0, 0.0);
    /* time going backwards starts over */
    weather_gust_add(&g, 1.0, 5.0f);
    CHECK_NEAR(weather_gust_ms(&g, 0.0f), 0.0, 0.0);
}

int main(void)
{
    if (spec_load(&spec, SPEC_PROTOCOL_PATH)) {
        fprintf(stderr, "test_weather: %s\n", spec.err);
        return 1;
    }
    RUN(test_length);
    RUN(test_ranges);
    RUN(test_none_values);
    RUN(test_gust);
    return check_report();
}
