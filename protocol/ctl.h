/* The JSON control half of the gale wire (PROTOCOL.md "Control messages"): hello,
 * welcome (scene description), view, wind commands, resync, ping/pong, error. Text in,
 * structs out and back, through cJSON; every rejection names the field and carries its
 * close code (wire.h enum wire_close). PROTOCOL.md lists the messages and their fields. */
#ifndef GALE_CTL_H
#define GALE_CTL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "wire_limits.h"

enum ctl_type {
    CTL_NONE = 0,
    /* client -> server */
    CTL_HELLO,  /* first message: role, protocol version, optional view, optional token */
    CTL_VIEW,   /* change the view (interest region) */
    CTL_WIND,   /* kiosk wind command (token required) */
    CTL_RESYNC, /* client saw a gap: send a keyframe */
    CTL_PING,   /* round trip, echoes the client time */
    /* server -> client */
    CTL_WELCOME, /* scene description, rates, asset URLs, instances */
    CTL_PONG,    /* reply to ping, with server time and tick */
    CTL_ERROR,   /* sent before closing: code and reason */
    /* display walls (PROTOCOL.md "Wall groups", ctl_wall.c) */
    CTL_WALL_JOIN,   /* client: a wall tile joins its wall's group */
    CTL_WALL_DRAWN,  /* client: frame N drawn, waiting to swap (swap-lock) */
    CTL_WALL_CAMERA, /* client (kiosk) sets the wall's camera; server: applies at frame N */
    CTL_WALL_SYNC,   /* server: the group's frame clock (reply to wall_join) */
    CTL_WALL_SWAP,   /* server: swap frame N now */
    /* kiosk */
    CTL_RESET,       /* client (kiosk): heal the forest, drop the dial, back to the playlist */
    /* operations (ctl_ops.c) */
    CTL_KIOSK_STATE, /* client (kiosk): the language it shows, the audio device it plays to */
    CTL_SCHEDULE,    /* server: open or closed by the opening hours, and the next change */
};

enum ctl_role {
    CTL_ROLE_VIEWER = 0,
    CTL_ROLE_KIOSK,
    CTL_ROLE_WALL_TILE,
    CTL_ROLE_LOAD,
};

/* Interest region: trees inside it get full modes, trees beyond lod_m fewer, trees
 * outside are not sent. kind NONE: the whole scene. Coordinates in scene metres, z up. */
enum ctl_view_kind {
    CTL_VIEW_ALL = 0,
    CTL_VIEW_CIRCLE, /* centre (x, y), radius_m */
    CTL_VIEW_FRUSTUM /* eye, dir (need not be unit), half-angle fov_deg / 2, far_m */
};

typedef struct ctl_view {
    int kind;            /* enum ctl_view_kind */
    float x, y, radius_m; /* CIRCLE; radius_m in (0, 1e6] */
    float eye[3], dir[3]; /* FRUSTUM; |dir| > 0 */
    float fov_deg;        /* FRUSTUM; full cone angle (0, 180) */
    float far_m;          /* FRUSTUM; (0, 1e6] */
    float lod_m;          /* beyond this distance fewer modes; 0 = no LOD */
} ctl_view;

typedef struct ctl_hello {
    int protocol;                /* must be WIRE_PROTOCOL_VERSION */
    int role;                    /* enum ctl_role */
    ctl_view view;               /* optional ("view" absent: CTL_VIEW_ALL) */
    char token[CTL_MAX_TOKEN];   /* optional; "" when absent */
} ctl_hello;

/* Wind command from a kiosk. Each field optional; has_* says which were given. */
typedef struct ctl_wind {
    char token[CTL_MAX_TOKEN]; /* required */
    bool has_speed, has_dir, has_gust, has_scenario;
    float speed_ms;            /* [m/s] at 10 m, [0, 100] */
    float dir_deg;             /* direction the wind blows towards, [0, 360) from +x, ccw */
    float gust;                /* turbulence intensity, [0, 1] */
    char scenario[CTL_MAX_NAME]; /* "" = none (manual), else a scenario name from the config */
    /* kiosk and script controls (PROTOCOL.md "wind"): release the dial, steer a replay */
    bool release;              /* true: drop this kiosk's dial; the scripted wind resumes */
    bool keep;                 /* true: the dial outlives this connection (a script's
                                  command), until a release or the server's idle time */
    bool has_replay_at, has_replay_speed;
    float replay_at_min;       /* storm minute to jump to (0 = the track's reference,
                                  landfall for the shipped replays), [-1e5, 1e5] */
    float replay_speed;        /* storm seconds per server second, [1, 10000] */
    bool has_replay_paused;
    bool replay_paused;        /* true: the replay's storm clock holds; false: it runs */
} ctl_wind;

/* reset from a kiosk (PROTOCOL.md "Control messages"). */
typedef struct ctl_reset {
    char token[CTL_MAX_TOKEN]; /* required */
} ctl_reset;

/* kiosk_state from a kiosk (PROTOCOL.md "Control messages"): what it shows and plays
 * through, for the staff's status page and the usage counters. */
#define CTL_MAX_LANG 16u /* a language tag: "en", "de-CH" (15 bytes at most) */
typedef struct ctl_kiosk_state {
    char token[CTL_MAX_TOKEN];  /* required */
    char lang[CTL_MAX_LANG];    /* a letter, then letters, digits or '-' */
    char audio[CTL_MAX_NAME];   /* output device name, "none" or "null"; no control bytes */
} ctl_kiosk_state;

/* schedule from the server: the exhibit's opening hours as they stand now. */
typedef struct ctl_schedule {
    bool open;                  /* false: the exhibit is closed (show the closed card) */
    char next_change[9];        /* local clock time of the next opening or closing, "HH:MM"
                                   or "HH:MM:SS"; "" when none is ahead (always open) */
    uint32_t next_in_s;         /* seconds until it, [1, 604800]; 0 exactly when "" */
} ctl_schedule;

typedef struct ctl_ping {
    uint32_t id;           /* echoed */
    uint64_t client_us;    /* client clock [us], echoed */
} ctl_ping;

typedef struct ctl_pong {
    uint32_t id;
    uint64_t client_us;    /* from the ping */
    uint64_t server_us;    /* server clock [us] when answered */
    uint32_t tick;         /* server tick then */
} ctl_pong;

typedef struct ctl_species {
    char name[CTL_MAX_NAME];
    char url[CTL_MAX_URL];  /* asset path on the server, e.g. "/assets/oak-<hash>.gasset" */
    char hash[17];          /* 16 hex digits: content hash of the asset file */
    uint32_t n_modes;       /* modes streamed for it */
} ctl_species;

typedef struct ctl_instance {
    uint32_t species;      /* index into species[] */
    float pos[3];          /* [m] scene frame, z up */
    float yaw_rad;         /* rotation about z */
    float scale;           /* uniform, > 0 */
} ctl_instance;

/* An obstacle (a house): an axis-aligned box, min[k] <= max[k], [m] scene frame, z up. */
typedef struct ctl_obstacle {
    float min[3];
    float max[3];
} ctl_obstacle;

enum ctl_scenario_kind {
    CTL_SCENARIO_STEADY = 0, /* a steady or gusty wind */
    CTL_SCENARIO_REPLAY,     /* a storm replayed along its track */
};

/* One scenario a kiosk may choose (welcome.scenarios). */
typedef struct ctl_scenario_info {
    char name[CTL_MAX_NAME];  /* what wind.scenario names it by, e.g. "andrew1992" */
    char title[CTL_MAX_NAME]; /* what a visitor reads, e.g. "Andrew 1992" */
    int kind;                 /* enum ctl_scenario_kind */
    float sustained_ms;       /* steady: its mean 10 m wind, [0, 100]; replay: 0 */
} ctl_scenario_info;

typedef struct ctl_welcome {
    int protocol;
    uint32_t client_id;
    int role;                   /* the role granted */
    float tick_hz;              /* simulation rate */
    float snapshot_hz;          /* state frames per second */
    uint64_t server_us;         /* server clock at send [us] */
    uint32_t tick;              /* server tick at send */
    uint32_t n_species;
    ctl_species *species;       /* [n_species]; owned by the message when decoded */
    uint32_t n_instances;
    ctl_instance *instances;    /* [n_instances]; owned by the message when decoded */
    uint32_t n_obstacles;       /* <= WIRE_MAX_OBSTACLES; "obstacles" absent on the wire: 0 */
    ctl_obstacle *obstacles;    /* [n_obstacles]; owned by the message when decoded */
    uint32_t n_scenarios;       /* <= WIRE_MAX_SCENARIOS; "scenarios" absent on the wire: 0 */
    ctl_scenario_info *scenarios; /* [n_scenarios]; owned by the message when decoded */
} ctl_welcome;

typedef struct ctl_error {
    int code;                  /* enum wire_close */
    char message[CTL_MAX_ERROR];
} ctl_error;

/* Display walls (PROTOCOL.md "Wall groups"). Frame N of a group shows server time
 * epoch_us + N period_us − delay_us and is presented at server time epoch_us + N period_us. */
#define CTL_WALL_MAX_RATE_HZ 240
typedef struct ctl_wall_join {
    char wall[CTL_MAX_NAME];  /* the group: the wall file's name */
    char tile[CTL_MAX_NAME];  /* this tile's name in it */
    bool swap_lock;           /* wait for wall_swap before presenting */
    float rate_hz;            /* frames a second, (0, CTL_WALL_MAX_RATE_HZ]; the first
                                 member's rate holds for the group */
    uint32_t budget_ms;       /* swap-lock: longest wait for the others, 1..1000 */
    uint32_t delay_ms;        /* playout delay behind server time, 1..10000 */
} ctl_wall_join;

typedef struct ctl_wall_sync {
    char wall[CTL_MAX_NAME];
    uint64_t epoch_us;        /* server clock of frame 0 */
    uint32_t period_us;       /* 1e6 / rate */
    uint32_t delay_us;        /* playout delay of every tile */
    uint32_t budget_ms;
    bool swap_lock;
    uint32_t members;         /* tiles in the group, this one included */
} ctl_wall_sync;

/* wall_drawn (client: frame) and wall_swap (server: frame, drawn = tiles in it, members =
 * tiles in the group). */
typedef struct ctl_wall_frame {
    uint32_t frame;
    uint32_t drawn;
    uint32_t members;
} ctl_wall_frame;

/* The wall's orbit camera (camera.h): from a kiosk without frame; from the server with
 * the frame every tile first draws it at. */
typedef struct ctl_wall_camera {
    char wall[CTL_MAX_NAME];
    uint32_t frame;           /* server → tile; 0 from a client */
    float target_m[3];
    float distance_m;         /* [0.5, 5000] */
    float yaw_deg, pitch_deg; /* [-720, 720], [-88, 88] */
} ctl_wall_camera;

typedef struct ctl_msg {
    int type; /* enum ctl_type */
    union {
        ctl_hello hello;
        ctl_view view;      /* CTL_VIEW */
        ctl_wind wind;
        uint32_t resync_seq; /* CTL_RESYNC: last seq the client holds (0 = none) */
        ctl_ping ping;
        ctl_welcome welcome;
        ctl_pong pong;
        ctl_error error;
        ctl_wall_join wall_join;
        ctl_wall_sync wall_sync;
        ctl_wall_frame wall_frame; /* CTL_WALL_DRAWN, CTL_WALL_SWAP */
        ctl_wall_camera wall_camera;
        ctl_reset reset;
        ctl_kiosk_state kiosk_state;
        ctl_schedule schedule;
    } u;
} ctl_msg;

/* Parses one control message of len bytes (not NUL-terminated necessarily) into *m.
 * max_len is the size limit for this direction (CTL_MAX_CLIENT_BYTES on the server,
 * CTL_MAX_SERVER_BYTES on the client; 0 = CTL_MAX_CLIENT_BYTES). On failure returns a
 * negative GALE_E_*, fills err with "where: what: expected, got" (the key path, and line:col
 * for bad JSON) and sets *close_code (enum wire_close) when close_code is not NULL; *m is
 * then empty. A decoded welcome owns its arrays: release with ctl_msg_fini. */
int ctl_decode(const char *text, size_t len, size_t max_len, ctl_msg *m, int *close_code,
               gale_err *err);

/* Frees what a decoded message owns and zeroes it. NULL is a no-op. */
void ctl_msg_fini(ctl_msg *m);

/* Encodes *m as one line of JSON into a new NUL-terminated buffer *out (malloc'd, caller
 * frees with free()) of *len bytes (without the NUL). Rejects values a decoder would
 * reject: each field is checked against the decoder's own limit as it is written
 * (GALE_E_RANGE; an enum outside its range GALE_E_ARG), so the text is not parsed again.
 * tests/test_ctl.c checks that whatever it writes decodes. */
int ctl_encode(const ctl_msg *m, char **out, size_t *len, gale_err *err);

/* Encodes *m into buf[cap] (NUL-terminated); for small messages on hot paths (pong,
 * error). GALE_E_RANGE when it does not fit. Does not allocate outside cJSON. */
int ctl_encode_into(const ctl_msg *m, char *buf, size_t cap, size_t *len, gale_err *err);

/* True for the types a client may send (hello, view, wind, resync, ping, wall_join,
 * wall_drawn, wall_camera, reset, kiosk_state). */
bool ctl_from_client(int type);

/* Role and type names as on the wire ("viewer", "wall-tile", "hello", ...); NULL for an
 * unknown value. */
const char *ctl_role_name(int role);
const char *ctl_type_name(int type);

#endif
