/* One snapshot stream's encoder: see srv_stream.h. */
#include "srv_stream.h"

void srv_stream_start(srv_stream *st, uint32_t id, const uint8_t *n_modes, uint32_t key_every)
{
    *st = (srv_stream){ .id = id, .n_modes = n_modes, .held = 0, .key_every = key_every };
}

int srv_stream_encode(srv_stream *st, const wire_header *h, uint32_t seq,
                      const wire_scene *scene, const srv_qhist *qh, net_snap *out,
                      gale_err *err)
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
    int rc = wire_encode_keyframe_lanes(h, seq, scene, &cur, qh->lanes, out->key, out->cap,
                                        &out->key_len, err);
    if (!rc && st->held >= 1) {
        rc = wire_encode_delta_lanes(h, seq, scene, &cur, &prev, NULL, qh->lanes, out->delta1,
                                     out->cap, &out->delta1_len, err);
    }
    if (!rc && st->held >= 2) {
        rc = wire_encode_delta_lanes(h, seq, scene, &cur, &prev, &prev2, qh->lanes,
                                     out->delta2, out->cap, &out->delta2_len, err);
    }
    st->held = rc ? 0 : st->held < 2 ? st->held + 1 : 2;
    return rc;
}

void srv_stream_skip(srv_stream *st)
{
    st->held = 0;
}
