/* House mesh generation for gale_render (see render_house.h): one obstacle box becomes
 * walls, gables and a pitched roof. No GL here, so tests build meshes without a context. */
#include "render_house.h"

#include <math.h>
#include <string.h>

typedef struct house_box {
    int ia, ib; /* ridge axis, across axis (0 = x, 1 = y) */
    float lo[3], hi[3];
    float ca, cb; /* centre along a and b */
    float zw;     /* eave height [m] */
    float *out;
} house_box;

static void house_vert(house_box *h, float a, float b, float z, float nx_a, float nx_b, float nz,
                       float u, float v, float half_w, float mat)
{
    float *o = h->out;
    o[h->ia] = a;
    o[h->ib] = b;
    o[2] = z;
    o[3 + h->ia] = nx_a;
    o[3 + h->ib] = nx_b;
    o[5] = nz;
    o[6] = u;
    o[7] = v;
    o[8] = h->zw - h->lo[2];
    o[9] = half_w;
    o[10] = mat;
    h->out += RENDER_HOUSE_FLOATS;
}

/* One box as a house: four walls up to the eaves at zw, the two end walls closed by gable
 * triangles, and two roof planes meeting in a ridge along the longer side at the box top.
 * Writes RENDER_HOUSE_VERTS vertices (triangles). The roof rises 40 % of the height, at most a
 * 40 degree pitch (tan 40° ≈ 0.84 over the half width). */
float *render_house_mesh(const float min_max[6], float *out)
{
    house_box h = { .out = out };
    memcpy(h.lo, min_max, sizeof h.lo);
    memcpy(h.hi, min_max + 3, sizeof h.hi);
    h.ia = h.hi[0] - h.lo[0] >= h.hi[1] - h.lo[1] ? 0 : 1;
    h.ib = 1 - h.ia;
    float a0 = h.lo[h.ia], a1 = h.hi[h.ia], b0 = h.lo[h.ib], b1 = h.hi[h.ib];
    float z0 = h.lo[2], z1 = h.hi[2];
    h.ca = 0.5f * (a0 + a1);
    h.cb = 0.5f * (b0 + b1);
    float half_a = 0.5f * (a1 - a0), half_b = 0.5f * (b1 - b0);
    float rh = fminf(0.4f * (z1 - z0), 0.84f * half_b);
    h.zw = z1 - rh;
    /* long walls (normal -b, +b): u along a */
    for (int s = -1; s <= 1; s += 2) {
        float b = s < 0 ? b0 : b1, fs = (float)s;
        float q[4][2] = { { a0, z0 }, { a1, z0 }, { a1, h.zw }, { a0, h.zw } };
        int idx[6] = { 0, 1, 2, 0, 2, 3 };
        for (int k = 0; k < 6; k++) {
            const float *p = q[idx[k]];
            house_vert(&h, p[0], b, p[1], 0.0f, fs, 0.0f, p[0] - h.ca, p[1] - z0, half_a, 0.0f);
        }
    }
    /* end walls (normal -a, +a) with their gables: u along b */
    for (int s = -1; s <= 1; s += 2) {
        float a = s < 0 ? a0 : a1, fs = (float)s;
        float q[5][2] = { { b0, z0 }, { b1, z0 }, { b1, h.zw }, { b0, h.zw }, { h.cb, z1 } };
        int idx[9] = { 0, 1, 2, 0, 2, 3, 3, 2, 4 };
        for (int k = 0; k < 9; k++) {
            const float *p = q[idx[k]];
            house_vert(&h, a, p[0], p[1], fs, 0.0f, 0.0f, p[0] - h.cb, p[1] - z0, half_b, 0.0f);
        }
    }
    /* roof planes: from the eave at b0 or b1 up to the ridge; v along the slope */
    float slope = sqrtf(half_b * half_b + rh * rh);
    float nb = slope > 0.0f ? rh / slope : 0.0f, nz = slope > 0.0f ? half_b / slope : 1.0f;
    for (int s = -1; s <= 1; s += 2) {
        float b = s < 0 ? b0 : b1, fs = (float)s;
        float q[4][3] = {
            { a0, b, 0.0f }, { a1, b, 0.0f }, { a1, h.cb, slope }, { a0, h.cb, slope }
        };
        int idx[6] = { 0, 1, 2, 0, 2, 3 };
        for (int k = 0; k < 6; k++) {
            const float *p = q[idx[k]];
            float z = p[2] > 0.0f ? z1 : h.zw;
            house_vert(&h, p[0], p[1], z, 0.0f, fs * nb, nz, p[0] - h.ca, p[2], half_a, 1.0f);
        }
    }
    return h.out;
}
