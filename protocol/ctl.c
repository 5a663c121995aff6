/* JSON control messages of the gale wire (DESIGN.md "Wire"): hello, view, wind,
 * resync, ping from clients; welcome, pong, error from the server. Parsed with
 * cJSON_ParseWithLengthOpts (length-bounded, line:col from the end pointer); every key is
 * checked, unknown keys are errors, and each rejection carries its close code. */
#include "ctl.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "wire.h"

/* Parse context: where errors go. */
typedef struct jctx {
    gale_err *err;
    int close; /* enum wire_close of the first error */
} jctx;

static const char *const role_names[] = { "viewer", "kiosk", "wall-tile", "load" };
static const char *const type_names[] = { NULL,      "hello",   "view", "wind", "resync",
                                          "ping",    "welcome", "pong", "error" };
static const char *const view_names[] = { "all", "circle", "frustum" };

#define N_ROLES (int)(sizeof role_names / sizeof role_names[0])
#define N_TYPES (int)(sizeof type_names / sizeof type_names[0])

const char *ctl_role_name(int role)
{
    return role >= 0 && role < N_ROLES ? role_names[role] : NULL;
}

const char *ctl_type_name(int type)
{
    return type > 0 && type < N_TYPES ? type_names[type] : NULL;
}

bool ctl_from_client(int type)
{
    return type >= CTL_HELLO && type <= CTL_PING;
}

static int fail(jctx *c, int close, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static int fail(jctx *c, int close, int code, const char *fmt, ...)
{
    char msg[sizeof c->err->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    c->close = close;
    return gale_errf(c->err, code, "%s", msg);
}

static const char *json_kind(const cJSON *j)
{
    if (!j) {
        return "nothing";
    }
    if (cJSON_IsString(j)) {
        return "a string";
    }
    if (cJSON_IsNumber(j)) {
        return "a number";
    }
    if (cJSON_IsBool(j)) {
        return "a boolean";
    }
    if (cJSON_IsNull(j)) {
        return "null";
    }
    if (cJSON_IsArray(j)) {
        return "an array";
    }
    return "an object";
}

/* Every key of object o must be in keys (NULL-terminated). */
static int check_keys(jctx *c, const cJSON *o, const char *path, const char *const *keys)
{
    for (const cJSON *k = o->child; k; k = k->next) {
        bool known = false;
        for (int i = 0; keys[i]; i++) {
            if (k->string && strcmp(k->string, keys[i]) == 0) {
                known = true;
                break;
            }
        }
        if (!known) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE, "ctl: %s: unknown key \"%.40s\"",
                        path, k->string ? k->string : "");
        }
    }
    return 0;
}

/* Number field: required or optional (*has set), within [lo, hi], integral if asked. */
static int get_num(jctx *c, const cJSON *o, const char *path, const char *key, bool required,
                   bool integral, double lo, double hi, double *out, bool *has)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(o, key);
    if (has) {
        *has = j != NULL;
    }
    if (!j) {
        if (required) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                        "ctl: %s.%s: missing: expected a number", path, key);
        }
        return 0;
    }
    if (!cJSON_IsNumber(j)) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE, "ctl: %s.%s: expected a number, got %s",
                    path, key, json_kind(j));
    }
    double v = j->valuedouble;
    if (!isfinite(v) || v < lo || v > hi || (integral && v != floor(v))) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                    "ctl: %s.%s: expected %s in [%.17g, %.17g], got %.17g", path, key,
                    integral ? "an integer" : "a number", lo, hi, v);
    }
    *out = v;
    return 0;
}

static int get_str(jctx *c, const cJSON *o, const char *path, const char *key, bool required,
                   char *out, size_t cap, bool *has)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(o, key);
    if (has) {
        *has = j != NULL;
    }
    if (!j) {
        if (required) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                        "ctl: %s.%s: missing: expected a string", path, key);
        }
        return 0;
    }
    if (!cJSON_IsString(j)) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE, "ctl: %s.%s: expected a string, got %s",
                    path, key, json_kind(j));
    }
    size_t n = strlen(j->valuestring);
    if (n >= cap) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                    "ctl: %s.%s: expected at most %zu bytes, got %zu", path, key, cap - 1, n);
    }
    memcpy(out, j->valuestring, n + 1);
    return 0;
}

static int get_vec3(jctx *c, const cJSON *o, const char *path, const char *key, float *v)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!j) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                    "ctl: %s.%s: missing: expected an array of 3 numbers", path, key);
    }
    if (!cJSON_IsArray(j) || cJSON_GetArraySize(j) != 3) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                    "ctl: %s.%s: expected an array of 3 numbers, got %s%s", path, key,
                    json_kind(j), cJSON_IsArray(j) ? " of another length" : "");
    }
    int i = 0;
    for (const cJSON *e = j->child; e; e = e->next, i++) {
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble) || fabs(e->valuedouble) > 1e6) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                        "ctl: %s.%s[%d]: expected a number in [-1e6, 1e6], got %s", path, key,
                        i, json_kind(e));
        }
        v[i] = (float)e->valuedouble;
    }
    return 0;
}

static int parse_enum(jctx *c, const cJSON *o, const char *path, const char *key,
                      const char *const *names, int n, const char *list, int *out)
{
    char s[32];
    int rc = get_str(c, o, path, key, true, s, sizeof s, NULL);
    if (rc) {
        const cJSON *j = cJSON_GetObjectItemCaseSensitive(o, key);
        if (j && cJSON_IsString(j)) { /* too long: report as not one of the names */
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                        "ctl: %s.%s: expected one of %s, got \"%.31s...\"", path, key, list,
                        j->valuestring);
        }
        return rc;
    }
    for (int i = 0; i < n; i++) {
        if (names[i] && strcmp(s, names[i]) == 0) {
            *out = i;
            return 0;
        }
    }
    return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE, "ctl: %s.%s: expected one of %s, got \"%s\"",
                path, key, list, s);
}

static int parse_view(jctx *c, const cJSON *j, const char *path, ctl_view *v)
{
    memset(v, 0, sizeof *v);
    if (!cJSON_IsObject(j)) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE, "ctl: %s: expected an object, got %s",
                    path, json_kind(j));
    }
    int rc = parse_enum(c, j, path, "kind", view_names, 3, "all|circle|frustum", &v->kind);
    if (rc) {
        return rc;
    }
    double x = 0, y = 0, r = 0, fov = 0, far = 0, lod = 0;
    static const char *const k_all[] = { "kind", "lod_m", NULL };
    static const char *const k_circle[] = { "kind", "x", "y", "radius_m", "lod_m", NULL };
    static const char *const k_frustum[] = { "kind", "eye", "dir", "fov_deg", "far_m", "lod_m",
                                             NULL };
    const char *const *keys = v->kind == CTL_VIEW_ALL      ? k_all
                              : v->kind == CTL_VIEW_CIRCLE ? k_circle
                                                           : k_frustum;
    rc = check_keys(c, j, path, keys);
    if (!rc) {
        rc = get_num(c, j, path, "lod_m", false, false, 0, 1e6, &lod, NULL);
    }
    if (!rc && v->kind == CTL_VIEW_CIRCLE) {
        rc = get_num(c, j, path, "x", true, false, -1e6, 1e6, &x, NULL);
        if (!rc) {
            rc = get_num(c, j, path, "y", true, false, -1e6, 1e6, &y, NULL);
        }
        if (!rc) {
            rc = get_num(c, j, path, "radius_m", true, false, 1e-3, 1e6, &r, NULL);
        }
    }
    if (!rc && v->kind == CTL_VIEW_FRUSTUM) {
        rc = get_vec3(c, j, path, "eye", v->eye);
        if (!rc) {
            rc = get_vec3(c, j, path, "dir", v->dir);
        }
        if (!rc && v->dir[0] == 0.0f && v->dir[1] == 0.0f && v->dir[2] == 0.0f) {
            rc = fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                      "ctl: %s.dir: expected a nonzero vector, got [0, 0, 0]", path);
        }
        if (!rc) {
            rc = get_num(c, j, path, "fov_deg", true, false, 1, 179, &fov, NULL);
        }
        if (!rc) {
            rc = get_num(c, j, path, "far_m", true, false, 1e-3, 1e6, &far, NULL);
        }
    }
    v->x = (float)x;
    v->y = (float)y;
    v->radius_m = (float)r;
    v->fov_deg = (float)fov;
    v->far_m = (float)far;
    v->lod_m = (float)lod;
    return rc;
}

static int parse_hello(jctx *c, const cJSON *o, ctl_hello *h)
{
    static const char *const keys[] = { "type", "protocol", "role", "view", "token", NULL };
    int rc = check_keys(c, o, "hello", keys);
    double proto = 0;
    if (!rc) {
        /* protocol first: a client of another version may not share the other fields. */
        rc = get_num(c, o, "hello", "protocol", true, true, 0, 65535, &proto, NULL);
    }
    if (!rc && proto != WIRE_PROTOCOL_VERSION) {
        rc = fail(c, WIRE_CLOSE_VERSION, GALE_E_VERSION,
                  "ctl: hello.protocol: expected %d, got %d", WIRE_PROTOCOL_VERSION, (int)proto);
    }
    h->protocol = (int)proto;
    if (!rc) {
        rc = parse_enum(c, o, "hello", "role", role_names, N_ROLES, "viewer|kiosk|wall-tile|load",
                        &h->role);
    }
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, "view");
    if (!rc && v) {
        rc = parse_view(c, v, "hello.view", &h->view);
    }
    if (!rc) {
        rc = get_str(c, o, "hello", "token", false, h->token, sizeof h->token, NULL);
    }
    return rc;
}

static int parse_wind(jctx *c, const cJSON *o, ctl_wind *w)
{
    static const char *const keys[] = { "type",  "token", "speed_ms", "dir_deg",
                                        "gust",  "scenario", NULL };
    int rc = check_keys(c, o, "wind", keys);
    double s = 0, d = 0, g = 0;
    if (!rc) {
        rc = get_str(c, o, "wind", "token", true, w->token, sizeof w->token, NULL);
    }
    if (!rc) {
        rc = get_num(c, o, "wind", "speed_ms", false, false, 0, 100, &s, &w->has_speed);
    }
    if (!rc) {
        rc = get_num(c, o, "wind", "dir_deg", false, false, 0, 360, &d, &w->has_dir);
    }
    if (!rc) {
        rc = get_num(c, o, "wind", "gust", false, false, 0, 1, &g, &w->has_gust);
    }
    if (!rc) {
        rc = get_str(c, o, "wind", "scenario", false, w->scenario, sizeof w->scenario,
                     &w->has_scenario);
    }
    w->speed_ms = (float)s;
    w->dir_deg = (float)(d >= 360 ? 0 : d);
    w->gust = (float)g;
    return rc;
}

#define U53 9007199254740992.0 /* 2^53: integers above are not exact in a JSON double */

/* welcome.obstacles: optional array of rows [min_x, min_y, min_z, max_x, max_y, max_z]. */
static int parse_obstacles(jctx *c, const cJSON *o, ctl_welcome *w)
{
    const cJSON *ob = cJSON_GetObjectItemCaseSensitive(o, "obstacles");
    if (!ob) {
        return 0;
    }
    if (!cJSON_IsArray(ob)) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                    "ctl: welcome.obstacles: wrong type: expected an array, got %s", json_kind(ob));
    }
    int n = cJSON_GetArraySize(ob);
    if (n > (int)WIRE_MAX_OBSTACLES) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                    "ctl: welcome.obstacles: expected <= %u entries, got %d", WIRE_MAX_OBSTACLES, n);
    }
    if (n > 0) {
        w->obstacles = calloc((size_t)n, sizeof *w->obstacles);
        if (!w->obstacles) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_NOMEM,
                        "ctl: welcome.obstacles: out of memory");
        }
    }
    w->n_obstacles = (uint32_t)n;
    int i = 0;
    for (const cJSON *e = ob->child; e; e = e->next, i++) {
        if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 6) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                        "ctl: welcome.obstacles[%d]: expected [min_x, min_y, min_z, max_x, max_y, max_z], got %s%s",
                        i, json_kind(e), cJSON_IsArray(e) ? " of another length" : "");
        }
        double v[6];
        int k = 0;
        for (const cJSON *x = e->child; x; x = x->next, k++) {
            if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble)) {
                return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                            "ctl: welcome.obstacles[%d][%d]: expected a number, got %s", i, k,
                            json_kind(x));
            }
            if (fabs(x->valuedouble) > 1e6) {
                return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                            "ctl: welcome.obstacles[%d][%d]: expected |value| <= 1e6, got %.17g",
                            i, k, x->valuedouble);
            }
            v[k] = x->valuedouble;
        }
        for (k = 0; k < 3; k++) {
            if (!(v[k] <= v[k + 3])) {
                return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                            "ctl: welcome.obstacles[%d]: expected min <= max on axis %c, got %.17g > %.17g",
                            i, "xyz"[k], v[k], v[k + 3]);
            }
        }
        ctl_obstacle *b = &w->obstacles[i];
        for (k = 0; k < 3; k++) {
            b->min[k] = (float)v[k];
            b->max[k] = (float)v[k + 3];
        }
    }
    return 0;
}

static int parse_welcome(jctx *c, const cJSON *o, ctl_welcome *w)
{
    static const char *const keys[] = { "type",     "protocol",  "client_id", "role",
                                        "tick_hz",  "snapshot_hz", "server_us", "tick",
                                        "species",  "instances", "obstacles", NULL };
    int rc = check_keys(c, o, "welcome", keys);
    double proto = 0, id = 0, th = 0, sh = 0, su = 0, tick = 0;
    if (!rc) {
        rc = get_num(c, o, "welcome", "protocol", true, true, 0, 65535, &proto, NULL);
    }
    if (!rc && proto != WIRE_PROTOCOL_VERSION) {
        rc = fail(c, WIRE_CLOSE_VERSION, GALE_E_VERSION,
                  "ctl: welcome.protocol: expected %d, got %d", WIRE_PROTOCOL_VERSION,
                  (int)proto);
    }
    if (!rc) {
        rc = get_num(c, o, "welcome", "client_id", true, true, 0, 4294967295.0, &id, NULL);
    }
    if (!rc) {
        rc = parse_enum(c, o, "welcome", "role", role_names, N_ROLES,
                        "viewer|kiosk|wall-tile|load", &w->role);
    }
    if (!rc) {
        rc = get_num(c, o, "welcome", "tick_hz", true, false, 1, 1000, &th, NULL);
    }
    if (!rc) {
        rc = get_num(c, o, "welcome", "snapshot_hz", true, false, 0.1, 1000, &sh, NULL);
    }
    if (!rc) {
        rc = get_num(c, o, "welcome", "server_us", true, true, 0, U53, &su, NULL);
    }
    if (!rc) {
        rc = get_num(c, o, "welcome", "tick", true, true, 0, 4294967295.0, &tick, NULL);
    }
    w->protocol = (int)proto;
    w->client_id = (uint32_t)id;
    w->tick_hz = (float)th;
    w->snapshot_hz = (float)sh;
    w->server_us = (uint64_t)su;
    w->tick = (uint32_t)tick;
    if (rc) {
        return rc;
    }
    const cJSON *sp = cJSON_GetObjectItemCaseSensitive(o, "species");
    if (!cJSON_IsArray(sp)) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                    "ctl: welcome.species: %s: expected an array, got %s", sp ? "wrong type" : "missing",
                    json_kind(sp));
    }
    int ns = cJSON_GetArraySize(sp);
    if (ns < 1 || ns > (int)WIRE_MAX_SPECIES) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                    "ctl: welcome.species: expected 1..%u entries, got %d", WIRE_MAX_SPECIES, ns);
    }
    w->species = calloc((size_t)ns, sizeof *w->species);
    if (!w->species) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_NOMEM, "ctl: welcome.species: out of memory");
    }
    w->n_species = (uint32_t)ns;
    int i = 0;
    for (const cJSON *e = sp->child; e; e = e->next, i++) {
        char path[40];
        snprintf(path, sizeof path, "welcome.species[%d]", i);
        if (!cJSON_IsObject(e)) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE, "ctl: %s: expected an object, got %s",
                        path, json_kind(e));
        }
        static const char *const skeys[] = { "name", "url", "hash", "n_modes", NULL };
        ctl_species *s = &w->species[i];
        double nm = 0;
        rc = check_keys(c, e, path, skeys);
        if (!rc) {
            rc = get_str(c, e, path, "name", true, s->name, sizeof s->name, NULL);
        }
        if (!rc) {
            rc = get_str(c, e, path, "url", true, s->url, sizeof s->url, NULL);
        }
        if (!rc) {
            rc = get_str(c, e, path, "hash", true, s->hash, sizeof s->hash, NULL);
        }
        if (!rc && (strlen(s->hash) != 16 || strspn(s->hash, "0123456789abcdef") != 16)) {
            rc = fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                      "ctl: %s.hash: expected 16 lowercase hex digits, got \"%s\"", path, s->hash);
        }
        if (!rc) {
            rc = get_num(c, e, path, "n_modes", true, true, 1, WIRE_MAX_MODES, &nm, NULL);
        }
        s->n_modes = (uint32_t)nm;
        if (rc) {
            return rc;
        }
    }
    const cJSON *in = cJSON_GetObjectItemCaseSensitive(o, "instances");
    if (!cJSON_IsArray(in)) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                    "ctl: welcome.instances: %s: expected an array, got %s",
                    in ? "wrong type" : "missing", json_kind(in));
    }
    int ni = cJSON_GetArraySize(in);
    if (ni > (int)WIRE_MAX_TREES) {
        return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                    "ctl: welcome.instances: expected <= %u entries, got %d", WIRE_MAX_TREES, ni);
    }
    if (ni > 0) {
        w->instances = calloc((size_t)ni, sizeof *w->instances);
        if (!w->instances) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_NOMEM,
                        "ctl: welcome.instances: out of memory");
        }
    }
    w->n_instances = (uint32_t)ni;
    i = 0;
    for (const cJSON *e = in->child; e; e = e->next, i++) {
        /* Row [species, x, y, z, yaw_rad, scale]. */
        if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 6) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                        "ctl: welcome.instances[%d]: expected [species, x, y, z, yaw_rad, scale], got %s%s",
                        i, json_kind(e), cJSON_IsArray(e) ? " of another length" : "");
        }
        double v[6];
        int k = 0;
        for (const cJSON *x = e->child; x; x = x->next, k++) {
            if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble)) {
                return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                            "ctl: welcome.instances[%d][%d]: expected a number, got %s", i, k,
                            json_kind(x));
            }
            v[k] = x->valuedouble;
        }
        if (v[0] < 0 || v[0] >= ns || v[0] != floor(v[0])) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                        "ctl: welcome.instances[%d][0]: species: expected an integer in [0, %d], got %.17g",
                        i, ns - 1, v[0]);
        }
        for (k = 1; k < 5; k++) {
            if (fabs(v[k]) > 1e6) {
                return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                            "ctl: welcome.instances[%d][%d]: expected |value| <= 1e6, got %.17g",
                            i, k, v[k]);
            }
        }
        if (!(v[5] > 0 && v[5] <= 100)) {
            return fail(c, WIRE_CLOSE_BAD_FIELD, GALE_E_RANGE,
                        "ctl: welcome.instances[%d][5]: scale: expected (0, 100], got %.17g", i,
                        v[5]);
        }
        ctl_instance *t = &w->instances[i];
        t->species = (uint32_t)v[0];
        t->pos[0] = (float)v[1];
        t->pos[1] = (float)v[2];
        t->pos[2] = (float)v[3];
        t->yaw_rad = (float)v[4];
        t->scale = (float)v[5];
    }
    return parse_obstacles(c, o, w);
}

static int depth_of(const cJSON *j, int depth)
{
    int best = depth;
    for (const cJSON *k = j->child; k; k = k->next) {
        if (k->child) {
            int d = depth_of(k, depth + 1);
            best = d > best ? d : best;
            if (best > CTL_MAX_DEPTH) {
                break;
            }
        }
    }
    return best;
}

/* 1-based line and column of offset `at` in text. */
static void line_col(const char *text, size_t at, int *line, int *col)
{
    *line = 1;
    *col = 1;
    for (size_t i = 0; i < at; i++) {
        if (text[i] == '\n') {
            ++*line;
            *col = 1;
        } else {
            ++*col;
        }
    }
}

int ctl_decode(const char *text, size_t len, size_t max_len, ctl_msg *m, int *close_code,
               gale_err *err)
{
    memset(m, 0, sizeof *m);
    jctx c = { err, 0 };
    if (max_len == 0) {
        max_len = CTL_MAX_CLIENT_BYTES;
    }
    int rc = 0;
    cJSON *root = NULL;
    if (len > max_len) {
        rc = fail(&c, WIRE_CLOSE_TOO_BIG, GALE_E_RANGE,
                  "ctl: message: expected <= %zu bytes, got %zu", max_len, len);
        goto done;
    }
    const char *end = NULL;
    root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    size_t at = end && end >= text && end <= text + len ? (size_t)(end - text) : len;
    if (root) {
        while (at < len && strchr(" \t\r\n", text[at]) && text[at] != '\0') {
            at++;
        }
    }
    if (!root || at < len) {
        int line, col;
        line_col(text, at, &line, &col);
        char near[16] = "";
        size_t k = 0;
        for (; k < 12 && at + k < len; k++) {
            char ch = text[at + k];
            near[k] = ch >= 0x20 && ch < 0x7f && ch != '"' ? ch : '?';
        }
        near[k] = '\0';
        rc = fail(&c, WIRE_CLOSE_BAD_JSON, GALE_E_PARSE, "ctl: %d:%d: %s near \"%s\"", line, col,
                  root ? "trailing characters after the JSON value" : "invalid JSON", near);
        goto done;
    }
    if (!cJSON_IsObject(root)) {
        rc = fail(&c, WIRE_CLOSE_BAD_JSON, GALE_E_PARSE, "ctl: message: expected an object, got %s",
                  json_kind(root));
        goto done;
    }
    if (depth_of(root, 1) > CTL_MAX_DEPTH) {
        rc = fail(&c, WIRE_CLOSE_BAD_JSON, GALE_E_RANGE,
                  "ctl: message: nesting: expected <= %d levels, got more", CTL_MAX_DEPTH);
        goto done;
    }
    const cJSON *ty = cJSON_GetObjectItemCaseSensitive(root, "type");
    if (!cJSON_IsString(ty)) {
        rc = fail(&c, WIRE_CLOSE_UNKNOWN_TYPE, GALE_E_PARSE,
                  "ctl: type: %s: expected a string, got %s", ty ? "wrong type" : "missing",
                  json_kind(ty));
        goto done;
    }
    int type = 0;
    for (int i = 1; i < N_TYPES; i++) {
        if (strcmp(ty->valuestring, type_names[i]) == 0) {
            type = i;
        }
    }
    if (!type) {
        rc = fail(&c, WIRE_CLOSE_UNKNOWN_TYPE, GALE_E_PARSE,
                  "ctl: type: expected one of hello|view|wind|resync|ping|welcome|pong|error, got \"%.40s\"",
                  ty->valuestring);
        goto done;
    }
    m->type = type;
    switch (type) {
    case CTL_HELLO:
        rc = parse_hello(&c, root, &m->u.hello);
        break;
    case CTL_VIEW: {
        static const char *const keys[] = { "type", "view", NULL };
        rc = check_keys(&c, root, "view", keys);
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "view");
        if (!rc && !v) {
            rc = fail(&c, WIRE_CLOSE_BAD_FIELD, GALE_E_PARSE,
                      "ctl: view.view: missing: expected an object");
        }
        if (!rc) {
            rc = parse_view(&c, v, "view.view", &m->u.view);
        }
        break;
    }
    case CTL_WIND:
        rc = parse_wind(&c, root, &m->u.wind);
        break;
    case CTL_RESYNC: {
        static const char *const keys[] = { "type", "seq", NULL };
        double seq = 0;
        rc = check_keys(&c, root, "resync", keys);
        if (!rc) {
            rc = get_num(&c, root, "resync", "seq", true, true, 0, 4294967295.0, &seq, NULL);
        }
        m->u.resync_seq = (uint32_t)seq;
        break;
    }
    case CTL_PING: {
        static const char *const keys[] = { "type", "id", "client_us", NULL };
        double id = 0, cu = 0;
        rc = check_keys(&c, root, "ping", keys);
        if (!rc) {
            rc = get_num(&c, root, "ping", "id", true, true, 0, 4294967295.0, &id, NULL);
        }
        if (!rc) {
            rc = get_num(&c, root, "ping", "client_us", true, true, 0, U53, &cu, NULL);
        }
        m->u.ping.id = (uint32_t)id;
        m->u.ping.client_us = (uint64_t)cu;
        break;
    }
    case CTL_WELCOME:
        rc = parse_welcome(&c, root, &m->u.welcome);
        break;
    case CTL_PONG: {
        static const char *const keys[] = { "type", "id", "client_us", "server_us", "tick", NULL };
        double id = 0, cu = 0, su = 0, tick = 0;
        rc = check_keys(&c, root, "pong", keys);
        if (!rc) {
            rc = get_num(&c, root, "pong", "id", true, true, 0, 4294967295.0, &id, NULL);
        }
        if (!rc) {
            rc = get_num(&c, root, "pong", "client_us", true, true, 0, U53, &cu, NULL);
        }
        if (!rc) {
            rc = get_num(&c, root, "pong", "server_us", true, true, 0, U53, &su, NULL);
        }
        if (!rc) {
            rc = get_num(&c, root, "pong", "tick", true, true, 0, 4294967295.0, &tick, NULL);
        }
        m->u.pong.id = (uint32_t)id;
        m->u.pong.client_us = (uint64_t)cu;
        m->u.pong.server_us = (uint64_t)su;
        m->u.pong.tick = (uint32_t)tick;
        break;
    }
    default: { /* CTL_ERROR */
        static const char *const keys[] = { "type", "code", "message", NULL };
        double code = 0;
        rc = check_keys(&c, root, "error", keys);
        if (!rc) {
            rc = get_num(&c, root, "error", "code", true, true, 1000, 4999, &code, NULL);
        }
        if (!rc) {
            rc = get_str(&c, root, "error", "message", true, m->u.error.message,
                         sizeof m->u.error.message, NULL);
        }
        m->u.error.code = (int)code;
        break;
    }
    }
done:
    cJSON_Delete(root);
    if (rc) {
        ctl_msg_fini(m);
        if (close_code) {
            *close_code = c.close;
        }
    } else if (close_code) {
        *close_code = 0;
    }
    return rc;
}

void ctl_msg_fini(ctl_msg *m)
{
    if (!m) {
        return;
    }
    if (m->type == CTL_WELCOME) {
        free(m->u.welcome.species);
        free(m->u.welcome.instances);
        free(m->u.welcome.obstacles);
    }
    memset(m, 0, sizeof *m);
}

/* ---- encoding ------------------------------------------------------------------------ */

/* A float as the shortest decimal of 7 significant digits, so JSON shows 1.3, not
 * 1.2999999523162842; exact to float precision for the control channel's needs. */
static double jnum(float f)
{
    char b[32];
    snprintf(b, sizeof b, "%.7g", (double)f);
    return strtod(b, NULL);
}

static bool add_num(cJSON *o, const char *k, double v)
{
    return cJSON_AddNumberToObject(o, k, v) != NULL;
}

static cJSON *view_json(const ctl_view *v)
{
    cJSON *o = cJSON_CreateObject();
    if (!o || v->kind < 0 || v->kind > CTL_VIEW_FRUSTUM) {
        cJSON_Delete(o);
        return NULL;
    }
    bool ok = cJSON_AddStringToObject(o, "kind", view_names[v->kind]) != NULL;
    if (v->kind == CTL_VIEW_CIRCLE) {
        ok = ok && add_num(o, "x", jnum(v->x)) && add_num(o, "y", jnum(v->y)) &&
             add_num(o, "radius_m", jnum(v->radius_m));
    } else if (v->kind == CTL_VIEW_FRUSTUM) {
        double e[3] = { jnum(v->eye[0]), jnum(v->eye[1]), jnum(v->eye[2]) };
        double d[3] = { jnum(v->dir[0]), jnum(v->dir[1]), jnum(v->dir[2]) };
        cJSON *ea = cJSON_CreateDoubleArray(e, 3);
        cJSON *da = cJSON_CreateDoubleArray(d, 3);
        ok = ok && cJSON_AddItemToObject(o, "eye", ea);
        ok = ok && cJSON_AddItemToObject(o, "dir", da);
        ok = ok && add_num(o, "fov_deg", jnum(v->fov_deg)) && add_num(o, "far_m", jnum(v->far_m));
    }
    if (ok && v->lod_m > 0.0f) {
        ok = add_num(o, "lod_m", jnum(v->lod_m));
    }
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static cJSON *to_json(const ctl_msg *m, gale_err *err)
{
    const char *tn = ctl_type_name(m->type);
    if (!tn) {
        gale_errf(err, GALE_E_ARG, "ctl_encode: type: expected a ctl_type, got %d", m->type);
        return NULL;
    }
    cJSON *o = cJSON_CreateObject();
    bool ok = o && cJSON_AddStringToObject(o, "type", tn);
    switch (m->type) {
    case CTL_HELLO: {
        const ctl_hello *h = &m->u.hello;
        const char *rn = ctl_role_name(h->role);
        ok = ok && rn && add_num(o, "protocol", h->protocol) &&
             cJSON_AddStringToObject(o, "role", rn);
        if (ok && h->view.kind != CTL_VIEW_ALL) {
            cJSON *v = view_json(&h->view);
            ok = v && cJSON_AddItemToObject(o, "view", v);
        }
        if (ok && h->token[0]) {
            ok = cJSON_AddStringToObject(o, "token", h->token) != NULL;
        }
        break;
    }
    case CTL_VIEW: {
        cJSON *v = view_json(&m->u.view);
        ok = ok && v && cJSON_AddItemToObject(o, "view", v);
        break;
    }
    case CTL_WIND: {
        const ctl_wind *w = &m->u.wind;
        ok = ok && cJSON_AddStringToObject(o, "token", w->token);
        if (ok && w->has_speed) {
            ok = add_num(o, "speed_ms", jnum(w->speed_ms));
        }
        if (ok && w->has_dir) {
            ok = add_num(o, "dir_deg", jnum(w->dir_deg));
        }
        if (ok && w->has_gust) {
            ok = add_num(o, "gust", jnum(w->gust));
        }
        if (ok && w->has_scenario) {
            ok = cJSON_AddStringToObject(o, "scenario", w->scenario) != NULL;
        }
        break;
    }
    case CTL_RESYNC:
        ok = ok && add_num(o, "seq", m->u.resync_seq);
        break;
    case CTL_PING:
        ok = ok && add_num(o, "id", m->u.ping.id) &&
             add_num(o, "client_us", (double)m->u.ping.client_us);
        break;
    case CTL_PONG:
        ok = ok && add_num(o, "id", m->u.pong.id) &&
             add_num(o, "client_us", (double)m->u.pong.client_us) &&
             add_num(o, "server_us", (double)m->u.pong.server_us) &&
             add_num(o, "tick", m->u.pong.tick);
        break;
    case CTL_ERROR:
        ok = ok && add_num(o, "code", m->u.error.code) &&
             cJSON_AddStringToObject(o, "message", m->u.error.message);
        break;
    default: { /* CTL_WELCOME */
        const ctl_welcome *w = &m->u.welcome;
        const char *rn = ctl_role_name(w->role);
        ok = ok && rn && add_num(o, "protocol", w->protocol) &&
             add_num(o, "client_id", w->client_id) && cJSON_AddStringToObject(o, "role", rn) &&
             add_num(o, "tick_hz", jnum(w->tick_hz)) &&
             add_num(o, "snapshot_hz", jnum(w->snapshot_hz)) &&
             add_num(o, "server_us", (double)w->server_us) && add_num(o, "tick", w->tick);
        cJSON *sa = ok ? cJSON_AddArrayToObject(o, "species") : NULL;
        ok = ok && sa;
        for (uint32_t i = 0; ok && i < w->n_species; i++) {
            const ctl_species *s = &w->species[i];
            cJSON *so = cJSON_CreateObject();
            ok = so && cJSON_AddItemToArray(sa, so) && cJSON_AddStringToObject(so, "name", s->name) &&
                 cJSON_AddStringToObject(so, "url", s->url) &&
                 cJSON_AddStringToObject(so, "hash", s->hash) && add_num(so, "n_modes", s->n_modes);
        }
        cJSON *ia = ok ? cJSON_AddArrayToObject(o, "instances") : NULL;
        ok = ok && ia;
        for (uint32_t i = 0; ok && i < w->n_instances; i++) {
            const ctl_instance *t = &w->instances[i];
            double row[6] = { t->species,        jnum(t->pos[0]),  jnum(t->pos[1]),
                              jnum(t->pos[2]),   jnum(t->yaw_rad), jnum(t->scale) };
            cJSON *r = cJSON_CreateDoubleArray(row, 6);
            ok = r && cJSON_AddItemToArray(ia, r);
        }
        /* Omitted when there are none, so a scene without houses keeps its old text. */
        cJSON *oa = ok && w->n_obstacles > 0 ? cJSON_AddArrayToObject(o, "obstacles") : NULL;
        ok = ok && (w->n_obstacles == 0 || oa);
        for (uint32_t i = 0; ok && i < w->n_obstacles; i++) {
            const ctl_obstacle *b = &w->obstacles[i];
            double row[6] = { jnum(b->min[0]), jnum(b->min[1]), jnum(b->min[2]),
                              jnum(b->max[0]), jnum(b->max[1]), jnum(b->max[2]) };
            cJSON *r = cJSON_CreateDoubleArray(row, 6);
            ok = r && cJSON_AddItemToArray(oa, r);
        }
        break;
    }
    }
    if (!ok) {
        cJSON_Delete(o);
        gale_errf(err, GALE_E_ARG, "ctl_encode: %s: a value out of range or out of memory", tn);
        return NULL;
    }
    return o;
}

/* Checks what the encoder is given by decoding its own output: whatever ctl_encode
 * writes, ctl_decode accepts (the encoder cannot emit what the other side rejects). */
static int self_check(const char *s, size_t n, gale_err *err)
{
    ctl_msg back;
    gale_err e2;
    int rc = ctl_decode(s, n, CTL_MAX_SERVER_BYTES, &back, NULL, &e2);
    ctl_msg_fini(&back);
    if (rc) {
        return gale_errf(err, rc == GALE_E_NOMEM ? rc : GALE_E_RANGE, "ctl_encode: %s", e2.msg);
    }
    return 0;
}

int ctl_encode(const ctl_msg *m, char **out, size_t *len, gale_err *err)
{
    *out = NULL;
    *len = 0;
    cJSON *o = to_json(m, err);
    if (!o) {
        return err ? err->code : GALE_E_ARG;
    }
    char *s = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    if (!s) {
        return gale_errf(err, GALE_E_NOMEM, "ctl_encode: out of memory");
    }
    size_t n = strlen(s);
    int rc = self_check(s, n, err);
    if (rc) {
        cJSON_free(s);
        return rc;
    }
    /* Hand back memory the caller frees with free(), whatever cJSON's hooks are. */
    char *copy = malloc(n + 1);
    if (!copy) {
        cJSON_free(s);
        return gale_errf(err, GALE_E_NOMEM, "ctl_encode: out of memory");
    }
    memcpy(copy, s, n + 1);
    cJSON_free(s);
    *out = copy;
    *len = n;
    return 0;
}

int ctl_encode_into(const ctl_msg *m, char *buf, size_t cap, size_t *len, gale_err *err)
{
    *len = 0;
    cJSON *o = to_json(m, err);
    if (!o) {
        return err ? err->code : GALE_E_ARG;
    }
    if (cap > 0x7fffffff) {
        cap = 0x7fffffff;
    }
    cJSON_bool ok = cJSON_PrintPreallocated(o, buf, (int)cap, 0);
    cJSON_Delete(o);
    if (!ok) {
        return gale_errf(err, GALE_E_RANGE, "ctl_encode_into: buffer: %zu bytes too small", cap);
    }
    size_t n = strlen(buf);
    int rc = self_check(buf, n, err);
    if (rc) {
        return rc;
    }
    *len = n;
    return 0;
}
