/* The WEATHER frame on the sim thread (PROTOCOL.md "WEATHER"): each tick's scenario state
 * (or, without a scenario, the steady inflow a kiosk may have set) and its 3-s gust
 * (weather_gust.h), encoded as a snapshot's third extra every SRV_WEATHER_EVERY snapshots
 * and, on the others, for connections that get that snapshot's keyframe, so a joining
 * kiosk names the weather in its first picture. The class and force are computed here,
 * from the sustained wind (the exhibit shows the server's, never a client average). */
#include "srv_int.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void srv_weather_sample(srv *s, uint32_t tick, double dt_s, const scenario_state *st)
{
    scenario_state m;
    if (!st) {
        /* no scenario: the scene's steady inflow, or what a kiosk set (srv_control.c) */
        pthread_mutex_lock(&s->scen_lock);
        wind_inflow in = s->man_inflow;
        pthread_mutex_unlock(&s->scen_lock);
        memset(&m, 0, sizeof m);
        m.sustained_ms = in.u10_ms;
        m.gust_ms = in.u10_ms;
        /* toward θ from +x counter-clockwise → from, clockwise from north */
        double from = fmod(270.0 - (double)in.dir_rad * 180.0 / M_PI + 720.0, 360.0);
        m.dir_from_deg = from >= 360.0 ? 0.0 : from;
        m.storm_category = -1;
        m.distance_km = -1.0;
        m.pressure_hpa = 1013.0;
        m.t_s = tick * dt_s;
        st = &m;
    }
    s->wx_state = *st;
    s->wx_have = true;
    atomic_store(&s->wx_sustained_pub, (float)st->sustained_ms);
    atomic_store(&s->wx_dial_pub, st->override_active);
    weather_gust_add(&s->wx_gust, tick * dt_s, (float)st->gust_ms);
}

static float clampf(double v, double lo, double hi)
{
    return !(v >= lo) ? (float)lo : v > hi ? (float)hi : (float)v;
}

void srv_weather_fill(const srv *s, wire_weather *w)
{
    const scenario_state *st = &s->wx_state;
    memset(w, 0, sizeof *w);
    w->sustained_ms = clampf(st->sustained_ms, 0.0, 200.0);
    /* a replay's 60 s of gust are storm seconds: 60/speed server seconds, at least the
       3 s the mean spans (an eyewall's peak of storm minutes ago is not the eye's gust) */
    int window_s = WEATHER_GUST_WINDOW_S;
    if (st->replay_speed > 1.0) {
        double span = (double)WEATHER_GUST_WINDOW_S / st->replay_speed;
        window_s = span < 3.0 ? 3 : (int)ceil(span);
    }
    w->gust_ms = clampf(weather_gust_ms_last(&s->wx_gust, w->sustained_ms, window_s), 0.0, 300.0);
    w->dir_from_deg = clampf(st->dir_from_deg, 0.0, 359.99);
    w->ss_class = (uint8_t)wind_scale_ss_class(w->sustained_ms);
    w->beaufort = (uint8_t)wind_scale_beaufort(w->sustained_ms);
    w->pressure_hpa = clampf(st->pressure_hpa, 800.0, 1100.0);
    w->storm_class = 255;
    w->distance_km = -1.0f;
    if (st->override_active) {
        w->flags |= WIRE_WEATHER_DIAL;
    }
    if (s->sim_scen && scenario_get_kind(s->sim_scen) == SCENARIO_HURRICANE && st->distance_km >= 0.0) {
        w->flags |= WIRE_WEATHER_STORM;
        w->storm_class = (uint8_t)(st->storm_category >= 0 ? st->storm_category : 0);
        w->central_hpa = clampf(st->central_hpa, 800.0, 1100.0);
        w->distance_km = clampf(st->distance_km, 0.0, 20000.0);
        w->bearing_deg = clampf(st->bearing_deg, 0.0, 359.99);
        w->storm_min = clampf(st->storm_min, -1e6, 1e6);
        w->replay_pos_s = clampf(st->replay_pos_s, 0.0, 1e9);
        w->replay_len_s = clampf(scenario_duration_s(s->sim_scen), 0.0, 1e9);
        w->replay_speed = clampf(st->replay_speed, 0.0, 1e5);
        if (st->finished) {
            w->flags |= WIRE_WEATHER_FINISHED;
        }
        if (st->paused) {
            w->flags |= WIRE_WEATHER_PAUSED;
        }
        if (st->has_clock && st->utc_min >= 0 && st->utc_min <= (long long)UINT32_MAX) {
            w->flags |= WIRE_WEATHER_CLOCK;
            w->utc_min = (uint32_t)st->utc_min;
            w->utc_offset_min = (int16_t)st->utc_offset_min;
        }
    }
    const char *name = s->sim_scen ? scenario_name(s->sim_scen) : s->d.sc->name;
    /* a whole name that fits, else cut at a UTF-8 character boundary */
    size_t n = strlen(name ? name : "");
    if (n > WIRE_WEATHER_NAME_MAX) {
        n = WIRE_WEATHER_NAME_MAX;
        while (n > 0 && ((unsigned char)name[n] & 0xC0u) == 0x80u) {
            n--;
        }
    }
    for (size_t i = 0; i < n; i++) {
        unsigned char ch = (unsigned char)name[i];
        w->name[i] = ch < 0x20 || ch == 0x7f ? ' ' : (char)ch;
    }
    /* a name that is not UTF-8 would be refused by every client: its other bytes as '?' */
    if (!wire_utf8_valid((const uint8_t *)w->name, n)) {
        for (size_t i = 0; i < n; i++) {
            w->name[i] = (unsigned char)w->name[i] >= 0x80u ? '?' : w->name[i];
        }
    }
}

int srv_weather_encode(srv *s, const wire_header *h, net_snap *p, gale_err *e)
{
    if (!s->wx_have) {
        return 0;
    }
    wire_weather w;
    srv_weather_fill(s, &w);
    int rc = wire_encode_weather(h, &w, p->extra[SRV_EXTRA_WEATHER], p->extra_cap,
                                 &p->extra_len[SRV_EXTRA_WEATHER], e);
    if (!rc && s->seq % SRV_WEATHER_EVERY != 1) {
        p->extra_key_only |= 1u << SRV_EXTRA_WEATHER;
    }
    return rc;
}

static const metric_row weather_rows[] = {
    { "gale_wind_sustained_meters_per_second", NULL,
      "1-minute sustained wind at 10 m the WEATHER frame names", METRIC_GAUGE, 0 },
    { "gale_wind_dial", NULL, "1 while a kiosk dial holds the wind", METRIC_GAUGE, 0 },
};

static void weather_metrics_fill(void *ctx, double *v)
{
    srv *s = ctx;
    v[0] = (double)atomic_load(&s->wx_sustained_pub);
    v[1] = atomic_load(&s->wx_dial_pub) ? 1.0 : 0.0;
}

int srv_weather_register(srv *s, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, weather_rows, 2, weather_metrics_fill, s, err);
}
