/* Range and entity-tag header values (RFC 7233 §2.1, RFC 7232 §2.3): see http_hdr.h.
 * Each parser walks v[0, n) once with a cursor and never reads past n. */
#include "http_hdr.h"

#include <string.h>

static bool is_ows(char c)
{
    return c == ' ' || c == '\t';
}

static bool is_digit(char c)
{
    return c >= '0' && c <= '9';
}

/* Digits at v[*i, n) as a number saturated at UINT64_MAX; false when there is none. */
static bool parse_u64(const char *v, size_t n, size_t *i, uint64_t *out)
{
    uint64_t x = 0;
    size_t start = *i;
    while (*i < n && is_digit(v[*i])) {
        uint64_t d = (uint64_t)(v[*i] - '0');
        x = x > (UINT64_MAX - d) / 10 ? UINT64_MAX : x * 10 + d;
        (*i)++;
    }
    *out = x;
    return *i > start;
}

http_hdr_range_kind http_hdr_range(const char *v, size_t n, uint64_t len, uint64_t *first,
                                   uint64_t *last)
{
    static const char unit[] = "bytes=";
    const size_t unit_len = sizeof unit - 1;
    *first = *last = 0;
    if (!v || n < unit_len) {
        return HTTP_HDR_RANGE_NONE;
    }
    for (size_t k = 0; k < unit_len; k++) {
        char c = v[k];
        if (c >= 'A' && c <= 'Z') {
            c = (char)(c - 'A' + 'a');
        }
        if (c != unit[k]) {
            return HTTP_HDR_RANGE_NONE;
        }
    }
    size_t i = unit_len;
    int count = 0;
    uint64_t a = 0, b = 0;
    bool suffix = false, open = false;
    for (;;) {
        while (i < n && is_ows(v[i])) {
            i++;
        }
        if (i < n && v[i] != ',') {
            /* one byte-range-spec or suffix-byte-range-spec */
            uint64_t x = 0, y = 0;
            bool sfx = false, opn = false;
            if (v[i] == '-') {
                i++;
                if (!parse_u64(v, n, &i, &y)) {
                    return HTTP_HDR_RANGE_NONE;
                }
                sfx = true;
            } else {
                if (!parse_u64(v, n, &i, &x) || i >= n || v[i] != '-') {
                    return HTTP_HDR_RANGE_NONE;
                }
                i++;
                opn = !parse_u64(v, n, &i, &y);
                if (!opn && y < x) {
                    return HTTP_HDR_RANGE_NONE;
                }
            }
            if (++count == 1) {
                a = x;
                b = y;
                suffix = sfx;
                open = opn;
            }
            while (i < n && is_ows(v[i])) {
                i++;
            }
        }
        if (i >= n) {
            break;
        }
        if (v[i] != ',') {
            return HTTP_HDR_RANGE_NONE;
        }
        i++;
    }
    if (count == 0) {
        return HTTP_HDR_RANGE_NONE;
    }
    if (count > 1) {
        return HTTP_HDR_RANGE_MULTI;
    }
    if (suffix) {
        if (b == 0 || len == 0) {
            return HTTP_HDR_RANGE_UNSATISFIABLE;
        }
        *first = b >= len ? 0 : len - b;
        *last = len - 1;
        return HTTP_HDR_RANGE_ONE;
    }
    if (a >= len) {
        return HTTP_HDR_RANGE_UNSATISFIABLE;
    }
    *first = a;
    *last = open || b >= len ? len - 1 : b;
    return HTTP_HDR_RANGE_ONE;
}

/* One entity-tag at v[*i, n): sets *weak and the opaque text's span [*o, *o + *olen);
 * false when v[*i] does not start a valid one. */
static bool parse_etag(const char *v, size_t n, size_t *i, bool *weak, size_t *o, size_t *olen)
{
    *weak = false;
    if (*i + 1 < n && v[*i] == 'W' && v[*i + 1] == '/') {
        *weak = true;
        *i += 2;
    }
    if (*i >= n || v[*i] != '"') {
        return false;
    }
    (*i)++;
    *o = *i;
    while (*i < n && v[*i] != '"') {
        unsigned char c = (unsigned char)v[*i];
        if (c < 0x21 || c == 0x7f) {
            return false; /* etagc: %x21 / %x23-7E / obs-text */
        }
        (*i)++;
    }
    if (*i >= n) {
        return false;
    }
    *olen = *i - *o;
    (*i)++;
    return true;
}

bool http_hdr_etag_match(const char *v, size_t n, const char *tag, bool weak)
{
    if (!v || !tag) {
        return false;
    }
    const size_t tag_len = strlen(tag);
    size_t i = 0;
    while (i < n && is_ows(v[i])) {
        i++;
    }
    size_t end = n;
    while (end > i && is_ows(v[end - 1])) {
        end--;
    }
    if (end - i == 1 && v[i] == '*') {
        return weak;
    }
    bool found = false;
    int count = 0;
    for (;;) {
        while (i < end && is_ows(v[i])) {
            i++;
        }
        if (i < end && v[i] != ',') {
            bool w;
            size_t o, olen;
            if (!parse_etag(v, end, &i, &w, &o, &olen)) {
                return false;
            }
            count++;
            if ((weak || !w) && olen == tag_len && !memcmp(v + o, tag, tag_len)) {
                found = true;
            }
            while (i < end && is_ows(v[i])) {
                i++;
            }
        }
        if (i >= end) {
            break;
        }
        if (v[i] != ',' || !weak) {
            return false; /* If-Range holds one entity-tag, not a list */
        }
        i++;
    }
    return found && (weak || count == 1);
}
