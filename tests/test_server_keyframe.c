/* Periodic keyframes on loopback (PROTOCOL.md "Sequence and gaps"): with a period of
 * 0.5 s (15 snapshots at 30/s), a client watching the shared stream and one following a
 * view stream each get, beside their join keyframe, a KEYFRAME on every seq that is a
 * multiple of 15, and every frame between decodes. */
#include "check.h"
#include "server_wsraw.h"
#include "ctl.h"
#include "srv.h"
#include "wire.h"

#include <pthread.h>
#include <time.h>

#include "server_fixture.h"

#define KEY_EVERY 15 /* 0.5 s × 30 snapshots/s */

static int open_hello(wsraw *c, const char *extra)
{
    if (wsraw_open(c, srv_port(S), 0)) {
        return -1;
    }
    char h[256];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"viewer\"%s}",
             WIRE_PROTOCOL_VERSION, extra ? extra : "");
    wsraw_text(c, h);
    uint8_t *m;
    size_t n;
    int op = wsraw_recv(c, &m, &n, 3000);
    free(m);
    return op == 1 ? 0 : -1;
}

/* Reads 66 state frames (2.2 s at 30 a second: over four periods), or what comes in
 * 30 s on a machine that starves the server; counts keyframes after the first, those on
 * a seq that is not a multiple of KEY_EVERY and frames that fail to decode. Counted in
 * frames, not seconds: a slow tick stretches the periods with the snapshots. */
#define WATCH_STATES 66
static void watch(wsraw *c, int *periodic, int *off_period, int *bad, int *states)
{
    wire_decoder *dec = wire_decoder_create(&(wire_decoder_desc){ N_TREES, N_MODES }, NULL);
    CHECK(dec != NULL);
    uint64_t end = mono_us() + 30000000u;
    bool first = true;
    while (dec && *states < WATCH_STATES && mono_us() < end) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(c, &b, &n, 3000);
        if (op < 0 || op == 8) {
            free(b);
            break;
        }
        wire_frame f;
        gale_err e;
        if (op == 2) {
            if (wire_decode(dec, b, n, &f, &e)) {
                fprintf(stderr, "  decode: %s\n", e.msg);
                (*bad)++;
            } else if (f.hdr.type == WIRE_MSG_KEYFRAME || f.hdr.type == WIRE_MSG_DELTA) {
                (*states)++;
                if (f.hdr.type == WIRE_MSG_KEYFRAME && !first) {
                    (*periodic)++;
                    *off_period += f.seq % KEY_EVERY != 0;
                }
                first = false;
            }
        }
        free(b);
    }
    wire_decoder_destroy(dec);
}

static void test_periodic(const char *what, const char *extra)
{
    wsraw c;
    CHECK(open_hello(&c, extra) == 0);
    int periodic = 0, off = 0, bad = 0, states = 0;
    watch(&c, &periodic, &off, &bad, &states);
    fprintf(stderr, "  %s: %d state frames, %d periodic keyframes\n", what, states, periodic);
    CHECK(states >= 40);
    CHECK(periodic >= 3); /* 66 frames, one keyframe in 15 seqs: 4 or 5 */
    CHECK(periodic <= 6);
    CHECK(off == 0);
    CHECK(bad == 0);
    wsraw_close(&c);
}

static void test_shared_stream(void)
{
    test_periodic("shared", NULL);
}

static void test_view_stream(void)
{
    test_periodic("view",
                  ", \"view\": {\"kind\": \"circle\", \"x\": 0, \"y\": 0, \"radius_m\": 20}");
}

int main(void)
{
    FIXTURE_KEYFRAME_S = 0.5;
    if (start_server()) {
        fprintf(stderr, "cannot start the server\n");
        return 1;
    }
    RUN(test_shared_stream);
    RUN(test_view_stream);
    stop_server();
    return check_report();
}
