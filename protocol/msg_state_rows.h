/* The row coder in 16-bit lanes, ROWS_GROUPS groups of 8 modes a register: included by
 * msg_state_rows.c once per width, with ROWS_GROUPS, ROWS_NAME and the lane orders below
 * defined, and undefined again at the end.
 *
 * It codes up to ROWS_GROUPS groups of one row at once: the residuals against each
 * predictor, each group's width from the exponent of its OR's float, the narrowest
 * predictor, and the packing (neighbouring words joined, then pairs, then the two 4w-bit
 * halves of a group), writing the bytes put_pair writes. It is exact while every value read
 * lies in [-ROWS_LIMIT, ROWS_LIMIT - 1]: the linear residual v - 2a + b is then within
 * +-4 ROWS_LIMIT <= 2^15 and its zigzag fits 16 bits.
 *
 * Lane orders, each a list of lane indices (ROWS_GROUPS = G):
 *   ROWS_SWAP      2G: each 64-bit lane with its neighbour (the halves of a group)
 *   ROWS_EVEN_ODD  2G: even lanes of the first vector, odd of the second
 *   ROWS_WIDTHS    4G: the zero and previous predictors' group ORs (2G lanes, alternating)
 *                  and the linear one's (2G, each twice): the zero predictor's per group,
 *                  then the previous one's, then the linear one's
 *   ROWS_PREV      4G: the previous predictor's widths moved to the first G lanes
 *   ROWS_LINEAR    4G: the linear predictor's, likewise
 *   ROWS_SPREAD    4G: lane g moved to the four lanes of group g
 *   ROWS_BYTE_AT   4G: the bit of lane g's header byte in the header word
 *   ROWS_FOLD(hw)  joins the first G lanes of hw into lane 0 */
#ifndef ROWS_GROUPS
#error "define ROWS_GROUPS and the lane orders before including msg_state_rows.h"
#endif

#define ROWS_MODES (ROWS_GROUPS * GROUP)

typedef uint16_t ROWS_NAME(vhu) __attribute__((vector_size(2 * ROWS_MODES)));
typedef int16_t ROWS_NAME(vhi) __attribute__((vector_size(2 * ROWS_MODES)));
typedef uint64_t ROWS_NAME(vdu) __attribute__((vector_size(2 * ROWS_MODES)));
typedef uint32_t ROWS_NAME(vnu) __attribute__((vector_size(ROWS_MODES)));
typedef uint32_t ROWS_NAME(vsu) __attribute__((vector_size(2 * ROWS_MODES)));
typedef int32_t ROWS_NAME(vsi) __attribute__((vector_size(2 * ROWS_MODES)));
typedef float ROWS_NAME(vsf) __attribute__((vector_size(2 * ROWS_MODES)));

/* Lanes 0 .. k - 1 (k a whole number of groups) from p, the rest zero. */
static inline __attribute__((always_inline)) ROWS_NAME(vhu)
    ROWS_NAME(load)(const int16_t *p, uint32_t k)
{
    ROWS_NAME(vhu) h = { 0 };
    if (k == ROWS_MODES) {
        memcpy(&h, p, sizeof h);
    } else {
        for (uint32_t g = 0; g < k / GROUP; g++) {
            memcpy((uint8_t *)&h + 2 * GROUP * g, p + GROUP * g, 2 * GROUP);
        }
    }
    return h;
}

static inline __attribute__((always_inline)) ROWS_NAME(vhu) ROWS_NAME(zigzag)(ROWS_NAME(vhu) r)
{
    return (r << 1) ^ (ROWS_NAME(vhu))((ROWS_NAME(vhi))r >> 15);
}

/* The residuals of up to G groups of one row (k modes read) against the first n_pred
 * predictors, and their widths in the order ROWS_WIDTHS gives. A value out of range sets
 * bit 14 or 15 of its lane in every residual, so its group's width is 15 or more
 * whichever predictor is chosen (put then falls back). */
static inline __attribute__((always_inline)) void
    ROWS_NAME(code)(const int16_t *q, const int16_t *qa, const int16_t *qb, uint32_t k,
                    int n_pred, ROWS_NAME(vhu) z[3], ROWS_NAME(vsi) *wd)
{
    const ROWS_NAME(vhu) zero = { 0 };
    const ROWS_NAME(vhu) v = ROWS_NAME(load)(q, k);
    const ROWS_NAME(vhu) a = qa ? ROWS_NAME(load)(qa, k) : zero;
    const ROWS_NAME(vhu) b = qb ? ROWS_NAME(load)(qb, k) : zero;
    const ROWS_NAME(vhu) out = ((v + ROWS_LIMIT) | (a + ROWS_LIMIT) | (b + ROWS_LIMIT)) &
                               (uint16_t)~(2u * ROWS_LIMIT - 1u);
    /* unsigned lanes wrap; in range the difference is the signed residual */
    z[PRED_ZERO] = ROWS_NAME(zigzag)(v) | out;
    z[PRED_PREV] = n_pred > PRED_PREV ? ROWS_NAME(zigzag)(v - a) | out : zero;
    z[PRED_LINEAR] = n_pred > PRED_LINEAR ? ROWS_NAME(zigzag)(v - a - a + b) | out : zero;
    /* the OR of each group's 8 lanes: the halves of a group joined, then its 4 words */
    ROWS_NAME(vdu) x0 = (ROWS_NAME(vdu))z[PRED_ZERO], x1 = (ROWS_NAME(vdu))z[PRED_PREV],
                   x2 = (ROWS_NAME(vdu))z[PRED_LINEAR];
    x0 |= __builtin_shufflevector(x0, x0, ROWS_SWAP);
    x1 |= __builtin_shufflevector(x1, x1, ROWS_SWAP);
    x2 |= __builtin_shufflevector(x2, x2, ROWS_SWAP);
    ROWS_NAME(vdu) m = __builtin_shufflevector(x0, x1, ROWS_EVEN_ODD);
    m |= m >> 32;
    m |= m >> 16;
    x2 |= x2 >> 32;
    x2 |= x2 >> 16;
    const ROWS_NAME(vnu) mn = __builtin_convertvector(m & 0xffffu, ROWS_NAME(vnu));
    const ROWS_NAME(vnu) ln = __builtin_convertvector(x2 & 0xffffu, ROWS_NAME(vnu));
    const ROWS_NAME(vsu) ors = __builtin_shufflevector(mn, ln, ROWS_WIDTHS);
    /* the width of x < 2^24 is its float's exponent less 126; 0 for x = 0 */
    const ROWS_NAME(vsi) e =
        ((ROWS_NAME(vsi))__builtin_convertvector((ROWS_NAME(vsi))ors, ROWS_NAME(vsf)) >> 23) -
        126;
    *wd = e & ~(e >> 31);
}

/* The groups code found (k modes, a whole number of groups) of one frame at *pp with the
 * narrowest of its first n_pred predictors (the first of equal widths), as put_pair writes
 * them. Returns false, writing nothing, when a group would be 15 bits wide or more: a
 * value out of range, or a residual too wide for these lanes. */
static inline __attribute__((always_inline)) bool
    ROWS_NAME(put)(uint8_t **pp, const ROWS_NAME(vhu) z[3], ROWS_NAME(vsi) wd, uint32_t k,
                   int n_pred)
{
    ROWS_NAME(vsi) wb = wd, best = { 0 };
    if (n_pred > PRED_PREV) {
        const ROWS_NAME(vsi) w1 = __builtin_shufflevector(wd, wd, ROWS_PREV);
        const ROWS_NAME(vsi) lt = w1 < wb;
        wb = (w1 & lt) | (wb & ~lt);
        best = lt & PRED_PREV;
    }
    if (n_pred > PRED_LINEAR) {
        const ROWS_NAME(vsi) w2 = __builtin_shufflevector(wd, wd, ROWS_LINEAR);
        const ROWS_NAME(vsi) lt = w2 < wb;
        wb = (w2 & lt) | (wb & ~lt);
        best = (lt & PRED_LINEAR) | (best & ~lt);
    }
    /* the header bytes in one word: each lane's moved to its byte, then joined */
    const ROWS_NAME(vsu) byte_at = { ROWS_BYTE_AT };
    ROWS_NAME(vsu) hw = (ROWS_NAME(vsu))(best << 5 | wb) << byte_at;
    ROWS_FOLD(hw);
    const uint32_t heads = hw[0];
    /* a width of 15-18 plus 113 reaches bit 7 of its byte */
    const uint32_t bytes = (uint32_t)((1ull << (8 * ROWS_GROUPS)) - 1u);
    if ((((heads & 0x1f1f1f1fu) + (0x71717171u & bytes)) & 0x80808080u) != 0) {
        return false;
    }
    /* each group's residuals from its chosen predictor, then packed */
    const ROWS_NAME(vsi) bg = __builtin_shufflevector(best, best, ROWS_SPREAD);
    const ROWS_NAME(vsu) s1 = (ROWS_NAME(vsu))__builtin_shufflevector(wb, wb, ROWS_SPREAD);
    const ROWS_NAME(vsu) m1 = (ROWS_NAME(vsu))(bg == PRED_PREV);
    const ROWS_NAME(vsu) m2 = (ROWS_NAME(vsu))(bg == PRED_LINEAR);
    ROWS_NAME(vsu) zs = (ROWS_NAME(vsu))z[PRED_ZERO];
    zs = ((ROWS_NAME(vsu))z[PRED_PREV] & m1) | (zs & ~m1);
    zs = ((ROWS_NAME(vsu))z[PRED_LINEAR] & m2) | (zs & ~m2);
    zs = (zs & 0xffffu) | (zs >> 16) << s1; /* 2w <= 32 bits a lane */
    ROWS_NAME(vdu) y = (ROWS_NAME(vdu))zs;
    const ROWS_NAME(vdu) s2 = ((ROWS_NAME(vdu))s1 & 0xffffffffu) * 2u;
    y = (y & 0xffffffffu) | (y >> 32) << s2; /* 4w <= 64 bits a lane */
    /* y0 | y1 << 4w as two words; each shift split in two of 2w <= 32, as a shift by the
     * lane's width or more is undefined */
    const ROWS_NAME(vdu) yo = __builtin_shufflevector(y, y, ROWS_SWAP);
    const ROWS_NAME(vdu) lo = y | (yo << s2) << s2;
    const ROWS_NAME(vdu) hi = (y >> (32 - s2)) >> (32 - s2);
    const ROWS_NAME(vdu) bits = __builtin_shufflevector(lo, hi, ROWS_EVEN_ODD);
    uint8_t *p = *pp;
    for (unsigned g = 0; g < k / GROUP; g++) {
        const uint8_t gh = (uint8_t)(heads >> (8 * g));
        *p = gh;
        memcpy(p + 1, (const uint8_t *)&bits + 16 * g, 16);
        p += 1 + (gh & 0x1fu); /* a full group of width w is w bytes */
    }
    *pp = p;
    return true;
}

/* Up to G groups of one row (k modes) into each of the nf frames at pos[f]: all of them,
 * or none when a group of any frame would be 15 bits wide or more (the frames' bytes stay
 * in step; the caller codes those groups in 32-bit lanes). */
static inline __attribute__((always_inline)) bool
    ROWS_NAME(row)(uint8_t **pos, int nf, const int *n_pred, int max_pred, const int16_t *q,
                   const int16_t *qa, const int16_t *qb, uint32_t k)
{
    ROWS_NAME(vhu) z[3];
    ROWS_NAME(vsi) wd;
    ROWS_NAME(code)(q, qa, qb, k, max_pred, z, &wd);
    uint8_t *at[3];
    for (int f = 0; f < nf; f++) {
        at[f] = pos[f];
        if (!ROWS_NAME(put)(&at[f], z, wd, k, n_pred[f])) {
            return false;
        }
    }
    for (int f = 0; f < nf; f++) {
        pos[f] = at[f];
    }
    return true;
}

#undef ROWS_MODES
#undef ROWS_GROUPS
#undef ROWS_NAME
#undef ROWS_SWAP
#undef ROWS_EVEN_ODD
#undef ROWS_WIDTHS
#undef ROWS_PREV
#undef ROWS_LINEAR
#undef ROWS_SPREAD
#undef ROWS_BYTE_AT
#undef ROWS_FOLD
