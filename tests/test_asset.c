/* Asset file format (protocol/ASSET.md): round trip of every field, golden bytes of a
 * minimal asset, rejection of every truncation, flipped bytes, wrong magic and version,
 * absurd counts (with the field and offset in the message); the optional SRID section
 * (source node ids): round trip, version rule, refused maps, skipped unknown sections;
 * the length-true reconstruction against hand-computed values; atomic save and load. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "asset.h"
#include "asset_file.h"
#include "check.h"
#include "hash.h"

static void *dup_mem(const void *src, size_t n)
{
    void *p = malloc(n);
    memcpy(p, src, n);
    return p;
}

#define DUP(arr) dup_mem(arr, sizeof arr)

/* 3 nodes in a chain, 2 modes with correction, a 4-vertex quad, 2 leaves. */
static void make_tiny(asset *a)
{
    memset(a, 0, sizeof *a);
    snprintf(a->species, sizeof a->species, "tiny");
    a->source_hash = 0x0123456789abcdefull;
    a->params_json = dup_mem("{\"E_pa\":1e10}", 14);
    a->n_nodes = 3;
    static const int32_t parent[3] = { -1, 0, 1 };
    static const float rest[9] = { 0, 0, 0, 0, 0, 1, 0.5f, 0, 2 };
    static const float radius[3] = { 0.2f, 0.1f, 0.05f };
    a->parent = DUP(parent);
    a->rest = DUP(rest);
    a->radius = DUP(radius);
    a->height_m = 2.0f;
    a->n_modes = 2;
    static const float omega[2] = { 3.0f, 7.5f }, gamma[2] = { 0.2f, 0.4f };
    static const float wb[6] = { 1, 2, 3, 4, 5, 6 };
    static const float phi[18] = {
        0, 0, 0, 0.1f, 0, 0, 0.3f, 0, 0, 0, 0, 0, 0, 0.2f, 0, 0, 0.5f, 0
    };
    static const float rot[18] = { 0,    0.1f, 0, 0,    0.2f, 0, 0,    0.3f, 0,
                                   0.1f, 0,    0, 0.2f, 0,    0, 0.3f, 0,    0 };
    static const float cw[18] = { 0, 0, 0, 0, 0, -0.01f, 0, 0, -0.04f,
                                  0, 0, 0, 0, 0, -0.02f, 0, 0, -0.05f };
    static const float ca[2] = { 2.0f, 1.5f }, cb[2] = { 0.5f, 0.0f };
    a->omega = DUP(omega);
    a->gamma = DUP(gamma);
    a->wind_basis = DUP(wb);
    a->phi = DUP(phi);
    a->phi_rot = DUP(rot);
    a->corr_v = DUP(phi);
    a->corr_w = DUP(cw);
    a->corr_a = DUP(ca);
    a->corr_b = DUP(cb);
    a->n_verts = 4;
    static const float mp[12] = { -0.1f, 0, 0, 0.1f, 0, 0, -0.1f, 0, 1, 0.1f, 0, 1 };
    static const float mn[12] = { 0, -1, 0, 0, -1, 0, 0, -1, 0, 0, -1, 0 };
    static const uint32_t mb[8] = { 0, 1, 0, 1, 0, 1, 0, 1 };
    static const float mw[4] = { 0, 0, 1, 1 };
    static const uint32_t mi[6] = { 0, 1, 2, 2, 1, 3 };
    a->mesh_pos = DUP(mp);
    a->mesh_normal = DUP(mn);
    a->mesh_bone = DUP(mb);
    a->mesh_weight = DUP(mw);
    a->n_indices = 6;
    a->mesh_index = DUP(mi);
    a->n_lods = 1;
    a->lod_first[0] = 0;
    a->lod_count[0] = 6;
    a->n_leaves = 2;
    static const uint32_t ln[2] = { 2, 2 };
    static const float lo[6] = { 0.05f, 0, 0, -0.05f, 0, 0 };
    static const float lnm[6] = { 0, 0, 1, 0, 1, 0 };
    static const float ls[2] = { 0.1f, 0.12f };
    a->leaf_node = DUP(ln);
    a->leaf_offset = DUP(lo);
    a->leaf_normal = DUP(lnm);
    a->leaf_size = DUP(ls);
    a->bark_rgb[0] = 0.3f;
    a->bark_rgb[1] = 0.2f;
    a->bark_rgb[2] = 0.1f;
    a->leaf_rgb[1] = 0.5f;
    a->leaf_shape = 2;
}

static int same_f(const float *x, const float *y, size_t n)
{
    return (x == NULL && y == NULL) || (x && y && memcmp(x, y, n * sizeof *x) == 0);
}

static void check_equal(const asset *a, const asset *b)
{
    CHECK(strcmp(a->species, b->species) == 0);
    CHECK(a->source_hash == b->source_hash);
    CHECK(strcmp(a->params_json, b->params_json) == 0);
    CHECK(a->n_nodes == b->n_nodes && a->n_modes == b->n_modes);
    size_t nn = a->n_nodes, nm = a->n_modes;
    CHECK(memcmp(a->parent, b->parent, nn * sizeof *a->parent) == 0);
    CHECK(same_f(a->rest, b->rest, 3 * nn) && same_f(a->radius, b->radius, nn));
    CHECK(a->height_m == b->height_m);
    CHECK((a->source_id == NULL) == (b->source_id == NULL));
    if (a->source_id && b->source_id) {
        CHECK(memcmp(a->source_id, b->source_id, nn * sizeof *a->source_id) == 0);
    }
    CHECK(same_f(a->source_origin, b->source_origin, 3));
    CHECK(same_f(a->omega, b->omega, nm) && same_f(a->gamma, b->gamma, nm));
    CHECK(same_f(a->wind_basis, b->wind_basis, 3 * nm));
    CHECK(same_f(a->phi, b->phi, 3 * nm * nn) && same_f(a->phi_rot, b->phi_rot, 3 * nm * nn));
    CHECK(same_f(a->corr_v, b->corr_v, 3 * nm * nn) && same_f(a->corr_w, b->corr_w, 3 * nm * nn));
    CHECK(same_f(a->corr_a, b->corr_a, nm) && same_f(a->corr_b, b->corr_b, nm));
    CHECK(a->n_verts == b->n_verts && a->n_indices == b->n_indices && a->n_lods == b->n_lods);
    CHECK(same_f(a->mesh_pos, b->mesh_pos, 3 * (size_t)a->n_verts));
    CHECK(same_f(a->mesh_normal, b->mesh_normal, 3 * (size_t)a->n_verts));
    CHECK(same_f(a->mesh_weight, b->mesh_weight, a->n_verts));
    CHECK(memcmp(a->mesh_bone, b->mesh_bone, 2 * a->n_verts * sizeof(uint32_t)) == 0);
    CHECK(memcmp(a->mesh_index, b->mesh_index, a->n_indices * sizeof(uint32_t)) == 0);
    CHECK(memcmp(a->lod_first, b->lod_first, sizeof a->lod_first) == 0);
    CHECK(memcmp(a->lod_count, b->lod_count, sizeof a->lod_count) == 0);
    CHECK(a->n_leaves == b->n_leaves);
    CHECK(memcmp(a->leaf_node, b->leaf_node, a->n_leaves * sizeof(uint32_t)) == 0);
    CHECK(same_f(a->leaf_offset, b->leaf_offset, 3 * (size_t)a->n_leaves));
    CHECK(same_f(a->leaf_normal, b->leaf_normal, 3 * (size_t)a->n_leaves));
    CHECK(same_f(a->leaf_size, b->leaf_size, a->n_leaves));
    CHECK(same_f(a->bark_rgb, b->bark_rgb, 3) && same_f(a->leaf_rgb, b->leaf_rgb, 3));
    CHECK(a->leaf_shape == b->leaf_shape);
}

/* Recomputes both checksums after a deliberate edit, so the edit reaches the parser. */
static void fix_crcs(uint8_t *b, size_t len)
{
    uint32_t p = hash_crc32(b + 24, len - 24);
    for (int i = 0; i < 4; i++) {
        b[16 + i] = (uint8_t)(p >> (8 * i));
    }
    uint32_t h = hash_crc32(b, 20);
    for (int i = 0; i < 4; i++) {
        b[20 + i] = (uint8_t)(h >> (8 * i));
    }
}

static void put32(uint8_t *b, size_t at, uint32_t v)
{
    for (int i = 0; i < 4; i++) {
        b[at + (size_t)i] = (uint8_t)(v >> (8 * i));
    }
}

static void test_hash(void)
{
    CHECK(hash_crc32("123456789", 9) == 0xcbf43926u);
    CHECK(hash_crc32("", 0) == 0u);
    uint32_t c = hash_crc32_update(hash_crc32_update(0, "1234", 4), "56789", 5);
    CHECK(c == 0xcbf43926u);
    /* FNV-1a 64 of "a" is 0xaf63dc4c8601ec8c before the final mix */
    CHECK(hash64_update(HASH64_INIT, "a", 1) == 0xaf63dc4c8601ec8cull);
    CHECK(hash64("a", 1) != hash64("b", 1));
    CHECK(hash64("oak", 3) ==
          hash64_final(hash64_update(hash64_update(HASH64_INIT, "o", 1), "ak", 2)));
}

static void test_round_trip(void)
{
    asset a, b;
    make_tiny(&a);
    uint8_t *buf;
    size_t len;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    int rc = asset_decode(buf, len, "tiny.asset", &b, &err);
    if (rc) {
        fprintf(stderr, "%s\n", err.msg);
    }
    CHECK(rc == 0);
    if (rc == 0) {
        check_equal(&a, &b);
    }
    /* encoding the decoded asset gives the same bytes */
    uint8_t *buf2;
    size_t len2;
    CHECK(asset_encode(&b, &buf2, &len2, &err) == 0);
    CHECK(len2 == len && memcmp(buf, buf2, len) == 0);
    free(buf2);
    /* a count without its array is refused */
    float *keep_phi = a.phi;
    a.phi = NULL;
    CHECK(asset_encode(&a, &buf2, &len2, &err) == GALE_E_ARG);
    CHECK_STR_HAS(err.msg, "asset encode: omega, gamma, wind_basis, phi or phi_rot: array missing");
    a.phi = keep_phi;
    /* without correction terms the CORR section is one flag */
    free(a.corr_v);
    a.corr_v = NULL;
    CHECK(asset_encode(&a, &buf2, &len2, &err) == 0);
    asset c;
    CHECK(asset_decode(buf2, len2, "nocorr", &c, &err) == 0);
    CHECK(c.corr_v == NULL && c.corr_w == NULL && c.corr_a == NULL && c.corr_b == NULL);
    CHECK(len2 == len - 4 * (2 * 18 + 2 * 2));
    asset_fini(&c);
    free(buf2);
    free(buf);
    asset_fini(&a);
    asset_fini(&b);
    asset_fini(NULL);
}

static void test_golden(void)
{
    /* one root node, nothing else: every byte known (ASSET.md) */
    asset a;
    memset(&a, 0, sizeof a);
    snprintf(a.species, sizeof a.species, "g");
    a.source_hash = 0x1122334455667788ull;
    a.params_json = dup_mem("{}", 3);
    a.n_nodes = 1;
    int32_t parent = -1;
    float rest[3] = { 0, 0, 0 }, radius = 0.5f;
    a.parent = &parent;
    a.rest = rest;
    a.radius = &radius;
    a.height_m = 1.0f;
    a.bark_rgb[0] = 1.0f;
    a.leaf_shape = 1;
    uint8_t *buf;
    size_t len;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    free(a.params_json);
    uint8_t want[24 + 90 + 40 + 16 + 16 + 56 + 16 + 40];
    memset(want, 0, sizeof want);
    size_t o = 0;
#define B4(a0, a1, a2, a3) \
    (want[o] = a0, want[o + 1] = a1, want[o + 2] = a2, want[o + 3] = a3, o += 4)
    B4('G', 'A', 'S', 'T');
    B4(1, 0, 0, 0);       /* version */
    B4(0x12, 0x01, 0, 0); /* payload length 274, low word */
    B4(0, 0, 0, 0);       /* high word */
    o += 8;               /* two CRCs, checked below */
    B4('M', 'E', 'T', 'A');
    B4(78, 0, 0, 0);
    B4(0, 0, 0, 0);
    want[o] = 'g';
    o += 64;
    B4(0x88, 0x77, 0x66, 0x55);
    B4(0x44, 0x33, 0x22, 0x11);
    B4(2, 0, 0, 0);
    want[o++] = '{';
    want[o++] = '}';
    B4('S', 'K', 'E', 'L');
    B4(28, 0, 0, 0);
    B4(0, 0, 0, 0);
    B4(1, 0, 0, 0);             /* n_nodes */
    B4(0, 0, 0x80, 0x3f);       /* height 1.0f */
    B4(0xff, 0xff, 0xff, 0xff); /* parent -1 */
    o += 12;                    /* rest 0,0,0 */
    B4(0, 0, 0, 0x3f);          /* radius 0.5f */
    B4('M', 'O', 'D', 'E');
    B4(4, 0, 0, 0);
    B4(0, 0, 0, 0);
    o += 4; /* n_modes 0 */
    B4('C', 'O', 'R', 'R');
    B4(4, 0, 0, 0);
    B4(0, 0, 0, 0);
    o += 4; /* no correction */
    B4('M', 'E', 'S', 'H');
    B4(44, 0, 0, 0);
    B4(0, 0, 0, 0);
    o += 4 + 4 + 4 + 32; /* n_verts, n_indices, n_lods, LOD table */
    B4('L', 'E', 'A', 'F');
    B4(4, 0, 0, 0);
    B4(0, 0, 0, 0);
    o += 4;
    B4('L', 'O', 'O', 'K');
    B4(28, 0, 0, 0);
    B4(0, 0, 0, 0);
    B4(0, 0, 0x80, 0x3f); /* bark r 1.0f */
    o += 20;
    B4(1, 0, 0, 0); /* leaf_shape */
#undef B4
    CHECK(o == sizeof want);
    CHECK(len == sizeof want);
    if (len == sizeof want) {
        CHECK(memcmp(buf, want, 16) == 0);
        CHECK(memcmp(buf + 24, want + 24, len - 24) == 0);
        uint32_t pc = (uint32_t)buf[16] | (uint32_t)buf[17] << 8 | (uint32_t)buf[18] << 16 |
                      (uint32_t)buf[19] << 24;
        CHECK(pc == hash_crc32(want + 24, len - 24));
    }
    /* its content hash, as a welcome names it (ASSET.md "Content hash") */
    CHECK(hash64(buf, len) == 0x1898eb1eeb74783aull);
    free(buf);
}

/* The content hash's test vectors in ASSET.md "Content hash": FNV-1a 64 (the standard
 * offset basis and prime) then the splitmix64 finaliser. */
static void test_hash_vectors(void)
{
    static const struct {
        const char *in;
        uint64_t fnv, hash;
    } v[] = {
        { "", 0xcbf29ce484222325ull, 0xf52a15e9a9b5e89bull },
        { "a", 0xaf63dc4c8601ec8cull, 0x02c0bdbf481420f8ull },
        { "gale", 0x8ade89720434de6aull, 0x5e643f92003bf3a8ull },
        { "The quick brown fox jumps over the lazy dog", 0xf3f9b7f5e7e47110ull,
          0x1e8e6a079b167ea7ull },
    };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        size_t n = strlen(v[i].in);
        CHECK(hash64_update(HASH64_INIT, v[i].in, n) == v[i].fnv);
        CHECK(hash64(v[i].in, n) == v[i].hash);
        CHECK(hash64_final(v[i].fnv) == v[i].hash);
    }
    /* incremental over any split gives the same */
    const char *q = v[3].in;
    CHECK(hash64_final(hash64_update(hash64_update(HASH64_INIT, q, 10), q + 10, strlen(q) - 10)) ==
          v[3].hash);
}

static void expect_reject(const uint8_t *buf, size_t len, int code, const char *msg)
{
    asset a;
    gale_err err = { 0 };
    uint8_t *copy = malloc(len ? len : 1); /* exact size, so ASan sees any overread */
    memcpy(copy, buf, len);
    int rc = asset_decode(copy, len, "t.asset", &a, &err);
    free(copy);
    CHECK(rc == code);
    if (msg) {
        CHECK_STR_HAS(err.msg, msg);
    }
    CHECK(a.n_nodes == 0 && a.parent == NULL && a.phi == NULL);
}

static void test_truncation(void)
{
    asset a;
    make_tiny(&a);
    uint8_t *buf;
    size_t len;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    asset_fini(&a);
    int bad = 0;
    for (size_t n = 0; n < len; n++) {
        asset b;
        uint8_t *copy = malloc(n ? n : 1);
        memcpy(copy, buf, n);
        int rc = asset_decode(copy, n, "t.asset", &b, &err);
        free(copy);
        bad += rc != GALE_E_FORMAT;
    }
    CHECK(bad == 0);
    expect_reject(buf, 10, GALE_E_FORMAT,
                  "t.asset: header at byte 0: truncated: need 24 bytes, got 10");
    expect_reject(buf, len - 1, GALE_E_FORMAT, "payload_length at byte 8: header states");
    expect_reject(buf, len - 1, GALE_E_FORMAT, "(truncated)");
    /* a trailing byte is no better */
    uint8_t *more = calloc(len + 1, 1);
    memcpy(more, buf, len);
    expect_reject(more, len + 1, GALE_E_FORMAT, "(trailing bytes)");
    free(more);
    free(buf);
}

static void test_corruption(void)
{
    asset a;
    make_tiny(&a);
    uint8_t *buf;
    size_t len;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    asset_fini(&a);
    /* every single flipped byte past the magic is caught by a checksum */
    int missed = 0;
    for (size_t i = 4; i < len; i++) {
        buf[i] ^= 0x5a;
        asset b;
        int rc = asset_decode(buf, len, "t.asset", &b, &err);
        /* in the header a flip may show as a length fault before the payload CRC */
        missed += !(rc == GALE_E_CHECKSUM || (i < 24 && rc == GALE_E_FORMAT));
        buf[i] ^= 0x5a;
    }
    CHECK(missed == 0);
    buf[200] ^= 1;
    expect_reject(buf, len, GALE_E_CHECKSUM, "payload_crc32 at byte 16: checksum mismatch");
    buf[200] ^= 1;
    buf[0] = 'X';
    expect_reject(buf, len, GALE_E_FORMAT, "magic at byte 0: expected \"GAST\"");
    buf[0] = 'G';
    put32(buf, 4, 3);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_VERSION, "t.asset: version at byte 4: expected 1..2, got 3");
    put32(buf, 4, 0);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_VERSION, "t.asset: version at byte 4: expected 1..2, got 0");
    /* version 2 with no optional section is read like version 1 */
    put32(buf, 4, 2);
    fix_crcs(buf, len);
    asset ok;
    CHECK(asset_decode(buf, len, "t.asset", &ok, &err) == 0);
    CHECK(ok.source_id == NULL);
    asset_fini(&ok);
    put32(buf, 4, 1);
    fix_crcs(buf, len);
    CHECK(asset_decode(buf, len, "t.asset", &ok, &err) == 0);
    asset_fini(&ok);
    free(buf);
}

static void test_absurd_counts(void)
{
    asset a;
    make_tiny(&a);
    uint8_t *buf;
    size_t len;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    asset_fini(&a);
    /* META: 24 header + 12 section header + 64 + 8 + 4 + 13 params = 125; SKEL body at 137 */
    const size_t n_nodes_at = 137;
    CHECK(buf[n_nodes_at] == 3);
    put32(buf, n_nodes_at, 0xffffffffu);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_FORMAT,
                  "n_nodes at byte 137: count 4294967295 over the limit 262144");
    put32(buf, n_nodes_at, 100000);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_FORMAT, "n_nodes at byte 137: count 100000 needs 2000000 bytes");
    put32(buf, n_nodes_at, 0);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_FORMAT, "n_nodes at byte 137: expected at least 1 node");
    put32(buf, n_nodes_at, 3);
    /* node 2's parent pointing forward */
    put32(buf, n_nodes_at + 8 + 8, 5);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_FORMAT,
                  "parent at byte 153: node 2: parent 5, expected an earlier node");
    put32(buf, n_nodes_at + 8 + 8, 1);
    /* a NaN coordinate */
    put32(buf, n_nodes_at + 20, 0x7fc00000u);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_FORMAT, "rest at byte 157: not a finite number");
    free(buf);
}

/* make_tiny with the source ids of a CSV whose ids were 70, 5, 12 and whose root sat at
 * (1.5, -2, 0.25). */
static void make_tiny_ids(asset *a)
{
    make_tiny(a);
    static const uint32_t ids[3] = { 70, 5, 12 };
    a->source_id = DUP(ids);
    a->source_origin[0] = 1.5f;
    a->source_origin[1] = -2.0f;
    a->source_origin[2] = 0.25f;
}

/* Appends a section (tag, body) to a copy of an encoded asset, sets the version and
 * repairs the payload length and both CRCs; *out_len is the new length. */
static uint8_t *append_section(const uint8_t *buf, size_t len, const char tag[4],
                               const uint8_t *body, size_t body_len, uint32_t version,
                               size_t *out_len)
{
    size_t n = len + 12 + body_len;
    uint8_t *b = calloc(n, 1);
    memcpy(b, buf, len);
    memcpy(b + len, tag, 4);
    put32(b, len + 4, (uint32_t)body_len);
    if (body_len) {
        memcpy(b + len + 12, body, body_len);
    }
    put32(b, 4, version);
    put32(b, 8, (uint32_t)(n - 24));
    put32(b, 12, 0);
    fix_crcs(b, n);
    *out_len = n;
    return b;
}

/* SRID (ASSET.md "Optional sections"): with source ids the file is version 2 and they
 * come back exactly; without them it is version 1 and source_id is NULL. */
static void test_source_ids(void)
{
    asset a, b;
    make_tiny_ids(&a);
    uint8_t *buf, *buf2;
    size_t len, len2;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    CHECK(buf[4] == 2 && buf[5] == 0 && buf[6] == 0 && buf[7] == 0);
    int rc = asset_decode(buf, len, "ids.asset", &b, &err);
    if (rc) {
        fprintf(stderr, "%s\n", err.msg);
    }
    CHECK(rc == 0);
    if (rc == 0) {
        check_equal(&a, &b);
        CHECK(b.source_id != NULL);
        if (b.source_id) {
            CHECK(b.source_id[0] == 70 && b.source_id[1] == 5 && b.source_id[2] == 12);
        }
        CHECK(b.source_origin[0] == 1.5f && b.source_origin[1] == -2.0f &&
              b.source_origin[2] == 0.25f);
        CHECK(asset_encode(&b, &buf2, &len2, &err) == 0);
        CHECK(len2 == len && memcmp(buf, buf2, len) == 0);
        free(buf2);
        asset_fini(&b);
    }
    /* the section: 12 header + origin 12 + count 4 + 3 ids */
    const size_t srid = len - 40;
    CHECK(memcmp(buf + srid, "SRID", 4) == 0 && buf[srid + 4] == 28);
    /* the same asset without ids: seven sections, version 1, 40 bytes less */
    free(a.source_id);
    a.source_id = NULL;
    CHECK(asset_encode(&a, &buf2, &len2, &err) == 0);
    CHECK(buf2[4] == 1 && len2 == len - 40);
    CHECK(asset_decode(buf2, len2, "noids.asset", &b, &err) == 0);
    CHECK(b.source_id == NULL);
    CHECK(b.source_origin[0] == 0.0f && b.source_origin[1] == 0.0f && b.source_origin[2] == 0.0f);
    asset_fini(&b);
    /* an optional section this build does not know is skipped; SRID after it still read */
    static const uint8_t five[5] = { 1, 2, 3, 4, 5 };
    size_t len3;
    uint8_t *unk = append_section(buf2, len2, "XTRA", five, sizeof five, 2, &len3);
    CHECK(asset_decode(unk, len3, "unk.asset", &b, &err) == 0);
    CHECK(b.source_id == NULL);
    asset_fini(&b);
    size_t len4;
    uint8_t *both = append_section(unk, len3, "SRID", buf + srid + 12, 28, 2, &len4);
    rc = asset_decode(both, len4, "both.asset", &b, &err);
    CHECK(rc == 0);
    if (rc == 0) {
        CHECK(b.source_id && b.source_id[0] == 70 && b.source_id[2] == 12);
        asset_fini(&b);
    }
    free(both);
    free(unk);
    /* version 1 has no optional sections: SRID after LOOK is refused there */
    unk = append_section(buf2, len2, "SRID", buf + srid + 12, 28, 1, &len3);
    char want[128];
    snprintf(want, sizeof want,
             "end at byte %zu: 40 bytes after the last section (version 1 has no optional "
             "sections)",
             len2);
    expect_reject(unk, len3, GALE_E_FORMAT, want);
    free(unk);
    free(buf2);
    free(buf);
    asset_fini(&a);
}

/* A map that does not fit the skeleton is refused naming the field and its byte. */
static void test_source_ids_refused(void)
{
    asset a;
    make_tiny_ids(&a);
    uint8_t *buf;
    size_t len;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    asset_fini(&a);
    const size_t srid = len - 40, origin_at = srid + 12, count_at = srid + 24, ids_at = srid + 28;
    char want[160];
    /* wrong count: fewer ids than nodes, the section length following */
    put32(buf, count_at, 2);
    put32(buf, srid + 4, 24);
    size_t short_len = len - 4;
    uint8_t *s = malloc(short_len);
    memcpy(s, buf, short_len);
    put32(s, 8, (uint32_t)(short_len - 24));
    fix_crcs(s, short_len);
    snprintf(want, sizeof want, "n_source_ids at byte %zu: count 2, expected n_nodes (3)",
             count_at);
    expect_reject(s, short_len, GALE_E_FORMAT, want);
    free(s);
    /* more ids than nodes */
    put32(buf, count_at, 4);
    put32(buf, srid + 4, 28);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_FORMAT, "n_source_ids at byte");
    expect_reject(buf, len, GALE_E_FORMAT, "count 4 needs 16 bytes, 12 left");
    /* the right count but the section length disagreeing */
    put32(buf, count_at, 3);
    put32(buf, srid + 4, 27);
    fix_crcs(buf, len);
    expect_reject(buf, len, GALE_E_FORMAT, "SRID at byte");
    put32(buf, srid + 4, 28);
    /* a duplicate id: node 2 says 70 like node 0 */
    put32(buf, ids_at + 8, 70);
    fix_crcs(buf, len);
    snprintf(want, sizeof want,
             "t.asset: source_id at byte %zu: node 2: id 70, already the id of node 0 (ids "
             "must be distinct)",
             ids_at + 8);
    expect_reject(buf, len, GALE_E_FORMAT, want);
    put32(buf, ids_at + 8, 12);
    /* a non-finite origin */
    put32(buf, origin_at + 4, 0x7f800000u);
    fix_crcs(buf, len);
    snprintf(want, sizeof want, "source_origin at byte %zu: not a finite number", origin_at + 4);
    expect_reject(buf, len, GALE_E_FORMAT, want);
    put32(buf, origin_at + 4, 0);
    fix_crcs(buf, len);
    asset ok;
    CHECK(asset_decode(buf, len, "t.asset", &ok, &err) == 0);
    asset_fini(&ok);
    /* SRID twice */
    size_t len2;
    uint8_t *twice = append_section(buf, len, "SRID", buf + srid + 12, 28, 2, &len2);
    snprintf(want, sizeof want, "SRID at byte %zu: second SRID section (at most one)", len);
    expect_reject(twice, len2, GALE_E_FORMAT, want);
    free(twice);
    /* an optional section longer than what is left */
    uint8_t *big = append_section(buf, len, "XTRA", NULL, 0, 2, &len2);
    put32(big, len + 4, 99);
    fix_crcs(big, len2);
    expect_reject(big, len2, GALE_E_FORMAT, "section length 99, only 0 bytes left");
    free(big);
    /* fewer than a section header's 12 bytes after the last section */
    uint8_t *tail = calloc(len + 5, 1);
    memcpy(tail, buf, len);
    put32(tail, 8, (uint32_t)(len + 5 - 24));
    fix_crcs(tail, len + 5);
    expect_reject(tail, len + 5, GALE_E_FORMAT, "section length at byte");
    expect_reject(tail, len + 5, GALE_E_FORMAT, "truncated: need 4 bytes, 1 left");
    free(tail);
    /* every truncation of the ids is a format fault, never a crash */
    int bad = 0;
    for (size_t n = srid + 1; n < len; n++) {
        uint8_t *c = malloc(n);
        memcpy(c, buf, n);
        put32(c, 8, (uint32_t)(n - 24));
        fix_crcs(c, n);
        asset b;
        bad += asset_decode(c, n, "t.asset", &b, &err) != GALE_E_FORMAT;
        free(c);
    }
    CHECK(bad == 0);
    free(buf);
}

/* SRES (ASSET.md "SRES"): the static correction comes back exactly from a version-2 file;
 * the force vector read back from q is w's part in the span of the wind basis (here two
 * modes: a plane); the linear pose and the drawn shapes add r (A q); a wrong column count,
 * a second SRES and a NaN are refused naming the field. */
static void test_static_res(void)
{
    asset a;
    make_tiny(&a);
    float r[27];
    for (int k = 0; k < 27; k++) {
        r[k] = 0.001f * (float)(k + 1) * (k % 2 ? -1.0f : 1.0f);
    }
    a.static_res = malloc(sizeof r);
    memcpy(a.static_res, r, sizeof r);
    uint8_t *buf;
    size_t len;
    gale_err err = { 0 };
    CHECK(asset_encode(&a, &buf, &len, &err) == 0);
    CHECK(buf[4] == 2);
    const size_t sres = len - 124;
    CHECK(memcmp(buf + sres, "SRES", 4) == 0 && buf[sres + 4] == 112 && buf[sres + 12] == 3);
    asset b;
    CHECK(asset_decode(buf, len, "t.asset", &b, &err) == 0);
    CHECK(b.static_res && memcmp(b.static_res, r, sizeof r) == 0);
    asset_fini(&b);

    /* w̃ = A q: p_0 = (1, 2, 3), p_1 = (4, 5, 6); w = p_0 + n with n = p_0 × p_1 across
     * both: q sees p_0 alone */
    double A[6];
    asset_static_map(a.omega, a.wind_basis, 2, A);
    const double w[3] = { 1 - 3, 2 + 6, 3 - 3 };
    float q[2];
    double wt[3] = { 0, 0, 0 };
    for (int i = 0; i < 2; i++) {
        const float *p = a.wind_basis + 3 * i;
        q[i] = (float)(((double)p[0] * w[0] + (double)p[1] * w[1] + (double)p[2] * w[2]) /
                       ((double)a.omega[i] * (double)a.omega[i]));
        for (int k = 0; k < 3; k++) {
            wt[k] += A[k * 2 + i] * (double)q[i];
        }
    }
    for (int k = 0; k < 3; k++) {
        CHECK_NEAR(wt[k], (double)(k + 1), 1e-5);
    }
    /* the linear pose and the drawn shapes: rest + Σ q φ + Σ_k r_k w̃_k */
    float lin[9], sh[18];
    asset_linear(&a, q, 2, lin);
    asset_pose_shapes(&a, sh);
    for (int j = 0; j < 9; j++) {
        double want = (double)a.rest[j], from_shapes = (double)a.rest[j];
        for (int i = 0; i < 2; i++) {
            want += (double)q[i] * (double)a.phi[9 * i + j];
            from_shapes += (double)q[i] * (double)sh[9 * i + j];
        }
        for (int k = 0; k < 3; k++) {
            want += (double)r[9 * k + j] * wt[k];
        }
        CHECK_NEAR(lin[j], want, 1e-5);
        CHECK_NEAR(from_shapes, want, 1e-5);
    }
    asset_fini(&a);

    char want_msg[160];
    put32(buf, sres + 12, 2);
    fix_crcs(buf, len);
    snprintf(want_msg, sizeof want_msg,
             "t.asset: n_static_cols at byte %zu: count 2, expected 3 (one per wind-basis column)",
             sres + 12);
    expect_reject(buf, len, GALE_E_FORMAT, want_msg);
    put32(buf, sres + 12, 3);
    put32(buf, sres + 16 + 4 * 5, 0x7fc00000u);
    fix_crcs(buf, len);
    snprintf(want_msg, sizeof want_msg, "static_res at byte %zu: not a finite number",
             sres + 16 + 4 * 5);
    expect_reject(buf, len, GALE_E_FORMAT, want_msg);
    put32(buf, sres + 16 + 4 * 5, 0);
    fix_crcs(buf, len);
    size_t len2;
    uint8_t *twice = append_section(buf, len, "SRES", buf + sres + 12, 112, 2, &len2);
    snprintf(want_msg, sizeof want_msg, "SRES at byte %zu: second SRES section (at most one)",
             len);
    expect_reject(twice, len2, GALE_E_FORMAT, want_msg);
    free(twice);
    free(buf);
}

static void test_reconstruct(void)
{
    asset a;
    make_tiny(&a);
    /* mode 1 alone (b = 0, q̃ = q): v = (0, 0.2, 0), (0, 0.5, 0) turn the segments about y,
     * w = (0, 0, -0.02), (0, 0, -0.05) stretch them; by hand, with q1 = -2: segment 1 is
     * (0, 0, 1.04) turned by -0.4 rad, segment 2 (0.5, 0, 1.1) by -1 rad */
    float q[2] = { 0.0f, -2.0f }, out[9], x[3];
    asset_reconstruct(&a, q, 2, out);
    CHECK(out[0] == 0.0f && out[1] == 0.0f && out[2] == 0.0f);
    const double x1 = 1.04 * sin(-0.4), z1 = 1.04 * cos(-0.4);
    const double x2 = x1 + 0.5 * cos(-1.0) + 1.1 * sin(-1.0);
    const double z2 = z1 - 0.5 * sin(-1.0) + 1.1 * cos(-1.0);
    CHECK_NEAR(out[3], x1, 1e-6);
    CHECK_NEAR(out[4], 0.0, 1e-7);
    CHECK_NEAR(out[5], z1, 1e-6);
    CHECK_NEAR(out[6], x2, 1e-6);
    CHECK_NEAR(out[8], z2, 1e-6);
    /* both modes, mode 0 saturated (q̃0 = 2 atan(0.5 q0)): each segment keeps the length
     * of its stretched rest vector s + Σ q̃ w */
    q[0] = 0.4f;
    asset_reconstruct(&a, q, 2, out);
    const double qt0 = 2.0 * atan(0.2), qt1 = -2.0;
    const double l1 = 1.0 + qt0 * -0.01 + qt1 * -0.02;
    const double l2 = hypot(0.5, 1.0 + qt0 * -0.04 + qt1 * -0.05);
    CHECK_NEAR(sqrt((double)out[3] * (double)out[3] + (double)out[4] * (double)out[4] +
                    (double)out[5] * (double)out[5]),
               l1, 1e-6);
    const double d2[3] = { (double)out[6] - (double)out[3], (double)out[7] - (double)out[4],
                           (double)out[8] - (double)out[5] };
    CHECK_NEAR(sqrt(d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]), l2, 1e-6);
    /* one node alone, walking up its parents, is the same pose */
    for (uint32_t i = 0; i < 3; i++) {
        asset_reconstruct_node(a.rest, a.parent, a.corr_v, a.corr_w, a.corr_a, a.corr_b, 3, q, 2,
                               i, x);
        for (int c = 0; c < 3; c++) {
            CHECK_NEAR(x[c], out[3 * i + c], 1e-6);
        }
    }
    /* only the first mode: mode 1's turn about y is gone */
    asset_reconstruct(&a, q, 1, out);
    CHECK_NEAR(out[3], 0.0, 1e-7);
    /* more modes than there are: clamped */
    asset_reconstruct(&a, q, 99, out);
    CHECK_NEAR(sqrt((double)out[3] * (double)out[3] + (double)out[4] * (double)out[4] +
                    (double)out[5] * (double)out[5]),
               l1, 1e-6);
    /* without the pose fields: linear in phi */
    free(a.corr_w);
    a.corr_w = NULL;
    asset_reconstruct(&a, q, 2, out);
    CHECK_NEAR(out[6], 0.5 + 0.4 * 0.3, 1e-6);
    CHECK_NEAR(out[7], -2.0 * 0.5, 1e-6);
    CHECK_NEAR(out[8], 2.0, 1e-6);
    asset_fini(&a);
}

/* asset_pose_fields: v × s + w = φ_i − φ_p for every segment (the slope at q = 0) */
static void test_pose_fields(void)
{
    asset a;
    make_tiny(&a);
    float v[18], w[18];
    asset_pose_fields(a.rest, a.parent, 3, a.phi, 2, v, w);
    for (int m = 0; m < 2; m++) {
        for (int i = 1; i < 3; i++) {
            const int p = a.parent[i];
            const float *vi = v + 9 * m + 3 * i, *wi = w + 9 * m + 3 * i;
            float sg[3], d[3];
            for (int c = 0; c < 3; c++) {
                sg[c] = a.rest[3 * i + c] - a.rest[3 * p + c];
                d[c] = a.phi[9 * m + 3 * i + c] - a.phi[9 * m + 3 * p + c];
            }
            CHECK_NEAR(vi[1] * sg[2] - vi[2] * sg[1] + wi[0], d[0], 1e-6);
            CHECK_NEAR(vi[2] * sg[0] - vi[0] * sg[2] + wi[1], d[1], 1e-6);
            CHECK_NEAR(vi[0] * sg[1] - vi[1] * sg[0] + wi[2], d[2], 1e-6);
            /* w lies along the segment */
            CHECK_NEAR(wi[0] * sg[2] - wi[2] * sg[0], 0.0, 1e-6);
        }
    }
    asset_fini(&a);
}

static void test_file(void)
{
    char dir[256];
    snprintf(dir, sizeof dir, "%s/asset_XXXXXX", GALE_TEST_DIR);
    CHECK(mkdtemp(dir) != NULL);
    char path[320];
    snprintf(path, sizeof path, "%s/tiny.asset", dir);
    asset a, b;
    make_tiny(&a);
    gale_err err = { 0 };
    CHECK(asset_save(&a, path, &err) == 0);
    CHECK(asset_load(path, &b, &err) == 0);
    check_equal(&a, &b);
    asset_fini(&b);
    /* a failing save leaves the old file whole: make the encoder fail */
    uint32_t keep = a.n_nodes;
    a.n_nodes = 0;
    CHECK(asset_save(&a, path, &err) == GALE_E_RANGE);
    a.n_nodes = keep;
    CHECK(asset_load(path, &b, &err) == 0);
    asset_fini(&b);
    CHECK(asset_save(&a, "/nonexistent/dir/x.asset", &err) == GALE_E_IO);
    CHECK_STR_HAS(err.msg, "/nonexistent/dir/x.asset");
    CHECK(asset_load("/nonexistent/x.asset", &b, &err) == GALE_E_IO);
    CHECK_STR_HAS(err.msg, "/nonexistent/x.asset: cannot open");
    /* a truncated file on disk */
    FILE *f = fopen(path, "r+b");
    CHECK(f != NULL);
    if (f) {
        CHECK(ftruncate(fileno(f), 100) == 0);
        fclose(f);
    }
    CHECK(asset_load(path, &b, &err) == GALE_E_FORMAT);
    CHECK_STR_HAS(err.msg, "tiny.asset: payload_length at byte 8");
    remove(path);
    CHECK(rmdir(dir) == 0); /* no temporary file was left behind */
    asset_fini(&a);
}

int main(void)
{
    RUN(test_hash);
    RUN(test_round_trip);
    RUN(test_golden);
    RUN(test_hash_vectors);
    RUN(test_truncation);
    RUN(test_corruption);
    RUN(test_absurd_counts);
    RUN(test_source_ids);
    RUN(test_source_ids_refused);
    RUN(test_static_res);
    RUN(test_reconstruct);
    RUN(test_pose_fields);
    RUN(test_file);
    return check_report();
}
