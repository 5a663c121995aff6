/* KEYFRAME and DELTA state frames: quantised modal coordinates q of every tree in view
 * (Diener 2008 section 3). Values are coded per group of 8 modes as bit-packed zigzag
 * residuals against a chosen predictor (zero, previous snapshot, linear extrapolation of
 * the two previous); PROTOCOL.md "State frames" has the byte table. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wire.h"
#include "wire_cursor.h"
#include "wire_int.h"

/* The vector helpers below are always inlined into put_values' clones, so no vector
 * crosses a call; GCC's note that such a call would change ABI without AVX is moot. */
#pragma GCC diagnostic ignored "-Wpsabi"

#define GROUP 8u        /* modes per group; a full group of width w is exactly w bytes */
#define MAX_WIDTH 18u   /* |v - pred| <= 4 * WIRE_QMAX < 2^17, zigzag < 2^18 */
/* Rows asked for this many trees ahead: the rows come from memory the update wrote last,
 * and 16 trees (~0.5 us of coding) cover its latency; at 100 000 trees the coding took
 * a fifth less than with the hardware's prefetch alone. */
#define PREFETCH_TREES 16u

enum { PRED_ZERO = 0, PRED_PREV = 1, PRED_LINEAR = 2 };
enum { SET_SAME = 0, SET_RUNS = 1 };
enum { MODES_FULL = 0, MODES_LIST = 1 };

static unsigned bit_width(uint32_t v)
{
    return v ? 32u - (unsigned)__builtin_clz(v) : 0u;
}

size_t wire_state_bound(uint32_t n_trees, uint32_t max_modes, uint32_t n_species)
{
    size_t groups = (max_modes + GROUP - 1) / GROUP;
    size_t per_tree = groups + ((size_t)max_modes * MAX_WIDTH + 7) / 8;
    size_t runs = ((size_t)n_trees / 2 + 1) * 10; /* (gap, len) varints, <= 5 bytes each */
    return WIRE_HEADER_BYTES + 4 + 4 + 1 + (size_t)n_species * (1 + 4 * (size_t)max_modes) +
           n_trees + 2 + 5 + runs + 1 + n_trees + (size_t)n_trees * per_tree;
}

static int check_scene(const wire_scene *sc, const char *what, gale_err *err)
{
    if (sc->n_trees == 0 || sc->n_trees > WIRE_MAX_TREES) {
        return gale_errf(err, GALE_E_RANGE, "%s: scene.n_trees: expected 1..%u, got %u", what,
                         WIRE_MAX_TREES, sc->n_trees);
    }
    if (sc->n_species == 0 || sc->n_species > WIRE_MAX_SPECIES) {
        return gale_errf(err, GALE_E_RANGE, "%s: scene.n_species: expected 1..%u, got %u",
                         what, WIRE_MAX_SPECIES, sc->n_species);
    }
    for (uint32_t s = 0; s < sc->n_species; s++) {
        if (sc->n_modes[s] == 0 || sc->n_modes[s] > WIRE_MAX_MODES) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: scene.n_modes[%u]: expected 1..%u, got %u", what, s,
                             WIRE_MAX_MODES, (unsigned)sc->n_modes[s]);
        }
        for (uint32_t m = 0; m < sc->n_modes[s]; m++) {
            float st = sc->step[s][m];
            if (!(st > 0.0f && st <= WIRE_MAX_STEP)) {
                return gale_errf(err, GALE_E_RANGE,
                                 "%s: scene.step[%u][%u]: expected in (0, %g], got %g", what,
                                 s, m, (double)WIRE_MAX_STEP, (double)st);
            }
        }
    }
    return 0;
}

static int check_state(const wire_scene *sc, const wire_state *st, const char *what,
                       const char *name, gale_err *err)
{
    if (st->n_trees != sc->n_trees) {
        return gale_errf(err, GALE_E_ARG, "%s: %s.n_trees: expected %u (the scene), got %u",
                         what, name, sc->n_trees, st->n_trees);
    }
    for (uint32_t t = 0; t < st->n_trees; t++) {
        uint32_t sp = sc->species[t];
        if (sp >= sc->n_species) {
            return gale_errf(err, GALE_E_RANGE, "%s: scene.species[%u]: expected < %u, got %u",
                             what, t, sc->n_species, sp);
        }
        uint32_t n = st->n_modes[t];
        if (n > sc->n_modes[sp] || n > st->stride) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: %s.n_modes[%u]: expected <= %u (species %u) and <= stride %u, got %u",
                             what, name, t, (unsigned)sc->n_modes[sp], sp, st->stride, n);
        }
        const int16_t *q = st->q + (size_t)t * st->stride;
        for (uint32_t m = 0; m < n; m++) {
            if (q[m] < -WIRE_QMAX) {
                return gale_errf(err, GALE_E_RANGE,
                                 "%s: %s.q[%u][%u]: expected >= %d, got %d", what, name, t, m,
                                 -WIRE_QMAX, q[m]);
            }
        }
    }
    return 0;
}

/* Writes k zigzag values of width w bits, LSB first. */
static void put_bits(wire_writer *w, const uint32_t *z, uint32_t k, unsigned width)
{
    uint64_t acc = 0;
    unsigned nacc = 0;
    for (uint32_t i = 0; i < k; i++) {
        acc |= (uint64_t)z[i] << nacc;
        nacc += width;
        while (nacc >= 8) {
            wire_put_u8(w, (uint8_t)(acc & 0xffu));
            acc >>= 8;
            nacc -= 8;
        }
    }
    if (nacc > 0) {
        wire_put_u8(w, (uint8_t)(acc & 0xffu));
    }
}

/* 8 bytes at p as a little-endian number. */
static inline uint64_t load_le64(const uint8_t *p)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    uint64_t v;
    memcpy(&v, p, sizeof v);
    return v;
#else
    uint64_t v = 0;
    for (unsigned i = 0; i < 8; i++) {
        v |= (uint64_t)p[i] << (8 * i);
    }
    return v;
#endif
}

/* Reads k values of width w bits, LSB first: the group's ceil(k w / 8) bytes are checked
 * to be there once, then read without a check per byte. */
static void get_bits(wire_reader *r, uint32_t *z, uint32_t k, unsigned width)
{
    const size_t n_bytes = ((size_t)k * width + 7u) / 8u;
    if (r->bad || wire_reader_left(r) < n_bytes) {
        r->bad = true;
        return;
    }
    const uint8_t *p = r->p;
    const uint32_t mask = width ? (uint32_t)((1u << width) - 1u) : 0u;
    uint64_t acc = 0;
    unsigned nacc = 0;
    for (uint32_t i = 0; i < k; i++) {
        while (nacc < width) {
            acc |= (uint64_t)*p++ << nacc;
            nacc += 8;
        }
        z[i] = (uint32_t)(acc & mask);
        acc >>= width;
        nacc -= width;
    }
    r->p = p;
    /* Padding bits of the last byte must be zero (one encoding per value). */
    if (acc != 0) {
        r->bad = true;
    }
}

/* Tree set and per-tree mode counts. */
static void put_set(wire_writer *w, const wire_scene *sc, const wire_state *cur)
{
    uint32_t n_runs = 0;
    bool full = true;
    for (uint32_t t = 0; t < cur->n_trees; t++) {
        if (cur->n_modes[t] && (t == 0 || !cur->n_modes[t - 1])) {
            n_runs++;
        }
        if (cur->n_modes[t] && cur->n_modes[t] != sc->n_modes[sc->species[t]]) {
            full = false;
        }
    }
    wire_put_u8(w, SET_RUNS);
    wire_put_varint(w, n_runs);
    uint32_t end = 0; /* end of the previous run */
    for (uint32_t t = 0; t < cur->n_trees;) {
        if (!cur->n_modes[t]) {
            t++;
            continue;
        }
        uint32_t start = t;
        while (t < cur->n_trees && cur->n_modes[t]) {
            t++;
        }
        wire_put_varint(w, start - end);
        wire_put_varint(w, t - start);
        end = t;
    }
    wire_put_u8(w, full ? MODES_FULL : MODES_LIST);
    if (!full) {
        for (uint32_t t = 0; t < cur->n_trees; t++) {
            if (cur->n_modes[t]) {
                wire_put_u8(w, cur->n_modes[t]);
            }
        }
    }
}

static bool same_set(const wire_state *a, const wire_state *b)
{
    return memcmp(a->n_modes, b->n_modes, a->n_trees) == 0;
}

/* One tree's rows as int32, zero beyond what is sent and up to a whole group: the
 * history rows 0 where a mode was not sent (PROTOCOL.md). */
static inline uint32_t tree_rows(const wire_state *cur, const wire_state *prev,
                                 const wire_state *prev2, uint32_t t, int32_t *v, int32_t *a,
                                 int32_t *b)
{
    const uint32_t n = cur->n_modes[t];
    const uint32_t ng = (n + GROUP - 1) / GROUP * GROUP;
    const int16_t *q = cur->q + (size_t)t * cur->stride;
    const uint32_t na = prev ? prev->n_modes[t] : 0, nb = prev2 ? prev2->n_modes[t] : 0;
    const int16_t *qa = prev ? prev->q + (size_t)t * prev->stride : NULL;
    const int16_t *qb = prev2 ? prev2->q + (size_t)t * prev2->stride : NULL;
    for (uint32_t m = 0; m < ng; m++) {
        v[m] = m < n ? q[m] : 0;
        a[m] = m < n && m < na ? qa[m] : 0;
        b[m] = m < n && m < nb ? qb[m] : 0;
    }
    return n;
}

/* The zigzag residuals of one group of 8 against each predictor, zero-padded to 8, and the
 * width of each. */
static inline void group_code(const int32_t *v, const int32_t *a, const int32_t *b,
                              uint32_t z[3][GROUP], unsigned wd[3])
{
    uint32_t o0 = 0, o1 = 0, o2 = 0;
    for (uint32_t i = 0; i < GROUP; i++) {
        z[PRED_ZERO][i] = wire_zigzag(v[i]);
        z[PRED_PREV][i] = wire_zigzag(v[i] - a[i]);
        z[PRED_LINEAR][i] = wire_zigzag(v[i] - (2 * a[i] - b[i]));
        o0 |= z[PRED_ZERO][i];
        o1 |= z[PRED_PREV][i];
        o2 |= z[PRED_LINEAR][i];
    }
    /* The OR of the values has the width of their maximum. */
    wd[0] = bit_width(o0);
    wd[1] = bit_width(o1);
    wd[2] = bit_width(o2);
}

/* The header byte of a group: the narrowest of the first n_pred predictors (the first of
 * equal widths) and its width. */
static inline uint8_t group_header(const unsigned wd[3], int n_pred, int *best_out)
{
    int best = PRED_ZERO;
    for (int p = 1; p < n_pred; p++) {
        if (wd[p] < wd[best]) {
            best = p;
        }
    }
    *best_out = best;
    return (uint8_t)((unsigned)best << 5 | wd[best]);
}

__extension__ typedef unsigned __int128 u128;

static inline void store_le64(uint8_t *p, uint64_t v)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy(p, &v, sizeof v);
#else
    for (unsigned i = 0; i < 8; i++) {
        p[i] = (uint8_t)(v >> (8 * i));
    }
#endif
}

/* Room past a tree's worst case the packer may overwrite with zeros (the 24 bytes a
 * group of width 17-18 is assembled in, plus the header byte before it). */
#define FAST_SLACK 32u

/* Packs 8 values of width w (zero beyond the group's k) LSB first at p, as put_bits
 * writes them; bytes past ceil(k w / 8) are written as zeros (FAST_SLACK). */
static inline void pack8(uint8_t *p, const uint32_t *z, unsigned width)
{
    if (width <= 8) {
        uint64_t acc = 0;
        for (unsigned i = 0; i < GROUP; i++) {
            acc |= (uint64_t)z[i] << (i * width);
        }
        store_le64(p, acc);
    } else if (width <= 16) {
        u128 acc = 0;
        for (unsigned i = 0; i < GROUP; i++) {
            acc |= (u128)z[i] << (i * width);
        }
        store_le64(p, (uint64_t)acc);
        store_le64(p + 8, (uint64_t)(acc >> 64));
    } else {
        uint8_t tmp[GROUP * MAX_WIDTH / 8 + 8] = { 0 };
        for (unsigned i = 0; i < GROUP; i++) {
            const unsigned off = i * width;
            uint64_t x = load_le64(tmp + (off >> 3));
            x |= (uint64_t)z[i] << (off & 7u);
            store_le64(tmp + (off >> 3), x);
        }
        memcpy(p, tmp, GROUP * MAX_WIDTH / 8);
    }
}

/* Worst-case bytes of one tree of n modes in the values section. */
static inline size_t tree_bound(uint32_t n)
{
    return (n + GROUP - 1) / GROUP + ((size_t)n * MAX_WIDTH + 7) / 8;
}

/* Sixteen lanes of int16 and int32, and their halves (GCC vector extensions): two
 * groups of 8 modes at a time, one AVX-512 register (two AVX2 ones, four SSE2 ones). */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define LITTLE_ENDIAN_LANES 1 /* pack_pair reads 32-bit lanes as 64-bit ones */
#else
#define LITTLE_ENDIAN_LANES 0
#endif
typedef int16_t v16hi __attribute__((vector_size(32)));
typedef int32_t v16si __attribute__((vector_size(64)));
typedef uint32_t v16su __attribute__((vector_size(64)));
typedef uint64_t v8du __attribute__((vector_size(64)));
typedef uint32_t v8su __attribute__((vector_size(32)));
typedef uint64_t v4du __attribute__((vector_size(32)));

/* z with its lanes permuted (GCC and clang spell it apart). */
#if defined(__clang__)
#define PERMUTE16(z, ...) __builtin_shufflevector(z, z, __VA_ARGS__)
#define PERMUTE4(z, ...) __builtin_shufflevector(z, z, __VA_ARGS__)
#define SHUFFLE4(a, b, ...) __builtin_shufflevector(a, b, __VA_ARGS__)
#else
#define PERMUTE16(z, ...) __builtin_shuffle(z, (v16su){ __VA_ARGS__ })
#define PERMUTE4(z, ...) __builtin_shuffle(z, (v4du){ __VA_ARGS__ })
#define SHUFFLE4(a, b, ...) __builtin_shuffle(a, b, (v4du){ __VA_ARGS__ })
#endif

/* Lanes 0 .. k - 1 (k 8 or 16) from p, the rest zero. */
static inline __attribute__((always_inline)) v16si load16(const int16_t *p, uint32_t k)
{
    v16hi h = { 0 };
    if (k == 2 * GROUP) {
        memcpy(&h, p, sizeof h);
    } else {
        memcpy(&h, p, GROUP * sizeof *p);
    }
    return __builtin_convertvector(h, v16si);
}

static inline __attribute__((always_inline)) v16su zigzag16(v16si v)
{
    return ((v16su)v << 1) ^ (v16su)(v >> 31);
}

static inline __attribute__((always_inline)) v16si min16(v16si a, v16si b)
{
    const v16si m = a < b;
    return (a & m) | (b & ~m);
}

/* The widths of each half's OR (which has the width of the half's maximum). */
static inline __attribute__((always_inline)) void widths16(v16su z, unsigned *w0, unsigned *w1)
{
    z |= PERMUTE16(z, 4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11);
    z |= PERMUTE16(z, 2, 3, 0, 1, 6, 7, 4, 5, 10, 11, 8, 9, 14, 15, 12, 13);
    z |= PERMUTE16(z, 1, 0, 3, 2, 5, 4, 7, 6, 9, 8, 11, 10, 13, 12, 15, 14);
    *w0 = bit_width(z[0]);
    *w1 = bit_width(z[GROUP]);
}

/* Two groups in lanes (the first in lanes 0-7 of width w0, the second in 8-15 of width
 * w1, both <= 16) packed as pack8 packs each: neighbouring lanes joined, then neighbouring
 * pairs, then the two 4w-bit halves of each group, each step in every lane at once.
 * Returns group 0's 8w bits in lanes 0 (low) and 1 (high), group 1's in lanes 2 and 3. */
static inline __attribute__((always_inline)) v4du pack_pair(v16su z, unsigned w0, unsigned w1)
{
    v8du x = (v8du)z; /* lane i: z[2i] | z[2i + 1] << 32 (little-endian) */
    const v8du s1 = { w0, w0, w0, w0, w1, w1, w1, w1 };
    x = (x & 0xffffffffu) | (x >> 32) << s1; /* 2w <= 32 bits a lane */
    v4du y = (v4du)__builtin_convertvector(x, v8su);
    const v4du s2 = { 2 * w0, 2 * w0, 2 * w1, 2 * w1 };
    y = (y & 0xffffffffu) | (y >> 32) << s2; /* 4w <= 64 bits a lane */
    /* y0 | y1 << 4w as two words; each shift split in two of 2w <= 32, as a shift by the
     * lane's width or more is undefined */
    const v4du yo = PERMUTE4(y, 1, 0, 3, 2);
    const v4du lo = y | (yo << s2) << s2;
    const v4du hi = (yo >> (32 - s2)) >> (32 - s2);
    return SHUFFLE4(lo, hi, 0, 4, 2, 6);
}

/* The residuals of groups g0 and g0 + 8 (k of their 16 modes read, the rest zero) of one
 * tree's full rows against the first n_pred predictors (qa, qb NULL: zero), and their
 * widths wd[g][p]; *lo keeps the lanes' minimum of every value read, for the range
 * check. */
static inline __attribute__((always_inline)) void pair_code(const int16_t *q, const int16_t *qa,
                                                            const int16_t *qb, uint32_t k,
                                                            int n_pred, v16su z[3],
                                                            unsigned wd[2][3], v16si *lo)
{
    const v16si zero = { 0 };
    const v16si v = load16(q, k);
    const v16si a = qa ? load16(qa, k) : zero, b = qb ? load16(qb, k) : zero;
    *lo = min16(min16(*lo, v), min16(a, b));
    z[PRED_ZERO] = zigzag16(v);
    widths16(z[PRED_ZERO], &wd[0][PRED_ZERO], &wd[1][PRED_ZERO]);
    if (n_pred > PRED_PREV) {
        z[PRED_PREV] = zigzag16(v - a);
        widths16(z[PRED_PREV], &wd[0][PRED_PREV], &wd[1][PRED_PREV]);
    }
    if (n_pred > PRED_LINEAR) {
        z[PRED_LINEAR] = zigzag16(v - (a + a - b));
        widths16(z[PRED_LINEAR], &wd[0][PRED_LINEAR], &wd[1][PRED_LINEAR]);
    }
}

/* Groups g0 and g0 + 8 (k modes, 8 or 16) of one frame at p, each with the narrowest of
 * the frame's first n_pred predictors; returns the end. Writes past it as pack8 does
 * (FAST_SLACK). */
static inline __attribute__((always_inline)) uint8_t *put_pair(uint8_t *p, const v16su z[3],
                                                               const unsigned wd[2][3],
                                                               uint32_t k, int n_pred)
{
    int best[2];
    const uint8_t gh[2] = { group_header(wd[0], n_pred, &best[0]),
                            group_header(wd[1], n_pred, &best[1]) };
    const unsigned w0 = gh[0] & 0x1fu, w1 = gh[1] & 0x1fu;
    const unsigned n_groups = k / GROUP;
    if (w0 <= 16 && w1 <= 16) {
        const v16su lo_half = { ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u };
        const v16su zs = (z[best[0]] & lo_half) | (z[best[1]] & ~lo_half);
        const v4du bits = pack_pair(zs, w0, w1);
        for (unsigned g = 0; g < n_groups; g++) {
            *p = gh[g];
            memcpy(p + 1, (const uint8_t *)&bits + 16 * g, 16);
            p += 1 + (g ? w1 : w0); /* a full group of width w is w bytes */
        }
        return p;
    }
    for (unsigned g = 0; g < n_groups; g++) { /* residuals of 17-18 bits: rare */
        uint32_t zz[2 * GROUP];
        memcpy(zz, &z[best[g]], sizeof zz);
        *p = gh[g];
        pack8(p + 1, zz + g * GROUP, gh[g] & 0x1fu);
        p += 1 + (gh[g] & 0x1fu);
    }
    return p;
}

/* Rows coded in 16-bit lanes (msg_state_rows.h): exact while every value read lies in
 * [-ROWS_LIMIT, ROWS_LIMIT - 1]. Four groups a register for AVX-512 (rows4_row), two for
 * AVX2 (rows2_row). */
#define ROWS_LIMIT 8192u

#define ROWS_GROUPS 4
#define ROWS_NAME(x) rows4_##x
#define ROWS_SWAP 1, 0, 3, 2, 5, 4, 7, 6
#define ROWS_EVEN_ODD 0, 9, 2, 11, 4, 13, 6, 15
#define ROWS_WIDTHS 0, 2, 4, 6, 1, 3, 5, 7, 8, 10, 12, 14, 8, 10, 12, 14
#define ROWS_PREV 4, 5, 6, 7, 4, 5, 6, 7, 4, 5, 6, 7, 4, 5, 6, 7
#define ROWS_LINEAR 8, 9, 10, 11, 8, 9, 10, 11, 8, 9, 10, 11, 8, 9, 10, 11
#define ROWS_SPREAD 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3
#define ROWS_BYTE_AT 0, 8, 16, 24, 0, 8, 16, 24, 0, 8, 16, 24, 0, 8, 16, 24
#define ROWS_FOLD(hw)                                                                       \
    ((hw) |= __builtin_shufflevector(hw, hw, 2, 3, 0, 1, 6, 7, 4, 5, 10, 11, 8, 9, 14, 15,  \
                                     12, 13),                                               \
     (hw) |= __builtin_shufflevector(hw, hw, 1, 0, 3, 2, 5, 4, 7, 6, 9, 8, 11, 10, 13, 12,  \
                                     15, 14))
#include "msg_state_rows.h"

#define ROWS_GROUPS 2
#define ROWS_NAME(x) rows2_##x
#define ROWS_SWAP 1, 0, 3, 2
#define ROWS_EVEN_ODD 0, 5, 2, 7
#define ROWS_WIDTHS 0, 2, 1, 3, 4, 6, 4, 6
#define ROWS_PREV 2, 3, 2, 3, 2, 3, 2, 3
#define ROWS_LINEAR 4, 5, 4, 5, 4, 5, 4, 5
#define ROWS_SPREAD 0, 0, 0, 0, 1, 1, 1, 1
#define ROWS_BYTE_AT 0, 8, 0, 8, 0, 8, 0, 8
#define ROWS_FOLD(hw) ((hw) |= __builtin_shufflevector(hw, hw, 1, 0, 3, 2, 5, 4, 7, 6))
#include "msg_state_rows.h"

/* Groups a register of the 16-bit path put_values takes: 4 where the CPU has AVX-512
 * (put_values' x86-64-v4 clone), 2 where it has AVX2 (the v3 clone), 0 (the 32-bit pairs
 * alone) otherwise. One lane, one DELTA of 100 000 trees x 32 modes: built for AVX-512,
 * 2.6-2.7 ms with 4 groups, 3.5 with 2, 4.0-4.4 in pairs; for AVX2, 4.1 ms with 2 groups
 * (25 with 4, whose 64-byte vectors split badly) against 13.7 in pairs; for SSE4.2 alone,
 * whose shifts of lanes by lanes go lane by lane, 10.6-10.8 ms in pairs against 17 and 22
 * in 16-bit lanes. GALE_WIRE_ROWS=4, 2 or 0 chooses instead: every choice writes the same
 * bytes on any CPU (for tests and comparisons). */
static int rows_groups(void)
{
    const char *force = getenv("GALE_WIRE_ROWS");
    if (force && (!strcmp(force, "4") || !strcmp(force, "2") || !strcmp(force, "0"))) {
        return force[0] - '0';
    }
#if defined(__GNUC__) && defined(__x86_64__)
    if (__builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl")) {
        return 4;
    }
    if (__builtin_cpu_supports("avx2")) {
        return 2;
    }
#endif
    return 0;
}

/* The smallest of q[m0..m1) (0 when empty). */
static inline int32_t row_min(const int16_t *q, uint32_t m0, uint32_t m1)
{
    int32_t lo = 0;
    for (uint32_t m = m0; m < m1; m++) {
        lo = q[m] < lo ? q[m] : lo;
    }
    return lo;
}

/* Tree t breaks none of check_state's counts in st (NULL: none to break). */
static inline bool counts_ok(const wire_scene *sc, const wire_state *st, uint32_t t)
{
    if (!st) {
        return true;
    }
    const uint32_t n = st->n_modes[t];
    return n <= sc->n_modes[sc->species[t]] && n <= st->stride;
}

/* Values of trees [t0, t1) into the nf frames w[f], group by group with the narrowest of
 * each frame's first n_pred[f] predictors (the residuals computed once for all), checking
 * every state's counts and values on the way (one pass over the rows): each tree straight
 * into memory while its worst case and FAST_SLACK fit before w[f]->end, the rest through
 * the checked writer (so a short buffer fails as it would byte by byte). Returns false at
 * the first tree whose state breaks a rule (check_state names it). */
static inline __attribute__((always_inline)) bool
    values_body(wire_writer *const *w, const int *n_pred, int nf, const wire_scene *sc,
                const wire_state *cur_in, const wire_state *prev_in, const wire_state *prev2_in,
                uint32_t t0, uint32_t t1)
{
    uint32_t z[3][GROUP];
    unsigned wd[3];
    int32_t v[WIRE_MAX_MODES + GROUP], a[WIRE_MAX_MODES + GROUP], b[WIRE_MAX_MODES + GROUP];
    v16si lo16 = { 0 };
    int32_t lo = 0;
    bool bad = false;
    int max_pred = 1;
    /* The frames' ends and the states kept in locals: a byte stored through a frame's
     * pointer could alias any field in memory, which would be read again after it. */
    uint8_t *pos[3], *lim[3];
    for (int f = 0; f < nf; f++) {
        max_pred = n_pred[f] > max_pred ? n_pred[f] : max_pred;
        pos[f] = w[f]->p;
        lim[f] = w[f]->end;
    }
    const wire_state none = { 0 };
    const wire_state cs = *cur_in, ps = prev_in ? *prev_in : none,
                     bs = prev2_in ? *prev2_in : none;
    const wire_state *const cur = &cs, *const prev = prev_in ? &ps : NULL,
                     *const prev2 = prev2_in ? &bs : NULL;
    const uint8_t *const species = sc->species;
    const uint32_t n_species = sc->n_species;
    const int groups = rows_groups();
    for (uint32_t t = t0; t < t1 && !bad; t++) {
        if (species[t] >= n_species || !counts_ok(sc, cur, t) || !counts_ok(sc, prev, t) ||
            !counts_ok(sc, prev2, t)) {
            for (int f = 0; f < nf; f++) {
                w[f]->p = pos[f];
            }
            return false;
        }
        const uint32_t n = cur->n_modes[t];
        const uint32_t na = prev ? prev->n_modes[t] : 0, nb = prev2 ? prev2->n_modes[t] : 0;
        const int16_t *q = cur->q + (size_t)t * cur->stride;
        if (t + PREFETCH_TREES < t1) {
            const size_t ahead = (size_t)t + PREFETCH_TREES;
            __builtin_prefetch(cur->q + ahead * cur->stride);
            if (prev) {
                __builtin_prefetch(prev->q + ahead * prev->stride);
            }
            if (prev2) {
                __builtin_prefetch(prev2->q + ahead * prev2->stride);
            }
        }
        const int16_t *qa = prev ? prev->q + (size_t)t * prev->stride : NULL;
        const int16_t *qb = prev2 ? prev2->q + (size_t)t * prev2->stride : NULL;
        /* the history values past what this frame reads are checked here */
        lo = qa && na > n ? (row_min(qa, n, na) < lo ? row_min(qa, n, na) : lo) : lo;
        lo = qb && nb > n ? (row_min(qb, n, nb) < lo ? row_min(qb, n, nb) : lo) : lo;
        if (n == 0) {
            continue;
        }
        bool all_fast = true;
        bool fast[3];
        for (int f = 0; f < nf; f++) {
            fast[f] = (size_t)(lim[f] - pos[f]) >= tree_bound(n) + FAST_SLACK;
            all_fast = all_fast && fast[f];
        }
        /* Whole groups of every row, straight into memory: read from the rows several
         * groups at a time, in 16-bit lanes (rows4_row, rows2_row), or two at a time in
         * 32-bit ones where a value or a residual is too wide for those or the CPU has
         * no AVX2 (pair_code, put_pair). */
        const bool rows = n % GROUP == 0 && (!prev || na >= n) && (!prev2 || nb >= n);
        if (rows && all_fast && LITTLE_ENDIAN_LANES) {
            const uint32_t span = groups ? (uint32_t)groups * GROUP : 2 * GROUP;
            for (uint32_t r0 = 0; r0 < n; r0 += span) {
                const uint32_t kr = n - r0 < span ? n - r0 : span;
                const int16_t *ra = qa ? qa + r0 : NULL, *rb = qb ? qb + r0 : NULL;
                if ((groups == 4 && rows4_row(pos, nf, n_pred, max_pred, q + r0, ra, rb, kr)) ||
                    (groups == 2 && rows2_row(pos, nf, n_pred, max_pred, q + r0, ra, rb, kr))) {
                    continue;
                }
                for (uint32_t g0 = r0; g0 < r0 + kr; g0 += 2 * GROUP) {
                    const uint32_t k = r0 + kr - g0 < 2 * GROUP ? r0 + kr - g0 : 2 * GROUP;
                    v16su z16[3];
                    unsigned wd2[2][3];
                    pair_code(q + g0, qa ? qa + g0 : NULL, qb ? qb + g0 : NULL, k, max_pred,
                              z16, wd2, &lo16);
                    for (int f = 0; f < nf; f++) {
                        pos[f] = put_pair(pos[f], z16, wd2, k, n_pred[f]);
                    }
                }
            }
            continue;
        }
        /* otherwise through the zero-padded copies, and the checked writer where the
         * worst case does not fit */
        for (int f = 0; f < nf; f++) {
            w[f]->p = pos[f];
        }
        tree_rows(cur, prev, prev2, t, v, a, b);
        const uint32_t ng = (n + GROUP - 1) / GROUP * GROUP;
        for (uint32_t m = 0; m < ng; m++) {
            lo = v[m] < lo ? v[m] : lo;
            lo = a[m] < lo ? a[m] : lo;
            lo = b[m] < lo ? b[m] : lo;
        }
        for (uint32_t g0 = 0; g0 < n; g0 += GROUP) {
            const uint32_t k = n - g0 < GROUP ? n - g0 : GROUP;
            group_code(v + g0, a + g0, b + g0, z, wd);
            for (int f = 0; f < nf; f++) {
                int best;
                const uint8_t gh = group_header(wd, n_pred[f], &best);
                const unsigned width = gh & 0x1fu;
                wire_writer *wf = w[f];
                if (fast[f]) {
                    *wf->p = gh;
                    pack8(wf->p + 1, z[best], width);
                    wf->p += 1 + ((size_t)k * width + 7) / 8;
                } else {
                    wire_put_u8(wf, gh);
                    put_bits(wf, z[best], k, width);
                }
            }
        }
        for (int f = 0; f < nf; f++) {
            bad = bad || w[f]->bad;
            pos[f] = w[f]->p;
        }
    }
    for (int f = 0; f < nf; f++) {
        w[f]->p = pos[f];
    }
    for (unsigned i = 0; i < 2 * GROUP; i++) {
        lo = lo16[i] < lo ? lo16[i] : lo;
    }
    return lo >= -WIRE_QMAX;
}

/* put_values for the frames the encoders write, each with its frame count and
 * predictors fixed, so the loops over frames and predictors and the checks of a history
 * not given fold away: a DELTA of 100 000 trees x 32 modes on one thread took 2.5-2.7 ms
 * so against 3.2-3.4 in general (gale-bench modal --threads 1, encode_ms_median). Cloned for AVX-512 and AVX2 machines (wider registers, variable shifts without cl,
 * lzcnt for the widths): the same bytes. */
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__) && \
    !defined(__SANITIZE_ADDRESS__)
#define VALUES_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define VALUES_CLONES
#endif
/* name: values_body for the frames n_pred lists, with the histories prev (h1) and prev2
 * (h2) given or NULL. */
#define VALUES_FIXED(name, h1, h2, ...)                                                      \
    VALUES_CLONES static bool name(wire_writer *const *w, const wire_scene *sc,              \
                                   const wire_state *cur, const wire_state *prev,            \
                                   const wire_state *prev2, uint32_t t0, uint32_t t1)        \
    {                                                                                        \
        static const int n_pred[] = { __VA_ARGS__ };                                         \
        return values_body(w, n_pred, (int)(sizeof n_pred / sizeof n_pred[0]), sc, cur,      \
                           (h1) ? prev : NULL, (h2) ? prev2 : NULL, t0, t1);                 \
    }
VALUES_FIXED(values_key, 0, 0, 1)
VALUES_FIXED(values_delta, 1, 0, 2)
VALUES_FIXED(values_delta2, 1, 1, 3)
VALUES_FIXED(values_snapshot2, 1, 0, 1, 2)
VALUES_FIXED(values_snapshot3, 1, 1, 1, 2, 3)

VALUES_CLONES static bool values_any(wire_writer *const *w, const int *n_pred, int nf,
                                     const wire_scene *sc, const wire_state *cur,
                                     const wire_state *prev, const wire_state *prev2,
                                     uint32_t t0, uint32_t t1)
{
    return values_body(w, n_pred, nf, sc, cur, prev, prev2, t0, t1);
}

/* Values of trees [t0, t1) into the nf frames w[f] (values_body): by the fixed frames
 * where they match, else in general. */
static bool put_values(wire_writer *const *w, const int *n_pred, int nf, const wire_scene *sc,
                       const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                       uint32_t t0, uint32_t t1)
{
    const int hist = (prev != NULL) + (prev2 != NULL) * 2; /* which histories are given */
    if (nf == 1 && n_pred[0] == 1 && hist == 0) {
        return values_key(w, sc, cur, prev, prev2, t0, t1);
    }
    if (nf == 1 && n_pred[0] == 2 && hist == 1) {
        return values_delta(w, sc, cur, prev, prev2, t0, t1);
    }
    if (nf == 1 && n_pred[0] == 3 && hist == 3) {
        return values_delta2(w, sc, cur, prev, prev2, t0, t1);
    }
    if (nf == 2 && n_pred[0] == 1 && n_pred[1] == 2 && hist == 1) {
        return values_snapshot2(w, sc, cur, prev, prev2, t0, t1);
    }
    if (nf == 3 && n_pred[0] == 1 && n_pred[1] == 2 && n_pred[2] == 3 && hist == 3) {
        return values_snapshot3(w, sc, cur, prev, prev2, t0, t1);
    }
    return values_any(w, n_pred, nf, sc, cur, prev, prev2, t0, t1);
}

typedef wire_lane_job lane_job;

/* True when trees [t0, t1) of st break none of check_state's rules. */
static bool states_ok(const wire_scene *sc, const wire_state *st, uint32_t t0, uint32_t t1)
{
    if (!st) {
        return true;
    }
    if (st->n_trees != sc->n_trees) {
        return false;
    }
    int32_t lo = 0;
    for (uint32_t t = t0; t < t1; t++) {
        const uint32_t sp = sc->species[t];
        const uint32_t n = st->n_modes[t];
        if (sp >= sc->n_species || n > sc->n_modes[sp] || n > st->stride) {
            return false;
        }
        const int16_t *q = st->q + (size_t)t * st->stride;
        for (uint32_t m = 0; m < n; m++) {
            lo = q[m] < lo ? q[m] : lo;
        }
    }
    return lo >= -WIRE_QMAX;
}

/* Moves down, in order, the lanes that have run from the first not yet moved, stopping
 * at one that has not run or went bad (lanes_join takes over from there). Lane k's bytes
 * go where the lanes before it end, which is below where lane k + 1 writes (each lane's
 * bytes fit its trees' worst case), so the lanes still running are untouched. One thread
 * moves at a time; a lane that finishes while another moves is taken by it, as the
 * mover looks again after letting go (sequentially consistent, so the finishing lane's
 * store and the mover's look cannot both miss). A lane missed all the same is moved by
 * lanes_join. */
static void lanes_settle(lane_job *j)
{
    for (;;) {
        if (atomic_exchange(&j->moving, 1u)) {
            return; /* the mover looks again when it lets go */
        }
        uint32_t k = j->n_moved;
        while (k < j->n_lanes && atomic_load(&j->done[k]) && !j->bad[k]) {
            for (int f = 0; f < j->nf; f++) {
                const size_t len = (size_t)(j->end[f][k] - j->at[f][k]);
                if (j->to[f] != j->at[f][k]) {
                    memmove(j->to[f], j->at[f][k], len);
                }
                j->to[f] += len;
            }
            k++;
        }
        j->n_moved = k;
        atomic_store(&j->moving, 0u);
        if (k >= j->n_lanes || !atomic_load(&j->done[k]) || j->bad[k]) {
            return;
        }
    }
}

static void lane_run(void *arg, int lane)
{
    lane_job *j = arg;
    const uint32_t i = (uint32_t)lane, t0 = j->t[i], t1 = j->t[i + 1];
    wire_writer w[3], *wp[3];
    for (int f = 0; f < j->nf; f++) {
        w[f] = wire_writer_make(j->at[f][i], (size_t)(j->at[f][i + 1] - j->at[f][i]));
        wp[f] = &w[f];
    }
    const bool ok = put_values(wp, j->n_pred, j->nf, j->sc, j->cur, j->prev, j->prev2, t0, t1);
    j->bad[i] = !ok;
    for (int f = 0; f < j->nf; f++) {
        j->bad[i] = j->bad[i] || w[f].bad;
        j->end[f][i] = w[f].p;
    }
    atomic_store(&j->done[i], 1u);
    lanes_settle(j);
}

/* The lanes' layout for the values of nf frames whose fixed parts are already in w[f]
 * (frame f coded with n_pred[f] predictors): the trees split into lanes->n contiguous
 * shares, each share's bytes written at the worst-case offset of its first tree (so the
 * lanes never overlap) and moved down after the lanes before it (lanes_settle as the lanes
 * finish, lanes_join for those left). The bytes
 * are those of one lane, whatever the split. With too little room for that layout, or no
 * lanes, one lane on the caller's thread. */
static void lanes_layout(lane_job *j, wire_writer *const *w, const int *n_pred, int nf,
                         const wire_scene *sc, const wire_state *cur, const wire_state *prev,
                         const wire_state *prev2, const wire_lanes *lanes)
{
    *j = (lane_job){ .sc = sc, .cur = cur, .prev = prev, .prev2 = prev2, .nf = nf, .n_lanes = 1 };
    const uint32_t n = cur->n_trees;
    uint32_t want = lanes && lanes->run && lanes->n > 1 ? (uint32_t)lanes->n : 1u;
    want = want > WIRE_MAX_LANES ? WIRE_MAX_LANES : want;
    want = want > n ? n : want;
    const size_t per_tree = tree_bound(cur->stride < WIRE_MAX_MODES ? cur->stride : WIRE_MAX_MODES);
    bool room = want > 1 && cur->stride <= WIRE_MAX_MODES;
    for (int f = 0; f < nf; f++) {
        j->n_pred[f] = n_pred[f];
        room = room && (size_t)(w[f]->end - w[f]->p) >= per_tree * n + (size_t)want * FAST_SLACK;
    }
    j->n_lanes = room ? want : 1;
    for (uint32_t i = 0; i <= j->n_lanes; i++) {
        j->t[i] = (uint32_t)((uint64_t)n * i / j->n_lanes);
        /* lane i's share: its trees' worst case, its slack, then the lanes before it */
        for (int f = 0; f < nf; f++) {
            j->at[f][i] = j->n_lanes == 1 ? (i ? w[f]->end : w[f]->p)
                                          : w[f]->p + per_tree * j->t[i] + (size_t)i * FAST_SLACK;
        }
    }
    /* a lane not run writes nothing (a defined frame, short of its trees) */
    for (uint32_t i = 0; i < j->n_lanes; i++) {
        j->bad[i] = false;
        atomic_init(&j->done[i], 0u);
        for (int f = 0; f < nf; f++) {
            j->end[f][i] = j->at[f][i];
        }
    }
    atomic_init(&j->moving, 0u);
    j->n_moved = 0;
    for (int f = 0; f < nf; f++) {
        j->to[f] = w[f]->p;
    }
}

/* Lanes [i0, i1) of j, lane i0 + k as job k. */
typedef struct lane_range {
    lane_job *j;
    int i0;
} lane_range;

static void lane_run_from(void *arg, int k)
{
    const lane_range *r = arg;
    lane_run(r->j, r->i0 + k);
}

static void lanes_run(lane_job *j, const wire_lanes *lanes, int i0, int i1)
{
    i0 = i0 < 0 ? 0 : i0;
    i1 = i1 > (int)j->n_lanes ? (int)j->n_lanes : i1;
    if (i1 - i0 == 1 || (i1 > i0 && j->n_lanes == 1)) {
        lane_run(j, i0);
    } else if (i1 > i0) {
        lane_range r = { j, i0 };
        lanes->run(lanes->ctx, i1 - i0, lane_run_from, &r);
    }
}

/* After every lane ran: the shares not yet moved down moved together. Returns non-zero
 * when a state breaks a rule (the caller's checks then name it); a short buffer sets that
 * frame's bad. */
static int lanes_join(lane_job *j, wire_writer *const *w)
{
    const int nf = j->nf;
    for (uint32_t i = 0; i < j->n_lanes; i++) {
        if (j->bad[i]) {
            /* a bad state, or lane 0 alone ran out of room: the caller tells which */
            if (states_ok(j->sc, j->cur, j->t[i], j->t[i + 1]) &&
                states_ok(j->sc, j->prev, j->t[i], j->t[i + 1]) &&
                states_ok(j->sc, j->prev2, j->t[i], j->t[i + 1])) {
                for (int f = 0; f < nf; f++) {
                    w[f]->bad = true;
                }
                return 0;
            }
            return 1;
        }
    }
    for (int f = 0; f < nf; f++) {
        uint8_t *p = j->to[f];
        for (uint32_t i = j->n_moved; i < j->n_lanes; i++) {
            const size_t len = (size_t)(j->end[f][i] - j->at[f][i]);
            if (p != j->at[f][i]) {
                memmove(p, j->at[f][i], len);
            }
            p += len;
        }
        w[f]->p = p;
    }
    return 0;
}

/* The checks and values of nf frames in lanes (lanes_layout, lanes_run, lanes_join). */
static int put_lanes(wire_writer *const *w, const int *n_pred, int nf, const wire_scene *sc,
                     const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                     const wire_lanes *lanes)
{
    lane_job j;
    lanes_layout(&j, w, n_pred, nf, sc, cur, prev, prev2, lanes);
    lanes_run(&j, lanes, 0, (int)j.n_lanes);
    return lanes_join(&j, w);
}

/* The state checks in order, for the message of the first rule broken. */
static int check_states(const wire_scene *sc, const wire_state *cur, const wire_state *prev,
                        const wire_state *prev2, const char *what, gale_err *err)
{
    int rc = check_state(sc, cur, what, "cur", err);
    if (!rc && prev) {
        rc = check_state(sc, prev, what, "prev", err);
    }
    if (!rc && prev2) {
        rc = check_state(sc, prev2, what, "prev2", err);
    }
    return rc;
}

static int finish(wire_writer *w, uint8_t *buf, size_t cap, size_t *len, const char *what,
                  gale_err *err)
{
    if (w->bad) {
        return gale_errf(err, GALE_E_RANGE, "%s: buffer: expected room, %zu bytes too small",
                         what, cap);
    }
    *len = (size_t)(w->p - buf);
    return 0;
}

/* The values through the lanes, then the frame's length; a broken rule of the states is
 * reported before a short buffer, as the checks run first. */
static int finish_lanes(wire_writer *w, const wire_scene *sc, const wire_state *cur,
                        const wire_state *prev, const wire_state *prev2,
                        const wire_lanes *lanes, uint8_t *buf, size_t cap, size_t *len,
                        const char *what, gale_err *err)
{
    wire_writer *const ws[1] = { w };
    const int n_pred[1] = { prev2 ? 3 : prev ? 2 : 1 };
    const int bad_state = !w->bad ? put_lanes(ws, n_pred, 1, sc, cur, prev, prev2, lanes) : 0;
    if (bad_state || w->bad) {
        int rc = check_states(sc, cur, prev, prev2, what, err);
        if (rc || bad_state) {
            return rc ? rc : gale_errf(err, GALE_E_RANGE, "%s: a state breaks a limit", what);
        }
    }
    return finish(w, buf, cap, len, what, err);
}

/* The same check as check_state's first one, before anything indexes by tree. */
static int check_counts(const wire_scene *sc, const wire_state *st, const char *what,
                        const char *name, gale_err *err)
{
    if (st && st->n_trees != sc->n_trees) {
        return gale_errf(err, GALE_E_ARG, "%s: %s.n_trees: expected %u (the scene), got %u",
                         what, name, sc->n_trees, st->n_trees);
    }
    return 0;
}

/* A KEYFRAME's fields before its values. */
static void put_key_head(wire_writer *w, const wire_header *h, uint32_t seq,
                         const wire_scene *scene, const wire_state *cur)
{
    wire_header hh = *h;
    hh.type = WIRE_MSG_KEYFRAME;
    hh.flags = 0;
    wire_put_header(w, &hh);
    wire_put_u32(w, seq);
    wire_put_u32(w, scene->n_trees);
    wire_put_u8(w, (uint8_t)scene->n_species);
    for (uint32_t s = 0; s < scene->n_species; s++) {
        wire_put_u8(w, scene->n_modes[s]);
        for (uint32_t m = 0; m < scene->n_modes[s]; m++) {
            wire_put_f32(w, scene->step[s][m]);
        }
    }
    if (!w->bad && (size_t)(w->end - w->p) >= scene->n_trees) {
        memcpy(w->p, scene->species, scene->n_trees);
        w->p += scene->n_trees;
    } else {
        w->bad = true;
    }
    put_set(w, scene, cur);
}

/* A DELTA's fields before its values. */
static void put_delta_head(wire_writer *w, const wire_header *h, uint32_t seq,
                           const wire_scene *scene, const wire_state *cur,
                           const wire_state *prev, bool two)
{
    wire_header hh = *h;
    hh.type = WIRE_MSG_DELTA;
    hh.flags = 0;
    wire_put_header(w, &hh);
    wire_put_u32(w, seq);
    wire_put_u8(w, two ? 2 : 1);
    if (same_set(cur, prev)) {
        wire_put_u8(w, SET_SAME);
    } else {
        put_set(w, scene, cur);
    }
}

int wire_encode_keyframe_lanes(const wire_header *h, uint32_t seq, const wire_scene *scene,
                               const wire_state *cur, const wire_lanes *lanes, uint8_t *buf,
                               size_t cap, size_t *len, gale_err *err)
{
    const char *what = "wire_encode_keyframe";
    int rc = check_scene(scene, what, err);
    if (!rc) {
        rc = check_counts(scene, cur, what, "cur", err);
    }
    for (uint32_t t = 0; !rc && t < scene->n_trees; t++) {
        /* put_set reads the species before the lanes check them */
        if (scene->species[t] >= scene->n_species) {
            rc = check_states(scene, cur, NULL, NULL, what, err);
        }
    }
    if (rc) {
        return rc;
    }
    wire_writer w = wire_writer_make(buf, cap);
    put_key_head(&w, h, seq, scene, cur);
    return finish_lanes(&w, scene, cur, NULL, NULL, lanes, buf, cap, len, what, err);
}

int wire_encode_keyframe(const wire_header *h, uint32_t seq, const wire_scene *scene,
                         const wire_state *cur, uint8_t *buf, size_t cap, size_t *len,
                         gale_err *err)
{
    return wire_encode_keyframe_lanes(h, seq, scene, cur, NULL, buf, cap, len, err);
}

int wire_encode_delta_lanes(const wire_header *h, uint32_t seq, const wire_scene *scene,
                            const wire_state *cur, const wire_state *prev,
                            const wire_state *prev2, const wire_lanes *lanes, uint8_t *buf,
                            size_t cap, size_t *len, gale_err *err)
{
    const char *what = "wire_encode_delta";
    if (!prev) {
        return gale_errf(err, GALE_E_ARG, "%s: prev: expected the snapshot seq - 1, got NULL",
                         what);
    }
    int rc = check_scene(scene, what, err);
    if (!rc) {
        rc = check_counts(scene, cur, what, "cur", err);
    }
    if (!rc) {
        rc = check_counts(scene, prev, what, "prev", err);
    }
    if (!rc) {
        rc = check_counts(scene, prev2, what, "prev2", err);
    }
    for (uint32_t t = 0; !rc && t < scene->n_trees; t++) {
        if (scene->species[t] >= scene->n_species) {
            rc = check_states(scene, cur, prev, prev2, what, err);
        }
    }
    if (rc) {
        return rc;
    }
    wire_writer w = wire_writer_make(buf, cap);
    put_delta_head(&w, h, seq, scene, cur, prev, prev2 != NULL);
    return finish_lanes(&w, scene, cur, prev, prev2, lanes, buf, cap, len, what, err);
}

int wire_encode_delta(const wire_header *h, uint32_t seq, const wire_scene *scene,
                      const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                      uint8_t *buf, size_t cap, size_t *len, gale_err *err)
{
    return wire_encode_delta_lanes(h, seq, scene, cur, prev, prev2, NULL, buf, cap, len, err);
}

/* The frames of wire_encode_snapshot_lanes one after the other: the first error is the
 * one the separate calls give. */
static int encode_each(const wire_header *h, uint32_t seq, const wire_scene *scene,
                       const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                       const wire_lanes *lanes, wire_frame_out *out)
{
    int rc = 0;
    if (out[0].buf) {
        rc = wire_encode_keyframe_lanes(h, seq, scene, cur, lanes, out[0].buf, out[0].cap,
                                        &out[0].len, out[0].err);
    }
    if (!rc && prev && out[1].buf) {
        rc = wire_encode_delta_lanes(h, seq, scene, cur, prev, NULL, lanes, out[1].buf,
                                     out[1].cap, &out[1].len, out[0].err);
    }
    if (!rc && prev && prev2 && out[2].buf) {
        rc = wire_encode_delta_lanes(h, seq, scene, cur, prev, prev2, lanes, out[2].buf,
                                     out[2].cap, &out[2].len, out[0].err);
    }
    return rc;
}

void wire_snapshot_begin(wire_snapshot_job *j, const wire_header *h, uint32_t seq,
                         const wire_scene *scene, const wire_state *cur,
                         const wire_state *prev, const wire_state *prev2,
                         const wire_lanes *lanes, wire_frame_out *out)
{
    prev2 = prev ? prev2 : NULL;
    j->h = *h;
    j->seq = seq;
    j->scene = scene;
    j->st[0] = *cur;
    j->st[1] = prev ? *prev : *cur;
    j->st[2] = prev2 ? *prev2 : *cur;
    j->prev = prev ? &j->st[1] : NULL;
    j->prev2 = prev2 ? &j->st[2] : NULL;
    j->lanes = lanes;
    j->out = out;
    j->lj.n_lanes = 0;
    const int avail = prev2 ? 3 : prev ? 2 : 1;
    int nf = 0;
    for (int f = 0; f < avail; f++) {
        out[f].len = 0;
        if (out[f].buf) {
            j->frame[nf++] = f;
        }
    }
    j->nf = nf;
    gale_err scratch;
    bool ok = !check_scene(scene, "", &scratch) && !check_counts(scene, cur, "", "", &scratch) &&
              !check_counts(scene, prev, "", "", &scratch) &&
              !check_counts(scene, prev2, "", "", &scratch);
    for (uint32_t t = 0; ok && t < scene->n_trees; t++) {
        ok = scene->species[t] < scene->n_species;
    }
    j->each = !ok;
    if (j->each) {
        return;
    }
    wire_writer *ws[3];
    int n_pred[3]; /* frame f is coded with the first f + 1 predictors */
    for (int k = 0; k < nf; k++) {
        const int f = j->frame[k];
        j->w[k] = wire_writer_make(out[f].buf, out[f].cap);
        ws[k] = &j->w[k];
        n_pred[k] = f + 1;
        if (f == 0) {
            put_key_head(&j->w[k], h, seq, scene, cur);
        } else {
            put_delta_head(&j->w[k], h, seq, scene, cur, prev, f == 2);
        }
        j->each = j->each || j->w[k].bad;
    }
    if (!j->each && nf > 0) {
        /* one pass over the rows for the frames: the residuals against each predictor
           once, each frame taking the narrowest of its own */
        lanes_layout(&j->lj, ws, n_pred, nf, scene, &j->st[0], j->prev, j->prev2, lanes);
    }
}

int wire_snapshot_lanes(const wire_snapshot_job *j)
{
    return j->each || !j->nf ? 0 : (int)j->lj.n_lanes;
}

void wire_snapshot_run(wire_snapshot_job *j, int i0, int i1)
{
    if (!j->each && j->nf) {
        lanes_run(&j->lj, j->lanes, i0, i1);
    }
}

int wire_snapshot_finish(wire_snapshot_job *j)
{
    const wire_state *cur = &j->st[0];
    if (j->each) {
        return encode_each(&j->h, j->seq, j->scene, cur, j->prev, j->prev2, j->lanes, j->out);
    }
    if (!j->nf) {
        return 0;
    }
    wire_writer *ws[3] = { &j->w[0], &j->w[1], &j->w[2] };
    if (lanes_join(&j->lj, ws)) {
        return encode_each(&j->h, j->seq, j->scene, cur, j->prev, j->prev2, j->lanes, j->out);
    }
    for (int f = 0; f < j->lj.nf; f++) {
        if (j->w[f].bad) {
            return encode_each(&j->h, j->seq, j->scene, cur, j->prev, j->prev2, j->lanes,
                               j->out);
        }
    }
    for (int k = 0; k < j->lj.nf; k++) {
        j->out[j->frame[k]].len = (size_t)(j->w[k].p - j->out[j->frame[k]].buf);
    }
    return 0;
}

int wire_encode_snapshot_lanes(const wire_header *h, uint32_t seq, const wire_scene *scene,
                               const wire_state *cur, const wire_state *prev,
                               const wire_state *prev2, const wire_lanes *lanes,
                               wire_frame_out *out)
{
    wire_snapshot_job j;
    wire_snapshot_begin(&j, h, seq, scene, cur, prev, prev2, lanes, out);
    wire_snapshot_run(&j, 0, wire_snapshot_lanes(&j));
    return wire_snapshot_finish(&j);
}

/* ---- decoding ---------------------------------------------------------------------- */

#define FAIL(...) return gale_errf(err, GALE_E_FORMAT, __VA_ARGS__)

/* Reads the tree set into n_modes[n_trees] (0 = absent). */
static int get_set(wire_reader *r, const uint8_t *start, const char *where,
                   const wire_scene *sc, const uint8_t *prev_modes, uint32_t max_modes,
                   bool keyframe, uint8_t *n_modes, gale_err *err)
{
    size_t at = wire_offset(r, start);
    uint8_t kind = wire_get_u8(r);
    if (r->bad) {
        FAIL("%s: tree set at byte %zu: truncated", where, at);
    }
    if (kind == SET_SAME && !keyframe) {
        memcpy(n_modes, prev_modes, sc->n_trees);
        return 0;
    }
    if (kind != SET_RUNS) {
        FAIL("%s: tree set kind at byte %zu: expected %s, got %u", where, at,
             keyframe ? "1 (runs)" : "0 (same) or 1 (runs)", (unsigned)kind);
    }
    memset(n_modes, 0, sc->n_trees);
    at = wire_offset(r, start);
    uint32_t n_runs = wire_get_varint(r);
    if (r->bad) {
        FAIL("%s: run count at byte %zu: truncated or bad varint", where, at);
    }
    if (n_runs > sc->n_trees) {
        FAIL("%s: run count at byte %zu: expected <= %u trees, got %u", where, at, sc->n_trees,
             n_runs);
    }
    uint32_t pos = 0;
    uint32_t n_present = 0;
    for (uint32_t i = 0; i < n_runs; i++) {
        at = wire_offset(r, start);
        uint32_t gap = wire_get_varint(r);
        uint32_t len = wire_get_varint(r);
        if (r->bad) {
            FAIL("%s: run %u at byte %zu: truncated or bad varint", where, i, at);
        }
        if (len == 0 || (i > 0 && gap == 0)) {
            FAIL("%s: run %u at byte %zu: expected gap >= %u and length >= 1, got %u, %u",
                 where, i, at, i > 0 ? 1u : 0u, gap, len);
        }
        if (gap > sc->n_trees - pos || len > sc->n_trees - pos - gap) {
            FAIL("%s: run %u at byte %zu: expected to end <= %u trees, got %u + %u + %u", where,
                 i, at, sc->n_trees, pos, gap, len);
        }
        pos += gap;
        for (uint32_t t = pos; t < pos + len; t++) {
            n_modes[t] = 1; /* marked; the count follows */
        }
        pos += len;
        n_present += len;
    }
    at = wire_offset(r, start);
    uint8_t mk = wire_get_u8(r);
    if (r->bad) {
        FAIL("%s: mode list kind at byte %zu: truncated", where, at);
    }
    if (mk != MODES_FULL && mk != MODES_LIST) {
        FAIL("%s: mode list kind at byte %zu: expected 0 (full) or 1 (list), got %u", where, at,
             (unsigned)mk);
    }
    if (mk == MODES_LIST && wire_reader_left(r) < n_present) {
        FAIL("%s: mode list at byte %zu: truncated: expected %u bytes, got %zu", where,
             wire_offset(r, start), n_present, wire_reader_left(r));
    }
    for (uint32_t t = 0; t < sc->n_trees; t++) {
        if (!n_modes[t]) {
            continue;
        }
        uint32_t full = sc->n_modes[sc->species[t]];
        uint32_t n = full;
        if (mk == MODES_LIST) {
            at = wire_offset(r, start);
            n = wire_get_u8(r);
            if (n == 0 || n > full) {
                FAIL("%s: modes of tree %u at byte %zu: expected 1..%u, got %u", where, t, at,
                     full, n);
            }
        }
        if (n > max_modes) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: modes of tree %u: expected <= %u (decoder capacity), got %u",
                             where, t, max_modes, n);
        }
        n_modes[t] = (uint8_t)n;
    }
    return 0;
}

/* A full group of width w (exactly w bytes, no padding) with 8 more bytes readable at p:
 * value i starts at bit i w and the 8 bytes from its first byte hold it (w + 7 <= 64), so
 * each is read, predicted and range-checked on its own, one loop per predictor. Writes v
 * and q as predict (below) does; true when a value is out of range. */
static inline bool group_full(const uint8_t *p, unsigned width, int pred, const int16_t *a,
                              const int16_t *b, int32_t *v, int16_t *q)
{
    const uint32_t mask = width ? (uint32_t)((1u << width) - 1u) : 0u;
    uint32_t out = 0;
#define GROUP_VALUE(i) ((uint32_t)(load_le64(p + ((i) * width >> 3)) >> ((i) * width & 7u)) & mask)
    if (pred == PRED_ZERO) {
#pragma GCC unroll 8
        for (uint32_t i = 0; i < GROUP; i++) {
            v[i] = wire_unzigzag(GROUP_VALUE(i));
        }
    } else if (pred == PRED_PREV) {
#pragma GCC unroll 8
        for (uint32_t i = 0; i < GROUP; i++) {
            v[i] = a[i] + wire_unzigzag(GROUP_VALUE(i));
        }
    } else {
#pragma GCC unroll 8
        for (uint32_t i = 0; i < GROUP; i++) {
            v[i] = 2 * a[i] - b[i] + wire_unzigzag(GROUP_VALUE(i));
        }
    }
#undef GROUP_VALUE
    for (uint32_t i = 0; i < GROUP; i++) {
        out |= (uint32_t)(v[i] + WIRE_QMAX) > 2u * WIRE_QMAX; /* v outside -QMAX..QMAX */
        q[i] = (int16_t)v[i];
    }
    return out != 0;
}

/* Values v = prediction + residual of k modes into v and q, one loop per predictor (a and b
 * the previous two snapshots' values); true when one is out of range (q then holds it
 * truncated, for the caller to reject the frame). */
static inline bool predict(const uint32_t *z, uint32_t k, int pred, const int16_t *a,
                           const int16_t *b, int32_t *v, int16_t *q)
{
    if (pred == PRED_ZERO) {
        for (uint32_t i = 0; i < k; i++) {
            v[i] = wire_unzigzag(z[i]);
        }
    } else if (pred == PRED_PREV) {
        for (uint32_t i = 0; i < k; i++) {
            v[i] = a[i] + wire_unzigzag(z[i]);
        }
    } else {
        for (uint32_t i = 0; i < k; i++) {
            v[i] = 2 * a[i] - b[i] + wire_unzigzag(z[i]);
        }
    }
    bool out = false;
    for (uint32_t i = 0; i < k; i++) {
        out |= v[i] < -WIRE_QMAX || v[i] > WIRE_QMAX;
        q[i] = (int16_t)v[i];
    }
    return out;
}

static int get_values(wire_reader *r, const uint8_t *start, const char *where, uint32_t n_trees,
                      uint32_t stride, const uint8_t *n_modes, const int16_t *prev,
                      const int16_t *prev2, int hist, int16_t *q, gale_err *err)
{
    uint32_t z[GROUP];
    for (uint32_t t = 0; t < n_trees; t++) {
        int16_t *qt = q + (size_t)t * stride;
        uint32_t n = n_modes[t];
        memset(qt + n, 0, (stride - n) * sizeof *qt);
        for (uint32_t g0 = 0; g0 < n; g0 += GROUP) {
            uint32_t k = n - g0 < GROUP ? n - g0 : GROUP;
            size_t at = wire_offset(r, start);
            uint8_t gh = wire_get_u8(r);
            unsigned width = gh & 0x1fu;
            int pred = gh >> 5;
            if (r->bad) {
                FAIL("%s: tree %u group %u at byte %zu: truncated", where, t, g0 / GROUP, at);
            }
            if (width > MAX_WIDTH || pred > hist) {
                FAIL("%s: tree %u group %u at byte %zu: expected width <= %u and predictor <= %d, got %u, %d",
                     where, t, g0 / GROUP, at, MAX_WIDTH, hist, width, pred);
            }
            const size_t ix = (size_t)t * stride + g0;
            int32_t v[GROUP];
            bool out;
            if (k == GROUP && wire_reader_left(r) >= (size_t)width + 8u) {
                out = group_full(r->p, width, pred, prev + ix, prev2 + ix, v, qt + g0);
                r->p += width;
            } else {
                get_bits(r, z, k, width);
                if (r->bad) {
                    FAIL("%s: tree %u group %u at byte %zu: truncated or nonzero padding", where,
                         t, g0 / GROUP, at);
                }
                out = predict(z, k, pred, prev + ix, prev2 + ix, v, qt + g0);
            }
            for (uint32_t i = 0; out && i < k; i++) {
                if (v[i] < -WIRE_QMAX || v[i] > WIRE_QMAX) {
                    FAIL("%s: tree %u mode %u at byte %zu: expected |q| <= %d, got %d", where,
                         t, g0 + i, at, WIRE_QMAX, v[i]);
                }
            }
        }
    }
    return 0;
}

int wire_decode_state(wire_decoder *d, wire_reader *r, const wire_header *h, wire_frame *out,
                      gale_err *err)
{
    const uint8_t *start = r->p - WIRE_HEADER_BYTES;
    const bool key = h->type == WIRE_MSG_KEYFRAME;
    char where[64];
    snprintf(where, sizeof where, "wire: %s tick %u", wire_type_name(h->type), h->tick);
    uint32_t seq = wire_get_u32(r);
    if (r->bad) {
        FAIL("%s: seq at byte %u: truncated", where, WIRE_HEADER_BYTES);
    }
    wire_slot *dst = &d->slot[d->scratch];
    const wire_slot *last = &d->slot[d->last];
    const wire_slot *before = &d->slot[d->before];
    wire_scene *sc = &d->scene[d->scene_cur];
    int hist = 0;
    if (key) {
        sc = &d->scene[1 - d->scene_cur];
        size_t at = wire_offset(r, start);
        sc->n_trees = wire_get_u32(r);
        if (r->bad) {
            FAIL("%s: n_trees at byte %zu: truncated", where, at);
        }
        if (sc->n_trees == 0 || sc->n_trees > WIRE_MAX_TREES) {
            FAIL("%s: n_trees at byte %zu: expected 1..%u, got %u", where, at, WIRE_MAX_TREES,
                 sc->n_trees);
        }
        if (sc->n_trees > d->max_trees) {
            return gale_errf(err, GALE_E_RANGE,
                             "%s: n_trees: expected <= %u (decoder capacity), got %u", where,
                             d->max_trees, sc->n_trees);
        }
        at = wire_offset(r, start);
        sc->n_species = wire_get_u8(r);
        if (r->bad || sc->n_species == 0 || sc->n_species > WIRE_MAX_SPECIES) {
            FAIL("%s: n_species at byte %zu: expected 1..%u, got %s%u", where, at,
                 WIRE_MAX_SPECIES, r->bad ? "truncated " : "", sc->n_species);
        }
        for (uint32_t s = 0; s < sc->n_species; s++) {
            at = wire_offset(r, start);
            uint8_t nm = wire_get_u8(r);
            if (r->bad || nm == 0 || nm > WIRE_MAX_MODES) {
                FAIL("%s: species %u n_modes at byte %zu: expected 1..%u, got %s%u", where, s,
                     at, WIRE_MAX_MODES, r->bad ? "truncated " : "", (unsigned)nm);
            }
            sc->n_modes[s] = nm;
            for (uint32_t m = 0; m < nm; m++) {
                at = wire_offset(r, start);
                float st = wire_get_f32(r);
                if (r->bad) {
                    FAIL("%s: species %u step %u at byte %zu: truncated", where, s, m, at);
                }
                if (!(st > 0.0f && st <= WIRE_MAX_STEP)) {
                    FAIL("%s: species %u step %u at byte %zu: expected in (0, %g], got %g",
                         where, s, m, at, (double)WIRE_MAX_STEP, (double)st);
                }
                sc->step[s][m] = st;
            }
        }
        at = wire_offset(r, start);
        if (wire_reader_left(r) < sc->n_trees) {
            FAIL("%s: species of trees at byte %zu: truncated: expected %u bytes, got %zu",
                 where, at, sc->n_trees, wire_reader_left(r));
        }
        uint8_t *species = d->species[1 - d->scene_cur];
        for (uint32_t t = 0; t < sc->n_trees; t++) {
            species[t] = wire_get_u8(r);
            if (species[t] >= sc->n_species) {
                FAIL("%s: species of tree %u at byte %zu: expected < %u, got %u", where, t,
                     at + t, sc->n_species, (unsigned)species[t]);
            }
        }
    } else {
        if (!d->synced) {
            return gale_errf(err, GALE_E_STATE,
                             "%s: seq %u: no keyframe yet: waiting for a keyframe", where, seq);
        }
        if (seq != last->seq + 1u) {
            return gale_errf(err, GALE_E_STATE,
                             "%s: seq %u: gap: expected seq %u (holding %u): waiting for a keyframe",
                             where, seq, last->seq + 1u, last->seq);
        }
        size_t at = wire_offset(r, start);
        uint8_t hb = wire_get_u8(r);
        if (r->bad) {
            FAIL("%s: history at byte %zu: truncated", where, at);
        }
        if (hb < 1 || hb > 2) {
            FAIL("%s: history at byte %zu: expected 1 or 2, got %u", where, at, (unsigned)hb);
        }
        if (hb == 2 && !d->have_before) {
            return gale_errf(err, GALE_E_STATE,
                             "%s: seq %u: predicts from seq %u which this decoder does not hold: waiting for a keyframe",
                             where, seq, seq - 2u);
        }
        hist = hb;
    }
    int rc = get_set(r, start, where, sc, last->n_modes, d->max_modes, key, dst->n_modes, err);
    if (rc) {
        return rc;
    }
    rc = get_values(r, start, where, sc->n_trees, d->max_modes, dst->n_modes, last->q,
                    before->q, hist, dst->q, err);
    if (rc) {
        return rc;
    }
    if (wire_reader_left(r) != 0) {
        FAIL("%s: length: expected %zu bytes, got %zu (trailing bytes)", where,
             wire_offset(r, start), wire_offset(r, start) + wire_reader_left(r));
    }
    /* The whole frame is valid: commit. */
    dst->seq = seq;
    int old_before = d->before;
    if (key) {
        d->scene_cur = 1 - d->scene_cur;
        d->have_before = false;
        d->scratch = d->last;
        d->last = (int)(dst - d->slot);
    } else {
        d->before = d->last;
        d->last = d->scratch;
        d->scratch = old_before;
        d->have_before = true;
    }
    d->synced = true;
    out->seq = seq;
    return 0;
}
