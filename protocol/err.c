/* gale error reporting: see err.h. */
#include "err.h"

#include <stdarg.h>
#include <stdio.h>

int gale_errf(gale_err *err, int code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}

void gale_err_clear(gale_err *err)
{
    if (err) {
        err->code = GALE_OK;
        err->msg[0] = '\0';
    }
}

const char *gale_err_name(int code)
{
    switch (code) {
    case GALE_OK: return "ok";
    case GALE_E_IO: return "io";
    case GALE_E_PARSE: return "parse";
    case GALE_E_RANGE: return "range";
    case GALE_E_NOMEM: return "nomem";
    case GALE_E_FORMAT: return "format";
    case GALE_E_VERSION: return "version";
    case GALE_E_CHECKSUM: return "checksum";
    case GALE_E_NUMERIC: return "numeric";
    case GALE_E_STATE: return "state";
    case GALE_E_ARG: return "arg";
    default: return "unknown";
    }
}
