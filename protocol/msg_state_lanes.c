/* The values section in lanes: the trees split into contiguous shares, each coded on its
 * own at its worst-case offset (msg_state_rows.c) and moved down into place as the lanes
 * before it finish; the bytes are those of one lane, whatever the split. */
#include <string.h>

#include "msg_state_int.h"

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
 * at one that has not run or went bad (state_lanes_join takes over from there). Lane k's bytes
 * go where the lanes before it end, which is below where lane k + 1 writes (each lane's
 * bytes fit its trees' worst case), so the lanes still running are untouched. One thread
 * moves at a time; a lane that finishes while another moves is taken by it, as the
 * mover looks again after letting go (sequentially consistent, so the finishing lane's
 * store and the mover's look cannot both miss). A lane missed all the same is moved by
 * state_lanes_join. */
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
    const bool ok =
        state_put_values(wp, j->n_pred, j->nf, j->sc, j->cur, j->prev, j->prev2, t0, t1);
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
 * finish, state_lanes_join for those left). The bytes
 * are those of one lane, whatever the split. With too little room for that layout, or no
 * lanes, one lane on the caller's thread. */
void state_lanes_layout(lane_job *j, wire_writer *const *w, const int *n_pred, int nf,
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

void state_lanes_run(lane_job *j, const wire_lanes *lanes, int i0, int i1)
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
int state_lanes_join(lane_job *j, wire_writer *const *w)
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

/* The checks and values of nf frames in lanes (state_lanes_layout, state_lanes_run,
 * state_lanes_join). */
int state_put_lanes(wire_writer *const *w, const int *n_pred, int nf, const wire_scene *sc,
                    const wire_state *cur, const wire_state *prev, const wire_state *prev2,
                    const wire_lanes *lanes)
{
    lane_job j;
    state_lanes_layout(&j, w, n_pred, nf, sc, cur, prev, prev2, lanes);
    state_lanes_run(&j, lanes, 0, (int)j.n_lanes);
    return state_lanes_join(&j, w);
}
