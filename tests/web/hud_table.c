/* gale-client's HUD lines of WEATHER (client/hud/hud_format.c hud_format_weather), one JSON
 * object a line, for tests/web/test_hud_js.mjs to hold web/hud_text.js to: each line has
 * the WEATHER frame as hex (protocol/msg_weather.c's encoding, so the browser reads the
 * same float32s) and the lines gale-client's HUD shows for it in each language (lang.h).
 * The cases sweep the wind
 * through every Beaufort force and Saffir-Simpson class (a tie of printf's rounding
 * among them), every compass point, a dial, steady scenarios, and storm replays with and
 * without their clock, name, length and end. */
#include <stdio.h>
#include <string.h>

#include "hud.h"
#include "lang.h"
#include "wind_scale.h"
#include "wire.h"

static void put_json_string(const char *s)
{
    putchar('"');
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') {
            putchar('\\');
        }
        putchar(*s);
    }
    putchar('"');
}

static int emit(const wire_weather *w)
{
    wire_header h = { .magic = WIRE_MAGIC, .version = WIRE_PROTOCOL_VERSION, .tick = 7,
                      .server_time_us = 123456789u };
    uint8_t buf[256];
    size_t len = 0;
    gale_err err = { 0 };
    if (wire_encode_weather(&h, w, buf, sizeof buf, &len, &err) != 0) {
        fprintf(stderr, "gale-web-hud-table: %s\n", err.msg);
        return 1;
    }
    printf("{\"hex\":\"");
    for (size_t i = 0; i < len; i++) {
        printf("%02x", buf[i]);
    }
    printf("\",\"lines\":{");
    for (int l = 0; l < LANG_COUNT; l++) {
        char lines[HUD_MAX_LINES][HUD_LINE_CHARS];
        int n = hud_format_weather(w, l, lines);
        printf("%s\"%s\":[", l ? "," : "", lang_code(l));
        for (int i = 0; i < n; i++) {
            if (i) {
                putchar(',');
            }
            put_json_string(lines[i]);
        }
        putchar(']');
    }
    printf("}}\n");
    return 0;
}

/* the wind of a steady scene: classes from protocol/wind_scale.c, no storm */
static wire_weather steady(float sustained_ms, float gust_ms, float dir_deg, const char *name,
                           int dial)
{
    wire_weather w = { .sustained_ms = sustained_ms, .gust_ms = gust_ms,
                       .dir_from_deg = dir_deg,
                       .ss_class = (uint8_t)wind_scale_ss_class(sustained_ms),
                       .beaufort = (uint8_t)wind_scale_beaufort(sustained_ms),
                       .flags = dial ? WIRE_WEATHER_DIAL : 0, .storm_class = 255,
                       .pressure_hpa = 1013.25f, .distance_km = -1.0f };
    snprintf(w.name, sizeof w.name, "%s", name);
    return w;
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        int help = strcmp(argv[1], "--help") == 0;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-hud-table\n"
                "  prints WEATHER frames (hex) and gale-client's HUD lines for each, JSON "
                "lines\n");
        return help ? 0 : 2;
    }
    int bad = 0;
    /* every force and class, ties of "%.1f" and "%.0f" (2.25, 2.5) among them */
    static const float speeds_ms[] = { 0.0f, 0.2f, 1.0f, 2.25f, 2.5f, 5.4f, 7.95f, 10.7f,
                                       13.8f, 17.1f, 20.7f, 24.4f, 28.4f, 32.6f, 32.7f, 33.0f,
                                       42.5f, 49.4f, 57.6f, 60.0f, 70.5f, 90.0f, 199.5f,
                                       /* NHC's edges where a unit alone would cross: 96 kt
                                        * (110.5 mph), 136 kt (156.5 mph), 82.5 kt */
                                       49.39f, 69.96f, 42.44f };
    const int n_speeds = (int)(sizeof speeds_ms / sizeof speeds_ms[0]);
    for (int i = 0; i < n_speeds; i++) {
        float dir = 22.5f * (float)i + (i % 3 == 1 ? 11.25f : 0.0f);
        while (dir >= 360.0f) {
            dir -= 360.0f;
        }
        wire_weather w = steady(speeds_ms[i], speeds_ms[i] * 1.4f + 0.5f, dir,
                                i % 4 == 0   ? ""
                                : i % 4 == 1 ? "Calm"
                                : i % 4 == 2 ? "Gusty afternoon"
                                             : "Stiff breeze",
                                i % 2);
        bad |= emit(&w);
    }
    /* after a dialled storm: a breeze with the last minute's storm gust */
    wire_weather after = steady(1.0f, 55.0f, 359.9f, "Calm", 0);
    bad |= emit(&after);
    wire_weather utf8 = steady(12.0f, 18.0f, 90.0f, "Cicl\xC3\xB3n \"A\xC3\xB1o\" \\ 1", 0);
    bad |= emit(&utf8);
    /* a replay with its clock: Andrew at landfall, Homestead's UTC-4 */
    wire_weather andrew = steady(64.0f, 81.0f, 112.5f, "Andrew (1992)", 0);
    andrew.flags = WIRE_WEATHER_STORM | WIRE_WEATHER_CLOCK;
    andrew.storm_class = WIND_SCALE_CAT5;
    andrew.pressure_hpa = 940.0f;
    andrew.central_hpa = 922.0f;
    andrew.distance_km = 31.5f;
    andrew.bearing_deg = 101.25f;
    andrew.utc_min = 11910760u; /* 1992-08-24 08:40 UTC */
    andrew.utc_offset_min = -240;
    andrew.storm_min = -20.0f;
    andrew.replay_pos_s = 125.7f;
    andrew.replay_len_s = 600.0f;
    andrew.replay_speed = 50.0f;
    bad |= emit(&andrew);
    wire_weather ended = andrew;
    ended.flags |= WIRE_WEATHER_FINISHED | WIRE_WEATHER_PAUSED;
    ended.replay_pos_s = 600.0f;
    ended.utc_min = 11911440u; /* 20:00 UTC, past midnight local */
    ended.utc_offset_min = 300;
    bad |= emit(&ended);
    /* a storm without a name, clock or end: a loop */
    wire_weather loop = andrew;
    loop.flags = WIRE_WEATHER_STORM | WIRE_WEATHER_DIAL;
    loop.name[0] = '\0';
    loop.utc_min = 0;
    loop.utc_offset_min = 0;
    loop.replay_len_s = 0.0f;
    loop.replay_pos_s = 3725.0f;
    loop.replay_speed = 2.5f;
    loop.storm_class = WIND_SCALE_TS;
    loop.distance_km = 0.5f;
    loop.bearing_deg = 348.75f;
    bad |= emit(&loop);
    return bad;
}
