/* The JSON kit of gale's two JSON readers, the control channel (ctl_*.c) and the server's
 * config files (server/common/cfg.c): a length-bounded cJSON parse with line:col from its
 * offset, typed getters that check type, range and length, unknown-key checks, key paths.
 * Every failure reads "where: key.path: what: expected, got". Private to gale. */
#ifndef GALE_JSON_H
#define GALE_JSON_H

#include <stdbool.h>
#include <stddef.h>

#include <cjson/cJSON.h>

#include "err.h"

/* How a reader words its failures. Each reader's texts are pinned by its tests and, for
 * the wire, seen by clients (PROTOCOL.md "Errors and close codes"), so the kit keeps both:
 *   WIRE: absent required key "missing: expected a number"; unknown key `P: unknown key
 *         "k"` (P the object's path); numbers shown exactly (%.17g); a non-finite number
 *         reported against its range; string limits in bytes; a repeated key is not
 *         checked (the first one counts); a child of the wrong type "wrong type: ...".
 *   FILE: absent required key "required key missing"; unknown key "P.k: unknown key";
 *         numbers shown short (%g); a non-finite number "expected a finite number";
 *         string limits in characters; a repeated key "P.k: duplicate key". */
enum json_voice {
    JSON_VOICE_WIRE = 0,
    JSON_VOICE_FILE = 1,
};

typedef struct json_rd {
    const char *where; /* first word of every message: "ctl" or the file name */
    int voice;         /* enum json_voice */
    gale_err *err;     /* where failures go; may be NULL */
} json_rd;

/* Parses text[len] (need not be NUL-terminated) with cJSON, without requiring the input
 * to end after the value. Returns the tree (caller frees with cJSON_Delete) or NULL on a
 * syntax error; *at gets the offset cJSON stopped at (the failing byte, or the first byte
 * after the value; len when cJSON gives none). Reports nothing: each reader words its own
 * syntax errors (with json_line_col). */
cJSON *json_parse(const char *text, size_t len, size_t *at);

/* Offset of the first byte at or after `at` in text[len] that is not JSON whitespace
 * (space, tab, LF, CR: RFC 8259 section 2; a NUL byte is not whitespace); len when the
 * rest is all whitespace. A reader that takes one value per text refuses the text when
 * this, taken from json_parse's *at, is below len: trailing bytes are never ignored. */
size_t json_skip_space(const char *text, size_t len, size_t at);

/* 1-based line and column of byte offset at in text. */
void json_line_col(const char *text, size_t at, int *line, int *col);

/* Nesting depth of j (a scalar is 1), counted no further than limit + 1. */
int json_depth(const cJSON *j, int limit);

/* "a number", "a string", "a boolean", "null", "an array", "an object", "nothing" (NULL). */
const char *json_kind(const cJSON *j);
/* The same for a cJSON type constant (cJSON_Object, cJSON_Array, ...). */
const char *json_type_kind(int type);

/* Key paths: out = path + "." + key (just key when path is empty or NULL, just path when
 * key is NULL), and out = path + "[i]". Truncated to cap. */
void json_path(char *out, size_t cap, const char *path, const char *key);
void json_path_index(char *out, size_t cap, const char *path, int i);

/* Fails (GALE_E_PARSE) naming the first key of obj not in keys (NULL-terminated); FILE
 * voice also when obj is not an object or a key repeats. path names obj. */
int json_check_keys(const json_rd *r, const cJSON *obj, const char *path,
                    const char *const *keys);

/* The getters: obj[key], named path.key in messages. *has (may be NULL) says whether the
 * key was there. Absent and !required: 0, *out untouched (json_string writes def). Absent
 * and required: GALE_E_PARSE. Wrong type: GALE_E_PARSE. Out of range, not finite, not
 * integral or too long: GALE_E_RANGE. */
int json_number(const json_rd *r, const cJSON *obj, const char *path, const char *key,
                bool required, double lo, double hi, double *out, bool *has);
int json_int(const json_rd *r, const cJSON *obj, const char *path, const char *key,
             bool required, long long lo, long long hi, long long *out, bool *has);
int json_bool(const json_rd *r, const cJSON *obj, const char *path, const char *key,
              bool required, bool *out, bool *has);
/* Copies the string into out[cap] (NUL-terminated); absent: def, or "" when def is NULL. */
int json_string(const json_rd *r, const cJSON *obj, const char *path, const char *key,
                bool required, const char *def, char *out, size_t cap, bool *has);
/* An array of exactly n numbers, each finite and in [lo, hi], into out[n]. */
int json_vec(const json_rd *r, const cJSON *obj, const char *path, const char *key,
             bool required, int n, double lo, double hi, double *out, bool *has);
/* obj[key] of cJSON type `type` into *out (NULL when absent and !required). */
int json_child(const json_rd *r, const cJSON *obj, const char *path, const char *key,
               int type, bool required, const cJSON **out);

/* The range checks of the getters on a value already in hand, with the same messages:
 * for an encoder that refuses what a decoder would reject. */
int json_check_number(const json_rd *r, const char *path, const char *key, double lo,
                      double hi, double v);
int json_check_int(const json_rd *r, const char *path, const char *key, long long lo,
                   long long hi, double v);
/* s must hold a NUL within cap bytes (at most cap - 1 characters); s is read no further
 * than cap bytes. */
int json_check_string(const json_rd *r, const char *path, const char *key, const char *s,
                      size_t cap);

/* Adds number v under key to object o, as json_number reads it back: an integer of
 * magnitude ≤ 2^53 is written with all its digits (cJSON alone prints 2^53 − 1 as
 * 9.00719925474099e+15), any other value as cJSON prints it. Returns the new item, or NULL
 * when out of memory (o unchanged). */
cJSON *json_add_number(cJSON *o, const char *key, double v);

/* Fails with code and "where: " + the formatted text. */
int json_fail(const json_rd *r, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#endif
