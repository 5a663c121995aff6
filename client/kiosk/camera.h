/* Client camera: orbit (left-drag orbit, right-drag pan, wheel zoom) and fly (WASD/QE)
 * about a z-up world, view and projection matrices, and the off-axis projection of one
 * tile of a video wall with bezel compensation (all tiles one picture). */
#ifndef GALE_CAMERA_H
#define GALE_CAMERA_H

enum camera_mode {
    CAMERA_ORBIT = 0,
    CAMERA_FLY,
};

/* Caller-owned; camera_init fills it. Angles: yaw about +z from +x (the direction the
 * camera looks along, projected), pitch above the horizon. */
typedef struct camera {
    int mode;         /* enum camera_mode */
    float target[3];  /* ORBIT: the point orbited [m] */
    float distance;   /* ORBIT: eye-to-target [m], [CAMERA_MIN_DIST, CAMERA_MAX_DIST] */
    float eye[3];     /* FLY: eye position [m] (ORBIT: derived, see camera_eye) */
    float yaw, pitch; /* [rad]; pitch within ±CAMERA_MAX_PITCH */
    float fov_y_deg;  /* vertical field of view */
    float fly_speed;  /* FLY: [m/s] */
    float orbit_rad_per_px;
} camera;

#define CAMERA_MIN_DIST  0.5f
#define CAMERA_MAX_DIST  5000.0f
#define CAMERA_MAX_PITCH 1.55f /* just under π/2: the view never flips over the pole */

/* Orbit camera looking at target from `distance`, 30° above the horizon, looking along +y
 * rotated by -35° (a three-quarter view). */
void camera_init(camera *c, const float target[3], float distance);

/* Unit view direction (from the eye). */
void camera_forward(const camera *c, float f[3]);

/* Eye position: FLY its own, ORBIT target − forward × distance. */
void camera_eye(const camera *c, float eye[3]);

/* Left-drag by (dx, dy) pixels: yaw and pitch about the target (fly: look around). */
void camera_orbit(camera *c, float dx_px, float dy_px);

/* Right-drag: moves the target (and eye) in the view plane so the point under the cursor
 * follows it; fb_h is the framebuffer height [px]. */
void camera_pan(camera *c, float dx_px, float dy_px, int fb_h);

/* Wheel: distance × 0.85^clicks (positive clicks zoom in), clamped; fly: moves along the
 * view direction. */
void camera_zoom(camera *c, float clicks);

/* Fly by the key axes (each −1..1: forward W/S, right D/A, up E/Q) for dt_s seconds.
 * Switches an orbit camera to fly, keeping the eye where it is. */
void camera_fly(camera *c, float forward, float right, float up, float dt_s);

/* Switches mode keeping the eye and view direction (fly → orbit puts the target
 * `distance` ahead). */
void camera_set_mode(camera *c, int mode);

/* Column-major view matrix (right-handed, OpenGL). */
void camera_view(const camera *c, float m[16]);

/* Column-major perspective projection for the whole screen. */
void camera_proj(const camera *c, float aspect, float z_near, float z_far, float m[16]);

/* One tile of a cols × rows wall, tiles of equal size and aspect `tile_aspect` (w/h),
 * visible areas separated by bezel_frac × tile width (horizontally) and bezel_frac ×
 * tile height (vertically) of hidden glass, so a straight line crossing tiles stays
 * straight. The wall's vertical field of view is fov_y_deg over its full height, bezels
 * included. col 0 is the left, row 0 the top. Column-major off-axis frustum into m. */
void camera_tile_proj(const camera *c, int col, int row, int cols, int rows, float tile_aspect,
                      float bezel_frac, float z_near, float z_far, float m[16]);

#endif
