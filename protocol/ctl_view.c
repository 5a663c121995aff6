/* The view object (PROTOCOL.md "Control messages": all, circle or frustum, optional
 * lod_m), which hello carries and the view message replaces, and the view message. */
#include <string.h>

#include "ctl_int.h"

#define COORD_M 1e6 /* |coordinate| limit [m] */

static const char *const k_all[] = { "kind", "lod_m", NULL };
static const char *const k_circle[] = { "kind", "x", "y", "radius_m", "lod_m", NULL };
static const char *const k_frustum[] = { "kind", "eye", "dir", "fov_deg", "far_m", "lod_m",
                                         NULL };

static int nonzero_fail(ctl_rd *c, const char *path)
{
    return ctl_fail(c, 0, GALE_E_RANGE, "%s.dir: expected a nonzero vector, got [0, 0, 0]",
                    path);
}

int ctl_view_parse(ctl_rd *c, const cJSON *j, const char *path, ctl_view *v)
{
    memset(v, 0, sizeof *v);
    if (!cJSON_IsObject(j)) {
        return ctl_fail(c, 0, GALE_E_PARSE, "%s: expected an object, got %s", path, json_kind(j));
    }
    int rc = ctl_get_enum(c, j, path, "kind", ctl_view_names, CTL_N_VIEWS, "all|circle|frustum",
                          &v->kind);
    if (rc) {
        return rc;
    }
    const json_rd *r = &c->j;
    double x = 0, y = 0, rad = 0, fov = 0, far = 0, lod = 0;
    double eye[3] = { 0 }, dir[3] = { 0 };
    const char *const *keys = v->kind == CTL_VIEW_ALL      ? k_all
                              : v->kind == CTL_VIEW_CIRCLE ? k_circle
                                                           : k_frustum;
    rc = json_check_keys(r, j, path, keys);
    if (!rc) {
        rc = json_number(r, j, path, "lod_m", false, 0, COORD_M, &lod, NULL);
    }
    if (!rc && v->kind == CTL_VIEW_CIRCLE) {
        rc = json_number(r, j, path, "x", true, -COORD_M, COORD_M, &x, NULL);
        if (!rc) {
            rc = json_number(r, j, path, "y", true, -COORD_M, COORD_M, &y, NULL);
        }
        if (!rc) {
            rc = json_number(r, j, path, "radius_m", true, 1e-3, COORD_M, &rad, NULL);
        }
    }
    if (!rc && v->kind == CTL_VIEW_FRUSTUM) {
        rc = json_vec(r, j, path, "eye", true, 3, -COORD_M, COORD_M, eye, NULL);
        if (!rc) {
            rc = json_vec(r, j, path, "dir", true, 3, -COORD_M, COORD_M, dir, NULL);
        }
        for (int k = 0; k < 3; k++) {
            v->eye[k] = (float)eye[k];
            v->dir[k] = (float)dir[k];
        }
        if (!rc && v->dir[0] == 0.0f && v->dir[1] == 0.0f && v->dir[2] == 0.0f) {
            rc = nonzero_fail(c, path);
        }
        if (!rc) {
            rc = json_number(r, j, path, "fov_deg", true, 1, 179, &fov, NULL);
        }
        if (!rc) {
            rc = json_number(r, j, path, "far_m", true, 1e-3, COORD_M, &far, NULL);
        }
    }
    v->x = (float)x;
    v->y = (float)y;
    v->radius_m = (float)rad;
    v->fov_deg = (float)fov;
    v->far_m = (float)far;
    v->lod_m = (float)lod;
    return rc;
}

/* Checks a vec3 the way json_vec reads it and adds it as o[key]. */
static int encode_vec3(ctl_rd *c, cJSON *o, const char *path, const char *key, const float *f,
                       double *out)
{
    char p[128];
    json_path(p, sizeof p, path, key);
    for (int k = 0; k < 3; k++) {
        char pk[140];
        json_path_index(pk, sizeof pk, p, k);
        out[k] = ctl_jnum(f[k]);
        int rc = json_check_number(&c->j, pk, NULL, -COORD_M, COORD_M, out[k]);
        if (rc) {
            return rc;
        }
    }
    cJSON *a = cJSON_CreateDoubleArray(out, 3);
    if (!a || !cJSON_AddItemToObject(o, key, a)) {
        cJSON_Delete(a);
        return ctl_fail(c, 0, GALE_E_NOMEM, "%s: out of memory", p);
    }
    return 0;
}

/* Checks v->field (as written: ctl_jnum) against [lo, hi] and adds it. */
static int encode_num(ctl_rd *c, cJSON *o, const char *path, const char *key, float f,
                      double lo, double hi)
{
    double v = ctl_jnum(f);
    int rc = json_check_number(&c->j, path, key, lo, hi, v);
    if (!rc && !ctl_add_num(o, key, v)) {
        rc = ctl_fail(c, 0, GALE_E_NOMEM, "%s.%s: out of memory", path, key);
    }
    return rc;
}

int ctl_view_encode(ctl_rd *c, const ctl_view *v, const char *path, cJSON **out)
{
    *out = NULL;
    if (v->kind < 0 || v->kind >= CTL_N_VIEWS) {
        return ctl_fail(c, 0, GALE_E_ARG, "%s.kind: expected a ctl_view_kind, got %d", path,
                        v->kind);
    }
    cJSON *o = cJSON_CreateObject();
    if (!o || !cJSON_AddStringToObject(o, "kind", ctl_view_names[v->kind])) {
        cJSON_Delete(o);
        return ctl_fail(c, 0, GALE_E_NOMEM, "%s: out of memory", path);
    }
    int rc = 0;
    if (v->kind == CTL_VIEW_CIRCLE) {
        rc = encode_num(c, o, path, "x", v->x, -COORD_M, COORD_M);
        if (!rc) {
            rc = encode_num(c, o, path, "y", v->y, -COORD_M, COORD_M);
        }
        if (!rc) {
            rc = encode_num(c, o, path, "radius_m", v->radius_m, 1e-3, COORD_M);
        }
    } else if (v->kind == CTL_VIEW_FRUSTUM) {
        double eye[3], dir[3];
        rc = encode_vec3(c, o, path, "eye", v->eye, eye);
        if (!rc) {
            rc = encode_vec3(c, o, path, "dir", v->dir, dir);
        }
        if (!rc && (float)dir[0] == 0.0f && (float)dir[1] == 0.0f && (float)dir[2] == 0.0f) {
            rc = nonzero_fail(c, path);
        }
        if (!rc) {
            rc = encode_num(c, o, path, "fov_deg", v->fov_deg, 1, 179);
        }
        if (!rc) {
            rc = encode_num(c, o, path, "far_m", v->far_m, 1e-3, COORD_M);
        }
    }
    /* lod_m = 0 (or not a positive number) is "no LOD": left out. */
    if (!rc && v->lod_m > 0.0f) {
        rc = encode_num(c, o, path, "lod_m", v->lod_m, 0, COORD_M);
    }
    if (rc) {
        cJSON_Delete(o);
        return rc;
    }
    *out = o;
    return 0;
}

int ctl_view_msg_parse(ctl_rd *c, const cJSON *o, ctl_view *v)
{
    static const char *const keys[] = { "type", "view", NULL };
    int rc = json_check_keys(&c->j, o, "view", keys);
    if (rc) {
        return rc;
    }
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(o, "view");
    if (!j) {
        return ctl_fail(c, 0, GALE_E_PARSE, "view.view: missing: expected an object");
    }
    return ctl_view_parse(c, j, "view.view", v);
}

int ctl_view_msg_encode(ctl_rd *c, const ctl_view *v, cJSON *o)
{
    cJSON *j = NULL;
    int rc = ctl_view_encode(c, v, "view.view", &j);
    if (!rc && !cJSON_AddItemToObject(o, "view", j)) {
        cJSON_Delete(j);
        rc = ctl_fail(c, 0, GALE_E_NOMEM, "view: out of memory");
    }
    return rc;
}
