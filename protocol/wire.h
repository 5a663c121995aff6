/* The binary half of the gale wire (PROTOCOL.md "Binary frames"): frame header, close
 * codes, quantisation of modal coordinates q (Diener 2008 section 3), state keyframes and
 * deltas, leaf seeds (Vazquez 2008), coarse wind slices (Oliapuram & Kumar section 2) and
 * the client's decoder. The byte cursor they are written with is wire_cursor.h.
 * PROTOCOL.md has the byte tables. */
#ifndef GALE_WIRE_H
#define GALE_WIRE_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "hash.h"
#include "wire_cursor.h"
#include "wire_limits.h"

/* ---- frame header: every binary frame starts with it (20 bytes) ---------------------- */

#define WIRE_MAGIC 0x454C4147u /* "GALE" as bytes G A L E */
#define WIRE_HEADER_BYTES 20u

enum wire_msg_type {
    WIRE_MSG_KEYFRAME = 1, /* absolute quantised q of the trees in view */
    WIRE_MSG_DELTA = 2,    /* q relative to the previous snapshot (seq - 1) */
    WIRE_MSG_LEAVES = 3,   /* leaf seeds shed this tick */
    WIRE_MSG_WIND = 4,     /* coarse horizontal wind slice */
    WIRE_MSG_WEATHER = 5,  /* what the exhibit shows: sustained wind, gust, class, storm */
    WIRE_MSG_DAMAGE = 6,   /* storm damage events, or the whole damage state */
    WIRE_MSG_BUNDLE = 7,   /* container: other frames of one snapshot in one message */
    WIRE_MSG_FOREST = 8,   /* the trees' fall and leaf level, whole, one byte a tree */
};

typedef struct wire_header {
    uint32_t magic;          /* WIRE_MAGIC */
    uint16_t version;        /* WIRE_PROTOCOL_VERSION */
    uint8_t type;            /* enum wire_msg_type */
    uint8_t flags;           /* reserved, 0 */
    uint32_t tick;           /* server simulation tick the frame describes */
    uint64_t server_time_us; /* server clock [us] at that tick (CLOCK_MONOTONIC based) */
} wire_header;

/* ---- close codes (WebSocket close status; 4000-4999 are application codes) ----------- */

enum wire_close {
    WIRE_CLOSE_NORMAL = 1000,      /* client or server is done */
    WIRE_CLOSE_GOING_AWAY = 1001,  /* server shutting down (SIGINT/SIGTERM) */
    WIRE_CLOSE_BAD_JSON = 4000,    /* control message is not valid JSON (or not an object) */
    WIRE_CLOSE_UNKNOWN_TYPE = 4001,/* "type" missing, not a string, or not a known message */
    WIRE_CLOSE_BAD_FIELD = 4002,   /* a field missing, of the wrong type, or out of range */
    WIRE_CLOSE_VERSION = 4003,     /* hello.protocol is not WIRE_PROTOCOL_VERSION */
    WIRE_CLOSE_TOO_BIG = 4004,     /* message longer than CTL_MAX_CLIENT_BYTES */
    WIRE_CLOSE_BINARY = 4005,      /* client sent a binary frame (clients send JSON only) */
    WIRE_CLOSE_FORBIDDEN = 4006,   /* role may not send this (a viewer sending wind) */
    WIRE_CLOSE_BAD_TOKEN = 4007,   /* kiosk token wrong */
    WIRE_CLOSE_SLOW = 4008,        /* client took nothing for the server's stall time */
    WIRE_CLOSE_ORDER = 4009,       /* message before hello, a second hello, no hello in time,
                                      or a server-only type (welcome, pong, error) from a
                                      client */
    WIRE_CLOSE_FULL = 4010,        /* server at its connection limit */
    WIRE_CLOSE_BAD_FRAME = 4011,   /* (client side) server frame failed to decode */
    WIRE_CLOSE_RATE = 4012,        /* client sent control messages faster than allowed */
};

/* Name of a close code ("bad-json", "version", ...), "unknown" for others. */
const char *wire_close_name(int code);

/* ---- frame header ------------------------------------------------------------------- */

/* Writes h (magic and version are written as WIRE_MAGIC / WIRE_PROTOCOL_VERSION). */
void wire_put_header(wire_writer *w, const wire_header *h);

/* Reads and checks a header: bad magic -> GALE_E_FORMAT, other version ->
 * GALE_E_VERSION, unknown type or short frame -> GALE_E_FORMAT; messages name the field
 * and what was expected. */
int wire_get_header(wire_reader *r, wire_header *h, gale_err *err);

/* ---- quantisation of q (PROTOCOL.md "Quantisation") -------------------------------- */

#define WIRE_QMAX 32767 /* quantised q is int16 in [-WIRE_QMAX, WIRE_QMAX] */

/* round(x * inv_step) (halves away from zero) clamped to +-WIRE_QMAX; NaN -> 0, +-inf
 * and +-1e30 clamp. The clamp happens in float before the cast (an out-of-range cast is
 * undefined). Branch-free enough for the compiler to vectorise the modal loop. */
static inline int16_t wire_quantize(float x, float inv_step)
{
    float s = x * inv_step;
    s = s == s ? s : 0.0f;
    s = s > (float)WIRE_QMAX ? (float)WIRE_QMAX : s;
    s = s < -(float)WIRE_QMAX ? -(float)WIRE_QMAX : s;
    return (int16_t)(int32_t)(s + (s < 0.0f ? -0.5f : 0.5f));
}

static inline float wire_dequantize(int16_t v, float step)
{
    return (float)v * step;
}

/* ---- scene and snapshots (server and client share the picture) --------------------- */

/* What both ends know about the scene for the state frames: sent in every keyframe. */
typedef struct wire_scene {
    uint32_t n_trees;                                  /* instances, <= WIRE_MAX_TREES */
    uint32_t n_species;                                /* <= WIRE_MAX_SPECIES */
    uint8_t n_modes[WIRE_MAX_SPECIES];                 /* modes per species, 1..WIRE_MAX_MODES */
    float step[WIRE_MAX_SPECIES][WIRE_MAX_MODES];      /* quantisation step per mode, > 0 */
    const uint8_t *species;                            /* [n_trees] borrowed (encoder side) */
} wire_scene;

/* One snapshot of quantised q, tree-major. n_modes[t] = 0: tree t not sent (out of the
 * client's view); n_modes[t] < its species' modes: LOD. Entries at m >= n_modes[t] are
 * read as 0 by both encoder and decoder (they need not be zeroed in q). */
typedef struct wire_state {
    uint32_t n_trees;        /* instances */
    uint32_t stride;         /* int16 per tree in q, >= every n_modes[t] */
    const uint8_t *n_modes;  /* [n_trees] borrowed */
    const int16_t *q;        /* [n_trees * stride] borrowed */
} wire_state;

/* Worst-case bytes of one KEYFRAME or DELTA for these sizes (to size a buffer once). */
size_t wire_state_bound(uint32_t n_trees, uint32_t max_modes, uint32_t n_species);

/* Lanes for the state encoders: run(ctx, n, job, arg) calls job(arg, i) for every i in
 * 0..n-1, on several threads at once or in turn, and returns when all have returned. The
 * trees are split into n contiguous shares; the frame's bytes are those of one lane. */
#define WIRE_MAX_LANES 16u
typedef void (*wire_lane_fn)(void *arg, int lane);
typedef struct wire_lanes {
    int n; /* lanes, <= WIRE_MAX_LANES; <= 1: one, on the caller's thread */
    void (*run)(void *ctx, int n, wire_lane_fn job, void *arg);
    void *ctx;
} wire_lanes;

/* Encodes a KEYFRAME (absolute q) of snapshot `seq` into buf[cap]; *len gets its size.
 * h->type is ignored (set to KEYFRAME). Fails with GALE_E_RANGE when buf is too small
 * or a count breaks a limit. Does not allocate. */
int wire_encode_keyframe(const wire_header *h, uint32_t seq, const wire_scene *scene,
                         const wire_state *cur, uint8_t *buf, size_t cap, size_t *len,
                         gale_err *err);

/* Encodes a DELTA of snapshot `seq` against prev (snapshot seq - 1) and, when not NULL,
 * prev2 (seq - 2, enabling linear prediction). prev/prev2 must be what the client
 * decoded (the encoder's own previous inputs). Does not allocate. */
int wire_encode_delta(const wire_header *h, uint32_t seq, const wire_scene *scene,
                      const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                      uint8_t *buf, size_t cap, size_t *len, gale_err *err);

/* The same two in lanes (NULL: one). A buffer of wire_state_bound bytes leaves the lanes
 * room; a smaller one that still fits the frame is encoded in one lane. */
int wire_encode_keyframe_lanes(const wire_header *h, uint32_t seq, const wire_scene *scene,
                               const wire_state *cur, const wire_lanes *lanes, uint8_t *buf,
                               size_t cap, size_t *len, gale_err *err);
int wire_encode_delta_lanes(const wire_header *h, uint32_t seq, const wire_scene *scene,
                            const wire_state *cur, const wire_state *prev,
                            const wire_state *prev2, const wire_lanes *lanes, uint8_t *buf,
                            size_t cap, size_t *len, gale_err *err);

/* One output of wire_encode_snapshot_lanes. */
typedef struct wire_frame_out {
    uint8_t *buf;   /* NULL: this frame is not wanted (its len is 0, nothing is written) */
    size_t cap;
    size_t len;     /* set on success */
    gale_err *err;  /* out[0]'s receives the error (may be NULL) */
} wire_frame_out;

/* A snapshot's frames in one pass over the states: out[0] the KEYFRAME, and with prev
 * out[1] the DELTA against prev, and with prev and prev2 out[2] the DELTA against both,
 * each unless its buf is NULL; the bytes and the first error are those of
 * wire_encode_keyframe_lanes and wire_encode_delta_lanes called in that order for the
 * frames wanted. */
int wire_encode_snapshot_lanes(const wire_header *h, uint32_t seq, const wire_scene *scene,
                               const wire_state *cur, const wire_state *prev,
                               const wire_state *prev2, const wire_lanes *lanes,
                               wire_frame_out *out);

/* The lanes' layout of one pass (msg_state_lanes.c): lane i writes trees [t[i], t[i + 1])
 * of frame f from at[f][i]. Private to msg_state_lanes.c and msg_state_enc.c. */
typedef struct wire_lane_job {
    const wire_scene *sc;
    const wire_state *cur, *prev, *prev2;
    int nf;                              /* frames written at once */
    int n_pred[3];                       /* predictors of each frame */
    uint32_t n_lanes;
    uint32_t t[WIRE_MAX_LANES + 1];      /* lane i: trees [t[i], t[i + 1]) */
    uint8_t *at[3][WIRE_MAX_LANES + 1];  /* lane i writes frame f in [at[f][i], at[f][i + 1]) */
    uint8_t *end[3][WIRE_MAX_LANES];     /* where lane i's values of frame f ended */
    bool bad[WIRE_MAX_LANES];            /* lane i found a bad state or ran out of room */
    /* lanes moved down in order as they finish, by the thread of whichever finishes */
    _Atomic uint8_t done[WIRE_MAX_LANES]; /* lane i has run */
    _Atomic uint32_t moving;             /* a lane's thread is moving lanes down */
    uint32_t n_moved;                    /* lanes moved, under moving */
    uint8_t *to[3];                      /* where the next lane's frame f goes, under moving */
} wire_lane_job;

/* wire_encode_snapshot_lanes in three calls, so that its lanes can run over several
 * turns between other work (the same bytes whatever the turns; tests/test_wire_lanes.c):
 * wire_snapshot_begin writes the frames' fixed parts and lays out the lanes,
 * wire_snapshot_run runs lanes [i0, i1) of wire_snapshot_lanes (each lane once, in any
 * split and order), wire_snapshot_finish moves them together. The bytes, lengths and
 * error are wire_encode_snapshot_lanes's. Caller-owned, not moved between the calls; the
 * header is copied, the scene, states, lanes and out borrowed until finish. Fields
 * private to msg_state_enc.c. */
typedef struct wire_snapshot_job {
    wire_header h;
    uint32_t seq;
    const wire_scene *scene;
    wire_state st[3];       /* cur, prev, prev2 */
    const wire_state *prev, *prev2; /* &st[1], &st[2] or NULL */
    const wire_lanes *lanes;
    wire_frame_out *out;
    wire_writer w[3];       /* of the frames written, in order */
    int frame[3];           /* which out[] each writer fills */
    int nf;                 /* frames written */
    bool each;              /* finish encodes the frames one by one (a rule broken, a buffer
                               short): the error is theirs */
    wire_lane_job lj;
} wire_snapshot_job;

void wire_snapshot_begin(wire_snapshot_job *j, const wire_header *h, uint32_t seq,
                         const wire_scene *scene, const wire_state *cur,
                         const wire_state *prev, const wire_state *prev2,
                         const wire_lanes *lanes, wire_frame_out *out);
/* The lanes to run: 0 when finish does all the work. */
int wire_snapshot_lanes(const wire_snapshot_job *j);
void wire_snapshot_run(wire_snapshot_job *j, int i0, int i1);
int wire_snapshot_finish(wire_snapshot_job *j);

/* ---- leaf seeds and coarse wind ----------------------------------------------------- */

typedef struct wire_leaf {
    uint32_t instance;   /* tree index, < n_trees */
    uint16_t slot;       /* leaf slot on that tree's species (asset.n_leaves) */
    uint32_t spawn_tick; /* tick it detached */
    uint32_t seed;       /* per-leaf variation seed (rotation, scale, start) */
} wire_leaf;

/* Encodes n leaf seeds (n <= WIRE_MAX_LEAVES). Does not allocate. */
int wire_encode_leaves(const wire_header *h, const wire_leaf *leaves, uint32_t n,
                       uint8_t *buf, size_t cap, size_t *len, gale_err *err);

/* A horizontal slice of the wind at height z_m: nx * ny cells, 3 components int8 each,
 * v = value * scale_ms. Cell (i, j) centre: (x0_m + (i + 0.5) cell_m, y0_m + (j + 0.5) cell_m). */
typedef struct wire_wind {
    float x0_m, y0_m, z_m, cell_m;  /* origin corner, height, cell size [m] */
    float scale_ms;                 /* [m/s] per unit, > 0 */
    uint16_t nx, ny;                /* 1..WIRE_MAX_WIND_SIDE */
    const int8_t *v;                /* [ny][nx][3] borrowed (encode) / decoder-owned (decode) */
} wire_wind;

/* Quantises a world wind component [m/s] for a slice with scale_ms (clamps, NaN -> 0). */
int8_t wire_wind_quantize(float v_ms, float scale_ms);

int wire_encode_wind(const wire_header *h, const wire_wind *wind, uint8_t *buf, size_t cap,
                     size_t *len, gale_err *err);

/* ---- weather (PROTOCOL.md "WEATHER") ---------------------------------------------- */

#define WIRE_WEATHER_NAME_MAX 63 /* bytes of the scenario or storm name */

enum wire_weather_flags {
    WIRE_WEATHER_STORM = 1u << 0,    /* a storm is replayed: the storm fields are valid */
    WIRE_WEATHER_DIAL = 1u << 1,     /* a kiosk dial holds the wind */
    WIRE_WEATHER_FINISHED = 1u << 2, /* the replay reached its end and holds there */
    WIRE_WEATHER_CLOCK = 1u << 3,    /* utc_min and utc_offset_min are valid */
    WIRE_WEATHER_PAUSED = 1u << 4,   /* the replay is paused: its storm clock holds */
    WIRE_WEATHER_FLAGS_ALL = 0x1fu,
};

/* The weather at the scene as the server computes it (10 m above ground, scene frame x
 * east, y north). Classes are protocol/wind_scale.h's. */
typedef struct wire_weather {
    float sustained_ms;   /* 1-minute sustained wind [m/s], [0, 200] */
    float gust_ms;        /* 3-s gust: highest 3-s mean of the last 60 s [m/s], [0, 300] */
    float dir_from_deg;   /* where the wind comes from, clockwise from north, [0, 360) */
    uint8_t ss_class;     /* Saffir-Simpson class of sustained_ms, 0..6 */
    uint8_t beaufort;     /* Beaufort force of sustained_ms, 0..12 */
    uint8_t flags;        /* enum wire_weather_flags */
    uint8_t storm_class;  /* class of the storm's own peak wind, 0..6; 255 = no storm */
    float pressure_hpa;   /* sea-level pressure at the scene [hPa], [800, 1100] */
    float central_hpa;    /* STORM: the eye's central pressure [hPa], [800, 1100]; else 0 */
    float distance_km;    /* STORM: scene to eye [km], [0, 20000]; else -1 */
    float bearing_deg;    /* STORM: direction from the scene to the eye, clockwise from
                             north, [0, 360); else 0 */
    uint32_t utc_min;     /* CLOCK: storm time, minutes since 1970-01-01 00:00 UTC */
    int16_t utc_offset_min; /* CLOCK: local time = UTC + this [min], [-840, 840] */
    float storm_min;      /* STORM: storm time from the track's reference [min] */
    float replay_pos_s;   /* STORM: server seconds since the replay began, >= 0 */
    float replay_len_s;   /* STORM: length of the replay [s], >= 0; 0 = endless (loops) */
    float replay_speed;   /* STORM: storm seconds per server second, [0, 1e5] */
    char name[WIRE_WEATHER_NAME_MAX + 1]; /* scenario name, UTF-8 without control bytes */
} wire_weather;

/* Largest WEATHER frame [bytes]. */
#define WIRE_WEATHER_MAX_BYTES (WIRE_HEADER_BYTES + 55u + WIRE_WEATHER_NAME_MAX)

/* Encodes w (fields checked against the ranges above: GALE_E_RANGE names the field).
 * Does not allocate. */
/* True when n bytes at s are well-formed UTF-8 (a WEATHER name must be). */
bool wire_utf8_valid(const uint8_t *s, size_t n);

int wire_encode_weather(const wire_header *h, const wire_weather *w, uint8_t *buf, size_t cap,
                        size_t *len, gale_err *err);
/* ---- storm damage (PROTOCOL.md "DAMAGE") ------------------------------------------- */

enum wire_damage_kind {
    WIRE_DAMAGE_BRANCH = 1, /* node: first node of a branch that broke off with its sub-tree */
    WIRE_DAMAGE_SNAP = 2,   /* whole tree: the stem broke at its base; value: fall azimuth */
    WIRE_DAMAGE_UPROOT = 3, /* whole tree: it tipped over its root plate; value: azimuth */
    WIRE_DAMAGE_STRIP = 4,  /* whole tree: value = leaf area left, in WIRE_DAMAGE_LEVELS */
};
#define WIRE_DAMAGE_WHOLE 0xFFFFFFFFu /* node of an event about the whole tree */
#define WIRE_DAMAGE_LEVELS 32u        /* leaf area steps of a STRIP value (32 = intact) */

typedef struct wire_damage {
    uint32_t tree;  /* tree index, < n_trees */
    uint32_t node;  /* skeleton node (BRANCH) or WIRE_DAMAGE_WHOLE */
    uint8_t kind;   /* enum wire_damage_kind */
    uint8_t value;  /* SNAP/UPROOT: fall azimuth in 1/256 turns (world, x towards y);
                       STRIP: 0..WIRE_DAMAGE_LEVELS; BRANCH: 0 */
    uint32_t tick;  /* tick it happened */
} wire_damage;

/* Encodes n damage events; full = 1 says they are the whole damage state at h->tick (the
 * receiver heals every tree first), 0 that they happened since the last frame. Does not
 * allocate. */
int wire_encode_damage(const wire_header *h, bool full, const wire_damage *ev, uint32_t n,
                       uint8_t *buf, size_t cap, size_t *len, gale_err *err);

/* ---- the trees' fall and leaf level, whole (PROTOCOL.md "FOREST") ------------------- */

#define WIRE_FOREST_LEVEL_MASK 0x3Fu /* a tree's state byte: leaf level in bits 0-5 */
#define WIRE_FOREST_FALL_SHIFT 6u    /* and 0, WIRE_DAMAGE_SNAP or _UPROOT in bits 6-7 */

typedef struct wire_forest_fall {
    uint8_t az;    /* fall azimuth, 1/256 turns (world, x towards y) */
    uint32_t tick; /* tick it fell */
} wire_forest_fall;

/* The whole of it at h->tick: trees [first, first + count) as state[i] = fall << 6 | level,
 * the fallen ones' azimuth and tick in fall[] in tree order (n_fall, as many as state has
 * fallen trees); every other tree stands with its full crown. Does not allocate. */
int wire_encode_forest(const wire_header *h, uint32_t first, uint32_t count, const uint8_t *state,
                       const wire_forest_fall *fall, uint32_t n_fall, uint8_t *buf, size_t cap,
                       size_t *len, gale_err *err);
/* The FOREST frame's bytes for count trees of which n_fall lie. */
size_t wire_forest_bytes(uint32_t count, uint32_t n_fall);

/* The rank of a leaf slot and of a tree in [0, 2^32): a slot's rank on tree t is
 * wire_damage_slot_rank(slot) + wire_damage_tree_rank(t) mod 2^32, so the server can find
 * the slots of a band of ranks in a species' slots sorted once. */
static inline uint32_t wire_damage_slot_rank(uint32_t slot)
{
    return hash_mix32(slot * 0x9E3779B1u + 0x7F4A7C15u);
}
static inline uint32_t wire_damage_tree_rank(uint32_t tree)
{
    return hash_mix32(tree * 0x85EBCA77u + 0x165667B1u);
}

/* Whether leaf slot `slot` of tree `tree` is still on a crown with `level` of
 * WIRE_DAMAGE_LEVELS left: the slots of rank below level / WIRE_DAMAGE_LEVELS of the
 * range stay. Server (which leaves it strips) and clients (which they draw) agree
 * through this one function. */
static inline bool wire_damage_leaf_kept(uint32_t tree, uint32_t slot, uint32_t level)
{
    uint32_t r = wire_damage_slot_rank(slot) + wire_damage_tree_rank(tree);
    return (uint64_t)r * WIRE_DAMAGE_LEVELS < (uint64_t)level << 32;
}
/* ---- BUNDLE: several frames in one message (PROTOCOL.md "BUNDLE") ------------------- */

/* buf holds one whole frame of *len bytes; rewrites it in place into a BUNDLE carrying that
 * frame first, then the n_more frames more[i] (more_len[i] bytes each, whole frames, not
 * inside buf); *len gets the bundle's size. The bundle's header has the first frame's tick
 * and server time. GALE_E_RANGE when it does not fit cap, GALE_E_ARG past WIRE_MAX_BUNDLE
 * frames. Does not allocate. */
int wire_bundle_wrap(uint8_t *buf, size_t cap, size_t *len, const uint8_t *const *more,
                     const size_t *more_len, uint32_t n_more, gale_err *err);

/* ---- decoder (client side) ---------------------------------------------------------- */

typedef struct wire_decoder_desc {
    uint32_t max_trees; /* 0 = WIRE_MAX_TREES; capacity fixed at create */
    uint32_t max_modes; /* 0 = WIRE_MAX_MODES */
} wire_decoder_desc;

typedef struct wire_decoder wire_decoder;

/* Allocates a decoder holding the last two decoded snapshots; NULL on failure. */
wire_decoder *wire_decoder_create(const wire_decoder_desc *d, gale_err *err);
void wire_decoder_destroy(wire_decoder *d); /* NULL is a no-op */

/* What one decoded frame was. Pointers are owned by the decoder and valid until the next
 * wire_decode on it. */
typedef struct wire_frame {
    wire_header hdr;            /* a BUNDLE: its state frame's header (else its first's) */
    uint32_t types;             /* bit 1 << type of every frame decoded: one bit for a plain
                                   frame, one per inner frame for a BUNDLE */
    uint32_t seq;               /* KEYFRAME / DELTA: snapshot sequence number */
    uint32_t n_leaves;          /* LEAVES */
    const wire_leaf *leaves;    /* LEAVES: [n_leaves] */
    wire_wind wind;             /* WIND */
    bool damage_full;           /* DAMAGE: the events are the whole state */
    uint32_t n_damage;          /* DAMAGE */
    const wire_damage *damage;  /* DAMAGE: [n_damage] */
    wire_weather weather;       /* WEATHER */
    /* FOREST: trees [forest_first, + forest_count) as wire_encode_forest's state bytes,
     * the fallen ones' azimuth and tick in tree order; all others intact */
    uint32_t forest_first, forest_count, n_forest_fall;
    const uint8_t *forest_state;           /* [forest_count] */
    const wire_forest_fall *forest_fall;   /* [n_forest_fall] */
} wire_frame;

/* A decoded FOREST (f->types has it) as the DAMAGE events it stands for, into out[cap]: a
 * SNAP or UPROOT for each fallen tree (its azimuth and tick), a STRIP for each crown below
 * WIRE_DAMAGE_LEVELS (the frame's tick), in tree order. Returns how many it has (more than
 * cap: out holds the first cap). Applied after healing every tree's fall and level (not its
 * branches), they give the state the frame holds. */
uint32_t wire_forest_events(const wire_frame *f, wire_damage *out, uint32_t cap);

/* Decodes one binary frame. KEYFRAME replaces the decoder's state; DELTA applies to it.
 * A BUNDLE decodes each inner frame into the one *out (see types); any inner failure
 * fails the whole bundle, the state unchanged.
 * Nothing in the decoder changes unless the whole frame is valid. Errors: GALE_E_FORMAT
 * (truncated, bad magic/type/count, trailing bytes, a value outside its range),
 * GALE_E_VERSION, GALE_E_RANGE (more trees/modes than the decoder was created for),
 * GALE_E_STATE (a DELTA whose base the decoder does not hold: a gap; wait for or ask
 * for a keyframe). Never allocates. */
int wire_decode(wire_decoder *d, const uint8_t *buf, size_t len, wire_frame *out,
                gale_err *err);

/* True once a keyframe has been decoded (and no gap since). */
bool wire_decoder_synced(const wire_decoder *d);
/* Sequence number of the last decoded snapshot (0 before any). */
uint32_t wire_decoder_seq(const wire_decoder *d);
/* The scene of the last keyframe (species pointer owned by the decoder). */
const wire_scene *wire_decoder_scene(const wire_decoder *d);
/* Quantised state of the last decoded snapshot (arrays owned by the decoder). */
wire_state wire_decoder_state(const wire_decoder *d);

/* Dequantised q of tree t from the last snapshot into q[max_modes] (zeros beyond what
 * was sent); returns the number of modes sent (0: tree not in view or t out of range). */
uint32_t wire_decoder_q(const wire_decoder *d, uint32_t t, float *q, uint32_t max_modes);

#endif
