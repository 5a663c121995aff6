/* The view thread: each snapshot's view streams (srv_int.h srv_vsel), encoded beside the
 * ticks rather than after them. The sim thread encodes the shared stream, hands the
 * snapshot to this thread and goes on; the ticks' threads run at a real-time priority
 * where the scene asks for it (SERVER.md "Loop") and this one at the normal one, so the
 * views take the cores the ticks leave. It may lag a snapshot behind (SRV_VJOBS queued);
 * a snapshot posted beyond that is skipped by every view stream (their connections see a
 * gap and get a keyframe). The q it reads stays put: SRV_QBUFS buffers, and a snapshot
 * tick that would write one a queued snapshot still reads has the view thread skip that
 * snapshot's remaining streams and waits only for the stream being encoded
 * (srv_views_hold): a starved view thread costs its streams keyframes, not the ticks
 * their time. */
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
        if (atomic_load(&s->vcut)) {
            srv_stream_skip(&vs->enc); /* a tick needs the q: its connections see a gap */
            atomic_fetch_add(&s->pubm.view_cut, 1);
            continue;
        }
        uint64_t t0 = mono_us();
        if (vs->enc.id != streams[k]) {
            view_select_grid(&s->vgrid, &views[k], s->tree_modes, s->view_margin_m,
                             SRV_LOD_MODES, vs->modes);
            srv_stream_start(&vs->enc, streams[k], vs->modes, s->key_every);
        }
        net_snap *q = net_snap_acquire(s->net);
        if (!q) {
            srv_stream_skip(&vs->enc); /* its connections see a gap and get a keyframe */
            continue;
        }
        gale_err e;
        int rc = srv_stream_encode(&vs->enc, &j->h, j->seq, &s->wscene, &qh, j->want, q, &e);
        for (int x = 0; x < NET_SNAP_MAX_EXTRA && !rc; x++) {
            q->extra_len[x] = j->extra_len[x];
            memcpy(q->extra[x], j->extra[x], j->extra_len[x]);
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
    if (s->vn_jobs == SRV_VJOBS) {
        s->vgap = true;
        atomic_fetch_add(&s->pubm.view_missed, 1);
        pthread_mutex_unlock(&s->vlock);
        return;
    }
    /* the slot no thread reads: the view thread reads vjob[vhead] only while it is queued */
    srv_vjob *j = &s->vjob[(s->vhead + s->vn_jobs) % SRV_VJOBS];
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
    s->vn_jobs++;
    pthread_cond_signal(&s->vpost);
    pthread_mutex_unlock(&s->vlock);
}

void srv_views_gap(srv *s)
{
    pthread_mutex_lock(&s->vlock);
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

void srv_views_hold(srv *s, int qi)
{
    pthread_mutex_lock(&s->vlock);
    uint64_t t0 = 0;
    while (reads_buffer(s, qi)) {
        t0 = t0 ? t0 : mono_ns();
        atomic_store(&s->vcut, true);
        pthread_cond_wait(&s->vdone, &s->vlock);
    }
    if (t0) {
        atomic_store(&s->vcut, false);
        atomic_fetch_add(&s->pubm.view_holds, 1);
        atomic_fetch_add(&s->pubm.view_hold_ns, mono_ns() - t0);
    }
    pthread_mutex_unlock(&s->vlock);
}
