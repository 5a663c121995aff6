/* gale-client's state, shared by its files: main.c (args, loop, teardown), client_stream.c
 * (network events), client_scene.c (scene setup from a welcome), client_assets.c (asset
 * fetch through the disk cache), client_input.c (keys and mouse), client_kiosk.c (the wind
 * dial) and client_frame.c (one frame: playout, camera, render, HUD). */
#ifndef GALE_CLIENT_H
#define GALE_CLIENT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "asset.h"
#include "asset_cache.h"
#include "camera.h"
#include "camera_preset.h"
#include "caption.h"
#include "attract.h"
#include "cli_net.h"
#include "ctl.h"
#include "damage_view.h"
#include "err.h"
#include "hud.h"
#include "jitter.h"
#include "lang.h"
#include "kiosk_ui.h"
#include "render.h"
#include "governor.h"
#include "hold.h"

struct GLFWwindow;

/* Species one session may load: what a welcome may name; a welcome naming more is
 * refused (client_stream_on_welcome), and the renderer holds them all. */
#define CLIENT_MAX_SPECIES WIRE_MAX_SPECIES
_Static_assert(CLIENT_MAX_SPECIES <= RENDER_MAX_SPECIES,
               "gale-client: every species a session loads must fit in gale_render");

/* Leaf seeds a frame starts falling at most: a client drawing a frame a second receives
 * a second of LEAVES frames at once (up to 41 000 seeds in a storm, each with its landing
 * time to find), more than its falling-leaf ring shows; past the budget seeds are left
 * out, so the frame's cost stays bounded however slowly it draws. */
#define CLIENT_LEAVES_PER_FRAME 4096u
/* The jitter buffer's snapshots: 64 on a small scene; on a large one as many as fit this
 * budget (100,000 trees of 32 modes: 12.8 MB a snapshot, 20 held, 0.67 s at 30 Hz, well
 * past the playout delay), never fewer than 4. */
/* The governor's frame time in a window: 30 frames a second. */
#define CLIENT_FRAME_MS (1000.0 / 30.0)

#define CLIENT_JITTER_SNAPSHOTS 64u
#define CLIENT_JITTER_BYTES (256u << 20)
#define CLIENT_JITTER_MIN_SNAPSHOTS 4u

typedef struct client_args {
    const char *url;
    const char *tls_ca;     /* --tls-ca: PEM certificates to trust for wss (NULL: system) */
    int role; /* enum ctl_role */
    int width, height;
    bool headless;
    int frames;             /* headless: frames to draw once state arrives */
    const char *screenshot; /* headless: PNG of the last frame */
    int shot_every;         /* --screenshot-every K: headless, every Kth frame too; 0 none */
    const char *token;      /* kiosk: --token, or token_buf from --token-file */
    char token_buf[CTL_MAX_TOKEN];
    double delay_s;         /* playout delay */
    double wait_s;          /* headless: give up after this long without state */
    double max_fps;         /* --max-fps: at most this many frames a second; 0 = no limit */
    int tile[4];            /* wall-tile: col, row, cols, rows */
    float bezel;            /* wall-tile: hidden strip / tile width */
    const char *cache_dir;
    /* wall-tile from a wall file (client_wall.c) */
    const char *wall_path;  /* --wall FILE */
    const char *tile_name;  /* --tile NAME with --wall */
    bool size_set;          /* --size given (else the tile's px) */
    bool list_tiles;        /* --list-tiles: print the file's tile names and exit */
    bool swap_lock;         /* --swap-lock: present frame N on the group's "swap N" */
    float rate_hz;          /* --rate: the wall group's frame rate (first tile's counts) */
    int budget_ms;          /* --budget: longest wait for the group's swap */
    const char *frame_log;  /* --frame-log FILE: "mono_us server_us_rendered frame_no" */
    int camera_preset;      /* enum camera_preset; -1 = fitted to the scene (camera_preset.h) */
    int lang;               /* --lang: the operator's language (lang.h), where idle returns */
    double attract_s;       /* kiosk: idle seconds before attract mode; 0 = default 90 */
    int storm_fx;           /* enum storm_fx_quality: --storm-fx, default low */
    bool view_all;          /* --view all: no view sent, the whole scene streamed */
    uint32_t max_trees;     /* --max-trees: trees held at most (a reduced view past it); 0 none */
    double governor_ms;     /* --governor: frame-time target [ms]; 0 off; < 0 the default */
    bool fullscreen;        /* --fullscreen: open on the primary monitor (F11 toggles) */
    const char *touch;      /* --touch SPEC: headless kiosk touches (client_kiosk.c) */
    /* --fall-shots T,T,...: headless pictures T s after a fall caught live
       (client_fall_shots.c), ascending */
    double fall_shot_s[8];
    int n_fall_shots;
    /* sound (client_audio.c) */
    const char *audio_out;    /* --audio-out F.wav: headless, what the speakers would play */
    const char *audio_device; /* --audio-device PCM: an ALSA PCM name; NULL "default" */
    bool sound_off;           /* --sound off */
    float volume_db;          /* --volume DB: the master gain */
    float volume_max_dbfs;    /* --volume-max DBFS: the limiter's ceiling */
    bool quiet;               /* --quiet: the quiet preset (sensory-friendly hours) */
} client_args;

/* One scripted touch of --touch (headless kiosk tests and screenshots). */
typedef struct client_touch {
    int phase; /* enum kiosk_ui_phase; -1 = wait one frame */
    float x, y; /* framebuffer pixels */
} client_touch;
#define CLIENT_MAX_TOUCHES 64

/* This tile's part of its wall group (client_wall_group.c, PROTOCOL.md "Wall groups"). */
typedef struct client_wall_group {
    bool have_sync;          /* the group's clock is known */
    ctl_wall_sync sync;
    uint32_t joined_connects; /* cli_net connects count the join was sent on; 0 none */
    uint32_t frame;          /* frame being drawn */
    bool have_frame;
    uint32_t last_frame;     /* last frame presented */
    bool have_last;
    uint32_t swap;           /* highest "swap N" heard */
    bool have_swap;
    bool have_camera;        /* a wall_camera waits for its frame */
    ctl_wall_camera camera;
    bool camera_from_server; /* the server's camera rules (no tour) */
    double render_t;         /* server time [s] the frame shows */
    int64_t render_us;       /* the same in the group's integer clock [us] */
    FILE *log;               /* --frame-log */
    /* the operator (a kiosk with --wall) */
    double next_camera_s;    /* no wall_camera before this [s, mono_s] */
    bool sent_camera;
    ctl_wall_camera last_sent;
    uint64_t presented, skipped, swap_timeouts;
} client_wall_group;

typedef struct client_species {
    char hash[17];
    int render_id;  /* id in gale_render, -1 until loaded */
    float height_m; /* the asset's height at unit scale */
} client_species;

/* A scene with more trees than this client holds (client_hold.c, CLIENT.md "Reduced
 * view"): the welcome's trees whole here, those held in client.w_instances. */
typedef struct client_hold {
    ctl_instance *scene;  /* owned: [n_scene] the welcome's instances */
    uint32_t n_scene;
    bool reduced;         /* fewer trees held than the scene has */
    uint32_t *held;       /* owned, reduced: [circle.n_held] scene index of each held tree,
                             ascending */
    int32_t *slot;        /* owned, reduced: [n_scene] held index of each tree, -1 not held */
    hold_circle circle;   /* reduced: the trees held about their point */
    double centre[2];     /* [m] the point held about, kept while the scene is the same */
    bool have_centre;
    uint32_t limit;       /* trees held at most */
    char why[256];        /* what sets the limit */
    uint32_t nomem_limit; /* after an allocation failed: half the trees it was for; 0 none */
    char nomem_why[200];
    float view_radius_m;  /* reduced: the circle view's radius (hold_view_radius_m) */
    bool said;            /* the reduced view is told on stderr (once a scene) */
    wire_damage *damage;  /* owned, reduced: [damage_cap] a frame's events, held trees */
    uint32_t damage_cap;  /* WIRE_MAX_DAMAGE, or a FOREST's events of n_scene trees */
    uint32_t trees_sent;  /* trees the last state frame carried (modes > 0) */
} client_hold;

/* The view this client last asked for (PROTOCOL.md "view"): the cone around its frustum. */
typedef struct client_view {
    bool sent;         /* on the current connection */
    uint32_t connects; /* cli_net_stats.connects when it was sent */
    double sent_s;
    float eye[3], axis[3], fov_deg, far_m, lod_m;
    uint64_t n_sent; /* views sent this run */
} client_view;

typedef struct client {
    client_args a;
    cli_net *net;
    render *r;
    hud *hud;
    asset_cache *cache;
    jitter *jit;
    camera cam;
    struct wall *wall; /* owned: the wall file of --wall, NULL without */
    int wall_tile;     /* this tile's index in it */
    bool hud_on;       /* this client draws the HUD (client_wall_hud_px) */
    float hud_px;      /* the HUD font's em [px] */
    client_wall_group wg;
    bool camera_set; /* the camera was fitted to a scene (once per run; R refits it) */

    /* scene of the last welcome (owned copies) */
    bool scene_pending, scene_ready;
    ctl_welcome w;             /* arrays owned below */
    ctl_species *w_species;    /* owned */
    ctl_instance *w_instances; /* owned: the trees held (all but in a reduced view) */
    float *w_boxes;            /* owned: [6 w.n_obstacles] house boxes, min xyz, max xyz */
    client_species loaded[CLIENT_MAX_SPECIES];
    uint32_t n_loaded;
    int species_id[CLIENT_MAX_SPECIES]; /* welcome index → render id */
    uint32_t stride, n_values;
    float *snap; /* owned: [n_values] scratch for one decoded snapshot */

    /* coarse wind of the last WIND frame */
    float *wind_v; /* owned: [WIRE_MAX_WIND_SIDE² × 3] */
    bool have_wind;
    float wind_ms;
    float kiosk_speed_ms; /* kiosk dial */
    /* the server's weather (last WEATHER frame): what the HUD names */
    wire_weather wx;
    bool have_wx;
    int lang;               /* the language shown now: a kiosk visitor may choose another */
    /* the HUD text of the last frame drawn (headless runs print it) */
    char hud_text[HUD_MAX_LINES][HUD_LINE_CHARS];
    int hud_lines;

    /* storm damage of the scene (DAMAGE frames), kept from the welcome on so the whole
     * state after the first keyframe is not lost while assets load */
    damage_view dmg;
    struct client_damage_fx *dfx; /* owned: falls and debris under way (client_damage.c) */

    bool got_state;
    bool closed;              /* the exhibit's hours keep it closed (client_closed.c) */
    char opens_at[9];         /* "HH:MM" it opens at; "" unknown */
    double state_t0_s;        /* when the first state arrived */
    uint64_t state_bytes0;    /* bytes received by then */
    bool live_since_welcome;  /* state taken since the last welcome */
    uint64_t frames_mismatch; /* state frames whose tree count disagreed with the scene */
    /* the render's figures for the headless summary: the last frame's counters and every
       frame's culling and LOD time [ms] (the first CLIENT_CULL_SAMPLES) */
    render_stats last_stats;
#define CLIENT_CULL_SAMPLES 4096
    float cull_ms[CLIENT_CULL_SAMPLES];
    uint32_t n_cull;
    uint64_t leaves_bad;
    uint32_t leaves_frame;    /* leaf seeds taken since the frame began (CLIENT_LEAVES_PER_FRAME) */
    uint64_t leaves_thinned;  /* seeds left out past that budget */
    double fps, last_frame_s;
    double cursor[2];
    int drag; /* 0 none, 1 orbit, 2 pan */
    bool want_screenshot;
    bool fullscreen;
    double tour_t0_s; /* --camera tour, attract mode: when the tour began */
    attract attract;  /* kiosk: attract mode after idle (attract.h) */
    kiosk_ui kiosk;   /* kiosk: the touch panel (kiosk_ui.h) */
    double kiosk_drag_sent_s; /* when a dragged dial last sent its value */
    client_touch touches[CLIENT_MAX_TOUCHES]; /* --touch, played one a frame */
    int fall_shot_next;  /* --fall-shots: the next one to write */
    bool fall_framed;    /* --fall-shots: the camera looks at the fall of fall_tree */
    uint32_t fall_tree;
    int n_touches, next_touch;
    bool touch_woke; /* the scripted touch down that woke the kiosk: its lift is no control */
    int win_pos[2], win_size[2];
    client_view view; /* the view last sent (client_view.c) */
    client_hold hold; /* the trees held of the welcome's (client_hold.c) */
    governor gov;     /* the detail a frame-time budget affords (--governor) */
    struct client_audio *aud; /* owned: the sound, NULL when off (client_audio.c) */
} client;

/* ---- client_audio.c: the wind's sound ---- */

/* Starts the sound the args ask for: the device (or the null device, logged), or headless
 * the WAV of --audio-out; nothing headless without it, nor with --sound off. 0, or -1
 * after printing why (a WAV that cannot be written). */
int client_audio_start(client *c);
/* A species' diameter classes and leaves from its asset (borrowed), by render id. */
void client_audio_species(client *c, int render_id, const asset *a);
/* A damage event new to the picture whose fall or break begins at server time t0_s (NaN:
 * an old one, silent): it sounds at the first frame showing that instant. */
void client_audio_event(client *c, uint32_t tree, int wire_kind, double t0_s);
/* After the frame of server time render_t is drawn (now_mono: its start): the listener's
 * wind and trees into the mixer, the events it shows started, headless that frame's sound
 * into the WAV, the log lines of sounds begun, the caption. */
void client_audio_frame(client *c, double render_t, double now_mono);
/* The caption line of what is heard, NULL when the sound is off. */
const char *client_audio_caption(const client *c);
/* A visitor's volume step (+1, -1), and its reset to the default (kiosk idle). */
void client_audio_volume(client *c, int dir);
void client_audio_idle(client *c);
/* The output device's name ("null" when there is none or the sound is off). */
const char *client_audio_device_name(const client *c);
/* Stops the device, closes the WAV, logs the run's peak, limiter and events; frees. */
void client_audio_stop(client *c);

/* ---- client_hold.c: a scene past what this client holds (CLIENT.md "Reduced view") ---- */

/* A welcome's trees: kept whole in c->hold (a reconnection to the same scene keeps its
 * point, held before), then client_hold_select. 0, or GALE_E_NOMEM with err set. */
int client_hold_welcome(client *c, const ctl_welcome *w, gale_err *err);
/* The trees held of c->hold.scene: all within this client's limit (--max-trees, the
 * GPU's texture buffers, the jitter budget, an allocation that failed), else as many as
 * the limit nearest one point (the one held about before, else a fitted camera's ground
 * point, else the scene's centre); those into c->w_instances and c->w.n_instances, a
 * damage view sized to them. 0, or GALE_E_NOMEM with err set. */
int client_hold_select(client *c, gale_err *err);
/* After an allocation for the scene failed (what: its message): half the trees held, the
 * scene set up again on this connection. 0, or -1 when one tree or none was held. */
int client_hold_fewer(client *c, const char *what);
/* The circle view's radius from the species' heights at unit scale by welcome index
 * (the server widens a circle by the tallest tree's height). */
void client_hold_margin(client *c, const float *height_m);
/* Once a scene: on stderr, the server, the scene's trees, those held, where and why. */
void client_hold_say(client *c);
/* Held index of the stream's tree t, UINT32_MAX for one not held. */
uint32_t client_hold_tree(const client *c, uint32_t t);
/* A frame whose DAMAGE names the trees held: f itself when the whole scene is held, else
 * tmp (a copy of f with the events of held trees, their indices held ones; c owns the
 * events until the next call). */
const wire_frame *client_hold_damage(client *c, const wire_frame *f, wire_frame *tmp);
/* Frees what c->hold owns. */
void client_hold_free(client *c);

/* ---- client_view.c: the view sent as the camera moves ---- */

/* At most 4 views a second, and one only when the eye moved, the view turned or its cone
 * changed: a camera at rest costs nothing, one in motion a few hundred bytes a second. */
#define CLIENT_VIEW_MIN_S 0.25
#define CLIENT_VIEW_MOVE_M 1.0f
#define CLIENT_VIEW_TURN_DEG 1.0f

/* After a frame: sends the last frame's view when it differs enough from the one sent
 * (or none was sent on this connection). Nothing with --view all. */
void client_view_update(client *c, double now);

/* A new scene: the next frame sends its view anew. */
void client_view_scene(client *c);

/* ---- client_damage.c: storm damage on screen ---- */

typedef struct client_damage_fx client_damage_fx;

/* Fallen (snapped or uprooted) trees tipped over their root towards the fall azimuth (as
 * far as their fall has come), broken branches and leaf levels; pushed to the renderer
 * when the scene is ready. */
void client_damage_draw(client *c);
/* A frame's DAMAGE events: starts the falls and debris of recent ones new to the picture,
 * then applies them to c->dmg and draws. */
void client_damage_take(client *c, const wire_frame *f);
/* A frame's FOREST (PROTOCOL.md "FOREST") with its DAMAGE if it has one, taken as one:
 * the DAMAGE applies, then the trees' fall and level are replaced by the FOREST's (the
 * broken branches kept); what is new to the picture before either starts as in
 * client_damage_take. */
void client_damage_take_forest(client *c, const wire_frame *f);
/* Before drawing the frame of server time now_s: falls under way and debris move on. */
void client_damage_frame(client *c, double now_s);
/* Debris pieces in flight or lying. */
uint32_t client_damage_debris_count(const client *c);
/* Whether this client saw tree t's fall begin (not one older than DAMAGE_RECENT_S at its
 * arrival); then when its stem gave way and the instant last drawn (server clock [s]), and
 * the heading its top falls to [rad]. */
bool client_damage_live_fall(const client *c, uint32_t t, double *t0_s, double *now_s,
                             float *az_rad);
/* --fall-shots (client_fall_shots.c): "T,T,..." seconds after a live fall, ascending,
 * 1..8 of them, into a. 0, or -1 after printing what is wrong. */
int client_fall_shots_parse(const char *spec, client_args *a);
/* After a headless frame is drawn: frames the first live fall once it is seen (of falls
 * beginning together, the one with the fewest trees in the way), then writes
 * PREFIX-fall-S.Ss.png (PREFIX: --screenshot without ".png", else "gale") at each time.
 * 1 once the last is written, else 0. */
int client_fall_shots_step(client *c);
/* --screenshot-every (client_fall_shots.c): the frame just drawn as PREFIX-NNNNNN.png, NNNNNN
 * the number --frame-log gives the frame (a wall tile's group frame); says so on stderr with
 * the server instant shown (none for a wall tile's frame before it joined its group). A
 * failed write is said and the run goes on. */
void client_shot_numbered(client *c);
/* Frees c->dfx (NULL is a no-op). */
void client_damage_free(client *c);

/* ---- client_stream.c: cli_net handler callbacks (user = the client) ---- */

/* Keeps owned copies of the welcome's scene and marks it pending for client_scene_setup.
 * A welcome it cannot hold (no memory, too many species) leaves an empty scene, logged. */
void client_stream_on_welcome(void *user, const ctl_welcome *w);
/* WIND frames update the HUD speed and the renderer's wind; once the scene is ready,
 * KEYFRAME/DELTA state goes into the jitter buffer and LEAVES into falling leaves. */
void client_stream_on_frame(void *user, const wire_frame *f, const wire_decoder *dec,
                            double recv_s);
/* Keeps the last state on screen; the jitter buffer restarts with the next keyframe. */
void client_stream_on_lost(void *user, int close_code, const char *why);

/* ---- client_scene.c ---- */

/* Builds the pending scene: loads every species not yet on the GPU (client_assets_load),
 * sets instances and houses, and sizes the jitter buffer and snapshot scratch to the
 * scene. 0, or negative GALE_E_* with err set (the caller drops the connection to retry). */
int client_scene_setup(client *c, gale_err *err);
/* Frames the scene's trees (their centre, at a distance from their spread). */
void client_scene_reset_camera(client *c);

/* ---- client_assets.c ---- */

/* The asset of one species into *a (caller frees with asset_fini): from the disk cache by
 * content hash, else over HTTP from the server (then stored in the cache). 0, or the
 * fetch's or the decoder's negative GALE_E_* with err set. */
int client_assets_load(client *c, const ctl_species *s, asset *a, gale_err *err);

/* ---- client_input.c ---- */

/* Installs key, mouse, cursor and scroll callbacks on win; c must outlive the window. */
void client_input_attach(client *c, struct GLFWwindow *win);
/* WASD/QE fly for dt [s] (not for wall tiles: every tile shows one fixed camera). */
void client_input_fly(client *c, struct GLFWwindow *win, float dt);
/* F11: the primary monitor at its mode, or back to the window it was. */
void client_input_toggle_fullscreen(client *c, struct GLFWwindow *win);
/* "gale-YYYYmmdd-HHMMSS.png" of the local time into buf (cap bytes). */
void client_input_screenshot_name(char *buf, size_t cap);

/* ---- client_kiosk.c ---- */

/* Kiosk role only: moves the wind dial by delta [m/s] (starting from the streamed speed,
 * kept within 0..KIOSK_UI_DIAL_MAX_MS) and sends the panel dial's command with the kiosk
 * token; failures are logged. */
void client_kiosk_dial(client *c, float delta_ms);
/* Kiosk role only: releases the kiosk's dial (attract mode); failures are logged. */
void client_kiosk_release(client *c);
/* The C key or the camera button: the next camera preset (camera_button_next), applied. */
void client_kiosk_camera_next(client *c);
/* A kiosk's camera button over the frame (camera_button_layout), labelled with its preset. */
void client_kiosk_draw_camera_button(client *c, int fb_w, int fb_h);
/* The welcome's scenarios become the panel's buttons (copied: w may go). */
void client_kiosk_on_welcome(client *c, const ctl_welcome *w);
/* A touch on the panel at framebuffer pixel (x, y) (kiosk role only): sends what it asks
 * for (a dragged dial at most every CLIENT_KIOSK_DRAG_S, and on release), logging each
 * message sent as "gale-client: kiosk sent {json}". True when the panel took the touch. */
bool client_kiosk_touch(client *c, int phase, float x, float y);
#define CLIENT_KIOSK_DRAG_S 0.25
/* Lays out and draws the panel for fb_w × fb_h (kiosk role with a HUD). */
void client_kiosk_draw_panel(client *c, int fb_w, int fb_h);
/* Parses --touch SPEC: events separated by ';', "down X,Y", "move X,Y", "up X,Y",
 * "tap X,Y" (down and up) or "wait" (one frame), X,Y in framebuffer pixels. 0, or -1 with
 * the reason on stderr. */
int client_kiosk_touch_script(client *c, const char *spec);
/* Headless: plays the next scripted touch (after a frame is drawn, so the panel is laid
 * out). */
void client_kiosk_touch_step(client *c);
/* A touch, key or wheel at now: true when it only woke the kiosk from attract mode (then
 * it is no control) and the camera is back at the kiosk's own view. */
bool client_input_woke(client *c);

/* ---- client_wall.c ---- */

/* --wall: loads the file, finds --tile (or prints the names for --list-tiles), takes the
 * tile's px as the size unless --size was given. 0, 1 when it listed the tiles (exit 0),
 * or -1 with the reason on stderr. */
int client_wall_setup(client *c);
/* HUD text size [px] for this client: a wall tile's hud_text_mm on its glass, 0 (no HUD)
 * on the wall's other tiles; default_px elsewhere. */
float client_wall_hud_px(const client *c, float default_px);
/* view and proj of this tile for the camera (wall file, or --tile C,R,COLS,ROWS). */
void client_wall_matrices(const client *c, int fb_w, int fb_h, float z_near, float z_far,
                          float view[16], float proj[16]);

/* ---- client_wall_group.c ---- */

/* cli_net's on_wall: the group's clock, swaps and camera. */
void client_wall_group_on_wall(void *user, const ctl_msg *m);
/* The server's schedule (open or closed, and when it opens), and the closed card over the
 * frame while closed (client_closed.c). */
void client_closed_on_schedule(client *c, const ctl_schedule *s);
void client_closed_draw(client *c, int fb_w, int fb_h);
/* Tells the server what a kiosk shows and plays through (kiosk_state), once after each
 * welcome. */
void client_kiosk_send_state(client *c);
/* Before drawing: (re)joins the group on each new connection; with the group's clock,
 * picks the next frame whose instant is ahead (wg.frame, wg.render_t) and its camera (the
 * server's, or the wall file's tour). False without a clock (the frame plays out on the
 * tile's own estimate). */
bool client_wall_group_begin(client *c);
/* After drawing frame wg.frame: finishes it, swap-lock reports it; waits (servicing the
 * network) for its instant and, swap-lock, for "swap N" at most the budget after. */
void client_wall_group_before_present(client *c);
/* After presenting: the frame log line. */
void client_wall_group_after_present(client *c);

/* ---- client_frame.c ---- */

/* One frame at local time now [s]: samples q a playout delay behind the server clock,
 * draws the scene from the camera (a wall tile's off-axis projection) and the HUD. 0, or
 * the renderer's negative GALE_E_* with err set. */
int client_frame_draw(client *c, double now, gale_err *err);

#endif
