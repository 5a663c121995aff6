/* Wind scenarios: steady/gusty wind and hurricane replays (see scenario.h). The hurricane
 * is the Holland (1980) vortex (holland.h) on an interpolated track, reduced to the
 * surface, made asymmetric by the storm's forward motion and turned inward by an inflow
 * angle, evaluated at the scene's location (PHYSICS.md "Hurricanes"). */
#include "scenario.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gust.h"
#include "holland.h"
#include "hurdat.h"
#include "scenario_int.h"

#define MAX_TRACK  256
#define MAX_BALLS  64
#define KM_PER_DEG 111.195 /* mean Earth radius 6371 km × π/180 */

/* A config error: "<doc>: <path>: <what>". */
#define CFG_ERR(err, code, d, p, ...) scenario_cfg_err(err, code, d, p, __VA_ARGS__)

static int scenario_cfg_err(gale_err *err, int code, const cfg_doc *d, const char *p,
                            const char *fmt, ...) __attribute__((format(printf, 5, 6)));

static int scenario_cfg_err(gale_err *err, int code, const cfg_doc *d, const char *p,
                            const char *fmt, ...)
{
    char what[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return gale_errf(err, code, "%s: %s: %s", d->name, p, what);
}

/* obj[key] of the given type: 1 found, 0 absent (and not required), < 0 error. */
static int child(const cfg_doc *d, const cJSON *obj, const char *path, const char *key, int type,
                 bool required, const cJSON **out, gale_err *err)
{
    gale_err e = { 0 };
    bool found = false;
    *out = cfg_child(d, obj, path, key, type, required, &found, &e);
    if (e.code < 0) {
        if (err) {
            *err = e;
        }
        return e.code;
    }
    return found ? 1 : 0;
}

/* "YYYY-MM-DDTHH:MMZ" → minutes since the epoch; 0 ok. */
static int parse_utc(const char *s, long long *out)
{
    int y, mo, da, h, mi;
    char z = 0, extra = 0;
    if (sscanf(s, "%4d-%2d-%2dT%2d:%2d%c%c", &y, &mo, &da, &h, &mi, &z, &extra) != 6 || z != 'Z' ||
        strlen(s) != 17) {
        return -1;
    }
    if (mo < 1 || mo > 12 || da < 1 || da > 31 || h > 23 || mi > 59 || y < 1800 || y > 2200) {
        return -1;
    }
    *out = hurdat_civil_minutes(y, mo, da, h, mi);
    return 0;
}

static int load_gust(scenario *s, const cfg_doc *d, const cJSON *root, const char *path,
                     gale_err *err)
{
    const cJSON *g;
    char p[256];
    cfg_path(p, sizeof p, path, "gust");
    int rc = child(d, root, path, "gust", cJSON_Object, false, &g, err);
    s->gust_on = true;
    s->gd = (gust_desc){ .seed = s->seed, .z0_m = s->z0_m };
    if (rc <= 0) {
        return rc;
    }
    static const char *const keys[] = { "enabled", "intensity", "length_m",
                                        "ratio_v", "ratio_w",   NULL };
    if ((rc = cfg_check_keys(d, g, p, keys, err)) < 0 ||
        (rc = cfg_bool(d, g, p, "enabled", false, true, &s->gust_on, err)) < 0 ||
        (rc = cfg_number(d, g, p, "intensity", false, 0.0, 0.0, 1.0, &s->gd.intensity, err)) < 0 ||
        (rc = cfg_number(d, g, p, "length_m", false, 50.0, 1.0, 1000.0, &s->gd.length_m, err)) <
            0 ||
        (rc = cfg_number(d, g, p, "ratio_v", false, 0.75, 0.01, 2.0, &s->gd.ratio_v, err)) < 0 ||
        (rc = cfg_number(d, g, p, "ratio_w", false, 0.5, 0.01, 2.0, &s->gd.ratio_w, err)) < 0) {
        return rc;
    }
    return GALE_OK;
}

static int load_balls(scenario *s, const cfg_doc *d, const cJSON *root, const char *path,
                      gale_err *err)
{
    const cJSON *arr;
    char p[256];
    cfg_path(p, sizeof p, path, "balls");
    int rc = child(d, root, path, "balls", cJSON_Array, false, &arr, err);
    if (rc <= 0) {
        return rc;
    }
    int n = cJSON_GetArraySize(arr);
    if (n > MAX_BALLS) {
        return CFG_ERR(err, GALE_E_RANGE, d, p, "expected at most %d balls, got %d", MAX_BALLS, n);
    }
    s->balls = calloc(n > 0 ? (size_t)n : 1, sizeof *s->balls);
    if (!s->balls) {
        return gale_errf(err, GALE_E_NOMEM, "%s: %s: out of memory", d->name, p);
    }
    static const char *const keys[] = { "center", "radius_m", "force", "jitter_m", NULL };
    int i = 0;
    for (const cJSON *b = arr->child; b; b = b->next, i++) {
        char bp[256];
        cfg_path_index(bp, sizeof bp, p, i);
        double c[3], f[3], r, j;
        if ((rc = cfg_check_keys(d, b, bp, keys, err)) < 0 ||
            (rc = cfg_vec(d, b, bp, "center", true, 3, NULL, -1e5, 1e5, c, err)) < 0 ||
            (rc = cfg_number(d, b, bp, "radius_m", true, 0.0, 0.1, 1e4, &r, err)) < 0 ||
            (rc = cfg_vec(d, b, bp, "force", true, 3, NULL, -1000.0, 1000.0, f, err)) < 0 ||
            (rc = cfg_number(d, b, bp, "jitter_m", false, 0.0, 0.0, 1e4, &j, err)) < 0) {
            return rc;
        }
        wind_ball *wb = &s->balls[i];
        for (int k = 0; k < 3; k++) {
            wb->center[k] = (float)c[k];
            wb->force[k] = (float)f[k];
        }
        wb->radius_m = (float)r;
        wb->jitter_m = (float)j;
    }
    s->n_balls = n;
    return GALE_OK;
}

static int load_steady(scenario *s, const cfg_doc *d, const cJSON *root, const char *path,
                       gale_err *err)
{
    const cJSON *o;
    char p[256];
    cfg_path(p, sizeof p, path, "steady");
    int rc = child(d, root, path, "steady", cJSON_Object, true, &o, err);
    if (rc < 0) {
        return rc;
    }
    static const char *const keys[] = { "u10_ms", "dir_from_deg", NULL };
    if ((rc = cfg_check_keys(d, o, p, keys, err)) < 0 ||
        (rc = cfg_number(d, o, p, "u10_ms", true, 0.0, 0.0, 90.0, &s->u10_ms, err)) < 0 ||
        (rc = cfg_number(d, o, p, "dir_from_deg", false, 270.0, 0.0, 360.0, &s->dir_from_deg,
                         err)) < 0) {
        return rc;
    }
    return GALE_OK;
}

static int load_track(scenario *s, const cfg_doc *d, const cJSON *h, const char *hp, gale_err *err)
{
    const cJSON *arr;
    char p[256];
    cfg_path(p, sizeof p, hp, "track");
    int rc = child(d, h, hp, "track", cJSON_Array, true, &arr, err);
    if (rc < 0) {
        return rc;
    }
    int n = cJSON_GetArraySize(arr);
    if (n < 2 || n > MAX_TRACK) {
        return CFG_ERR(err, GALE_E_RANGE, d, p, "expected 2 to %d track points, got %d", MAX_TRACK,
                       n);
    }
    s->track = calloc((size_t)n, sizeof *s->track);
    if (!s->track) {
        return gale_errf(err, GALE_E_NOMEM, "%s: %s: out of memory", d->name, p);
    }
    static const char *const keys[] = { "t_min", "lat_deg", "lon_deg", "x_km", "y_km",
                                        "p_hpa", "rmax_km", "vmax_ms", NULL };
    double coslat = cos(s->site_lat * M_PI / 180.0);
    int i = 0;
    for (const cJSON *o = arr->child; o; o = o->next, i++) {
        char ip[256];
        cfg_path_index(ip, sizeof ip, p, i);
        scenario_track_pt *t = &s->track[i];
        double tmin, p_hpa, rmax_km;
        if ((rc = cfg_check_keys(d, o, ip, keys, err)) < 0 ||
            (rc = cfg_number(d, o, ip, "t_min", true, 0.0, -1e5, 1e5, &tmin, err)) < 0) {
            return rc;
        }
        bool has_geo = cJSON_GetObjectItemCaseSensitive(o, "lat_deg") ||
                       cJSON_GetObjectItemCaseSensitive(o, "lon_deg");
        bool has_xy = cJSON_GetObjectItemCaseSensitive(o, "x_km") ||
                      cJSON_GetObjectItemCaseSensitive(o, "y_km");
        if (has_geo && has_xy) {
            return CFG_ERR(err, GALE_E_PARSE, d, ip,
                           "expected lat_deg/lon_deg or x_km/y_km, got both");
        }
        if (i == 0) {
            s->geo = !has_xy;
        } else if (s->geo != !has_xy) {
            return CFG_ERR(err, GALE_E_PARSE, d, ip, "expected %s like track[0], got %s",
                           s->geo ? "lat_deg/lon_deg" : "x_km/y_km",
                           s->geo ? "x_km/y_km" : "lat_deg/lon_deg");
        }
        if (s->geo) {
            double lat, lon;
            if ((rc = cfg_number(d, o, ip, "lat_deg", true, 0.0, -70.0, 70.0, &lat, err)) < 0 ||
                (rc = cfg_number(d, o, ip, "lon_deg", true, 0.0, -180.0, 180.0, &lon, err)) < 0) {
                return rc;
            }
            double dlon = lon - s->site_lon;
            /* the short way round the date line */
            if (dlon > 180.0) {
                dlon -= 360.0;
            } else if (dlon < -180.0) {
                dlon += 360.0;
            }
            /* local equirectangular projection about the site: x east, y north */
            t->x_m = dlon * coslat * KM_PER_DEG * 1000.0;
            t->y_m = (lat - s->site_lat) * KM_PER_DEG * 1000.0;
        } else {
            double x, y;
            if ((rc = cfg_number(d, o, ip, "x_km", true, 0.0, -5000.0, 5000.0, &x, err)) < 0 ||
                (rc = cfg_number(d, o, ip, "y_km", true, 0.0, -5000.0, 5000.0, &y, err)) < 0) {
                return rc;
            }
            t->x_m = x * 1000.0;
            t->y_m = y * 1000.0;
        }
        if ((rc = cfg_number(d, o, ip, "p_hpa", true, 0.0, 850.0, 1050.0, &p_hpa, err)) < 0 ||
            (rc = cfg_number(d, o, ip, "rmax_km", true, 0.0, 2.0, 200.0, &rmax_km, err)) < 0 ||
            (rc = cfg_number(d, o, ip, "vmax_ms", true, 0.0, 5.0, 100.0, &t->vmax_ms, err)) < 0) {
            return rc;
        }
        if (!(p_hpa < s->pn_pa / 100.0)) {
            char kp[256];
            cfg_path(kp, sizeof kp, ip, "p_hpa");
            return CFG_ERR(err, GALE_E_RANGE, d, kp,
                           "expected a central pressure below ambient_hpa (%g), got %g",
                           s->pn_pa / 100.0, p_hpa);
        }
        t->t_s = tmin * 60.0;
        t->pc_pa = p_hpa * 100.0;
        t->rmax_m = rmax_km * 1000.0;
        if (i > 0 && !(t->t_s > s->track[i - 1].t_s)) {
            char kp[256];
            cfg_path(kp, sizeof kp, ip, "t_min");
            return CFG_ERR(err, GALE_E_RANGE, d, kp,
                           "expected a time after track[%d] (%g min), got %g", i - 1,
                           s->track[i - 1].t_s / 60.0, tmin);
        }
    }
    s->n_track = n;
    /* translation velocity at each point: centred differences (one-sided at the ends),
     * interpolated in time like everything else */
    for (i = 0; i < n; i++) {
        int a = i > 0 ? i - 1 : 0, b = i < n - 1 ? i + 1 : n - 1;
        double dt = s->track[b].t_s - s->track[a].t_s;
        s->track[i].vx = (s->track[b].x_m - s->track[a].x_m) / dt;
        s->track[i].vy = (s->track[b].y_m - s->track[a].y_m) / dt;
    }
    return GALE_OK;
}

static int load_hurricane(scenario *s, const cfg_doc *d, const cJSON *root, const char *path,
                          gale_err *err)
{
    const cJSON *h, *site;
    char p[256], sp[256];
    cfg_path(p, sizeof p, path, "hurricane");
    int rc = child(d, root, path, "hurricane", cJSON_Object, true, &h, err);
    if (rc < 0) {
        return rc;
    }
    static const char *const keys[] = { "source",         "site",        "ref_utc",
                                        "ambient_hpa",    "rho_air",     "inflow_angle_deg",
                                        "surface_factor", "land_factor", "asymmetry",
                                        "time_scale",     "start_min",   "end_min",
                                        "loop",           "track",       NULL };
    if ((rc = cfg_check_keys(d, h, p, keys, err)) < 0) {
        return rc;
    }
    cfg_path(sp, sizeof sp, p, "site");
    if ((rc = child(d, h, p, "site", cJSON_Object, true, &site, err)) < 0) {
        return rc;
    }
    static const char *const site_keys[] = { "lat_deg", "lon_deg", "over_land", "label",
                                             "utc_offset_min", NULL };
    char ref[32];
    double pn_hpa, angle, utc_off;
    if ((rc = cfg_check_keys(d, site, sp, site_keys, err)) < 0 ||
        (rc = cfg_number(d, site, sp, "lat_deg", true, 0.0, -70.0, 70.0, &s->site_lat, err)) < 0 ||
        (rc = cfg_number(d, site, sp, "lon_deg", false, 0.0, -180.0, 180.0, &s->site_lon, err)) <
            0 ||
        (rc = cfg_bool(d, site, sp, "over_land", false, true, &s->over_land, err)) < 0 ||
        (rc = cfg_string(d, site, sp, "label", false, "", s->site_label, sizeof s->site_label,
                         err)) < 0 ||
        /* absent: the nautical zone of the longitude (15° an hour) */
        (rc = cfg_number(d, site, sp, "utc_offset_min", false,
                         60.0 * floor(s->site_lon / 15.0 + 0.5), -840.0, 840.0, &utc_off,
                         err)) < 0 ||
        (rc = cfg_string(d, h, p, "source", false, "", s->source, sizeof s->source, err)) < 0 ||
        (rc = cfg_string(d, h, p, "ref_utc", false, "", ref, sizeof ref, err)) < 0 ||
        (rc = cfg_number(d, h, p, "ambient_hpa", false, 1013.0, 950.0, 1050.0, &pn_hpa, err)) < 0 ||
        (rc = cfg_number(d, h, p, "rho_air", false, HOLLAND_RHO_AIR, 0.9, 1.4, &s->rho, err)) < 0 ||
        (rc = cfg_number(d, h, p, "inflow_angle_deg", false, 20.0, 0.0, 45.0, &angle, err)) < 0 ||
        (rc = cfg_number(d, h, p, "surface_factor", false, 0.9, 0.5, 1.0, &s->surface_factor,
                         err)) < 0 ||
        (rc = cfg_number(d, h, p, "land_factor", false, 0.8, 0.5, 1.0, &s->land_factor, err)) < 0 ||
        (rc = cfg_number(d, h, p, "asymmetry", false, 0.5, 0.0, 1.0, &s->asymmetry, err)) < 0 ||
        (rc = cfg_number(d, h, p, "time_scale", false, 1.0, 1.0, 10000.0, &s->time_scale, err)) <
            0 ||
        (rc = cfg_bool(d, h, p, "loop", false, false, &s->loop, err)) < 0) {
        return rc;
    }
    if (ref[0]) {
        if (parse_utc(ref, &s->ref_min) != 0) {
            char kp[256];
            cfg_path(kp, sizeof kp, p, "ref_utc");
            return CFG_ERR(err, GALE_E_PARSE, d, kp,
                           "expected a UTC time like \"1992-08-24T09:05Z\", got \"%s\"", ref);
        }
        s->has_ref = true;
    }
    s->utc_offset_min = (int)lround(utc_off);
    s->pn_pa = pn_hpa * 100.0;
    s->inflow_rad = angle * M_PI / 180.0;
    s->f = holland_coriolis(s->site_lat);
    if ((rc = load_track(s, d, h, p, err)) < 0) {
        return rc;
    }
    if (s->geo && !cJSON_GetObjectItemCaseSensitive(site, "lon_deg")) {
        return gale_errf(err, GALE_E_PARSE, "%s: %s.lon_deg: required key missing", d->name, sp);
    }
    double t_first = s->track[0].t_s / 60.0, t_last = s->track[s->n_track - 1].t_s / 60.0;
    double smin, emin;
    if ((rc = cfg_number(d, h, p, "start_min", false, t_first, t_first, t_last, &smin, err)) < 0 ||
        (rc = cfg_number(d, h, p, "end_min", false, t_last, t_first, t_last, &emin, err)) < 0) {
        return rc;
    }
    if (!(emin > smin)) {
        char kp[256];
        cfg_path(kp, sizeof kp, p, "end_min");
        return CFG_ERR(err, GALE_E_RANGE, d, kp, "expected a time after start_min (%g), got %g",
                       smin, emin);
    }
    s->start_s = smin * 60.0;
    s->end_s = emin * 60.0;
    return GALE_OK;
}

scenario *scenario_create(const cfg_doc *doc, const cJSON *obj, const char *path, gale_err *err)
{
    gale_err local = { 0 };
    if (!err) {
        err = &local;
    }
    if (!path) {
        path = "";
    }
    if (!obj) {
        obj = doc->root;
    }
    scenario *s = calloc(1, sizeof *s);
    if (!s) {
        gale_errf(err, GALE_E_NOMEM, "%s: out of memory", doc->name);
        return NULL;
    }
    static const char *const keys[] = { "name",  "description", "kind",          "seed",
                                        "z0_m",  "zmin_m",      "dial_rate_ms2", "gust",
                                        "balls", "steady",      "hurricane",     NULL };
    char kind[16];
    long long seed;
    int rc;
    if ((rc = cfg_check_keys(doc, obj, path, keys, err)) < 0 ||
        (rc = cfg_string(doc, obj, path, "name", false, "", s->name, sizeof s->name, err)) < 0 ||
        (rc = cfg_string(doc, obj, path, "description", false, "", s->description,
                         sizeof s->description, err)) < 0 ||
        (rc = cfg_string(doc, obj, path, "kind", false, "steady", kind, sizeof kind, err)) < 0 ||
        (rc = cfg_int(doc, obj, path, "seed", false, 1, 0, 9007199254740991LL, &seed, err)) < 0 ||
        (rc = cfg_number(doc, obj, path, "z0_m", false, 0.3, 0.001, 3.0, &s->z0_m, err)) < 0 ||
        (rc = cfg_number(doc, obj, path, "zmin_m", false, 5.0, 0.5, 50.0, &s->zmin_m, err)) < 0 ||
        (rc = cfg_number(doc, obj, path, "dial_rate_ms2", false, 4.0, 0.1, 100.0, &s->dial_rate_ms2,
                         err)) < 0) {
        goto fail;
    }
    if (!s->name[0]) {
        snprintf(s->name, sizeof s->name, "%.95s", doc->name);
    }
    s->seed = (uint64_t)seed;
    if (strcmp(kind, "steady") == 0) {
        s->kind = SCENARIO_STEADY;
    } else if (strcmp(kind, "hurricane") == 0) {
        s->kind = SCENARIO_HURRICANE;
    } else {
        char kp[256];
        cfg_path(kp, sizeof kp, path, "kind");
        CFG_ERR(err, GALE_E_RANGE, doc, kp, "expected \"steady\" or \"hurricane\", got \"%s\"",
                kind);
        goto fail;
    }
    /* the section of the other kind would be silently ignored: reject it */
    const char *other = s->kind == SCENARIO_STEADY ? "hurricane" : "steady";
    if (cJSON_GetObjectItemCaseSensitive(obj, other)) {
        char kp[256];
        cfg_path(kp, sizeof kp, path, other);
        CFG_ERR(err, GALE_E_PARSE, doc, kp, "not used by kind \"%s\"", kind);
        goto fail;
    }
    if (load_gust(s, doc, obj, path, err) < 0 || load_balls(s, doc, obj, path, err) < 0) {
        goto fail;
    }
    if (s->kind == SCENARIO_STEADY) {
        if (load_steady(s, doc, obj, path, err) < 0) {
            goto fail;
        }
    } else if (load_hurricane(s, doc, obj, path, err) < 0) {
        goto fail;
    }
    s->gd.seed = s->seed;
    s->gd.z0_m = s->z0_m;
    s->gd = gust_desc_resolve(&s->gd);
    s->first_storm_s = s->start_s;
    s->first_scale = s->time_scale;
    scenario_restart(s, 0.0);
    return s;
fail:
    scenario_destroy(s);
    return NULL;
}

scenario *scenario_parse(const char *name, const char *text, size_t len, gale_err *err)
{
    cfg_doc d;
    if (cfg_parse(&d, name, text, len, err) < 0) {
        return NULL;
    }
    scenario *s = scenario_create(&d, NULL, "", err);
    cfg_fini(&d);
    return s;
}

scenario *scenario_load(const char *file, gale_err *err)
{
    cfg_doc d;
    if (cfg_load(&d, file, err) < 0) {
        return NULL;
    }
    scenario *s = scenario_create(&d, NULL, "", err);
    cfg_fini(&d);
    return s;
}

void scenario_destroy(scenario *s)
{
    if (!s) {
        return;
    }
    free(s->balls);
    free(s->track);
    free(s);
}

const char *scenario_name(const scenario *s)
{
    return s->name;
}

int scenario_balls(const scenario *s, const wind_ball **out)
{
    *out = s->balls;
    return s->n_balls;
}

scenario_kind scenario_get_kind(const scenario *s)
{
    return s->kind;
}

double scenario_steady_ms(const scenario *s)
{
    return s->kind == SCENARIO_STEADY ? s->u10_ms : 0.0;
}

double scenario_duration_s(const scenario *s)
{
    if (s->kind != SCENARIO_HURRICANE || s->loop) {
        return 0.0;
    }
    return (s->end_s - s->start_s) / s->time_scale;
}

void scenario_restart(scenario *s, double t_s)
{
    s->t0 = t_s;
    s->base_storm_s = s->first_storm_s;
    s->base_t = 0.0;
    s->paused = false;
    if (s->kind == SCENARIO_HURRICANE) {
        s->time_scale = s->first_scale;
    }
    s->have_last = false;
    s->ramping = false;
    s->last_dir = s->kind == SCENARIO_STEADY ? (270.0 - s->dir_from_deg) * M_PI / 180.0 : 0.0;
    gust_init(&s->gust, &s->gd);
}

/* The storm at storm time ts [s]: linear interpolation between track points, clamped. */
void scenario_storm_at(const scenario *s, double ts, scenario_track_pt *out)
{
    const scenario_track_pt *t = s->track;
    int n = s->n_track;
    if (ts <= t[0].t_s) {
        *out = t[0];
        out->t_s = ts;
        return;
    }
    if (ts >= t[n - 1].t_s) {
        *out = t[n - 1];
        out->t_s = ts;
        return;
    }
    int i = 0;
    while (i < n - 2 && ts > t[i + 1].t_s) {
        i++;
    }
    double a = (ts - t[i].t_s) / (t[i + 1].t_s - t[i].t_s);
#define LERP(f) (t[i].f + a * (t[i + 1].f - t[i].f))
    out->t_s = ts;
    out->x_m = LERP(x_m);
    out->y_m = LERP(y_m);
    out->pc_pa = LERP(pc_pa);
    out->rmax_m = LERP(rmax_m);
    out->vmax_ms = LERP(vmax_ms);
    out->vx = LERP(vx);
    out->vy = LERP(vy);
#undef LERP
}

void scenario_vortex_of(const scenario *s, const scenario_track_pt *c, holland_vortex *v)
{
    /* HURDAT2's Vmax is the 1-min 10 m wind; B is fitted to the gradient-level peak,
     * V_g = Vmax / surface_factor (PHYSICS.md: B ≈ 2.36 for Andrew at landfall) */
    double vg = c->vmax_ms / s->surface_factor;
    v->pc_pa = c->pc_pa;
    v->pn_pa = s->pn_pa;
    v->rmax_m = c->rmax_m;
    v->rho = s->rho;
    v->f = s->f;
    v->b = holland_b(vg, s->pn_pa - c->pc_pa, s->rho);
}

/* The hurricane's surface wind at the scene (x east, y north) [m/s] and the HUD figures. */
static void hurricane_wind(const scenario *s, double storm_s, double wind[2], scenario_state *out)
{
    scenario_track_pt c;
    scenario_storm_at(s, storm_s, &c);
    holland_vortex v;
    scenario_vortex_of(s, &c, &v);
    /* r̂: unit vector from the storm centre to the scene (the scene is at the origin) */
    double rx = -c.x_m, ry = -c.y_m;
    double r = hypot(rx, ry);
    double reduce = s->surface_factor * (s->over_land ? s->land_factor : 1.0);
    double vsym = reduce * holland_gradient_wind(&v, r);
    double vpeak = reduce * holland_gradient_wind(&v, v.rmax_m);
    wind[0] = wind[1] = 0.0;
    if (r > 0.0) {
        rx /= r;
        ry /= r;
        /* cyclonic tangent: counter-clockwise in the northern hemisphere (f > 0) */
        double hs = s->f >= 0.0 ? 1.0 : -1.0;
        double tx = -hs * ry, ty = hs * rx;
        /* turned inward across the isobars by the inflow angle α */
        double ca = cos(s->inflow_rad), sa = sin(s->inflow_rad);
        wind[0] = vsym * (ca * tx - sa * rx);
        wind[1] = vsym * (ca * ty - sa * ry);
    }
    /* forward-motion asymmetry: + asymmetry·V_t on the right of track at Rmax (the storm's
     * motion adds to the cyclonic wind there), scaled with the symmetric profile so that
     * the eye stays calm and the far field is not a uniform drift */
    if (vpeak > 0.0) {
        double k = s->asymmetry * vsym / vpeak;
        wind[0] += k * c.vx;
        wind[1] += k * c.vy;
    }
    out->pressure_hpa = holland_pressure(&v, r) / 100.0;
    out->distance_km = r / 1000.0;
    out->central_hpa = c.pc_pa / 100.0;
    /* the eye seen from the scene (origin): bearing clockwise from north */
    double b = atan2(c.x_m, c.y_m) * 180.0 / M_PI;
    b = b < 0.0 ? b + 360.0 : b;
    out->bearing_deg = b >= 360.0 ? 0.0 : b;
    out->storm_category = (int)saffir_classify(c.vmax_ms);
}

void scenario_eval(scenario *s, double t_s, scenario_state *out)
{
    memset(out, 0, sizeof *out);
    double t = t_s - s->t0;
    double dt = 0.0;
    if (s->have_last) {
        dt = t - s->last_t;
        if (dt < 0.0) {
            /* time went backwards: replay from the seed */
            gust_init(&s->gust, &s->gd);
            s->ramping = false;
            dt = 0.0;
        }
    }
    out->t_s = t;
    out->storm_category = -1;
    out->distance_km = -1.0;
    out->pressure_hpa = s->kind == SCENARIO_HURRICANE ? s->pn_pa / 100.0 : 1013.0;

    /* scripted wind vector at the scene [m/s], x east, y north */
    double w[2];
    if (s->kind == SCENARIO_HURRICANE) {
        double run_s = s->paused || t <= s->base_t ? 0.0 : t - s->base_t;
        double storm_s = s->base_storm_s + run_s * s->time_scale;
        out->paused = s->paused;
        if (storm_s > s->end_s) {
            if (s->loop) {
                storm_s = s->start_s + fmod(storm_s - s->start_s, s->end_s - s->start_s);
            } else {
                storm_s = s->end_s;
                out->finished = true;
            }
        }
        out->storm_min = storm_s / 60.0;
        out->replay_speed = s->time_scale;
        out->replay_pos_s = (storm_s - s->start_s) / s->time_scale;
        hurricane_wind(s, storm_s, w, out);
        if (s->has_ref) {
            out->utc_min = s->ref_min + (long long)floor(storm_s / 60.0);
            out->utc_offset_min = s->utc_offset_min;
            out->has_clock = true;
            int y, mo, d, h, mi;
            hurdat_civil_from_minutes(s->ref_min + (long long)floor(storm_s / 60.0), &y, &mo, &d,
                                      &h, &mi);
            snprintf(out->clock_utc, sizeof out->clock_utc, "%04d-%02d-%02d %02d:%02dZ", y, mo, d,
                     h, mi);
        }
    } else {
        out->storm_min = t / 60.0;
        /* meteorological "from" direction → the vector it blows toward */
        double to = (270.0 - s->dir_from_deg) * M_PI / 180.0;
        w[0] = s->u10_ms * cos(to);
        w[1] = s->u10_ms * sin(to);
    }

    /* kiosk holds replace speed and/or direction */
    double target[2] = { w[0], w[1] };
    if (s->dial_on || s->dir_on) {
        double spd = s->dial_on ? s->dial_ms : hypot(w[0], w[1]);
        double to = s->dir_on ? (270.0 - s->dir_hold_deg) * M_PI / 180.0 : atan2(w[1], w[0]);
        if (!s->dir_on && hypot(w[0], w[1]) == 0.0 && s->have_last) {
            to = atan2(s->last_w[1], s->last_w[0]);
        }
        target[0] = spd * cos(to);
        target[1] = spd * sin(to);
        out->override_active = true;
    }
    /* after a kiosk change, move at most dial_rate·dt toward the target (no jump) */
    double u[2] = { target[0], target[1] };
    if (s->ramping && s->have_last) {
        double dx = target[0] - s->last_w[0], dy = target[1] - s->last_w[1];
        double dist = hypot(dx, dy), step = s->dial_rate_ms2 * dt;
        if (dist > step) {
            u[0] = s->last_w[0] + dx * step / dist;
            u[1] = s->last_w[1] + dy * step / dist;
        } else {
            s->ramping = false;
        }
    } else {
        s->ramping = false;
    }
    s->last_w[0] = u[0];
    s->last_w[1] = u[1];
    s->last_t = t;
    s->have_last = true;

    double speed = hypot(u[0], u[1]);
    /* in a dead calm (the eye) keep the last direction rather than report a jump */
    double to = speed > 1e-6 ? atan2(u[1], u[0]) : s->last_dir;
    s->last_dir = to;
    double g[3] = { 0.0, 0.0, 0.0 };
    if (s->gust_on) {
        gust_step(&s->gust, dt, speed, g);
    }
    double ca = cos(to), sa = sin(to);
    double gx = g[0] * ca - g[1] * sa, gy = g[0] * sa + g[1] * ca, gz = g[2];

    out->inflow.dir_rad = (float)to;
    out->inflow.u10_ms = (float)speed;
    out->inflow.z0_m = (float)s->z0_m;
    out->inflow.zmin_m = (float)s->zmin_m;
    out->inflow.gust[0] = (float)gx;
    out->inflow.gust[1] = (float)gy;
    out->inflow.gust[2] = (float)gz;
    out->sustained_ms = speed;
    out->gust_ms = sqrt((u[0] + gx) * (u[0] + gx) + (u[1] + gy) * (u[1] + gy) + gz * gz);
    double from = fmod(270.0 - to * 180.0 / M_PI, 360.0);
    if (from < 0.0) {
        from += 360.0;
    }
    if (from >= 360.0) {
        from -= 360.0;
    }
    out->dir_from_deg = from;
    out->category = saffir_classify(speed);
    out->category_name = saffir_name(out->category);
    out->beaufort = saffir_beaufort(speed);
    out->turbulence_intensity = s->gust_on ? s->gust.d.intensity : 0.0;
}

/* The replay's storm time [s] at scenario time t, as scenario_eval puts it (wrapped when
 * it loops, held at the end otherwise). */
static double replay_now_s(const scenario *s, double t)
{
    double run_s = s->paused || t <= s->base_t ? 0.0 : t - s->base_t;
    double now_s = s->base_storm_s + run_s * s->time_scale;
    if (now_s > s->end_s) {
        now_s = s->loop ? s->start_s + fmod(now_s - s->start_s, s->end_s - s->start_s) : s->end_s;
    }
    return now_s;
}

int scenario_replay_set(scenario *s, double t_s, bool has_at, double at_min, bool has_speed,
                        double speed, gale_err *err)
{
    if (s->kind != SCENARIO_HURRICANE) {
        return gale_errf(err, GALE_E_STATE, "scenario %s: replay: not a hurricane replay",
                         s->name);
    }
    if (has_speed && !(speed >= 1.0 && speed <= 10000.0)) {
        return gale_errf(err, GALE_E_RANGE,
                         "scenario %s: replay speed: expected [1, 10000], got %g", s->name, speed);
    }
    if (has_at && !isfinite(at_min)) {
        return gale_errf(err, GALE_E_RANGE, "scenario %s: replay at: expected a minute, got %g",
                         s->name, at_min);
    }
    /* where the replay is now (as scenario_eval would put it), then the new base */
    double t = t_s - s->t0;
    double now_s = replay_now_s(s, t);
    if (has_at) {
        now_s = at_min * 60.0;
        now_s = now_s < s->start_s ? s->start_s : now_s > s->end_s ? s->end_s : now_s;
    }
    if (has_speed) {
        s->time_scale = speed;
    }
    s->base_storm_s = now_s;
    s->base_t = t;
    return GALE_OK;
}

int scenario_set_dial(scenario *s, double sustained_ms, gale_err *err)
{
    if (!(sustained_ms >= 0.0 && sustained_ms <= 90.0)) {
        return gale_errf(err, GALE_E_RANGE,
                         "scenario %s: dial: expected a sustained wind in [0, 90] m/s, got %g",
                         s->name, sustained_ms);
    }
    s->dial_on = true;
    s->dial_ms = sustained_ms;
    s->ramping = true;
    return GALE_OK;
}

int scenario_set_category(scenario *s, saffir_class c, gale_err *err)
{
    if (c < 0 || c >= SAFFIR_COUNT) {
        return gale_errf(err, GALE_E_RANGE,
                         "scenario %s: category: expected a class in [0, %d], got %d", s->name,
                         SAFFIR_COUNT - 1, (int)c);
    }
    return scenario_set_dial(s, saffir_representative_ms(c), err);
}

int scenario_set_direction(scenario *s, double from_deg, gale_err *err)
{
    if (!(from_deg >= 0.0 && from_deg <= 360.0)) {
        return gale_errf(err, GALE_E_RANGE,
                         "scenario %s: direction: expected degrees in [0, 360], got %g", s->name,
                         from_deg);
    }
    s->dir_on = true;
    s->dir_hold_deg = from_deg;
    s->ramping = true;
    return GALE_OK;
}

void scenario_clear_override(scenario *s)
{
    if (s->dial_on || s->dir_on) {
        s->ramping = true;
    }
    s->dial_on = false;
    s->dir_on = false;
}

int scenario_replay_pause(scenario *s, double t_s, bool paused, gale_err *err)
{
    if (s->kind != SCENARIO_HURRICANE) {
        return gale_errf(err, GALE_E_STATE, "scenario %s: replay: not a hurricane replay",
                         s->name);
    }
    /* the clock's new base is where it stands now, so neither edge jumps */
    double t = t_s - s->t0;
    s->base_storm_s = replay_now_s(s, t);
    s->base_t = t;
    s->paused = paused;
    return GALE_OK;
}

int scenario_set_start(scenario *s, double t_s, bool has_at, double at_min, bool has_speed,
                       double speed, gale_err *err)
{
    int rc = scenario_replay_set(s, t_s, has_at, at_min, has_speed, speed, err);
    if (rc) {
        return rc;
    }
    if (has_at) {
        double at_s = at_min * 60.0;
        s->first_storm_s = at_s < s->start_s ? s->start_s : at_s > s->end_s ? s->end_s : at_s;
    }
    if (has_speed) {
        s->first_scale = speed;
    }
    scenario_restart(s, t_s);
    return GALE_OK;
}
