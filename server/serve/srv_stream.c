/* One snapshot stream's encoder: see srv_stream.h. */
#include "srv_stream.h"

void srv_stream_start(srv_stream *st, uint32_t id, const uint8_t *n_modes, uint32_t key_every)
{
    *st = (srv_stream){ .id = id, .n_modes = n_modes, .held = 0, .key_every = key_every };
}

void srv_stream_begin(srv_stream *st, const wire_header *h, uint32_t seq,
                      const wire_scene *scene, const srv_qhist *qh, net_snap *out)
{
    wire_state cur = { .n_trees = qh->n_trees, .stride = qh->stride, .n_modes = st->n_modes,
                       .q = qh->q[0] };
    wire_state prev = cur, prev2 = cur;
    prev.q = qh->q[1];
    prev2.q = qh->q[2];
    out->seq = seq;
    out->stream = st->id;
    if (st->key_every && seq % st->key_every == 0) {
        st->held = 0; /* no delta: every connection takes the keyframe (net.h net_snap) */
    }
    st->out = out;
    st->using = st->held < 2 ? st->held : 2;
    st->ran = 0;
    /* the keyframe and the deltas the stream can send, in one pass over the snapshots */
    st->f[0] = (wire_frame_out){ out->key, out->cap, 0, &st->err };
    st->f[1] = (wire_frame_out){ out->delta1, out->cap, 0, NULL };
    st->f[2] = (wire_frame_out){ out->delta2, out->cap, 0, NULL };
    wire_snapshot_begin(&st->job, h, seq, scene, &cur, st->using >= 1 ? &prev : NULL,
                        st->using >= 2 ? &prev2 : NULL, qh->lanes, st->f);
}

int srv_stream_lanes(const srv_stream *st)
{
    return st->out ? wire_snapshot_lanes(&st->job) : 0;
}

void srv_stream_run(srv_stream *st, int n)
{
    const int all = srv_stream_lanes(st);
    n = n < all - st->ran ? n : all - st->ran;
    if (n > 0) {
        wire_snapshot_run(&st->job, st->ran, st->ran + n);
        st->ran += n;
    }
}

int srv_stream_finish(srv_stream *st, gale_err *err)
{
    net_snap *out = st->out;
    if (!out) {
        return gale_errf(err, GALE_E_STATE, "srv_stream_finish: no snapshot begun");
    }
    srv_stream_run(st, srv_stream_lanes(st));
    int rc = wire_snapshot_finish(&st->job);
    out->key_len = st->f[0].len;
    if (st->using >= 1) {
        out->delta1_len = st->f[1].len;
    }
    if (st->using >= 2) {
        out->delta2_len = st->f[2].len;
    }
    if (rc && err) {
        *err = st->err;
    }
    st->out = NULL;
    st->held = rc ? 0 : st->held < 2 ? st->held + 1 : 2;
    return rc;
}

int srv_stream_encode(srv_stream *st, const wire_header *h, uint32_t seq,
                      const wire_scene *scene, const srv_qhist *qh, net_snap *out,
                      gale_err *err)
{
    srv_stream_begin(st, h, seq, scene, qh, out);
    return srv_stream_finish(st, err);
}

void srv_stream_skip(srv_stream *st)
{
    st->held = 0;
}
