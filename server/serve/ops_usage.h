/* The exhibit's usage counters (server/SERVER.md "Usage counters"): kiosk sessions, the
 * time visitors spent, the Saffir-Simpson classes they dialled, the scenarios they chose
 * and the languages kiosks showed. Nothing personal: no address, no connection id, no
 * time of day. Kept across restarts in a file (ops_usage_load, ops_usage_save). Not
 * locked: its owner serialises calls (srv_ops.c). */
#ifndef GALE_OPS_USAGE_H
#define GALE_OPS_USAGE_H

#include <stdbool.h>
#include <stddef.h>

#include "err.h"
#include "wind_scale.h"

#define OPS_USAGE_MAX_NAMES 32 /* scenarios (a welcome lists 32 at most) and languages */
#define OPS_USAGE_NAME 64      /* bytes of a name, with its NUL */
#define OPS_USAGE_OTHER "other" /* what counts once a table is full */

typedef struct ops_count {
    char name[OPS_USAGE_NAME];
    unsigned long long n;
} ops_count;

typedef struct ops_usage {
    unsigned long long sessions;   /* kiosk sessions begun */
    double dwell_s;                /* summed length of the ended sessions [s] */
    unsigned long long categories[WIND_SCALE_SS_COUNT]; /* dials by class (wind_scale.h) */
    int n_replays;
    ops_count replays[OPS_USAGE_MAX_NAMES]; /* scenario picks by name */
    int n_langs;
    ops_count langs[OPS_USAGE_MAX_NAMES];   /* languages kiosks reported */
    /* the session under way (not kept in the file) */
    bool in_session;
    double start_s, last_s;        /* its first and last interaction [s, monotonic] */
    int last_class;                /* class of its last counted dial; -1 none yet */
} ops_usage;

/* Zero counters, no session. */
void ops_usage_init(ops_usage *u);
/* A kiosk interaction at now_s: begins a session when none is under way or the last
 * interaction is more than idle_s ago (ending that one first); true when it began one. */
bool ops_usage_interaction(ops_usage *u, double now_s, double idle_s);
/* Ends the session under way once idle_s passed since its last interaction; returns true
 * when one ended. */
bool ops_usage_poll(ops_usage *u, double now_s, double idle_s);
/* Ends the session under way at its last interaction (shutdown). */
void ops_usage_end(ops_usage *u);
/* A dialled sustained wind [m/s]: counted into its class when that differs from the last
 * dial counted in this session (a drag through one class counts once). */
void ops_usage_dial(ops_usage *u, double speed_ms);
/* One more of name in t[*n] (a new name takes a free row; with none left, "other"). */
void ops_usage_count(ops_count *t, int *n, const char *name);
/* The session's dwell so far [s] (0 without one). */
double ops_usage_open_dwell_s(const ops_usage *u);

/* Loads the counters of path into *u. A missing file is no error (*u zero, *found false);
 * one that cannot be read or does not parse is GALE_E_IO / GALE_E_PARSE naming the file,
 * line:col and key, and *u is left zero. */
int ops_usage_load(ops_usage *u, const char *path, bool *found, gale_err *err);
/* The file's text[len] (not NUL-terminated necessarily) into *u, named name in messages;
 * what ops_usage_load does once it has read the file. *u zero on failure. */
int ops_usage_parse(ops_usage *u, const char *name, const char *text, size_t len, gale_err *err);
/* Writes the counters to path atomically: path.tmp written and fsync'ed, renamed over
 * path, the folder fsync'ed; the old file stays whole until the rename. */
int ops_usage_save(const ops_usage *u, const char *path, gale_err *err);
/* The counters as a JSON object's text (malloc'd; NULL without memory), the file's
 * format: {"format":"gale-usage","version":1,"sessions":...}. */
char *ops_usage_json(const ops_usage *u);
/* Appends the counters as Prometheus text rows to out[cap] from *len; false when full. */
bool ops_usage_prom(const ops_usage *u, char *out, size_t cap, size_t *len);

#endif
