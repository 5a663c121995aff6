/* Internal state of the wind grid shared by wind.c (creation, the step), wind_force.c
 * (inflow, forces, boundaries), wind_advect.c (semi-Lagrangian advection, Oliapuram &
 * Kumar 2010 eq. 4), wind_mg.c (pressure Poisson solve, eq. 9, by geometric multigrid),
 * wind_project.c (divergence, projection, eq. 7), wind_sample.c and wind_probe.c
 * (sampling). Not a public header. */
#ifndef GALE_WIND_INT_H
#define GALE_WIND_INT_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "wind.h"

/* Single-pass kernels (advection, divergence, projection, ghosts) over fewer cells than
 * this run on one thread: fork/join (3-5 us here) costs more there. Multigrid levels,
 * swept many times per step, have their own threshold (wind_mg.c). */
#define WIND_PAR_MIN 4096

/* Hot row kernels are compiled for AVX-512 and AVX2 besides the baseline and chosen at
 * load time (GNU ifunc); sanitizer builds keep one version. */
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(__clang__) && !defined(WIND_NO_CLONES)
#define WIND_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define WIND_CLONES
#endif

/* Most force balls queued for one step; further ones in the same step are dropped and
 * counted in wind_grid.balls_dropped. */
#define WIND_MAX_BALLS 16

/* Domain sides in the order x-low, x-high, y-low, y-high. */
enum { WIND_SIDE_XLO, WIND_SIDE_XHI, WIND_SIDE_YLO, WIND_SIDE_YHI, WIND_NSIDES };

/* One velocity component on its staggered (MAC) sample lattice, with one ghost layer on
 * every side. Sample (i, j, k), -1 <= i <= n[0] etc., lies at cell coordinates
 * (i + off[0], j + off[1], k + off[2]). */
typedef struct wind_comp {
    float *d;      /* owned: padded samples */
    float *tmp;    /* owned: advection target, swapped with d */
    float *pub;    /* owned: the samplers' copy of d (wind_publish); NULL: they read d */
    int n[3];      /* samples per axis without ghosts */
    int sy, sz;    /* strides of the padded array (sx = 1) */
    size_t count;  /* padded sample count */
    float off[3];  /* position of sample (0,0,0) in cell units */
} wind_comp;

/* The samples the samplers read: the copy wind_publish made last, else the field. */
static inline const float *wind_comp_read(const wind_comp *c)
{
    return c->pub ? c->pub : c->d;
}

/* c ? a : b for floats, by a bit mask: both operands are evaluated, so when they are
 * loads gcc cannot sink them into the arms, and a loop using it vectorises without masked
 * loads (AVX2, SSE; AVX-512's masked loads are slower here too). */
static inline float wind_select(int c, float a, float b)
{
    uint32_t m = 0u - (uint32_t)(c != 0), ua, ub;
    memcpy(&ua, &a, sizeof ua);
    memcpy(&ub, &b, sizeof ub);
    uint32_t r = (ua & m) | (ub & ~m);
    float f;
    memcpy(&f, &r, sizeof f);
    return f;
}

/* Index of sample (i, j, k) of a padded array with strides sy, sz and one ghost layer. */
static inline size_t wind_idx(int sy, int sz, int i, int j, int k)
{
    return (size_t)(k + 1) * (size_t)sz + (size_t)(j + 1) * (size_t)sy + (size_t)(i + 1);
}

/* One multigrid level: a cell-centred Poisson problem in flux form, A p = b with
 * (A p)_c = sum over the faces f of c of g_f (p_c - p_nb(f)), padded by one ghost cell kept
 * at p = 0. g_f = open area / centre distance, both in finest-cell units (h0 = 1): the
 * finest level has g = 1 between fluid cells, 0 at closed faces (Neumann) and 2 on open
 * borders (p = 0 on the border face, half a cell from the centre). Coarse cells may have
 * one or two children per axis (odd sizes), so widths are kept per axis. Each row of A is
 * the sum of its children's rows, so the coarse right-hand side is the children's sum. */
typedef struct wind_level {
    int nx, ny, nz; /* cells */
    int sy, sz;     /* padded strides */
    size_t count;   /* padded cells */
    float *p;       /* owned: unknowns; ghosts stay 0 */
    float *b;       /* owned: right-hand side */
    float *ax;      /* owned: g of the x-low face of each padded cell */
    float *ay;      /* owned: y-low face */
    float *az;      /* owned: z-low face */
    float *diag;    /* owned: sum of the six g, 0 in cells without any open face */
    float *idiag;   /* owned: 1 / diag, 0 where diag is 0 */
    int *wd[3];     /* owned: cell width per axis in finest cells */
    float *rowg;    /* owned: per row (j, k), WIND_ROWG floats: [0..6) the six face g (x, y, z
                     * low/high) shared by its cells 1 .. nx-2, or g[0] = -1 where they
                     * differ (solids); [6], [7] those cells' diag and idiag;
                     * [WIND_END0..+8) and [WIND_END1..+8) cell 0's and
                     * cell nx-1's six g, diag and idiag (so constant rows never touch
                     * the coefficient arrays: one cache line per row instead of eight) */
    int r[3];       /* coarsening factor to the next level, 1 or 2 */
    double *rowsum; /* owned: per-row partial sums (ny * nz), summed in a fixed order */
} wind_level;

/* Layout of a row's entry in wind_level.rowg. */
#define WIND_ROWG 24
#define WIND_END0 8
#define WIND_END1 16

#define WIND_MAX_LEVELS 24

struct wind_grid {
    wind_desc d;                /* resolved; obstacles pointer cleared */
    int nx, ny, nz;
    float h;                    /* cell edge [m] */
    wind_comp c[3];             /* u, v, w */
    uint8_t *solid;             /* owned: 1 for solid cells, padded like level 0 */
    int n_fluid;                /* fluid cells */
    int (*boxes)[6];            /* owned: obstacle cell ranges i0,i1,j0,j1,k0,k1 (half-open) */
    int n_boxes;
    wind_level lv[WIND_MAX_LEVELS];
    int n_levels;
    int dirichlet[WIND_NSIDES]; /* 1: open border (p = 0), 0: inflow border (u.n given) */
    wind_inflow inflow;         /* resolved */
    float *inflow_z[3];         /* owned: inflow velocity per component at each sample height,
                                 * index k + 1 for k = -1 .. nz */
    wind_ball balls[WIND_MAX_BALLS];
    int n_balls;
    long balls_dropped;
    uint64_t rng;               /* jitter generator state */
    double *rowsum;             /* owned: per-row partial sums for stats (ny * nz) */
    float *scratch;             /* owned: WIND_SCRATCH_ROW floats per thread */
    /* desc.subgrid_profile: U(z) - U~(z) of the current inflow [m/s] every
     * h / WIND_SUBGRID_PER_CELL from the grid's floor to its lid, zeros when off */
    float *subgrid;             /* owned [n_subgrid] */
    int n_subgrid;
};

/* Subgrid profile table entries per cell height. */
#define WIND_SUBGRID_PER_CELL 16

/* Per-thread scratch: three displacement rows of up to nx + 1 samples (advection) or
 * one stencil row (multigrid). */
#define WIND_SCRATCH_ROW(w) ((size_t)3 * (size_t)((w)->nx + 4))

/* wind_force.c */
/* Resolves an inflow (defaults for unset fields, the profile at every sample height, the
 * subgrid table) and makes the borders it enters through inflow borders, rebuilding the
 * solver's coefficients when a border changes type. */
void wind_inflow_resolve(wind_grid *w, const wind_inflow *in);
/* Fills the ghost layer of the three components from the inflow (open sides) and by
 * free-slip reflection (ground, lid). */
void wind_fill_ghosts(wind_grid *w);
/* Adds a Gaussian force ball over dt (eq. 5) to the field. */
void wind_apply_ball(wind_grid *w, const wind_ball *b, float dt);
/* Boundary conditions on the face samples before projection (eq. 10). */
void wind_apply_bc(wind_grid *w);

/* wind_advect.c: advects the three components through themselves over dt (dt_over_h =
 * dt / h turns m/s into cells per step) into c[].tmp, then swaps d and tmp. */
void wind_advect(wind_grid *w, float dt_over_h);

/* wind_mg.c */
/* Allocates the level hierarchy for the grid's dims; 0 or GALE_E_NOMEM. */
int wind_mg_alloc(wind_grid *w, gale_err *err);
void wind_mg_free(wind_grid *w);
/* (Re)builds coefficients of every level from the solid mask and the border types. */
void wind_mg_setup(wind_grid *w);
/* Solves A p = b on level 0 from the current p (warm start) until ||b - A p||_2 <= tol
 * or max_it cycles; returns the cycles used and the final residual norm in *r_final. */
int wind_mg_solve(wind_grid *w, double tol, int max_it, double *r_final);
/* Sum of a per-row partial sum array in a fixed order. */
double wind_sum_rows(const double *rows, int n);

/* wind_project.c */
/* Right-hand side of eq. 9 on level 0 from the field's divergence; returns ||b||_2. */
double wind_divergence_rhs(wind_grid *w);
/* Eq. 7: subtracts the gradient of level 0's pressure from the field. */
void wind_project(wind_grid *w);

#endif
