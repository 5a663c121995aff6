/* The error of a wind grid against a reference grid where it matters, at the trees: both
 * grids driven by the same inflow, gusts and force balls tick by tick, each stepped on
 * its own schedule, sampled at the same crown points every tick; per point the mean and
 * standard deviation of the horizontal speed and its 3-s gust factor (the largest 3-s
 * running mean over the record mean, WMO-No. 8 part I section 5.8.3), compared point by
 * point and as a mean profile by height (PHYSICS.md "Wind at landscape scale"). */
#ifndef GALE_WIND_ERROR_H
#define GALE_WIND_ERROR_H

#include "err.h"
#include "wind.h"

#define WIND_ERROR_MAX_BINS 32

/* The forcing at time t_s: the inflow (mean wind and this instant's gust) and the force
 * balls of the steps taken at this tick (borrowed until the next call). */
typedef void (*wind_error_drive)(void *ctx, double t_s, wind_inflow *in,
                                 const wind_ball **balls, int *n_balls);

typedef struct wind_error_desc {
    wind_desc ref;           /* the reference grid (obstacles borrowed for the call) */
    wind_desc test;          /* the grid under test */
    int ref_every;           /* steps every k ticks; 0 → 1 */
    int test_every;
    double tick_hz;          /* sampling and inflow rate; 0 → 60 */
    double spinup_s;         /* run before recording */
    double record_s;         /* recorded; at least 3 s (one gust window) */
    const float *points;     /* [n_points][3] world [m], borrowed */
    int n_points;
    float bin_z0_m, bin_m;   /* mean profile bins [z0 + b bin, z0 + (b+1) bin) */
    int n_bins;              /* 0 .. WIND_ERROR_MAX_BINS */
    wind_error_drive drive;
    void *drive_ctx;
} wind_error_desc;

/* One grid's figures, averaged over the points. */
typedef struct wind_error_side {
    double mean_ms;          /* mean horizontal speed */
    double std_ms;           /* its standard deviation over time */
    double gust3;            /* 3-s gust factor */
    double step_ms;          /* median wall time of a step */
} wind_error_side;

typedef struct wind_error_result {
    wind_error_side ref, test;
    /* point by point: |test - ref| / ref of the mean and the std, |test - ref| of the
     * gust factor; mean over the points and the largest */
    double mean_rel_err, mean_rel_err_max;
    double std_rel_err, std_rel_err_max;
    double gust3_abs_err, gust3_abs_err_max;
    /* the 90th percentile over the points of the same three errors: the largest ones
     * are a few points (beside a house, under a ball's passage), the mean hides them */
    double mean_rel_err_p90, std_rel_err_p90, gust3_abs_err_p90;
    double corr;             /* mean over points of the speed series' correlation */
    int n_bins;
    struct {
        float z_lo_m, z_hi_m;
        int n;               /* points in the bin */
        double ref_ms, test_ms;
    } bin[WIND_ERROR_MAX_BINS];
} wind_error_result;

/* Runs both grids and fills *r; a negative GALE_E_* with err filled on a bad desc, no
 * memory or a wind step that breaks down. */
int wind_error_run(const wind_error_desc *d, wind_error_result *r, gale_err *err);

#endif
