/* Batch modal update of every tree (Diener 2008 sections 3-4): the wind sampled at a
 * tree is rotated into its frame, f_i = |v| v.p_i, and each mode's oscillator advances by
 * the exact 2x2 transition (server/oscillator.h), then is quantised for the wire.
 * Storage is tree-major, each tree's modes contiguous and padded to a vector multiple:
 * the inner loop runs over one tree's modes with per-species constant arrays, so it
 * vectorises, and the quantised modes land in the tree's snapshot row as one
 * contiguous store (no transpose). */
#include "modal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "big_alloc.h"
#include "wire_limits.h"
#include "oscillator.h"
#include "sim_team.h"
#include "wire.h"

/* Modes per tree are padded to a multiple of this (one AVX-512 vector of floats). */
#define MODE_PAD 16u

/* One species' per-mode constants as arrays over the padded modes: the update runs
 * over a tree's modes as vector lanes. Padding modes have all-zero coefficients, so
 * their q stays 0 and quantises to 0 (the snapshot's "beyond a tree's modes"). */
typedef struct modal_sp {
    uint32_t n_modes;
    float *a11, *a12, *a21, *a22, *b1, *b2; /* osc_exact per mode */
    float *px, *py, *pz;                     /* wind basis p_i, tree frame */
    float *inv_step;                         /* 1 / quantisation step; 0 in padding */
    float drag_u0, drag_cap, drag_b;         /* the streamlining's terms that do not depend
                                                on U (drag_law_terms; PHYSICS.md
                                                "Streamlining") */
} modal_sp;

struct modal {
    uint32_t n_trees, n_species, stride, pad;
    int n_threads;
    modal_sp *sp;            /* owned: [n_species] */
    float *coef;             /* owned: the arrays modal_sp points into */
    float *state;            /* owned: per tree [2][pad]: q then q' */
    uint8_t *tree_species;   /* owned: [n_trees] */
    float *cos_yaw, *sin_yaw;/* owned: [n_trees] */
    float *drag_mult;        /* owned: [n_trees] multiplier of the tree's modal force, 1 =
                                intact (damage.h: stripped leaves, lost branches) */
    float *qnorm2;           /* owned: [n_trees] Σ q_i² after the last tick (damage.h screens
                                with it without reading the state) */
    float *force_scale;      /* owned: [n_trees] s(U) k_t |v| of the last tick (damage.h forms
                                the tick's force vector from it without a second power) */
};

modal *modal_create(const modal_desc *d, gale_err *err)
{
    modal *m = NULL;
    if (d->n_trees == 0 || d->n_trees > WIRE_MAX_TREES) {
        gale_errf(err, GALE_E_ARG, "modal_create: n_trees: expected 1..%u, got %u",
                  WIRE_MAX_TREES, d->n_trees);
        return NULL;
    }
    if (d->n_species == 0 || d->n_species > WIRE_MAX_SPECIES || !d->species ||
        !d->tree_species) {
        gale_errf(err, GALE_E_ARG,
                  "modal_create: n_species: expected 1..%u with species and tree_species, got %u",
                  WIRE_MAX_SPECIES, d->n_species);
        return NULL;
    }
    double dt_s = d->dt_s > 0.0 ? d->dt_s : 1.0 / 60.0;
    if (!(dt_s > 0.0 && dt_s <= 1.0)) {
        gale_errf(err, GALE_E_ARG, "modal_create: dt_s: expected (0, 1], got %g", dt_s);
        return NULL;
    }
    m = calloc(1, sizeof *m);
    if (!m) {
        goto nomem;
    }
    m->n_trees = d->n_trees;
    m->n_species = d->n_species;
    m->n_threads = d->n_threads > 0 ? d->n_threads : 2;
    m->sp = calloc(d->n_species, sizeof *m->sp);
    if (!m->sp) {
        goto nomem;
    }
    for (uint32_t s = 0; s < d->n_species; s++) {
        const modal_species *in = &d->species[s];
        if (in->n_modes == 0 || in->n_modes > WIRE_MAX_MODES || !in->omega || !in->gamma ||
            !in->wind_basis || !in->qstep) {
            gale_errf(err, GALE_E_ARG,
                      "modal_create: species[%u].n_modes: expected 1..%u with omega, gamma, wind_basis, qstep, got %u",
                      s, WIRE_MAX_MODES, in->n_modes);
            goto fail;
        }
        m->sp[s].n_modes = in->n_modes;
        const drag_law rigid = { 0 };
        drag_law_terms(d->species_drag ? &d->species_drag[s] : &rigid, &m->sp[s].drag_u0,
                       &m->sp[s].drag_cap, &m->sp[s].drag_b);
        m->stride = in->n_modes > m->stride ? in->n_modes : m->stride;
    }
    m->pad = (m->stride + MODE_PAD - 1) / MODE_PAD * MODE_PAD;
    /* Ten constant arrays of pad floats per species, 64-byte aligned each. */
    size_t coef_bytes = (size_t)d->n_species * 10 * m->pad * sizeof(float);
    coef_bytes = (coef_bytes + 63) & ~(size_t)63;
    m->coef = aligned_alloc(64, coef_bytes);
    if (!m->coef) {
        goto nomem;
    }
    memset(m->coef, 0, coef_bytes);
    for (uint32_t s = 0; s < d->n_species; s++) {
        const modal_species *in = &d->species[s];
        modal_sp *sp = &m->sp[s];
        float *a = m->coef + (size_t)s * 10 * m->pad;
        float **dst[10] = { &sp->a11, &sp->a12, &sp->a21, &sp->a22, &sp->b1,
                            &sp->b2,  &sp->px,  &sp->py,  &sp->pz,  &sp->inv_step };
        for (int k = 0; k < 10; k++) {
            *dst[k] = a + (size_t)k * m->pad;
        }
        for (uint32_t i = 0; i < in->n_modes; i++) {
            float om = in->omega[i], ga = in->gamma[i], st = in->qstep[i];
            if (!(om > 0.0f) || !isfinite(om) || !(ga >= 0.0f) || !isfinite(ga) ||
                !(st > 0.0f) || !isfinite(st)) {
                gale_errf(err, GALE_E_RANGE,
                          "modal_create: species[%u] mode %u: expected omega > 0, gamma >= 0, qstep > 0 (finite), got %g, %g, %g",
                          s, i, (double)om, (double)ga, (double)st);
                goto fail;
            }
            /* Diener 2008 eq. 8-9, advanced exactly for f constant over dt. */
            osc_coef c = osc_exact(om, ga, dt_s);
            sp->a11[i] = c.a11;
            sp->a12[i] = c.a12;
            sp->a21[i] = c.a21;
            sp->a22[i] = c.a22;
            sp->b1[i] = c.b1;
            sp->b2[i] = c.b2;
            sp->px[i] = in->wind_basis[3 * i];
            sp->py[i] = in->wind_basis[3 * i + 1];
            sp->pz[i] = in->wind_basis[3 * i + 2];
            sp->inv_step[i] = 1.0f / st;
        }
    }
    m->tree_species = malloc(d->n_trees);
    m->cos_yaw = malloc(sizeof(float) * d->n_trees);
    m->sin_yaw = malloc(sizeof(float) * d->n_trees);
    m->drag_mult = malloc(sizeof(float) * d->n_trees);
    m->qnorm2 = calloc(d->n_trees, sizeof(float));
    m->force_scale = calloc(d->n_trees, sizeof(float));
    if (!m->tree_species || !m->cos_yaw || !m->sin_yaw || !m->drag_mult || !m->qnorm2 ||
        !m->force_scale) {
        goto nomem;
    }
    for (uint32_t t = 0; t < d->n_trees; t++) {
        if (d->tree_species[t] >= d->n_species) {
            gale_errf(err, GALE_E_RANGE, "modal_create: tree_species[%u]: expected < %u, got %u",
                      t, d->n_species, (unsigned)d->tree_species[t]);
            goto fail;
        }
        if (d->tree_yaw_rad && !isfinite(d->tree_yaw_rad[t])) {
            gale_errf(err, GALE_E_RANGE, "modal_create: tree_yaw_rad[%u]: expected finite, got %g",
                      t, (double)d->tree_yaw_rad[t]);
            goto fail;
        }
        float yaw = d->tree_yaw_rad ? d->tree_yaw_rad[t] : 0.0f;
        m->tree_species[t] = d->tree_species[t];
        m->cos_yaw[t] = cosf(yaw);
        m->sin_yaw[t] = sinf(yaw);
        m->drag_mult[t] = 1.0f;
    }
    /* 64-byte aligned so a tree's state starts on a cache line when pad is a multiple
     * of 16 (the common 16 / 32 / 64 modes). */
    size_t bytes = (size_t)d->n_trees * 2 * m->pad * sizeof(float);
    m->state = big_alloc(bytes);
    if (!m->state) {
        goto nomem;
    }
    return m;
nomem:
    gale_errf(err, GALE_E_NOMEM, "modal_create: out of memory for %u trees", d->n_trees);
fail:
    modal_destroy(m);
    return NULL;
}

void modal_destroy(modal *m)
{
    if (!m) {
        return;
    }
    free(m->sp);
    free(m->coef);
    free(m->state);
    free(m->tree_species);
    free(m->cos_yaw);
    free(m->sin_yaw);
    free(m->drag_mult);
    free(m->qnorm2);
    free(m->force_scale);
    free(m);
}

uint32_t modal_stride(const modal *m)
{
    return m->stride;
}

uint32_t modal_n_trees(const modal *m)
{
    return m->n_trees;
}

uint32_t modal_tree_modes(const modal *m, uint32_t t)
{
    return t < m->n_trees ? m->sp[m->tree_species[t]].n_modes : 0;
}

/* One group of MODE_PAD modes of one tree: forces, exact update, quantisation; q² added
 * lane by lane into sq. A fixed trip count and restrict parameters let the compiler
 * vectorise it at -O2. */
static inline void modes_step(const modal_sp *sp, uint32_t g, float vx, float vy, float vz,
                              float sv, float *restrict q, float *restrict v,
                              int16_t *restrict qq, float *restrict sq)
{
    const float *restrict a11 = sp->a11 + g, *restrict a12 = sp->a12 + g;
    const float *restrict a21 = sp->a21 + g, *restrict a22 = sp->a22 + g;
    const float *restrict b1 = sp->b1 + g, *restrict b2 = sp->b2 + g;
    const float *restrict px = sp->px + g, *restrict py = sp->py + g, *restrict pz = sp->pz + g;
    const float *restrict inv = sp->inv_step + g;
    for (uint32_t i = 0; i < MODE_PAD; i++) {
        /* Diener 2008 section 4: f_i = |v| (v . p_i), v in the tree frame. */
        float f = sv * (vx * px[i] + vy * py[i] + vz * pz[i]);
        float q0 = q[i], v0 = v[i];
        float q1 = a11[i] * q0 + a12[i] * v0 + b1[i] * f;
        float v1 = a21[i] * q0 + a22[i] * v0 + b2[i] * f;
        q[i] = q1;
        v[i] = v1;
        qq[i] = wire_quantize(q1, inv[i]);
        sq[i] += q1 * q1;
    }
}

/* Σ sq[i] over the MODE_PAD lanes, halving: lane i takes lane i + h for h = 8, 4, 2, 1.
 * A running sum would be a chain of dependent adds, the update's longest path; this
 * order is fixed, so every clone and thread count sums alike. */
static inline float lanes_sum(const float *restrict sq)
{
    _Static_assert(MODE_PAD == 16, "lanes_sum halves 16 lanes");
    float s8[8], s4[4];
    for (uint32_t i = 0; i < 8; i++) {
        s8[i] = sq[i] + sq[i + 8];
    }
    for (uint32_t i = 0; i < 4; i++) {
        s4[i] = s8[i] + s8[i + 4];
    }
    return (s4[0] + s4[2]) + (s4[1] + s4[3]);
}

/* Trees whose wind a block turns into the tree frame and force scale before their modes. */
#define FRAME_BLOCK 64u

/* The wind of trees [t0, t1) (t1 - t0 <= FRAME_BLOCK) in each tree's frame (vx, vy, vz)
 * and its force scale sv, and sv kept for damage.h: the drag law's powers of the whole
 * block in one loop of float arithmetic, which vectorises (drag_pow). */
static inline __attribute__((always_inline)) void
    block_frame(modal *m, uint32_t t0, uint32_t t1, const float *wind_world, float *vx, float *vy,
                float *vz, float *sv)
{
    float u[FRAME_BLOCK], u0[FRAME_BLOCK], cap[FRAME_BLOCK], e[FRAME_BLOCK];
    const uint32_t n = t1 - t0;
    for (uint32_t b = 0; b < n; b++) {
        const size_t t = (size_t)t0 + b;
        float wx = wind_world[3 * t];
        float wy = wind_world[3 * t + 1];
        float wz = wind_world[3 * t + 2];
        /* A non-finite or absurd sample (> 1 km/s) would poison the state for good:
         * treat it as calm air for this tick. */
        if (!(wx * wx + wy * wy + wz * wz <= 1.0e6f)) {
            wx = wy = wz = 0.0f;
        }
        /* World -> tree frame: rotate by -yaw about z (the tree's yaw maps tree to world). */
        const float cy = m->cos_yaw[t], sy = m->sin_yaw[t];
        vx[b] = cy * wx + sy * wy;
        vy[b] = -sy * wx + cy * wy;
        vz[b] = wz;
        u[b] = sqrtf(wx * wx + wy * wy + wz * wz);
        const modal_sp *sp = &m->sp[m->tree_species[t]];
        u0[b] = sp->drag_u0;
        cap[b] = sp->drag_cap;
        e[b] = sp->drag_b;
    }
    for (uint32_t b = n; b < FRAME_BLOCK; b++) {
        u[b] = u0[b] = cap[b] = 1.0f; /* a whole block, so the powers run in whole vectors */
        e[b] = 0.0f;
    }
    float x[FRAME_BLOCK];
    for (uint32_t b = 0; b < FRAME_BLOCK; b++) {
        x[b] = drag_pow(drag_base(u[b], u0[b], cap[b]), e[b]);
    }
    /* f_i = C_d(U)/C_d0 · mult · |v| v·p_i: the crown's streamlining (drag_law.h) and the
     * tree's own factor (modal_set_drag_mult) scale the whole force */
    const float *restrict mult = m->drag_mult + t0;
    float *restrict kept = m->force_scale + t0;
    for (uint32_t b = 0; b < n; b++) {
        sv[b] = u[b] * x[b] * mult[b];
        kept[b] = sv[b];
    }
}

/* Trees [t0, t1), a block at a time: wind into the tree frame (block_frame), then each
 * tree's groups of modes. Cloned for AVX-512 and AVX2 (chosen at load time by the CPU);
 * the default build targets SSE4.2. -std=c11 leaves floating-point contraction off, so
 * every clone rounds alike. */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
static void range_tick(modal *m, uint32_t t0, uint32_t t1, const float *wind_world,
                       int16_t *qsnap)
{
    const uint32_t pad = m->pad, stride = m->stride;
    int16_t qq[WIRE_MAX_MODES];
    float vx[FRAME_BLOCK], vy[FRAME_BLOCK], vz[FRAME_BLOCK], sv[FRAME_BLOCK];
    for (uint32_t b0 = t0; b0 < t1; b0 += FRAME_BLOCK) {
        const uint32_t b1 = t1 - b0 < FRAME_BLOCK ? t1 : b0 + FRAME_BLOCK;
        block_frame(m, b0, b1, wind_world, vx, vy, vz, sv);
        for (uint32_t t = b0; t < b1; t++) {
            const uint32_t b = t - b0;
            const modal_sp *sp = &m->sp[m->tree_species[t]];
            float *q = m->state + (size_t)t * 2 * pad;
            /* When the row is exactly the padded modes (16, 32, 64), quantise straight
             * into the snapshot; otherwise into qq and copy the row's part. */
            int16_t *out = qsnap && pad == stride ? qsnap + (size_t)t * stride : qq;
            float sq[MODE_PAD] = { 0 };
            for (uint32_t g = 0; g < pad; g += MODE_PAD) {
                modes_step(sp, g, vx[b], vy[b], vz[b], sv[b], q + g, q + pad + g, out + g, sq);
            }
            m->qnorm2[t] = lanes_sum(sq);
            if (qsnap && out == qq) {
                memcpy(qsnap + (size_t)t * stride, qq, stride * sizeof(int16_t));
            }
        }
    }
}

/* Trees per chunk a thread takes at a time. */
#define TICK_CHUNK 512u

typedef struct tick_job {
    modal *m;
    const float *wind_world;
    int16_t *qsnap;
} tick_job;

static void chunk_tick(void *ctx, int c)
{
    const tick_job *j = ctx;
    const uint32_t t0 = (uint32_t)c * TICK_CHUNK;
    const uint32_t t1 = t0 + TICK_CHUNK < j->m->n_trees ? t0 + TICK_CHUNK : j->m->n_trees;
    range_tick(j->m, t0, t1, j->wind_world, j->qsnap);
}

void modal_tick(modal *m, const float *wind_world, int16_t *qsnap)
{
    /* Trees are independent: the threads take chunks of 512 as they come free (on a busy
     * machine a descheduled thread does not hold the other back; sim_team.h). */
    const int nc = (int)((m->n_trees + TICK_CHUNK - 1) / TICK_CHUNK);
    tick_job j = { .m = m, .wind_world = wind_world, .qsnap = qsnap };
    sim_team_run(nc > 2 ? m->n_threads : 1, nc, chunk_tick, &j);
}

uint32_t modal_get(const modal *m, uint32_t t, float *q, float *qdot)
{
    if (t >= m->n_trees) {
        return 0;
    }
    uint32_t nm = m->sp[m->tree_species[t]].n_modes;
    const float *st = m->state + (size_t)t * 2 * m->pad;
    if (q) {
        memcpy(q, st, nm * sizeof(float));
    }
    if (qdot) {
        memcpy(qdot, st + m->pad, nm * sizeof(float));
    }
    return nm;
}

void modal_set_drag_mult(modal *m, uint32_t t, float mult)
{
    if (t < m->n_trees && mult >= 0.0f && isfinite(mult)) {
        m->drag_mult[t] = mult;
    }
}

float modal_drag_mult(const modal *m, uint32_t t)
{
    return t < m->n_trees ? m->drag_mult[t] : 0.0f;
}

void modal_set(modal *m, uint32_t t, const float *q, const float *qdot)
{
    if (t >= m->n_trees) {
        return;
    }
    uint32_t nm = m->sp[m->tree_species[t]].n_modes;
    float *st = m->state + (size_t)t * 2 * m->pad;
    if (q) {
        memcpy(st, q, nm * sizeof(float));
    }
    if (qdot) {
        memcpy(st + m->pad, qdot, nm * sizeof(float));
    }
}

modal_rows modal_get_rows(const modal *m)
{
    return (modal_rows){ .state = m->state,
                         .stride = 2 * (size_t)m->pad,
                         .pad = m->pad,
                         .qnorm2 = m->qnorm2,
                         .force_scale = m->force_scale };
}
