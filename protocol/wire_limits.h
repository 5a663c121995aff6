/* Hard limits of the gale wire protocol. Every count and length read from the wire is
 * checked against one of these before anything is allocated or indexed; the reason for
 * each value is written beside it. PROTOCOL.md repeats them. */
#ifndef GALE_LIMITS_H
#define GALE_LIMITS_H

/* Protocol version spoken by this build: in every binary frame header and in hello. */
#define WIRE_PROTOCOL_VERSION 1

/* Tree instances in one scene. The modal benchmark runs 100 000 trees; 2^18 leaves
 * headroom and keeps a tree index within 18 bits. */
#define WIRE_MAX_TREES 262144u

/* Modes per tree. A scene bakes 16..64 modes per species (the shipped ones 24..32). */
#define WIRE_MAX_MODES 64u

/* Species in one scene. A species index is one byte on the wire; 64 species is far more
 * than any scene ships (each is a baked asset a client downloads). */
#define WIRE_MAX_SPECIES 64u

/* Obstacles (houses: axis-aligned boxes) in one scene, sent in welcome. Each is a solid
 * block in the wind grid and a drawn house on every client; a village scene has tens,
 * 1024 leaves room and keeps the welcome row list (about 40 bytes each) under 64 KiB. */
#define WIRE_MAX_OBSTACLES 1024u
#define WIRE_MAX_SCENARIOS 32u   /* welcome.scenarios: the choices a kiosk shows */

/* Leaf seeds in one LEAVES frame. Shedding peaks at a few hundred per tick in a
 * hurricane scene; more are dropped by the server (leaves are decoration). */
#define WIRE_MAX_LEAVES 4096u

/* Damage events in one DAMAGE frame: a storm breaks a few branches per tree and moves
 * each crown's leaf level through at most 32 steps; the whole-state frame after a
 * keyframe lists every broken branch and fallen or stripped tree of a scene of hundreds
 * of trees. 4096 events are 57 KiB, inside one of the server's 64 KiB extra buffers. */
#define WIRE_MAX_DAMAGE 4096u

/* Coarse wind slice: cells per side. A 256 x 256 x 16 grid (Oliapuram & Kumar) is the
 * largest wind grid; a slice is at most 256 x 256 cells. */
#define WIRE_MAX_WIND_SIDE 256u

/* Frames in one BUNDLE: a snapshot's state and its leaves, wind, weather, damage ...
 * (one of each type) need fewer than 8; 16 leaves room for types to come. */
#define WIRE_MAX_BUNDLE 16u

/* Largest quantisation step: |Q| <= 32767 times it stays a finite float (FLT_MAX / 32768
 * is about 1e34), so every dequantised q is finite. */
#define WIRE_MAX_STEP 1e30f

/* Largest binary frame either side accepts: a keyframe of every tree at full modes is
 * bounded by wire_state_bound(); 100 000 trees x 32 modes fit in well under 16 MiB. */
#define WIRE_MAX_FRAME_BYTES (16u << 20)

/* Largest control (JSON) message a client may send. hello with a view, wind commands
 * and pings are under 1 KiB; 4 KiB leaves room without letting a client make the server
 * parse megabytes. */
#define CTL_MAX_CLIENT_BYTES 4096u

/* Largest control message the server sends (welcome lists every instance: about 60
 * bytes each, so 262 144 trees stay under 16 MiB). */
#define CTL_MAX_SERVER_BYTES (16u << 20)

/* JSON nesting accepted in control messages (welcome nests 3 deep: object, array of
 * instances, instance row). cJSON's own limit is 1000; ours is far smaller. */
#define CTL_MAX_DEPTH 8

/* Strings in control messages: tokens, species names, URLs, roles, error text. */
#define CTL_MAX_TOKEN 64u   /* kiosk token from the scene config */
#define CTL_MAX_NAME 64u    /* species name (asset.species is 64 bytes) */
#define CTL_MAX_URL 256u    /* asset URL path on the server */
#define CTL_MAX_ERROR 256u  /* error text (gale_err.msg is 256 bytes) */

#endif
