/* Wall files (configs/walls/README.md) and each tile's off-axis frustum: the generalized
 * perspective projection of Kooima (2008), whose equation numbers the comments cite. */
#include "wall.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"

#define COORD_M 1e4 /* |coordinate| limit of a wall [m] */

/* ---- vectors ------------------------------------------------------------------------- */

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    float c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0] };
    memcpy(out, c, sizeof c);
}

static float norm3(float v[3])
{
    float n = sqrtf(dot3(v, v));
    if (n > 0.0f) {
        for (int k = 0; k < 3; k++) {
            v[k] /= n;
        }
    }
    return n;
}

/* ---- file ---------------------------------------------------------------------------- */

static int read_vec(const json_rd *r, const cJSON *o, const char *path, const char *key,
                    bool required, int n, double lo, double hi, float *out)
{
    double v[4] = { 0 };
    bool has = false;
    int rc = json_vec(r, o, path, key, required, n, lo, hi, v, &has);
    if (!rc && has) {
        for (int k = 0; k < n; k++) {
            out[k] = (float)v[k];
        }
    }
    return rc;
}

static int parse_tile(const json_rd *r, const cJSON *o, const char *path, wall_tile *t)
{
    static const char *const keys[] = { "name", "px", "size_m", "bezel_m", "centre_m",
                                        "normal", "up", NULL };
    int rc = json_check_keys(r, o, path, keys);
    if (!rc) {
        rc = json_string(r, o, path, "name", true, NULL, t->name, sizeof t->name, NULL);
    }
    float px[2] = { 0 };
    if (!rc) {
        rc = read_vec(r, o, path, "px", true, 2, 16, 16384, px);
    }
    t->px[0] = (int)px[0];
    t->px[1] = (int)px[1];
    if (!rc && (px[0] != (float)t->px[0] || px[1] != (float)t->px[1])) {
        rc = json_fail(r, GALE_E_RANGE, "%s.px: expected whole pixels, got [%g, %g]", path,
                       (double)px[0], (double)px[1]);
    }
    if (!rc) {
        rc = read_vec(r, o, path, "size_m", true, 2, 1e-3, COORD_M, t->size_m);
    }
    if (!rc) {
        rc = read_vec(r, o, path, "bezel_m", false, 4, 0, 1, t->bezel_m);
    }
    if (!rc) {
        rc = read_vec(r, o, path, "centre_m", true, 3, -COORD_M, COORD_M, t->centre_m);
    }
    if (!rc) {
        rc = read_vec(r, o, path, "normal", true, 3, -1e3, 1e3, t->normal);
    }
    if (!rc) {
        rc = read_vec(r, o, path, "up", true, 3, -1e3, 1e3, t->up);
    }
    if (rc) {
        return rc;
    }
    if (norm3(t->normal) < 1e-6f) {
        return json_fail(r, GALE_E_RANGE, "%s.normal: expected a nonzero vector, got [0, 0, 0]",
                         path);
    }
    if (norm3(t->up) < 1e-6f) {
        return json_fail(r, GALE_E_RANGE, "%s.up: expected a nonzero vector, got [0, 0, 0]",
                         path);
    }
    float c = dot3(t->normal, t->up);
    if (fabsf(c) > 1e-3f) {
        return json_fail(r, GALE_E_RANGE,
                         "%s.up: expected orthogonal to normal (|cos| <= 0.001), got cos %.4f",
                         path, (double)c);
    }
    return 0;
}

static int parse_stop(const json_rd *r, const cJSON *o, const char *path, wall_stop *s)
{
    static const char *const keys[] = { "t_s", "target_m", "distance_m", "yaw_deg",
                                        "pitch_deg", NULL };
    double t = 0, d = 0, yaw = 0, pitch = 0;
    int rc = json_check_keys(r, o, path, keys);
    if (!rc) {
        rc = json_number(r, o, path, "t_s", true, 0, 86400, &t, NULL);
    }
    if (!rc) {
        rc = read_vec(r, o, path, "target_m", true, 3, -1e6, 1e6, s->target_m);
    }
    if (!rc) {
        rc = json_number(r, o, path, "distance_m", true, 0.5, 5000, &d, NULL);
    }
    if (!rc) {
        rc = json_number(r, o, path, "yaw_deg", true, -720, 720, &yaw, NULL);
    }
    if (!rc) {
        rc = json_number(r, o, path, "pitch_deg", true, -88, 88, &pitch, NULL);
    }
    s->t_s = (float)t;
    s->distance_m = (float)d;
    s->yaw_deg = (float)yaw;
    s->pitch_deg = (float)pitch;
    return rc;
}

static int parse_root(const json_rd *r, const cJSON *root, wall *w)
{
    static const char *const keys[] = { "name", "eye_m", "hud_tile", "hud_text_mm", "tour",
                                        "tiles", NULL };
    int rc = json_check_keys(r, root, "wall", keys);
    if (!rc) {
        rc = json_string(r, root, "wall", "name", true, NULL, w->name, sizeof w->name, NULL);
    }
    if (!rc) {
        rc = read_vec(r, root, "wall", "eye_m", true, 3, -COORD_M, COORD_M, w->eye_m);
    }
    const cJSON *tiles = NULL, *tour = NULL;
    if (!rc) {
        rc = json_child(r, root, "wall", "tiles", cJSON_Array, true, &tiles);
    }
    int n = rc ? 0 : cJSON_GetArraySize(tiles);
    if (!rc && (n < 1 || n > WALL_MAX_TILES)) {
        rc = json_fail(r, GALE_E_RANGE, "wall.tiles: expected 1..%d tiles, got %d",
                       WALL_MAX_TILES, n);
    }
    for (int i = 0; !rc && i < n; i++) {
        char p[48];
        json_path_index(p, sizeof p, "wall.tiles", i);
        wall_tile *t = &w->tiles[i];
        rc = parse_tile(r, cJSON_GetArrayItem(tiles, i), p, t);
        for (int k = 0; !rc && k < i; k++) {
            if (strcmp(w->tiles[k].name, t->name) == 0) {
                rc = json_fail(r, GALE_E_RANGE, "%s.name: \"%s\" repeats wall.tiles[%d]", p,
                               t->name, k);
            }
        }
        float to_eye[3];
        for (int k = 0; k < 3; k++) {
            to_eye[k] = w->eye_m[k] - t->centre_m[k];
        }
        if (!rc && dot3(to_eye, t->normal) <= 1e-3f) {
            rc = json_fail(r, GALE_E_RANGE,
                           "%s.normal: expected the eye in front of the tile (normal towards "
                           "wall.eye_m), got the eye %.3f m behind it",
                           p, -(double)dot3(to_eye, t->normal));
        }
        w->n_tiles = i + 1;
    }
    char hud[WALL_MAX_NAME] = "";
    double text_mm = 12.0;
    if (!rc) {
        rc = json_string(r, root, "wall", "hud_tile", false, w->tiles[0].name, hud, sizeof hud,
                         NULL);
    }
    if (!rc) {
        rc = json_number(r, root, "wall", "hud_text_mm", false, 1, 1000, &text_mm, NULL);
    }
    w->hud_text_mm = (float)text_mm;
    w->hud_tile = -1;
    if (!rc && strcmp(hud, "off") != 0) {
        w->hud_tile = wall_find_tile(w, hud);
        if (w->hud_tile < 0) {
            rc = json_fail(r, GALE_E_RANGE, "wall.hud_tile: expected a tile name or \"off\", "
                                            "got \"%s\"", hud);
        }
    }
    if (!rc) {
        rc = json_child(r, root, "wall", "tour", cJSON_Array, false, &tour);
    }
    int ns = rc || !tour ? 0 : cJSON_GetArraySize(tour);
    if (!rc && ns > WALL_MAX_TOUR) {
        rc = json_fail(r, GALE_E_RANGE, "wall.tour: expected <= %d stops, got %d", WALL_MAX_TOUR,
                       ns);
    }
    for (int i = 0; !rc && i < ns; i++) {
        char p[48];
        json_path_index(p, sizeof p, "wall.tour", i);
        rc = parse_stop(r, cJSON_GetArrayItem(tour, i), p, &w->stops[i]);
        if (!rc && i > 0 && !(w->stops[i].t_s > w->stops[i - 1].t_s)) {
            rc = json_fail(r, GALE_E_RANGE, "%s.t_s: expected > %g (the stop before), got %g",
                           p, (double)w->stops[i - 1].t_s, (double)w->stops[i].t_s);
        }
        w->n_stops = i + 1;
    }
    if (!rc && ns == 1) {
        rc = json_fail(r, GALE_E_RANGE, "wall.tour: expected 0 or >= 2 stops, got 1");
    }
    return rc;
}

int wall_parse(wall *w, const char *name, const char *text, size_t len, gale_err *err)
{
    memset(w, 0, sizeof *w);
    json_rd r = { name, JSON_VOICE_FILE, err };
    size_t at = 0;
    cJSON *root = json_parse(text, len, &at);
    if (root) {
        at = json_skip_space(text, len, at);
    }
    if (!root || at < len) {
        int line, col;
        json_line_col(text, at, &line, &col);
        cJSON_Delete(root);
        return gale_errf(err, GALE_E_PARSE, "%s:%d:%d: %s", name, line, col,
                         root ? "trailing characters after the JSON value" : "invalid JSON");
    }
    int rc = cJSON_IsObject(root)
                 ? parse_root(&r, root, w)
                 : json_fail(&r, GALE_E_PARSE, "wall: expected an object, got %s",
                             json_kind(root));
    cJSON_Delete(root);
    if (rc) {
        memset(w, 0, sizeof *w);
    }
    return rc;
}

int wall_load(wall *w, const char *path, gale_err *err)
{
    memset(w, 0, sizeof *w);
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len + 4096 > cap) {
            cap = cap ? 2 * cap : 65536;
            char *nb = cap <= (1u << 24) ? realloc(buf, cap) : NULL;
            if (!nb) {
                free(buf);
                fclose(f);
                return gale_errf(err, GALE_E_RANGE, "%s: expected a wall file under 16 MiB",
                                 path);
            }
            buf = nb;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            break;
        }
    }
    bool bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: read error", path);
    }
    int rc = wall_parse(w, path, buf, len, err);
    free(buf);
    return rc;
}

int wall_find_tile(const wall *w, const char *name)
{
    for (int i = 0; i < w->n_tiles; i++) {
        if (strcmp(w->tiles[i].name, name) == 0) {
            return i;
        }
    }
    return -1;
}

float wall_hud_px(const wall *w, int tile, int fb_h)
{
    if (tile < 0 || tile >= w->n_tiles || tile != w->hud_tile) {
        return 0.0f;
    }
    float px = w->hud_text_mm * 1e-3f * (float)fb_h / w->tiles[tile].size_m[1];
    return px < 8.0f ? 8.0f : px > 256.0f ? 256.0f : px;
}

/* ---- projection ---------------------------------------------------------------------- */

void wall_tour_at(const wall *w, double t_s, wall_stop *out)
{
    const wall_stop *s = w->stops;
    const int n = w->n_stops;
    double t = fmod(t_s, (double)s[n - 1].t_s);
    int i = 0;
    while (i + 2 < n && t >= (double)s[i + 1].t_s) {
        i++;
    }
    const float u = (float)((t - (double)s[i].t_s) / (double)(s[i + 1].t_s - s[i].t_s));
    out->t_s = (float)t;
    for (int k = 0; k < 3; k++) {
        out->target_m[k] = s[i].target_m[k] + u * (s[i + 1].target_m[k] - s[i].target_m[k]);
    }
    out->distance_m = s[i].distance_m + u * (s[i + 1].distance_m - s[i].distance_m);
    out->yaw_deg = s[i].yaw_deg + u * (s[i + 1].yaw_deg - s[i].yaw_deg);
    out->pitch_deg = s[i].pitch_deg + u * (s[i + 1].pitch_deg - s[i].pitch_deg);
}

void wall_tile_corners(const wall_tile *t, float pa[3], float pb[3], float pc[3])
{
    float right[3];
    cross3(t->up, t->normal, right); /* x = y × z for a right-handed tile frame */
    const float hw = 0.5f * t->size_m[0], hh = 0.5f * t->size_m[1];
    for (int k = 0; k < 3; k++) {
        pa[k] = t->centre_m[k] - hw * right[k] - hh * t->up[k];
        pb[k] = t->centre_m[k] + hw * right[k] - hh * t->up[k];
        pc[k] = t->centre_m[k] - hw * right[k] + hh * t->up[k];
    }
}

void wall_mat_mul(const float a[16], const float b[16], float out[16])
{
    float m[16];
    for (int c = 0; c < 4; c++) {
        for (int r = 0; r < 4; r++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++) {
                s += a[k * 4 + r] * b[c * 4 + k];
            }
            m[c * 4 + r] = s;
        }
    }
    memcpy(out, m, sizeof m);
}

void wall_offaxis(const float pa[3], const float pb[3], const float pc[3], const float pe[3],
                  float z_near, float z_far, float rot[16], float proj[16])
{
    float vr[3], vu[3], vn[3], va[3], vb[3], vc[3];
    for (int k = 0; k < 3; k++) {
        vr[k] = pb[k] - pa[k];
        vu[k] = pc[k] - pa[k];
        va[k] = pa[k] - pe[k]; /* eq. 5 */
        vb[k] = pb[k] - pe[k];
        vc[k] = pc[k] - pe[k];
    }
    norm3(vr); /* eqs. 1-3: the screen's orthonormal basis */
    norm3(vu);
    cross3(vr, vu, vn);
    norm3(vn);
    const float d = -dot3(vn, va);       /* eq. 6: eye to screen plane */
    const float s = z_near / d;
    const float l = dot3(vr, va) * s;    /* eqs. 7-10: extents at the near plane */
    const float r = dot3(vr, vb) * s;
    const float b = dot3(vu, va) * s;
    const float t = dot3(vu, vc) * s;
    memset(proj, 0, 16 * sizeof(float));
    proj[0] = 2 * z_near / (r - l);
    proj[5] = 2 * z_near / (t - b);
    proj[8] = (r + l) / (r - l);
    proj[9] = (t + b) / (t - b);
    proj[10] = -(z_far + z_near) / (z_far - z_near);
    proj[11] = -1.0f;
    proj[14] = -2 * z_far * z_near / (z_far - z_near);
    /* M^T (rows vr, vu, vn) then the translation by -pe (section "Projection" of the
     * paper: P' = P M^T T) */
    memset(rot, 0, 16 * sizeof(float));
    for (int k = 0; k < 3; k++) {
        rot[k * 4 + 0] = vr[k];
        rot[k * 4 + 1] = vu[k];
        rot[k * 4 + 2] = vn[k];
    }
    rot[12] = -dot3(vr, pe);
    rot[13] = -dot3(vu, pe);
    rot[14] = -dot3(vn, pe);
    rot[15] = 1.0f;
}

void wall_tile_matrices(const wall *w, int tile, const float cam_view[16], float z_near,
                        float z_far, float view[16], float proj[16])
{
    float pa[3], pb[3], pc[3], rot[16];
    wall_tile_corners(&w->tiles[tile], pa, pb, pc);
    wall_offaxis(pa, pb, pc, w->eye_m, z_near, z_far, rot, proj);
    /* camera frame → wall frame: the camera sits at the eye point */
    float to_wall[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0,
                          w->eye_m[0], w->eye_m[1], w->eye_m[2], 1 };
    float m[16];
    wall_mat_mul(to_wall, cam_view, m);
    wall_mat_mul(rot, m, view);
}
