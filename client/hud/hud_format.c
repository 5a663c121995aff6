/* What the HUD says: the wind in m/s, km/h and mph with the Saffir–Simpson class or
 * Beaufort force of protocol/wind_scale.h, the server's weather and storm, connection, fps
 * and latency, as lines of text (hud.h "what the HUD says"). No GL. */
#include "hud.h"

#include <math.h>
#include <stdio.h>

#include "lang.h"
#include "wind_scale.h"

int hud_saffir_simpson(float speed_ms)
{
    /* the HUD counts from tropical storm = 0, so a hurricane's number is its category */
    return wind_scale_ss_class((double)speed_ms) - 1;
}

const char *hud_category_name(int cls)
{
    return cls >= -1 && cls < WIND_SCALE_SS_COUNT - 1 ? wind_scale_ss_title(cls + 1) : "?";
}

int hud_beaufort(float speed_ms)
{
    return wind_scale_beaufort((double)speed_ms);
}

const char *hud_beaufort_name(int force)
{
    return wind_scale_beaufort_title(force);
}

const char *hud_compass_point(float bearing_deg)
{
    return hud_compass_text(LANG_EN, bearing_deg);
}

/* "HH:MM" of minutes since the epoch (UTC) plus an offset, and its date "YYYY-MM-DD". */
static void civil(long long min, char *date, size_t dcap, char *hm, size_t hcap)
{
    long long days = min >= 0 ? min / 1440 : -((-min + 1439) / 1440);
    long long rem = min - days * 1440;
    /* days since 1970-01-01 → civil date (Hinnant's days_from_civil inverse) */
    long long z = days + 719468;
    long long era = (z >= 0 ? z : z - 146096) / 146097;
    long long doe = z - era * 146097;
    long long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    long long y = yoe + era * 400, doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    long long mp = (5 * doy + 2) / 153, d = doy - (153 * mp + 2) / 5 + 1;
    long long m = mp < 10 ? mp + 3 : mp - 9;
    y += m <= 2;
    snprintf(date, dcap, "%04lld-%02lld-%02lld", y, m, d);
    snprintf(hm, hcap, "%02lld:%02lld", rem / 60, rem % 60);
}

int hud_compass_index(float bearing_deg)
{
    if (!isfinite(bearing_deg)) {
        return -1;
    }
    double b = fmod((double)bearing_deg, 360.0);
    b = b < 0.0 ? b + 360.0 : b;
    return (int)floor(b / 22.5 + 0.5) % 16;
}

const char *hud_compass_text(int lang, float bearing_deg)
{
    int i = hud_compass_index(bearing_deg);
    return i < 0 ? "?" : lang_text(lang, L_COMPASS_0 + i);
}

/* a whole number of a reading, half up (web/hud_text.js: Math.floor(x + 0.5)) */
static int whole(double x)
{
    return isfinite(x) ? (int)floor(x + 0.5) : 0;
}

/* The wind's class line: its Saffir-Simpson class from tropical storm up, else its
 * Beaufort force, where "tropical depression" would mislabel a breeze. */
static void class_line(int lang, int ss_class, int beaufort, char *out, size_t cap)
{
    if (ss_class >= WIND_SCALE_TS && ss_class < WIND_SCALE_SS_COUNT) {
        snprintf(out, cap, "%s", lang_text(lang, L_SS_0 + ss_class));
    } else {
        int b = beaufort >= 0 && beaufort <= 12 ? beaufort : 0;
        lang_format(out, cap, lang, L_HUD_BEAUFORT, lang_text(lang, L_BFT_0 + b), b);
    }
}

int hud_format_weather(const wire_weather *w, int lang, char lines[HUD_MAX_LINES][HUD_LINE_CHARS])
{
    int n = 0;
    double v = (double)w->sustained_ms;
    int cls = (int)w->ss_class; /* the server's class (wind_scale.h numbering) */
    char speed[96], gust[48];
    hud_format_speed(lang, v, cls, speed, sizeof speed);
    hud_format_speed_first(lang, (double)w->gust_ms, gust, sizeof gust);
    lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_WIND, speed, gust);
    class_line(lang, cls, (int)w->beaufort, lines[n++], HUD_LINE_CHARS);
    char from[HUD_LINE_CHARS];
    lang_format(from, sizeof from, lang, L_HUD_FROM, hud_compass_text(lang, w->dir_from_deg),
                whole((double)w->dir_from_deg) % 360);
    snprintf(lines[n++], HUD_LINE_CHARS, "%s%s", from,
             (w->flags & WIRE_WEATHER_DIAL) ? lang_text(lang, L_HUD_DIALLED) : "");
    if (w->flags & WIRE_WEATHER_STORM) {
        const char *name = w->name[0] ? w->name : lang_text(lang, L_HUD_STORM_DEFAULT);
        if (w->flags & WIRE_WEATHER_CLOCK) {
            char d[32], hm[24], ld[32], lhm[24];
            civil((long long)w->utc_min, d, sizeof d, hm, sizeof hm);
            civil((long long)w->utc_min + w->utc_offset_min, ld, sizeof ld, lhm, sizeof lhm);
            lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_STORM_CLOCK, name, d, hm, lhm);
        } else {
            snprintf(lines[n++], HUD_LINE_CHARS, "%s", name);
        }
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_EYE, whole((double)w->distance_km),
                    hud_compass_text(lang, w->bearing_deg), whole((double)w->central_hpa),
                    w->storm_class < WIND_SCALE_SS_COUNT
                        ? lang_text(lang, L_SS_ABBREV_0 + w->storm_class)
                        : "?");
        int pos = (int)w->replay_pos_s, len = (int)w->replay_len_s;
        int speed_x = whole((double)w->replay_speed);
        if (len > 0) {
            char rl[HUD_LINE_CHARS];
            lang_format(rl, sizeof rl, lang, L_HUD_REPLAY, pos / 60, pos % 60, len / 60,
                        len % 60, speed_x);
            snprintf(lines[n++], HUD_LINE_CHARS, "%s%s", rl,
                     (w->flags & WIRE_WEATHER_FINISHED) ? lang_text(lang, L_HUD_REPLAY_ENDED)
                                                        : "");
        } else {
            lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_REPLAY_LOOP, pos / 60, pos % 60,
                        speed_x);
        }
    } else if (w->name[0] && !(w->flags & WIRE_WEATHER_DIAL)) {
        /* a dial overrides a steady scenario: its title would contradict the wind above */
        snprintf(lines[n++], HUD_LINE_CHARS, "%s", lang_scenario_title(lang, w->name));
    }
    /* the expert line, the one place knots appear: the class's own unit, and m/s */
    lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_EXPERT,
                (int)hud_unit_sustained(v, HUD_UNIT_KT, cls),
                (int)hud_unit_sustained(v, HUD_UNIT_MS, cls),
                (int)hud_unit_round((double)w->gust_ms, HUD_UNIT_KT),
                (int)hud_unit_round((double)w->gust_ms, HUD_UNIT_MS));
    return n;
}

int hud_format(const hud_state *s, char lines[HUD_MAX_LINES][HUD_LINE_CHARS])
{
    int n = 0;
    const int lang = s->lang;
    if (s->wx) {
        n = hud_format_weather(s->wx, lang, lines);
    } else if (s->have_wind) {
        double v = (double)s->wind_ms;
        int cls = wind_scale_ss_class(v);
        char speed[96];
        hud_format_speed(lang, v, cls, speed, sizeof speed);
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_WIND_PLAIN, speed);
        class_line(lang, cls, wind_scale_beaufort(v), lines[n++], HUD_LINE_CHARS);
    } else {
        snprintf(lines[n++], HUD_LINE_CHARS, "%s", lang_text(lang, L_HUD_WIND_NONE));
    }
    const char *srv = s->server ? s->server : "";
    switch (s->conn) {
    case HUD_CONN_LIVE:
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_LIVE, srv,
                    s->role ? s->role : "viewer");
        break;
    case HUD_CONN_WAIT_KEY:
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_WAIT_KEY, srv);
        break;
    case HUD_CONN_RECONNECTING:
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_LOST, s->attempt, s->retry_in_s);
        break;
    case HUD_CONN_FAILED:
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_DISCONNECTED, srv);
        break;
    default:
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_CONNECTING, srv);
        break;
    }
    char lat[48];
    if (s->latency_ms >= 0.0f) {
        snprintf(lat, sizeof lat, "%.1f ms", (double)s->latency_ms);
    } else {
        snprintf(lat, sizeof lat, "\xE2\x80\x93");
    }
    /* no rate before the first half-second window closes (a headless frame saved at once) */
    char fps[24];
    if (s->fps >= 9.5f) {
        snprintf(fps, sizeof fps, "%.0f", (double)s->fps);
    } else if (s->fps > 0.0f) {
        /* a software renderer at a frame or two a second reads "0.4", not "0" */
        snprintf(fps, sizeof fps, "%.1f", (double)s->fps);
    } else {
        snprintf(fps, sizeof fps, "\xE2\x80\x93");
    }
    /* the governor's step, when it draws less than full detail */
    char detail[40] = "";
    if (s->detail_step > 0) {
        lang_format(detail, sizeof detail, lang, L_HUD_DETAIL, s->detail_step);
    }
    lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_PERF, fps, lat, (double)s->delay_ms,
                detail);
    if (s->trees_held < s->trees_scene) {
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_REDUCED, s->trees_held,
                    s->trees_scene);
    }
    if (s->frames_bad) {
        lang_format(lines[n++], HUD_LINE_CHARS, lang, L_HUD_BAD_FRAMES,
                    (unsigned long long)s->frames_bad);
    }
    return n;
}
