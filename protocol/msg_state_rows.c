/* The values section of a state frame: each tree's groups coded against the predictors
 * and packed, for one frame or several at once (a snapshot's KEYFRAME and DELTAs from one
 * pass over the rows), in 16-bit lanes several groups a register (msg_state_rows.h), in
 * 32-bit pairs, or value by value through the checked writer near a buffer's end. */
#include <stdlib.h>
#include <string.h>

#include "msg_state_int.h"

/* The vector helpers below are always inlined into state_put_values' clones, so no vector
 * crosses a call; GCC's note that such a call would change ABI without AVX is moot. */
#pragma GCC diagnostic ignored "-Wpsabi"

/* Rows asked for this many trees ahead: the rows come from memory the update wrote last,
 * and 16 trees (~0.5 us of coding) cover its latency; at 100 000 trees the coding took
 * a fifth less than with the hardware's prefetch alone. */
#define PREFETCH_TREES 16u

static unsigned bit_width(uint32_t v)
{
    return v ? 32u - (unsigned)__builtin_clz(v) : 0u;
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

/* Groups a register of the 16-bit path state_put_values takes: 4 where the CPU has AVX-512
 * (state_put_values' x86-64-v4 clone), 2 where it has AVX2 (the v3 clone), 0 (the 32-bit pairs
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

/* Trees t..t+7 of st (NULL: none) are all sent with 0 modes. */
static inline bool unsent8(const wire_state *st, uint32_t t)
{
    uint64_t x = 0;
    if (st) {
        memcpy(&x, st->n_modes + t, sizeof x);
    }
    return x == 0;
}

/* Species sp[0..7] are all below n_species. */
static inline bool species8_ok(const uint8_t *sp, uint32_t n_species)
{
    uint8_t hi = 0;
    for (int i = 0; i < 8; i++) {
        hi = sp[i] > hi ? sp[i] : hi;
    }
    return hi < n_species;
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
        /* trees no state sends, 8 at a time (only their species are checked): a view's
         * stream sends a few trees of many, and their turn through the loop below cost it
         * as much as a tenth of the whole state's */
        while (t + 8 <= t1 && unsent8(cur, t) && unsent8(prev, t) && unsent8(prev2, t) &&
               species8_ok(species + t, n_species)) {
            t += 8;
        }
        if (t >= t1) {
            break;
        }
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
            /* only the rows read: a view's stream sends a few trees of many, and fetching
             * every tree's rows cost it the whole state's memory traffic */
            const size_t ahead = (size_t)t + PREFETCH_TREES;
            if (cur->n_modes[ahead]) {
                __builtin_prefetch(cur->q + ahead * cur->stride);
            }
            if (prev && prev->n_modes[ahead]) {
                __builtin_prefetch(prev->q + ahead * prev->stride);
            }
            if (prev2 && prev2->n_modes[ahead]) {
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

/* state_put_values for the frames the encoders write, each with its frame count and
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
bool state_put_values(wire_writer *const *w, const int *n_pred, int nf, const wire_scene *sc,
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
