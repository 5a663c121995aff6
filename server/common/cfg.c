/* Validated JSON configuration: see cfg.h. Parsing, key checks and typed getters are
 * protocol/json.h's, in its FILE voice; what is cfg's own is the file and its name. */
#include "cfg.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"

/* The kit's reader for document d: messages start with its file name. */
static json_rd reader(const cfg_doc *d, gale_err *err)
{
    json_rd r = { d->name, JSON_VOICE_FILE, err };
    return r;
}

void cfg_path(char *out, size_t cap, const char *path, const char *key)
{
    json_path(out, cap, path, key);
}

void cfg_path_index(char *out, size_t cap, const char *path, int i)
{
    json_path_index(out, cap, path, i);
}

int cfg_parse(cfg_doc *d, const char *name, const char *text, size_t len, gale_err *err)
{
    memset(d, 0, sizeof *d);
    snprintf(d->name, sizeof d->name, "%s", name ? name : "<config>");
    size_t at = 0;
    d->root = json_parse(text, len, &at);
    if (!d->root) {
        if (len == 0) {
            return gale_errf(err, GALE_E_PARSE, "%s: empty file: expected a JSON object",
                             d->name);
        }
        int line, col;
        json_line_col(text, at, &line, &col);
        return gale_errf(err, GALE_E_PARSE, "%s:%d:%d: invalid JSON", d->name, line, col);
    }
    if (!cJSON_IsObject(d->root)) {
        int rc = gale_errf(err, GALE_E_PARSE, "%s: expected a JSON object at the top, got %s",
                           d->name, json_kind(d->root));
        cfg_fini(d);
        return rc;
    }
    /* cJSON stops after the first value: a second object or stray text after it would
     * otherwise be silently ignored (a config pasted twice, a merge left half-done) */
    size_t rest = json_skip_space(text, len, at);
    if (rest < len) {
        int line, col;
        json_line_col(text, rest, &line, &col);
        cfg_fini(d);
        return gale_errf(err, GALE_E_PARSE,
                         "%s:%d:%d: trailing bytes after the JSON object: expected the end of "
                         "the file",
                         d->name, line, col);
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
    json_rd r = reader(d, err);
    return json_check_keys(&r, obj, path, allowed);
}

const cJSON *cfg_child(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
                       int type, bool required, bool *found, gale_err *err)
{
    json_rd r = reader(d, err);
    const cJSON *c = NULL;
    int rc = json_child(&r, obj, path, key, type, required, &c);
    if (found) {
        *found = rc == 0 && c != NULL;
    }
    return c;
}

int cfg_number(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
               bool required, double def, double min, double max, double *out, gale_err *err)
{
    json_rd r = reader(d, err);
    double v = def;
    int rc = json_number(&r, obj, path, key, required, min, max, &v, NULL);
    if (rc == GALE_OK) {
        *out = v;
    }
    return rc;
}

int cfg_int(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
            bool required, long long def, long long min, long long max, long long *out,
            gale_err *err)
{
    json_rd r = reader(d, err);
    long long v = def;
    int rc = json_int(&r, obj, path, key, required, min, max, &v, NULL);
    if (rc == GALE_OK) {
        *out = v;
    }
    return rc;
}

int cfg_bool(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
             bool required, bool def, bool *out, gale_err *err)
{
    json_rd r = reader(d, err);
    bool v = def;
    int rc = json_bool(&r, obj, path, key, required, &v, NULL);
    if (rc == GALE_OK) {
        *out = v;
    }
    return rc;
}

int cfg_string(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
               bool required, const char *def, char *out, size_t cap, gale_err *err)
{
    json_rd r = reader(d, err);
    return json_string(&r, obj, path, key, required, def, out, cap, NULL);
}

int cfg_vec(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
            bool required, int n, const double *def, double min, double max, double *out,
            gale_err *err)
{
    json_rd r = reader(d, err);
    bool has = false;
    int rc = json_vec(&r, obj, path, key, required, n, min, max, out, &has);
    if (rc == GALE_OK && !has && def) {
        memcpy(out, def, (size_t)n * sizeof *out);
    }
    return rc;
}
