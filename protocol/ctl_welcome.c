/* welcome (PROTOCOL.md "Control messages"): the scene a client is let into: protocol,
 * its id and granted role, rates, the server clock, the species with their asset URLs
 * and hashes, every instance as a row [species, x, y, z, yaw_rad, scale] and every
 * obstacle as a row [min_x, min_y, min_z, max_x, max_y, max_z], and the scenarios a kiosk
 * may choose (ctl_scenarios.c). A decoded welcome owns its four arrays. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctl_int.h"

#define COORD_M 1e6   /* |coordinate| limit [m] */
#define SCALE_MAX 100 /* instance scale in (0, SCALE_MAX] */

/* ---- decoding ------------------------------------------------------------------------ */

/* An array member of the welcome that must be there. */
static int get_array(ctl_rd *c, const cJSON *o, const char *key, const cJSON **out)
{
    *out = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsArray(*out)) {
        return ctl_fail(c, 0, GALE_E_PARSE, "welcome.%s: %s: expected an array, got %s", key,
                        *out ? "wrong type" : "missing", json_kind(*out));
    }
    return 0;
}

/* One row of 6 finite numbers into v[6]; shape names the columns for the message. */
static int get_row(ctl_rd *c, const cJSON *e, const char *what, int i, const char *shape,
                   double *v)
{
    if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 6) {
        return ctl_fail(c, 0, GALE_E_PARSE, "welcome.%s[%d]: expected %s, got %s%s", what, i,
                        shape, json_kind(e), cJSON_IsArray(e) ? " of another length" : "");
    }
    int k = 0;
    for (const cJSON *x = e->child; x; x = x->next, k++) {
        if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble)) {
            return ctl_fail(c, 0, GALE_E_PARSE, "welcome.%s[%d][%d]: expected a number, got %s",
                            what, i, k, json_kind(x));
        }
        v[k] = x->valuedouble;
    }
    return 0;
}

static int welcome_species_parse(ctl_rd *c, const cJSON *e, int i, ctl_species *s)
{
    static const char *const keys[] = { "name", "url", "hash", "n_modes", NULL };
    const json_rd *r = &c->j;
    char path[40];
    snprintf(path, sizeof path, "welcome.species[%d]", i);
    if (!cJSON_IsObject(e)) {
        return ctl_fail(c, 0, GALE_E_PARSE, "%s: expected an object, got %s", path, json_kind(e));
    }
    long long nm = 0;
    int rc = json_check_keys(r, e, path, keys);
    if (!rc) {
        rc = json_string(r, e, path, "name", true, NULL, s->name, sizeof s->name, NULL);
    }
    if (!rc) {
        rc = json_string(r, e, path, "url", true, NULL, s->url, sizeof s->url, NULL);
    }
    if (!rc) {
        rc = json_string(r, e, path, "hash", true, NULL, s->hash, sizeof s->hash, NULL);
    }
    if (!rc && (strlen(s->hash) != 16 || strspn(s->hash, "0123456789abcdef") != 16)) {
        rc = ctl_fail(c, 0, GALE_E_RANGE, "%s.hash: expected 16 lowercase hex digits, got \"%s\"",
                      path, s->hash);
    }
    if (!rc) {
        rc = json_int(r, e, path, "n_modes", true, 1, WIRE_MAX_MODES, &nm, NULL);
    }
    s->n_modes = (uint32_t)nm;
    return rc;
}

/* Checks an instance row v[6] against ns species (both directions). */
static int instance_check(ctl_rd *c, int i, const double *v, int ns)
{
    if (v[0] < 0 || v[0] >= ns || v[0] != floor(v[0])) {
        return ctl_fail(c, 0, GALE_E_RANGE,
                        "welcome.instances[%d][0]: species: expected an integer in [0, %d], got %.17g",
                        i, ns - 1, v[0]);
    }
    for (int k = 1; k < 5; k++) {
        if (fabs(v[k]) > COORD_M) {
            return ctl_fail(c, 0, GALE_E_RANGE,
                            "welcome.instances[%d][%d]: expected |value| <= 1e6, got %.17g", i, k,
                            v[k]);
        }
    }
    if (!(v[5] > 0 && v[5] <= SCALE_MAX)) {
        return ctl_fail(c, 0, GALE_E_RANGE,
                        "welcome.instances[%d][5]: scale: expected (0, 100], got %.17g", i, v[5]);
    }
    return 0;
}

/* Checks an obstacle row v[6] (both directions). */
static int obstacle_check(ctl_rd *c, int i, const double *v)
{
    for (int k = 0; k < 6; k++) {
        if (fabs(v[k]) > COORD_M) {
            return ctl_fail(c, 0, GALE_E_RANGE,
                            "welcome.obstacles[%d][%d]: expected |value| <= 1e6, got %.17g", i, k,
                            v[k]);
        }
    }
    for (int k = 0; k < 3; k++) {
        if (!(v[k] <= v[k + 3])) {
            return ctl_fail(c, 0, GALE_E_RANGE,
                            "welcome.obstacles[%d]: expected min <= max on axis %c, got %.17g > %.17g",
                            i, "xyz"[k], v[k], v[k + 3]);
        }
    }
    return 0;
}

static int instances_parse(ctl_rd *c, const cJSON *o, ctl_welcome *w)
{
    const cJSON *in = NULL;
    int rc = get_array(c, o, "instances", &in);
    if (rc) {
        return rc;
    }
    int ni = cJSON_GetArraySize(in);
    if (ni > (int)WIRE_MAX_TREES) {
        return ctl_fail(c, 0, GALE_E_RANGE, "welcome.instances: expected <= %u entries, got %d",
                        WIRE_MAX_TREES, ni);
    }
    if (ni > 0) {
        w->instances = calloc((size_t)ni, sizeof *w->instances);
        if (!w->instances) {
            return ctl_fail(c, 0, GALE_E_NOMEM, "welcome.instances: out of memory");
        }
    }
    w->n_instances = (uint32_t)ni;
    int i = 0;
    for (const cJSON *e = in->child; e; e = e->next, i++) {
        double v[6];
        if ((rc = get_row(c, e, "instances", i, "[species, x, y, z, yaw_rad, scale]", v)) ||
            (rc = instance_check(c, i, v, (int)w->n_species))) {
            return rc;
        }
        ctl_instance *t = &w->instances[i];
        t->species = (uint32_t)v[0];
        t->pos[0] = (float)v[1];
        t->pos[1] = (float)v[2];
        t->pos[2] = (float)v[3];
        t->yaw_rad = (float)v[4];
        t->scale = (float)v[5];
    }
    return 0;
}

/* welcome.obstacles: optional. */
static int obstacles_parse(ctl_rd *c, const cJSON *o, ctl_welcome *w)
{
    const cJSON *ob = cJSON_GetObjectItemCaseSensitive(o, "obstacles");
    if (!ob) {
        return 0;
    }
    if (!cJSON_IsArray(ob)) {
        return ctl_fail(c, 0, GALE_E_PARSE,
                        "welcome.obstacles: wrong type: expected an array, got %s", json_kind(ob));
    }
    int n = cJSON_GetArraySize(ob);
    if (n > (int)WIRE_MAX_OBSTACLES) {
        return ctl_fail(c, 0, GALE_E_RANGE, "welcome.obstacles: expected <= %u entries, got %d",
                        WIRE_MAX_OBSTACLES, n);
    }
    if (n > 0) {
        w->obstacles = calloc((size_t)n, sizeof *w->obstacles);
        if (!w->obstacles) {
            return ctl_fail(c, 0, GALE_E_NOMEM, "welcome.obstacles: out of memory");
        }
    }
    w->n_obstacles = (uint32_t)n;
    int i = 0;
    for (const cJSON *e = ob->child; e; e = e->next, i++) {
        double v[6];
        int rc = get_row(c, e, "obstacles", i, "[min_x, min_y, min_z, max_x, max_y, max_z]", v);
        if (rc || (rc = obstacle_check(c, i, v))) {
            return rc;
        }
        ctl_obstacle *b = &w->obstacles[i];
        for (int k = 0; k < 3; k++) {
            b->min[k] = (float)v[k];
            b->max[k] = (float)v[k + 3];
        }
    }
    return 0;
}

int ctl_welcome_parse(ctl_rd *c, const cJSON *o, ctl_welcome *w)
{
    static const char *const keys[] = { "type",     "protocol",  "client_id", "role",
                                        "tick_hz",  "snapshot_hz", "server_us", "tick",
                                        "species",  "instances", "obstacles", "scenarios",
                                        NULL };
    const json_rd *r = &c->j;
    int rc = json_check_keys(r, o, "welcome", keys);
    long long proto = 0, id = 0, su = 0, tick = 0;
    double th = 0, sh = 0;
    if (!rc) {
        rc = json_int(r, o, "welcome", "protocol", true, 0, 65535, &proto, NULL);
    }
    if (!rc && proto != WIRE_PROTOCOL_VERSION) {
        rc = ctl_fail(c, WIRE_CLOSE_VERSION, GALE_E_VERSION,
                      "welcome.protocol: expected %d, got %d", WIRE_PROTOCOL_VERSION, (int)proto);
    }
    if (!rc) {
        rc = json_int(r, o, "welcome", "client_id", true, 0, CTL_U32, &id, NULL);
    }
    if (!rc) {
        rc = ctl_get_enum(c, o, "welcome", "role", ctl_role_names, CTL_N_ROLES,
                          "viewer|kiosk|wall-tile|load", &w->role);
    }
    if (!rc) {
        rc = json_number(r, o, "welcome", "tick_hz", true, 1, 1000, &th, NULL);
    }
    if (!rc) {
        rc = json_number(r, o, "welcome", "snapshot_hz", true, 0.1, 1000, &sh, NULL);
    }
    if (!rc) {
        rc = json_int(r, o, "welcome", "server_us", true, 0, CTL_U53, &su, NULL);
    }
    if (!rc) {
        rc = json_int(r, o, "welcome", "tick", true, 0, CTL_U32, &tick, NULL);
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
    const cJSON *sp = NULL;
    if ((rc = get_array(c, o, "species", &sp))) {
        return rc;
    }
    int ns = cJSON_GetArraySize(sp);
    if (ns < 1 || ns > (int)WIRE_MAX_SPECIES) {
        return ctl_fail(c, 0, GALE_E_RANGE, "welcome.species: expected 1..%u entries, got %d",
                        WIRE_MAX_SPECIES, ns);
    }
    w->species = calloc((size_t)ns, sizeof *w->species);
    if (!w->species) {
        return ctl_fail(c, 0, GALE_E_NOMEM, "welcome.species: out of memory");
    }
    w->n_species = (uint32_t)ns;
    int i = 0;
    for (const cJSON *e = sp->child; e; e = e->next, i++) {
        if ((rc = welcome_species_parse(c, e, i, &w->species[i]))) {
            return rc;
        }
    }
    if ((rc = instances_parse(c, o, w)) || (rc = obstacles_parse(c, o, w))) {
        return rc;
    }
    return ctl_scenarios_parse(c, o, w);
}

/* ---- encoding ------------------------------------------------------------------------ */

static int oom(ctl_rd *c)
{
    return ctl_fail(c, 0, GALE_E_NOMEM, "welcome: out of memory");
}

static int welcome_species_encode(ctl_rd *c, const ctl_species *s, int i, cJSON *sa)
{
    const json_rd *r = &c->j;
    char path[40];
    snprintf(path, sizeof path, "welcome.species[%d]", i);
    int rc = json_check_string(r, path, "name", s->name, sizeof s->name);
    if (!rc) {
        rc = json_check_string(r, path, "url", s->url, sizeof s->url);
    }
    if (!rc && (json_check_string(r, path, "hash", s->hash, sizeof s->hash) ||
                strlen(s->hash) != 16 || strspn(s->hash, "0123456789abcdef") != 16)) {
        rc = ctl_fail(c, 0, GALE_E_RANGE, "%s.hash: expected 16 lowercase hex digits, got \"%.16s\"",
                      path, s->hash);
    }
    if (!rc) {
        rc = json_check_int(r, path, "n_modes", 1, WIRE_MAX_MODES, s->n_modes);
    }
    if (rc) {
        return rc;
    }
    cJSON *so = cJSON_CreateObject();
    if (!so || !cJSON_AddItemToArray(sa, so)) {
        cJSON_Delete(so);
        return oom(c);
    }
    return cJSON_AddStringToObject(so, "name", s->name) &&
                   cJSON_AddStringToObject(so, "url", s->url) &&
                   cJSON_AddStringToObject(so, "hash", s->hash) &&
                   ctl_add_num(so, "n_modes", s->n_modes)
               ? 0
               : oom(c);
}

/* A row of 6 numbers as written, checked finite first (a non-finite value would go out
 * as null), then added to array a. */
static int put_row(ctl_rd *c, cJSON *a, const char *what, int i, const double *row)
{
    for (int k = 0; k < 6; k++) {
        if (!isfinite(row[k])) {
            return ctl_fail(c, 0, GALE_E_RANGE, "welcome.%s[%d][%d]: expected a number, got %g",
                            what, i, k, row[k]);
        }
    }
    cJSON *r = cJSON_CreateDoubleArray(row, 6);
    if (!r || !cJSON_AddItemToArray(a, r)) {
        cJSON_Delete(r);
        return oom(c);
    }
    return 0;
}

static int rows_encode(ctl_rd *c, const ctl_welcome *w, cJSON *o)
{
    if (w->n_instances > WIRE_MAX_TREES) {
        return ctl_fail(c, 0, GALE_E_RANGE, "welcome.instances: expected <= %u entries, got %u",
                        WIRE_MAX_TREES, w->n_instances);
    }
    cJSON *ia = cJSON_AddArrayToObject(o, "instances");
    if (!ia) {
        return oom(c);
    }
    for (uint32_t i = 0; i < w->n_instances; i++) {
        const ctl_instance *t = &w->instances[i];
        double row[6] = { t->species,        ctl_jnum(t->pos[0]),  ctl_jnum(t->pos[1]),
                          ctl_jnum(t->pos[2]), ctl_jnum(t->yaw_rad), ctl_jnum(t->scale) };
        int rc = put_row(c, ia, "instances", (int)i, row);
        if (rc || (rc = instance_check(c, (int)i, row, (int)w->n_species))) {
            return rc;
        }
    }
    if (w->n_obstacles > WIRE_MAX_OBSTACLES) {
        return ctl_fail(c, 0, GALE_E_RANGE, "welcome.obstacles: expected <= %u entries, got %u",
                        WIRE_MAX_OBSTACLES, w->n_obstacles);
    }
    /* Omitted when there are none, so a scene without houses keeps its text. */
    if (w->n_obstacles == 0) {
        return 0;
    }
    cJSON *oa = cJSON_AddArrayToObject(o, "obstacles");
    if (!oa) {
        return oom(c);
    }
    for (uint32_t i = 0; i < w->n_obstacles; i++) {
        const ctl_obstacle *b = &w->obstacles[i];
        double row[6] = { ctl_jnum(b->min[0]), ctl_jnum(b->min[1]), ctl_jnum(b->min[2]),
                          ctl_jnum(b->max[0]), ctl_jnum(b->max[1]), ctl_jnum(b->max[2]) };
        int rc = put_row(c, oa, "obstacles", (int)i, row);
        if (rc || (rc = obstacle_check(c, (int)i, row))) {
            return rc;
        }
    }
    return 0;
}

int ctl_welcome_encode(ctl_rd *c, const ctl_welcome *w, cJSON *o)
{
    const json_rd *r = &c->j;
    /* A role outside its enum first: it is the caller's bug, whatever else. */
    const char *rn = ctl_role_name(w->role);
    if (!rn) {
        return ctl_fail(c, 0, GALE_E_ARG, "welcome.role: expected a ctl_role, got %d", w->role);
    }
    if (w->protocol != WIRE_PROTOCOL_VERSION) {
        return ctl_fail(c, WIRE_CLOSE_VERSION, GALE_E_RANGE,
                        "welcome.protocol: expected %d, got %d", WIRE_PROTOCOL_VERSION,
                        w->protocol);
    }
    double th = ctl_jnum(w->tick_hz), sh = ctl_jnum(w->snapshot_hz);
    int rc = json_check_number(r, "welcome", "tick_hz", 1, 1000, th);
    if (!rc) {
        rc = json_check_number(r, "welcome", "snapshot_hz", 0.1, 1000, sh);
    }
    if (!rc) {
        rc = json_check_int(r, "welcome", "server_us", 0, CTL_U53, (double)w->server_us);
    }
    if (!rc && (w->n_species < 1 || w->n_species > WIRE_MAX_SPECIES)) {
        rc = ctl_fail(c, 0, GALE_E_RANGE, "welcome.species: expected 1..%u entries, got %u",
                      WIRE_MAX_SPECIES, w->n_species);
    }
    if (rc) {
        return rc;
    }
    if (!ctl_add_num(o, "protocol", w->protocol) || !ctl_add_num(o, "client_id", w->client_id) ||
        !cJSON_AddStringToObject(o, "role", rn) || !ctl_add_num(o, "tick_hz", th) ||
        !ctl_add_num(o, "snapshot_hz", sh) || !ctl_add_num(o, "server_us", (double)w->server_us) ||
        !ctl_add_num(o, "tick", w->tick)) {
        return oom(c);
    }
    cJSON *sa = cJSON_AddArrayToObject(o, "species");
    if (!sa) {
        return oom(c);
    }
    for (uint32_t i = 0; i < w->n_species; i++) {
        if ((rc = welcome_species_encode(c, &w->species[i], (int)i, sa))) {
            return rc;
        }
    }
    if ((rc = rows_encode(c, w, o))) {
        return rc;
    }
    return ctl_scenarios_encode(c, w, o);
}
