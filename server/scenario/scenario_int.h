/* Internals of the scenario module shared by scenario.c, scenario_apply.c and the
 * scenario tool and tests; not part of the public API. */
#ifndef GALE_SCENARIO_INT_H
#define GALE_SCENARIO_INT_H

#include <stdbool.h>
#include <stdint.h>

#include "gust.h"
#include "holland.h"
#include "scenario.h"

/* A storm centre at one time, relative to the scene (x east, y north). */
typedef struct scenario_track_pt {
    double t_s;      /* storm time from the reference [s] */
    double x_m, y_m; /* centre [m] */
    double vx, vy;   /* translation velocity [m/s] */
    double pc_pa;    /* central pressure [Pa] */
    double rmax_m;   /* radius of maximum wind [m] */
    double vmax_ms;  /* 1-min sustained 10 m peak wind [m/s] */
} scenario_track_pt;

struct scenario {
    char name[96];
    char description[240];
    scenario_kind kind;
    uint64_t seed;
    double z0_m, zmin_m; /* inflow log law */
    double dial_rate_ms2;

    bool gust_on;
    gust_desc gd; /* resolved at create */
    gust gust;

    int n_balls;
    wind_ball *balls; /* owned */

    /* steady */
    double u10_ms, dir_from_deg;

    /* hurricane */
    char source[240];
    char site_label[96];
    double site_lat, site_lon;
    int utc_offset_min; /* site's local time = UTC + this (site.utc_offset_min) */
    bool over_land;
    bool geo; /* track in lat/lon (else x/y km) */
    bool has_ref;
    long long ref_min; /* reference UTC, minutes since the epoch */
    double pn_pa, rho, f, inflow_rad;
    double surface_factor, land_factor, asymmetry, time_scale;
    double start_s, end_s;
    bool loop;
    int n_track;
    scenario_track_pt *track; /* owned */

    /* run time */
    double t0;     /* server time of the (re)start */
    double first_storm_s, first_scale; /* where and how fast a restart replays from: the
                                          window's start and time_scale, or what
                                          scenario_set_start gave */
    bool paused;   /* the replay clock holds at base_storm_s */
    double base_storm_s, base_t; /* replay clock: storm time base_storm_s at scenario time
                                    base_t, advancing time_scale storm s per server s */
    double last_t; /* scenario time of the previous eval */
    bool have_last;
    double last_w[2]; /* mean wind of the previous eval [m/s] */
    double last_dir;  /* direction of the previous eval [rad, toward, from +x] */
    bool ramping;
    bool dial_on, dir_on;
    double dial_ms, dir_hold_deg;
};

/* The storm centre and figures at storm time ts [s] (interpolated, clamped to the track). */
void scenario_storm_at(const scenario *s, double ts, scenario_track_pt *out);
/* The Holland vortex of a storm state under the scenario's constants. */
void scenario_vortex_of(const scenario *s, const scenario_track_pt *c, holland_vortex *v);

#endif
