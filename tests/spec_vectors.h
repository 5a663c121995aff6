/* The test vectors of protocol/PROTOCOL.md read from the spec file itself (PROTOCOL.md
 * "Test vectors", "Marker"): every fenced block opened by "```gale-hex NAME" (a hex dump,
 * one "OFFSET: b b ..." line per up to 16 bytes) or "```gale-json NAME" (one line: a
 * control message, byte for byte). A test takes the bytes from here, so the spec is the
 * one copy. Header-only, for the tests (a browser client parses the same blocks). */
#ifndef GALE_SPEC_VECTORS_H
#define GALE_SPEC_VECTORS_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SPEC_MAX_VECTORS 64
#define SPEC_MAX_BYTES 2048 /* the longest vector's bytes or JSON text */
#define SPEC_NAME_MAX 32

typedef struct spec_vector {
    char name[SPEC_NAME_MAX]; /* e.g. "KEYFRAME", "WALL-SYNC" */
    int json;                 /* 1: gale-json (text), 0: gale-hex (bytes) */
    int line;                 /* line of the opening fence (1-based) */
    size_t len;               /* bytes */
    uint8_t bytes[SPEC_MAX_BYTES + 1]; /* the bytes; a JSON text is also NUL-terminated */
} spec_vector;

typedef struct spec_file {
    spec_vector v[SPEC_MAX_VECTORS];
    int n;
    char err[256]; /* "PROTOCOL.md:LINE: what" when spec_load failed */
} spec_file;

static inline int spec_hexval(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

/* One hex dump line "OFFSET: b b b" (lowercase hex, OFFSET the index of its first byte,
 * 1..16 bytes, single spaces) appended to v; 0, or -1 with why. */
static inline int spec_hex_line(spec_vector *v, const char *s, char *why, size_t why_cap)
{
    size_t off = 0;
    int digits = 0;
    for (; spec_hexval(*s) >= 0; s++, digits++) {
        off = off * 16 + (size_t)spec_hexval(*s);
    }
    if (digits < 2 || s[0] != ':') {
        snprintf(why, why_cap, "expected \"OFFSET: bytes\" (lowercase hex)");
        return -1;
    }
    if (off != v->len) {
        snprintf(why, why_cap, "offset: expected %zx, got %zx", v->len, off);
        return -1;
    }
    s++;
    int n = 0;
    while (*s == ' ') {
        int hi = spec_hexval(s[1]), lo = hi < 0 ? -1 : spec_hexval(s[2]);
        if (hi < 0 || lo < 0 || (s[3] != ' ' && s[3] != '\0')) {
            snprintf(why, why_cap, "byte %d: expected two lowercase hex digits", n);
            return -1;
        }
        if (v->len >= SPEC_MAX_BYTES) {
            snprintf(why, why_cap, "more than %d bytes", SPEC_MAX_BYTES);
            return -1;
        }
        v->bytes[v->len++] = (uint8_t)(hi * 16 + lo);
        s += 3;
        n++;
    }
    if (*s != '\0' || n < 1 || n > 16) {
        snprintf(why, why_cap, "expected 1..16 bytes after the offset, got %d%s", n,
                 *s ? " and trailing text" : "");
        return -1;
    }
    return 0;
}

/* Whether an unmarked line looks like a hex dump line ("00: 47 41"): such a block must
 * carry a marker. */
static inline int spec_looks_hex(const char *s)
{
    return spec_hexval(s[0]) >= 0 && spec_hexval(s[1]) >= 0 && s[2] == ':' && s[3] == ' ' &&
           spec_hexval(s[4]) >= 0 && spec_hexval(s[5]) >= 0;
}

/* Reads every vector of the markdown file at path into f. 0, or -1 with f->err naming the
 * line: a file that cannot be read, a malformed block, a name used twice, an info string
 * "gale-..." of another form, or an unmarked block that holds a hex dump. */
static inline int spec_load(spec_file *f, const char *path)
{
    memset(f, 0, sizeof *f);
    FILE *fp = fopen(path, "r");
    if (!fp) {
        snprintf(f->err, sizeof f->err, "%s: cannot open", path);
        return -1;
    }
    char line[8192], why[160];
    int ln = 0, rc = 0;
    spec_vector *cur = NULL;
    int in_fence = 0, body_lines = 0;
    why[0] = '\0';
    while (!rc && fgets(line, sizeof line, fp)) {
        ln++;
        size_t L = strlen(line);
        if (L && line[L - 1] == '\n') {
            line[--L] = '\0';
        } else if (!feof(fp)) {
            snprintf(why, sizeof why, "line longer than %zu bytes", sizeof line - 2);
            rc = -1;
            break;
        }
        if (!in_fence) {
            if (strncmp(line, "```", 3) != 0) {
                continue;
            }
            in_fence = 1;
            body_lines = 0;
            const char *info = line + 3;
            if (strncmp(info, "gale-", 5) != 0) {
                cur = NULL;
                continue;
            }
            int json = strncmp(info, "gale-json ", 10) == 0;
            if (!json && strncmp(info, "gale-hex ", 9) != 0) {
                snprintf(why, sizeof why, "marker: expected \"gale-hex NAME\" or \"gale-json NAME\", got \"%.40s\"", info);
                rc = -1;
                break;
            }
            const char *name = info + (json ? 10 : 9);
            size_t nl = strlen(name);
            int ok = nl >= 1 && nl < SPEC_NAME_MAX && name[0] >= 'A' && name[0] <= 'Z';
            for (size_t i = 0; ok && i < nl; i++) {
                char c = name[i];
                ok = (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-';
            }
            if (!ok) {
                snprintf(why, sizeof why, "vector name: expected [A-Z][A-Z0-9-]* of at most %d bytes, got \"%.40s\"",
                         SPEC_NAME_MAX - 1, name);
                rc = -1;
                break;
            }
            for (int i = 0; i < f->n; i++) {
                if (!strcmp(f->v[i].name, name)) {
                    snprintf(why, sizeof why, "vector %s: named twice (first at line %d)", name,
                             f->v[i].line);
                    rc = -1;
                }
            }
            if (rc) {
                break;
            }
            if (f->n == SPEC_MAX_VECTORS) {
                snprintf(why, sizeof why, "more than %d vectors", SPEC_MAX_VECTORS);
                rc = -1;
                break;
            }
            cur = &f->v[f->n++];
            memcpy(cur->name, name, nl + 1);
            cur->json = json;
            cur->line = ln;
            continue;
        }
        if (strncmp(line, "```", 3) == 0) {
            if (cur && (cur->len == 0 || (cur->json && body_lines != 1))) {
                snprintf(why, sizeof why, "vector %s: %s", cur->name,
                         cur->json ? "expected exactly one line of JSON" : "no bytes");
                rc = -1;
                break;
            }
            in_fence = 0;
            cur = NULL;
            continue;
        }
        body_lines++;
        if (!cur) {
            if (spec_looks_hex(line)) {
                snprintf(why, sizeof why, "a hex dump without a \"gale-hex NAME\" marker");
                rc = -1;
            }
            continue;
        }
        if (cur->json) {
            if (L > SPEC_MAX_BYTES || body_lines > 1) {
                snprintf(why, sizeof why, "vector %s: expected one line of at most %d bytes",
                         cur->name, SPEC_MAX_BYTES);
                rc = -1;
                break;
            }
            memcpy(cur->bytes, line, L + 1);
            cur->len = L;
        } else if (spec_hex_line(cur, line, why, sizeof why)) {
            /* room for the whole line, then cut to why's size */
            char w2[sizeof why + SPEC_NAME_MAX + 16];
            snprintf(w2, sizeof w2, "vector %s: %s", cur->name, why);
            memcpy(why, w2, sizeof why - 1);
            why[sizeof why - 1] = 0;
            rc = -1;
        }
    }
    if (!rc && in_fence) {
        snprintf(why, sizeof why, "a fenced block left open at the end of the file");
        rc = -1;
    }
    fclose(fp);
    if (rc) {
        snprintf(f->err, sizeof f->err, "%s:%d: %s", path, ln, why);
    }
    return rc;
}

/* The vector named name, or NULL. */
static inline const spec_vector *spec_find(const spec_file *f, const char *name)
{
    for (int i = 0; i < f->n; i++) {
        if (!strcmp(f->v[i].name, name)) {
            return &f->v[i];
        }
    }
    return NULL;
}

/* protocol/PROTOCOL.md of this source tree. */
#define SPEC_PROTOCOL_PATH GALE_SOURCE_DIR "/protocol/PROTOCOL.md"

#endif
