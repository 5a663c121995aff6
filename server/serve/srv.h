/* The running server: a simulation thread (tick.h at tick_hz, a snapshot every
 * tick_hz/snapshot_hz ticks, quantised and encoded once per stream with protocol/wire.h)
 * handing frames to the lws service thread (net.h), and the control protocol (ctl.h:
 * hello, welcome, views, kiosk wind commands, resync, ping). server/SERVER.md "Loop",
 * "Views and LOD" and "Serving"; protocol/PROTOCOL.md. */
#ifndef GALE_SRV_H
#define GALE_SRV_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "net.h"
#include "ops_hours.h"
#include "scen_lib.h"
#include "scenario.h"
#include "scene.h"
#include "sim_metrics.h"
#include "tick.h"

/* One species as served: its modal data, quantisation steps and asset file. */
typedef struct srv_species {
    tick_species modal;        /* arrays borrowed for the server's life */
    const float *qstep;        /* [modal.n_modes] quantisation step per mode (quant_steps_derive) */
    char hash[17];             /* content hash of the asset file, 16 hex digits; "" = none */
    const uint8_t *asset_bytes; /* borrowed; NULL = not served */
    size_t asset_len;
} srv_species;

typedef struct srv_desc {
    const scene *sc;              /* borrowed for the server's life */
    const srv_species *species;   /* [sc->n_species], borrowed likewise */
    scenario *scen;               /* borrowed; NULL → the playlist's first (sc->playlist),
                                     else the scene's steady inflow */
    scen_lib *lib;                /* borrowed: the scenarios a kiosk may switch to and the
                                     playlist's (SERVER.md "Scenarios"); NULL → none */
    const tick_wind *wind;        /* borrowed; NULL → log-law profile, no grid */
    int port;                     /* 0 → 8080, -1 → ephemeral */
    const char *iface;            /* NULL → all interfaces */
    int queue_frames;             /* per-connection snapshot queue; 0 → 8 */
    int stall_ms;                 /* a reader taking nothing this long is closed (4008);
                                     0 → NET_STALL_MS (net_desc.stall_ms) */
    int max_clients;              /* 0 → net default (net_desc.max_clients) */
    int hello_timeout_ms;         /* 0 → net default, < 0 → never (net_desc.hello_timeout_ms) */
    int sndbuf;                   /* 0 → net default */
    int quiet;                    /* 1: no start-up lines */
    void (*published)(void *user, const net_snap *snap); /* net_desc.published; NULL none */
    void *published_user;
    bool separate_extras;         /* leaves, wind, damage and weather as messages of their
                                     own, not inside the state's BUNDLE
                                     (net_desc.separate_extras) */
    int history;                  /* snapshots of float q kept for srv_history_q; 0 → none */
    double kiosk_idle_s;          /* a kiosk's dial is released this long after its last
                                     command [s]; 0 → SRV_KIOSK_IDLE_S, < 0 → never */
    double keyframe_s;            /* server time between periodic keyframes on every stream;
                                     0 → SRV_KEYFRAME_S (PROTOCOL.md "Sequence and gaps") */
    ops_hours hours;              /* opening hours (.set false: always open; SERVER.md
                                     "Opening hours") */
    const char *state_file;       /* the usage counters' file; NULL: not kept (SERVER.md
                                     "Usage counters") */
    const char *tls_cert;         /* PEM files: serve https and wss; NULL → plain */
    const char *tls_key;
} srv_desc;

/* The snapshot publisher's counters (the sim and view threads write, any thread reads). */
typedef struct srv_pub_counters {
    atomic_ullong leaves_shed;    /* leaf seeds gathered for LEAVES frames */
    atomic_ullong view_snapshots; /* view-stream snapshots encoded and published */
    atomic_ullong view_encode_ns; /* time spent encoding them [ns] */
    atomic_ullong view_missed;    /* snapshots the view streams skipped: the view thread was
                                     still busy with an earlier one */
    atomic_ullong view_idle;      /* view-stream snapshots not encoded: every reader of the
                                     stream a slow one, none due (net_stream_due) */
} srv_pub_counters;

typedef struct srv srv;

/* Builds the simulation and starts listening (not yet serving); NULL with err filled. */
srv *srv_create(const srv_desc *d, gale_err *err);
/* Runs the simulation thread and serves on the calling thread until srv_stop; then
 * closes every client with 1001 (each socket within NET_CLOSE_BOUND_MS) and returns 0. */
int srv_run(srv *s);
/* Any thread or a signal handler: ends srv_run. */
void srv_stop(srv *s);
/* NULL is a no-op. */
void srv_destroy(srv *s);

/* For a broker bridge (server/relay/): a relayed connection's control message and close,
 * handled as the lws thread handles its own (serialised with it, any thread); the
 * assets served; the snapshot buffer sizes (net_desc.snap_cap, extra_cap). */
int srv_remote_control(srv *s, net_peer *p, const char *text, size_t len, char **reply,
                       size_t *reply_len, char *why, size_t why_cap);
void srv_remote_closed(srv *s, const net_peer *p);
const net_asset *srv_assets(const srv *s, int *n);
void srv_snap_caps(const srv *s, size_t *snap_cap, size_t *extra_cap, int *max_streams);
/* The view rule's parameters, for a relay that selects its clients' views itself
 * (server/SERVER.md "Relays"): what view_select_grid reads besides the view and each
 * tree's modes, and the view streams' periodic keyframe. tree_pos is borrowed for the
 * server's life. */
typedef struct srv_view_rule {
    uint32_t n_trees;
    const float *tree_pos; /* [n_trees * 3] tree bases */
    float margin_m;        /* a tree counts as in view within this of the region */
    float cell_m;          /* the selection grid's cell */
    uint32_t lod_modes;    /* modes sent for a tree past the view's lod_m */
    uint32_t key_every;    /* snapshots between a stream's periodic keyframes */
    uint32_t max_modes;    /* the most modes of any species */
} srv_view_rule;
srv_view_rule srv_view_rule_get(const srv *s);

int srv_port(const srv *s);
/* The connection limits the network settled on (net_get_limits). */
net_limits srv_net_limits(const srv *s);
/* The counters behind /metrics, by owner: the network's, the simulation's, the
 * publisher's. Valid until srv_destroy; readable from any thread. */
net_metrics *srv_metrics(srv *s);
sim_metrics *srv_sim_metrics(srv *s);
srv_pub_counters *srv_pub_metrics(srv *s);
/* Float q (before quantisation) of tree t at snapshot seq, kept when desc.history > 0
 * (tests compare decoded frames with it): copies up to cap modes and returns the count,
 * or -1 when that snapshot is no longer (or not yet) held. Thread-safe. */
int srv_history_q(srv *s, uint32_t seq, int t, float *q, int cap);
/* The quantisation step of mode m of tree t's species. */
float srv_qstep(const srv *s, int t, int m);
/* Heals the forest before the next tick (kiosk reset, scenario restart): every client
 * then gets the whole, empty damage state. Any thread. */
void srv_heal(srv *s);

#endif
