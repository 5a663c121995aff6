/* Usage counters, their sessions and their file (ops_usage.h). */
#include "ops_usage.h"

#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "json.h"

#define FILE_FORMAT "gale-usage"
#define FILE_VERSION 1
#define FILE_MAX_BYTES (1u << 20) /* a file is a few hundred bytes; more is not ours */

/* The file's key of each Saffir-Simpson class (wind_scale.h order). */
static const char *const class_keys[WIND_SCALE_SS_COUNT] = { "td",   "ts",   "cat1", "cat2",
                                                             "cat3", "cat4", "cat5" };

void ops_usage_init(ops_usage *u)
{
    memset(u, 0, sizeof *u);
    u->last_class = -1;
}

static void end_session(ops_usage *u)
{
    if (u->in_session) {
        u->dwell_s += u->last_s - u->start_s;
        u->in_session = false;
    }
}

bool ops_usage_interaction(ops_usage *u, double now_s, double idle_s)
{
    if (u->in_session && now_s - u->last_s > idle_s) {
        end_session(u);
    }
    const bool began = !u->in_session;
    if (began) {
        u->in_session = true;
        u->sessions++;
        u->start_s = now_s;
        u->last_class = -1;
    }
    u->last_s = now_s;
    return began;
}

bool ops_usage_poll(ops_usage *u, double now_s, double idle_s)
{
    if (u->in_session && now_s - u->last_s > idle_s) {
        end_session(u);
        return true;
    }
    return false;
}

void ops_usage_end(ops_usage *u)
{
    end_session(u);
}

void ops_usage_dial(ops_usage *u, double speed_ms)
{
    const int c = wind_scale_ss_class(speed_ms);
    if (c != u->last_class) {
        u->categories[c]++;
        u->last_class = c;
    }
}

void ops_usage_count(ops_count *t, int *n, const char *name)
{
    for (int i = 0; i < *n; i++) {
        if (!strcmp(t[i].name, name)) {
            t[i].n++;
            return;
        }
    }
    if (*n < OPS_USAGE_MAX_NAMES - 1 || (*n == OPS_USAGE_MAX_NAMES - 1 &&
                                         !strcmp(name, OPS_USAGE_OTHER))) {
        snprintf(t[*n].name, sizeof t[*n].name, "%s", name);
        t[(*n)++].n = 1;
        return;
    }
    ops_usage_count(t, n, OPS_USAGE_OTHER); /* the last row is kept for the rest */
}

double ops_usage_open_dwell_s(const ops_usage *u)
{
    return u->in_session ? u->last_s - u->start_s : 0.0;
}

/* --- the file ---------------------------------------------------------------------------- */

static cJSON *names_json(const ops_count *t, int n)
{
    cJSON *o = cJSON_CreateObject();
    for (int i = 0; o && i < n; i++) {
        if (!json_add_number(o, t[i].name, (double)t[i].n)) {
            cJSON_Delete(o);
            return NULL;
        }
    }
    return o;
}

char *ops_usage_json(const ops_usage *u)
{
    cJSON *o = cJSON_CreateObject(), *cat = cJSON_CreateObject();
    cJSON *rep = names_json(u->replays, u->n_replays), *lang = names_json(u->langs, u->n_langs);
    char *text = NULL;
    bool ok = o && cat && rep && lang && cJSON_AddStringToObject(o, "format", FILE_FORMAT) &&
              json_add_number(o, "version", FILE_VERSION) &&
              json_add_number(o, "sessions", (double)u->sessions) &&
              json_add_number(o, "dwell_s", round(u->dwell_s * 1e3) / 1e3); /* to the ms */
    for (int c = 0; ok && c < WIND_SCALE_SS_COUNT; c++) {
        ok = json_add_number(cat, class_keys[c], (double)u->categories[c]) != NULL;
    }
    if (ok) {
        cJSON_AddItemToObject(o, "categories", cat);
        cJSON_AddItemToObject(o, "replays", rep);
        cJSON_AddItemToObject(o, "languages", lang);
        cat = rep = lang = NULL;
        text = cJSON_PrintUnformatted(o);
    }
    cJSON_Delete(o);
    cJSON_Delete(cat);
    cJSON_Delete(rep);
    cJSON_Delete(lang);
    return text;
}

/* A names object of the file (each value a count) into t[*n]. */
static int load_names(const json_rd *r, const cJSON *root, const char *key, ops_count *t, int *n)
{
    const cJSON *o = NULL;
    int rc = json_child(r, root, "", key, cJSON_Object, true, &o);
    for (const cJSON *k = o ? o->child : NULL; !rc && k; k = k->next) {
        if (!k->string[0] || strlen(k->string) >= OPS_USAGE_NAME) {
            return json_fail(r, GALE_E_PARSE, "%s: expected names of 1 to %u bytes, got \"%.40s\"",
                             key, OPS_USAGE_NAME - 1, k->string);
        }
        if (*n >= OPS_USAGE_MAX_NAMES) {
            return json_fail(r, GALE_E_RANGE, "%s: expected at most %d names, got more", key,
                             OPS_USAGE_MAX_NAMES);
        }
        for (int i = 0; i < *n; i++) {
            if (!strcmp(t[i].name, k->string)) {
                return json_fail(r, GALE_E_PARSE, "%s.%s: duplicate key", key, k->string);
            }
        }
        long long v = 0;
        rc = json_int(r, o, key, k->string, true, 0, 1LL << 53, &v, NULL);
        snprintf(t[*n].name, sizeof t[*n].name, "%s", k->string);
        t[(*n)++].n = (unsigned long long)v;
    }
    return rc;
}

static int parse_file(ops_usage *u, const json_rd *r, const char *text, size_t len)
{
    size_t at = 0;
    cJSON *root = json_parse(text, len, &at);
    int rc = 0;
    if (!root) {
        int line, col;
        json_line_col(text, at, &line, &col);
        return gale_errf(r->err, GALE_E_PARSE, "%s:%d:%d: invalid JSON", r->where, line, col);
    }
    static const char *const keys[] = { "format",  "version",  "sessions",  "dwell_s",
                                        "categories", "replays", "languages", NULL };
    char format[32];
    long long version = 0, sessions = 0;
    double dwell = 0;
    rc = json_check_keys(r, root, "", keys);
    if (!rc) {
        rc = json_string(r, root, "", "format", true, NULL, format, sizeof format, NULL);
    }
    if (!rc && strcmp(format, FILE_FORMAT)) {
        rc = json_fail(r, GALE_E_PARSE, "format: expected \"%s\", got \"%s\"", FILE_FORMAT,
                       format);
    }
    if (!rc) {
        rc = json_int(r, root, "", "version", true, FILE_VERSION, FILE_VERSION, &version, NULL);
    }
    if (!rc) {
        rc = json_int(r, root, "", "sessions", true, 0, 1LL << 53, &sessions, NULL);
    }
    if (!rc) {
        rc = json_number(r, root, "", "dwell_s", true, 0, 1e15, &dwell, NULL);
    }
    const cJSON *cat = NULL;
    if (!rc) {
        rc = json_child(r, root, "", "categories", cJSON_Object, true, &cat);
    }
    if (!rc) {
        static const char *const ckeys[] = { "td", "ts", "cat1", "cat2", "cat3", "cat4", "cat5",
                                             NULL };
        rc = json_check_keys(r, cat, "categories", ckeys);
    }
    for (int c = 0; !rc && c < WIND_SCALE_SS_COUNT; c++) {
        long long v = 0;
        rc = json_int(r, cat, "categories", class_keys[c], true, 0, 1LL << 53, &v, NULL);
        u->categories[c] = (unsigned long long)v;
    }
    if (!rc) {
        rc = load_names(r, root, "replays", u->replays, &u->n_replays);
    }
    if (!rc) {
        rc = load_names(r, root, "languages", u->langs, &u->n_langs);
    }
    u->sessions = (unsigned long long)sessions;
    u->dwell_s = dwell;
    cJSON_Delete(root);
    return rc;
}

int ops_usage_load(ops_usage *u, const char *path, bool *found, gale_err *err)
{
    ops_usage_init(u);
    *found = false;
    FILE *f = fopen(path, "rb");
    if (!f) {
        if (errno == ENOENT) {
            return 0;
        }
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    char *text = malloc(FILE_MAX_BYTES + 1);
    size_t n = text ? fread(text, 1, FILE_MAX_BYTES + 1, f) : 0;
    const bool bad = ferror(f);
    fclose(f);
    int rc = 0;
    if (!text) {
        rc = gale_errf(err, GALE_E_NOMEM, "%s: no memory to read it", path);
    } else if (bad) {
        rc = gale_errf(err, GALE_E_IO, "%s: cannot read: %s", path, strerror(errno));
    } else if (n > FILE_MAX_BYTES) {
        rc = gale_errf(err, GALE_E_PARSE, "%s: expected at most %u bytes, got more", path,
                       FILE_MAX_BYTES);
    } else {
        rc = ops_usage_parse(u, path, text, n, err);
    }
    free(text);
    *found = rc == 0;
    return rc;
}

int ops_usage_parse(ops_usage *u, const char *name, const char *text, size_t len, gale_err *err)
{
    ops_usage_init(u);
    json_rd r = { name, JSON_VOICE_FILE, err };
    int rc = parse_file(u, &r, text, len);
    if (rc) {
        ops_usage_init(u);
    }
    return rc;
}

int ops_usage_save(const ops_usage *u, const char *path, gale_err *err)
{
    ops_usage v = *u;
    ops_usage_end(&v); /* the session under way counts what it has so far */
    char *text = ops_usage_json(&v);
    if (!text) {
        return gale_errf(err, GALE_E_NOMEM, "%s: no memory to write it", path);
    }
    char tmp[4096];
    if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp", path) >= sizeof tmp) {
        free(text);
        return gale_errf(err, GALE_E_ARG, "%s: expected a shorter path", path);
    }
    int rc = 0;
    const size_t n = strlen(text);
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0640);
    if (fd < 0) {
        rc = gale_errf(err, GALE_E_IO, "%s: cannot create: %s", tmp, strerror(errno));
    } else {
        size_t off = 0;
        while (!rc && off < n) {
            ssize_t w = write(fd, text + off, n - off);
            if (w < 0 && errno == EINTR) {
                continue;
            }
            if (w <= 0) {
                rc = gale_errf(err, GALE_E_IO, "%s: cannot write: %s", tmp, strerror(errno));
            } else {
                off += (size_t)w;
            }
        }
        if (!rc && (write(fd, "\n", 1) != 1 || fsync(fd))) {
            rc = gale_errf(err, GALE_E_IO, "%s: cannot write: %s", tmp, strerror(errno));
        }
        if (close(fd) && !rc) {
            rc = gale_errf(err, GALE_E_IO, "%s: cannot close: %s", tmp, strerror(errno));
        }
        if (!rc && rename(tmp, path)) {
            rc = gale_errf(err, GALE_E_IO, "%s: cannot rename %s over it: %s", path, tmp,
                           strerror(errno));
        }
        if (rc) {
            unlink(tmp);
        }
    }
    if (!rc) {
        /* the rename itself is durable once the folder's entry is */
        char dir[4096];
        snprintf(dir, sizeof dir, "%s", path);
        char *slash = strrchr(dir, '/');
        if (slash) {
            *(slash == dir ? slash + 1 : slash) = 0;
        } else {
            snprintf(dir, sizeof dir, ".");
        }
        int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (dfd >= 0) {
            fsync(dfd);
            close(dfd);
        }
    }
    free(text);
    return rc;
}

/* --- Prometheus -------------------------------------------------------------------------- */

static bool add(char *out, size_t cap, size_t *len, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static bool add(char *out, size_t cap, size_t *len, const char *fmt, ...)
{
    if (*len >= cap) {
        return false;
    }
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(out + *len, cap - *len, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= cap - *len) {
        return false;
    }
    *len += (size_t)n;
    return true;
}

/* name as a Prometheus label value: \, " and newline escaped. */
static void label(char *out, size_t cap, const char *name)
{
    size_t k = 0;
    for (const char *p = name; *p && k + 3 < cap; p++) {
        if (*p == '\\' || *p == '"') {
            out[k++] = '\\';
            out[k++] = *p;
        } else if (*p == '\n') {
            out[k++] = '\\';
            out[k++] = 'n';
        } else {
            out[k++] = *p;
        }
    }
    out[k] = 0;
}

static bool prom_names(char *out, size_t cap, size_t *len, const char *metric, const char *lkey,
                       const char *help, const ops_count *t, int n)
{
    bool ok = add(out, cap, len, "# HELP %s %s\n# TYPE %s counter\n", metric, help, metric);
    for (int i = 0; ok && i < n; i++) {
        char l[2 * OPS_USAGE_NAME + 2];
        label(l, sizeof l, t[i].name);
        ok = add(out, cap, len, "%s{%s=\"%s\"} %llu\n", metric, lkey, l, t[i].n);
    }
    return ok;
}

bool ops_usage_prom(const ops_usage *u, char *out, size_t cap, size_t *len)
{
    ops_usage v = *u;
    ops_usage_end(&v);
    bool ok = add(out, cap, len,
                  "# HELP gale_usage_sessions_total Kiosk sessions begun (kept across restarts)\n"
                  "# TYPE gale_usage_sessions_total counter\ngale_usage_sessions_total %llu\n"
                  "# HELP gale_usage_dwell_seconds_total Time from each session's first to its "
                  "last interaction, summed\n"
                  "# TYPE gale_usage_dwell_seconds_total counter\n"
                  "gale_usage_dwell_seconds_total %.3f\n"
                  "# HELP gale_usage_dials_total Dialled winds by Saffir-Simpson class\n"
                  "# TYPE gale_usage_dials_total counter\n",
                  v.sessions, v.dwell_s);
    for (int c = 0; ok && c < WIND_SCALE_SS_COUNT; c++) {
        ok = add(out, cap, len, "gale_usage_dials_total{class=\"%s\"} %llu\n", class_keys[c],
                 v.categories[c]);
    }
    return ok &&
           prom_names(out, cap, len, "gale_usage_scenarios_total", "scenario",
                      "Scenarios chosen at a kiosk, by name", v.replays, v.n_replays) &&
           prom_names(out, cap, len, "gale_usage_languages_total", "lang",
                      "Languages kiosks reported (kiosk_state), by tag", v.langs, v.n_langs);
}
