/* gale-relay on loopback with a real nats-server, gale-server --nats and relays, all
 * processes started here (server/SERVER.md "Relays"): a client on a relay decodes the
 * same state as a client on the server for the same seqs, gets the same welcome species
 * and the same asset bytes over HTTP; the relay answers its own /healthz and /metrics;
 * resync, view and kiosk hellos (wrong token closed 4007 by the server's check, right one
 * welcomed) work through a relay; a killed relay's
 * client is back on a keyframe from another relay within 2 s; a restarted gale-server
 * brings the relay's client back on a keyframe, a restarted nats-server back to decoded
 * state, each within 2 s without reconnecting, seq still increasing, and no frame fails
 * to decode. Palm scene of
 * 12 trees, assets cached in the build tree. */
#include "check.h"
#include "hash.h"
#include "mono.h"
#include "relay_fixture.h"
#include "server_wsraw.h"
#include "wire.h"

#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>

#define TOKEN "relay-test-token"

/* A client: its socket, decoder and what it saw. */
typedef struct cli {
    wsraw ws;
    wire_decoder *dec;
    int bad, gaps, keys, states, backwards;
    uint32_t last_seq;
    int last_type;
    char *welcome;
    uint32_t seqs[400];
    uint64_t hashes[400];
    int n_rec;
} cli;

static uint64_t state_hash(const wire_decoder *d)
{
    wire_state s = wire_decoder_state(d);
    uint64_t h = hash64(s.n_modes, s.n_trees);
    return hash64_update(h, s.q, sizeof(int16_t) * s.stride * s.n_trees);
}

/* Opens port, says hello (extra fields appended); 0 with the welcome kept, else -1 and
 * the close code in ws.close_code. */
static int cli_open(cli *c, int port, const char *role, const char *extra)
{
    memset(c, 0, sizeof *c);
    c->dec = wire_decoder_create(&(wire_decoder_desc){ 0 }, NULL);
    if (wsraw_open(&c->ws, port, 0)) {
        return -1;
    }
    char hello[512];
    snprintf(hello, sizeof hello, "{\"type\":\"hello\",\"protocol\":1,\"role\":\"%s\"%s}", role,
             extra ? extra : "");
    wsraw_text(&c->ws, hello);
    for (int i = 0; i < 20; i++) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&c->ws, &b, &n, 3000);
        if (op == 1 && strstr((char *)b, "\"welcome\"")) {
            c->welcome = (char *)b;
            return 0;
        }
        free(b);
        if (op < 0 || op == 8) {
            return -1;
        }
    }
    return -1;
}

static void cli_fini(cli *c)
{
    wsraw_close(&c->ws);
    wire_decoder_destroy(c->dec);
    free(c->welcome);
}

/* The server's end closed (wsraw_recv's -1 is also a quiet 200 ms). */
static bool ended(const cli *c)
{
    char ch;
    ssize_t k = recv(c->ws.fd, &ch, 1, MSG_PEEK | MSG_DONTWAIT);
    return k == 0 || (k < 0 && errno != EAGAIN && errno != EWOULDBLOCK);
}

/* Reads until `states` more state frames decoded (or a keyframe when want_key) or
 * timeout_s; a gap asks for a keyframe as gale-client does. Returns 1 when it got what
 * it waited for, 0 on timeout, -1 when the connection ended. */
static int cli_read(cli *c, int states, bool want_key, double timeout_s)
{
    double until = mono_s() + timeout_s;
    int got = 0;
    while (mono_s() < until) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&c->ws, &b, &n, 200);
        if (op == 8 || (op < 0 && ended(c))) {
            free(b);
            return -1;
        }
        if (op != 2) {
            free(b);
            continue;
        }
        wire_frame f;
        gale_err e;
        int rc = wire_decode(c->dec, b, n, &f, &e);
        free(b);
        if (rc == GALE_E_STATE) {
            c->gaps++;
            wsraw_text(&c->ws, "{\"type\":\"resync\",\"seq\":0}");
            continue;
        }
        if (rc) {
            fprintf(stderr, "  decode: %s\n", e.msg);
            c->bad++;
            continue;
        }
        if (f.hdr.type != WIRE_MSG_KEYFRAME && f.hdr.type != WIRE_MSG_DELTA) {
            continue;
        }
        c->backwards += c->last_seq && f.seq <= c->last_seq;
        c->last_seq = f.seq;
        c->last_type = f.hdr.type;
        c->states++;
        c->keys += f.hdr.type == WIRE_MSG_KEYFRAME;
        if (c->n_rec < 400) {
            c->seqs[c->n_rec] = f.seq;
            c->hashes[c->n_rec++] = state_hash(c->dec);
        }
        got++;
        if (want_key ? f.hdr.type == WIRE_MSG_KEYFRAME : got >= states) {
            return 1;
        }
    }
    return 0;
}

/* The welcome's "species" array (same on server and relay; client_id, clocks differ). */
static const char *species_of(const char *w)
{
    const char *s = w ? strstr(w, "\"species\"") : NULL;
    return s ? s : "";
}

/* HTTP GET of path: status, and the body's length and hash. */
static int http_get(int port, const char *path, size_t *len, uint64_t *h)
{
    int fd = wsraw_tcp(port, 0);
    char req[256];
    int n = snprintf(req, sizeof req, "GET %s HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n",
                     path);
    wsraw c = { .fd = fd };
    if (fd < 0 || wsraw_send_all(fd, req, (size_t)n)) {
        return -1;
    }
    while (wsraw_fill(&c, 3000) == 0) {
    }
    close(fd);
    int status = -1;
    *len = 0;
    if (c.len > 12 && sscanf((const char *)c.buf, "HTTP/1.1 %d", &status) == 1) {
        for (size_t i = 3; i < c.len; i++) {
            if (!memcmp(c.buf + i - 3, "\r\n\r\n", 4)) {
                *len = c.len - i - 1;
                *h = hash64(c.buf + i + 1, *len);
                break;
            }
        }
    }
    free(c.buf);
    return status;
}

static proc nats, server, relay_a, relay_b;

static void test_same_values(void)
{
    cli s, r;
    CHECK(cli_open(&s, server.port, "viewer", NULL) == 0);
    CHECK(cli_open(&r, relay_a.port, "viewer", NULL) == 0);
    CHECK(strcmp(species_of(s.welcome), species_of(r.welcome)) == 0);
    CHECK(strlen(species_of(r.welcome)) > 20);
    CHECK(cli_read(&s, 60, false, 6) == 1);
    CHECK(cli_read(&r, 60, false, 6) == 1);
    int common = 0, differ = 0;
    for (int i = 0; i < r.n_rec; i++) {
        for (int j = 0; j < s.n_rec; j++) {
            if (r.seqs[i] == s.seqs[j]) {
                common++;
                differ += r.hashes[i] != s.hashes[j];
            }
        }
    }
    fprintf(stderr, "  %d seqs decoded on both, %d differ\n", common, differ);
    CHECK(common >= 30);
    CHECK(differ == 0);
    CHECK(s.bad == 0 && r.bad == 0 && r.backwards == 0);
    CHECK(r.seqs[0] && r.keys >= 1); /* a joiner starts on a keyframe */

    /* the first species' asset, from the relay's cache, is the server's byte for byte */
    const char *u = strstr(r.welcome, "\"url\":\"");
    char path[128] = "";
    if (u) {
        sscanf(u + 7, "%127[^\"]", path);
    }
    size_t ls = 0, lr = 0;
    uint64_t hs = 0, hr = 1;
    CHECK(http_get(server.port, path, &ls, &hs) == 200);
    CHECK(http_get(relay_a.port, path, &lr, &hr) == 200);
    CHECK(ls > 1000 && ls == lr && hs == hr);
    /* the relay's own /healthz and /metrics */
    char *body = NULL;
    CHECK(wsraw_http_get(relay_a.port, "/healthz", &body) == 200 && body && !strncmp(body, "ok tick ", 8));
    free(body);
    CHECK(wsraw_http_get(relay_a.port, "/metrics", &body) == 200 && body &&
          strstr(body, "\ngale_relay_snapshots_total ") && strstr(body, "gale_clients{role=\"viewer\"} 1"));
    free(body);
    cli_fini(&s);
    cli_fini(&r);
}

static void test_controls(void)
{
    cli r;
    CHECK(cli_open(&r, relay_a.port, "viewer", NULL) == 0);
    CHECK(cli_read(&r, 5, false, 3) == 1);
    /* resync: the answer is a keyframe */
    wsraw_text(&r.ws, "{\"type\":\"resync\",\"seq\":1}");
    int keys = r.keys;
    CHECK(cli_read(&r, 0, true, 2) == 1 && r.keys == keys + 1);
    /* a view: a keyframe of its own stream, with trees out of view not sent */
    wsraw_text(&r.ws, "{\"type\":\"view\",\"view\":{\"kind\":\"circle\",\"x\":-100,\"y\":-100,"
                      "\"radius_m\":1}}");
    CHECK(cli_read(&r, 0, true, 2) == 1);
    CHECK(cli_read(&r, 3, false, 2) == 1);
    wire_state st = wire_decoder_state(r.dec);
    uint32_t sent = 0;
    for (uint32_t t = 0; t < st.n_trees; t++) {
        sent += st.n_modes[t] > 0;
    }
    fprintf(stderr, "  view through the relay: %u of %u trees sent\n", sent, st.n_trees);
    CHECK(st.n_trees == 12 && sent < 12);
    /* a ping is answered by the server, through the relay */
    wsraw_text(&r.ws, "{\"type\":\"ping\",\"id\":77,\"client_us\":5}");
    int pong = 0;
    for (int i = 0; i < 30 && !pong; i++) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&r.ws, &b, &n, 1000);
        pong = op == 1 && strstr((char *)b, "\"pong\"") && strstr((char *)b, "\"id\":77");
        free(b);
    }
    CHECK(pong);
    CHECK(r.bad == 0);
    cli_fini(&r);

    /* kiosk: the server checks the token (the right one first: after a wrong one the
     * address waits out a delay, SERVER.md "Kiosk tokens") */
    cli k;
    CHECK(cli_open(&k, relay_a.port, "kiosk", ",\"token\":\"" TOKEN "\"") == 0);
    CHECK(k.welcome && strstr(k.welcome, "\"role\":\"kiosk\""));
    wsraw_text(&k.ws, "{\"type\":\"wind\",\"token\":\"" TOKEN "\",\"speed_ms\":20}");
    CHECK(cli_read(&k, 10, false, 3) == 1); /* still open: the command was accepted */
    cli_fini(&k);
    CHECK(cli_open(&k, relay_a.port, "kiosk", ",\"token\":\"wrong\"") == -1);
    wsraw_wait_close(&k.ws, 3000);
    CHECK(k.ws.close_code == WIRE_CLOSE_BAD_TOKEN);
    cli_fini(&k);
    /* an unknown type is the server's 4001, through the relay */
    cli u;
    CHECK(cli_open(&u, relay_a.port, "viewer", NULL) == 0);
    wsraw_text(&u.ws, "{\"type\":\"launch\"}");
    wsraw_wait_close(&u.ws, 3000);
    CHECK(u.ws.close_code == WIRE_CLOSE_UNKNOWN_TYPE);
    cli_fini(&u);
}

static void test_relay_killed(void)
{
    cli r;
    CHECK(cli_open(&r, relay_a.port, "viewer", NULL) == 0);
    CHECK(cli_read(&r, 5, false, 3) == 1);
    double t0 = mono_s();
    end(&relay_a, SIGKILL);
    CHECK(cli_read(&r, 1000, false, 2) == -1); /* the connection ends */
    cli_fini(&r);
    /* the next relay of the client's list */
    int ok = cli_open(&r, relay_b.port, "viewer", NULL) == 0 && cli_read(&r, 0, true, 2) == 1;
    double dt = mono_s() - t0;
    fprintf(stderr, "  relay killed: back on a keyframe from the other relay in %.3f s\n", dt);
    CHECK(ok && dt <= 2.0 && r.bad == 0);
    cli_fini(&r);
    CHECK(start_relay(&relay_a) == 0);
}

/* Kills and restarts what `which` names under a reading client; the client stays
 * connected and decodes state again within 2 s of the restart: a keyframe when want_key
 * (a new server), else any state frame (after a broker restart the server's buffered
 * snapshots may continue the delta chain with no gap). */
static void restart_under_client(const char *what, proc *p, int (*start)(proc *), bool want_key)
{
    cli r;
    CHECK(cli_open(&r, relay_a.port, "viewer", NULL) == 0);
    CHECK(cli_read(&r, 10, false, 3) == 1);
    double t_kill = mono_s();
    end(p, SIGTERM);
    cli_read(&r, 1000, false, 0.3); /* what was in flight before the kill */
    CHECK(start(p) == 0);
    double t0 = mono_s();
    int keys = r.keys, states = r.states;
    int ok = 0;
    while (!ok && mono_s() - t0 < 4.0 && cli_read(&r, 1, false, 0.5) >= 0) {
        ok = want_key ? r.keys > keys : r.states > states;
    }
    double dt = mono_s() - t0;
    fprintf(stderr,
            "  %s restarted: the relay's client decodes %s again %.3f s after it listened "
            "(%.3f s after the kill), seq %u\n",
            what, want_key ? "a keyframe" : "state", dt, mono_s() - t_kill, r.last_seq);
    CHECK(ok && dt <= 2.0);
    CHECK(cli_read(&r, 10, false, 2) == 1); /* and it goes on */
    CHECK(r.bad == 0 && r.backwards == 0);
    cli_fini(&r);
}

static void test_server_restart(void)
{
    restart_under_client("gale-server", &server, start_server, true);
}

static void test_nats_restart(void)
{
    restart_under_client("nats-server", &nats, start_nats, false);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    FILE *f = fopen("relay_scene.json", "w");
    if (f) {
        fprintf(f,
                "{\"name\": \"relay\", \"species\": [{\"name\": \"palm\", \"file\": "
                "\"%s/configs/species/palm.json\", \"modes\": 8}],"
                " \"forest\": [{\"species\": \"palm\", \"count\": 12, \"area_min\": [-40, -40],"
                " \"area_max\": [40, 40], \"min_spacing_m\": 3}],"
                " \"wind\": {\"solver\": false, \"u10_ms\": 12}}",
                GALE_SOURCE_DIR);
        fclose(f);
    }
    f = fopen("relay_token", "w");
    if (f) {
        fputs(TOKEN "\n", f);
        fclose(f);
    }
    int nats_rc = start_nats_fresh(&nats);
    snprintf(nats_url, sizeof nats_url, "nats://127.0.0.1:%d", nats_port);
    if (nats_rc || start_server(&server) || start_relay(&relay_a) || start_relay(&relay_b)) {
        fprintf(stderr, "test_relay: could not start nats-server, gale-server and relays\n");
        end(&relay_a, SIGKILL);
        end(&server, SIGKILL);
        end(&nats, SIGKILL);
        return 1;
    }
    RUN(test_same_values);
    RUN(test_controls);
    RUN(test_relay_killed);
    RUN(test_server_restart);
    RUN(test_nats_restart);
    end(&relay_a, SIGTERM);
    end(&relay_b, SIGTERM);
    end(&server, SIGTERM);
    end(&nats, SIGTERM);
    return check_report();
}
