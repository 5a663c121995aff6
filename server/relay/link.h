/* What gale-server and gale-relay say to each other over NATS (server/SERVER.md "Relays"):
 * the subjects and the byte layout of each message. The server publishes every encoded
 * snapshot once on its stream's subject; relays answer clients from those and forward
 * every control message to the server by request/reply. Little-endian, wire_cursor.h. */
#ifndef GALE_LINK_H
#define GALE_LINK_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "net.h"

#define LINK_SUBJ_SNAP "gale.snap"     /* + ".<stream>": one net_snap per snapshot */
#define LINK_SUBJ_CTL "gale.ctl"       /* request: a client's control message; reply: verdict */
#define LINK_SUBJ_CLOSED "gale.closed" /* a relayed connection that said hello closed */
#define LINK_SUBJ_INFO "gale.info"     /* request: sizes and the asset list */
#define LINK_SUBJ_ASSET "gale.asset"   /* request: a chunk of one asset's bytes */

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

#endif
