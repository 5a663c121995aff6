/* The scenario library: every scenario file of one folder (configs/scenarios/), loaded at
 * start and keyed by file stem, so a kiosk may switch to any of them at run time and the
 * welcome lists them (server/SERVER.md "Scenarios"). The library owns its scenarios. */
#ifndef GALE_SCEN_LIB_H
#define GALE_SCEN_LIB_H

#include <stdbool.h>
#include <stddef.h>

#include "err.h"
#include "scenario.h"
#include "scene.h"

#define SCEN_LIB_MAX 32      /* scenarios in a library: what a welcome may list */
#define SCEN_LIB_NAME_MAX 64 /* a file stem, NUL included */

typedef struct scen_lib_entry {
    char name[SCEN_LIB_NAME_MAX]; /* the file's stem: "andrew1992" */
    scenario *scen;               /* owned */
} scen_lib_entry;

typedef struct scen_lib {
    int n;
    scen_lib_entry e[SCEN_LIB_MAX]; /* sorted by name */
    char dir[512];                  /* the folder read ("" when none was) */
} scen_lib;

/* Loads every *.json file of dir (sorted by name). A missing folder is an empty library;
 * a file that does not load, or more than SCEN_LIB_MAX files, fails naming the file. */
int scen_lib_load(scen_lib *l, const char *dir, gale_err *err);
/* Frees the scenarios; NULL or an empty library is a no-op. */
void scen_lib_fini(scen_lib *l);
/* The entry named name (matched as scen_lib_same_name: by stem, else by the scenario's
 * "name"), or -1. */
int scen_lib_find(const scen_lib *l, const char *name);
/* Letters and digits, lower case: "Andrew 1992" and "andrew1992" name one scenario. */
bool scen_lib_same_name(const char *a, const char *b);
/* The scene's playlist (sc->playlist) as the library's scenarios into out[SCENE_MAX_PLAYLIST]
 * (borrowed from l), their count in *n; fails naming the entry and the valid names. */
int scen_lib_playlist(const scen_lib *l, const scene *sc, scenario **out, int *n,
                      gale_err *err);
/* The stems, comma-separated, into out[cap] (cut with "..." when they do not fit). */
void scen_lib_names(const scen_lib *l, char *out, size_t cap);
/* A comma-separated list into out[cap]: whole when it fits, else the names that fit
 * and "...". */
void scen_lib_names_cut(const char *list, char *out, size_t cap);

#endif
