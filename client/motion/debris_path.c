/* Tumbling debris: see debris_path.h. */
#include "debris_path.h"

#include <math.h>
#include <string.h>

#include "hash.h"


static float hash01(uint32_t tree, uint32_t node, uint32_t k)
{
    uint32_t h = hash_mix32(hash_mix32(tree * 0x9E3779B1u + k) ^ (node * 0x85EBCA77u + 0x165667B1u));
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* column-major 3x3: r[3 col + row] */
static void mat_mul(const float a[9], const float b[9], float out[9])
{
    float t[9];
    for (int c = 0; c < 3; c++) {
        for (int rr = 0; rr < 3; rr++) {
            t[3 * c + rr] = a[rr] * b[3 * c] + a[3 + rr] * b[3 * c + 1] + a[6 + rr] * b[3 * c + 2];
        }
    }
    memcpy(out, t, sizeof t);
}

static void mat_vec(const float a[9], const float v[3], float out[3])
{
    for (int rr = 0; rr < 3; rr++) {
        out[rr] = a[rr] * v[0] + a[3 + rr] * v[1] + a[6 + rr] * v[2];
    }
}

/* rotation by angle about unit axis k (Rodrigues) */
static void axis_angle(const float k[3], float angle, float r[9])
{
    float c = cosf(angle), s = sinf(angle), t = 1.0f - c;
    r[0] = c + t * k[0] * k[0];
    r[1] = t * k[0] * k[1] + s * k[2];
    r[2] = t * k[0] * k[2] - s * k[1];
    r[3] = t * k[0] * k[1] - s * k[2];
    r[4] = c + t * k[1] * k[1];
    r[5] = t * k[1] * k[2] + s * k[0];
    r[6] = t * k[0] * k[2] + s * k[1];
    r[7] = t * k[1] * k[2] - s * k[0];
    r[8] = c + t * k[2] * k[2];
}

void debris_frame_matrix(float yaw, float fall, float az, float r[9])
{
    const float k[3] = { -sinf(az), cosf(az), 0.0f }; /* across the fall: top goes to az */
    float tip[9], rz[9] = { cosf(yaw), sinf(yaw), 0, -sinf(yaw), cosf(yaw), 0, 0, 0, 1 };
    axis_angle(k, fall, tip);
    mat_mul(tip, rz, r);
}

void debris_frame_angles(const float r[9], float *yaw, float *fall, float *az)
{
    /* the frame's z axis is where the tip took +z: (sin f cos az, sin f sin az, cos f) */
    const float *z = &r[6];
    float zz = fminf(fmaxf(z[2], -1.0f), 1.0f);
    *fall = acosf(zz);
    *az = hypotf(z[0], z[1]) > 1e-6f ? atan2f(z[1], z[0]) : 0.0f;
    /* what is left is the yaw: tip^T r = R_z(yaw) */
    float tip[9], k[3] = { -sinf(*az), cosf(*az), 0.0f };
    axis_angle(k, *fall, tip);
    float x[3] = { tip[0] * r[0] + tip[1] * r[1] + tip[2] * r[2],
                   tip[3] * r[0] + tip[4] * r[1] + tip[5] * r[2] };
    *yaw = atan2f(x[1], x[0]);
}

void debris_path_start(debris_path *p, uint32_t tree, uint32_t node, double t0_s,
                       const float c0[3], const float r0[9], const float rest_axis[3],
                       float extent_m)
{
    memset(p, 0, sizeof *p);
    p->tree = tree;
    p->node = node;
    p->t0_s = p->t_s = p->sim_s = t0_s;
    memcpy(p->c, c0, sizeof p->c);
    memcpy(p->r0, r0, sizeof p->r0);
    /* a random axis, well away from none (uniform on the sphere) */
    float u = 2.0f * hash01(tree, node, 1) - 1.0f, ph = 6.2831853f * hash01(tree, node, 2);
    float s = sqrtf(fmaxf(1.0f - u * u, 0.0f));
    p->spin_axis[0] = s * cosf(ph);
    p->spin_axis[1] = s * sinf(ph);
    p->spin_axis[2] = u;
    p->spin_rad_s = 1.2f + 2.3f * hash01(tree, node, 3);
    /* terminal speeds 9..15 m/s: a leafy branch falls like a bundle of leaves, a bare one
     * faster (k = g / v_t²) */
    float vt = 9.0f + 6.0f * hash01(tree, node, 4);
    p->k_per_m = 9.81f / (vt * vt);
    float n = sqrtf(rest_axis[0] * rest_axis[0] + rest_axis[1] * rest_axis[1] +
                    rest_axis[2] * rest_axis[2]);
    for (int k = 0; k < 3; k++) {
        p->rest_axis[k] = n > 1e-9f ? rest_axis[k] / n : (k == 0 ? 1.0f : 0.0f);
    }
    /* lying, its centre about a third of its half-width up (a branch rests on its limbs) */
    p->lie_z_m = fminf(fmaxf(0.3f * extent_m, 0.15f), 1.2f);
}

static void rotation_falling(const debris_path *p, double t_s, float r[9])
{
    float spin[9];
    axis_angle(p->spin_axis, p->spin_rad_s * (float)(t_s - p->t0_s), spin);
    mat_mul(spin, p->r0, r);
}

static void land(debris_path *p)
{
    p->landed = true;
    p->land_s = p->sim_s;
    p->v[0] = p->v[1] = p->v[2] = 0.0f;
    rotation_falling(p, p->sim_s, p->r_land);
    /* lay the main axis flat: the shortest turn to its horizontal direction */
    float a[3];
    mat_vec(p->r_land, p->rest_axis, a);
    float h[3] = { a[0], a[1], 0.0f }, hn = hypotf(a[0], a[1]);
    if (hn < 1e-4f) {
        h[0] = 1.0f; /* straight up or down: any way will do */
        hn = 1.0f;
    }
    h[0] /= hn;
    h[1] /= hn;
    float k[3] = { a[1] * h[2] - a[2] * h[1], a[2] * h[0] - a[0] * h[2], a[0] * h[1] - a[1] * h[0] };
    float kn = sqrtf(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
    float d = a[0] * h[0] + a[1] * h[1] + a[2] * h[2];
    p->settle_rad = atan2f(kn, d);
    for (int i = 0; i < 3; i++) {
        p->settle_axis[i] = kn > 1e-6f ? k[i] / kn : (i == 2 ? 1.0f : 0.0f);
    }
}

void debris_path_advance(debris_path *p, double t_s, debris_wind_fn wind, void *user)
{
    while (!p->landed && p->sim_s + DEBRIS_DT_S <= t_s) {
        const float dt = (float)DEBRIS_DT_S;
        float u[3] = { 0.0f, 0.0f, 0.0f };
        if (wind) {
            wind(user, p->c, u);
        }
        float rel[3] = { u[0] - p->v[0], u[1] - p->v[1], u[2] - p->v[2] };
        float rs = sqrtf(rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2]);
        for (int k = 0; k < 3; k++) {
            p->v[k] += dt * (p->k_per_m * rs * rel[k] - (k == 2 ? 9.81f : 0.0f));
            p->c[k] += dt * p->v[k];
        }
        p->sim_s += DEBRIS_DT_S;
        if (p->c[2] <= p->lie_z_m || p->sim_s - p->t0_s >= DEBRIS_MAX_FALL_S) {
            p->c[2] = p->lie_z_m;
            land(p);
        }
    }
    if (t_s > p->t_s) {
        p->t_s = t_s;
    }
}

void debris_path_rotation(const debris_path *p, float r[9])
{
    if (!p->landed || p->t_s < p->land_s) {
        rotation_falling(p, p->landed ? p->land_s : p->t_s, r);
        return;
    }
    float f = (float)((p->t_s - p->land_s) / DEBRIS_SETTLE_S);
    f = f < 0.0f ? 0.0f : f > 1.0f ? 1.0f : f;
    f = f * f * (3.0f - 2.0f * f);
    float turn[9];
    axis_angle(p->settle_axis, f * p->settle_rad, turn);
    mat_mul(turn, p->r_land, r);
}

float debris_path_sink_m(const debris_path *p)
{
    if (!p->landed) {
        return 0.0f;
    }
    double s = (p->t_s - p->land_s - DEBRIS_LIE_S) / DEBRIS_SINK_S;
    return s > 0.0 ? (float)s * (2.0f * p->lie_z_m + 2.0f) : 0.0f;
}

bool debris_path_done(const debris_path *p)
{
    return p->landed && p->t_s - p->land_s >= DEBRIS_LIE_S + DEBRIS_SINK_S;
}
