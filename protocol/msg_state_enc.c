/* The state frames' encoders: the scene and states checked, each frame's fields before
 * its values (the scene in a KEYFRAME, the tree set), the values through the lanes
 * (msg_state_lanes.c), and a snapshot's frames in one pass over the states. */
#include <string.h>

#include "msg_state_int.h"

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
    const int bad_state = !w->bad ? state_put_lanes(ws, n_pred, 1, sc, cur, prev, prev2, lanes) : 0;
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
        state_lanes_layout(&j->lj, ws, n_pred, nf, scene, &j->st[0], j->prev, j->prev2, lanes);
    }
}

int wire_snapshot_lanes(const wire_snapshot_job *j)
{
    return j->each || !j->nf ? 0 : (int)j->lj.n_lanes;
}

void wire_snapshot_run(wire_snapshot_job *j, int i0, int i1)
{
    if (!j->each && j->nf) {
        state_lanes_run(&j->lj, j->lanes, i0, i1);
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
    if (state_lanes_join(&j->lj, ws)) {
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
