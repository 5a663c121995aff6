/* Client jitter buffer: q snapshots sorted by tick, sampled a fixed playout delay behind
 * the server clock with a C1 cubic Hermite whose tangents are the derivative of the
 * parabola through three neighbouring snapshots (exact for quadratic motion, any spacing). */
#include "jitter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct jitter {
    jitter_desc d;
    float *store;         /* owned: capacity × n_values */
    uint64_t *slot_tick;  /* owned: [capacity] */
    double *slot_t;       /* owned: [capacity] */
    uint32_t *order;      /* owned: [capacity] slot ids sorted by tick, order[0] oldest */
    uint32_t *free_slots; /* owned: [capacity] stack of unused slot ids */
    uint32_t n, n_free;
    double passed_t; /* playout has sampled at this time; older arrivals are late */
    jitter_stats st;
};

jitter *jitter_create(const jitter_desc *d, gale_err *err)
{
    jitter_desc r = *d;
    if (r.n_values == 0) {
        gale_errf(err, GALE_E_ARG, "jitter_desc.n_values: expected > 0, got 0");
        return NULL;
    }
    if (r.capacity == 0) {
        r.capacity = 32;
    }
    if (r.capacity < 2 || r.capacity > JITTER_MAX_CAPACITY) {
        gale_errf(err, GALE_E_ARG, "jitter_desc.capacity: expected 2..%d, got %u",
                  JITTER_MAX_CAPACITY, r.capacity);
        return NULL;
    }
    if (r.playout_delay_s == 0.0) {
        r.playout_delay_s = 0.1;
    }
    if (!(r.playout_delay_s > 0.0 && r.playout_delay_s < 10.0)) {
        gale_errf(err, GALE_E_ARG, "jitter_desc.playout_delay_s: expected (0, 10) s, got %g",
                  r.playout_delay_s);
        return NULL;
    }
    jitter *j = calloc(1, sizeof *j);
    if (!j) {
        goto fail;
    }
    j->d = r;
    j->store = malloc((size_t)r.capacity * r.n_values * sizeof(float));
    j->slot_tick = calloc(r.capacity, sizeof(uint64_t));
    j->slot_t = calloc(r.capacity, sizeof(double));
    j->order = calloc(r.capacity, sizeof(uint32_t));
    j->free_slots = calloc(r.capacity, sizeof(uint32_t));
    if (!j->store || !j->slot_tick || !j->slot_t || !j->order || !j->free_slots) {
        goto fail;
    }
    /* touch every page now, so the first inserts of a frame loop do not fault them in */
    memset(j->store, 0, (size_t)r.capacity * r.n_values * sizeof(float));
    jitter_reset(j);
    return j;
fail:
    jitter_destroy(j);
    gale_errf(err, GALE_E_NOMEM, "jitter_create: no memory for %u snapshots of %u floats",
              r.capacity, r.n_values);
    return NULL;
}

void jitter_destroy(jitter *j)
{
    if (!j) {
        return;
    }
    free(j->store);
    free(j->slot_tick);
    free(j->slot_t);
    free(j->order);
    free(j->free_slots);
    free(j);
}

jitter_desc jitter_get_desc(const jitter *j)
{
    return j->d;
}

void jitter_reset(jitter *j)
{
    j->n = 0;
    j->n_free = j->d.capacity;
    for (uint32_t i = 0; i < j->d.capacity; i++) {
        j->free_slots[i] = j->d.capacity - 1 - i;
    }
    j->passed_t = -INFINITY;
}

static float *slot_q(const jitter *j, uint32_t slot)
{
    return j->store + (size_t)slot * j->d.n_values;
}

int jitter_insert(jitter *j, uint64_t tick, double t_s, const float *q, gale_err *err)
{
    if (!isfinite(t_s)) {
        return gale_errf(err, GALE_E_RANGE, "snapshot tick %llu: server time not finite",
                         (unsigned long long)tick);
    }
    if (t_s < j->passed_t) {
        j->st.late++;
        return JITTER_LATE;
    }
    /* position: first entry with a tick >= this one */
    uint32_t pos = j->n;
    while (pos > 0 && j->slot_tick[j->order[pos - 1]] >= tick) {
        pos--;
    }
    if (pos < j->n && j->slot_tick[j->order[pos]] == tick) {
        j->st.duplicates++;
        return JITTER_DUPLICATE;
    }
    if ((pos > 0 && !(j->slot_t[j->order[pos - 1]] < t_s)) ||
        (pos < j->n && !(t_s < j->slot_t[j->order[pos]]))) {
        return gale_errf(err, GALE_E_RANGE,
                         "snapshot tick %llu: server time %.6f s out of tick order with its "
                         "neighbours",
                         (unsigned long long)tick, t_s);
    }
    if (j->n == j->d.capacity) {
        if (pos == 0) {
            /* older than everything in a full buffer: nothing to make room for */
            j->st.late++;
            return JITTER_LATE;
        }
        j->free_slots[j->n_free++] = j->order[0];
        memmove(j->order, j->order + 1, (j->n - 1) * sizeof(uint32_t));
        j->n--;
        pos--;
        j->st.evicted++;
    }
    if (pos < j->n) {
        j->st.out_of_order++;
    }
    uint32_t slot = j->free_slots[--j->n_free];
    memmove(j->order + pos + 1, j->order + pos, (j->n - pos) * sizeof(uint32_t));
    j->order[pos] = slot;
    j->n++;
    j->slot_tick[slot] = tick;
    j->slot_t[slot] = t_s;
    memcpy(slot_q(j, slot), q, (size_t)j->d.n_values * sizeof(float));
    j->st.inserted++;
    return JITTER_INSERTED;
}

/* Derivative at the middle point of the parabola through (ta,·), (tb,·), (tc,·), as weights
 * on the three values: m = wa qa + wb qb + wc qc. */
static void parabola_slope(double ta, double tb, double tc, double *wa, double *wb, double *wc)
{
    double dab = tb - ta, dbc = tc - tb, dac = tc - ta;
    *wa = -dbc / (dab * dac);
    *wc = dab / (dbc * dac);
    *wb = dbc / (dab * dac) - dab / (dbc * dac);
}

/* out[k] = c0 q0[k] + c1 q1[k] + c2 q2[k] + c3 q3[k] for k < n, eight at a time so that -O2
 * turns each eight into vector operations (restrict: out and the snapshots are apart). */
static void mix4(float *restrict out, const float *restrict q0, const float *restrict q1,
                 const float *restrict q2, const float *restrict q3, float c0, float c1,
                 float c2, float c3, uint32_t n)
{
    uint32_t k = 0;
    for (; k + 8 <= n; k += 8) {
#pragma GCC unroll 8
        for (uint32_t i = k; i < k + 8; i++) {
            out[i] = c0 * q0[i] + c1 * q1[i] + c2 * q2[i] + c3 * q3[i];
        }
    }
    for (; k < n; k++) {
        out[k] = c0 * q0[k] + c1 * q1[k] + c2 * q2[k] + c3 * q3[k];
    }
}

int jitter_sample(jitter *j, double render_t_s, float *out, jitter_sample_info *info)
{
    if (j->n == 0) {
        return GALE_E_STATE;
    }
    jitter_sample_info inf = { 0 };
    const uint32_t nv = j->d.n_values;
    const double t_first = j->slot_t[j->order[0]], t_last = j->slot_t[j->order[j->n - 1]];
    const double played_t = fmin(render_t_s, t_last); /* an underrun shows the newest */
    if (played_t > j->passed_t) {
        j->passed_t = played_t;
    }
    if (j->n == 1 || render_t_s <= t_first || render_t_s >= t_last) {
        uint32_t slot = render_t_s <= t_first ? j->order[0] : j->order[j->n - 1];
        memcpy(out, slot_q(j, slot), (size_t)nv * sizeof(float));
        inf.tick0 = inf.tick1 = j->slot_tick[slot];
        inf.s = 0.0f;
        inf.before_first = render_t_s < t_first;
        inf.underrun = render_t_s > t_last;
        if (inf.underrun) {
            j->st.underruns++;
        }
        if (info) {
            *info = inf;
        }
        return 0;
    }
    uint32_t i = 0; /* order[i] <= render < order[i+1] */
    while (i + 2 < j->n && j->slot_t[j->order[i + 1]] <= render_t_s) {
        i++;
    }
    const uint32_t s1 = j->order[i], s2 = j->order[i + 1];
    const double t1 = j->slot_t[s1], t2 = j->slot_t[s2], h = t2 - t1;
    const double s = (render_t_s - t1) / h;

    /* Tangents m1, m2 [value/s] as weights on q0..q3; one-sided at the ends. */
    double a0 = 0, a1 = -1.0 / h, a2 = 1.0 / h;
    double b1 = -1.0 / h, b2 = 1.0 / h, b3 = 0;
    const float *q0 = NULL, *q3 = NULL;
    if (i > 0) {
        uint32_t s0 = j->order[i - 1];
        parabola_slope(j->slot_t[s0], t1, t2, &a0, &a1, &a2);
        q0 = slot_q(j, s0);
    }
    if (i + 2 < j->n) {
        uint32_t s3 = j->order[i + 2];
        parabola_slope(t1, t2, j->slot_t[s3], &b1, &b2, &b3);
        q3 = slot_q(j, s3);
    }
    /* Hermite basis: q(s) = h00 q1 + h10 h m1 + h01 q2 + h11 h m2. */
    const double s2_ = s * s, s3_ = s2_ * s;
    const double h00 = 2 * s3_ - 3 * s2_ + 1, h10 = s3_ - 2 * s2_ + s;
    const double h01 = -2 * s3_ + 3 * s2_, h11 = s3_ - s2_;
    const float c0 = (float)(h10 * h * a0);
    const float c1 = (float)(h00 + h10 * h * a1 + h11 * h * b1);
    const float c2 = (float)(h01 + h10 * h * a2 + h11 * h * b2);
    const float c3 = (float)(h11 * h * b3);
    const float *q1 = slot_q(j, s1), *q2 = slot_q(j, s2);
    if (q0 && q3) {
        mix4(out, q0, q1, q2, q3, c0, c1, c2, c3, nv);
    } else {
        for (uint32_t k = 0; k < nv; k++) {
            float v = c1 * q1[k] + c2 * q2[k];
            v += q0 ? c0 * q0[k] : 0.0f;
            v += q3 ? c3 * q3[k] : 0.0f;
            out[k] = v;
        }
    }
    inf.tick0 = j->slot_tick[s1];
    inf.tick1 = j->slot_tick[s2];
    inf.s = (float)s;
    if (info) {
        *info = inf;
    }
    return 0;
}

uint32_t jitter_count(const jitter *j)
{
    return j->n;
}

double jitter_newest_time(const jitter *j)
{
    return j->n ? j->slot_t[j->order[j->n - 1]] : -(double)INFINITY;
}

double jitter_oldest_time(const jitter *j)
{
    return j->n ? j->slot_t[j->order[0]] : (double)INFINITY;
}

jitter_stats jitter_get_stats(const jitter *j)
{
    return j->st;
}

double jitter_render_time(const jitter *j, double server_now_s)
{
    return server_now_s - j->d.playout_delay_s;
}

void jitter_clock_init(jitter_clock *c)
{
    memset(c, 0, sizeof *c);
    c->arrival_max = -INFINITY;
}

void jitter_clock_pong(jitter_clock *c, double t_sent_s, double t_server_s, double t_recv_s)
{
    if (!isfinite(t_sent_s) || !isfinite(t_server_s) || !isfinite(t_recv_s) ||
        t_recv_s < t_sent_s) {
        return;
    }
    c->offset_s[c->next] = t_server_s - 0.5 * (t_sent_s + t_recv_s);
    c->rtt_s[c->next] = t_recv_s - t_sent_s;
    c->next = (c->next + 1) % JITTER_CLOCK_WINDOW;
    if (c->n < JITTER_CLOCK_WINDOW) {
        c->n++;
    }
}

void jitter_clock_arrival(jitter_clock *c, double t_server_s, double t_recv_s)
{
    if (!isfinite(t_server_s) || !isfinite(t_recv_s)) {
        return;
    }
    double d = t_server_s - t_recv_s;
    if (!c->have_arrival || d > c->arrival_max) {
        c->arrival_max = d;
    }
    c->have_arrival = true;
}

static int clock_best(const jitter_clock *c)
{
    int best = -1;
    for (uint32_t i = 0; i < c->n; i++) {
        if (best < 0 || c->rtt_s[i] < c->rtt_s[best]) {
            best = (int)i;
        }
    }
    return best;
}

bool jitter_clock_server_time(const jitter_clock *c, double local_s, double *server_s)
{
    int b = clock_best(c);
    if (b >= 0) {
        *server_s = local_s + c->offset_s[b];
        return true;
    }
    if (c->have_arrival) {
        *server_s = local_s + c->arrival_max;
        return true;
    }
    *server_s = local_s;
    return false;
}

double jitter_clock_rtt(const jitter_clock *c)
{
    int b = clock_best(c);
    return b >= 0 ? c->rtt_s[b] : -1.0;
}
