/* The JSON kit: see json.h. Each getter is fetch, type check, then the json_check_* an
 * encoder uses too, so a rejection reads the same from either side. */
#include "json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int json_fail(const json_rd *r, int code, const char *fmt, ...)
{
    char msg[sizeof r->err->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return gale_errf(r->err, code, "%s: %s", r->where, msg);
}

cJSON *json_parse(const char *text, size_t len, size_t *at)
{
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    *at = end && end >= text && end <= text + len ? (size_t)(end - text) : len;
    return root;
}

size_t json_skip_space(const char *text, size_t len, size_t at)
{
    while (at < len && (text[at] == ' ' || text[at] == '\t' || text[at] == '\n' ||
                        text[at] == '\r')) {
        at++;
    }
    return at;
}

void json_line_col(const char *text, size_t at, int *line, int *col)
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

static int depth_from(const cJSON *j, int depth, int limit)
{
    int best = depth;
    for (const cJSON *k = j->child; k; k = k->next) {
        if (k->child) {
            int d = depth_from(k, depth + 1, limit);
            best = d > best ? d : best;
            if (best > limit) {
                break;
            }
        }
    }
    return best;
}

int json_depth(const cJSON *j, int limit)
{
    return j ? depth_from(j, 1, limit) : 0;
}

const char *json_type_kind(int type)
{
    switch (type & 0xff) {
    case cJSON_False:
    case cJSON_True: return "a boolean";
    case cJSON_NULL: return "null";
    case cJSON_Number: return "a number";
    case cJSON_String: return "a string";
    case cJSON_Array: return "an array";
    case cJSON_Object: return "an object";
    default: return "an invalid value";
    }
}

const char *json_kind(const cJSON *j)
{
    return j ? json_type_kind(j->type) : "nothing";
}

void json_path(char *out, size_t cap, const char *path, const char *key)
{
    if (!key) {
        snprintf(out, cap, "%s", path ? path : "");
    } else if (path && path[0]) {
        snprintf(out, cap, "%s.%s", path, key);
    } else {
        snprintf(out, cap, "%s", key);
    }
}

void json_path_index(char *out, size_t cap, const char *path, int i)
{
    snprintf(out, cap, "%s[%d]", path ? path : "", i);
}

static bool wire(const json_rd *r)
{
    return r->voice == JSON_VOICE_WIRE;
}

/* An absent required key; what = "a number", "a string", ... for the WIRE voice. */
static int missing(const json_rd *r, const char *p, const char *what)
{
    if (wire(r)) {
        return json_fail(r, GALE_E_PARSE, "%s: missing: expected %s", p, what);
    }
    return json_fail(r, GALE_E_PARSE, "%s: required key missing", p);
}

int json_check_keys(const json_rd *r, const cJSON *obj, const char *path,
                    const char *const *keys)
{
    if (!wire(r) && !cJSON_IsObject(obj)) {
        return json_fail(r, GALE_E_PARSE, "%s: expected an object, got %s",
                         path && path[0] ? path : "(top)", json_kind(obj));
    }
    for (const cJSON *c = obj->child; c; c = c->next) {
        bool known = false;
        for (const char *const *k = keys; *k; k++) {
            if (c->string && strcmp(c->string, *k) == 0) {
                known = true;
                break;
            }
        }
        char p[256];
        if (!known) {
            if (wire(r)) {
                return json_fail(r, GALE_E_PARSE, "%s: unknown key \"%.40s\"", path,
                                 c->string ? c->string : "");
            }
            json_path(p, sizeof p, path, c->string ? c->string : "?");
            return json_fail(r, GALE_E_PARSE, "%s: unknown key", p);
        }
        if (wire(r)) {
            continue;
        }
        /* a duplicate key would silently shadow the first: reject it */
        for (const cJSON *e = c->next; e; e = e->next) {
            if (c->string && e->string && strcmp(c->string, e->string) == 0) {
                json_path(p, sizeof p, path, c->string);
                return json_fail(r, GALE_E_PARSE, "%s: duplicate key", p);
            }
        }
    }
    return GALE_OK;
}

int json_check_number(const json_rd *r, const char *path, const char *key, double lo,
                      double hi, double v)
{
    char p[256];
    json_path(p, sizeof p, path, key);
    if (wire(r)) {
        if (!isfinite(v) || v < lo || v > hi) {
            return json_fail(r, GALE_E_RANGE, "%s: expected a number in [%.17g, %.17g], got %.17g",
                             p, lo, hi, v);
        }
        return GALE_OK;
    }
    if (!isfinite(v)) {
        return json_fail(r, GALE_E_RANGE, "%s: expected a finite number", p);
    }
    if (v < lo || v > hi) {
        return json_fail(r, GALE_E_RANGE, "%s: expected a number in [%g, %g], got %g", p, lo, hi,
                         v);
    }
    return GALE_OK;
}

int json_check_int(const json_rd *r, const char *path, const char *key, long long lo,
                   long long hi, double v)
{
    char p[256];
    json_path(p, sizeof p, path, key);
    if (!wire(r) && !isfinite(v)) {
        return json_fail(r, GALE_E_RANGE, "%s: expected a finite number", p);
    }
    if (!isfinite(v) || v != floor(v) || v < (double)lo || v > (double)hi) {
        return json_fail(r, GALE_E_RANGE,
                         wire(r) ? "%s: expected an integer in [%lld, %lld], got %.17g"
                                 : "%s: expected an integer in [%lld, %lld], got %g",
                         p, lo, hi, v);
    }
    return GALE_OK;
}

static int check_len(const json_rd *r, const char *path, const char *key, size_t n, size_t cap)
{
    if (n >= cap) {
        char p[256];
        json_path(p, sizeof p, path, key);
        return json_fail(r, GALE_E_RANGE,
                         wire(r) ? "%s: expected at most %zu bytes, got %zu"
                                 : "%s: expected at most %zu characters, got %zu",
                         p, cap - 1, n);
    }
    return GALE_OK;
}

int json_check_string(const json_rd *r, const char *path, const char *key, const char *s,
                      size_t cap)
{
    /* bounded: an encoder's fixed-size field need not hold a NUL */
    size_t n = 0;
    while (n < cap && s[n]) {
        n++;
    }
    return check_len(r, path, key, n, cap);
}

/* obj[key] when present and a number: 1; absent (and allowed to be): 0; else < 0. */
static int fetch_number(const json_rd *r, const cJSON *obj, const char *path, const char *key,
                        bool required, double *v, bool *has)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (has) {
        *has = j != NULL;
    }
    char p[256];
    json_path(p, sizeof p, path, key);
    if (!j) {
        return required ? missing(r, p, "a number") : 0;
    }
    if (!cJSON_IsNumber(j)) {
        return json_fail(r, GALE_E_PARSE, "%s: expected a number, got %s", p, json_kind(j));
    }
    *v = j->valuedouble;
    return 1;
}

int json_number(const json_rd *r, const cJSON *obj, const char *path, const char *key,
                bool required, double lo, double hi, double *out, bool *has)
{
    double v = 0.0;
    int rc = fetch_number(r, obj, path, key, required, &v, has);
    if (rc <= 0) {
        return rc;
    }
    if ((rc = json_check_number(r, path, key, lo, hi, v))) {
        return rc;
    }
    *out = v;
    return GALE_OK;
}

int json_int(const json_rd *r, const cJSON *obj, const char *path, const char *key,
             bool required, long long lo, long long hi, long long *out, bool *has)
{
    double v = 0.0;
    int rc = fetch_number(r, obj, path, key, required, &v, has);
    if (rc <= 0) {
        return rc;
    }
    if ((rc = json_check_int(r, path, key, lo, hi, v))) {
        return rc;
    }
    *out = (long long)v;
    return GALE_OK;
}

int json_bool(const json_rd *r, const cJSON *obj, const char *path, const char *key,
              bool required, bool *out, bool *has)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (has) {
        *has = j != NULL;
    }
    char p[256];
    json_path(p, sizeof p, path, key);
    if (!j) {
        return required ? missing(r, p, "a boolean") : GALE_OK;
    }
    if (!cJSON_IsBool(j)) {
        return json_fail(r, GALE_E_PARSE, "%s: expected a boolean, got %s", p, json_kind(j));
    }
    *out = cJSON_IsTrue(j);
    return GALE_OK;
}

int json_string(const json_rd *r, const cJSON *obj, const char *path, const char *key,
                bool required, const char *def, char *out, size_t cap, bool *has)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (has) {
        *has = j != NULL;
    }
    const char *s = def;
    if (!j) {
        if (required) {
            char p[256];
            json_path(p, sizeof p, path, key);
            return missing(r, p, "a string");
        }
    } else if (!cJSON_IsString(j)) {
        char p[256];
        json_path(p, sizeof p, path, key);
        return json_fail(r, GALE_E_PARSE, "%s: expected a string, got %s", p, json_kind(j));
    } else {
        s = j->valuestring;
    }
    if (!s) {
        s = "";
    }
    size_t n = strlen(s);
    int rc = check_len(r, path, key, n, cap);
    if (rc) {
        return rc;
    }
    memcpy(out, s, n + 1);
    return GALE_OK;
}

int json_vec(const json_rd *r, const cJSON *obj, const char *path, const char *key,
             bool required, int n, double lo, double hi, double *out, bool *has)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (has) {
        *has = j != NULL;
    }
    char p[256];
    json_path(p, sizeof p, path, key);
    if (!j) {
        if (required) {
            char what[40];
            snprintf(what, sizeof what, "an array of %d numbers", n);
            return missing(r, p, what);
        }
        return GALE_OK;
    }
    if (!cJSON_IsArray(j) || cJSON_GetArraySize(j) != n) {
        return json_fail(r, GALE_E_PARSE, "%s: expected an array of %d numbers, got %s%s", p, n,
                         json_kind(j),
                         wire(r) && cJSON_IsArray(j) ? " of another length" : "");
    }
    int i = 0;
    for (const cJSON *e = j->child; e; e = e->next, i++) {
        char pi[280];
        json_path_index(pi, sizeof pi, p, i);
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble)) {
            if (wire(r)) {
                return json_fail(r, GALE_E_RANGE, "%s: expected a number in [%.17g, %.17g], got %s",
                                 pi, lo, hi, json_kind(e));
            }
            return json_fail(r, GALE_E_PARSE, "%s: expected a finite number, got %s", pi,
                             json_kind(e));
        }
        int rc = json_check_number(r, pi, NULL, lo, hi, e->valuedouble);
        if (rc) {
            return rc;
        }
        out[i] = e->valuedouble;
    }
    return GALE_OK;
}

int json_child(const json_rd *r, const cJSON *obj, const char *path, const char *key,
               int type, bool required, const cJSON **out)
{
    *out = NULL;
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    char p[256];
    json_path(p, sizeof p, path, key);
    if (!j) {
        return required ? missing(r, p, json_type_kind(type)) : GALE_OK;
    }
    if ((j->type & 0xff) != type) {
        return json_fail(r, GALE_E_PARSE, wire(r) ? "%s: wrong type: expected %s, got %s"
                                                  : "%s: expected %s, got %s",
                         p, json_type_kind(type), json_kind(j));
    }
    *out = j;
    return GALE_OK;
}

cJSON *json_add_number(cJSON *o, const char *key, double v)
{
    /* cJSON's own %d covers the int range; beyond it its %.15g (accepted when it reads back
     * within a relative DBL_EPSILON) drops the last digits of large integers. */
    if (v == floor(v) && fabs(v) > 2147483647.0 && fabs(v) <= 9007199254740992.0) {
        char b[24];
        snprintf(b, sizeof b, "%.0f", v);
        return cJSON_AddRawToObject(o, key, b);
    }
    return cJSON_AddNumberToObject(o, key, v);
}
