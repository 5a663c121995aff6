/* A broken branch as tumbling debris (PROTOCOL.md "DAMAGE" BRANCH): a rigid piece that
 * leaves the tree where it broke, falls under gravity with quadratic drag relative to the
 * streamed wind (a = g + k |u - v| (u - v), the point-mass model of falling_path.c's
 * leaves), spins about an axis of its own, lands, settles flat and lies, then sinks away
 * so debris stays bounded. Everything random comes from a hash of (tree, node), and the
 * motion is integrated in fixed steps from the moment it broke, so every screen of a wall
 * that is fed the same wind shows the same fall. Plain C, no GL. */
#ifndef GALE_DEBRIS_PATH_H
#define GALE_DEBRIS_PATH_H

#include <stdbool.h>
#include <stdint.h>

#define DEBRIS_DT_S (1.0 / 120.0) /* integration step */
#define DEBRIS_SETTLE_S 0.6       /* from touching the ground to lying flat */
#define DEBRIS_LIE_S 45.0         /* lying on the ground, then */
#define DEBRIS_SINK_S 6.0         /* sinking out of sight, then gone */
#define DEBRIS_MAX_FALL_S 30.0    /* a piece blown about longer than this is put down */

/* The wind [m/s] at world point p (the caller's streamed field). */
typedef void (*debris_wind_fn)(void *user, const float p[3], float out[3]);

typedef struct debris_path {
    uint32_t tree, node;
    double t0_s;          /* when it broke (server clock [s]) */
    double t_s;           /* time shown (debris_path_rotation, _sink_m, _done) */
    double sim_s;         /* time of c and v: t0_s + whole steps */
    float c[3], v[3];     /* centre of the piece [m, world] and its velocity [m/s] */
    float r0[9];          /* orientation when it broke (column-major, tree frame to world) */
    float spin_axis[3];   /* unit, world */
    float spin_rad_s;
    float k_per_m;        /* drag per mass: terminal speed sqrt(g / k) */
    float rest_axis[3];   /* unit, tree frame: from the break towards the centre */
    float lie_z_m;        /* height of the centre when lying */
    bool landed;
    double land_s;        /* when it touched the ground */
    float r_land[9];      /* orientation then */
    float settle_axis[3]; /* the turn that lays it flat: unit axis, angle */
    float settle_rad;
} debris_path;

/* Starts the piece of (tree, node) at t0_s: centre c0 [m, world], orientation r0 (the
 * tree's frame then), rest_axis its main axis in the tree frame (any nonzero vector),
 * extent_m the distance from its centre to its farthest node [m, world]. */
void debris_path_start(debris_path *p, uint32_t tree, uint32_t node, double t0_s,
                       const float c0[3], const float r0[9], const float rest_axis[3],
                       float extent_m);

/* Integrates up to t_s (never backwards; steps of DEBRIS_DT_S from t0_s). */
void debris_path_advance(debris_path *p, double t_s, debris_wind_fn wind, void *user);

/* Orientation at the state's time (column-major, tree frame to world) and how far it has
 * sunk [m] (0 until the lying time is over). */
void debris_path_rotation(const debris_path *p, float r[9]);
float debris_path_sink_m(const debris_path *p);

/* Whether the piece is gone (sunk away) at the state's time. */
bool debris_path_done(const debris_path *p);

/* The C copy of shaders/common.glsl tree_frame: yaw about z, then tipped by fall towards
 * azimuth az (column-major). */
void debris_frame_matrix(float yaw, float fall, float az, float r[9]);
/* Its inverse: angles with debris_frame_matrix(yaw, fall, az) = r for a rotation r, fall in
 * 0..π. */
void debris_frame_angles(const float r[9], float *yaw, float *fall, float *az);

#endif
