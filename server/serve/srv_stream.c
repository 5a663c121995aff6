/* One snapshot stream's encoder: see srv_stream.h. */
#include "srv_stream.h"

void srv_stream_start(srv_stream *st, uint32_t id, const uint8_t *n_modes, uint32_t key_every)
{
    *st = (srv_stream){ .id = id, .n_modes = n_modes, .held = 0, .key_every = key_every };
}

int srv_stream_encode(srv_stream *st, const wire_header *h, uint32_t seq, const wire_scene *scene,
                      const srv_qhist *qh, unsigned want, net_snap *out, gale_err *err)
{
    wire_state cur = {
        .n_trees = qh->n_trees, .stride = qh->stride, .n_modes = st->n_modes, .q = qh->q[0]
    };
    wire_state prev = cur, prev2 = cur;
    prev.q = qh->q[1];
    prev2.q = qh->q[2];
    out->seq = seq;
    out->stream = st->id;
    if (st->key_every && seq % st->key_every == 0) {
        st->held = 0; /* no delta: every connection takes the keyframe (net.h net_snap) */
    }
    /* the frames wanted of those the stream can send, in one pass over the snapshots: a
       connection holding the two previous takes delta2, so the others only on demand */
    const bool key = st->held == 0 || (want & NET_WANT_KEY);
    const bool delta1 = st->held == 1 || (st->held >= 1 && (want & NET_WANT_DELTA1));
    wire_frame_out f[3] = { { key ? out->key : NULL, out->cap, 0, err },
                            { delta1 ? out->delta1 : NULL, out->cap, 0, NULL },
                            { out->delta2, out->cap, 0, NULL } };
    int rc = wire_encode_snapshot_lanes(h, seq, scene, &cur, st->held >= 1 ? &prev : NULL,
                                        st->held >= 2 ? &prev2 : NULL, qh->lanes, f);
    out->key_len = key ? f[0].len : 0;
    out->delta1_len = delta1 ? f[1].len : 0;
    out->delta2_len = st->held >= 2 ? f[2].len : 0;
    st->held = rc ? 0 : st->held < 2 ? st->held + 1 : 2;
    return rc;
}

void srv_stream_skip(srv_stream *st)
{
    st->held = 0;
}
