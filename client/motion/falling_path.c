/* Falling-leaf path: a quasi-steady falling-plate simulation (gravity, normal pressure
 * force ∝ |v|(v·n), tangential friction, centre of pressure ahead of the centre, which
 * pitches the plate up and makes it flutter) sampled into the one shared path of
 * Vazquez 2008 section 3.2, with starting and continuity points (sections 3.5, 4.2). */
#include "falling_path.h"

#include <math.h>
#include <string.h>

#include "hash.h"

#define RHO_AIR 1.2f
#define GRAV    9.81f

static float hash01(uint32_t x)
{
    return (float)(hash_mix32(x) >> 8) * (1.0f / 16777216.0f);
}

static void cross3(const float a[3], const float b[3], float o[3])
{
    float t[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0] };
    memcpy(o, t, sizeof t);
}

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* v' = q v q* for a unit quaternion (x, y, z, w) */
static void quat_rotate(const float q[4], const float v[3], float o[3])
{
    float u[3] = { q[0], q[1], q[2] }, t[3], c[3];
    cross3(u, v, t);
    for (int k = 0; k < 3; k++) {
        t[k] *= 2.0f;
    }
    cross3(u, t, c);
    for (int k = 0; k < 3; k++) {
        o[k] = v[k] + q[3] * t[k] + c[k];
    }
}

static void quat_mul(const float a[4], const float b[4], float o[4])
{
    float t[4] = { a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
                   a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
                   a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
                   a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2] };
    memcpy(o, t, sizeof t);
}

static void quat_normalize(float q[4])
{
    float n = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; k++) {
        q[k] /= n;
    }
}

int falling_path_build(falling_path *p, const falling_path_desc *desc, gale_err *err)
{
    falling_path_desc d = desc ? *desc : (falling_path_desc){ 0 };
    if (d.duration_s == 0.0f) {
        d.duration_s = 8.0f;
    }
    if (d.leaf_size_m == 0.0f) {
        d.leaf_size_m = 0.08f;
    }
    if (d.leaf_mass_kg == 0.0f) {
        d.leaf_mass_kg = 6e-4f;
    }
    if (d.seed == 0) {
        d.seed = 1;
    }
    const float sample_dt = 1.0f / 60.0f;
    if (!(d.duration_s > 0.5f) || d.duration_s * 60.0f > (float)(FALL_MAX_SAMPLES - 1) ||
        !(d.leaf_size_m > 0.0f) || !(d.leaf_mass_kg > 0.0f)) {
        return gale_errf(err, GALE_E_RANGE,
                         "falling_path: duration_s in (0.5, %.1f], size and mass > 0; got %g %g %g",
                         (double)(FALL_MAX_SAMPLES - 1) / 60.0, (double)d.duration_s,
                         (double)d.leaf_size_m, (double)d.leaf_mass_kg);
    }
    memset(p, 0, sizeof *p);
    const float L = d.leaf_size_m, A = L * L, m = d.leaf_mass_kg;
    const float cn = 1.2f, ct = 0.08f;
    /* In-plane and normal moments of inertia of a square plate, with the air carried
       along (added inertia of a disc ~ (8/3) ρ r³ r², Lamb) which keeps a light leaf from
       spinning up without bound. */
    const float r = 0.5f * L;
    const float i_add = (8.0f / 3.0f) * RHO_AIR * r * r * r * r * r;
    const float inertia[3] = { m * L * L / 12.0f + i_add, m * L * L / 12.0f + i_add,
                               m * L * L / 6.0f };
    const float m_eff = m + (8.0f / 3.0f) * RHO_AIR * r * r * r * 0.3f;

    float x[3] = { 0 }, v[3] = { 0 }, w[3] = { 0 };
    float tilt = 0.25f + 0.2f * hash01(d.seed), az = 6.2831853f * hash01(d.seed * 7u + 3u);
    float q[4] = { sinf(0.5f * tilt) * cosf(az), sinf(0.5f * tilt) * sinf(az), 0.0f,
                   cosf(0.5f * tilt) };
    const int sub = 40;
    const float h = sample_dt / (float)sub;
    uint32_t n = (uint32_t)(d.duration_s / sample_dt) + 1;
    for (uint32_t s = 0; s < n; s++) {
        memcpy(p->pos[s], x, sizeof x);
        memcpy(p->quat[s], q, sizeof q);
        for (int k = 0; k < sub; k++) {
            const float ez[3] = { 0, 0, 1 };
            float nrm[3];
            quat_rotate(q, ez, nrm);
            float speed = sqrtf(dot3(v, v));
            float vn = dot3(v, nrm);
            float vt[3], f[3], fn[3];
            for (int c = 0; c < 3; c++) {
                vt[c] = v[c] - vn * nrm[c];
                fn[c] = -0.5f * RHO_AIR * A * cn * speed * vn * nrm[c];
                f[c] = fn[c] - 0.5f * RHO_AIR * A * ct * speed * vt[c];
            }
            f[2] -= m * GRAV;
            /* centre of pressure: a quarter chord ahead at grazing flow, the centre when
               the flow is broadside */
            float vtl = sqrtf(dot3(vt, vt)), torque[3] = { 0, 0, 0 };
            if (vtl > 1e-6f && speed > 1e-6f) {
                float sin_a = fabsf(vn) / speed;
                float e = 0.25f * L * (1.0f - sin_a);
                float rcp[3] = { e * vt[0] / vtl, e * vt[1] / vtl, e * vt[2] / vtl };
                cross3(rcp, fn, torque);
            }
            /* rotational damping: the air resists turning, ∝ ρ L^5 |ω| ω */
            float wl = sqrtf(dot3(w, w));
            for (int c = 0; c < 3; c++) {
                torque[c] -= 0.3f * RHO_AIR * L * L * L * L * L * wl * w[c] + 2e-8f * w[c];
            }
            /* angular acceleration in the body frame (diagonal inertia) */
            float qi[4] = { -q[0], -q[1], -q[2], q[3] }, tb[3], wb[3], iw[3], gyro[3];
            quat_rotate(qi, torque, tb);
            quat_rotate(qi, w, wb);
            for (int c = 0; c < 3; c++) {
                iw[c] = inertia[c] * wb[c];
            }
            cross3(wb, iw, gyro);
            for (int c = 0; c < 3; c++) {
                wb[c] += h * (tb[c] - gyro[c]) / inertia[c];
            }
            quat_rotate(q, wb, w);
            for (int c = 0; c < 3; c++) {
                v[c] += h * f[c] / m_eff;
                x[c] += h * v[c];
            }
            float wq[4] = { w[0], w[1], w[2], 0.0f }, dq[4];
            quat_mul(wq, q, dq);
            for (int c = 0; c < 4; c++) {
                q[c] += 0.5f * h * dq[c];
            }
            quat_normalize(q);
        }
        if (!isfinite(x[0] + x[1] + x[2] + q[3])) {
            return gale_errf(err, GALE_E_NUMERIC, "falling_path: simulation diverged at %.2f s",
                             (double)((float)s * sample_dt));
        }
    }
    p->n = n;
    p->dt = sample_dt;
    /* keep quaternions in one hemisphere along the path so interpolation is short */
    for (uint32_t s = 1; s < n; s++) {
        if (dot3(p->quat[s], p->quat[s - 1]) + p->quat[s][3] * p->quat[s - 1][3] < 0.0f) {
            for (int c = 0; c < 4; c++) {
                p->quat[s][c] = -p->quat[s][c];
            }
        }
    }
    p->fall_speed = -p->pos[n - 1][2] / ((float)(n - 1) * sample_dt);
    if (!(p->fall_speed > 0.05f)) {
        return gale_errf(err, GALE_E_NUMERIC, "falling_path: plate does not fall (%.3f m/s)",
                         (double)p->fall_speed);
    }

    /* starting points (section 4.2): slow and nearly flat, in the first half */
    p->start[p->n_start++] = 0;
    for (uint32_t s = 8; s < n / 2 && p->n_start < FALL_MAX_POINTS; s++) {
        float up[3];
        const float ez[3] = { 0, 0, 1 };
        quat_rotate(p->quat[s], ez, up);
        float dv[3];
        for (int c = 0; c < 3; c++) {
            dv[c] = (p->pos[s + 1][c] - p->pos[s][c]) / sample_dt;
        }
        float sp = sqrtf(dot3(dv, dv));
        if (fabsf(up[2]) > 0.9f && sp < 0.8f * p->fall_speed + 0.3f &&
            s - p->start[p->n_start - 1] >= 12) {
            p->start[p->n_start++] = s;
        }
    }
    /* continuity points: samples whose velocity and orientation best match the end */
    float score[FALL_MAX_SAMPLES];
    float ve[3];
    for (int c = 0; c < 3; c++) {
        ve[c] = p->pos[n - 1][c] - p->pos[n - 2][c];
    }
    float vel = sqrtf(dot3(ve, ve)) + 1e-6f;
    for (uint32_t s = 0; s < n; s++) {
        score[s] = INFINITY;
        if (s < n / 6 || s > (n * 3) / 4) {
            continue;
        }
        float dv[3];
        for (int c = 0; c < 3; c++) {
            dv[c] = p->pos[s][c] - p->pos[s - 1][c] - ve[c];
        }
        float qd = fabsf(dot3(p->quat[s], p->quat[n - 1]) + p->quat[s][3] * p->quat[n - 1][3]);
        score[s] = sqrtf(dot3(dv, dv)) / vel + 2.0f * (1.0f - qd);
    }
    while (p->n_cont < 4) {
        uint32_t best = 0;
        float bs = INFINITY;
        for (uint32_t s = 0; s < n; s++) {
            if (score[s] < bs) {
                bs = score[s];
                best = s;
            }
        }
        if (!isfinite(bs)) {
            break;
        }
        p->cont[p->n_cont++] = best;
        for (uint32_t s = best > 10 ? best - 10 : 0; s < n && s <= best + 10; s++) {
            score[s] = INFINITY;
        }
    }
    if (p->n_cont == 0) {
        return gale_errf(err, GALE_E_NUMERIC, "falling_path: no continuity point");
    }
    return 0;
}

void falling_var_from_seed(const falling_path *p, uint32_t seed, falling_var *v)
{
    uint32_t h = hash_mix32(seed ^ 0x9e3779b9u);
    v->start = p->start[h % p->n_start];
    v->yaw = 6.2831853f * hash01(h + 1u);
    v->sx = 1.0f + 2.0f * hash01(h + 2u);
    v->sy = 1.0f + 2.0f * hash01(h + 3u);
    v->seed = h;
}

void falling_path_eval(const falling_path *p, const falling_var *v, float tau, float pos[3],
                       float quat[4])
{
    float f = (float)v->start + (tau > 0.0f ? tau : 0.0f) / p->dt;
    float off[3] = { -p->pos[v->start][0], -p->pos[v->start][1], -p->pos[v->start][2] };
    const float last = (float)(p->n - 1);
    for (uint32_t j = 0; f >= last && j < FALL_MAX_JUMPS; j++) {
        uint32_t c = p->cont[hash_mix32(v->seed + j) % p->n_cont];
        for (int k = 0; k < 3; k++) {
            off[k] += p->pos[p->n - 1][k] - p->pos[c - 1][k];
        }
        f = f - last + (float)(c - 1);
    }
    if (f > last) {
        f = last;
    }
    uint32_t i0 = (uint32_t)f;
    uint32_t i1 = i0 + 1 < p->n ? i0 + 1 : i0;
    float t = f - (float)i0;
    float d[3], q[4];
    for (int k = 0; k < 3; k++) {
        d[k] = off[k] + p->pos[i0][k] + t * (p->pos[i1][k] - p->pos[i0][k]);
    }
    for (int k = 0; k < 4; k++) {
        q[k] = p->quat[i0][k] + t * (p->quat[i1][k] - p->quat[i0][k]);
    }
    quat_normalize(q);
    /* variation: scale the horizontal displacement, rotate the path about z */
    float cy = cosf(v->yaw), sy = sinf(v->yaw);
    float hx = d[0] * v->sx, hy = d[1] * v->sy;
    pos[0] = cy * hx - sy * hy;
    pos[1] = sy * hx + cy * hy;
    pos[2] = d[2];
    float qy[4] = { 0.0f, 0.0f, sinf(0.5f * v->yaw), cosf(0.5f * v->yaw) };
    quat_mul(qy, q, quat);
}

float falling_path_land_time(const falling_path *p, const falling_var *v, float h0,
                             float max_s)
{
    float pos[3], q[4], prev_t = 0.0f, prev_z = h0;
    const float step = 2.0f * p->dt;
    for (float t = step; t <= max_s; t += step) {
        falling_path_eval(p, v, t, pos, q);
        float z = h0 + pos[2];
        if (z <= 0.0f) {
            /* linear between the last two samples */
            return prev_t + step * prev_z / (prev_z - z);
        }
        prev_t = t;
        prev_z = z;
    }
    return max_s;
}
