/* Interest and LOD selection: see view_select.h. The frustum is taken as a cone (axis dir,
 * half angle fov_deg / 2) so a tree's distance to it is two dot products. view_select and
 * view_select_grid share one per-tree test (tree_modes), so the grid can only differ in
 * which trees it tests, and it skips a cell only when none of its trees can be in view. */
#include "view_select.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* What the per-tree test needs of a view besides the view itself. */
typedef struct view_shape {
    float ax, ay, az; /* frustum: unit axis */
    float ch, sh;     /* frustum: cos and sin of the half angle */
    uint32_t lod_modes;
} view_shape;

static view_shape shape_of(const ctl_view *v, uint32_t lod_modes)
{
    view_shape c = { .ch = 1.0f, .lod_modes = lod_modes < 1 ? 1 : lod_modes };
    if (v->kind == CTL_VIEW_FRUSTUM) {
        float n = sqrtf(v->dir[0] * v->dir[0] + v->dir[1] * v->dir[1] + v->dir[2] * v->dir[2]);
        if (n > 0.0f) {
            c.ax = v->dir[0] / n;
            c.ay = v->dir[1] / n;
            c.az = v->dir[2] / n;
        }
        float half = v->fov_deg * 0.5f * 0.017453292519943295f;
        c.ch = cosf(half);
        c.sh = sinf(half);
    }
    return c;
}

/* The rule of PROTOCOL.md "view" for one tree at base p with full modes. */
static inline uint8_t tree_modes(const ctl_view *v, const view_shape *c, const float *p,
                                 uint32_t full, float margin_m)
{
    float dist = 0.0f;
    bool inside = true;
    if (v->kind == CTL_VIEW_CIRCLE) {
        float dx = p[0] - v->x, dy = p[1] - v->y;
        dist = sqrtf(dx * dx + dy * dy);
        inside = dist <= v->radius_m + margin_m;
    } else if (v->kind == CTL_VIEW_FRUSTUM) {
        float dx = p[0] - v->eye[0], dy = p[1] - v->eye[1], dz = p[2] - v->eye[2];
        dist = sqrtf(dx * dx + dy * dy + dz * dz);
        float along = dx * c->ax + dy * c->ay + dz * c->az;
        float across = sqrtf(fmaxf(dist * dist - along * along, 0.0f));
        /* Distance from the point to the cone's surface, positive outside. */
        float out = across * c->ch - along * c->sh;
        inside = dist <= margin_m ||
                 (out <= margin_m && along >= -margin_m && along <= v->far_m + margin_m);
    }
    if (!inside) {
        return 0;
    }
    return (uint8_t)((v->lod_m > 0.0f && dist > v->lod_m && c->lod_modes < full) ? c->lod_modes
                                                                                : full);
}

void view_select(const ctl_view *v, uint32_t n_trees, const float *pos,
                 const uint8_t *full_modes, float margin_m, uint32_t lod_modes,
                 uint8_t *n_modes)
{
    const view_shape c = shape_of(v, lod_modes);
    for (uint32_t t = 0; t < n_trees; t++) {
        n_modes[t] = tree_modes(v, &c, pos + 3 * (size_t)t, full_modes[t], margin_m);
    }
}

/* --- the grid ------------------------------------------------------------------------- */

int view_grid_build(view_grid *g, uint32_t n_trees, const float *pos, float cell_m,
                    gale_err *err)
{
    memset(g, 0, sizeof *g);
    g->n_trees = n_trees;
    g->pos = pos;
    float lo[2] = { 0.0f, 0.0f }, hi[2] = { 0.0f, 0.0f };
    for (uint32_t t = 0; t < n_trees; t++) {
        const float *p = pos + 3 * (size_t)t;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            return gale_errf(err, GALE_E_RANGE, "view_grid: tree %u: position not finite", t);
        }
        for (int a = 0; a < 2; a++) {
            lo[a] = t == 0 || p[a] < lo[a] ? p[a] : lo[a];
            hi[a] = t == 0 || p[a] > hi[a] ? p[a] : hi[a];
        }
    }
    double cell = cell_m > 0.0f ? (double)cell_m : 32.0;
    double nx, ny;
    for (;;) {
        nx = floor(((double)hi[0] - (double)lo[0]) / cell) + 1.0;
        ny = floor(((double)hi[1] - (double)lo[1]) / cell) + 1.0;
        if (nx * ny <= (double)VIEW_GRID_MAX_CELLS) {
            break;
        }
        cell *= 2.0;
    }
    g->x0_m = lo[0];
    g->y0_m = lo[1];
    g->cell_m = (float)cell;
    g->nx = (uint32_t)nx;
    g->ny = (uint32_t)ny;
    const size_t cells = (size_t)g->nx * g->ny;
    g->start = calloc(cells + 1, sizeof *g->start);
    g->tree = malloc((n_trees ? n_trees : 1) * sizeof *g->tree);
    g->box = malloc(cells * 6 * sizeof *g->box);
    uint32_t *cell_of = malloc((n_trees ? n_trees : 1) * sizeof *cell_of);
    if (!g->start || !g->tree || !g->box || !cell_of) {
        free(cell_of);
        view_grid_fini(g);
        return gale_errf(err, GALE_E_NOMEM, "view_grid: no memory for %zu cells", cells);
    }
    for (size_t c = 0; c < cells; c++) {
        float *b = g->box + 6 * c;
        b[0] = b[1] = b[2] = INFINITY;
        b[3] = b[4] = b[5] = -INFINITY;
    }
    for (uint32_t t = 0; t < n_trees; t++) {
        const float *p = pos + 3 * (size_t)t;
        uint32_t ix = (uint32_t)(((double)p[0] - (double)lo[0]) / cell);
        uint32_t iy = (uint32_t)(((double)p[1] - (double)lo[1]) / cell);
        ix = ix < g->nx ? ix : g->nx - 1;
        iy = iy < g->ny ? iy : g->ny - 1;
        const uint32_t c = iy * g->nx + ix;
        cell_of[t] = c;
        g->start[c + 1]++;
        float *b = g->box + 6 * (size_t)c;
        for (int a = 0; a < 3; a++) {
            b[a] = p[a] < b[a] ? p[a] : b[a];
            b[3 + a] = p[a] > b[3 + a] ? p[a] : b[3 + a];
        }
    }
    for (size_t c = 0; c < cells; c++) {
        g->start[c + 1] += g->start[c];
    }
    /* counting sort, stable: each cell's trees in index order */
    uint32_t *fill = cell_of;
    for (uint32_t t = 0; t < n_trees; t++) {
        const uint32_t c = fill[t];
        g->tree[g->start[c]++] = t;
    }
    for (size_t c = cells; c > 0; c--) {
        g->start[c] = g->start[c - 1];
    }
    g->start[0] = 0;
    free(cell_of);
    return 0;
}

void view_grid_fini(view_grid *g)
{
    free(g->start);
    free(g->tree);
    free(g->box);
    memset(g, 0, sizeof *g);
}

/* Room left for the per-tree test's float arithmetic at distance d_m from the view's
 * origin, with coordinates of magnitude up to mag_m: across = sqrtf(dist² − along²)
 * cancels to about 5e-4 of dist when a tree lies near the axis, and each coordinate
 * difference rounds by an ulp of the larger coordinate (6e-8 of it). Generous by 4. */
static double slack_m(double d_m, double mag_m)
{
    return 2e-3 * d_m + 1e-6 * mag_m + 1e-3;
}

/* Whether no point of box b (min x, y, z, max x, y, z) can be in view v widened by
 * margin_m, as the per-tree test computes it: the box's bounding sphere (centre k,
 * radius r) against the view, each distance being 1-Lipschitz in the point. */
static bool box_out(const ctl_view *v, const view_shape *c, const float *b, float margin_m)
{
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = (double)b[a];
        hi[a] = (double)b[3 + a];
    }
    const double kx = 0.5 * (lo[0] + hi[0]), ky = 0.5 * (lo[1] + hi[1]), kz = 0.5 * (lo[2] + hi[2]);
    const double ex = 0.5 * (hi[0] - lo[0]), ey = 0.5 * (hi[1] - lo[1]), ez = 0.5 * (hi[2] - lo[2]);
    const double m = (double)margin_m;
    if (v->kind == CTL_VIEW_CIRCLE) {
        const double r = sqrt(ex * ex + ey * ey);
        const double dx = kx - (double)v->x, dy = ky - (double)v->y, d = sqrt(dx * dx + dy * dy);
        const double mag = fabs(kx) + fabs(ky) + fabs((double)v->x) + fabs((double)v->y) + r;
        return d - r > (double)v->radius_m + m + slack_m(d + r, mag);
    }
    if (v->kind == CTL_VIEW_FRUSTUM) {
        const double r = sqrt(ex * ex + ey * ey + ez * ez);
        const double dx = kx - (double)v->eye[0], dy = ky - (double)v->eye[1],
                     dz = kz - (double)v->eye[2];
        const double d = sqrt(dx * dx + dy * dy + dz * dz);
        const double along = dx * (double)c->ax + dy * (double)c->ay + dz * (double)c->az;
        const double across = sqrt(fmax(d * d - along * along, 0.0));
        const double out = across * (double)c->ch - along * (double)c->sh;
        const double mag = fabs(kx) + fabs(ky) + fabs(kz) + fabs((double)v->eye[0]) +
                           fabs((double)v->eye[1]) + fabs((double)v->eye[2]) + r;
        const double sl = slack_m(d + r + (double)v->far_m, mag);
        if (d - r <= m + sl) {
            return false; /* a point may lie within the margin of the eye */
        }
        return out - r > m + sl || along + r < -m - sl || along - r > (double)v->far_m + m + sl;
    }
    return false;
}

void view_select_grid(const view_grid *g, const ctl_view *v, const uint8_t *full_modes,
                      float margin_m, uint32_t lod_modes, uint8_t *n_modes)
{
    if (v->kind != CTL_VIEW_CIRCLE && v->kind != CTL_VIEW_FRUSTUM) {
        view_select(v, g->n_trees, g->pos, full_modes, margin_m, lod_modes, n_modes);
        return;
    }
    const view_shape c = shape_of(v, lod_modes);
    memset(n_modes, 0, g->n_trees);
    if (!g->n_trees) {
        return;
    }
    /* The cells the view can reach on the ground: within reach_m of its origin
     * horizontally (a point in view is within it in 3D), one cell more each side for the
     * rounding of cell indices. */
    double ox, oy, reach_m;
    const double m = (double)margin_m;
    if (v->kind == CTL_VIEW_CIRCLE) {
        ox = (double)v->x;
        oy = (double)v->y;
        reach_m = (double)v->radius_m + m;
    } else {
        ox = (double)v->eye[0];
        oy = (double)v->eye[1];
        /* in view: along <= far + m and across <= (m + along sin h) / cos h, or dist <= m */
        const double al = (double)v->far_m + m;
        const double ac = (m + al * (double)c.sh) / (c.ch > 1e-6f ? (double)c.ch : 1e-6);
        reach_m = fmax(sqrt(al * al + ac * ac), m);
    }
    reach_m += slack_m(reach_m, fabs(ox) + fabs(oy) + reach_m);
    if (!isfinite(reach_m) || !isfinite(ox) || !isfinite(oy)) {
        /* not a view ctl accepts: the rule tree by tree says what it means */
        view_select(v, g->n_trees, g->pos, full_modes, margin_m, lod_modes, n_modes);
        return;
    }
    const double cell = (double)g->cell_m, gx0 = (double)g->x0_m, gy0 = (double)g->y0_m;
    double fx0 = floor((ox - reach_m - gx0) / cell) - 1.0;
    double fx1 = floor((ox + reach_m - gx0) / cell) + 1.0;
    double fy0 = floor((oy - reach_m - gy0) / cell) - 1.0;
    double fy1 = floor((oy + reach_m - gy0) / cell) + 1.0;
    if (fx1 < 0.0 || fy1 < 0.0 || fx0 >= (double)g->nx || fy0 >= (double)g->ny) {
        return;
    }
    const uint32_t ix0 = fx0 < 0.0 ? 0 : (uint32_t)fx0;
    const uint32_t iy0 = fy0 < 0.0 ? 0 : (uint32_t)fy0;
    const uint32_t ix1 = fx1 >= (double)g->nx ? g->nx - 1 : (uint32_t)fx1;
    const uint32_t iy1 = fy1 >= (double)g->ny ? g->ny - 1 : (uint32_t)fy1;
    for (uint32_t iy = iy0; iy <= iy1; iy++) {
        for (uint32_t ix = ix0; ix <= ix1; ix++) {
            const uint32_t k = iy * g->nx + ix;
            if (g->start[k] == g->start[k + 1] || box_out(v, &c, g->box + 6 * (size_t)k, margin_m)) {
                continue;
            }
            for (uint32_t i = g->start[k]; i < g->start[k + 1]; i++) {
                const uint32_t t = g->tree[i];
                n_modes[t] = tree_modes(v, &c, g->pos + 3 * (size_t)t, full_modes[t], margin_m);
            }
        }
    }
}
