/* Camera: the view matrix against the eye/target geometry, orbit keeps the radius and
 * clamps pitch, zoom and pan in closed form, fly moves along the view, projection maps
 * the field-of-view edge to the clip edge, and wall tiles tile the full frustum. */
#include <math.h>

#include "camera.h"
#include "check.h"

static void xform(const float m[16], const float p[3], float w_out[4])
{
    for (int r = 0; r < 4; r++) {
        w_out[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    }
}

static double dist3(const float a[3], const float b[3])
{
    double dx = (double)a[0] - (double)b[0], dy = (double)a[1] - (double)b[1],
           dz = (double)a[2] - (double)b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static void test_view(void)
{
    camera c;
    const float target[3] = { 10, -4, 3 };
    camera_init(&c, target, 25.0f);
    float v[16], e[3], p[4];
    camera_view(&c, v);
    camera_eye(&c, e);
    CHECK_NEAR(dist3(e, target), 25.0, 1e-4);
    CHECK(e[2] > target[2]); /* looking down */
    xform(v, e, p);
    CHECK_NEAR(p[0], 0, 1e-4);
    CHECK_NEAR(p[1], 0, 1e-4);
    CHECK_NEAR(p[2], 0, 1e-4);
    xform(v, target, p);
    CHECK_NEAR(p[0], 0, 1e-4);
    CHECK_NEAR(p[1], 0, 1e-4);
    CHECK_NEAR(p[2], -25.0, 1e-4);
    /* world up stays up on screen: a point above the target has view y > 0, x = 0 */
    const float above[3] = { 10, -4, 4 };
    xform(v, above, p);
    CHECK(p[1] > 0.0f);
    CHECK_NEAR(p[0], 0, 1e-5);
    /* rotation part orthonormal */
    for (int a = 0; a < 3; a++) {
        for (int b = 0; b < 3; b++) {
            double d = 0;
            for (int k = 0; k < 3; k++) {
                d += (double)v[k * 4 + a] * (double)v[k * 4 + b];
            }
            CHECK_NEAR(d, a == b ? 1.0 : 0.0, 1e-6);
        }
    }
}

static void test_orbit_zoom(void)
{
    camera c;
    const float target[3] = { 0, 0, 5 };
    camera_init(&c, target, 40.0f);
    float e0[3], e1[3];
    camera_eye(&c, e0);
    camera_orbit(&c, 200.0f, 0.0f); /* 1 rad of yaw */
    camera_eye(&c, e1);
    CHECK_NEAR(dist3(e1, target), 40.0, 1e-4);
    CHECK_NEAR(e1[2], e0[2], 1e-4); /* horizontal drag keeps the height */
    /* chord of 1 rad on the horizontal circle of radius 40 cos 30° */
    CHECK_NEAR(dist3(e0, e1), 2 * 40 * cos(0.5235988) * sin(0.5), 1e-3);
    camera_orbit(&c, 0.0f, -100000.0f); /* far up: clamped below the pole */
    CHECK_NEAR(c.pitch, CAMERA_MAX_PITCH, 1e-6);
    camera_orbit(&c, 0.0f, 100000.0f);
    CHECK_NEAR(c.pitch, -CAMERA_MAX_PITCH, 1e-6);
    camera_zoom(&c, 2.0f);
    CHECK_NEAR(c.distance, 40.0 * 0.85 * 0.85, 1e-4);
    camera_zoom(&c, 1000.0f);
    CHECK_NEAR(c.distance, CAMERA_MIN_DIST, 0);
    camera_zoom(&c, -1000.0f);
    CHECK_NEAR(c.distance, CAMERA_MAX_DIST, 0);
}

static void test_pan(void)
{
    camera c;
    const float target[3] = { 0, 0, 0 };
    camera_init(&c, target, 30.0f);
    float e0[3], e1[3], f[3];
    camera_eye(&c, e0);
    camera_forward(&c, f);
    camera_pan(&c, 0.0f, 600.0f, 600); /* a full screen height down-drag */
    camera_eye(&c, e1);
    /* moves by the visible height at the target: 2 d tan(fov/2) */
    CHECK_NEAR(dist3(c.target, target), 2 * 30 * tan(0.5 * 50 * 3.14159265 / 180), 1e-3);
    double along = (double)(c.target[0] * f[0] + c.target[1] * f[1] + c.target[2] * f[2]);
    CHECK_NEAR(along, 0.0, 1e-4);                /* in the view plane */
    CHECK_NEAR(dist3(e1, c.target), 30.0, 1e-4); /* same offset */
    CHECK_NEAR(e1[0] - e0[0], c.target[0], 1e-4);
    camera_pan(&c, 50.0f, 0.0f, 0); /* no framebuffer: no move */
    CHECK_NEAR(dist3(e1, c.target), 30.0, 1e-4);
}

static void test_fly(void)
{
    camera c;
    const float target[3] = { 0, 0, 0 };
    camera_init(&c, target, 20.0f);
    float e0[3], f[3], e1[3];
    camera_eye(&c, e0);
    camera_forward(&c, f);
    camera_fly(&c, 1.0f, 0.0f, 0.0f, 0.5f); /* W for half a second */
    CHECK(c.mode == CAMERA_FLY);
    camera_eye(&c, e1);
    for (int k = 0; k < 3; k++) {
        CHECK_NEAR(e1[k] - e0[k], f[k] * c.fly_speed * 0.5f, 1e-4);
    }
    camera_fly(&c, 0.0f, 0.0f, 1.0f, 1.0f); /* E: straight up */
    float e2[3];
    camera_eye(&c, e2);
    CHECK_NEAR(e2[2] - e1[2], c.fly_speed, 1e-4);
    CHECK_NEAR(e2[0], e1[0], 1e-6);
    camera_fly(&c, 0.0f, 1.0f, 0.0f, 1.0f); /* D: to the right, horizontal */
    float e3[3];
    camera_eye(&c, e3);
    CHECK_NEAR(e3[2], e2[2], 1e-5);
    /* right of the view: positive x in view space */
    float v[16], p[4];
    camera_view(&c, v);
    xform(v, e2, p);
    CHECK(p[0] < 0.0f); /* where we were is now to our left */
    /* back to orbit: eye kept, target ahead at `distance` */
    camera_set_mode(&c, CAMERA_ORBIT);
    float e4[3];
    camera_eye(&c, e4);
    CHECK_NEAR(dist3(e4, e3), 0.0, 1e-4);
}

static void test_proj_and_tiles(void)
{
    camera c;
    const float target[3] = { 0, 0, 0 };
    camera_init(&c, target, 20.0f);
    float pm[16], p[4];
    camera_proj(&c, 16.0f / 9.0f, 0.5f, 1000.0f, pm);
    /* a view-space point on the top edge of the field of view at depth 10 */
    double ty = 10 * tan(25 * 3.14159265358979 / 180);
    const float top[3] = { 0, (float)ty, -10 };
    xform(pm, top, p);
    CHECK_NEAR(p[1] / p[3], 1.0, 1e-5);
    const float right[3] = { (float)(ty * 16 / 9), 0, -10 };
    xform(pm, right, p);
    CHECK_NEAR(p[0] / p[3], 1.0, 1e-5);
    const float nearp[3] = { 0, 0, -0.5f }, farp[3] = { 0, 0, -1000.0f };
    xform(pm, nearp, p);
    CHECK_NEAR(p[2] / p[3], -1.0, 1e-5);
    xform(pm, farp, p);
    CHECK_NEAR(p[2] / p[3], 1.0, 1e-4);

    /* one tile, no bezel: the ordinary projection */
    float tm[16];
    camera_tile_proj(&c, 0, 0, 1, 1, 16.0f / 9.0f, 0.1f, 0.5f, 1000.0f, tm);
    for (int k = 0; k < 16; k++) {
        CHECK_NEAR(tm[k], pm[k], 1e-6);
    }
    /* 3 × 2 wall without bezels: the seam between tiles (0,0) and (1,0) is clip x = +1 in
     * one and −1 in the other; the wall's top-left corner is (−1, +1) in tile (0,0). */
    const float a = 4.0f / 3.0f;
    float t00[16], t10[16], t21[16];
    camera_tile_proj(&c, 0, 0, 3, 2, a, 0.0f, 0.5f, 1000.0f, t00);
    camera_tile_proj(&c, 1, 0, 3, 2, a, 0.0f, 0.5f, 1000.0f, t10);
    camera_tile_proj(&c, 2, 1, 3, 2, a, 0.0f, 0.5f, 1000.0f, t21);
    /* wall at depth 10: half-height 10 tan 25°, half-width 1.5 a / 1 × that */
    double hh = 10 * tan(25 * 3.14159265358979 / 180), hw = hh * 3 * (double)a / 2;
    const float seam[3] = { (float)(-hw + 2 * hw / 3), (float)(hh * 0.5), -10 };
    float p0[4], p1[4];
    xform(t00, seam, p0);
    xform(t10, seam, p1);
    CHECK_NEAR(p0[0] / p0[3], 1.0, 1e-5);
    CHECK_NEAR(p1[0] / p1[3], -1.0, 1e-5);
    CHECK_NEAR(p0[1] / p0[3], p1[1] / p1[3], 1e-5); /* same height in both tiles */
    const float corner[3] = { (float)-hw, (float)hh, -10 };
    xform(t00, corner, p0);
    CHECK_NEAR(p0[0] / p0[3], -1.0, 1e-5);
    CHECK_NEAR(p0[1] / p0[3], 1.0, 1e-5);
    const float br[3] = { (float)hw, (float)-hh, -10 };
    xform(t21, br, p0);
    CHECK_NEAR(p0[0] / p0[3], 1.0, 1e-5);
    CHECK_NEAR(p0[1] / p0[3], -1.0, 1e-5);
    /* with bezels a point in the hidden strip between two tiles is on neither */
    float b00[16], b10[16];
    camera_tile_proj(&c, 0, 0, 2, 1, a, 0.1f, 0.5f, 1000.0f, b00);
    camera_tile_proj(&c, 1, 0, 2, 1, a, 0.1f, 0.5f, 1000.0f, b10);
    const float mid[3] = { 0, 0, -10 };
    xform(b00, mid, p0);
    xform(b10, mid, p1);
    CHECK(p0[0] / p0[3] > 1.0f && p1[0] / p1[3] < -1.0f);
    /* and the strip is 0.1 tile wide: tile 0 clip x at the centre = 1 + 0.05 × 2 */
    CHECK_NEAR(p0[0] / p0[3], 1.1, 1e-5);
    CHECK_NEAR(p1[0] / p1[3], -1.1, 1e-5);
}

int main(void)
{
    RUN(test_view);
    RUN(test_orbit_zoom);
    RUN(test_pan);
    RUN(test_fly);
    RUN(test_proj_and_tiles);
    return check_report();
}
