/* Batch modal update of every tree (Diener 2008 sections 3-4): the wind sampled at a
 * tree is rotated into its frame, f_i = |v| v.p_i, and each mode's oscillator advances by
 * the exact 2x2 transition (server/oscillator.h), then is quantised for the wire.
 * Storage is blocks of 16 trees of one species, mode-major within a block, so the inner
 * loop runs over 16 lanes with per-(species, mode) constants: vectorisable, and one
 * block's snapshot rows are written together (cache-line sized). */
#include "modal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "wire_limits.h"
#include "oscillator.h"
#include "wire.h"

#define LANES 16u
#define NO_TREE UINT32_MAX

typedef struct modal_block {
    uint32_t species;
    uint32_t n_live;            /* lanes holding a tree; the rest are inert padding */
    size_t off;                 /* first float of this block in state */
    uint32_t tree[LANES];       /* tree index per lane, NO_TREE for padding */
    float cos_yaw[LANES], sin_yaw[LANES];
} modal_block;

typedef struct modal_sp {
    uint32_t n_modes;
    osc_coef coef[WIRE_MAX_MODES];
    float p[WIRE_MAX_MODES][3];
    float inv_step[WIRE_MAX_MODES];
} modal_sp;

struct modal {
    uint32_t n_trees, n_species, stride, n_blocks;
    int n_threads;
    modal_sp *sp;            /* owned: [n_species] */
    modal_block *blocks;     /* owned: [n_blocks] */
    float *state;            /* owned: per block [n_modes][2][LANES]: q then q' */
    uint32_t *tree_block;    /* owned: [n_trees] block index of tree t */
    uint8_t *tree_lane;      /* owned: [n_trees] lane of tree t */
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
        modal_sp *sp = &m->sp[s];
        if (in->n_modes == 0 || in->n_modes > WIRE_MAX_MODES || !in->omega || !in->gamma ||
            !in->wind_basis || !in->qstep) {
            gale_errf(err, GALE_E_ARG,
                      "modal_create: species[%u].n_modes: expected 1..%u with omega, gamma, wind_basis, qstep, got %u",
                      s, WIRE_MAX_MODES, in->n_modes);
            goto fail;
        }
        sp->n_modes = in->n_modes;
        m->stride = in->n_modes > m->stride ? in->n_modes : m->stride;
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
            sp->coef[i] = osc_exact(om, ga, dt_s);
            for (int k = 0; k < 3; k++) {
                sp->p[i][k] = in->wind_basis[3 * i + (uint32_t)k];
            }
            sp->inv_step[i] = 1.0f / st;
        }
    }
    /* Count trees per species, then lay blocks out species by species. */
    uint32_t count[WIRE_MAX_SPECIES] = { 0 };
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
        count[d->tree_species[t]]++;
    }
    uint32_t first_block[WIRE_MAX_SPECIES];
    size_t floats = 0;
    for (uint32_t s = 0; s < d->n_species; s++) {
        first_block[s] = m->n_blocks;
        m->n_blocks += (count[s] + LANES - 1) / LANES;
    }
    m->blocks = calloc(m->n_blocks, sizeof *m->blocks);
    m->tree_block = calloc(d->n_trees, sizeof *m->tree_block);
    m->tree_lane = calloc(d->n_trees, 1);
    if (!m->blocks || !m->tree_block || !m->tree_lane) {
        goto nomem;
    }
    for (uint32_t s = 0; s < d->n_species; s++) {
        uint32_t nb = (count[s] + LANES - 1) / LANES;
        for (uint32_t b = first_block[s]; b < first_block[s] + nb; b++) {
            modal_block *bl = &m->blocks[b];
            bl->species = s;
            bl->off = floats;
            floats += (size_t)m->sp[s].n_modes * 2 * LANES;
            for (uint32_t l = 0; l < LANES; l++) {
                bl->tree[l] = NO_TREE;
                bl->cos_yaw[l] = 1.0f;
            }
        }
    }
    uint32_t fill[WIRE_MAX_SPECIES] = { 0 };
    for (uint32_t t = 0; t < d->n_trees; t++) {
        uint32_t s = d->tree_species[t];
        uint32_t b = first_block[s] + fill[s] / LANES, l = fill[s] % LANES;
        fill[s]++;
        modal_block *bl = &m->blocks[b];
        float yaw = d->tree_yaw_rad ? d->tree_yaw_rad[t] : 0.0f;
        bl->tree[l] = t;
        bl->cos_yaw[l] = cosf(yaw);
        bl->sin_yaw[l] = sinf(yaw);
        bl->n_live = l + 1;
        m->tree_block[t] = b;
        m->tree_lane[t] = (uint8_t)l;
    }
    /* 64-byte aligned so a block's lanes are whole cache lines. */
    size_t bytes = (floats * sizeof(float) + 63) & ~(size_t)63;
    m->state = aligned_alloc(64, bytes > 0 ? bytes : 64);
    if (!m->state) {
        goto nomem;
    }
    memset(m->state, 0, bytes);
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
    free(m->blocks);
    free(m->state);
    free(m->tree_block);
    free(m->tree_lane);
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
    return t < m->n_trees ? m->sp[m->blocks[m->tree_block[t]].species].n_modes : 0;
}

/* One block: wind into the tree frame, forces, exact update, quantisation. Cloned for
 * AVX-512 and AVX2 (chosen at load time by the CPU); the default build targets SSE4.2.
 * -std=c11 leaves floating-point contraction off, so every clone rounds alike. */
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
static void block_tick(const modal *m, const modal_block *bl, const float *wind_world,
                       int16_t *qsnap)
{
    const modal_sp *sp = &m->sp[bl->species];
    float vx[LANES], vy[LANES], vz[LANES], sp_v[LANES];
    for (uint32_t l = 0; l < LANES; l++) {
        float wx = 0.0f, wy = 0.0f, wz = 0.0f;
        uint32_t t = bl->tree[l];
        if (t != NO_TREE) {
            wx = wind_world[3 * (size_t)t];
            wy = wind_world[3 * (size_t)t + 1];
            wz = wind_world[3 * (size_t)t + 2];
            /* A non-finite or absurd sample (> 1 km/s) would poison the state for good:
             * treat it as calm air for this tick. */
            if (!(wx * wx + wy * wy + wz * wz <= 1.0e6f)) {
                wx = wy = wz = 0.0f;
            }
        }
        /* World -> tree frame: rotate by -yaw about z (the tree's yaw maps tree to world). */
        vx[l] = bl->cos_yaw[l] * wx + bl->sin_yaw[l] * wy;
        vy[l] = -bl->sin_yaw[l] * wx + bl->cos_yaw[l] * wy;
        vz[l] = wz;
        sp_v[l] = sqrtf(wx * wx + wy * wy + wz * wz);
    }
    int16_t qq[WIRE_MAX_MODES][LANES];
    float *st = m->state + bl->off;
    const uint32_t nm = sp->n_modes;
    for (uint32_t i = 0; i < nm; i++) {
        const osc_coef c = sp->coef[i];
        const float px = sp->p[i][0], py = sp->p[i][1], pz = sp->p[i][2];
        const float inv = sp->inv_step[i];
        float *q = st + (size_t)i * 2 * LANES;
        float *v = q + LANES;
        for (uint32_t l = 0; l < LANES; l++) {
            /* Diener 2008 section 4: f_i = |v| (v . p_i), v in the tree frame. */
            float f = sp_v[l] * (vx[l] * px + vy[l] * py + vz[l] * pz);
            float q0 = q[l], v0 = v[l];
            float q1 = c.a11 * q0 + c.a12 * v0 + c.b1 * f;
            float v1 = c.a21 * q0 + c.a22 * v0 + c.b2 * f;
            q[l] = q1;
            v[l] = v1;
            qq[i][l] = wire_quantize(q1, inv);
        }
    }
    if (!qsnap) {
        return;
    }
    for (uint32_t l = 0; l < bl->n_live; l++) {
        int16_t *row = qsnap + (size_t)bl->tree[l] * m->stride;
        for (uint32_t i = 0; i < nm; i++) {
            row[i] = qq[i][l];
        }
        for (uint32_t i = nm; i < m->stride; i++) {
            row[i] = 0;
        }
    }
}

void modal_tick(modal *m, const float *wind_world, int16_t *qsnap)
{
    const int nb = (int)m->n_blocks;
    /* Blocks are independent: the threads take chunks of 32 blocks as they come free
     * (on a busy machine a descheduled thread does not hold the other back); libgomp
     * allocates nothing per tick once its pool exists. */
#pragma omp parallel for schedule(dynamic, 32) num_threads(m->n_threads) if (nb > 64)
    for (int b = 0; b < nb; b++) {
        block_tick(m, &m->blocks[b], wind_world, qsnap);
    }
}

uint32_t modal_get(const modal *m, uint32_t t, float *q, float *qdot)
{
    if (t >= m->n_trees) {
        return 0;
    }
    const modal_block *bl = &m->blocks[m->tree_block[t]];
    uint32_t l = m->tree_lane[t], nm = m->sp[bl->species].n_modes;
    const float *st = m->state + bl->off;
    for (uint32_t i = 0; i < nm; i++) {
        if (q) {
            q[i] = st[(size_t)i * 2 * LANES + l];
        }
        if (qdot) {
            qdot[i] = st[(size_t)i * 2 * LANES + LANES + l];
        }
    }
    return nm;
}

void modal_set(modal *m, uint32_t t, const float *q, const float *qdot)
{
    if (t >= m->n_trees) {
        return;
    }
    const modal_block *bl = &m->blocks[m->tree_block[t]];
    uint32_t l = m->tree_lane[t], nm = m->sp[bl->species].n_modes;
    float *st = m->state + bl->off;
    for (uint32_t i = 0; i < nm; i++) {
        if (q) {
            st[(size_t)i * 2 * LANES + l] = q[i];
        }
        if (qdot) {
            st[(size_t)i * 2 * LANES + LANES + l] = qdot[i];
        }
    }
}
