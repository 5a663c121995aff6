/* Client camera: orbit and fly about a z-up world, look-at view matrix, symmetric and
 * off-axis (wall tile) perspective frusta in OpenGL clip conventions. */
#include "camera.h"

#include <math.h>
#include <string.h>

static float clampf(float v, float lo, float hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

void camera_init(camera *c, const float target[3], float distance)
{
    memset(c, 0, sizeof *c);
    c->mode = CAMERA_ORBIT;
    memcpy(c->target, target, sizeof c->target);
    c->distance = clampf(distance, CAMERA_MIN_DIST, CAMERA_MAX_DIST);
    c->yaw = 1.5707963f - 0.6108652f; /* +y turned 35° clockwise */
    c->pitch = -0.5235988f;           /* looking down 30° */
    c->fov_y_deg = 50.0f;
    c->fly_speed = 15.0f;
    c->orbit_rad_per_px = 0.005f;
    camera_eye(c, c->eye);
}

void camera_forward(const camera *c, float f[3])
{
    float cp = cosf(c->pitch);
    f[0] = cp * cosf(c->yaw);
    f[1] = cp * sinf(c->yaw);
    f[2] = sinf(c->pitch);
}

void camera_eye(const camera *c, float eye[3])
{
    if (c->mode == CAMERA_FLY) {
        memcpy(eye, c->eye, 3 * sizeof(float));
        return;
    }
    float f[3];
    camera_forward(c, f);
    for (int k = 0; k < 3; k++) {
        eye[k] = c->target[k] - f[k] * c->distance;
    }
}

void camera_orbit(camera *c, float dx_px, float dy_px)
{
    /* dragging right turns the scene right: the eye moves left about the target */
    c->yaw -= dx_px * c->orbit_rad_per_px;
    c->yaw = remainderf(c->yaw, 6.2831853f);
    c->pitch = clampf(c->pitch - dy_px * c->orbit_rad_per_px, -CAMERA_MAX_PITCH, CAMERA_MAX_PITCH);
    if (c->mode == CAMERA_ORBIT) {
        camera_eye(c, c->eye);
    }
}

/* Right and up unit vectors of the view (z-up world). */
static void basis(const camera *c, float r[3], float u[3])
{
    float f[3];
    camera_forward(c, f);
    r[0] = sinf(c->yaw);
    r[1] = -cosf(c->yaw);
    r[2] = 0.0f;
    u[0] = r[1] * f[2] - r[2] * f[1];
    u[1] = r[2] * f[0] - r[0] * f[2];
    u[2] = r[0] * f[1] - r[1] * f[0];
}

void camera_pan(camera *c, float dx_px, float dy_px, int fb_h)
{
    if (fb_h <= 0) {
        return;
    }
    float r[3], u[3];
    basis(c, r, u);
    /* world metres per pixel at the target's depth */
    float d = c->mode == CAMERA_ORBIT ? c->distance : 10.0f;
    float m_per_px = 2.0f * d * tanf(0.5f * c->fov_y_deg * 0.017453293f) / (float)fb_h;
    for (int k = 0; k < 3; k++) {
        float delta = (-dx_px * r[k] + dy_px * u[k]) * m_per_px;
        c->target[k] += delta;
        c->eye[k] += delta;
    }
}

void camera_zoom(camera *c, float clicks)
{
    if (c->mode == CAMERA_FLY) {
        float f[3];
        camera_forward(c, f);
        for (int k = 0; k < 3; k++) {
            c->eye[k] += f[k] * clicks * 0.2f * c->fly_speed;
        }
        return;
    }
    c->distance = clampf(c->distance * powf(0.85f, clicks), CAMERA_MIN_DIST, CAMERA_MAX_DIST);
    camera_eye(c, c->eye);
}

void camera_set_mode(camera *c, int mode)
{
    if (mode == c->mode) {
        return;
    }
    float eye[3], f[3];
    camera_eye(c, eye);
    camera_forward(c, f);
    c->mode = mode;
    memcpy(c->eye, eye, sizeof eye);
    if (mode == CAMERA_ORBIT) {
        for (int k = 0; k < 3; k++) {
            c->target[k] = eye[k] + f[k] * c->distance;
        }
    }
}

void camera_fly(camera *c, float forward, float right, float up, float dt_s)
{
    if (forward == 0.0f && right == 0.0f && up == 0.0f) {
        return;
    }
    camera_set_mode(c, CAMERA_FLY);
    float f[3], r[3], u[3];
    camera_forward(c, f);
    basis(c, r, u);
    const float step = c->fly_speed * dt_s;
    for (int k = 0; k < 3; k++) {
        c->eye[k] += step * (forward * f[k] + right * r[k]);
    }
    c->eye[2] += step * up; /* Q/E move along world up, as in most fly cameras */
}

void camera_view(const camera *c, float m[16])
{
    float e[3], f[3], s[3], u[3];
    camera_eye(c, e);
    camera_forward(c, f);
    basis(c, s, u);
    /* s = f × z normalised: (sin yaw, −cos yaw, 0) is that for any pitch */
    const float rows[3][3] = { { s[0], s[1], s[2] },
                               { u[0], u[1], u[2] },
                               { -f[0], -f[1], -f[2] } };
    memset(m, 0, 16 * sizeof(float));
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++) {
            m[k * 4 + r] = rows[r][k];
        }
        m[12 + r] = -(rows[r][0] * e[0] + rows[r][1] * e[1] + rows[r][2] * e[2]);
    }
    m[15] = 1.0f;
}

/* glFrustum */
static void frustum(float l, float r, float b, float t, float n, float f, float m[16])
{
    memset(m, 0, 16 * sizeof(float));
    m[0] = 2 * n / (r - l);
    m[5] = 2 * n / (t - b);
    m[8] = (r + l) / (r - l);
    m[9] = (t + b) / (t - b);
    m[10] = -(f + n) / (f - n);
    m[11] = -1.0f;
    m[14] = -2 * f * n / (f - n);
}

void camera_proj(const camera *c, float aspect, float z_near, float z_far, float m[16])
{
    float t = z_near * tanf(0.5f * c->fov_y_deg * 0.017453293f);
    frustum(-t * aspect, t * aspect, -t, t, z_near, z_far, m);
}

void camera_tile_proj(const camera *c, int col, int row, int cols, int rows, float tile_aspect,
                      float bezel_frac, float z_near, float z_far, float m[16])
{
    /* wall in tile units: width cols + (cols − 1) g, height rows + (rows − 1) g */
    const float g = bezel_frac;
    const float wall_w = (float)cols + (float)(cols - 1) * g;
    const float wall_h = (float)rows + (float)(rows - 1) * g;
    const float t_full = z_near * tanf(0.5f * c->fov_y_deg * 0.017453293f);
    /* metres at the near plane per tile-height unit; a tile unit wide is tile_aspect × */
    const float per_h = 2.0f * t_full / wall_h;
    const float per_w = per_h * tile_aspect;
    const float x0 = (float)col * (1.0f + g), y0 = (float)row * (1.0f + g);
    const float l = (x0 - 0.5f * wall_w) * per_w, r = l + per_w;
    const float t = (0.5f * wall_h - y0) * per_h, b = t - per_h;
    frustum(l, r, b, t, z_near, z_far, m);
}
