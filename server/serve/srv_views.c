/* The view thread: each snapshot's view streams (srv_int.h srv_vsel), encoded beside the
 * ticks rather than after them. The sim thread encodes the shared stream, hands the
 * snapshot to this thread and goes on; the ticks' threads run at a real-time priority
 * where the scene asks for it (SERVER.md "Loop") and this one at the normal one, so the
 * views take the cores the ticks leave. Beside the snapshot it encodes one more waits, the
 * newest posted: a snapshot posted while one waits takes its place, and the one it
 * replaces is skipped by every view stream (their connections see a gap and get a
 * keyframe). The q it reads stays put without the ticks waiting for it: of SRV_QBUFS
 * buffers a snapshot tick fills one that neither the next deltas nor a queued snapshot
 * read (srv_views_next_buffer), so a starved view thread costs its streams keyframes, not
 * the ticks their time. */
#include "srv_int.h"
#include "view_select.h"

#include <stdio.h>
#include <string.h>

/* One snapshot per view stream: the state encoded with the view's per-tree mode counts
 * (view_select_grid), the extras of the shared snapshot copied. A stream whose selection
 * is new starts with a keyframe, and every stream sends only a keyframe on the periodic
 * seqs (srv_stream_start), the shared one and the views on the same snapshots. */
static void encode_views(srv *s, const srv_vjob *j)
{
    uint32_t streams[SRV_MAX_VIEWS];
    ctl_view views[SRV_MAX_VIEWS];
    pthread_mutex_lock(&s->view_lock);
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        streams[k] = s->views[k].stream;
        views[k] = s->views[k].v;
    }
    pthread_mutex_unlock(&s->view_lock);
    const srv_qhist qh = { .q = { s->qbuf[j->qi[0]], s->qbuf[j->qi[1]], s->qbuf[j->qi[2]] },
                           .n_trees = (uint32_t)s->d.sc->n_trees,
                           .stride = (uint32_t)s->stride,
                           .lanes = &s->vlanes };
    for (int k = 0; k < SRV_MAX_VIEWS; k++) {
        srv_vsel *vs = &s->vsel[k];
        if (!streams[k]) {
            vs->enc.id = 0;
            continue;
        }
        uint64_t t0 = mono_us();
        if (vs->enc.id != streams[k]) {
            view_select_grid(&s->vgrid, &views[k], s->tree_modes, s->view_margin_m,
                             SRV_LOD_MODES, vs->modes);
            srv_stream_start(&vs->enc, streams[k], vs->modes, s->key_every);
        }
        /* a stream whose every reader is a slow one, none due yet, is not encoded: each
           snapshot such a reader takes is a keyframe, which the stream's next one is */
        const uint32_t due = net_stream_due(s->net, streams[k]);
        if (due && (int32_t)(j->seq - due) < 0) {
            srv_stream_skip(&vs->enc);
            atomic_fetch_add(&s->pubm.view_idle, 1);
            continue;
        }
        net_snap *q = net_snap_acquire(s->net);
        if (!q) {
            srv_stream_skip(&vs->enc); /* its connections see a gap and get a keyframe */
            continue;
        }
        gale_err e;
        int rc = srv_stream_encode(&vs->enc, &j->h, j->seq, &s->wscene, &qh, j->want, q, &e);
        for (int x = 0; x < NET_SNAP_MAX_EXTRA && !rc; x++) {
            /* what goes only with a keyframe (the whole damage state: after a storm on the
               landscape 0.5 MB) is copied only into a snapshot that has one */
            const bool key_only = (j->extra_key_only >> x & 1u) != 0;
            q->extra_len[x] = key_only && !q->key_len ? 0 : j->extra_len[x];
            memcpy(q->extra[x], j->extra[x], q->extra_len[x]);
        }
        q->extra_key_only = j->extra_key_only;
        if (rc) {
            fprintf(stderr, "gale-server: snapshot %u of view stream %u not sent: %s\n", j->seq,
                    vs->enc.id, e.msg);
            atomic_fetch_sub(&q->refs, 1);
            continue;
        }
        atomic_fetch_add(&s->pubm.view_snapshots, 1);
        atomic_fetch_add(&s->pubm.view_encode_ns, (mono_us() - t0) * 1000u);
        net_publish(s->net, q);
    }
}

static void *view_thread(void *arg)
{
    srv *s = arg;
    pthread_mutex_lock(&s->vlock);
    for (;;) {
        while (!s->vn_jobs && !s->vstop) {
            pthread_cond_wait(&s->vpost, &s->vlock);
        }
        if (s->vstop) {
            break;
        }
        const srv_vjob *j = &s->vjob[s->vhead];
        pthread_mutex_unlock(&s->vlock);
        if (j->gap) {
            for (int k = 0; k < SRV_MAX_VIEWS; k++) {
                srv_stream_skip(&s->vsel[k].enc);
            }
        }
        encode_views(s, j);
        pthread_mutex_lock(&s->vlock);
        s->vhead = (s->vhead + 1) % SRV_VJOBS;
        s->vn_jobs--;
        pthread_cond_broadcast(&s->vdone);
    }
    pthread_mutex_unlock(&s->vlock);
    return NULL;
}

int srv_views_start(srv *s, gale_err *err)
{
    if (pthread_create(&s->vthread, NULL, view_thread, s)) {
        return gale_errf(err, GALE_E_STATE, "gale-server: cannot start the view thread");
    }
    s->vthread_on = true;
    return 0;
}

void srv_views_stop(srv *s)
{
    if (!s->vthread_on) {
        return;
    }
    pthread_mutex_lock(&s->vlock);
    s->vstop = true;
    pthread_cond_broadcast(&s->vpost);
    pthread_mutex_unlock(&s->vlock);
    pthread_join(s->vthread, NULL);
    s->vthread_on = false;
}

void srv_views_post(srv *s, const wire_header *h, uint32_t seq, unsigned want,
                    const net_snap *p, const int qi[3])
{
    pthread_mutex_lock(&s->vlock);
    srv_vjob *j;
    if (s->vn_jobs == SRV_VJOBS) {
        /* the newest waiting gives way (the view thread reads vjob[vhead] alone): the
           streams miss it */
        j = &s->vjob[(s->vhead + SRV_VJOBS - 1) % SRV_VJOBS];
        s->vgap = true;
        atomic_fetch_add(&s->pubm.view_missed, 1);
    } else {
        j = &s->vjob[(s->vhead + s->vn_jobs) % SRV_VJOBS];
        s->vn_jobs++;
    }
    j->gap = s->vgap;
    s->vgap = false;
    j->h = *h;
    j->seq = seq;
    j->want = want;
    for (int k = 0; k < 3; k++) {
        j->qi[k] = qi[k];
    }
    for (int x = 0; x < NET_SNAP_MAX_EXTRA; x++) {
        j->extra_len[x] = p->extra_len[x];
        memcpy(j->extra[x], p->extra[x], p->extra_len[x]);
    }
    j->extra_key_only = p->extra_key_only;
    pthread_cond_signal(&s->vpost);
    pthread_mutex_unlock(&s->vlock);
}

void srv_views_gap(srv *s)
{
    pthread_mutex_lock(&s->vlock);
    if (s->vn_jobs == SRV_VJOBS) {
        s->vn_jobs--; /* the snapshot waiting goes too */
        atomic_fetch_add(&s->pubm.view_missed, 1);
    }
    s->vgap = true;
    pthread_mutex_unlock(&s->vlock);
}

/* A queued snapshot reads qbuf[qi]; s->vlock held. */
static bool reads_buffer(const srv *s, int qi)
{
    for (int i = 0; i < s->vn_jobs; i++) {
        const srv_vjob *j = &s->vjob[(s->vhead + i) % SRV_VJOBS];
        if (j->qi[0] == qi || j->qi[1] == qi || j->qi[2] == qi) {
            return true;
        }
    }
    return false;
}

int srv_views_next_buffer(srv *s)
{
    /* the last two snapshots, the newest queued (the snapshot just posted, or the one it
       replaced: its newest two are the last two) and the one being encoded read at most
       2 + 1 + 3 buffers, so one is free */
    _Static_assert(SRV_VJOBS == 2 && SRV_QBUFS >= 2 + 1 + 3 + 1, "a buffer is always free");
    /* (a snapshot not published drops the one waiting, srv_views_gap, so the newest
       queued is always the last snapshot) */
    int free_qi = -1;
    pthread_mutex_lock(&s->vlock);
    for (;;) {
        for (int k = 0; k < SRV_QBUFS && free_qi < 0; k++) {
            if (k != s->qlast[0] && k != s->qlast[1] && !reads_buffer(s, k)) {
                free_qi = k;
            }
        }
        if (free_qi >= 0) {
            break;
        }
        pthread_cond_wait(&s->vdone, &s->vlock); /* not reached: see above */
    }
    pthread_mutex_unlock(&s->vlock);
    return free_qi;
}
