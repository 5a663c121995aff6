/* Slow readers on loopback (server/SERVER.md "Slow readers"): a reader that takes its
 * socket's bytes only once a second, in a burst, stays connected and is sent fewer
 * snapshots, every one of which decodes (a DELTA only ever follows the seq just before
 * it); reading steadily again brings it back to the full rate; one that takes nothing
 * at all is closed with 4008 once stall_ms has passed, not before; a slow reader's own
 * view stream is encoded only for the snapshots it takes. The rate is read off
 * the seqs received and /metrics (gale_readers_decimated, gale_decimations_total). */
#include "check.h"
#include "server_wsraw.h"
#include "ctl.h"
#include "srv.h"
#include "wire.h"

#include <pthread.h>
#include <time.h>

#include "server_fixture.h"

#define STALL_S 2.0 /* the fixture's srv_desc.stall_ms */

/* view_json: a view object for the hello (NULL: none, the shared stream) */
static int open_hello_view(wsraw *c, int rcvbuf, const char *view_json)
{
    if (wsraw_open(c, srv_port(S), rcvbuf)) {
        return -1;
    }
    char h[320];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"viewer\"%s%s}",
             WIRE_PROTOCOL_VERSION, view_json ? ", \"view\": " : "", view_json ? view_json : "");
    wsraw_text(c, h);
    uint8_t *m;
    size_t n;
    int op = wsraw_recv(c, &m, &n, 3000);
    free(m);
    return op == 1 ? 0 : -1;
}

static int open_hello(wsraw *c, int rcvbuf)
{
    return open_hello_view(c, rcvbuf, NULL);
}

/* A /metrics row's value, -1 when absent. */
static double metric(const char *name)
{
    char *body = NULL;
    double v = -1;
    if (wsraw_http_get(srv_port(S), "/metrics", &body) == 200 && body) {
        char key[96];
        snprintf(key, sizeof key, "\n%s ", name);
        const char *at = strstr(body, key);
        if (at) {
            v = atof(at + strlen(key));
        }
    }
    free(body);
    return v;
}

/* What the reader saw: state frames by seq, decode errors, deltas whose base it lacked. */
typedef struct seen {
    wire_decoder *dec;
    uint32_t last_seq;
    int states, keys, deltas, bad, orphan_deltas, closes;
    int steps1; /* state frames whose seq follows the last one's */
    size_t bytes; /* of every binary message */
} seen;

static void take(seen *s, const uint8_t *b, size_t n)
{
    wire_frame f;
    gale_err e;
    if (wire_decode(s->dec, b, n, &f, &e)) {
        if (s->bad++ < 3) {
            fprintf(stderr, "  decode: %s\n", e.msg);
        }
        return;
    }
    if (f.hdr.type != WIRE_MSG_KEYFRAME && f.hdr.type != WIRE_MSG_DELTA) {
        return;
    }
    /* independent of the decoder: a delta is sent only on the seq after the last one */
    if (f.hdr.type == WIRE_MSG_DELTA && (!s->states || f.seq != s->last_seq + 1u)) {
        s->orphan_deltas++;
    }
    s->steps1 += s->states && f.seq == s->last_seq + 1u;
    s->keys += f.hdr.type == WIRE_MSG_KEYFRAME;
    s->deltas += f.hdr.type == WIRE_MSG_DELTA;
    s->states++;
    s->last_seq = f.seq;
}

/* Reads every whole message that arrives until wait_s has passed (0: until nothing
 * waits, a burst, as a client bound to its frames reads), or the close. */
static void drain(wsraw *c, seen *s, double wait_s)
{
    const double until = mono_s() + wait_s;
    for (;;) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(c, &b, &n, wait_s > 0 ? 10 : 0);
        if (op == 2) {
            take(s, b, n);
            s->bytes += n;
        }
        s->closes += op == 8;
        free(b);
        if (op == 8 || (wait_s > 0 ? mono_s() >= until : op < 0)) {
            return;
        }
    }
}

static void test_bursty_reader(void)
{
    wsraw c;
    CHECK(open_hello(&c, 4096) == 0);
    seen s = { .dec = wire_decoder_create(&(wire_decoder_desc){ N_TREES, N_MODES }, NULL) };
    CHECK(s.dec != NULL);
    const double dec0 = metric("gale_decimations_total");
    CHECK(dec0 >= 0);
    /* slow: 10 bursts, one a second (the socket untouched between them) */
    double gauge_max = 0;
    int states_late = 0;
    size_t bytes_late = 0;
    for (int k = 0; k < 10; k++) {
        usleep(1000000);
        int before = s.states;
        size_t bytes_before = s.bytes;
        drain(&c, &s, 0);
        states_late += k >= 5 ? s.states - before : 0;
        bytes_late += k >= 5 ? s.bytes - bytes_before : 0;
        double g = metric("gale_readers_decimated");
        gauge_max = g > gauge_max ? g : gauge_max;
    }
    const double dec1 = metric("gale_decimations_total");
    fprintf(stderr,
            "  bursty reader: %d state frames in 10 s (%d in the last 5 s: %.1f a second), "
            "%d keyframes, %d deltas, %d bad, %d orphan deltas; gauge max %.0f, "
            "decimations %.0f\n",
            s.states, states_late, states_late / 5.0, s.keys, s.deltas, s.bad, s.orphan_deltas,
            gauge_max, dec1 - dec0);
    CHECK(s.closes == 0 && c.close_code == 0); /* still connected */
    CHECK(s.bad == 0);
    CHECK(s.orphan_deltas == 0);
    CHECK(gauge_max >= 1);
    CHECK(dec1 - dec0 >= 1);
    CHECK(states_late > 0);
    CHECK(states_late < 5 * 30 / 2); /* under half the published rate */

    /* steady again: it reads as fast as it can; the rate comes back step by step */
    double t0 = mono_s(), recovered = -1;
    while (mono_s() - t0 < 20.0 && recovered < 0) {
        drain(&c, &s, 0.05);
        if (metric("gale_readers_decimated") == 0) {
            recovered = mono_s() - t0;
        }
    }
    /* a second more at full rate: consecutive seqs, deltas again */
    int steps_mid = s.steps1, states_mid = s.states, deltas_mid = s.deltas;
    size_t bytes_mid = s.bytes;
    drain(&c, &s, 1.0);
    fprintf(stderr,
            "  steady again: full rate after %.1f s; then %d state frames in 1 s, %d in "
            "sequence, %d deltas, %zu bytes (%.0f a second while slow); %d bad, %d orphan "
            "deltas in all\n",
            recovered, s.states - states_mid, s.steps1 - steps_mid, s.deltas - deltas_mid,
            s.bytes - bytes_mid, (double)bytes_late / 5.0, s.bad, s.orphan_deltas);
    /* the lower rate sends fewer bytes a second than the full one, not more: each snapshot
       a decimated reader gets is a keyframe, several deltas' worth (the margin: the
       weather and leaves, which follow the snapshots' own rate) */
    CHECK((double)bytes_late / 5.0 <= 1.1 * (double)(s.bytes - bytes_mid));
    CHECK(recovered >= 0);
    CHECK(s.states - states_mid >= 20);
    CHECK(s.steps1 - steps_mid >= s.states - states_mid - 3);
    CHECK(s.deltas - deltas_mid >= 15);
    CHECK(s.bad == 0);
    CHECK(s.orphan_deltas == 0);
    CHECK(s.closes == 0 && c.close_code == 0);
    wire_decoder_destroy(s.dec);
    wsraw_close(&c);
}

/* A slow reader on a view stream of its own: the stream is not encoded for the snapshots
 * it would not take (gale_view_snapshots_idle_total), and every frame it gets decodes. */
static void test_bursty_viewer(void)
{
    wsraw c;
    CHECK(open_hello_view(&c, 4096, "{\"kind\": \"circle\", \"x\": 0, \"y\": 0, "
                                    "\"radius_m\": 500, \"lod_m\": 5}") == 0);
    seen s = { .dec = wire_decoder_create(&(wire_decoder_desc){ N_TREES, N_MODES }, NULL) };
    CHECK(s.dec != NULL);
    const double idle0 = metric("gale_view_snapshots_idle_total");
    const double views0 = metric("gale_view_snapshots_total");
    CHECK(idle0 >= 0 && views0 >= 0);
    int states_late = 0;
    for (int k = 0; k < 8; k++) {
        usleep(1000000);
        int before = s.states;
        drain(&c, &s, 0);
        states_late += k >= 4 ? s.states - before : 0;
    }
    const double idle = metric("gale_view_snapshots_idle_total") - idle0;
    const double views = metric("gale_view_snapshots_total") - views0;
    fprintf(stderr,
            "  bursty viewer: %d state frames in 8 s (%d in the last 4 s), %d keyframes, "
            "%d bad, %d orphan deltas; its stream encoded %.0f snapshots, %.0f not\n",
            s.states, states_late, s.keys, s.bad, s.orphan_deltas, views, idle);
    CHECK(s.closes == 0 && c.close_code == 0);
    CHECK(s.bad == 0);
    CHECK(s.orphan_deltas == 0);
    CHECK(states_late > 0);
    /* the snapshots it skipped at the lower rate were never encoded */
    CHECK(idle > 0.1 * 8 * 30);
    CHECK(views + idle > 0.8 * 8 * 30);
    wire_decoder_destroy(s.dec);
    wsraw_close(&c);
}

static void test_stalled_reader(void)
{
    const double closed0 = metric("gale_laggards_closed_total");
    wsraw c;
    CHECK(open_hello(&c, 4096) == 0);
    const double t0 = mono_s();
    /* reads nothing: the kernel's buffers fill, snapshots wait, and only stall_ms after the
       last byte it took is it closed */
    double closed_at = -1;
    while (mono_s() - t0 < 15.0 && closed_at < 0) {
        if (metric("gale_laggards_closed_total") > closed0) {
            closed_at = mono_s() - t0;
        }
        usleep(50000);
    }
    /* its close frame, behind what the kernel holds (bounded: a reader that reads is one
       the server keeps) */
    seen s = { .dec = wire_decoder_create(&(wire_decoder_desc){ N_TREES, N_MODES }, NULL) };
    drain(&c, &s, closed_at >= 0 ? 3.0 : 0.0);
    wire_decoder_destroy(s.dec);
    const int code = c.close_code;
    fprintf(stderr, "  stalled reader: closed %.2f s after its hello with %d (%s)\n", closed_at,
            code, c.close_reason);
    CHECK(closed_at >= STALL_S);
    CHECK(closed_at < STALL_S + 5.0);
    CHECK(code == WIRE_CLOSE_SLOW);
    CHECK_STR_HAS(c.close_reason, "took nothing for");
    wsraw_close(&c);
}

int main(void)
{
    FIXTURE_SNDBUF = 4096; /* little in flight: the queue, not the kernel, holds the backlog */
    if (start_server()) {
        return 1;
    }
    usleep(300000);
    RUN(test_bursty_reader);
    RUN(test_bursty_viewer);
    RUN(test_stalled_reader);
    stop_server();
    return check_report();
}
