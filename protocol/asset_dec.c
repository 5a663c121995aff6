/* The asset file's reader: asset_decode checks the header and both checksums, then reads
 * each section through a bounds-checked cursor, checking every count, index and value
 * as it goes; the first fault names the field and its byte offset. asset_fini frees what
 * it allocated. */
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "asset_int.h"
#include "hash.h"

/* ---- reader: a cursor with a sticky bad flag; the first fault is kept for the message ---- */

typedef struct asset_reader {
    const uint8_t *buf;
    size_t pos, len;
    bool bad;
    int code;          /* GALE_E_* of the first fault */
    const char *field; /* field of the first fault */
    size_t at;         /* its byte offset in the file */
    char why[128];
} asset_reader;

static void r_fail(asset_reader *r, int code, const char *field, size_t at, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

static void r_fail(asset_reader *r, int code, const char *field, size_t at, const char *fmt, ...)
{
    if (r->bad) {
        return;
    }
    r->bad = true;
    r->code = code;
    r->field = field;
    r->at = at;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->why, sizeof r->why, fmt, ap);
    va_end(ap);
}

static bool r_need(asset_reader *r, size_t n, const char *field)
{
    if (r->bad) {
        return false;
    }
    if (r->len - r->pos < n) {
        r_fail(r, GALE_E_FORMAT, field, r->pos, "truncated: need %zu bytes, %zu left", n,
               r->len - r->pos);
        return false;
    }
    return true;
}

static uint32_t r_u32(asset_reader *r, const char *field)
{
    if (!r_need(r, 4, field)) {
        return 0;
    }
    const uint8_t *p = r->buf + r->pos;
    uint32_t v = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    r->pos += 4;
    return v;
}

static uint64_t r_u64(asset_reader *r, const char *field)
{
    uint64_t lo = r_u32(r, field);
    uint64_t hi = r_u32(r, field);
    return lo | hi << 32;
}

static float r_f32(asset_reader *r, const char *field)
{
    size_t at = r->pos;
    uint32_t v = r_u32(r, field);
    float f;
    memcpy(&f, &v, sizeof f);
    if (!r->bad && !isfinite(f)) {
        r_fail(r, GALE_E_FORMAT, field, at, "not a finite number (bits 0x%08x)", v);
        return 0.0f;
    }
    return f;
}

static void r_f32s(asset_reader *r, float *dst, size_t n, const char *field)
{
    if (!r_need(r, 4 * n, field)) {
        return;
    }
    for (size_t i = 0; i < n && !r->bad; i++) {
        dst[i] = r_f32(r, field);
    }
}

static void r_u32s(asset_reader *r, uint32_t *dst, size_t n, const char *field)
{
    if (!r_need(r, 4 * n, field)) {
        return;
    }
    for (size_t i = 0; i < n; i++) {
        dst[i] = r_u32(r, field);
    }
}

/* A count: at most `max` (the limit's reason is beside its #define), and no more items of
 * `item_bytes` each than the bytes left could hold. */
static uint32_t r_count(asset_reader *r, const char *field, uint32_t max, size_t item_bytes)
{
    size_t at = r->pos;
    uint32_t n = r_u32(r, field);
    if (r->bad) {
        return 0;
    }
    if (n > max) {
        r_fail(r, GALE_E_FORMAT, field, at, "count %u over the limit %u", n, max);
        return 0;
    }
    if (item_bytes && (size_t)n > (r->len - r->pos) / item_bytes) {
        r_fail(r, GALE_E_FORMAT, field, at, "count %u needs %zu bytes, %zu left", n,
               (size_t)n * item_bytes, r->len - r->pos);
        return 0;
    }
    return n;
}

static void *r_alloc(asset_reader *r, size_t n, size_t size, const char *field)
{
    if (r->bad) {
        return NULL;
    }
    void *p = calloc(n ? n : 1, size);
    if (!p) {
        r_fail(r, GALE_E_NOMEM, field, r->pos, "out of memory for %zu items", n);
    }
    return p;
}

/* ---- decode ---- */

/* Reads a section header; checks the tag (any tag when section < 0: an optional section,
 * its tag then in *tag) and that the stated length fits. Returns the offset where the
 * section must end. */
static size_t r_section(asset_reader *r, int section, uint32_t *tag_out)
{
    size_t at = r->pos;
    uint32_t tag = r_u32(r, "section tag");
    uint64_t slen = r_u64(r, "section length");
    if (r->bad) {
        return 0;
    }
    if (tag_out) {
        *tag_out = tag;
    }
    if (section >= 0 && tag != asset_tags[section]) {
        r_fail(r, GALE_E_FORMAT, "section tag", at, "expected %s (0x%08x), got 0x%08x",
               asset_tag_names[section], asset_tags[section], tag);
        return 0;
    }
    if (slen > (uint64_t)(r->len - r->pos)) {
        r_fail(r, GALE_E_FORMAT, section >= 0 ? asset_tag_names[section] : "section length",
               at + 4, "section length %llu, only %zu bytes left", (unsigned long long)slen,
               r->len - r->pos);
        return 0;
    }
    return r->pos + (size_t)slen;
}

static void r_section_end(asset_reader *r, int section, size_t end)
{
    if (!r->bad && r->pos != end) {
        r_fail(r, GALE_E_FORMAT, asset_tag_names[section], r->pos,
               "section length disagrees with its content (ends at %zu, content at %zu)", end,
               r->pos);
    }
}

static void r_check_unit(asset_reader *r, const float *v, size_t n, const char *field, size_t base)
{
    for (size_t i = 0; i < n && !r->bad; i++) {
        double x = v[3 * i], y = v[3 * i + 1], z = v[3 * i + 2];
        double l = sqrt(x * x + y * y + z * z);
        if (fabs(l - 1.0) > 1e-3) {
            r_fail(r, GALE_E_FORMAT, field, base + 12 * i,
                   "item %zu: not a unit vector (length %g)", i, l);
        }
    }
}

static void r_meta(asset_reader *r, asset *a)
{
    size_t end = r_section(r, 0, NULL);
    size_t at = r->pos;
    if (r_need(r, 64, "species")) {
        memcpy(a->species, r->buf + r->pos, 64);
        r->pos += 64;
        if (!memchr(a->species, 0, 64)) {
            r_fail(r, GALE_E_FORMAT, "species", at, "name not NUL-terminated within 64 bytes");
        }
    }
    a->source_hash = r_u64(r, "source_hash");
    at = r->pos;
    uint32_t plen = r_count(r, "params_json length", ASSET_MAX_PARAMS, 1);
    a->params_json = r_alloc(r, (size_t)plen + 1, 1, "params_json");
    if (r->bad) {
        return;
    }
    memcpy(a->params_json, r->buf + r->pos, plen);
    a->params_json[plen] = '\0';
    if (memchr(a->params_json, 0, plen)) {
        r_fail(r, GALE_E_FORMAT, "params_json", at + 4, "contains a NUL byte");
    }
    r->pos += plen;
    r_section_end(r, 0, end);
}

static void r_skel(asset_reader *r, asset *a)
{
    size_t end = r_section(r, 1, NULL);
    size_t at = r->pos;
    /* per node: parent, 3 coordinates, radius */
    a->n_nodes = r_count(r, "n_nodes", ASSET_MAX_NODES, 20);
    if (!r->bad && a->n_nodes == 0) {
        r_fail(r, GALE_E_FORMAT, "n_nodes", at, "expected at least 1 node, got 0");
    }
    a->height_m = r_f32(r, "height_m");
    size_t nn = a->n_nodes;
    a->parent = r_alloc(r, nn, sizeof *a->parent, "parent");
    a->rest = r_alloc(r, 3 * nn, sizeof *a->rest, "rest");
    a->radius = r_alloc(r, nn, sizeof *a->radius, "radius");
    if (r->bad) {
        return;
    }
    at = r->pos;
    for (size_t i = 0; i < nn && !r->bad; i++) {
        uint32_t p = r_u32(r, "parent");
        bool ok = i == 0 ? p == 0xffffffffu : p < i;
        if (!ok && !r->bad) {
            r_fail(r, GALE_E_FORMAT, "parent", at + 4 * i, "node %zu: parent %d, expected %s", i,
                   (int)p, i == 0 ? "-1 for the root" : "an earlier node");
        }
        a->parent[i] = i == 0 ? -1 : (int32_t)p;
    }
    r_f32s(r, a->rest, 3 * nn, "rest");
    at = r->pos;
    r_f32s(r, a->radius, nn, "radius");
    for (size_t i = 0; i < nn && !r->bad; i++) {
        if (!(a->radius[i] > 0.0f)) {
            r_fail(r, GALE_E_FORMAT, "radius", at + 4 * i, "node %zu: radius %g, expected > 0", i,
                   (double)a->radius[i]);
        }
    }
    r_section_end(r, 1, end);
}

static void r_modes(asset_reader *r, asset *a)
{
    size_t end = r_section(r, 2, NULL);
    size_t at = r->pos;
    a->n_modes = r_count(r, "n_modes", ASSET_MAX_MODES, 20);
    if (!r->bad && (uint64_t)a->n_modes * a->n_nodes > ASSET_MAX_MODE_NODES) {
        r_fail(r, GALE_E_FORMAT, "n_modes", at, "%u modes x %u nodes over the limit %u", a->n_modes,
               a->n_nodes, ASSET_MAX_MODE_NODES);
    }
    size_t nm = a->n_modes, nmn = nm * a->n_nodes;
    /* phi and phi_rot must fit in what is left before allocating them */
    if (!r->bad && 24 * nmn > r->len - r->pos) {
        r_fail(r, GALE_E_FORMAT, "n_modes", at, "%zu modes need %zu bytes, %zu left", nm, 24 * nmn,
               r->len - r->pos);
    }
    a->omega = r_alloc(r, nm, sizeof(float), "omega");
    a->gamma = r_alloc(r, nm, sizeof(float), "gamma");
    a->wind_basis = r_alloc(r, 3 * nm, sizeof(float), "wind_basis");
    a->phi = r_alloc(r, 3 * nmn, sizeof(float), "phi");
    a->phi_rot = r_alloc(r, 3 * nmn, sizeof(float), "phi_rot");
    at = r->pos;
    r_f32s(r, a->omega, nm, "omega");
    for (size_t i = 1; i < nm && !r->bad; i++) {
        if (a->omega[i] < a->omega[i - 1]) {
            r_fail(r, GALE_E_FORMAT, "omega", at + 4 * i, "mode %zu: not ascending (%g after %g)",
                   i, (double)a->omega[i], (double)a->omega[i - 1]);
        }
    }
    r_f32s(r, a->gamma, nm, "gamma");
    r_f32s(r, a->wind_basis, 3 * nm, "wind_basis");
    r_f32s(r, a->phi, 3 * nmn, "phi");
    r_f32s(r, a->phi_rot, 3 * nmn, "phi_rot");
    r_section_end(r, 2, end);
}

static void r_corr(asset_reader *r, asset *a)
{
    size_t end = r_section(r, 3, NULL);
    size_t at = r->pos;
    uint32_t has = r_u32(r, "has_correction");
    if (!r->bad && has > 1) {
        r_fail(r, GALE_E_FORMAT, "has_correction", at, "expected 0 or 1, got %u", has);
    }
    if (!r->bad && has) {
        size_t nm = a->n_modes, nmn = nm * a->n_nodes;
        if (24 * nmn + 8 * nm > r->len - r->pos) {
            r_fail(r, GALE_E_FORMAT, "corr_v", r->pos, "needs %zu bytes, %zu left",
                   24 * nmn + 8 * nm, r->len - r->pos);
        }
        a->corr_v = r_alloc(r, 3 * nmn, sizeof(float), "corr_v");
        a->corr_w = r_alloc(r, 3 * nmn, sizeof(float), "corr_w");
        a->corr_a = r_alloc(r, nm, sizeof(float), "corr_a");
        a->corr_b = r_alloc(r, nm, sizeof(float), "corr_b");
        r_f32s(r, a->corr_v, 3 * nmn, "corr_v");
        r_f32s(r, a->corr_w, 3 * nmn, "corr_w");
        r_f32s(r, a->corr_a, nm, "corr_a");
        r_f32s(r, a->corr_b, nm, "corr_b");
    }
    r_section_end(r, 3, end);
}

static void r_mesh(asset_reader *r, asset *a)
{
    size_t end = r_section(r, 4, NULL);
    /* per vertex: position, normal, two bones, weight */
    a->n_verts = r_count(r, "n_verts", ASSET_MAX_VERTS, 36);
    size_t nv = a->n_verts;
    a->mesh_pos = r_alloc(r, 3 * nv, sizeof(float), "mesh_pos");
    a->mesh_normal = r_alloc(r, 3 * nv, sizeof(float), "mesh_normal");
    a->mesh_bone = r_alloc(r, 2 * nv, sizeof(uint32_t), "mesh_bone");
    a->mesh_weight = r_alloc(r, nv, sizeof(float), "mesh_weight");
    r_f32s(r, a->mesh_pos, 3 * nv, "mesh_pos");
    size_t at = r->pos;
    r_f32s(r, a->mesh_normal, 3 * nv, "mesh_normal");
    if (!r->bad) {
        r_check_unit(r, a->mesh_normal, nv, "mesh_normal", at);
    }
    at = r->pos;
    r_u32s(r, a->mesh_bone, 2 * nv, "mesh_bone");
    for (size_t i = 0; i < 2 * nv && !r->bad; i++) {
        if (a->mesh_bone[i] >= a->n_nodes) {
            r_fail(r, GALE_E_FORMAT, "mesh_bone", at + 4 * i, "vertex %zu: node %u, expected < %u",
                   i / 2, a->mesh_bone[i], a->n_nodes);
        }
    }
    at = r->pos;
    r_f32s(r, a->mesh_weight, nv, "mesh_weight");
    for (size_t i = 0; i < nv && !r->bad; i++) {
        if (!(a->mesh_weight[i] >= 0.0f && a->mesh_weight[i] <= 1.0f)) {
            r_fail(r, GALE_E_FORMAT, "mesh_weight", at + 4 * i,
                   "vertex %zu: weight %g, expected in [0, 1]", i, (double)a->mesh_weight[i]);
        }
    }
    a->n_indices = r_count(r, "n_indices", ASSET_MAX_INDICES, 4);
    a->mesh_index = r_alloc(r, a->n_indices, sizeof(uint32_t), "mesh_index");
    at = r->pos;
    r_u32s(r, a->mesh_index, a->n_indices, "mesh_index");
    for (size_t i = 0; i < a->n_indices && !r->bad; i++) {
        if (a->mesh_index[i] >= a->n_verts) {
            r_fail(r, GALE_E_FORMAT, "mesh_index", at + 4 * i,
                   "index %zu: vertex %u, expected < %u", i, a->mesh_index[i], a->n_verts);
        }
    }
    at = r->pos;
    a->n_lods = r_u32(r, "n_lods");
    if (!r->bad && (a->n_lods > ASSET_MAX_LODS || (a->n_lods == 0 && a->n_indices > 0))) {
        r_fail(r, GALE_E_FORMAT, "n_lods", at, "expected 1..%d, got %u", ASSET_MAX_LODS, a->n_lods);
    }
    for (uint32_t l = 0; l < ASSET_MAX_LODS && !r->bad; l++) {
        at = r->pos;
        a->lod_first[l] = r_u32(r, "lod_first");
        a->lod_count[l] = r_u32(r, "lod_count");
        uint64_t last = (uint64_t)a->lod_first[l] + a->lod_count[l];
        if (!r->bad && (last > a->n_indices || a->lod_count[l] % 3 != 0 ||
                        (l >= a->n_lods && (a->lod_first[l] | a->lod_count[l]) != 0))) {
            r_fail(r, GALE_E_FORMAT, "lod_first", at,
                   "LOD %u: [%u, +%u) not whole triangles within %u indices (or set past n_lods)",
                   l, a->lod_first[l], a->lod_count[l], a->n_indices);
        }
    }
    r_section_end(r, 4, end);
}

static void r_leaves(asset_reader *r, asset *a)
{
    size_t end = r_section(r, 5, NULL);
    /* per leaf: node, offset, normal, size */
    a->n_leaves = r_count(r, "n_leaves", ASSET_MAX_LEAVES, 32);
    size_t nl = a->n_leaves;
    a->leaf_node = r_alloc(r, nl, sizeof(uint32_t), "leaf_node");
    a->leaf_offset = r_alloc(r, 3 * nl, sizeof(float), "leaf_offset");
    a->leaf_normal = r_alloc(r, 3 * nl, sizeof(float), "leaf_normal");
    a->leaf_size = r_alloc(r, nl, sizeof(float), "leaf_size");
    size_t at = r->pos;
    r_u32s(r, a->leaf_node, nl, "leaf_node");
    for (size_t i = 0; i < nl && !r->bad; i++) {
        if (a->leaf_node[i] >= a->n_nodes) {
            r_fail(r, GALE_E_FORMAT, "leaf_node", at + 4 * i, "leaf %zu: node %u, expected < %u", i,
                   a->leaf_node[i], a->n_nodes);
        }
    }
    r_f32s(r, a->leaf_offset, 3 * nl, "leaf_offset");
    at = r->pos;
    r_f32s(r, a->leaf_normal, 3 * nl, "leaf_normal");
    if (!r->bad) {
        r_check_unit(r, a->leaf_normal, nl, "leaf_normal", at);
    }
    at = r->pos;
    r_f32s(r, a->leaf_size, nl, "leaf_size");
    for (size_t i = 0; i < nl && !r->bad; i++) {
        if (!(a->leaf_size[i] > 0.0f)) {
            r_fail(r, GALE_E_FORMAT, "leaf_size", at + 4 * i, "leaf %zu: size %g, expected > 0", i,
                   (double)a->leaf_size[i]);
        }
    }
    r_section_end(r, 5, end);
}

static void r_look(asset_reader *r, asset *a)
{
    size_t end = r_section(r, 6, NULL);
    r_f32s(r, a->bark_rgb, 3, "bark_rgb");
    r_f32s(r, a->leaf_rgb, 3, "leaf_rgb");
    size_t at = r->pos;
    a->leaf_shape = r_u32(r, "leaf_shape");
    if (!r->bad && a->leaf_shape > 2) {
        r_fail(r, GALE_E_FORMAT, "leaf_shape", at, "expected 0..2, got %u", a->leaf_shape);
    }
    r_section_end(r, 6, end);
}

static int u64_cmp(const void *x, const void *y)
{
    const uint64_t p = *(const uint64_t *)x, q = *(const uint64_t *)y;
    return p < q ? -1 : p > q;
}

/* SRID body from r->pos to end: the CSV position of the root, then one id per node, all
 * distinct. */
static void r_srid(asset_reader *r, asset *a, size_t end)
{
    r_f32s(r, a->source_origin, 3, "source_origin");
    size_t at = r->pos;
    uint32_t n = r_count(r, "n_source_ids", ASSET_MAX_NODES, 4);
    if (!r->bad && n != a->n_nodes) {
        r_fail(r, GALE_E_FORMAT, "n_source_ids", at, "count %u, expected n_nodes (%u)", n,
               a->n_nodes);
    }
    size_t nn = a->n_nodes;
    a->source_id = r_alloc(r, nn, sizeof *a->source_id, "source_id");
    at = r->pos;
    r_u32s(r, a->source_id, nn, "source_id");
    /* distinct: sort (id, node) pairs; report the duplicate that comes first by node */
    uint64_t *keys = r_alloc(r, nn, sizeof *keys, "source_id");
    if (keys) {
        for (size_t i = 0; i < nn; i++) {
            keys[i] = (uint64_t)a->source_id[i] << 32 | (uint64_t)i;
        }
        qsort(keys, nn, sizeof *keys, u64_cmp);
        size_t dup = nn, first = 0;
        for (size_t i = 1; i < nn; i++) {
            size_t node = (size_t)(keys[i] & 0xffffffffu);
            if (keys[i] >> 32 == keys[i - 1] >> 32 && node < dup) {
                dup = node;
                first = (size_t)(keys[i - 1] & 0xffffffffu);
            }
        }
        if (dup < nn) {
            r_fail(r, GALE_E_FORMAT, "source_id", at + 4 * dup,
                   "node %zu: id %u, already the id of node %zu (ids must be distinct)", dup,
                   a->source_id[dup], first);
        }
        free(keys);
    }
    r_section_end(r, ASSET_SECTION_SRID, end);
}

/* SRES body from r->pos to end: the static correction, one translation per node for each
 * of the ASSET_STATIC_COLS wind-basis columns. */
static void r_sres(asset_reader *r, asset *a, size_t end)
{
    const size_t at = r->pos;
    const uint32_t nc = r_u32(r, "n_static_cols");
    if (!r->bad && nc != ASSET_STATIC_COLS) {
        r_fail(r, GALE_E_FORMAT, "n_static_cols", at, "count %u, expected %u (one per wind-basis column)",
               nc, ASSET_STATIC_COLS);
    }
    const size_t n = 3u * ASSET_STATIC_COLS * (size_t)a->n_nodes;
    if (r_need(r, 4 * n, "static_res")) {
        a->static_res = r_alloc(r, n, sizeof *a->static_res, "static_res");
        r_f32s(r, a->static_res, n, "static_res");
    }
    r_section_end(r, ASSET_SECTION_SRES, end);
}

/* The optional sections after LOOK (version 2 on): SRID and SRES at most once each; a tag
 * this build does not know is skipped by its length (ASSET.md "Optional sections"). */
static void r_optional(asset_reader *r, asset *a)
{
    while (!r->bad && r->pos < r->len) {
        size_t at = r->pos;
        uint32_t tag = 0;
        size_t end = r_section(r, -1, &tag);
        if (r->bad) {
            return;
        }
        if (tag == asset_tags[ASSET_SECTION_SRES]) {
            if (a->static_res) {
                r_fail(r, GALE_E_FORMAT, "SRES", at, "second SRES section (at most one)");
            } else {
                r_sres(r, a, end);
            }
        } else if (tag != asset_tags[ASSET_SECTION_SRID]) {
            r->pos = end;
        } else if (a->source_id) {
            r_fail(r, GALE_E_FORMAT, "SRID", at, "second SRID section (at most one)");
        } else {
            r_srid(r, a, end);
        }
    }
}

int asset_decode(const uint8_t *buf, size_t len, const char *name, asset *a, gale_err *err)
{
    memset(a, 0, sizeof *a);
    if (!name) {
        name = "<asset>";
    }
    if (!buf || len < ASSET_HEADER_BYTES) {
        return gale_errf(err, GALE_E_FORMAT,
                         "%s: header at byte 0: truncated: need %u bytes, got %zu", name,
                         ASSET_HEADER_BYTES, buf ? len : 0);
    }
    if (memcmp(buf, asset_magic, 4) != 0) {
        return gale_errf(err, GALE_E_FORMAT,
                         "%s: magic at byte 0: expected \"GAST\", got %02x %02x %02x %02x", name,
                         buf[0], buf[1], buf[2], buf[3]);
    }
    asset_reader r = { .buf = buf, .len = len, .pos = 4 };
    uint32_t version = r_u32(&r, "version");
    uint64_t payload = r_u64(&r, "payload_length");
    uint32_t pcrc = r_u32(&r, "payload_crc32");
    uint32_t hcrc = r_u32(&r, "header_crc32");
    uint32_t hcrc_now = hash_crc32(buf, 20);
    if (hcrc != hcrc_now) {
        return gale_errf(err, GALE_E_CHECKSUM,
                         "%s: header_crc32 at byte 20: checksum mismatch: stored 0x%08x, "
                         "computed 0x%08x",
                         name, hcrc, hcrc_now);
    }
    if (version < ASSET_VERSION_MIN || version > ASSET_VERSION) {
        return gale_errf(err, GALE_E_VERSION, "%s: version at byte 4: expected %d..%d, got %u",
                         name, ASSET_VERSION_MIN, ASSET_VERSION, version);
    }
    if (payload != (uint64_t)(len - ASSET_HEADER_BYTES)) {
        return gale_errf(err, GALE_E_FORMAT,
                         "%s: payload_length at byte 8: header states %llu bytes, file has %zu%s",
                         name, (unsigned long long)payload, len - ASSET_HEADER_BYTES,
                         payload > (uint64_t)(len - ASSET_HEADER_BYTES) ? " (truncated)"
                                                                        : " (trailing bytes)");
    }
    uint32_t pcrc_now = hash_crc32(buf + ASSET_HEADER_BYTES, len - ASSET_HEADER_BYTES);
    if (pcrc != pcrc_now) {
        return gale_errf(err, GALE_E_CHECKSUM,
                         "%s: payload_crc32 at byte 16: checksum mismatch: stored 0x%08x, "
                         "computed 0x%08x (corrupt file)",
                         name, pcrc, pcrc_now);
    }
    r_meta(&r, a);
    r_skel(&r, a);
    r_modes(&r, a);
    r_corr(&r, a);
    r_mesh(&r, a);
    r_leaves(&r, a);
    r_look(&r, a);
    if (version >= 2) {
        r_optional(&r, a);
    } else if (!r.bad && r.pos != len) {
        r_fail(&r, GALE_E_FORMAT, "end", r.pos,
               "%zu bytes after the last section (version 1 has no optional sections)",
               len - r.pos);
    }
    if (r.bad) {
        asset_fini(a);
        return gale_errf(err, r.code, "%s: %s at byte %zu: %s", name, r.field, r.at, r.why);
    }
    return GALE_OK;
}

void asset_fini(asset *a)
{
    if (!a) {
        return;
    }
    free(a->params_json);
    free(a->parent);
    free(a->rest);
    free(a->radius);
    free(a->source_id);
    free(a->static_res);
    free(a->omega);
    free(a->gamma);
    free(a->wind_basis);
    free(a->phi);
    free(a->phi_rot);
    free(a->corr_v);
    free(a->corr_w);
    free(a->corr_a);
    free(a->corr_b);
    free(a->mesh_pos);
    free(a->mesh_normal);
    free(a->mesh_bone);
    free(a->mesh_weight);
    free(a->mesh_index);
    free(a->leaf_node);
    free(a->leaf_offset);
    free(a->leaf_normal);
    free(a->leaf_size);
    memset(a, 0, sizeof *a);
}
