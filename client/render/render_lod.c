/* Distance LOD for gale_render (see render_cull.h, the numbers in lod_policy.h): modes
 * drop with distance as in Diener 2008 section 5.1, the bark's mesh LODs step with
 * distance within FULL, the crown thins past FULL and turns into an impostor past THIN,
 * each change a dithered cross-fade over the last LOD_FADE_SHARE of the level's outer
 * distance. The frame's budget scales FULL's and THIN's distances. No GL here. */
#include <math.h>
#include <stdbool.h>

#include "render_cull.h"

static float smooth01(float x)
{
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return x * x * (3.0f - 2.0f * x);
}

/* 0 inside the fade band of outer distance outer_m, 1 past it */
static float fade_past(float dist_m, float outer_m)
{
    return smooth01((dist_m - (1.0f - LOD_FADE_SHARE) * outer_m) / (LOD_FADE_SHARE * outer_m));
}

void render_lod_pick_into(float dist_m, const render_cull_species *s, const render_lod_desc *d,
                          bool stays_posed, render_tree_lod *outp)
{
    render_tree_lod out = { 0 };
    if (!(dist_m < lod_outer_m[LOD_IMPOSTOR])) {
        *outp = out;
        return;
    }
    const float sc = d->scale > 0.0f ? d->scale : 1.0f;
    const float full_m = lod_outer_m[LOD_FULL] * sc, thin_m = lod_outer_m[LOD_THIN] * sc;
    if (dist_m >= thin_m) {
        /* past THIN's fade, where most of a landscape is: what the rest works out (both fades
           whole), without it */
        if (!stays_posed) {
            out.level = LOD_IMPOSTOR;
            out.thin_t = out.bill_t = 1.0f;
            out.flags = RENDER_LOD_BILLBOARD;
        }
        *outp = out;
        return;
    }
    out.thin_t = fade_past(dist_m, full_m);
    out.bill_t = fade_past(dist_m, thin_m);
    if (stays_posed && out.bill_t >= 1.0f) {
        *outp = (render_tree_lod){ 0 }; /* a debris piece past THIN: not drawn */
        return;
    }
    out.level = out.bill_t > 0.0f && !stays_posed ? LOD_IMPOSTOR
                : out.thin_t > 0.0f                ? LOD_THIN
                                                   : LOD_FULL;
    if (out.bill_t < 1.0f) {
        out.flags |= RENDER_LOD_FULL;
        /* modes: all up to mode_dist_m, then fewer as 1/d, never below 4 (section 5.1),
           never more than the coarsest level drawn poses */
        float nm = (float)s->n_modes;
        if (dist_m > d->mode_dist_m) {
            nm = fmaxf(fminf(4.0f, nm), nm * d->mode_dist_m / dist_m);
        }
        int lv = out.thin_t > 0.0f ? LOD_THIN : LOD_FULL;
        out.n_modes = fminf(nm, (float)lod_modes_max[lv]);
        if (out.thin_t < 1.0f) {
            /* a mesh LOD per LOD_MESH_STEP_M; the last 30 % of each step dithers into the
               next */
            float lf = dist_m / (LOD_MESH_STEP_M * sc);
            uint32_t k = (uint32_t)fminf(lf, (float)(s->n_lods - 1));
            out.mesh_lod = k;
            out.mesh_fade =
                k + 1 < s->n_lods ? smooth01((lf - (float)k - 0.7f) / 0.3f) : 0.0f;
        } else {
            out.mesh_lod = s->n_lods - 1;
        }
    }
    if (out.bill_t > 0.0f && !stays_posed) {
        out.flags |= RENDER_LOD_BILLBOARD;
    }
    *outp = out;
}

render_tree_lod render_lod_pick(float dist_m, const render_cull_species *s,
                                const render_lod_desc *d, bool stays_posed)
{
    render_tree_lod out;
    render_lod_pick_into(dist_m, s, d, stays_posed, &out);
    return out;
}

uint32_t render_leaves_at(uint32_t n_leaves, float share)
{
    if (n_leaves == 0 || !(share > 0.0f)) {
        return 0;
    }
    uint32_t k = (uint32_t)lroundf((float)n_leaves * share);
    return k < 1 ? 1 : k > n_leaves ? n_leaves : k;
}

float render_bill_fall_code(float fall_rad, float fall_az_rad)
{
    if (!(fall_rad > 0.0f)) {
        return 0.0f;
    }
    long k = (long)floorf(fall_az_rad * (256.0f / 6.2831853f) + 0.5f) % 256;
    k = k < 0 ? k + 256 : k;
    return 1.0f + (float)k + fminf(fall_rad, 1.5707963f) / 3.1415927f;
}

uint32_t render_lod_bin(float dist_m)
{
    /* bins even in √d: fine near the eye, where a tree costs the most */
    float u = dist_m / lod_outer_m[LOD_IMPOSTOR];
    float b = u >= 0.0f ? sqrtf(u) * (float)RENDER_LOD_BINS : -1.0f;
    return b >= 0.0f && b < (float)RENDER_LOD_BINS ? (uint32_t)b : RENDER_LOD_BINS;
}

/* The near edge of bin b [m]. */
static float bin_near_m(uint32_t b)
{
    float u = (float)b / (float)RENDER_LOD_BINS;
    return u * u * lod_outer_m[LOD_IMPOSTOR];
}

float render_lod_bin_near_m(uint32_t b)
{
    return bin_near_m(b);
}

/* The worst case of scale sc: each bin's trees at its near edge, in both levels inside a
 * fade band (render_lod_pick's bands). */
static void worst_case(const uint32_t *hist, const uint32_t *felled_hist,
                       const render_lod_cost *cost, uint32_t n_species, float sc, double *tris,
                       double *nodes)
{
    const float full_m = lod_outer_m[LOD_FULL] * sc, thin_m = lod_outer_m[LOD_THIN] * sc;
    *tris = 0.0;
    *nodes = 0.0;
    for (uint32_t b = 0; felled_hist && b < RENDER_LOD_BINS && bin_near_m(b) < thin_m; b++) {
        *tris += (double)felled_hist[b] * (double)RENDER_FELLED_TRIS_MAX;
    }
    for (uint32_t s = 0; s < n_species; s++) {
        const render_lod_cost *c = &cost[s];
        for (uint32_t b = 0; b < RENDER_LOD_BINS; b++) {
            const uint32_t k = hist[s * RENDER_LOD_BINS + b];
            if (k == 0) {
                continue;
            }
            const float d = bin_near_m(b);
            double t = 0.0;
            bool posed = false;
            if (d < full_m) {
                /* the mesh LOD at d (render_lod_pick), and the next one inside its fade */
                float lf = d / (LOD_MESH_STEP_M * sc);
                uint32_t m = (uint32_t)fminf(lf, (float)(c->n_lods - 1));
                t += (double)c->full_leaves + (double)c->mesh[m];
                if (m + 1 < c->n_lods && lf - (float)m > 0.7f) {
                    t += (double)c->mesh[m + 1];
                }
                posed = true;
            }
            if (d >= (1.0f - LOD_FADE_SHARE) * full_m && d < thin_m) {
                t += (double)c->thin;
                posed = true;
            }
            if (d >= (1.0f - LOD_FADE_SHARE) * thin_m) {
                t += (double)c->impostor;
            }
            *tris += (double)k * t;
            *nodes += posed ? (double)k * (double)c->nodes : 0.0;
        }
    }
}

float render_lod_budget(const uint32_t *hist, const uint32_t *felled_hist,
                        const render_lod_cost *cost, uint32_t n_species, float max_scale,
                        double budget_triangles, double budget_nodes)
{
    double tris, nodes;
    float sc = max_scale;
    worst_case(hist, felled_hist, cost, n_species, sc, &tris, &nodes);
    if (tris <= budget_triangles && nodes <= budget_nodes) {
        return sc;
    }
    /* the cost grows with the scale: bisect between a scale that fits (none posed at
       all at scale 0: impostors alone, which the budget must take) and one that does not */
    float lo = 0.0f, hi = sc;
    for (int it = 0; it < 14; it++) {
        float mid = 0.5f * (lo + hi);
        worst_case(hist, felled_hist, cost, n_species, mid, &tris, &nodes);
        if (tris <= budget_triangles && nodes <= budget_nodes) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo > 0.0f ? lo : 1e-3f;
}
