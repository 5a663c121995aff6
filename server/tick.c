/* The fixed-step simulation: see tick.h. */
#include "tick.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Exact transition of q'' + γq' + ω²q = f over dt with f held constant (a 2×2 matrix
 * exponential plus a forcing column), per species and mode. */
typedef struct tick_coef {
    float a11, a12, a21, a22, b1, b2;
} tick_coef;

struct tick_sim {
    tick_desc d;
    float dt_s;
    int n_trees, stride;
    float *q, *qd;          /* owned [n_trees][stride] */
    tick_coef *coef;        /* owned [n_species][stride] */
    float *crown;           /* owned [n_trees][3] sample points, world */
    float *vel;             /* owned [n_trees][3] sampled wind */
    float *cos_yaw, *sin_yaw; /* owned [n_trees] */
    leaf_seed *leaves;      /* owned [max_leaves_per_tick] */
    int n_leaves;
    uint32_t tick;
    leaf_desc leaf;
    pthread_mutex_t lock;   /* guards inflow below */
    wind_inflow inflow;
    bool inflow_dirty;
};

/* x(dt) = E (x0 - xp) + xp with xp = (f/ω², 0) and E = exp(A dt), A = [[0,1],[-ω²,-γ]].
 * E = e^{-γdt/2} [c I + s (A + γ/2 I)] with c, s = cos, sin(ω_d dt)/ω_d (under-damped),
 * cosh, sinh (over-damped) or 1, dt (critical), ω_d² = |ω² - γ²/4|. */
static tick_coef coef_exact(double w, double g, double dt)
{
    double disc = 0.25 * g * g - w * w, c, s;
    if (disc < -1e-12 * w * w) {
        double wd = sqrt(-disc);
        c = cos(wd * dt);
        s = sin(wd * dt) / wd;
    } else if (disc > 1e-12 * w * w) {
        double wd = sqrt(disc);
        c = cosh(wd * dt);
        s = sinh(wd * dt) / wd;
    } else {
        c = 1;
        s = dt;
    }
    double e = exp(-0.5 * g * dt);
    double e11 = e * (c + 0.5 * g * s), e12 = e * s, e21 = -e * s * w * w,
           e22 = e * (c - 0.5 * g * s);
    return (tick_coef){ .a11 = (float)e11,
                        .a12 = (float)e12,
                        .a21 = (float)e21,
                        .a22 = (float)e22,
                        .b1 = (float)((1 - e11) / (w * w)),
                        .b2 = (float)(-e21 / (w * w)) };
}

tick_sim *tick_create(const tick_desc *d, gale_err *err)
{
    tick_sim *t = calloc(1, sizeof *t);
    if (!t) {
        gale_errf(err, GALE_E_NOMEM, "tick_create: no memory");
        return NULL;
    }
    pthread_mutex_init(&t->lock, NULL);
    t->d = *d;
    const scene *sc = d->sc;
    if (!t->d.max_leaves_per_tick) {
        t->d.max_leaves_per_tick = 4096;
    }
    t->dt_s = (float)(1.0 / sc->tick_hz);
    t->n_trees = sc->n_trees;
    for (int i = 0; i < sc->n_species; i++) {
        const tick_species *sp = &d->species[i];
        if (sp->n_modes < 1 || sp->n_modes > 256) {
            gale_errf(err, GALE_E_RANGE, "tick_create: species %s: expected 1..256 modes, got %u",
                      sc->species[i].name, sp->n_modes);
            goto fail;
        }
        for (uint32_t m = 0; m < sp->n_modes; m++) {
            if (!(sp->omega[m] > 0) || !(sp->gamma[m] >= 0) || !isfinite(sp->omega[m]) ||
                !isfinite(sp->gamma[m])) {
                gale_errf(err, GALE_E_RANGE,
                          "tick_create: species %s mode %u: expected omega > 0 and gamma >= 0, "
                          "got %g and %g",
                          sc->species[i].name, m, (double)sp->omega[m], (double)sp->gamma[m]);
                goto fail;
            }
        }
        if ((int)sp->n_modes > t->stride) {
            t->stride = (int)sp->n_modes;
        }
    }
    size_t nq = (size_t)t->n_trees * (size_t)t->stride;
    t->q = calloc(nq, sizeof *t->q);
    t->qd = calloc(nq, sizeof *t->qd);
    t->coef = calloc((size_t)sc->n_species * (size_t)t->stride, sizeof *t->coef);
    t->crown = calloc((size_t)t->n_trees * 3, sizeof *t->crown);
    t->vel = calloc((size_t)t->n_trees * 3, sizeof *t->vel);
    t->cos_yaw = calloc((size_t)t->n_trees, sizeof *t->cos_yaw);
    t->sin_yaw = calloc((size_t)t->n_trees, sizeof *t->sin_yaw);
    t->leaves = calloc((size_t)t->d.max_leaves_per_tick, sizeof *t->leaves);
    if (!t->q || !t->qd || !t->coef || !t->crown || !t->vel || !t->cos_yaw || !t->sin_yaw ||
        !t->leaves) {
        gale_errf(err, GALE_E_NOMEM, "tick_create: no memory for %d trees x %d modes",
                  t->n_trees, t->stride);
        goto fail;
    }
    for (int i = 0; i < sc->n_species; i++) {
        const tick_species *sp = &d->species[i];
        for (uint32_t m = 0; m < sp->n_modes; m++) {
            t->coef[i * t->stride + (int)m] =
                coef_exact((double)sp->omega[m], (double)sp->gamma[m], (double)t->dt_s);
        }
    }
    for (int k = 0; k < t->n_trees; k++) {
        const scene_tree *tr = &sc->trees[k];
        float h = d->species[tr->species].height_m * tr->scale;
        t->crown[3 * k + 0] = tr->pos[0];
        t->crown[3 * k + 1] = tr->pos[1];
        t->crown[3 * k + 2] = tr->pos[2] + 0.7f * h;
        t->cos_yaw[k] = cosf(tr->yaw_rad);
        t->sin_yaw[k] = sinf(tr->yaw_rad);
    }
    t->leaf = (leaf_desc){ .rate_hz = sc->leaf_rate_hz,
                           .calm_ms = sc->leaf_calm_ms,
                           .ref_ms = sc->leaf_ref_ms,
                           .seed = sc->leaf_seed };
    t->inflow = (wind_inflow){ .dir_rad = sc->wind_dir_deg * 0.017453292f,
                               .u10_ms = sc->wind_u10_ms };
    t->inflow_dirty = true;
    return t;
fail:
    tick_destroy(t);
    return NULL;
}

void tick_destroy(tick_sim *t)
{
    if (!t) {
        return;
    }
    free(t->q);
    free(t->qd);
    free(t->coef);
    free(t->crown);
    free(t->vel);
    free(t->cos_yaw);
    free(t->sin_yaw);
    free(t->leaves);
    pthread_mutex_destroy(&t->lock);
    free(t);
}

void tick_set_inflow(tick_sim *t, const wind_inflow *in)
{
    pthread_mutex_lock(&t->lock);
    t->inflow = *in;
    t->inflow_dirty = true;
    pthread_mutex_unlock(&t->lock);
}

/* The log-law profile alone (no grid): U(z) = U10 ln(z/z0) / ln(10/z0), z clamped below
 * at zmin (defaults z0 = 0.3 m, EN 1991-1-4 terrain III, and 5 m), plus the gust. */
static void sample_profile(tick_sim *t, const wind_inflow *in)
{
    const float z0 = in->z0_m > 0 ? in->z0_m : 0.3f, zmin = in->zmin_m > 0 ? in->zmin_m : 5.0f;
    const float u10 = in->u10_ms, *gust = in->gust;
    float cx = cosf(in->dir_rad), cy = sinf(in->dir_rad), l10 = logf(10.0f / z0);
    for (int k = 0; k < t->n_trees; k++) {
        float z = t->crown[3 * k + 2] < zmin ? zmin : t->crown[3 * k + 2];
        float u = u10 * logf(z / z0) / l10;
        t->vel[3 * k + 0] = u * cx + gust[0];
        t->vel[3 * k + 1] = u * cy + gust[1];
        t->vel[3 * k + 2] = gust[2];
    }
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

int tick_step(tick_sim *t, tick_stats *st, gale_err *err)
{
    tick_stats local = { 0 };
    double t0 = now_ms();
    const scene *sc = t->d.sc;
    wind_inflow in;
    bool dirty;
    pthread_mutex_lock(&t->lock);
    in = t->inflow;
    dirty = t->inflow_dirty;
    t->inflow_dirty = false;
    pthread_mutex_unlock(&t->lock);

    /* 1. wind */
    if (t->d.wind) {
        if (dirty) {
            t->d.wind->set_inflow(t->d.wind->ctx, &in);
        }
        int every = sc->wind_every > 0 ? sc->wind_every : 1;
        if (t->tick % (uint32_t)every == 0) {
            wind_step_stats ws = { 0 };
            double w0 = now_ms();
            if (t->d.wind->step(t->d.wind->ctx, t->dt_s * (float)every, &ws)) {
                return gale_errf(err, GALE_E_NUMERIC,
                                 "tick %u: wind step broke down (non-finite field)", t->tick);
            }
            local.wind_ms = now_ms() - w0;
            local.wind_iters = ws.iterations;
            local.wind_div = ws.div_after;
        }
        /* 2. sample the wind at every crown */
        t->d.wind->sample_many(t->d.wind->ctx, t->n_trees, t->crown, t->vel);
    } else {
        sample_profile(t, &in);
    }

    /* 3. forces and the exact modal update; 4. leaves */
    t->n_leaves = 0;
    const int stride = t->stride;
    for (int k = 0; k < t->n_trees; k++) {
        const scene_tree *tr = &sc->trees[k];
        const tick_species *sp = &t->d.species[tr->species];
        const tick_coef *cf = &t->coef[tr->species * stride];
        float vx = t->vel[3 * k], vy = t->vel[3 * k + 1], vz = t->vel[3 * k + 2];
        /* world → tree frame: rotate by -yaw about z */
        float c = t->cos_yaw[k], s = t->sin_yaw[k];
        float lx = c * vx + s * vy, ly = -s * vx + c * vy, lz = vz;
        float speed = sqrtf(vx * vx + vy * vy + vz * vz);
        if (speed > local.max_speed_ms) {
            local.max_speed_ms = speed;
        }
        float *q = &t->q[(size_t)k * (size_t)stride], *qd = &t->qd[(size_t)k * (size_t)stride];
        const float *p = sp->wind_basis;
        for (uint32_t m = 0; m < sp->n_modes; m++) {
            /* Diener 2008 section 4: f_i = |v| v·p_i, v in the tree frame */
            float f = speed * (lx * p[3 * m] + ly * p[3 * m + 1] + lz * p[3 * m + 2]);
            float q0 = q[m], v0 = qd[m];
            q[m] = cf[m].a11 * q0 + cf[m].a12 * v0 + cf[m].b1 * f;
            qd[m] = cf[m].a21 * q0 + cf[m].a22 * v0 + cf[m].b2 * f;
        }
        if (sp->n_leaves) {
            local.leaves_lost +=
                leaf_shed(&t->leaf, (uint32_t)k, sp->n_leaves, (double)speed, t->tick,
                          (double)t->dt_s, t->leaves, t->d.max_leaves_per_tick, &t->n_leaves);
        }
    }
    local.leaves = t->n_leaves;
    t->tick++;
    local.ms = now_ms() - t0;
    if (st) {
        *st = local;
    }
    return GALE_OK;
}

uint32_t tick_now(const tick_sim *t)
{
    return t->tick;
}

int tick_n_trees(const tick_sim *t)
{
    return t->n_trees;
}

int tick_stride(const tick_sim *t)
{
    return t->stride;
}

const float *tick_q(const tick_sim *t)
{
    return t->q;
}

int tick_leaves(const tick_sim *t, const leaf_seed **out)
{
    *out = t->leaves;
    return t->n_leaves;
}

const float *tick_crown_wind(const tick_sim *t)
{
    return t->vel;
}
