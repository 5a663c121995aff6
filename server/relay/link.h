/* What gale-server and gale-relay say to each other over NATS (server/SERVER.md "Relays"):
 * the subjects and the byte layout of each message. The server publishes every encoded
 * snapshot of its shared whole-scene stream once; relays answer clients from those,
 * select their views themselves, and forward every other control message to the server
 * by request/reply. Little-endian, wire_cursor.h. */
#ifndef GALE_LINK_H
#define GALE_LINK_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "net.h"

#define LINK_SUBJ_SNAP "gale.snap"     /* + ".0": one net_snap per shared-stream snapshot */
#define LINK_SUBJ_CTL "gale.ctl"       /* request: a client's control message; reply: verdict */
#define LINK_SUBJ_CLOSED "gale.closed" /* a relayed connection that said hello closed */
#define LINK_SUBJ_INFO "gale.info"     /* request: sizes and the asset list */
#define LINK_SUBJ_ASSET "gale.asset"   /* request: a chunk of one asset's bytes */
#define LINK_SUBJ_SCENE "gale.scene"   /* request: a chunk of the view rule (link_scene) */

/* An asset chunk: under NATS's default 1 MiB payload. */
#define LINK_ASSET_CHUNK (512u << 10)
/* A relay waits this long for the server's verdict on a control message. */
#define LINK_CTL_TIMEOUT_MS 1000

/* A snapshot: the publishing server's epoch (a number drawn at its start: a relay that
 * sees it change knows the server restarted), seq, stream, the three state variants and
 * the extras (net.h net_snap). */
size_t link_snap_size(const net_snap *p);
void link_snap_encode(const net_snap *p, uint64_t epoch, uint8_t *buf);
/* Into a pool snapshot (its buffers' capacities checked); 0 or GALE_E_FORMAT/RANGE. */
int link_snap_decode(const uint8_t *buf, size_t len, net_snap *p, uint64_t *epoch,
                     gale_err *err);

/* A control message with the connection state the server's handler reads and changes. */
typedef struct link_ctl {
    net_peer peer;      /* id, addr, role, resync, stream */
    const char *text;   /* request: the message; reply: the text to send back (or NULL) */
    size_t text_len;
    int rc;             /* reply: 0 or a close code */
    const char *why;    /* reply: the reason of a close */
} link_ctl;

/* *out is malloc'd; 0 or GALE_E_NOMEM. */
int link_ctl_encode(const link_ctl *c, uint8_t **out, size_t *len, gale_err *err);
/* Pointers into buf (text and why not NUL-terminated beyond their lengths: why is copied
 * to why_buf). 0 or GALE_E_FORMAT. */
int link_ctl_decode(const uint8_t *buf, size_t len, link_ctl *c, char *addr_buf, size_t addr_cap,
                    char *why_buf, size_t why_cap, gale_err *err);

/* gale.info reply: the server's buffer sizes and assets (hash and length). */
typedef struct link_info {
    uint64_t snap_cap, extra_cap;
    uint32_t max_streams;
    uint32_t n_assets;
    net_asset assets[64]; /* bytes not filled: fetched with gale.asset */
} link_info;

int link_info_encode(const link_info *in, uint8_t *buf, size_t cap, size_t *len);
int link_info_decode(const uint8_t *buf, size_t len, link_info *out, gale_err *err);

/* gale.scene: what a relay needs to select a client's view as the server does
 * (view_select.h, server/SERVER.md "Relays"): the tree bases, the margin a tree counts in
 * view within, the grid cell, the modes sent past lod_m and the view streams' periodic
 * keyframe. Larger than one NATS message on big scenes, so it is fetched in
 * LINK_ASSET_CHUNK pieces: a request is a u64 offset, the reply up to a chunk from there
 * (empty past the end); the message opens with its own length. */
typedef struct link_scene {
    uint32_t n_trees;
    uint32_t lod_modes; /* modes of a tree past lod_m (SRV_LOD_MODES) */
    uint32_t key_every; /* snapshots between a stream's periodic keyframes */
    uint32_t max_modes; /* the most modes of any species (sizes the relay's decoder) */
    float margin_m;     /* a tree counts as in view within this of the region */
    float cell_m;       /* the selection grid's cell (speed only: no result depends on it) */
    float *pos;         /* [n_trees * 3] tree bases; encode: borrowed, decode: owned (free) */
} link_scene;

size_t link_scene_size(uint32_t n_trees);
void link_scene_encode(const link_scene *sc, uint8_t *buf);
/* The message's length from its first 8 bytes (0 when fewer). */
uint64_t link_scene_total(const uint8_t *buf, size_t len);
/* sc->pos is malloc'd. 0, GALE_E_FORMAT or GALE_E_NOMEM. */
int link_scene_decode(const uint8_t *buf, size_t len, link_scene *sc, gale_err *err);

#endif
