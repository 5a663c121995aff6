/* Validated JSON configuration: see cfg.h. */
#include "cfg.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void cfg_path(char *out, size_t cap, const char *path, const char *key)
{
    if (path && path[0]) {
        snprintf(out, cap, "%s.%s", path, key);
    } else {
        snprintf(out, cap, "%s", key);
    }
}

void cfg_path_index(char *out, size_t cap, const char *path, int i)
{
    snprintf(out, cap, "%s[%d]", path ? path : "", i);
}

static const char *type_name(const cJSON *j)
{
    if (!j) {
        return "nothing";
    }
    switch (j->type & 0xff) {
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

int cfg_parse(cfg_doc *d, const char *name, const char *text, size_t len, gale_err *err)
{
    memset(d, 0, sizeof *d);
    snprintf(d->name, sizeof d->name, "%s", name ? name : "<config>");
    const char *end = NULL;
    d->root = cJSON_ParseWithLengthOpts(text, len, &end, false);
    if (!d->root) {
        /* cJSON leaves end at the byte where parsing failed: turn it into line:col. */
        size_t off = (end && end >= text && (size_t)(end - text) <= len) ? (size_t)(end - text)
                                                                          : 0;
        int line = 1, col = 1;
        for (size_t i = 0; i < off; i++) {
            if (text[i] == '\n') {
                line++;
                col = 1;
            } else {
                col++;
            }
        }
        if (len == 0) {
            return gale_errf(err, GALE_E_PARSE, "%s: empty file: expected a JSON object",
                             d->name);
        }
        return gale_errf(err, GALE_E_PARSE, "%s:%d:%d: invalid JSON", d->name, line, col);
    }
    if (!cJSON_IsObject(d->root)) {
        int rc = gale_errf(err, GALE_E_PARSE, "%s: expected a JSON object at the top, got %s",
                           d->name, type_name(d->root));
        cfg_fini(d);
        return rc;
    }
    return GALE_OK;
}

int cfg_load(cfg_doc *d, const char *path, gale_err *err)
{
    memset(d, 0, sizeof *d);
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len == cap) {
            cap = cap ? cap * 2 : 4096;
            if (cap > (64u << 20)) {
                free(buf);
                fclose(f);
                return gale_errf(err, GALE_E_RANGE, "%s: larger than 64 MiB", path);
            }
            char *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(f);
                return gale_errf(err, GALE_E_NOMEM, "%s: out of memory", path);
            }
            buf = nb;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            break;
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: read error", path);
    }
    int rc = cfg_parse(d, path, buf, len, err);
    free(buf);
    return rc;
}

void cfg_fini(cfg_doc *d)
{
    if (d) {
        cJSON_Delete(d->root);
        d->root = NULL;
    }
}

int cfg_check_keys(const cfg_doc *d, const cJSON *obj, const char *path,
                   const char *const *allowed, gale_err *err)
{
    if (!cJSON_IsObject(obj)) {
        return gale_errf(err, GALE_E_PARSE, "%s: %s: expected an object, got %s", d->name,
                         path && path[0] ? path : "(top)", type_name(obj));
    }
    for (const cJSON *c = obj->child; c; c = c->next) {
        bool ok = false;
        for (const char *const *a = allowed; *a; a++) {
            if (c->string && strcmp(c->string, *a) == 0) {
                ok = true;
                break;
            }
        }
        if (!ok) {
            char p[256];
            cfg_path(p, sizeof p, path, c->string ? c->string : "?");
            return gale_errf(err, GALE_E_PARSE, "%s: %s: unknown key", d->name, p);
        }
        /* a duplicate key would silently shadow the first: reject it */
        for (const cJSON *e = c->next; e; e = e->next) {
            if (c->string && e->string && strcmp(c->string, e->string) == 0) {
                char p[256];
                cfg_path(p, sizeof p, path, c->string);
                return gale_errf(err, GALE_E_PARSE, "%s: %s: duplicate key", d->name, p);
            }
        }
    }
    return GALE_OK;
}

const cJSON *cfg_child(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
                       int type, bool required, bool *found, gale_err *err)
{
    char p[256];
    cfg_path(p, sizeof p, path, key);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (found) {
        *found = c != NULL;
    }
    if (!c) {
        if (required) {
            gale_errf(err, GALE_E_PARSE, "%s: %s: required key missing", d->name, p);
        }
        return NULL;
    }
    if ((c->type & 0xff) != type) {
        cJSON probe = { 0 };
        probe.type = type;
        gale_errf(err, GALE_E_PARSE, "%s: %s: expected %s, got %s", d->name, p,
                  type_name(&probe), type_name(c));
        if (found) {
            *found = false;
        }
        return NULL;
    }
    return c;
}

/* Fetches obj[key] as a number; 1 = got it, 0 = absent (not required), < 0 = error. */
static int get_number(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
                      bool required, double *v, gale_err *err)
{
    char p[256];
    cfg_path(p, sizeof p, path, key);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!c) {
        if (required) {
            return gale_errf(err, GALE_E_PARSE, "%s: %s: required key missing", d->name, p);
        }
        return 0;
    }
    if (!cJSON_IsNumber(c)) {
        return gale_errf(err, GALE_E_PARSE, "%s: %s: expected a number, got %s", d->name, p,
                         type_name(c));
    }
    if (!isfinite(c->valuedouble)) {
        return gale_errf(err, GALE_E_RANGE, "%s: %s: expected a finite number", d->name, p);
    }
    *v = c->valuedouble;
    return 1;
}

int cfg_number(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
               bool required, double def, double min, double max, double *out, gale_err *err)
{
    double v = def;
    int rc = get_number(d, obj, path, key, required, &v, err);
    if (rc < 0) {
        return rc;
    }
    if (rc == 1 && (v < min || v > max)) {
        char p[256];
        cfg_path(p, sizeof p, path, key);
        return gale_errf(err, GALE_E_RANGE, "%s: %s: expected a number in [%g, %g], got %g",
                         d->name, p, min, max, v);
    }
    *out = v;
    return GALE_OK;
}

int cfg_int(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
            bool required, long long def, long long min, long long max, long long *out,
            gale_err *err)
{
    double v = (double)def;
    int rc = get_number(d, obj, path, key, required, &v, err);
    if (rc < 0) {
        return rc;
    }
    if (rc == 1) {
        char p[256];
        cfg_path(p, sizeof p, path, key);
        if (v != floor(v) || v < (double)min || v > (double)max) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: %s: expected an integer in [%lld, %lld], got %g", d->name, p,
                             min, max, v);
        }
        *out = (long long)v;
    } else {
        *out = def;
    }
    return GALE_OK;
}

int cfg_bool(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
             bool required, bool def, bool *out, gale_err *err)
{
    char p[256];
    cfg_path(p, sizeof p, path, key);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!c) {
        if (required) {
            return gale_errf(err, GALE_E_PARSE, "%s: %s: required key missing", d->name, p);
        }
        *out = def;
        return GALE_OK;
    }
    if (!cJSON_IsBool(c)) {
        return gale_errf(err, GALE_E_PARSE, "%s: %s: expected a boolean, got %s", d->name, p,
                         type_name(c));
    }
    *out = cJSON_IsTrue(c);
    return GALE_OK;
}

int cfg_string(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
               bool required, const char *def, char *out, size_t cap, gale_err *err)
{
    char p[256];
    cfg_path(p, sizeof p, path, key);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(obj, key);
    const char *s = def;
    if (!c) {
        if (required) {
            return gale_errf(err, GALE_E_PARSE, "%s: %s: required key missing", d->name, p);
        }
    } else if (!cJSON_IsString(c)) {
        return gale_errf(err, GALE_E_PARSE, "%s: %s: expected a string, got %s", d->name, p,
                         type_name(c));
    } else {
        s = c->valuestring;
    }
    if (!s) {
        s = "";
    }
    if (strlen(s) >= cap) {
        return gale_errf(err, GALE_E_RANGE, "%s: %s: expected at most %zu characters, got %zu",
                         d->name, p, cap - 1, strlen(s));
    }
    memcpy(out, s, strlen(s) + 1);
    return GALE_OK;
}

int cfg_vec(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
            bool required, int n, const double *def, double min, double max, double *out,
            gale_err *err)
{
    char p[256];
    cfg_path(p, sizeof p, path, key);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!c) {
        if (required) {
            return gale_errf(err, GALE_E_PARSE, "%s: %s: required key missing", d->name, p);
        }
        if (def) {
            memcpy(out, def, (size_t)n * sizeof *out);
        }
        return GALE_OK;
    }
    if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) != n) {
        return gale_errf(err, GALE_E_PARSE, "%s: %s: expected an array of %d numbers, got %s",
                         d->name, p, n, type_name(c));
    }
    int i = 0;
    for (const cJSON *e = c->child; e; e = e->next, i++) {
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble)) {
            return gale_errf(err, GALE_E_PARSE, "%s: %s[%d]: expected a finite number, got %s",
                             d->name, p, i, type_name(e));
        }
        if (e->valuedouble < min || e->valuedouble > max) {
            return gale_errf(err, GALE_E_RANGE, "%s: %s[%d]: expected a number in [%g, %g], got %g",
                             d->name, p, i, min, max, e->valuedouble);
        }
        out[i] = e->valuedouble;
    }
    return GALE_OK;
}
