/* gale error reporting: one polarity (0 ok, negative GALE_E_*), and a caller-owned
 * buffer that the failing callee fills with "where: what: expected, got". */
#ifndef GALE_ERR_H
#define GALE_ERR_H

enum {
    GALE_OK = 0,
    GALE_E_IO = -1,       /* open/read/write failed */
    GALE_E_PARSE = -2,    /* malformed text (JSON, CSV, numbers) */
    GALE_E_RANGE = -3,    /* a value outside its allowed range */
    GALE_E_NOMEM = -4,    /* allocation failed */
    GALE_E_FORMAT = -5,   /* binary layout wrong: truncated, bad magic, bad count */
    GALE_E_VERSION = -6,  /* a version this build does not read */
    GALE_E_CHECKSUM = -7, /* content does not match its checksum */
    GALE_E_NUMERIC = -8,  /* a numerical method failed (no convergence, not SPD) */
    GALE_E_STATE = -9,    /* called in a state that does not allow it */
    GALE_E_ARG = -10,     /* bad command-line or API argument */
};

typedef struct gale_err {
    int code;      /* GALE_OK or a GALE_E_* */
    char msg[256]; /* "where: what: expected, got" */
} gale_err;

/* Fills *err (when not NULL) with code and the formatted message; returns code, so a
 * failing function can end with `return gale_errf(err, GALE_E_RANGE, ...)`. */
int gale_errf(gale_err *err, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Resets *err to GALE_OK with an empty message. NULL is a no-op. */
void gale_err_clear(gale_err *err);

/* Name of a GALE_E_* code ("range", "io", ...), for logs. */
const char *gale_err_name(int code);

#endif
