/* Pure parsers of the HTTP request header values net_http.c acts on: Range (RFC 7233
 * §2.1, §3.1), and the entity-tag lists of If-None-Match and If-Range (RFC 7232 §2.3,
 * §3.2; RFC 7233 §3.2). No lws, no allocation: bytes in, a verdict out. */
#ifndef GALE_HTTP_HDR_H
#define GALE_HTTP_HDR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* What a Range header asks of a body of len bytes. */
typedef enum http_hdr_range_kind {
    HTTP_HDR_RANGE_NONE,          /* absent, another unit or not valid syntax: serve the whole (200) */
    HTTP_HDR_RANGE_ONE,           /* one satisfiable range [first, last]: 206 */
    HTTP_HDR_RANGE_MULTI,         /* two or more ranges: gale serves the whole (200) */
    HTTP_HDR_RANGE_UNSATISFIABLE, /* one range that selects no byte of the body: 416 */
} http_hdr_range_kind;

/* Parses the value v[n] of a Range header (v need not be NUL-terminated; NULL with n 0 is
 * an absent header) against a body of len bytes. "bytes=a-b", "bytes=a-" and "bytes=-k"
 * (the last k bytes); the unit is case-insensitive, list elements may carry spaces or tabs
 * around commas and empty elements are skipped. A last position past the body is clamped
 * to len - 1, a suffix longer than the body selects all of it; a first position at or past
 * len, or a suffix of 0, is unsatisfiable. b < a is invalid syntax (NONE), and so is any
 * element that is not digits, "-" and digits. Numbers saturate at UINT64_MAX. For ONE,
 * *first <= *last < len on return; otherwise both are 0. */
http_hdr_range_kind http_hdr_range(const char *v, size_t n, uint64_t len, uint64_t *first,
                                   uint64_t *last);

/* Whether the header value v[n] (If-None-Match or If-Range: "*", or a comma-separated list
 * of entity tags "x" or W/"x") names the entity tag whose opaque text (without quotes) is
 * tag. weak: the weak comparison of If-None-Match (W/ ignored, "*" matches); otherwise the
 * strong one of If-Range (a W/ tag or "*" never matches, nor does a date). A value that is
 * not valid syntax matches nothing. */
bool http_hdr_etag_match(const char *v, size_t n, const char *tag, bool weak);

#endif
