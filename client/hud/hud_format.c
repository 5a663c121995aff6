/* What the HUD says: the wind in m/s, km/h and mph with the Saffir–Simpson class or
 * Beaufort force of protocol/wind_scale.h, the server's weather and storm, connection, fps
 * and latency, as lines of text (hud.h "what the HUD says"). No GL. */
#include "hud.h"

#include <math.h>
#include <stdio.h>

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
    static const char *const pts[16] = { "N", "NNE", "NE", "ENE", "E", "ESE", "SE", "SSE",
                                         "S", "SSW", "SW", "WSW", "W", "WNW", "NW", "NNW" };
    if (!isfinite(bearing_deg)) {
        return "?";
    }
    double b = fmod((double)bearing_deg, 360.0);
    b = b < 0.0 ? b + 360.0 : b;
    return pts[(int)floor(b / 22.5 + 0.5) % 16];
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

int hud_format_weather(const wire_weather *w, char lines[HUD_MAX_LINES][HUD_LINE_CHARS])
{
    int n = 0;
    double v = (double)w->sustained_ms;
    snprintf(lines[n++], HUD_LINE_CHARS,
             "Wind %.1f m/s \xC2\xB7 %.0f km/h \xC2\xB7 %.0f mph \xC2\xB7 gusts %.0f m/s", v,
             v * 3.6, v / 0.44704, (double)w->gust_ms);
    int cls = (int)w->ss_class; /* the server's class (wind_scale.h numbering) */
    if (cls >= WIND_SCALE_TS) {
        snprintf(lines[n++], HUD_LINE_CHARS, "%s", wind_scale_ss_title(cls));
    } else {
        snprintf(lines[n++], HUD_LINE_CHARS, "%s \xC2\xB7 Beaufort %d",
                 wind_scale_beaufort_title(w->beaufort), (int)w->beaufort);
    }
    snprintf(lines[n++], HUD_LINE_CHARS, "From the %s (%.0f\xC2\xB0)%s",
             hud_compass_point(w->dir_from_deg), (double)w->dir_from_deg,
             (w->flags & WIRE_WEATHER_DIAL) ? " \xC2\xB7 dialled at the kiosk" : "");
    if (w->flags & WIRE_WEATHER_STORM) {
        char clock[96] = "";
        if (w->flags & WIRE_WEATHER_CLOCK) {
            char d[32], hm[24], ld[32], lhm[24];
            civil((long long)w->utc_min, d, sizeof d, hm, sizeof hm);
            civil((long long)w->utc_min + w->utc_offset_min, ld, sizeof ld, lhm, sizeof lhm);
            snprintf(clock, sizeof clock, " \xC2\xB7 %s %s UTC (%s local)", d, hm, lhm);
        }
        snprintf(lines[n++], HUD_LINE_CHARS, "%s%s", w->name[0] ? w->name : "Storm", clock);
        snprintf(lines[n++], HUD_LINE_CHARS,
                 "Eye %.0f km %s \xC2\xB7 %.0f hPa \xC2\xB7 storm %s",
                 (double)w->distance_km, hud_compass_point(w->bearing_deg),
                 (double)w->central_hpa,
                 w->storm_class < WIND_SCALE_SS_COUNT ? wind_scale_ss_abbrev(w->storm_class) : "?");
        int pos = (int)w->replay_pos_s, len = (int)w->replay_len_s;
        if (len > 0) {
            snprintf(lines[n++], HUD_LINE_CHARS, "Replay %d:%02d / %d:%02d \xC2\xB7 \xC3\x97%.0f%s",
                     pos / 60, pos % 60, len / 60, len % 60, (double)w->replay_speed,
                     (w->flags & WIRE_WEATHER_FINISHED) ? " \xC2\xB7 ended" : "");
        } else {
            snprintf(lines[n++], HUD_LINE_CHARS, "Replay %d:%02d \xC2\xB7 \xC3\x97%.0f (looping)",
                     pos / 60, pos % 60, (double)w->replay_speed);
        }
    } else if (w->name[0] && !(w->flags & WIRE_WEATHER_DIAL)) {
        /* a dial overrides a steady scenario: its title would contradict the wind above */
        snprintf(lines[n++], HUD_LINE_CHARS, "%s", w->name);
    }
    return n;
}

int hud_format(const hud_state *s, char lines[HUD_MAX_LINES][HUD_LINE_CHARS])
{
    int n = 0;
    if (s->wx) {
        n = hud_format_weather(s->wx, lines);
    } else if (s->have_wind) {
        float v = s->wind_ms;
        snprintf(lines[n++], HUD_LINE_CHARS, "Wind %.1f m/s \xC2\xB7 %.0f km/h \xC2\xB7 %.0f mph",
                 (double)v, (double)v * 3.6, (double)v / 0.44704);
        int cls = hud_saffir_simpson(v);
        if (cls >= 0) {
            snprintf(lines[n++], HUD_LINE_CHARS, "%s", hud_category_name(cls));
        } else {
            int b = hud_beaufort(v);
            snprintf(lines[n++], HUD_LINE_CHARS, "%s \xC2\xB7 Beaufort %d", hud_beaufort_name(b), b);
        }
    } else {
        snprintf(lines[n++], HUD_LINE_CHARS, "Wind \xE2\x80\x93 (no wind data yet)");
    }
    const char *srv = s->server ? s->server : "";
    switch (s->conn) {
    case HUD_CONN_LIVE:
        snprintf(lines[n++], HUD_LINE_CHARS, "Live \xC2\xB7 %s \xC2\xB7 %s", srv,
                 s->role ? s->role : "viewer");
        break;
    case HUD_CONN_WAIT_KEY:
        snprintf(lines[n++], HUD_LINE_CHARS,
                 "Connected \xC2\xB7 %s \xC2\xB7 waiting for a keyframe", srv);
        break;
    case HUD_CONN_RECONNECTING:
        snprintf(lines[n++], HUD_LINE_CHARS,
                 "Server lost \xC2\xB7 retry %u in %.1f s \xC2\xB7 showing last state", s->attempt,
                 s->retry_in_s);
        break;
    case HUD_CONN_FAILED:
        snprintf(lines[n++], HUD_LINE_CHARS, "Disconnected \xC2\xB7 %s", srv);
        break;
    default:
        snprintf(lines[n++], HUD_LINE_CHARS, "Connecting to %s\xE2\x80\xA6", srv);
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
        snprintf(detail, sizeof detail, " \xC2\xB7 detail \xE2\x88\x92%d", s->detail_step);
    }
    snprintf(lines[n++], HUD_LINE_CHARS, "%s fps \xC2\xB7 latency %s \xC2\xB7 delay %.0f ms%s",
             fps, lat, (double)s->delay_ms, detail);
    if (s->frames_bad) {
        snprintf(lines[n++], HUD_LINE_CHARS, "%llu bad frames dropped",
                 (unsigned long long)s->frames_bad);
    }
    return n;
}
