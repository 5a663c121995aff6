/* The asset file's writer: asset_encode checks the counts and arrays, writes the sections
 * in file order through a growing buffer, then the header with both checksums. */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "asset_int.h"
#include "hash.h"

/* ---- writer: a growing buffer with a sticky out-of-memory flag ---- */

typedef struct asset_writer {
    uint8_t *buf;
    size_t len, cap;
    bool oom;
} asset_writer;

static uint8_t *w_room(asset_writer *w, size_t n)
{
    if (w->oom) {
        return NULL;
    }
    if (w->cap - w->len < n) {
        size_t cap = w->cap ? w->cap : 4096;
        while (cap - w->len < n) {
            if (cap > SIZE_MAX / 2) {
                w->oom = true;
                return NULL;
            }
            cap *= 2;
        }
        uint8_t *b = realloc(w->buf, cap);
        if (!b) {
            w->oom = true;
            return NULL;
        }
        w->buf = b;
        w->cap = cap;
    }
    uint8_t *p = w->buf + w->len;
    w->len += n;
    return p;
}

static void put_u32_at(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xffu);
    p[1] = (uint8_t)((v >> 8) & 0xffu);
    p[2] = (uint8_t)((v >> 16) & 0xffu);
    p[3] = (uint8_t)((v >> 24) & 0xffu);
}

static void put_u64_at(uint8_t *p, uint64_t v)
{
    put_u32_at(p, (uint32_t)(v & 0xffffffffu));
    put_u32_at(p + 4, (uint32_t)(v >> 32));
}

static void w_u32(asset_writer *w, uint32_t v)
{
    uint8_t *p = w_room(w, 4);
    if (p) {
        put_u32_at(p, v);
    }
}

static void w_u64(asset_writer *w, uint64_t v)
{
    uint8_t *p = w_room(w, 8);
    if (p) {
        put_u64_at(p, v);
    }
}

static void w_f32(asset_writer *w, float f)
{
    uint32_t v;
    memcpy(&v, &f, sizeof v);
    w_u32(w, v);
}

static void w_bytes(asset_writer *w, const void *src, size_t n)
{
    uint8_t *p = w_room(w, n);
    if (p && n) {
        memcpy(p, src, n);
    }
}

static void w_f32s(asset_writer *w, const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        w_f32(w, v ? v[i] : 0.0f);
    }
}

static void w_u32s(asset_writer *w, const uint32_t *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        w_u32(w, v ? v[i] : 0u);
    }
}

/* Opens a section: tag and a length patched by w_end. Returns the length's offset. */
static size_t w_begin(asset_writer *w, int section)
{
    w_u32(w, asset_tags[section]);
    size_t at = w->len;
    w_u64(w, 0);
    return at;
}

static void w_end(asset_writer *w, size_t at)
{
    if (!w->oom) {
        put_u64_at(w->buf + at, (uint64_t)(w->len - at - 8));
    }
}

/* ---- encode ---- */

int asset_encode(const asset *a, uint8_t **out, size_t *len, gale_err *err)
{
    *out = NULL;
    *len = 0;
    if (a->n_nodes == 0 || a->n_nodes > ASSET_MAX_NODES || a->n_modes > ASSET_MAX_MODES ||
        (uint64_t)a->n_modes * a->n_nodes > ASSET_MAX_MODE_NODES || a->n_verts > ASSET_MAX_VERTS ||
        a->n_indices > ASSET_MAX_INDICES || a->n_leaves > ASSET_MAX_LEAVES ||
        a->n_lods > ASSET_MAX_LODS) {
        return gale_errf(err, GALE_E_RANGE,
                         "asset encode: counts out of range: nodes %u (1..%u), modes %u (<= %u), "
                         "verts %u, indices %u, leaves %u, lods %u",
                         a->n_nodes, ASSET_MAX_NODES, a->n_modes, ASSET_MAX_MODES, a->n_verts,
                         a->n_indices, a->n_leaves, a->n_lods);
    }
    const char *missing =
        !a->parent   ? "parent"
        : !a->rest   ? "rest"
        : !a->radius ? "radius"
        : a->n_modes && (!a->omega || !a->gamma || !a->wind_basis || !a->phi || !a->phi_rot)
            ? "omega, gamma, wind_basis, phi or phi_rot"
        : a->n_verts && (!a->mesh_pos || !a->mesh_normal || !a->mesh_bone || !a->mesh_weight)
            ? "mesh_pos, mesh_normal, mesh_bone or mesh_weight"
        : a->n_indices && !a->mesh_index ? "mesh_index"
        : a->n_leaves && (!a->leaf_node || !a->leaf_offset || !a->leaf_normal || !a->leaf_size)
            ? "leaf_node, leaf_offset, leaf_normal or leaf_size"
            : NULL;
    if (missing) {
        return gale_errf(err, GALE_E_ARG, "asset encode: %s: array missing for a non-zero count",
                         missing);
    }
    size_t plen = a->params_json ? strlen(a->params_json) : 0;
    if (plen > ASSET_MAX_PARAMS) {
        return gale_errf(err, GALE_E_RANGE, "asset encode: params_json: %zu bytes, limit %u", plen,
                         ASSET_MAX_PARAMS);
    }
    size_t nn = a->n_nodes, nm = a->n_modes, nmn = nm * nn;
    asset_writer w = { 0 };
    w_room(&w, ASSET_HEADER_BYTES);

    size_t at = w_begin(&w, 0); /* META */
    char name[64];
    memset(name, 0, sizeof name);
    memcpy(name, a->species, strnlen(a->species, sizeof name - 1));
    w_bytes(&w, name, sizeof name);
    w_u64(&w, a->source_hash);
    w_u32(&w, (uint32_t)plen);
    w_bytes(&w, a->params_json, plen);
    w_end(&w, at);

    at = w_begin(&w, 1); /* SKEL */
    w_u32(&w, a->n_nodes);
    w_f32(&w, a->height_m);
    for (size_t i = 0; i < nn; i++) {
        w_u32(&w, (uint32_t)a->parent[i]);
    }
    w_f32s(&w, a->rest, 3 * nn);
    w_f32s(&w, a->radius, nn);
    w_end(&w, at);

    at = w_begin(&w, 2); /* MODE */
    w_u32(&w, a->n_modes);
    w_f32s(&w, a->omega, nm);
    w_f32s(&w, a->gamma, nm);
    w_f32s(&w, a->wind_basis, 3 * nm);
    w_f32s(&w, a->phi, 3 * nmn);
    w_f32s(&w, a->phi_rot, 3 * nmn);
    w_end(&w, at);

    at = w_begin(&w, 3); /* CORR */
    uint32_t has_corr = a->corr_v && a->corr_w && a->corr_a && a->corr_b ? 1u : 0u;
    w_u32(&w, has_corr);
    if (has_corr) {
        w_f32s(&w, a->corr_v, 3 * nmn);
        w_f32s(&w, a->corr_w, 3 * nmn);
        w_f32s(&w, a->corr_a, nm);
        w_f32s(&w, a->corr_b, nm);
    }
    w_end(&w, at);

    at = w_begin(&w, 4); /* MESH */
    w_u32(&w, a->n_verts);
    w_f32s(&w, a->mesh_pos, 3 * (size_t)a->n_verts);
    w_f32s(&w, a->mesh_normal, 3 * (size_t)a->n_verts);
    w_u32s(&w, a->mesh_bone, 2 * (size_t)a->n_verts);
    w_f32s(&w, a->mesh_weight, a->n_verts);
    w_u32(&w, a->n_indices);
    w_u32s(&w, a->mesh_index, a->n_indices);
    w_u32(&w, a->n_lods);
    for (int l = 0; l < ASSET_MAX_LODS; l++) {
        w_u32(&w, a->lod_first[l]);
        w_u32(&w, a->lod_count[l]);
    }
    w_end(&w, at);

    at = w_begin(&w, 5); /* LEAF */
    w_u32(&w, a->n_leaves);
    w_u32s(&w, a->leaf_node, a->n_leaves);
    w_f32s(&w, a->leaf_offset, 3 * (size_t)a->n_leaves);
    w_f32s(&w, a->leaf_normal, 3 * (size_t)a->n_leaves);
    w_f32s(&w, a->leaf_size, a->n_leaves);
    w_end(&w, at);

    at = w_begin(&w, 6); /* LOOK */
    w_f32s(&w, a->bark_rgb, 3);
    w_f32s(&w, a->leaf_rgb, 3);
    w_u32(&w, a->leaf_shape);
    w_end(&w, at);

    /* optional sections: their presence makes the file version 2 */
    const uint32_t version = a->source_id || a->static_res ? 2u : 1u;
    if (a->source_id) {
        at = w_begin(&w, ASSET_SECTION_SRID);
        w_f32s(&w, a->source_origin, 3);
        w_u32(&w, a->n_nodes);
        w_u32s(&w, a->source_id, nn);
        w_end(&w, at);
    }
    if (a->static_res) {
        at = w_begin(&w, ASSET_SECTION_SRES);
        w_u32(&w, ASSET_STATIC_COLS);
        w_f32s(&w, a->static_res, 3 * ASSET_STATIC_COLS * nn);
        w_end(&w, at);
    }

    if (w.oom) {
        free(w.buf);
        return gale_errf(err, GALE_E_NOMEM, "asset encode: out of memory");
    }
    uint8_t *h = w.buf;
    size_t payload = w.len - ASSET_HEADER_BYTES;
    memcpy(h, asset_magic, 4);
    put_u32_at(h + 4, version);
    put_u64_at(h + 8, (uint64_t)payload);
    put_u32_at(h + 16, hash_crc32(h + ASSET_HEADER_BYTES, payload));
    put_u32_at(h + 20, hash_crc32(h, 20));
    *out = w.buf;
    *len = w.len;
    return GALE_OK;
}
