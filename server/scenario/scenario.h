/* Wind scenarios: what drives the wind grid's borders over time. A steady or gusty wind
 * (mean speed, direction, log-law profile, Ornstein–Uhlenbeck gusts, Gaussian force balls;
 * Oliapuram & Kumar 2010 section 2), or a hurricane replay: a Holland (1980) vortex moving
 * along a track past the scene, reduced to the surface (PHYSICS.md "Hurricane scenario"). */
#ifndef GALE_SCENARIO_H
#define GALE_SCENARIO_H

#include <stdbool.h>
#include <stddef.h>

#include "cfg.h"
#include "err.h"
#include "saffir.h"
#include "wind.h"

typedef struct scenario scenario;

typedef enum scenario_kind {
    SCENARIO_STEADY = 0,    /* mean wind + gusts + balls */
    SCENARIO_HURRICANE = 1, /* Holland vortex on a track, replayed with time compression */
} scenario_kind;

/* Everything the server applies and the HUD shows at one instant. Scene frame: x east,
 * y north, z up. All speeds at 10 m above ground. */
typedef struct scenario_state {
    wind_inflow inflow;          /* for wind_set_inflow: mean (sustained) speed + this gust */
    double t_s;                  /* scenario time of this state: server time − start [s] */
    double storm_min;            /* scenario clock: storm time from the track's reference [min];
                                    for steady scenarios the scenario time in minutes */
    char clock_utc[24];          /* "1992-08-24 09:24Z" for a dated replay, "" otherwise */
    double sustained_ms;         /* 1-minute sustained wind at the scene [m/s] */
    double gust_ms;              /* instantaneous speed, mean + gust vector [m/s] */
    double dir_from_deg;         /* meteorological: where the wind comes FROM, clockwise
                                    from north [0, 360) */
    saffir_class category;       /* class of sustained_ms */
    const char *category_name;   /* saffir_name(category), static */
    int beaufort;                /* Beaufort number of sustained_ms, 0..12 */
    int storm_category;          /* class of the storm's own Vmax on the track; -1 no storm */
    double pressure_hpa;         /* sea-level pressure at the scene (Holland p(r)) [hPa] */
    double distance_km;          /* scene to storm centre [km]; -1 when there is no storm */
    double bearing_deg;          /* direction from the scene to the storm centre, clockwise
                                    from north [0, 360); 0 when there is no storm */
    double central_hpa;          /* the storm's central pressure [hPa]; 0 when no storm */
    long long utc_min;           /* dated replay: storm time, minutes since the epoch (UTC) */
    bool has_clock;              /* utc_min and utc_offset_min are valid */
    int utc_offset_min;          /* the site's local time = UTC + this [min] */
    double replay_speed;         /* replay: storm seconds per server second; 0 otherwise */
    double replay_pos_s;         /* replay: server seconds from its window's start at the
                                    present speed; 0 otherwise */
    double turbulence_intensity; /* I_u of the gust process, σ_u / U */
    bool override_active;        /* a kiosk dial holds the wind */
    bool finished;               /* a replay reached its end and holds its last state */
    bool paused;                 /* a replay whose storm clock a kiosk holds */
} scenario_state;

/* Builds a scenario from a validated JSON object: obj (NULL → doc->root) at key path
 * `path` ("" at the root, "scene.wind" inside a scene) names errors as
 * "<doc name>: <path.key>: <what>: expected ..., got ...". The doc is borrowed for this
 * call only. Returns NULL on failure with err filled. */
scenario *scenario_create(const cfg_doc *doc, const cJSON *obj, const char *path, gale_err *err);
/* Reads and builds a scenario file; I/O, syntax and value errors name the file. */
scenario *scenario_load(const char *file, gale_err *err);
/* Builds a scenario from JSON text (len bytes) named `name` in messages. */
scenario *scenario_parse(const char *name, const char *text, size_t len, gale_err *err);
/* Frees the scenario. NULL is a no-op. */
void scenario_destroy(scenario *s);

/* The scenario's "name" (static for its lifetime). */
const char *scenario_name(const scenario *s);
scenario_kind scenario_get_kind(const scenario *s);
/* A steady scenario's mean 1-minute sustained wind at 10 m [m/s]; 0 for a replay. */
double scenario_steady_ms(const scenario *s);
/* Length of a replay in server seconds (storm span / time_scale); 0 = endless. */
double scenario_duration_s(const scenario *s);

/* The state at server time t_s [s]. The scenario starts at server time 0, or at the time
 * given to scenario_restart. Deterministic: the same seed and the same sequence of t_s give
 * the same states. The gust process advances by t_s − (previous t_s); an earlier t_s than
 * the previous call restarts the gust process from its seed. Does not allocate. */
void scenario_eval(scenario *s, double t_s, scenario_state *out);
/* scenario_eval, then wind_set_inflow(w, &out->inflow) and wind_add_ball for each of the
 * scenario's force balls. Call once before each wind_step. out may be NULL. */
void scenario_apply(scenario *s, wind_grid *w, double t_s, scenario_state *out);

/* The scenario's force balls (*out borrowed for the scenario's lifetime); returns their
 * count. For callers that set the inflow themselves and add the balls before each step. */
int scenario_balls(const scenario *s, const wind_ball **out);

/* Kiosk controls. Each takes effect at the next eval and moves the wind there at a bounded
 * rate ("dial_rate_ms2" in the file, default 4 m/s per second) so trees never see a jump.
 * Dial: hold this 1-minute sustained wind [m/s], in [0, 90], until cleared. */
int scenario_set_dial(scenario *s, double sustained_ms, gale_err *err);
/* Hold the representative wind of a Saffir–Simpson class (saffir_representative_ms). */
int scenario_set_category(scenario *s, saffir_class c, gale_err *err);
/* Hold the direction the wind comes from [deg clockwise from north], in [0, 360]. */
int scenario_set_direction(scenario *s, double from_deg, gale_err *err);
/* Drops the dial and direction holds; the scripted wind resumes (ramped). */
void scenario_clear_override(scenario *s);
/* Replay controls (a hurricane scenario; GALE_E_STATE for a steady one), from server time
 * t_s on: with has_at, jump to storm minute at_min (clamped to the replayed window, so a
 * replay near landfall needs no edited copy of the file); with has_speed, run at speed
 * storm seconds per server second, in [1, 10000], from where the replay is. */
int scenario_replay_set(scenario *s, double t_s, bool has_at, double at_min, bool has_speed,
                        double speed, gale_err *err);
/* Holds (paused true) or resumes a replay's storm clock from server time t_s on; a jump
 * while held moves the held minute. GALE_E_STATE for a steady scenario. */
int scenario_replay_pause(scenario *s, double t_s, bool paused, gale_err *err);
/* Restarts the scripted timeline (a replay from its first minute, or the start
 * scenario_set_start gave, running, at its configured speed) and the gust process at
 * server time t_s. Overrides are kept. */
void scenario_restart(scenario *s, double t_s);
/* The start a restart replays from (gale-server --start-min / --replay-speed): storm
 * minute at_min (clamped to the window) and speed in [1, 10000] storm seconds per server
 * second; then restarts at server time t_s. GALE_E_STATE for a steady scenario. */
int scenario_set_start(scenario *s, double t_s, bool has_at, double at_min, bool has_speed,
                       double speed, gale_err *err);

#endif
