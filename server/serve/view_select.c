/* Interest and LOD selection: see view_select.h. The frustum is taken as a cone (axis dir,
 * half angle fov_deg / 2) so a tree's distance to it is two dot products. */
#include "view_select.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

void view_select(const ctl_view *v, uint32_t n_trees, const float *pos,
                 const uint8_t *full_modes, float margin_m, uint32_t lod_modes,
                 uint8_t *n_modes)
{
    if (lod_modes < 1) {
        lod_modes = 1;
    }
    /* Frustum as a cone: unit axis, cos and sin of the half angle. */
    float ax = 0.0f, ay = 0.0f, az = 0.0f, ch = 1.0f, sh = 0.0f;
    if (v->kind == CTL_VIEW_FRUSTUM) {
        float n = sqrtf(v->dir[0] * v->dir[0] + v->dir[1] * v->dir[1] + v->dir[2] * v->dir[2]);
        if (n > 0.0f) {
            ax = v->dir[0] / n;
            ay = v->dir[1] / n;
            az = v->dir[2] / n;
        }
        float half = v->fov_deg * 0.5f * 0.017453292519943295f;
        ch = cosf(half);
        sh = sinf(half);
    }
    for (uint32_t t = 0; t < n_trees; t++) {
        const float *p = pos + 3 * (size_t)t;
        float dist = 0.0f;
        bool inside = true;
        if (v->kind == CTL_VIEW_CIRCLE) {
            float dx = p[0] - v->x, dy = p[1] - v->y;
            dist = sqrtf(dx * dx + dy * dy);
            inside = dist <= v->radius_m + margin_m;
        } else if (v->kind == CTL_VIEW_FRUSTUM) {
            float dx = p[0] - v->eye[0], dy = p[1] - v->eye[1], dz = p[2] - v->eye[2];
            dist = sqrtf(dx * dx + dy * dy + dz * dz);
            float along = dx * ax + dy * ay + dz * az;
            float across = sqrtf(fmaxf(dist * dist - along * along, 0.0f));
            /* Distance from the point to the cone's surface, positive outside. */
            float out = across * ch - along * sh;
            inside = dist <= margin_m ||
                     (out <= margin_m && along >= -margin_m && along <= v->far_m + margin_m);
        }
        uint32_t full = full_modes[t];
        uint32_t n = 0;
        if (inside) {
            n = (v->lod_m > 0.0f && dist > v->lod_m && lod_modes < full) ? lod_modes : full;
        }
        n_modes[t] = (uint8_t)n;
    }
}
