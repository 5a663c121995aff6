/* Display-wall control messages (PROTOCOL.md "Wall groups"): wall_join, wall_drawn and
 * wall_camera from clients, wall_sync, wall_swap and wall_camera from the server. Ordinary
 * control JSON, so whatever forwards client control messages forwards these. */
#include <string.h>

#include "ctl_int.h"

#define COORD_M 1e6

static int oom(ctl_rd *c, const char *what)
{
    return ctl_fail(c, 0, GALE_E_NOMEM, "%s: out of memory", what);
}

static int get_u32(ctl_rd *c, const cJSON *o, const char *path, const char *key, bool required,
                   long long lo, long long hi, uint32_t *out)
{
    long long v = 0;
    bool has = false;
    int rc = json_int(&c->j, o, path, key, required, lo, hi, &v, &has);
    if (!rc && has) {
        *out = (uint32_t)v;
    }
    return rc;
}

static int get_float(ctl_rd *c, const cJSON *o, const char *path, const char *key, double lo,
                     double hi, float *out)
{
    double v = 0;
    int rc = json_number(&c->j, o, path, key, true, lo, hi, &v, NULL);
    *out = (float)v;
    return rc;
}

static int parse_join(ctl_rd *c, const cJSON *o, ctl_wall_join *j)
{
    static const char *const keys[] = { "type",      "wall",     "tile", "swap_lock",
                                        "rate_hz",   "budget_ms", "delay_ms", NULL };
    const char *p = "wall_join";
    j->budget_ms = 8;
    j->delay_ms = 100;
    int rc = json_check_keys(&c->j, o, p, keys);
    if (!rc) {
        rc = json_string(&c->j, o, p, "wall", true, NULL, j->wall, sizeof j->wall, NULL);
    }
    if (!rc) {
        rc = json_string(&c->j, o, p, "tile", true, NULL, j->tile, sizeof j->tile, NULL);
    }
    if (!rc) {
        rc = json_bool(&c->j, o, p, "swap_lock", false, &j->swap_lock, NULL);
    }
    if (!rc) {
        rc = get_float(c, o, p, "rate_hz", 1, CTL_WALL_MAX_RATE_HZ, &j->rate_hz);
    }
    if (!rc) {
        rc = get_u32(c, o, p, "budget_ms", false, 1, 1000, &j->budget_ms);
    }
    if (!rc) {
        rc = get_u32(c, o, p, "delay_ms", false, 1, 10000, &j->delay_ms);
    }
    if (!rc && (!j->wall[0] || !j->tile[0])) {
        rc = ctl_fail(c, 0, GALE_E_RANGE, "wall_join.%s: expected a name, got \"\"",
                      j->wall[0] ? "tile" : "wall");
    }
    return rc;
}

static int encode_join(ctl_rd *c, const ctl_wall_join *j, cJSON *o)
{
    const json_rd *r = &c->j;
    const char *p = "wall_join";
    double rate = ctl_jnum(j->rate_hz);
    int rc = json_check_string(r, p, "wall", j->wall, sizeof j->wall);
    if (!rc) {
        rc = json_check_string(r, p, "tile", j->tile, sizeof j->tile);
    }
    if (!rc && (!j->wall[0] || !j->tile[0])) {
        rc = ctl_fail(c, 0, GALE_E_RANGE, "wall_join.%s: expected a name, got \"\"",
                      j->wall[0] ? "tile" : "wall");
    }
    if (!rc) {
        rc = json_check_number(r, p, "rate_hz", 1, CTL_WALL_MAX_RATE_HZ, rate);
    }
    if (!rc) {
        rc = json_check_int(r, p, "budget_ms", 1, 1000, j->budget_ms);
    }
    if (!rc) {
        rc = json_check_int(r, p, "delay_ms", 1, 10000, j->delay_ms);
    }
    if (rc) {
        return rc;
    }
    return cJSON_AddStringToObject(o, "wall", j->wall) &&
                   cJSON_AddStringToObject(o, "tile", j->tile) &&
                   cJSON_AddBoolToObject(o, "swap_lock", j->swap_lock) &&
                   ctl_add_num(o, "rate_hz", rate) && ctl_add_num(o, "budget_ms", j->budget_ms) &&
                   ctl_add_num(o, "delay_ms", j->delay_ms)
               ? 0
               : oom(c, p);
}

static int parse_sync(ctl_rd *c, const cJSON *o, ctl_wall_sync *s)
{
    static const char *const keys[] = { "type",      "wall",      "epoch_us", "period_us",
                                        "delay_us",  "budget_ms", "swap_lock", "members",
                                        NULL };
    const char *p = "wall_sync";
    long long epoch = 0;
    int rc = json_check_keys(&c->j, o, p, keys);
    if (!rc) {
        rc = json_string(&c->j, o, p, "wall", true, NULL, s->wall, sizeof s->wall, NULL);
    }
    if (!rc) {
        rc = json_int(&c->j, o, p, "epoch_us", true, 0, CTL_U53, &epoch, NULL);
    }
    s->epoch_us = (uint64_t)epoch;
    if (!rc) {
        rc = get_u32(c, o, p, "period_us", true, 1000000 / CTL_WALL_MAX_RATE_HZ, 1000000,
                     &s->period_us);
    }
    if (!rc) {
        rc = get_u32(c, o, p, "delay_us", true, 0, 10000000, &s->delay_us);
    }
    if (!rc) {
        rc = get_u32(c, o, p, "budget_ms", true, 1, 1000, &s->budget_ms);
    }
    if (!rc) {
        rc = json_bool(&c->j, o, p, "swap_lock", true, &s->swap_lock, NULL);
    }
    if (!rc) {
        rc = get_u32(c, o, p, "members", true, 1, CTL_U32, &s->members);
    }
    return rc;
}

static int encode_sync(ctl_rd *c, const ctl_wall_sync *s, cJSON *o)
{
    const json_rd *r = &c->j;
    const char *p = "wall_sync";
    int rc = json_check_string(r, p, "wall", s->wall, sizeof s->wall);
    if (!rc) {
        rc = json_check_int(r, p, "epoch_us", 0, CTL_U53, (double)s->epoch_us);
    }
    if (!rc) {
        rc = json_check_int(r, p, "period_us", 1000000 / CTL_WALL_MAX_RATE_HZ, 1000000,
                            s->period_us);
    }
    if (!rc) {
        rc = json_check_int(r, p, "delay_us", 0, 10000000, s->delay_us);
    }
    if (!rc) {
        rc = json_check_int(r, p, "budget_ms", 1, 1000, s->budget_ms);
    }
    if (!rc) {
        rc = json_check_int(r, p, "members", 1, CTL_U32, s->members);
    }
    if (rc) {
        return rc;
    }
    return cJSON_AddStringToObject(o, "wall", s->wall) &&
                   ctl_add_num(o, "epoch_us", (double)s->epoch_us) &&
                   ctl_add_num(o, "period_us", s->period_us) &&
                   ctl_add_num(o, "delay_us", s->delay_us) &&
                   ctl_add_num(o, "budget_ms", s->budget_ms) &&
                   cJSON_AddBoolToObject(o, "swap_lock", s->swap_lock) &&
                   ctl_add_num(o, "members", s->members)
               ? 0
               : oom(c, p);
}

/* wall_drawn: frame; wall_swap: frame, drawn, members. */
static int parse_frame(ctl_rd *c, const cJSON *o, bool swap, ctl_wall_frame *f)
{
    static const char *const k_drawn[] = { "type", "frame", NULL };
    static const char *const k_swap[] = { "type", "frame", "drawn", "members", NULL };
    const char *p = swap ? "wall_swap" : "wall_drawn";
    int rc = json_check_keys(&c->j, o, p, swap ? k_swap : k_drawn);
    if (!rc) {
        rc = get_u32(c, o, p, "frame", true, 0, CTL_U32, &f->frame);
    }
    if (!rc && swap) {
        rc = get_u32(c, o, p, "drawn", true, 0, CTL_U32, &f->drawn);
    }
    if (!rc && swap) {
        rc = get_u32(c, o, p, "members", true, 0, CTL_U32, &f->members);
    }
    return rc;
}

static int encode_frame(ctl_rd *c, const ctl_wall_frame *f, bool swap, cJSON *o)
{
    bool ok = ctl_add_num(o, "frame", f->frame);
    if (swap) {
        ok = ok && ctl_add_num(o, "drawn", f->drawn) && ctl_add_num(o, "members", f->members);
    }
    return ok ? 0 : oom(c, swap ? "wall_swap" : "wall_drawn");
}

static int parse_camera(ctl_rd *c, const cJSON *o, ctl_wall_camera *w)
{
    static const char *const keys[] = { "type",    "wall",      "frame", "target_m", "distance_m",
                                        "yaw_deg", "pitch_deg", NULL };
    const char *p = "wall_camera";
    double t[3] = { 0 };
    int rc = json_check_keys(&c->j, o, p, keys);
    if (!rc) {
        rc = json_string(&c->j, o, p, "wall", true, NULL, w->wall, sizeof w->wall, NULL);
    }
    if (!rc) {
        rc = get_u32(c, o, p, "frame", false, 0, CTL_U32, &w->frame);
    }
    if (!rc) {
        rc = json_vec(&c->j, o, p, "target_m", true, 3, -COORD_M, COORD_M, t, NULL);
    }
    for (int k = 0; k < 3; k++) {
        w->target_m[k] = (float)t[k];
    }
    if (!rc) {
        rc = get_float(c, o, p, "distance_m", 0.5, 5000, &w->distance_m);
    }
    if (!rc) {
        rc = get_float(c, o, p, "yaw_deg", -720, 720, &w->yaw_deg);
    }
    if (!rc) {
        rc = get_float(c, o, p, "pitch_deg", -88, 88, &w->pitch_deg);
    }
    return rc;
}

static int encode_camera(ctl_rd *c, const ctl_wall_camera *w, cJSON *o)
{
    const json_rd *r = &c->j;
    const char *p = "wall_camera";
    double t[3], d = ctl_jnum(w->distance_m), yaw = ctl_jnum(w->yaw_deg),
                 pitch = ctl_jnum(w->pitch_deg);
    int rc = json_check_string(r, p, "wall", w->wall, sizeof w->wall);
    for (int k = 0; k < 3 && !rc; k++) {
        t[k] = ctl_jnum(w->target_m[k]);
        rc = json_check_number(r, p, "target_m", -COORD_M, COORD_M, t[k]);
    }
    if (!rc) {
        rc = json_check_number(r, p, "distance_m", 0.5, 5000, d);
    }
    if (!rc) {
        rc = json_check_number(r, p, "yaw_deg", -720, 720, yaw);
    }
    if (!rc) {
        rc = json_check_number(r, p, "pitch_deg", -88, 88, pitch);
    }
    if (rc) {
        return rc;
    }
    cJSON *a = cJSON_CreateDoubleArray(t, 3);
    if (!a || !cJSON_AddItemToObject(o, "target_m", a)) {
        cJSON_Delete(a);
        return oom(c, p);
    }
    return cJSON_AddStringToObject(o, "wall", w->wall) &&
                   (w->frame == 0 || ctl_add_num(o, "frame", w->frame)) &&
                   ctl_add_num(o, "distance_m", d) && ctl_add_num(o, "yaw_deg", yaw) &&
                   ctl_add_num(o, "pitch_deg", pitch)
               ? 0
               : oom(c, p);
}

int ctl_wall_parse(ctl_rd *c, const cJSON *o, int type, ctl_msg *m)
{
    switch (type) {
    case CTL_WALL_JOIN: return parse_join(c, o, &m->u.wall_join);
    case CTL_WALL_SYNC: return parse_sync(c, o, &m->u.wall_sync);
    case CTL_WALL_DRAWN: return parse_frame(c, o, false, &m->u.wall_frame);
    case CTL_WALL_SWAP: return parse_frame(c, o, true, &m->u.wall_frame);
    default: return parse_camera(c, o, &m->u.wall_camera); /* CTL_WALL_CAMERA */
    }
}

int ctl_wall_encode(ctl_rd *c, const ctl_msg *m, cJSON *o)
{
    switch (m->type) {
    case CTL_WALL_JOIN: return encode_join(c, &m->u.wall_join, o);
    case CTL_WALL_SYNC: return encode_sync(c, &m->u.wall_sync, o);
    case CTL_WALL_DRAWN: return encode_frame(c, &m->u.wall_frame, false, o);
    case CTL_WALL_SWAP: return encode_frame(c, &m->u.wall_frame, true, o);
    default: return encode_camera(c, &m->u.wall_camera, o); /* CTL_WALL_CAMERA */
    }
}
