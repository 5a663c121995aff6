/* Validated JSON configuration (species, scenarios, scenes): syntax errors carry
 * file:line:col, value errors carry the key path ("scene.trees[3].yaw_deg"); unknown
 * and repeated keys are errors. The config files' face of protocol/json.h. */
#ifndef GALE_CFG_H
#define GALE_CFG_H

#include <stdbool.h>
#include <stddef.h>

#include <cjson/cJSON.h>

#include "err.h"

typedef struct cfg_doc {
    char name[160]; /* file name or "<embedded>", for messages */
    cJSON *root;    /* owned */
} cfg_doc;

/* Parses text (len bytes, need not be NUL-terminated) into *d. A syntax error reports
 * name:line:col. The root must be an object, and nothing but JSON whitespace may follow
 * it (anything else is refused at its name:line:col). */
int cfg_parse(cfg_doc *d, const char *name, const char *text, size_t len, gale_err *err);
/* Reads a file and parses it; I/O errors name the path. */
int cfg_load(cfg_doc *d, const char *path, gale_err *err);
/* Frees the tree. NULL is a no-op. */
void cfg_fini(cfg_doc *d);

/* Fails naming the first key of obj (at key path `path`) that is not in allowed
 * (NULL-terminated list), or if obj is not an object. */
int cfg_check_keys(const cfg_doc *d, const cJSON *obj, const char *path,
                   const char *const *allowed, gale_err *err);

/* Reads obj[key] as a number in [min, max] into *out. Absent: *out = def when !required,
 * else an error. Wrong type, NaN or out of range: an error naming path.key, the expected
 * range and what was there. */
int cfg_number(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
               bool required, double def, double min, double max, double *out, gale_err *err);
/* The same for an integer (a number with no fractional part). */
int cfg_int(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
            bool required, long long def, long long min, long long max, long long *out,
            gale_err *err);
/* A boolean. */
int cfg_bool(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
             bool required, bool def, bool *out, gale_err *err);
/* A string copied into out[cap] (NUL-terminated; too long is an error). */
int cfg_string(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
               bool required, const char *def, char *out, size_t cap, gale_err *err);
/* An array of exactly n numbers, each in [min, max]. Absent: out keeps def[n] when
 * !required (def may be NULL to leave out untouched). */
int cfg_vec(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
            bool required, int n, const double *def, double min, double max, double *out,
            gale_err *err);
/* obj[key] when it is of the given cJSON type (cJSON_Object, cJSON_Array...), NULL when
 * absent and !required; otherwise an error. *found tells the two NULL cases apart. */
const cJSON *cfg_child(const cfg_doc *d, const cJSON *obj, const char *path, const char *key,
                       int type, bool required, bool *found, gale_err *err);
/* Joins a key path: out = path + "." + key (or just key when path is empty). */
void cfg_path(char *out, size_t cap, const char *path, const char *key);
/* Joins an array index: out = path + "[i]". */
void cfg_path_index(char *out, size_t cap, const char *path, int i);

#endif
