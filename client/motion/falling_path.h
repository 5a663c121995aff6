/* One shared falling-leaf path (Vazquez 2008 sections 3.2-4.2): a small falling-plate
 * simulation sampled into positions and orientations, with starting points (slow, flat)
 * and continuity points (matching velocity and orientation) for path reuse. The same
 * evaluation runs on the CPU (landing time) and in shaders/fall.vert. */
#ifndef GALE_FALLING_PATH_H
#define GALE_FALLING_PATH_H

#include <stdint.h>

#include "err.h"

#define FALL_MAX_SAMPLES 1024
#define FALL_MAX_POINTS  8   /* starting points and continuity points each */
#define FALL_MAX_JUMPS   64  /* path reuses per leaf before it stops (well past landing) */

typedef struct falling_path {
    uint32_t n;                      /* samples */
    float dt;                        /* sample spacing [s] */
    float pos[FALL_MAX_SAMPLES][3];  /* displacement from sample 0 [m], z up */
    float quat[FALL_MAX_SAMPLES][4]; /* orientation (x, y, z, w): leaf frame to world */
    uint32_t n_start, start[FALL_MAX_POINTS]; /* samples where a leaf may begin */
    uint32_t n_cont, cont[FALL_MAX_POINTS];   /* c: after sample n-1 the path goes on at c
                                                 with the increment P[c] - P[c-1] */
    float fall_speed;                /* mean descent speed [m/s] */
} falling_path;

typedef struct falling_path_desc {
    float duration_s;   /* simulated length; 0 = 8 */
    float leaf_size_m;  /* plate side; 0 = 0.08 */
    float leaf_mass_kg; /* 0 = 6e-4 */
    uint32_t seed;      /* initial tilt and perturbation; 0 = 1 */
} falling_path_desc;

/* Simulates a falling plate (gravity, quasi-steady normal and tangential air force,
 * centre of pressure ahead of the centre, rotational damping) and fills *p. */
int falling_path_build(falling_path *p, const falling_path_desc *desc, gale_err *err);

/* Per-leaf variation of the shared path, from its seed (section 4.1). */
typedef struct falling_var {
    uint32_t start;  /* starting sample */
    float yaw;       /* rotation of the path about the vertical [rad] */
    float sx, sy;    /* horizontal displacement scales */
    uint32_t seed;   /* picks continuity points */
} falling_var;

void falling_var_from_seed(const falling_path *p, uint32_t seed, falling_var *v);

/* Displacement from the start and orientation at time tau [s] after release, with path
 * reuse at continuity points (section 4.2) and the per-leaf variation applied. */
void falling_path_eval(const falling_path *p, const falling_var *v, float tau, float pos[3],
                       float quat[4]);

/* Time [s] after release when a leaf released at height h0 [m] above the ground
 * reaches it; capped at max_s. */
float falling_path_land_time(const falling_path *p, const falling_var *v, float h0,
                             float max_s);

#endif
