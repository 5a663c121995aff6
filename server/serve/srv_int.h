/* The server object shared by its parts: srv.c (life cycle), srv_control.c (control
 * messages, lws thread), srv_publish.c (snapshots, sim thread) and srv_loop.c (the
 * fixed-step loop, sim thread). Beside each field: which thread owns it. */
#ifndef GALE_SRV_INT_H
#define GALE_SRV_INT_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <time.h>

#include "mono.h"
#include "ctl.h"
#include "host_steal.h"
#include "kiosk_gate.h"
#include "metric.h"
#include "srv.h"
#include "srv_ops.h"
#include "scen_lib.h"
#include "srv_stream.h"
#include "view_select.h"
#include "weather_gust.h"
#include "wire.h"
#include "wall_group.h"

#define SRV_MAX_VIEWS 32   /* distinct client views encoded per snapshot; beyond them a
                              connection's view is ignored (it gets the whole scene). Each
                              costs the pool queue + 16 snapshots (SERVER.md "Views and
                              LOD") and n_trees bytes of selection */
#define SRV_VIEW_CELL_M 32.0f /* the view selection's grid cells (view_select.h): 25 trees
                                 a cell on the 2 km scene */
#define SRV_LOD_MODES 4    /* modes sent for trees beyond a view's lod_m */
#define SRV_WIND_EVERY 15  /* snapshots between coarse wind slices (2 per second at 30/s) */
#define SRV_WIND_FACTOR 4  /* grid cells per coarse cell along each axis */
/* Snapshots that carry a frame after it was last wanted (net_frames_wanted): a
 * connection's queue may hold snapshots encoded before it asked. */
#define SRV_WANT_HOLD 4
#define SRV_WANT_BITS (2 * NET_WANT_VIEWS_SHIFT) /* the bits of a net_frames_wanted_apart
                                                    mask */
#define SRV_LEAF_EVERY 3   /* snapshots between leaf frames (10 per second at 30/s): leaves
                              carry their spawn tick, so batching them costs no accuracy
                              and saves a WebSocket message per client per snapshot */
#define SRV_KEYFRAME_S 5.0 /* default seconds between periodic keyframes: a client that lost
                              state without noticing recovers within it, for one keyframe
                              (about 2.3 deltas' bytes, PROTOCOL.md Figures) per 150
                              snapshots at 30/s */
#define SRV_WEATHER_EVERY 10 /* snapshots between WEATHER frames (3 a second at 30/s; a
                                keyframe carries one too, PROTOCOL.md "WEATHER") */
#define SRV_KIOSK_IDLE_S 300.0 /* default: a kiosk's dial held this long without a command
                                  is released (a visitor who walked away leaves no one
                                  stuck at their setting) */
#define SRV_PLAYLIST_STEADY_S 120.0 /* a steady playlist entry plays this long before the
                                       next (a replay plays until it finishes) */
#define SRV_DIAL_KEPT UINT32_MAX /* dial_owner of a dial no connection holds (wind.keep) */
#define SRV_CLOSED_NAP_MS 50 /* the simulation loop's nap while closed (watchdog pings
                                 come 4 per WatchdogSec, 1.25 s at the unit's 5 s) */
#define SRV_OVERRUN_LOG_PER_S 5 /* overrun lines a second at most */
#define SRV_SOLVE_LOG_S 10 /* seconds between lines about solves out of budget */

/* One distinct view and the connections following it (lws thread, under view_lock). */
typedef struct srv_view {
    ctl_view v;
    uint32_t stream; /* 0 = slot free */
    int users;
} srv_view;

/* The view thread's encoder for one view slot. */
typedef struct srv_vsel {
    srv_stream enc;  /* enc.id: the stream the modes below were selected for; 0 none */
    uint8_t *modes;  /* owned [n_trees]: view_select of the slot's view */
} srv_vsel;

#define SRV_VJOBS 2 /* snapshots queued for the view thread: the one it encodes and the
                       newest posted since */
#define SRV_QBUFS 7 /* snapshots of quantised q (6.4 MB each at 100,000 trees): the last
                       two (the next snapshot's deltas read them), the one more the newest
                       queued snapshot reads, the three of the one the view thread encodes,
                       however old, and one the next snapshot's tick fills
                       (srv_views_next_buffer) */

/* A snapshot's view streams for the view thread: what the sim thread hands over. */
typedef struct srv_vjob {
    wire_header h;
    uint32_t seq;
    unsigned want;                       /* frames_to_encode's */
    int qi[3];                           /* qbuf of this snapshot, the one before, before that */
    uint8_t *extra[NET_SNAP_MAX_EXTRA];  /* owned [extra_cap]: the shared snapshot's extras */
    size_t extra_len[NET_SNAP_MAX_EXTRA];
    unsigned extra_key_only;
    bool gap;                            /* the view streams missed a snapshot before it */
} srv_vjob;

struct srv {
    srv_desc d;
    net_server *net;
    srv_ops *ops;                /* opening hours, kiosk reports, usage counters, /status */
    net_asset assets[SCENE_MAX_SPECIES];
    tick_sim *tick;
    tick_species ts[SCENE_MAX_SPECIES]; /* what the tick borrows */
    pthread_t thread;
    atomic_int stop;
    pthread_mutex_t scen_lock;   /* scenario: evaluated by the sim thread, dialled by kiosks */
    scenario *scen;              /* under scen_lock: the running one (the library's, or
                                    desc.scen); NULL: the steady inflow */
    /* scenarios (srv_scenarios.c), under scen_lock: the playlist and what a kiosk picked */
    scenario *playlist[SCENE_MAX_PLAYLIST]; /* the scene's playlist, resolved in the library */
    int n_playlist;              /* 0: no playlist (the head alone) */
    int pl_at;                   /* the playlist entry playing (or resumed) */
    scenario *head;              /* what a reset starts: playlist[0], else desc.scen */
    bool picked;                 /* a kiosk picked s->scen: the playlist waits */
    double entry_t_s;            /* server time the running scenario (re)started [s] */
    bool wx_reset_due;           /* the weather's gust window starts over (a jump, a
                                    switch, a restart) before the next sample */
    bool wx_reset_after_ramp;    /* under scen_lock: reset the gust window again when the
                                    ramp after a start or jump has reached the new wind */
    scenario *sim_scen;          /* sim thread: the scenario of its last eval (weather) */
    scenario *balls_scen;        /* sim thread: whose force balls the tick holds */
    pthread_mutex_t ctl_lock;    /* serialises control handling (srv_remote.c) */
    size_t snap_cap, extra_cap;  /* net_desc's, for a broker bridge */
    kiosk_gate kgate;            /* kiosk token checks and their per-address delays (lws
                                    thread; its counters are read by /metrics) */
    /* metrics: each owner's counters, and the registry /metrics renders (complete after
     * srv_create) */
    sim_metrics simm;
    srv_pub_counters pubm;
    metric_reg reg;
    /* snapshot encoding (sim thread only) */
    wire_scene wscene;
    uint8_t *tree_species;       /* owned [n_trees] */
    uint8_t *tree_modes;         /* owned [n_trees] */
    int16_t *qbuf[SRV_QBUFS];    /* owned [n_trees * stride] */
    int cur;                     /* the qbuf the next snapshot tick fills */
    int qlast[2];                /* the qbufs of the last snapshot and the one before */
    srv_stream shared;           /* the whole-scene stream (net_snap.stream 0) */
    int want_hold[SRV_WANT_BITS]; /* snapshots still to carry each wanted frame, by bit of
                                    a net_frames_wanted_apart mask (srv_publish.c
                                    frames_to_encode) */
    wire_lanes lanes;            /* the encoders' lanes on the scene's tick_threads */
    uint32_t seq;
    int ticks_per_snap;
    uint32_t key_every;          /* snapshots between periodic keyframes (desc.keyframe_s) */
    wire_leaf *leaves;           /* owned [WIRE_MAX_LEAVES] gathered since the last snapshot */
    uint32_t n_leaves;
    /* storm damage (sim thread; srv_damage.c): events gathered since the last snapshot, a
     * whole-state frame due to everyone after a heal, the state for keyframes */
    wire_damage *dmg_ev;         /* owned [WIRE_MAX_DAMAGE] */
    uint32_t n_dmg_ev;
    bool dmg_full_due;
    unsigned long long dmg_heals;/* heals seen (damage_counts.heals) */
    wire_damage *dmg_state;      /* owned [WIRE_MAX_DAMAGE] */
    uint8_t *forest_state;       /* owned [n_trees]: the FOREST frame's state bytes */
    wire_forest_fall *forest_fall; /* owned [n_trees] */
    /* the welcome's scene part (srv_welcome.c), under ctl_lock: what it is built from,
     * and the text built once per scene that every connection's welcome shares */
    ctl_species *wspecies;       /* owned [n_species] */
    ctl_instance *winst;         /* owned [n_trees] */
    ctl_scenario_info *wscen;    /* owned [n_wscen]: the library, as a kiosk chooses */
    uint32_t n_wscen;
    net_shared *wbody;           /* one reference: the scene part's text; NULL before the
                                    first build */
    bool wstale;                 /* the scene changed since wbody was built */
    unsigned long long wbuilds;  /* builds of wbody */
    double wbuild_ms;            /* the last build's time [ms] */
    /* float history for tests */
    pthread_mutex_t hist_lock;
    float *hist;                 /* owned [history][n_trees * stride] */
    uint32_t *hist_seq;          /* owned [history] */
    int stride;
    /* coarse wind slices (sim thread): a WIND frame every SRV_WIND_EVERY snapshots */
    float *coarse;               /* owned [coarse_cap] */
    int coarse_cap;
    int8_t *slice;               /* owned [WIRE_MAX_WIND_SIDE² × 3] */
    /* per-client views: up to SRV_MAX_VIEWS distinct views, each its own snapshot stream
     * (net.h net_snap.stream), encoded once per snapshot and shared by its connections */
    pthread_mutex_t view_lock;   /* guards views (lws thread joins/leaves, sim thread reads) */
    srv_view views[SRV_MAX_VIEWS];
    uint32_t next_stream;
    srv_vsel vsel[SRV_MAX_VIEWS]; /* view thread: the encoder of each slot's stream */
    /* the view thread (srv_views.c): encodes each snapshot's view streams beside the ticks */
    pthread_t vthread;
    bool vthread_on;
    pthread_mutex_t vlock;       /* guards the fields below */
    pthread_cond_t vpost;        /* a job posted, or vstop */
    pthread_cond_t vdone;        /* a job done */
    srv_vjob vjob[SRV_VJOBS];    /* a ring: vjob[vhead] the oldest queued (the view
                                    thread's while it encodes it), vn_jobs queued */
    int vhead, vn_jobs;
    bool vgap;                   /* the view streams missed a snapshot since the last job
                                    queued */
    bool vstop;
    wire_lanes vlanes;           /* the view thread's lanes, on its own team */
    float *tree_pos;             /* owned [n_trees * 3] tree bases for view_select */
    view_grid vgrid;             /* tree_pos bucketed for view_select_grid */
    float view_margin_m;         /* a tree counts as in view within this of the region */
    /* weather (sim thread, srv_weather.c): the last scenario state and its 3-s gust */
    scenario_state wx_state;
    bool wx_have;
    weather_gust wx_gust;
    _Atomic float wx_sustained_pub; /* wx_state's sustained wind and dial, for /metrics */
    _Atomic bool wx_dial_pub;
    wind_inflow man_inflow;      /* under scen_lock: the inflow when there is no scenario
                                    (the scene's, or the last kiosk command's) */
    uint32_t dial_owner;         /* under scen_lock: connection whose dial holds the wind
                                    (0 none, SRV_DIAL_KEPT a script's): released when it
                                    leaves or idles out */
    double dial_last_s;          /* under scen_lock: its last command [s, mono_s] */
    /* log rate limits (sim thread) */
    time_t olog_sec;             /* overruns: the second being counted */
    int olog_n;                  /*           lines in it */
    host_steal_window steal;     /* the host's steal of the last 1-2 s, for overrun lines */
    wall_groups *walls;          /* display walls' groups (lws thread, srv_control.c) */
    double slog_next_s;          /* solves out of budget: next line no earlier [s, mono_s] */
    unsigned long long slog_n;   /* solves out of budget since that line */
};

/* srv_remote.c: net_desc.control and net_desc.closed, srv_on_control and srv_on_closed
 * under ctl_lock (the lws thread and a broker bridge's thread both call them). */
int srv_control_serial(void *user, net_peer *p, const char *text, size_t len, char **reply,
                       size_t *reply_len, char *why, size_t why_cap);
void srv_closed_serial(void *user, const net_peer *p);

/* srv_welcome.c, under s->ctl_lock (or before the server runs). srv_welcome_build encodes
 * the welcome's scene part from wspecies, winst, wscen and the scene's obstacles into
 * s->wbody, 0 or an error; srv_welcome_stale says they changed (a new scene), so the next
 * hello's welcome is built anew; connections sending the old one finish it. srv_welcome
 * answers connection p's hello: 0 with *reply (malloc'd, *len bytes) and, where
 * p->shared_ok, *tail (one reference to the shared scene part, which the message goes on
 * with), else the whole text in *reply; or WIRE_CLOSE_BAD_FIELD with why. */
int srv_welcome_build(srv *s, gale_err *err);
void srv_welcome_stale(srv *s);
int srv_welcome(srv *s, const net_peer *p, int ctl_role, char **reply, size_t *len,
                net_shared **tail, char *why, size_t why_cap);
void srv_welcome_fini(srv *s);

/* srv_control.c, lws thread: net_desc.control and net_desc.closed. */
int srv_on_control(void *user, net_peer *p, const char *text, size_t len, char **reply,
                   size_t *reply_len, char *why, size_t why_cap);
void srv_on_closed(void *user, const net_peer *p);
/* wall_group.h's send: text to one connection (lws thread). */
void srv_wall_send(void *user, uint32_t conn, const char *text, size_t len);

/* srv_publish.c, sim thread: snapshot s->seq + 1 of tick `tick` from s->qbuf[s->cur]
 * (which tick_step just filled) to the shared stream, the view streams' share to the view
 * thread; then rotates the buffers. */
void srv_publish(srv *s, uint32_t tick);

/* srv_views.c: the view thread. srv_views_start starts it (srv_run), srv_views_stop ends
 * it after its job (idempotent). Sim thread: srv_views_post queues snapshot seq for it
 * (header h, the shared snapshot p for its extras, q in qbuf qi[0..2], frames want); when
 * SRV_VJOBS are queued it takes the place of the newest, not yet started, which the
 * streams miss (they then send keyframes);
 * srv_views_gap marks one for a snapshot not published (and drops a snapshot waiting:
 * the newest queued is always the last posted); srv_views_next_buffer gives the
 * qbuf the next snapshot tick may fill: neither of s->qlast nor one a queued snapshot
 * reads. */
int srv_views_start(srv *s, gale_err *err);
void srv_views_stop(srv *s);
void srv_views_post(srv *s, const wire_header *h, uint32_t seq, unsigned want,
                    const net_snap *p, const int qi[3]);
void srv_views_gap(srv *s);
int srv_views_next_buffer(srv *s);
/* The publisher's rows (gale_leaves_shed_total, gale_view_*) into r. */
int srv_publish_register(srv *s, metric_reg *r, gale_err *err);

/* The extra messages of a snapshot (net_snap.extra), by what they carry. */
enum srv_extra {
    SRV_EXTRA_LEAVES = 0,       /* LEAVES, every SRV_LEAF_EVERY snapshots */
    SRV_EXTRA_WIND = 1,         /* WIND, every SRV_WIND_EVERY snapshots */
    SRV_EXTRA_DAMAGE = 2,       /* DAMAGE events of the snapshot */
    SRV_EXTRA_DAMAGE_STATE = 3, /* DAMAGE: the whole state, with keyframes only */
    SRV_EXTRA_WEATHER = 4,      /* WEATHER: every SRV_WEATHER_EVERY snapshots and keyframes */
    SRV_EXTRA_FOREST = 5,       /* FOREST: the trees' whole state, with keyframes and with the
                                   whole state of extra[SRV_EXTRA_DAMAGE] */
};
_Static_assert(SRV_EXTRA_FOREST < NET_SNAP_MAX_EXTRA, "net_snap holds every extra");

/* srv_damage.c, sim thread: gathers the damage events of the last tick (a heal makes the
 * next snapshot carry the whole state to everyone). */
void srv_damage_gather(srv *s);
/* Encodes the damage frames of this snapshot into p: extra[SRV_EXTRA_DAMAGE] the events (or
 * the whole state's branches after a heal), extra[SRV_EXTRA_DAMAGE_STATE] the whole state's
 * branches, key-only, extra[SRV_EXTRA_FOREST] its trees (key-only but after a heal). */
int srv_damage_encode(srv *s, const wire_header *h, net_snap *p, gale_err *e);

/* srv_weather.c, sim thread: a tick's scenario state (NULL: no scenario, the steady
 * inflow) into the weather; the weather as WEATHER frame extra[SRV_EXTRA_WEATHER] of p; the frame's fields. */
void srv_weather_sample(srv *s, uint32_t tick, double dt_s, const scenario_state *st);
int srv_weather_encode(srv *s, const wire_header *h, net_snap *p, gale_err *e);
void srv_weather_fill(const srv *s, wire_weather *w);
/* /metrics rows of the weather: gale_wind_sustained_meters_per_second, gale_wind_dial. */
int srv_weather_register(srv *s, metric_reg *r, gale_err *err);

/* srv_control.c: drops the dial that holds the wind (the scenario's override, or the
 * manual inflow back to the scene's); s->scen_lock held. why names it in the log. */
void srv_release_dial_locked(srv *s, const char *why);

/* srv_scenarios.c, s->scen_lock held (t_s: server time [s]). The library's entry or the
 * running scenario named `name`, restarted from its start (forest healed, dial dropped,
 * the playlist waiting); 0, or WIRE_CLOSE_BAD_FIELD with the valid names in why. */
int srv_scen_pick_locked(srv *s, const char *name, double t_s, char *why, size_t why_cap);
/* Back to the playlist (a kiosk's "" or its idle time): the entry that was playing,
 * restarted; nothing when no kiosk picked a scenario. */
void srv_playlist_resume_locked(srv *s, double t_s);
/* A reset: the forest healed, the dial dropped, the head from its configured start. */
void srv_reset_locked(srv *s, double t_s);
/* Sim thread, after scenario_eval gave st: the next playlist entry when this one is done
 * (a replay finished, a steady entry played SRV_PLAYLIST_STEADY_S); true when it switched
 * (evaluate again). */
bool srv_playlist_poll_locked(srv *s, double t_s, const scenario_state *st);
/* The running scenario jumped (a seek): the weather's 3-s gust window starts over. */
void srv_weather_jumped_locked(srv *s);
/* srv_create: the playlist's names in desc.lib and the head; 0 or an error naming them. */
int srv_scenarios_init(srv *s, gale_err *err);

/* srv_loop.c: the simulation thread (arg: the srv), until s->stop. */
void *srv_loop(void *arg);

#endif
