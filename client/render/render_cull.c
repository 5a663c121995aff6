/* Frustum culling and distance LOD for gale_render (see render_cull.h): modes drop with
 * distance as in Diener 2008 section 5.1, mesh LODs share the distance up to the billboard
 * band. No GL here, so tests run it without a context. */
#include "render_cull.h"

#include <cglm/cglm.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>

void render_cull_planes(const float viewproj[16], float planes[6][4])
{
    vec4 pl[6];
    mat4 vp; /* cglm wants its 16-byte alignment */
    memcpy(vp, viewproj, sizeof vp);
    glm_frustum_planes(vp, pl);
    memcpy(planes, pl, sizeof pl);
}

static float smooth01(float x)
{
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return x * x * (3.0f - 2.0f * x);
}

render_tree_lod render_cull_tree(const float planes[6][4], const float eye[3],
                                 const render_instance *in, const render_cull_species *s,
                                 const render_lod_desc *d)
{
    render_tree_lod out = { 0 };
    const float bill_end = d->billboard_dist_m, bill_start = 0.8f * bill_end;
    const float mode_d = d->mode_dist_m;
    float sc = in->scale > 0.0f ? in->scale : 1.0f;
    float c[3] = { in->pos[0], in->pos[1], in->pos[2] + 0.5f * s->height_m * sc };
    /* bound: the crown can sway by a good part of its height */
    float rad = sc * sqrtf(0.25f * s->height_m * s->height_m + s->crown_r_m * s->crown_r_m) * 1.3f;
    bool vis = true;
    for (int k = 0; k < 6 && vis; k++) {
        vis = planes[k][0] * c[0] + planes[k][1] * c[1] + planes[k][2] * c[2] + planes[k][3] > -rad;
    }
    if (!vis) {
        return out;
    }
    float dx = c[0] - eye[0], dy = c[1] - eye[1], dz = c[2] - eye[2];
    float dist = sqrtf(dx * dx + dy * dy + dz * dz) / sc;
    float tb = smooth01((dist - bill_start) / (bill_end - bill_start));
    out.bill_t = tb;
    if (tb < 1.0f) {
        out.flags |= RENDER_LOD_FULL;
        /* modes: all up to mode_d, then fewer as 1/d, never below 4 (section 5.1) */
        float nm = (float)s->n_modes;
        if (dist > mode_d) {
            nm = fmaxf(fminf(4.0f, nm), nm * mode_d / dist);
        }
        out.n_modes = nm;
        /* mesh LODs share the distance up to the billboard band; the last 30 % of each
           band dithers into the next */
        float lf = fmaxf(dist, 0.0f) / (bill_start / (float)s->n_lods);
        uint32_t k = (uint32_t)fminf(lf, (float)(s->n_lods - 1));
        out.mesh_lod = k;
        out.mesh_fade = k + 1 < s->n_lods ? smooth01((lf - (float)k - 0.7f) / 0.3f) : 0.0f;
    }
    if (tb > 0.0f) {
        out.flags |= RENDER_LOD_BILLBOARD;
    }
    return out;
}

bool render_cull_cone(const float viewproj[16], const float eye[3], float axis[3],
                      float *fov_deg, float *far_m)
{
    mat4 vp, inv;
    memcpy(vp, viewproj, sizeof vp);
    if (!(fabsf(glm_mat4_det(vp)) > 0.0f)) {
        return false;
    }
    glm_mat4_inv(vp, inv);
    /* the frustum's corners, near (z = -1) and far (z = +1) in clip space, in the world */
    float corner[8][3], dir[8][3];
    float sum[3] = { 0.0f, 0.0f, 0.0f };
    for (int k = 0; k < 8; k++) {
        vec4 clip = { (k & 1) ? 1.0f : -1.0f, (k & 2) ? 1.0f : -1.0f, (k & 4) ? 1.0f : -1.0f,
                      1.0f };
        vec4 w;
        glm_mat4_mulv(inv, clip, w);
        if (!(fabsf(w[3]) > 0.0f)) {
            return false;
        }
        float len2 = 0.0f;
        for (int i = 0; i < 3; i++) {
            corner[k][i] = w[i] / w[3];
            dir[k][i] = corner[k][i] - eye[i];
            len2 += dir[k][i] * dir[k][i];
        }
        float len = sqrtf(len2);
        for (int i = 0; i < 3; i++) {
            dir[k][i] = len > 0.0f ? dir[k][i] / len : 0.0f;
            sum[i] += (k & 4) ? dir[k][i] : 0.0f; /* the far corners span the view */
        }
    }
    float n = sqrtf(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (!(n > 0.0f)) {
        return false;
    }
    float min_cos = 1.0f, depth = 0.0f;
    for (int i = 0; i < 3; i++) {
        axis[i] = sum[i] / n;
    }
    for (int k = 0; k < 8; k++) {
        float c = dir[k][0] * axis[0] + dir[k][1] * axis[1] + dir[k][2] * axis[2];
        float d = (corner[k][0] - eye[0]) * axis[0] + (corner[k][1] - eye[1]) * axis[1] +
                  (corner[k][2] - eye[2]) * axis[2];
        min_cos = fminf(min_cos, c);
        depth = fmaxf(depth, d);
    }
    *fov_deg = 2.0f * acosf(fmaxf(-1.0f, fminf(1.0f, min_cos))) * (180.0f / (float)M_PI);
    *far_m = depth;
    return true;
}
