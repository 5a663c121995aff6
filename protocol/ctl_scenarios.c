/* welcome.scenarios (PROTOCOL.md "Control messages"): the scenarios a kiosk may switch
 * to, each with the name wind.scenario takes, the title a visitor reads, its kind and,
 * for a steady one, its mean 10 m wind. Optional on the wire; a decoded list belongs to
 * its welcome. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctl_int.h"

#define SUSTAINED_MAX_MS 100.0

static const char *const kind_names[] = { "steady", "replay" };
#define N_KINDS 2

/* No byte below 0x20 nor 0x7f: a title goes straight onto a screen. */
static int check_printable(ctl_rd *c, const char *path, const char *key, const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p < 0x20 || *p == 0x7f) {
            return ctl_fail(c, 0, GALE_E_RANGE, "%s.%s: expected printable text, got byte 0x%02x",
                            path, key, *p);
        }
    }
    return 0;
}

static int scenario_parse(ctl_rd *c, const cJSON *e, int i, ctl_scenario_info *s)
{
    static const char *const keys[] = { "name", "title", "kind", "sustained_ms", NULL };
    const json_rd *r = &c->j;
    char path[40];
    snprintf(path, sizeof path, "welcome.scenarios[%d]", i);
    if (!cJSON_IsObject(e)) {
        return ctl_fail(c, 0, GALE_E_PARSE, "%s: expected an object, got %s", path, json_kind(e));
    }
    double sus = 0;
    int rc = json_check_keys(r, e, path, keys);
    if (!rc) {
        rc = json_string(r, e, path, "name", true, NULL, s->name, sizeof s->name, NULL);
    }
    if (!rc && !s->name[0]) {
        rc = ctl_fail(c, 0, GALE_E_RANGE, "%s.name: expected a non-empty string, got \"\"", path);
    }
    if (!rc) {
        rc = check_printable(c, path, "name", s->name);
    }
    if (!rc) {
        rc = json_string(r, e, path, "title", true, NULL, s->title, sizeof s->title, NULL);
    }
    if (!rc) {
        rc = check_printable(c, path, "title", s->title);
    }
    if (!rc) {
        rc = ctl_get_enum(c, e, path, "kind", kind_names, N_KINDS, "steady|replay", &s->kind);
    }
    if (!rc) {
        rc = json_number(r, e, path, "sustained_ms", true, 0, SUSTAINED_MAX_MS, &sus, NULL);
    }
    s->sustained_ms = (float)sus;
    return rc;
}

int ctl_scenarios_parse(ctl_rd *c, const cJSON *o, ctl_welcome *w)
{
    const cJSON *sa = cJSON_GetObjectItemCaseSensitive(o, "scenarios");
    if (!sa) {
        return 0;
    }
    if (!cJSON_IsArray(sa)) {
        return ctl_fail(c, 0, GALE_E_PARSE,
                        "welcome.scenarios: wrong type: expected an array, got %s", json_kind(sa));
    }
    int n = cJSON_GetArraySize(sa);
    if (n > (int)WIRE_MAX_SCENARIOS) {
        return ctl_fail(c, 0, GALE_E_RANGE, "welcome.scenarios: expected <= %u entries, got %d",
                        WIRE_MAX_SCENARIOS, n);
    }
    if (n > 0) {
        w->scenarios = calloc((size_t)n, sizeof *w->scenarios);
        if (!w->scenarios) {
            return ctl_fail(c, 0, GALE_E_NOMEM, "welcome.scenarios: out of memory");
        }
    }
    w->n_scenarios = (uint32_t)n;
    int i = 0;
    for (const cJSON *e = sa->child; e; e = e->next, i++) {
        int rc = scenario_parse(c, e, i, &w->scenarios[i]);
        if (rc) {
            return rc;
        }
    }
    return 0;
}

static int scenario_encode(ctl_rd *c, const ctl_scenario_info *s, int i, cJSON *sa)
{
    const json_rd *r = &c->j;
    char path[40];
    snprintf(path, sizeof path, "welcome.scenarios[%d]", i);
    const char *kn = s->kind >= 0 && s->kind < N_KINDS ? kind_names[s->kind] : NULL;
    if (!kn) {
        return ctl_fail(c, 0, GALE_E_ARG, "%s.kind: expected a ctl_scenario_kind, got %d", path,
                        s->kind);
    }
    double sus = ctl_jnum(s->sustained_ms);
    int rc = json_check_string(r, path, "name", s->name, sizeof s->name);
    if (!rc && !s->name[0]) {
        rc = ctl_fail(c, 0, GALE_E_RANGE, "%s.name: expected a non-empty string, got \"\"", path);
    }
    if (!rc) {
        rc = check_printable(c, path, "name", s->name);
    }
    if (!rc) {
        rc = json_check_string(r, path, "title", s->title, sizeof s->title);
    }
    if (!rc) {
        rc = check_printable(c, path, "title", s->title);
    }
    if (!rc) {
        rc = json_check_number(r, path, "sustained_ms", 0, SUSTAINED_MAX_MS, sus);
    }
    if (rc) {
        return rc;
    }
    cJSON *so = cJSON_CreateObject();
    if (!so || !cJSON_AddItemToArray(sa, so)) {
        cJSON_Delete(so);
        return ctl_fail(c, 0, GALE_E_NOMEM, "welcome: out of memory");
    }
    return cJSON_AddStringToObject(so, "name", s->name) &&
                   cJSON_AddStringToObject(so, "title", s->title) &&
                   cJSON_AddStringToObject(so, "kind", kn) && ctl_add_num(so, "sustained_ms", sus)
               ? 0
               : ctl_fail(c, 0, GALE_E_NOMEM, "welcome: out of memory");
}

int ctl_scenarios_encode(ctl_rd *c, const ctl_welcome *w, cJSON *o)
{
    if (w->n_scenarios > WIRE_MAX_SCENARIOS) {
        return ctl_fail(c, 0, GALE_E_RANGE, "welcome.scenarios: expected <= %u entries, got %u",
                        WIRE_MAX_SCENARIOS, w->n_scenarios);
    }
    /* Omitted when there are none, so a server without choices keeps its welcome. */
    if (w->n_scenarios == 0) {
        return 0;
    }
    cJSON *sa = cJSON_AddArrayToObject(o, "scenarios");
    if (!sa) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "welcome: out of memory");
    }
    for (uint32_t i = 0; i < w->n_scenarios; i++) {
        int rc = scenario_encode(c, &w->scenarios[i], (int)i, sa);
        if (rc) {
            return rc;
        }
    }
    return 0;
}
