/* The exhibit's operation beside the simulation (server/SERVER.md "Status", "Opening
 * hours", "Usage counters"): the opening hours and what clients are told of them (the
 * schedule notice), the kiosks' reported language and audio device, the usage counters
 * and their file, and the /status document. Its own thread polls the clock once every
 * SRV_OPS_POLL_MS; the rest is called from the control handler and the HTTP thread. */
#ifndef GALE_SRV_OPS_H
#define GALE_SRV_OPS_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "net.h"
#include "ops_hours.h"

#define SRV_OPS_POLL_MS 200     /* the schedule is followed to within this */
#define SRV_OPS_SAVE_S 60.0     /* the usage file is written this often, and at shutdown */
#define SRV_OPS_MAX_KIOSKS 64   /* kiosks whose kiosk_state is shown; more are counted only */

typedef struct srv_ops srv_ops;

typedef struct srv_ops_desc {
    ops_hours hours;            /* .set false: always open */
    const char *state_file;     /* the usage counters' file; NULL: counted, not kept */
    double idle_s;              /* a kiosk session ends this long after its last interaction */
    bool quiet;                 /* no log lines but errors */
} srv_ops_desc;

/* Loads the state file (a missing one starts at zero); NULL with err naming the file and
 * key when it cannot be read or parsed (the file is left as it is). */
srv_ops *srv_ops_create(const srv_ops_desc *d, gale_err *err);
/* Starts the poll thread; net and its metrics are borrowed until srv_ops_stop. Sends the
 * first schedule notice. */
int srv_ops_start(srv_ops *o, net_server *net, const atomic_uint *tick, gale_err *err);
/* Ends the poll thread, ends the session under way and writes the state file. */
void srv_ops_stop(srv_ops *o);
/* NULL is a no-op. */
void srv_ops_destroy(srv_ops *o);

/* Open now by the hours (any thread; the simulation idles while false). */
bool srv_ops_open(const srv_ops *o);

/* Control thread: a visitor's kiosk control message (wind, reset) was accepted from
 * connection conn. A session it begins counts the language that kiosk shows. */
void srv_ops_interaction(srv_ops *o, uint32_t conn);
void srv_ops_dial(srv_ops *o, double speed_ms);
void srv_ops_pick(srv_ops *o, const char *scenario);
/* A kiosk's report: its first on a connection is the kiosk's own (no interaction, no
 * count); a later one that changes the language is a visitor's choice (an interaction,
 * and the new language counted). */
void srv_ops_kiosk_state(srv_ops *o, uint32_t conn, const char *lang, const char *audio);
void srv_ops_conn_closed(srv_ops *o, uint32_t conn);

/* Service thread: the /status body (malloc'd JSON of *len bytes; NULL without memory). */
char *srv_ops_status(void *o, size_t *len);
/* Service thread: the usage rows for /metrics (malloc'd text of *len bytes). */
char *srv_ops_metrics(void *o, size_t *len);

#endif
