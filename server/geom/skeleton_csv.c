/* Skeleton CSV import: `id,parent,x,y,z,radius`, a header line first, one node a line,
 * parent -1 for the single root, z up, metres. Every fault is reported with the file
 * name and line; the nodes are reordered parents-first (breadth-first from the root),
 * moved so the root sits at the origin, and given branch orders (the child that
 * continues its parent's direction best keeps the parent's order). */
#include "skeleton.h"

#include <ctype.h>
#include <stddef.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* 10^6 rows: 100 times the largest benchmark tree; the bake could not use more. */
#define CSV_MAX_NODES 1000000
/* Coordinates beyond a kilometre are not a tree (and lose float precision). */
#define CSV_MAX_COORD 1000.0
/* Radii below a micrometre are no wood: they would also underflow to 0 as float32 and
 * make the element stiffness singular. */
#define CSV_MIN_RADIUS 1e-6
/* Widest field kept for parsing and messages; a number needs far fewer characters. */
#define CSV_FIELD_MAX 64
/* Two nodes closer than this are a zero-length element [m]. */
#define CSV_MIN_EDGE 1e-6

typedef struct csv_row {
    long long id, parent;
    double x[3], r;
    int line;
} csv_row;

typedef struct csv_key {
    long long id;
    int row;
} csv_key;

static int key_cmp(const void *a, const void *b)
{
    const csv_key *p = a, *q = b;
    if (p->id != q->id) {
        return p->id < q->id ? -1 : 1;
    }
    return p->row < q->row ? -1 : (p->row > q->row);
}

/* Row index of id, or -1. */
static int find_id(const csv_key *keys, int n, long long id)
{
    int lo = 0, hi = n - 1;
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2;
        if (keys[mid].id == id) {
            return keys[mid].row;
        }
        if (keys[mid].id < id) {
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    return -1;
}

/* Splits one line [p, end) into trimmed fields copied into f[6][CSV_FIELD_MAX]; returns
 * the number of fields, or -1 when a field is too long (then *toolong is its index). */
static int split_fields(const char *p, const char *end, char f[6][CSV_FIELD_MAX], int *toolong)
{
    int n = 0;
    for (;;) {
        const char *c = p;
        while (c < end && *c != ',') {
            c++;
        }
        const char *a = p, *b = c;
        while (a < b && (*a == ' ' || *a == '\t')) {
            a++;
        }
        while (b > a && (b[-1] == ' ' || b[-1] == '\t' || b[-1] == '\r')) {
            b--;
        }
        if (n < 6) {
            if ((size_t)(b - a) >= CSV_FIELD_MAX) {
                *toolong = n;
                return -1;
            }
            for (ptrdiff_t i = 0; i < b - a; i++) {
                /* a NUL byte would end the C string early: make it a bad character */
                f[n][i] = a[i] ? a[i] : '\x01';
            }
            f[n][b - a] = '\0';
        }
        n++;
        if (c >= end) {
            return n;
        }
        p = c + 1;
    }
}

/* Printable copy of a field for messages. */
static const char *shown(const char *s, char *buf, size_t cap)
{
    size_t j = 0;
    for (size_t i = 0; s[i] && j + 1 < cap; i++) {
        buf[j++] = isprint((unsigned char)s[i]) ? s[i] : '?';
    }
    buf[j] = '\0';
    return buf;
}

static int parse_int(const char *s, long long *out)
{
    if (!*s) {
        return -1;
    }
    char *e = NULL;
    errno = 0;
    long long v = strtoll(s, &e, 10);
    if (errno || !e || *e) {
        return -2;
    }
    *out = v;
    return 0;
}

static int parse_num(const char *s, double *out)
{
    if (!*s) {
        return -1;
    }
    char *e = NULL;
    errno = 0;
    double v = strtod(s, &e);
    if (!e || *e || e == s) {
        return -2;
    }
    if (!isfinite(v)) {
        return -3;
    }
    *out = v;
    return 0;
}

static int is_blank(const char *p, const char *end)
{
    for (; p < end; p++) {
        if (*p != ' ' && *p != '\t' && *p != '\r') {
            return 0;
        }
    }
    return 1;
}

int skeleton_parse_csv(const char *text, size_t len, const char *name, skeleton *s, gale_err *err)
{
    static const char *const cols[6] = { "id", "parent", "x", "y", "z", "radius" };
    memset(s, 0, sizeof *s);
    if (!name) {
        name = "<csv>";
    }
    csv_row *rows = NULL;
    csv_key *keys = NULL;
    int *queue = NULL, *new_of = NULL, *first_child = NULL, *next_sib = NULL;
    int nrows = 0, cap = 0, rc = GALE_OK;
    int line = 0, header_seen = 0;
    char f[6][CSV_FIELD_MAX], show[CSV_FIELD_MAX];
    const char *p = text, *end = text + len;

    while (p < end) {
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        const char *le = eol ? eol : end;
        line++;
        const char *lp = p;
        p = eol ? eol + 1 : end;
        if (is_blank(lp, le) || *lp == '#') {
            continue; /* blank lines and # comments */
        }
        int toolong = 0;
        int nf = split_fields(lp, le, f, &toolong);
        if (nf < 0) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: field longer than %d characters", name,
                           line, header_seen ? cols[toolong] : "header", CSV_FIELD_MAX - 1);
            goto fail;
        }
        if (!header_seen) {
            int ok = nf == 6;
            for (int i = 0; ok && i < 6; i++) {
                ok = strcasecmp(f[i], cols[i]) == 0;
            }
            if (!ok) {
                long long dummy;
                rc = gale_errf(err, GALE_E_PARSE,
                               "%s:%d: header missing: expected \"id,parent,x,y,z,radius\" as the "
                               "first line, got %s\"%s...\"",
                               name, line, nf >= 1 && parse_int(f[0], &dummy) == 0 ? "data " : "",
                               shown(f[0], show, sizeof show));
                goto fail;
            }
            header_seen = 1;
            continue;
        }
        if (nf != 6) {
            rc = gale_errf(err, GALE_E_PARSE,
                           "%s:%d: expected 6 columns (id,parent,x,y,z,radius), got %d", name, line,
                           nf);
            goto fail;
        }
        if (nrows == CSV_MAX_NODES) {
            rc = gale_errf(err, GALE_E_RANGE, "%s:%d: more than %d nodes", name, line,
                           CSV_MAX_NODES);
            goto fail;
        }
        if (nrows == cap) {
            int ncap = cap ? 2 * cap : 256;
            csv_row *nr = realloc(rows, (size_t)ncap * sizeof *nr);
            if (!nr) {
                rc = gale_errf(err, GALE_E_NOMEM, "%s:%d: out of memory", name, line);
                goto fail;
            }
            rows = nr;
            cap = ncap;
        }
        csv_row *r = &rows[nrows];
        r->line = line;
        for (int c = 0; c < 2; c++) {
            long long v = 0;
            int e = parse_int(f[c], &v);
            if (e == -1) {
                rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: missing", name, line, cols[c]);
                goto fail;
            }
            if (e != 0) {
                rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: expected an integer, got \"%s\"",
                               name, line, cols[c], shown(f[c], show, sizeof show));
                goto fail;
            }
            if (c == 0 && (v < 0 || v > INT32_MAX)) {
                rc = gale_errf(err, GALE_E_RANGE, "%s:%d: id: expected 0..%d, got %lld", name, line,
                               INT32_MAX, v);
                goto fail;
            }
            if (c == 1 && (v < -1 || v > INT32_MAX)) {
                rc = gale_errf(err, GALE_E_RANGE,
                               "%s:%d: parent: expected -1 (root) or a node id, got %lld", name,
                               line, v);
                goto fail;
            }
            if (c == 0) {
                r->id = v;
            } else {
                r->parent = v;
            }
        }
        for (int c = 2; c < 6; c++) {
            double v = 0.0;
            int e = parse_num(f[c], &v);
            if (e == -1) {
                rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: missing", name, line, cols[c]);
                goto fail;
            }
            if (e == -2) {
                rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: expected a number, got \"%s\"", name,
                               line, cols[c], shown(f[c], show, sizeof show));
                goto fail;
            }
            if (e == -3) {
                rc = gale_errf(err, GALE_E_PARSE, "%s:%d: %s: expected a finite number, got \"%s\"",
                               name, line, cols[c], shown(f[c], show, sizeof show));
                goto fail;
            }
            if (c < 5 && fabs(v) > CSV_MAX_COORD) {
                rc = gale_errf(err, GALE_E_RANGE, "%s:%d: %s: expected |%s| <= %g m, got %g", name,
                               line, cols[c], cols[c], CSV_MAX_COORD, v);
                goto fail;
            }
            if (c == 5 && v > 0.0 && v < CSV_MIN_RADIUS) {
                rc = gale_errf(err, GALE_E_RANGE, "%s:%d: radius: expected at least %g m, got %g",
                               name, line, CSV_MIN_RADIUS, v);
                goto fail;
            }
            if (c == 5 && !(v > 0.0 && v <= CSV_MAX_COORD)) {
                rc = gale_errf(err, GALE_E_RANGE, "%s:%d: radius: expected > 0, got %g", name, line,
                               v);
                goto fail;
            }
            if (c < 5) {
                r->x[c - 2] = v;
            } else {
                r->r = v;
            }
        }
        nrows++;
    }
    if (!header_seen) {
        rc = gale_errf(
            err, GALE_E_PARSE,
            "%s: empty file: expected a header line \"id,parent,x,y,z,radius\" and nodes", name);
        goto fail;
    }
    if (nrows == 0) {
        rc = gale_errf(err, GALE_E_PARSE, "%s: no nodes after the header", name);
        goto fail;
    }

    /* ids: sorted copy for duplicates and parent lookup */
    keys = malloc((size_t)nrows * sizeof *keys);
    if (!keys) {
        rc = gale_errf(err, GALE_E_NOMEM, "%s: out of memory for %d nodes", name, nrows);
        goto fail;
    }
    for (int i = 0; i < nrows; i++) {
        keys[i].id = rows[i].id;
        keys[i].row = i;
    }
    qsort(keys, (size_t)nrows, sizeof *keys, key_cmp);
    {
        /* within equal ids rows are ascending: the first is the original, the second the
         * duplicate; report the duplicate that comes first in the file */
        int dup_row = -1, first_row = -1;
        for (int i = 1; i < nrows; i++) {
            if (keys[i].id == keys[i - 1].id && (i < 2 || keys[i - 2].id != keys[i].id) &&
                (dup_row < 0 || keys[i].row < dup_row)) {
                dup_row = keys[i].row;
                first_row = keys[i - 1].row;
            }
        }
        if (dup_row >= 0) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: duplicate id %lld (first on line %d)", name,
                           rows[dup_row].line, rows[dup_row].id, rows[first_row].line);
            goto fail;
        }
    }
    int root = -1;
    for (int i = 0; i < nrows; i++) {
        csv_row *r = &rows[i];
        if (r->parent == -1) {
            if (root >= 0) {
                rc = gale_errf(err, GALE_E_PARSE,
                               "%s:%d: several roots: node %lld has parent -1, as has node %lld "
                               "on line %d",
                               name, r->line, r->id, rows[root].id, rows[root].line);
                goto fail;
            }
            root = i;
        } else if (r->parent == r->id) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: cycle: node %lld is its own parent", name,
                           r->line, r->id);
            goto fail;
        } else if (find_id(keys, nrows, r->parent) < 0) {
            rc = gale_errf(err, GALE_E_PARSE, "%s:%d: unknown parent %lld of node %lld", name,
                           r->line, r->parent, r->id);
            goto fail;
        }
    }
    if (root < 0) {
        rc = gale_errf(err, GALE_E_PARSE, "%s: no root: expected one node with parent -1", name);
        goto fail;
    }

    /* children lists (file order), then breadth-first from the root */
    queue = malloc((size_t)nrows * sizeof *queue);
    new_of = malloc((size_t)nrows * sizeof *new_of);
    first_child = malloc((size_t)nrows * sizeof *first_child);
    next_sib = malloc((size_t)nrows * sizeof *next_sib);
    if (!queue || !new_of || !first_child || !next_sib) {
        rc = gale_errf(err, GALE_E_NOMEM, "%s: out of memory for %d nodes", name, nrows);
        goto fail;
    }
    for (int i = 0; i < nrows; i++) {
        first_child[i] = -1;
        next_sib[i] = -1;
        new_of[i] = -1;
    }
    for (int i = nrows - 1; i >= 0; i--) {
        if (i == root) {
            continue;
        }
        int pr = find_id(keys, nrows, rows[i].parent);
        next_sib[i] = first_child[pr];
        first_child[pr] = i;
    }
    int head = 0, tail = 0;
    queue[tail++] = root;
    new_of[root] = 0;
    while (head < tail) {
        int u = queue[head++];
        for (int c = first_child[u]; c >= 0; c = next_sib[c]) {
            new_of[c] = tail;
            queue[tail++] = c;
        }
    }
    if (tail < nrows) {
        /* an unreached node leads into a cycle: walk its parents until one repeats */
        int u = -1;
        for (int i = 0; i < nrows && u < 0; i++) {
            if (new_of[i] < 0) {
                u = i;
            }
        }
        for (int step = 0; step < nrows; step++) {
            u = find_id(keys, nrows, rows[u].parent);
        }
        /* u is now on the cycle; report its member that comes first in the file */
        int best = u;
        for (int v = find_id(keys, nrows, rows[u].parent); v != u;
             v = find_id(keys, nrows, rows[v].parent)) {
            if (rows[v].line < rows[best].line) {
                best = v;
            }
        }
        rc = gale_errf(err, GALE_E_PARSE,
                       "%s:%d: cycle: node %lld (parent %lld) never reaches the root", name,
                       rows[best].line, rows[best].id, rows[best].parent);
        goto fail;
    }
    for (int i = 0; i < nrows; i++) {
        if (i == root) {
            continue;
        }
        const csv_row *r = &rows[i], *q = &rows[find_id(keys, nrows, r->parent)];
        double d = sqrt((r->x[0] - q->x[0]) * (r->x[0] - q->x[0]) +
                        (r->x[1] - q->x[1]) * (r->x[1] - q->x[1]) +
                        (r->x[2] - q->x[2]) * (r->x[2] - q->x[2]));
        if (d < CSV_MIN_EDGE) {
            rc = gale_errf(err, GALE_E_RANGE,
                           "%s:%d: zero-length edge: node %lld sits at the position of its parent "
                           "%lld (line %d)",
                           name, r->line, r->id, q->id, q->line);
            goto fail;
        }
    }

    rc = skeleton_alloc(s, nrows, err);
    if (rc != 0) {
        goto fail;
    }
    s->src_id = malloc((size_t)nrows * sizeof *s->src_id);
    if (!s->src_id) {
        rc = gale_errf(err, GALE_E_NOMEM, "%s: out of memory for %d nodes", name, nrows);
        goto fail;
    }
    for (int k = 0; k < nrows; k++) {
        const csv_row *r = &rows[queue[k]];
        s->src_id[k] = (int)r->id;
        s->parent[k] = k == 0 ? -1 : new_of[find_id(keys, nrows, r->parent)];
        for (int c = 0; c < 3; c++) {
            s->pos[3 * k + c] = (float)(r->x[c] - rows[root].x[c]);
        }
        s->radius[k] = (float)r->r;
    }
    for (int c = 0; c < 3; c++) {
        s->src_origin[c] = (float)rows[root].x[c];
    }
    /* branch orders: among a node's children the one whose direction continues the
     * node's own (vertical for the root) best keeps its order; the others add one */
    for (int k = 0; k < nrows; k++) {
        int u = queue[k];
        double in[3] = { 0.0, 0.0, 1.0 };
        if (k > 0) {
            int pk = s->parent[k];
            for (int c = 0; c < 3; c++) {
                in[c] = (double)s->pos[3 * k + c] - (double)s->pos[3 * pk + c];
            }
        }
        double best = -2.0;
        int best_c = -1;
        for (int c = first_child[u]; c >= 0; c = next_sib[c]) {
            int ck = new_of[c];
            double d[3], dl = 0.0, il = 0.0, dot = 0.0;
            for (int j = 0; j < 3; j++) {
                d[j] = (double)s->pos[3 * ck + j] - (double)s->pos[3 * k + j];
                dl += d[j] * d[j];
                il += in[j] * in[j];
                dot += d[j] * in[j];
            }
            double cosang = dot / sqrt(dl * il);
            if (cosang > best) {
                best = cosang;
                best_c = ck;
            }
        }
        for (int c = first_child[u]; c >= 0; c = next_sib[c]) {
            int ck = new_of[c];
            s->order[ck] = s->order[k] + (ck == best_c ? 0 : 1);
        }
    }
    rc = GALE_OK;
    goto done;
fail:
    skeleton_fini(s);
done:
    free(rows);
    free(keys);
    free(queue);
    free(new_of);
    free(first_child);
    free(next_sib);
    return rc;
}

int skeleton_load_csv(const char *path, skeleton *s, gale_err *err)
{
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    /* ~60 bytes a row: 64 MiB holds the row limit */
    const size_t max_bytes = (size_t)64 << 20;
    size_t cap = 65536, len = 0;
    char *buf = malloc(cap);
    while (buf) {
        if (len == cap) {
            if (cap >= max_bytes) {
                free(buf);
                fclose(f);
                return gale_errf(err, GALE_E_RANGE, "%s: larger than %zu bytes", path, max_bytes);
            }
            char *nb = realloc(buf, cap * 2);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            break;
        }
    }
    int rerr = ferror(f);
    fclose(f);
    if (!buf) {
        return gale_errf(err, GALE_E_NOMEM, "%s: out of memory", path);
    }
    if (rerr) {
        free(buf);
        return gale_errf(err, GALE_E_IO, "%s: read error", path);
    }
    int rc = skeleton_parse_csv(buf, len, path, s, err);
    free(buf);
    return rc;
}
