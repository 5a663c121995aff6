/* Many views on loopback (server/SERVER.md "Views and LOD"): 20 raw clients, each with a
 * frustum view of its own (street, roof and aerial heights, with lod_m; half sent in the
 * hello, half in a view message after it), read their streams side by side. Each gets a
 * stream of its own: from its first keyframe of the view on, every state it decodes has
 * view_select's trees and mode counts for its view (the rule tree by tree, PROTOCOL.md
 * "view"), the values within half a step of the server's. */
#include "check.h"
#include "server_wsraw.h"
#include "ctl.h"
#include "srv.h"
#include "view_select.h"
#include "wire.h"

#include <pthread.h>
#include <time.h>

#include "server_fixture.h"

#define N_CLIENTS 20
#define LOD_MODES 4 /* the server's SRV_LOD_MODES */

/* Client k's view: an eye on a ring about the scene, at street, roof or aerial height,
 * looking across it; every field different from the other clients'. */
static ctl_view client_view(int k)
{
    static const float z_m[3] = { 1.75f, 12.0f, 60.0f };
    const double a = 2.0 * M_PI * k / N_CLIENTS;
    const double look = a + M_PI + 0.6 * sin(3.0 * k); /* inward, off the centre */
    const double pitch = k % 3 == 2 ? -0.5 : -0.05 * (k % 3);
    ctl_view v = { .kind = CTL_VIEW_FRUSTUM, .fov_deg = (float)(35 + 3 * k),
                   .far_m = (float)(25 + 4 * k), .lod_m = (float)(8 + k % 7 * 3) };
    v.eye[0] = (float)(45.0 * cos(a));
    v.eye[1] = (float)(45.0 * sin(a));
    v.eye[2] = z_m[k % 3];
    v.dir[0] = (float)(cos(look) * cos(pitch));
    v.dir[1] = (float)(sin(look) * cos(pitch));
    v.dir[2] = (float)sin(pitch);
    return v;
}

static void view_json(const ctl_view *v, char *out, size_t cap)
{
    snprintf(out, cap,
             "{\"kind\": \"frustum\", \"eye\": [%.9g, %.9g, %.9g], \"dir\": [%.9g, %.9g, %.9g],"
             " \"fov_deg\": %.9g, \"far_m\": %.9g, \"lod_m\": %.9g}",
             (double)v->eye[0], (double)v->eye[1], (double)v->eye[2], (double)v->dir[0],
             (double)v->dir[1], (double)v->dir[2], (double)v->fov_deg, (double)v->far_m,
             (double)v->lod_m);
}

/* Opens client c with view v in its hello (in_hello) or in a view message after it. */
static int open_client(wsraw *c, const ctl_view *v, bool in_hello)
{
    if (wsraw_open(c, srv_port(S), 0)) {
        return -1;
    }
    char vj[512], h[768];
    view_json(v, vj, sizeof vj);
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"viewer\"%s%s}",
             WIRE_PROTOCOL_VERSION, in_hello ? ", \"view\": " : "", in_hello ? vj : "");
    wsraw_text(c, h);
    uint8_t *m;
    size_t n;
    int op = wsraw_recv(c, &m, &n, 15000); /* generous: a sanitizer build on a busy machine */
    free(m);
    if (op != 1) {
        return -1;
    }
    if (!in_hello) {
        snprintf(h, sizeof h, "{\"type\": \"view\", \"view\": %s}", vj);
        wsraw_text(c, h);
    }
    return 0;
}

/* One state frame of c into dec (other frames are read past): 1, or 0 when none came in
 * time, -1 on a decode error. */
static int read_state(wsraw *c, wire_decoder *dec, wire_frame *f)
{
    for (int i = 0; i < 16; i++) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(c, &b, &n, 5000);
        if (op < 0 || op == 8) {
            free(b);
            return 0;
        }
        gale_err e;
        if (op == 2 && wire_decode(dec, b, n, f, &e)) {
            fprintf(stderr, "  decode: %s\n", e.msg);
            free(b);
            return -1;
        }
        free(b);
        if (op == 2 && (f->hdr.type == WIRE_MSG_KEYFRAME || f->hdr.type == WIRE_MSG_DELTA)) {
            return 1;
        }
    }
    return 0;
}

static void test_twenty_views(void)
{
    static wsraw c[N_CLIENTS];
    static wire_decoder *dec[N_CLIENTS];
    ctl_view v[N_CLIENTS];
    for (int k = 0; k < N_CLIENTS; k++) {
        v[k] = client_view(k);
        CHECK(open_client(&c[k], &v[k], k % 2 == 0) == 0);
        dec[k] = wire_decoder_create(&(wire_decoder_desc){ 0 }, NULL);
    }
    /* what each view selects, by the rule tree by tree */
    float pos[N_TREES * 3], margin_m = 0.0f;
    uint8_t full[N_TREES], want[N_CLIENTS][N_TREES];
    for (int t = 0; t < N_TREES; t++) {
        memcpy(pos + 3 * t, SC.trees[t].pos, sizeof SC.trees[t].pos);
        full[t] = N_MODES;
        float h = 12.0f * SC.trees[t].scale; /* the fixture's species are 12 m tall */
        margin_m = h > margin_m ? h : margin_m;
    }
    for (int k = 0; k < N_CLIENTS; k++) {
        view_select(&v[k], N_TREES, pos, full, margin_m, LOD_MODES, want[k]);
    }
    /* each reads its keyframe and then 20 frames more, the clients in turn so that none
     * falls behind; frames before its view took hold (the shared stream's, for a view sent
     * after the hello) are read past by waiting for a keyframe that matches */
    int keys_after[N_CLIENTS] = { 0 }, bad_states = 0, bad_trees = 0, shown = 0, empty = 0,
        distinct = 0, keys = 0;
    bool matched[N_CLIENTS] = { false };
    uint32_t seq[N_CLIENTS] = { 0 };
    double worst = 0.0;
    for (int round = 0; round < 60; round++) {
        for (int k = 0; k < N_CLIENTS; k++) {
            wire_frame f;
            int r = read_state(&c[k], dec[k], &f);
            CHECK(r == 1);
            if (r != 1) {
                continue;
            }
            seq[k] = f.seq;
            int off = 0;
            for (int t = 0; t < N_TREES; t++) {
                float q[N_MODES];
                off += wire_decoder_q(dec[k], (uint32_t)t, q, N_MODES) != want[k][t];
            }
            if (matched[k]) {
                /* a gap (the server starved) brings a keyframe, of the same selection */
                keys_after[k] += f.hdr.type == WIRE_MSG_KEYFRAME;
                bad_states += off != 0;
            }
            matched[k] = matched[k] || (off == 0 && f.hdr.type == WIRE_MSG_KEYFRAME);
        }
    }
    for (int k = 0; k < N_CLIENTS; k++) {
        CHECK(matched[k]);
        keys += keys_after[k];
        int in = 0;
        for (int t = 0; t < N_TREES; t++) {
            float qd[N_MODES], qs[N_MODES];
            uint32_t nm = wire_decoder_q(dec[k], (uint32_t)t, qd, N_MODES);
            bad_trees += nm != want[k][t];
            in += nm != 0;
            if (nm && srv_history_q(S, seq[k], t, qs, N_MODES) == N_MODES) {
                for (uint32_t m = 0; m < nm; m++) {
                    double e = fabs((double)qd[m] - (double)qs[m]) /
                               (double)srv_qstep(S, t, (int)m);
                    worst = e > worst ? e : worst;
                }
            }
        }
        shown += in;
        empty += in == 0;
        bool same = false;
        for (int j = 0; j < k; j++) {
            same = same || memcmp(want[j], want[k], N_TREES) == 0;
        }
        distinct += !same;
    }
    fprintf(stderr, "  %d clients: %d distinct selections, %.1f trees each of %d, %d empty; "
                    "%d keyframes after the first; worst %.3f steps\n",
            N_CLIENTS, distinct, (double)shown / N_CLIENTS, N_TREES, empty, keys, worst);
    CHECK(bad_states == 0);
    CHECK(bad_trees == 0);
    CHECK(distinct >= N_CLIENTS - 2); /* the views differ in what they select, too */
    CHECK(shown > 0 && shown < N_CLIENTS * N_TREES);
    CHECK_NEAR(worst, 0, 0.5 + 1e-3);
    srv_pub_counters *mt = srv_pub_metrics(S);
    unsigned long long vn = atomic_load(&mt->view_snapshots);
    CHECK(vn >= 20ull * N_CLIENTS);
    if (vn) {
        fprintf(stderr, "  %llu view snapshots, %.1f us each to encode (%d trees); %llu "
                        "missed\n", vn,
                (double)atomic_load(&mt->view_encode_ns) * 1e-3 / (double)vn, N_TREES,
                (unsigned long long)atomic_load(&mt->view_missed));
    }
    for (int k = 0; k < N_CLIENTS; k++) {
        wire_decoder_destroy(dec[k]);
        wsraw_close(&c[k]);
    }
}

int main(void)
{
    if (start_server()) {
        fprintf(stderr, "cannot start the server\n");
        return 1;
    }
    RUN(test_twenty_views);
    stop_server();
    return check_report();
}
