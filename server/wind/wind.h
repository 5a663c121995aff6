/* The global wind field: incompressible, inviscid stable fluids on a 3D grid
 * (Oliapuram & Kumar 2010 section 2; Stam 1999): semi-Lagrangian advection, forces,
 * pressure projection to a stated divergence tolerance, free-slip ground and solid
 * obstacle boxes, inflow borders with a log-law height profile. World frame: z up,
 * metres, grid corner at desc.origin. */
#ifndef GALE_WIND_H
#define GALE_WIND_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"

typedef struct wind_grid wind_grid;

/* An axis-aligned solid box (house, wall) in world coordinates [m]. */
typedef struct wind_box {
    float min[3];
    float max[3];
} wind_box;

typedef struct wind_desc {
    int nx, ny, nz;            /* cells; 0 → 256 × 256 × 16 */
    float cell_m;              /* cell edge [m]; 0 → 2 */
    float origin[3];           /* world position of the grid's low corner [m] */
    float div_reduction;       /* required ‖div‖ before / after projection; 0 → 100 */
    int max_iterations;        /* pressure solver budget per step; 0 → solver default */
    int threads;               /* 0 → 2 */
    uint64_t seed;             /* turbulence jitter; same seed, same field */
    const wind_box *obstacles; /* borrowed for the create call only */
    int n_obstacles;
    /* 1: restore, at sampling, the log-law shear the grid cannot resolve between its
     * lowest cell centres (wind_sample*, PHYSICS.md "Wind at landscape scale"): a coarse
     * grid then gives the trees the mean profile of a fine one. 0: plain trilinear. */
    int subgrid_profile;
} wind_desc;

/* Inflow at the open borders: the mean wind far upstream, with a log-law height
 * profile U(z) = U10 ln(z/z0) / ln(10/z0), z clamped below at z_min. */
typedef struct wind_inflow {
    float dir_rad;    /* direction the wind blows TOWARD, from +x counter-clockwise */
    float u10_ms;     /* mean speed at 10 m [m/s] */
    float z0_m;       /* roughness length; 0 → 0.3 (suburban, EN 1991-1-4 terrain III) */
    float zmin_m;     /* 0 → 5 */
    float gust[3];    /* gust velocity added uniformly this step [m/s] (from the gust process) */
} wind_inflow;

/* A Gaussian ball of force (the paper's trackball control). */
typedef struct wind_ball {
    float center[3];  /* [m] world */
    float radius_m;   /* Gaussian σ */
    float force[3];   /* acceleration at the centre [m/s²] */
    float jitter_m;   /* random displacement of the centre each step (turbulence) */
} wind_ball;

typedef struct wind_step_stats {
    double div_before;  /* L2 of divergence over fluid cells before projection */
    double div_after;   /* after projection */
    int iterations;     /* pressure solver iterations (V-cycles or CG steps) */
    double residual;    /* final ||b - A p|| / ||b|| of the pressure solve (= after / before) */
    double ms;          /* wall time of the step */
    double ms_advect;   /* of which: advection (with ghost filling) */
    double ms_forces;   /*           forces, boundary conditions, divergence */
    double ms_solve;    /*           pressure solve */
    double ms_project;  /*           projection */
} wind_step_stats;

/* Creates a wind grid at rest; NULL on failure with err filled. */
wind_grid *wind_create(const wind_desc *d, gale_err *err);
/* Frees the grid. NULL is a no-op. */
void wind_destroy(wind_grid *w);
/* The desc with every default resolved, as the grid uses it. */
wind_desc wind_get_desc(const wind_grid *w);

/* Sets the inflow used from the next step on. */
void wind_set_inflow(wind_grid *w, const wind_inflow *in);
/* Sets only what the samplers' subgrid term reads of the inflow (desc.subgrid_profile:
 * the direction and the table), at once; the step keeps the inflow wind_set_inflow gave
 * it. Touches nothing wind_step reads, so it may run while another thread steps. */
void wind_set_subgrid_inflow(wind_grid *w, const wind_inflow *in);
/* Copies the field for the samplers (wind_sample, wind_sample_many, wind_probe_sample,
 * wind_coarse): from the first call on they read the field as it stood at the last,
 * while wind_step may advance it on another thread; before it, the field itself.
 * GALE_E_NOMEM when the copy cannot be allocated (the samplers' copy is left as it was). */
int wind_publish(wind_grid *w);
/* Adds a force ball applied in the next step only. */
void wind_add_ball(wind_grid *w, const wind_ball *b);
/* Advances the field by dt_s; fills *st when not NULL. Fails only on a numerical
 * breakdown (non-finite values), which the caller logs. */
int wind_step(wind_grid *w, float dt_s, wind_step_stats *st);

/* Sets the whole field to the current inflow profile (solid faces, ground and lid at
 * zero normal velocity) and clears the pressure warm start: a start already in the wind. */
void wind_fill_inflow(wind_grid *w);
/* RMS divergence [1/s] of the current field over fluid cells, computed from the face
 * velocities in double, independently of the solver. */
double wind_divergence_rms(const wind_grid *w);

/* Trilinear wind velocity [m/s] at a world point; points outside the grid clamp to it.
 * With desc.subgrid_profile the horizontal wind gains U(z) - U~(z) along the inflow
 * direction: the log law at the point's height minus the log law as the grid's samples
 * interpolate it there. */
void wind_sample(const wind_grid *w, const float p[3], float v[3]);
/* The same for n points p[3n] into v[3n] (one per tree per tick). */
void wind_sample_many(const wind_grid *w, int n, const float *p, float *v);

/* Points fixed for the grid's life (a forest's crowns: trees never move), with each
 * point's trilinear stencil on the three staggered components worked out once: an
 * index and three fractions per component, the same numbers wind_sample computes per
 * call, so reading the grid there costs only the gather and the blend. */
typedef struct wind_probe wind_probe;
/* Stencils of n points p[3n] on w's lattice (used with w, or a grid of the same desc);
 * NULL on failure with err filled (no memory, or a grid too large for 32-bit indices). */
wind_probe *wind_probe_create(const wind_grid *w, int n, const float *p, gale_err *err);
/* NULL is a no-op. */
void wind_probe_destroy(wind_probe *pr);
/* The grid's part of the wind (wind_sample without the subgrid profile) at the probe's
 * points [i0, i1) into v[3 * i0 .. 3 * i1): the same floats as wind_sample gives there
 * with desc.subgrid_profile 0. One thread; callers split the points. What it reads
 * changes only in wind_step and wind_fill_inflow (once published, only in wind_publish),
 * so between those this needs no repeating. */
void wind_probe_sample(const wind_grid *w, const wind_probe *pr, int i0, int i1, float *v);
/* The distinct 64-byte lines of memory wind_probe_sample(w, pr, i0, i1, ...) reads from
 * the grid now (the stencils' eight samples of each component, in the buffers it reads),
 * into *lines: the least a pass over those points moves when the grid is not cached (a
 * grid larger than the caches, rewritten by each step). Non-zero with err filled when
 * there is no memory for the count. */
int wind_probe_lines(const wind_grid *w, const wind_probe *pr, int i0, int i1, size_t *lines,
                     gale_err *err);
/* Adds the subgrid profile's term of the current inflow (desc.subgrid_profile) at n
 * points p[3n] to v[3n]; nothing without it. The grid's part from wind_probe_sample
 * plus this is wind_sample's result, float for float; the term follows wind_set_inflow
 * at once (the table depends on U10, z0, z_min and the direction). */
void wind_add_subgrid(const wind_grid *w, int n, const float *p, float *v);

/* Coarse copy for clients: the grid averaged over factor³ blocks (factor in z capped to
 * nz), written as float [cz][cy][cx][3] into out (capacity floats). Returns the number of
 * floats written and the coarse dims in dims[3], or a negative GALE_E_* if out is small. */
int wind_coarse(const wind_grid *w, int factor, float *out, int capacity, int dims[3]);

#endif
