/* wind (PROTOCOL.md "Control messages"): a kiosk's command, with its token and any of
 * speed, direction, gust intensity, scenario and the replay's position, speed and pause.
 * Each field is optional and flagged by has_*; only the given ones are written. And reset:
 * a kiosk's token alone. */
#include "ctl_int.h"

/* Limits of the command's fields, shared by both directions. */
#define SPEED_MAX_MS 100.0
#define DIR_MAX_DEG 360.0
#define GUST_MAX 1.0
#define REPLAY_AT_MAX_MIN 1e5
#define REPLAY_SPEED_MAX 1e4

int ctl_wind_parse(ctl_rd *c, const cJSON *o, ctl_wind *w)
{
    static const char *const keys[] = { "type",  "token", "speed_ms", "dir_deg",
                                        "gust",  "scenario", "release", "keep",
                                        "replay_at_min", "replay_speed", "replay_paused",
                                        NULL };
    const json_rd *r = &c->j;
    int rc = json_check_keys(r, o, "wind", keys);
    double s = 0, d = 0, g = 0;
    if (!rc) {
        rc = json_string(r, o, "wind", "token", true, NULL, w->token, sizeof w->token, NULL);
    }
    if (!rc) {
        rc = json_number(r, o, "wind", "speed_ms", false, 0, SPEED_MAX_MS, &s, &w->has_speed);
    }
    if (!rc) {
        rc = json_number(r, o, "wind", "dir_deg", false, 0, DIR_MAX_DEG, &d, &w->has_dir);
    }
    if (!rc) {
        rc = json_number(r, o, "wind", "gust", false, 0, GUST_MAX, &g, &w->has_gust);
    }
    if (!rc) {
        rc = json_string(r, o, "wind", "scenario", false, NULL, w->scenario, sizeof w->scenario,
                         &w->has_scenario);
    }
    double at = 0, sp = 0;
    bool has_release = false;
    if (!rc) {
        rc = json_bool(r, o, "wind", "release", false, &w->release, &has_release);
    }
    if (!rc) {
        rc = json_bool(r, o, "wind", "keep", false, &w->keep, &has_release);
    }
    if (!rc) {
        rc = json_number(r, o, "wind", "replay_at_min", false, -REPLAY_AT_MAX_MIN,
                         REPLAY_AT_MAX_MIN, &at, &w->has_replay_at);
    }
    if (!rc) {
        rc = json_number(r, o, "wind", "replay_speed", false, 1, REPLAY_SPEED_MAX, &sp,
                         &w->has_replay_speed);
    }
    if (!rc) {
        rc = json_bool(r, o, "wind", "replay_paused", false, &w->replay_paused,
                       &w->has_replay_paused);
    }
    w->replay_at_min = (float)at;
    w->replay_speed = (float)sp;
    w->speed_ms = (float)s;
    w->dir_deg = (float)(d >= DIR_MAX_DEG ? 0 : d);
    w->gust = (float)g;
    return rc;
}

/* Checks an optional number as written (ctl_jnum) and adds it. */
static int put_num_in(ctl_rd *c, cJSON *o, const char *key, float f, double lo, double hi)
{
    double v = ctl_jnum(f);
    int rc = json_check_number(&c->j, "wind", key, lo, hi, v);
    if (!rc && !ctl_add_num(o, key, v)) {
        rc = ctl_fail(c, 0, GALE_E_NOMEM, "wind: out of memory");
    }
    return rc;
}

static int put_num(ctl_rd *c, cJSON *o, const char *key, float f, double hi)
{
    return put_num_in(c, o, key, f, 0, hi);
}

int ctl_wind_encode(ctl_rd *c, const ctl_wind *w, cJSON *o)
{
    int rc = json_check_string(&c->j, "wind", "token", w->token, sizeof w->token);
    if (!rc && w->has_scenario) {
        rc = json_check_string(&c->j, "wind", "scenario", w->scenario, sizeof w->scenario);
    }
    if (rc) {
        return rc;
    }
    if (!cJSON_AddStringToObject(o, "token", w->token)) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "wind: out of memory");
    }
    if (w->has_speed && (rc = put_num(c, o, "speed_ms", w->speed_ms, SPEED_MAX_MS))) {
        return rc;
    }
    if (w->has_dir && (rc = put_num(c, o, "dir_deg", w->dir_deg, DIR_MAX_DEG))) {
        return rc;
    }
    if (w->has_gust && (rc = put_num(c, o, "gust", w->gust, GUST_MAX))) {
        return rc;
    }
    if (w->has_scenario && !cJSON_AddStringToObject(o, "scenario", w->scenario)) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "wind: out of memory");
    }
    if ((w->release && !cJSON_AddBoolToObject(o, "release", 1)) ||
        (w->keep && !cJSON_AddBoolToObject(o, "keep", 1))) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "wind: out of memory");
    }
    if (w->has_replay_at && (rc = put_num_in(c, o, "replay_at_min", w->replay_at_min,
                                             -REPLAY_AT_MAX_MIN, REPLAY_AT_MAX_MIN))) {
        return rc;
    }
    if (w->has_replay_speed &&
        (rc = put_num_in(c, o, "replay_speed", w->replay_speed, 1, REPLAY_SPEED_MAX))) {
        return rc;
    }
    if (w->has_replay_paused && !cJSON_AddBoolToObject(o, "replay_paused", w->replay_paused)) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "wind: out of memory");
    }
    return 0;
}

int ctl_reset_parse(ctl_rd *c, const cJSON *o, ctl_reset *m)
{
    static const char *const keys[] = { "type", "token", NULL };
    int rc = json_check_keys(&c->j, o, "reset", keys);
    if (!rc) {
        rc = json_string(&c->j, o, "reset", "token", true, NULL, m->token, sizeof m->token, NULL);
    }
    return rc;
}

int ctl_reset_encode(ctl_rd *c, const ctl_reset *m, cJSON *o)
{
    int rc = json_check_string(&c->j, "reset", "token", m->token, sizeof m->token);
    if (rc) {
        return rc;
    }
    return cJSON_AddStringToObject(o, "token", m->token)
               ? 0
               : ctl_fail(c, 0, GALE_E_NOMEM, "reset: out of memory");
}
