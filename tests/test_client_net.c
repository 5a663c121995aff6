/* Client networking against a scripted peer on a loopback port (a real lws server in a
 * thread, speaking the real protocol): hello with the role, welcome, frames decoded, bad
 * and truncated frames dropped and counted, a gap answered with a resync, the clock from
 * pongs, HTTP asset fetches (200, 404, too long, bytes that do not hash to the welcome's
 * hash refused), and reconnection with backoff after the
 * server closes the connection and after it goes away and comes back on the same port. */
#include <libwebsockets.h>

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mono.h"
#include "check.h"
#include "cli_net.h"
#include "hash.h"

#define N_TREES         3
#define N_MODES         4
#define ASSET_BYTES     100000
#define CLOCK_OFFSET_US 5000000ull /* the peer's clock runs 5 s ahead of ours */

/* ---- scripted peer ------------------------------------------------------------------ */

typedef struct peer {
    pthread_t thread;
    pthread_mutex_t lock;
    struct lws_context *ctx;
    int port;
    volatile int stop;
    /* script state (peer thread only) */
    uint8_t frames[8][LWS_PRE + 4096];
    size_t frame_len[8];
    bool frame_binary[8];
    int n_frames, next_frame;
    bool close_after_script;
    uint64_t pong_us;
    bool pong_pending;
    uint32_t pong_id;
    uint64_t ping_client_us;
    const uint8_t *http_body;
    size_t http_len, http_off;
    /* what the peer saw (under lock) */
    int hellos, role, pings, resyncs, resync_seq, connections, winds;
    float wind_speed;
    char wind_token[CTL_MAX_TOKEN];
    char token[CTL_MAX_TOKEN];
} peer;

static uint8_t asset_bytes[ASSET_BYTES];

static void add_text(peer *p, const ctl_msg *m)
{
    size_t len = 0;
    gale_err err = { 0 };
    char *buf = (char *)p->frames[p->n_frames] + LWS_PRE;
    CHECK(ctl_encode_into(m, buf, 4096, &len, &err) == 0);
    p->frame_len[p->n_frames] = len;
    p->frame_binary[p->n_frames++] = false;
}

/* The script of one connection: welcome, keyframe (seq 1), garbage, a truncated delta,
 * delta seq 2, delta seq 4 (a gap: seq 3 missing). */
static void build_script(peer *p)
{
    p->n_frames = 0;
    p->next_frame = 0;
    ctl_species sp = { .name = "oak",
                       .url = "/assets/0123456789abcdef.gasset",
                       .hash = "0123456789abcdef",
                       .n_modes = N_MODES };
    ctl_instance inst[N_TREES] = { { 0, { 0, 0, 0 }, 0, 1 },
                                   { 0, { 5, 0, 0 }, 1, 1 },
                                   { 0, { 0, 5, 0 }, 2, 1 } };
    ctl_msg w = { .type = CTL_WELCOME };
    w.u.welcome = (ctl_welcome){ .protocol = WIRE_PROTOCOL_VERSION,
                                 .client_id = 7,
                                 .role = p->role,
                                 .tick_hz = 60,
                                 .snapshot_hz = 30,
                                 .server_us = 1,
                                 .tick = 1,
                                 .n_species = 1,
                                 .species = &sp,
                                 .n_instances = N_TREES,
                                 .instances = inst };
    add_text(p, &w);
    wire_scene scene = { .n_trees = N_TREES, .n_species = 1 };
    scene.n_modes[0] = N_MODES;
    uint8_t species[N_TREES] = { 0 }, nm[N_TREES] = { N_MODES, N_MODES, N_MODES };
    scene.species = species;
    for (int m = 0; m < N_MODES; m++) {
        scene.step[0][m] = 1e-3f;
    }
    int16_t q[4][N_TREES * N_MODES];
    for (int k = 0; k < 4; k++) {
        for (int i = 0; i < N_TREES * N_MODES; i++) {
            q[k][i] = (int16_t)(100 * k + i);
        }
    }
    gale_err err = { 0 };
    for (int seq = 1; seq <= 4; seq++) {
        wire_state cur = { N_TREES, N_MODES, nm, q[seq - 1] };
        wire_state prev = { N_TREES, N_MODES, nm, q[seq >= 2 ? seq - 2 : 0] };
        wire_header h = { .tick = (uint32_t)seq * 2,
                          .server_time_us = CLOCK_OFFSET_US + (uint64_t)seq * 33333 };
        uint8_t *buf = p->frames[p->n_frames] + LWS_PRE;
        size_t len = 0;
        int rc = seq == 1 ? wire_encode_keyframe(&h, 1, &scene, &cur, buf, 4096, &len, &err)
                          : wire_encode_delta(&h, (uint32_t)seq, &scene, &cur, &prev, NULL, buf,
                                              4096, &len, &err);
        CHECK(rc == 0);
        if (seq == 3) {
            continue; /* encoded (so seq 4 is a delta on it) but never sent: a gap */
        }
        p->frame_len[p->n_frames] = len;
        p->frame_binary[p->n_frames++] = true;
        if (seq == 1) {
            /* garbage after the keyframe, then a truncated copy of the next delta */
            uint8_t *g = p->frames[p->n_frames] + LWS_PRE;
            memcpy(g, "GALE\x01\x00\x07\x00garbage-garbage", 23);
            p->frame_len[p->n_frames] = 23;
            p->frame_binary[p->n_frames++] = true;
        }
        if (seq == 2) {
            /* the same delta cut short: must not be applied (the next delta is seq 4) */
            memcpy(p->frames[p->n_frames] + LWS_PRE, buf, len / 2);
            p->frame_len[p->n_frames] = len / 2;
            p->frame_binary[p->n_frames++] = true;
        }
    }
}

static int peer_http(peer *p, struct lws *wsi, const char *uri)
{
    uint8_t hdr[LWS_PRE + 512], *start = hdr + LWS_PRE, *pp = start, *end = hdr + sizeof hdr;
    if (strcmp(uri, "/assets/0123456789abcdef.gasset") != 0) {
        lws_return_http_status(wsi, HTTP_STATUS_NOT_FOUND, NULL);
        return lws_http_transaction_completed(wsi) ? -1 : 0;
    }
    if (lws_add_http_common_headers(wsi, HTTP_STATUS_OK, "application/octet-stream", ASSET_BYTES,
                                    &pp, end) ||
        lws_finalize_write_http_header(wsi, start, &pp, end)) {
        return 1;
    }
    p->http_body = asset_bytes;
    p->http_len = ASSET_BYTES;
    p->http_off = 0;
    lws_callback_on_writable(wsi);
    return 0;
}

static int peer_cb(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                   size_t len)
{
    peer *p = lws_context_user(lws_get_context(wsi));
    switch (reason) {
    case LWS_CALLBACK_HTTP:
        return peer_http(p, wsi, (const char *)in);
    case LWS_CALLBACK_HTTP_WRITEABLE: {
        static uint8_t buf[LWS_PRE + 8192];
        size_t n = p->http_len - p->http_off;
        n = n > 8192 ? 8192 : n;
        bool last = p->http_off + n == p->http_len;
        memcpy(buf + LWS_PRE, p->http_body + p->http_off, n);
        if (lws_write(wsi, buf + LWS_PRE, n, last ? LWS_WRITE_HTTP_FINAL : LWS_WRITE_HTTP) !=
            (int)n) {
            return 1;
        }
        p->http_off += n;
        if (!last) {
            lws_callback_on_writable(wsi);
            return 0;
        }
        return lws_http_transaction_completed(wsi) ? -1 : 0;
    }
    case LWS_CALLBACK_ESTABLISHED:
        pthread_mutex_lock(&p->lock);
        p->connections++;
        pthread_mutex_unlock(&p->lock);
        p->n_frames = 0;
        return 0;
    case LWS_CALLBACK_RECEIVE: {
        ctl_msg m;
        gale_err err = { 0 };
        if (ctl_decode(in, len, 0, &m, NULL, &err) != 0) {
            fprintf(stderr, "peer: bad control message: %s\n", err.msg);
            return -1;
        }
        pthread_mutex_lock(&p->lock);
        if (m.type == CTL_HELLO) {
            p->hellos++;
            p->role = m.u.hello.role;
            snprintf(p->token, sizeof p->token, "%s", m.u.hello.token);
            build_script(p);
        } else if (m.type == CTL_PING) {
            p->pings++;
            p->pong_pending = true;
            p->pong_id = m.u.ping.id;
            p->ping_client_us = m.u.ping.client_us;
        } else if (m.type == CTL_WIND) {
            p->winds++;
            p->wind_speed = m.u.wind.has_speed ? m.u.wind.speed_ms : -1.0f;
            snprintf(p->wind_token, sizeof p->wind_token, "%s", m.u.wind.token);
        } else if (m.type == CTL_RESYNC) {
            p->resyncs++;
            p->resync_seq = (int)m.u.resync_seq;
        }
        pthread_mutex_unlock(&p->lock);
        ctl_msg_fini(&m);
        lws_callback_on_writable(wsi);
        return 0;
    }
    case LWS_CALLBACK_SERVER_WRITEABLE:
        if (p->pong_pending) {
            ctl_msg m = { .type = CTL_PONG };
            m.u.pong = (ctl_pong){ .id = p->pong_id,
                                   .client_us = p->ping_client_us,
                                   .server_us = (uint64_t)(mono_s() * 1e6) + CLOCK_OFFSET_US };
            uint8_t buf[LWS_PRE + 512];
            size_t n = 0;
            ctl_encode_into(&m, (char *)buf + LWS_PRE, 512, &n, NULL);
            p->pong_pending = false;
            if (lws_write(wsi, buf + LWS_PRE, n, LWS_WRITE_TEXT) < (int)n) {
                return -1;
            }
        } else if (p->next_frame < p->n_frames) {
            int i = p->next_frame++;
            if (lws_write(wsi, p->frames[i] + LWS_PRE, p->frame_len[i],
                          p->frame_binary[i] ? LWS_WRITE_BINARY : LWS_WRITE_TEXT) <
                (int)p->frame_len[i]) {
                return -1;
            }
        } else if (p->n_frames && p->close_after_script) {
            lws_close_reason(wsi, LWS_CLOSE_STATUS_GOINGAWAY, (unsigned char *)"bye", 3);
            return -1;
        }
        if (p->next_frame < p->n_frames || p->pong_pending ||
            (p->n_frames && p->close_after_script)) {
            lws_callback_on_writable(wsi);
        }
        return 0;
    default:
        return lws_callback_http_dummy(wsi, reason, user, in, len);
    }
}

static const struct lws_protocols peer_protocols[] = {
    { "gale", peer_cb, 0, 4096, 0, NULL, 0 },
    { NULL, NULL, 0, 0, 0, NULL, 0 },
};

static void *peer_main(void *arg)
{
    peer *p = arg;
    while (!p->stop) {
        lws_service(p->ctx, -1);
        usleep(300);
    }
    return NULL;
}

static int peer_start(peer *p, int port)
{
    struct lws_context_creation_info info;
    memset(&info, 0, sizeof info);
    info.port = port;
    info.iface = "127.0.0.1";
    info.protocols = peer_protocols;
    info.user = p;
    info.options = LWS_SERVER_OPTION_DISABLE_IPV6;
    p->stop = 0;
    p->ctx = lws_create_context(&info);
    if (!p->ctx) {
        return -1;
    }
    struct lws_vhost *vh = lws_get_vhost_by_name(p->ctx, "default");
    p->port = vh ? lws_get_vhost_listen_port(vh) : port;
    return pthread_create(&p->thread, NULL, peer_main, p);
}

static void peer_stop(peer *p)
{
    p->stop = 1;
    pthread_join(p->thread, NULL);
    lws_context_destroy(p->ctx);
    p->ctx = NULL;
}

/* ---- client side -------------------------------------------------------------------- */

typedef struct seen {
    int welcomes, lost, keyframes, deltas;
    uint32_t n_trees, n_species;
    float q_last[N_TREES * N_MODES];
    uint32_t last_seq;
    char species_url[CTL_MAX_URL];
} seen;

static void on_welcome(void *user, const ctl_welcome *w)
{
    seen *s = user;
    s->welcomes++;
    s->n_trees = w->n_instances;
    s->n_species = w->n_species;
    snprintf(s->species_url, sizeof s->species_url, "%s", w->species[0].url);
}

static void on_frame(void *user, const wire_frame *f, const wire_decoder *dec, double recv_s)
{
    seen *s = user;
    (void)recv_s;
    if (f->hdr.type == WIRE_MSG_KEYFRAME) {
        s->keyframes++;
    } else if (f->hdr.type == WIRE_MSG_DELTA) {
        s->deltas++;
    }
    s->last_seq = f->seq;
    for (uint32_t t = 0; t < N_TREES; t++) {
        wire_decoder_q(dec, t, s->q_last + t * N_MODES, N_MODES);
    }
}

static void on_lost(void *user, int code, const char *why)
{
    seen *s = user;
    (void)code;
    (void)why;
    s->lost++;
}

/* Polls the client until cond holds or timeout_s passes. */
#define POLL_UNTIL(n, cond, timeout_s)           \
    do {                                         \
        double until_ = mono_s() + (timeout_s); \
        while (!(cond) && mono_s() < until_) {  \
            cli_net_poll((n));                       \
            usleep(1000);                        \
        }                                        \
    } while (0)

static peer P;

static void test_session(void)
{
    seen s = { 0 };
    gale_err err = { 0 };
    char url[64];
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", P.port);
    cli_net *n = cli_net_create(&(cli_net_desc){ .url = url,
                                     .role = CTL_ROLE_KIOSK,
                                     .token = "t0k3n",
                                     .backoff_min_s = 0.05,
                                     .backoff_max_s = 0.4,
                                     .ping_interval_s = 0.05 },
                        &(cli_net_handler){ &s, on_welcome, on_frame, on_lost, NULL }, &err);
    CHECK(n != NULL);
    if (!n) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    POLL_UNTIL(n,
               s.welcomes == 1 && cli_net_get_stats(n).frames_gap >= 1 && P.resyncs >= 1 &&
                   jitter_clock_rtt(cli_net_clock(n)) >= 0.0,
               10.0);
    cli_net_stats st = cli_net_get_stats(n);
    pthread_mutex_lock(&P.lock);
    CHECK(P.hellos == 1 && P.role == CTL_ROLE_KIOSK);
    CHECK(strcmp(P.token, "t0k3n") == 0);
    CHECK(P.resyncs >= 1 && P.resync_seq == 2); /* the last seq the client holds */
    CHECK(P.pings >= 1);
    pthread_mutex_unlock(&P.lock);
    CHECK(s.welcomes == 1 && s.n_trees == N_TREES && s.n_species == 1);
    CHECK(st.state == CLI_NET_LIVE);
    CHECK(s.keyframes == 1 && s.deltas == 1);
    CHECK(st.frames_ok == 2);  /* keyframe, delta 2 */
    CHECK(st.frames_bad == 2); /* garbage, truncated */
    CHECK(st.frames_gap == 1); /* delta 4 without 3 */
    CHECK(s.last_seq == 2);
    /* the truncated delta changed nothing: q is snapshot 2's: (100 + i) × 1e-3 */
    for (int i = 0; i < N_TREES * N_MODES; i++) {
        CHECK_NEAR(s.q_last[i], (100 + i) * 1e-3, 1e-6);
    }
    /* clock: the peer runs 5 s ahead; error at most rtt/2 */
    double srv;
    CHECK(jitter_clock_server_time(cli_net_clock(n), 100.0, &srv));
    CHECK_NEAR(srv - 100.0, 5.0, jitter_clock_rtt(cli_net_clock(n)) * 0.5 + 1e-3);

    /* kiosk wind dial: the command reaches the server with the token */
    ctl_wind wind = { .has_speed = true, .speed_ms = 42.0f };
    snprintf(wind.token, sizeof wind.token, "t0k3n");
    CHECK(cli_net_send_wind(n, &wind, &err) == 0);
    POLL_UNTIL(n, P.winds >= 1, 5.0);
    pthread_mutex_lock(&P.lock);
    CHECK(P.winds == 1);
    CHECK_NEAR(P.wind_speed, 42.0, 0);
    CHECK(strcmp(P.wind_token, "t0k3n") == 0);
    pthread_mutex_unlock(&P.lock);
    wind.speed_ms = 1000.0f; /* out of range: refused before it is sent */
    CHECK(cli_net_send_wind(n, &wind, &err) != 0);

    /* HTTP on the same server while the WebSocket lives */
    uint8_t *body = NULL;
    size_t len = 0;
    CHECK(cli_net_fetch(n, s.species_url, 1 << 20, 5.0, &body, &len, &err) == 0);
    CHECK(len == ASSET_BYTES && body && memcmp(body, asset_bytes, len) == 0);
    free(body);
    CHECK(cli_net_fetch(n, "/assets/ffffffffffffffff.gasset", 1 << 20, 5.0, &body, &len, &err) ==
          GALE_E_IO);
    CHECK_STR_HAS(err.msg, "/assets/ffffffffffffffff.gasset: HTTP status 404");
    CHECK(cli_net_fetch(n, s.species_url, 1000, 5.0, &body, &len, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "body over 1000 bytes");
    CHECK(body == NULL);
    /* an asset must hash to the welcome's hash: the peer's bytes are not the ones
     * 0123456789abcdef names, so they are refused and none come back */
    body = asset_bytes;
    len = 1;
    CHECK(cli_net_fetch_asset(n, s.species_url, "0123456789abcdef", 1 << 20, 5.0, &body, &len,
                              &err) == GALE_E_CHECKSUM);
    CHECK(body == NULL && len == 0);
    CHECK_STR_HAS(err.msg, "/assets/0123456789abcdef.gasset: content hash ");
    CHECK_STR_HAS(err.msg, ", expected 0123456789abcdef (the welcome's): refused");
    char right[17];
    snprintf(right, sizeof right, "%016llx", (unsigned long long)hash64(asset_bytes, ASSET_BYTES));
    CHECK(cli_net_fetch_asset(n, s.species_url, right, 1 << 20, 5.0, &body, &len, &err) == 0);
    CHECK(len == ASSET_BYTES && body && memcmp(body, asset_bytes, len) == 0);
    free(body);
    /* and the WebSocket is still live after the fetches */
    POLL_UNTIL(n, 0, 0.1);
    CHECK(cli_net_get_stats(n).state == CLI_NET_LIVE);

    /* the peer closes: the client reconnects and gets a new welcome and keyframe */
    pthread_mutex_lock(&P.lock);
    P.close_after_script = true;
    pthread_mutex_unlock(&P.lock);
    POLL_UNTIL(n, 0, 0.2); /* a ping makes the peer writeable, which closes */
    POLL_UNTIL(n, s.lost >= 1, 5.0);
    CHECK(s.lost >= 1);
    pthread_mutex_lock(&P.lock);
    P.close_after_script = false;
    pthread_mutex_unlock(&P.lock);
    POLL_UNTIL(n, s.welcomes >= 2 && s.keyframes >= 2, 5.0);
    CHECK(s.welcomes >= 2 && s.keyframes >= 2);
    CHECK(cli_net_get_stats(n).connects >= 2);

    /* the server goes away: attempts fail with growing delays; it comes back on the
     * same port and the client resumes from its next keyframe */
    int port = P.port;
    peer_stop(&P);
    /* the delay each failed attempt sets: min 0.05 s doubling (x 0.8-1.2 spread), read
       with the attempt that set it (the network thread runs on while this one polls, so
       the time left to the next attempt says less); a constant delay fails by attempt 3 */
    for (uint32_t a = 1; a <= 3; a++) {
        POLL_UNTIL(n, cli_net_get_stats(n).attempt >= a, 10.0);
        cli_net_stats b = cli_net_get_stats(n);
        double want = 0.05 * (double)(1u << (b.attempt < 8 ? b.attempt - 1 : 7));
        if (want > 5.0) {
            want = 5.0;
        }
        fprintf(stderr, "  attempt %u: backoff %.3f s (%.3f-%.3f)\n", b.attempt,
                b.retry_delay_s, 0.8 * want, 1.2 * want);
        CHECK(b.attempt >= a);
        CHECK(b.retry_delay_s >= 0.8 * want - 1e-9 && b.retry_delay_s <= 1.2 * want + 1e-9);
    }
    st = cli_net_get_stats(n);
    CHECK(st.state == CLI_NET_BACKOFF || st.state == CLI_NET_CONNECTING);
    CHECK(st.attempt >= 3);
    CHECK(st.last_error[0] != '\0');
    int kf = s.keyframes;
    CHECK(peer_start(&P, port) == 0);
    POLL_UNTIL(n, s.keyframes > kf, 10.0);
    CHECK(s.keyframes > kf);
    CHECK(cli_net_get_stats(n).state == CLI_NET_LIVE && cli_net_get_stats(n).attempt == 0);
    cli_net_destroy(n);
}

/* A client whose frames take long (ASan, llvmpipe on a loaded machine) polls once a
 * frame: its hello must leave in the poll that sees the connection open, not wait a
 * frame, or the server's hello timeout (4009) closes it before the next. */
static void test_hello_slow_frames(void)
{
    seen s = { 0 };
    gale_err err = { 0 };
    char url[64];
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", P.port);
    pthread_mutex_lock(&P.lock);
    const int hellos0 = P.hellos;
    pthread_mutex_unlock(&P.lock);
    cli_net *n = cli_net_create(&(cli_net_desc){ .url = url, .role = CTL_ROLE_VIEWER },
                                &(cli_net_handler){ &s, on_welcome, on_frame, on_lost, NULL },
                                &err);
    CHECK(n != NULL);
    if (!n) {
        return;
    }
    /* polled until the connection opens (the poll that sees ESTABLISHED) */
#define OPENING(st) ((st) == CLI_NET_IDLE || (st) == CLI_NET_CONNECTING)
    for (int i = 0; i < 200 && OPENING(cli_net_get_stats(n).state); i++) {
        cli_net_poll(n);
        if (OPENING(cli_net_get_stats(n).state)) {
            usleep(20000);
        }
    }
    CHECK(!OPENING(cli_net_get_stats(n).state));
#undef OPENING
    /* the frame the client draws now: no poll for 0.5 s */
    usleep(500000);
    pthread_mutex_lock(&P.lock);
    CHECK(P.hellos == hellos0 + 1);
    pthread_mutex_unlock(&P.lock);
    cli_net_destroy(n);
}

static void test_bad_url(void)
{
    gale_err err = { 0 };
    CHECK(cli_net_create(&(cli_net_desc){ .url = "http://x:1" }, NULL, &err) == NULL);
    CHECK_STR_HAS(err.msg, "--url \"http://x:1\": expected ws://HOST:PORT");
    CHECK(cli_net_create(&(cli_net_desc){ .url = "ws://localhost" }, NULL, &err) == NULL);
    CHECK_STR_HAS(err.msg, "expected a port");
    CHECK(cli_net_create(&(cli_net_desc){ 0 }, NULL, &err) == NULL);
    CHECK_STR_HAS(err.msg, "--url: required");
    cli_net_destroy(NULL);
}

int main(void)
{
    for (int i = 0; i < ASSET_BYTES; i++) {
        asset_bytes[i] = (uint8_t)(i * 131 + (i >> 8));
    }
    pthread_mutex_init(&P.lock, NULL);
    lws_set_log_level(LLL_ERR, NULL);
    if (peer_start(&P, 0) != 0) {
        fprintf(stderr, "cannot start the loopback peer\n");
        return 1;
    }
    RUN(test_bad_url);
    RUN(test_session);
    RUN(test_hello_slow_frames);
    if (P.ctx) {
        peer_stop(&P);
    }
    return check_report();
}
