/* The welcome on a large scene (server/SERVER.md "The welcome"): a loopback server of
 * 12,000 trees and a house, and clients that say hello at once (viewers, load clients and
 * a kiosk through its token) with a hello deadline of 2 s. Each gets its welcome in time;
 * the scene part (everything after the head's tick) is the same bytes for all, encoded
 * once; each head is its own (client_id, role); every welcome is exactly what the encoder
 * makes of the whole message, and a relayed connection's (srv_remote_control) is the same
 * text in one piece. After a scene change the next clients get the new scene, encoded once
 * more. */
#include "check.h"
#include "server_wsraw.h"
#include "ctl.h"
#include "srv.h"
#include "srv_int.h"
#include "wire.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define N_TREES 12000
#define N_MODES 6
#define N_CLIENTS 8
#define HELLO_TIMEOUT_MS 2000

static float omega[2][N_MODES], gamma_[2][N_MODES], basis[2][N_MODES * 3], qstep[2][N_MODES];
static srv *S;
static pthread_t S_thread;
static scene SC;

static void *serve(void *arg)
{
    (void)arg;
    srv_run(S);
    return NULL;
}

static int start_server(void)
{
    char cfg[1024];
    snprintf(cfg, sizeof cfg,
             "{\"name\": \"welcome\", \"tick_hz\": 60, \"snapshot_hz\": 30,"
             " \"kiosk_token\": \"sesame\","
             " \"species\": [{\"name\": \"a\", \"file\": \"a.json\"}, {\"name\": \"b\", \"file\": \"b.json\"}],"
             " \"obstacles\": [{\"min\": [-30, -30, 0], \"max\": [-18, -20, 7]}],"
             " \"forest\": [{\"species\": \"a\", \"count\": %d, \"area_min\": [-150, -150],"
             " \"area_max\": [150, 150], \"min_spacing_m\": 1.5, \"seed\": 3},"
             " {\"species\": \"b\", \"count\": %d, \"area_min\": [-150, -150],"
             " \"area_max\": [150, 150], \"min_spacing_m\": 1.5, \"seed\": 4}],"
             " \"wind\": {\"solver\": false, \"u10_ms\": 14, \"dir_deg\": 30}}",
             N_TREES / 2, N_TREES / 2);
    gale_err e;
    if (scene_parse(&SC, "welcome.json", cfg, strlen(cfg), NULL, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    static srv_species sp[2];
    for (int s = 0; s < 2; s++) {
        for (int m = 0; m < N_MODES; m++) {
            omega[s][m] = (float)(2 * M_PI * (0.4 + 0.37 * m + 0.1 * s));
            gamma_[s][m] = 0.1f * omega[s][m];
            basis[s][3 * m] = 0.02f / (float)(m + 1);
            basis[s][3 * m + 1] = 0.01f * (float)(s + 1);
            qstep[s][m] = 1e-4f;
        }
        sp[s] = (srv_species){ .modal = { .n_modes = N_MODES, .omega = omega[s], .gamma = gamma_[s],
                                          .wind_basis = basis[s], .height_m = 12, .n_leaves = 400 },
                               .qstep = qstep[s] };
        snprintf(sp[s].hash, sizeof sp[s].hash, "%016x", 0xabc0 + s);
    }
    S = srv_create(&(srv_desc){ .sc = &SC, .species = sp, .port = -1, .iface = "127.0.0.1",
                                .hello_timeout_ms = HELLO_TIMEOUT_MS, .quiet = 1 },
                   &e);
    if (!S) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    return pthread_create(&S_thread, NULL, serve, NULL);
}

static void stop_server(void)
{
    srv_stop(S);
    pthread_join(S_thread, NULL);
    srv_destroy(S);
    scene_fini(&SC);
}

/* One client's welcome as received. */
typedef struct got {
    uint8_t *text; /* owned, NUL-terminated */
    size_t len;
    ctl_msg m;     /* decoded */
    bool ok;       /* a welcome that decoded */
} got;

static unsigned long long builds(void)
{
    pthread_mutex_lock(&S->ctl_lock);
    unsigned long long n = S->wbuilds;
    pthread_mutex_unlock(&S->ctl_lock);
    return n;
}

/* The scene part of an encoded welcome: from its species on. */
static const char *scene_part(const got *g)
{
    const char *p = strstr((const char *)g->text, ",\"species\":");
    return p ? p : "";
}

/* Client k's role: viewers, load clients and one kiosk, in turn. */
static const char *role_of(int k)
{
    return k == 3 ? "kiosk" : k % 2 ? "load" : "viewer";
}

/* n clients open, all send their hellos, then each reads its welcome (the server answers
 * them side by side). Any close (a 4009 for a hello not answered in time) fails. */
static void welcome_all(wsraw *c, got *g, int n)
{
    for (int k = 0; k < n; k++) {
        CHECK(wsraw_open(&c[k], srv_port(S), 0) == 0);
    }
    const uint64_t t0 = mono_us();
    for (int k = 0; k < n; k++) {
        char h[256];
        snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"%s\"%s}",
                 WIRE_PROTOCOL_VERSION, role_of(k),
                 !strcmp(role_of(k), "kiosk") ? ", \"token\": \"sesame\"" : "");
        CHECK(wsraw_text(&c[k], h) == 0);
    }
    for (int k = 0; k < n; k++) {
        memset(&g[k], 0, sizeof g[k]);
        int op;
        /* state frames may follow the welcome: the welcome comes first */
        op = wsraw_recv(&c[k], &g[k].text, &g[k].len, 10000);
        CHECK(op == 1);
        if (op != 1) {
            fprintf(stderr, "client %d: opcode %d, close %d (%s)\n", k, op, c[k].close_code,
                    c[k].close_reason);
            continue;
        }
        gale_err e;
        int code = 0;
        g[k].ok = !ctl_decode((const char *)g[k].text, g[k].len, CTL_MAX_SERVER_BYTES, &g[k].m,
                              &code, &e) &&
                  g[k].m.type == CTL_WELCOME;
        CHECK(g[k].ok);
        if (!g[k].ok) {
            fprintf(stderr, "client %d: %.200s\n", k, (const char *)g[k].text);
        }
    }
    fprintf(stderr, "  %d welcomes of %zu bytes in %.1f ms\n", n, g[0].len,
            (double)(mono_us() - t0) * 1e-3);
}

static void got_fini(got *g, int n)
{
    for (int k = 0; k < n; k++) {
        free(g[k].text);
        ctl_msg_fini(&g[k].m);
    }
}

/* Every welcome decodes to its own head and the scene, and is what the encoder makes of
 * it; the scene parts are one text. */
static void check_welcomes(const got *g, int n, float tree0_x)
{
    for (int k = 0; k < n; k++) {
        if (!g[k].ok) {
            continue;
        }
        const ctl_welcome *w = &g[k].m.u.welcome;
        CHECK(w->n_instances == N_TREES);
        CHECK(w->n_species == 2);
        CHECK(w->n_obstacles == 1);
        CHECK(!strcmp(ctl_role_name(w->role), role_of(k)));
        CHECK(w->n_instances == N_TREES && w->instances[0].pos[0] == tree0_x);
        for (int j = 0; j < k; j++) {
            CHECK(!g[j].ok || g[j].m.u.welcome.client_id != w->client_id);
        }
        /* head + shared part == the whole message's encoding */
        char *again = NULL;
        size_t again_len = 0;
        CHECK(ctl_encode(&g[k].m, &again, &again_len, NULL) == 0);
        CHECK(again && again_len == g[k].len && !memcmp(again, g[k].text, g[k].len));
        free(again);
        CHECK(!strcmp(scene_part(&g[k]), scene_part(&g[0])));
    }
}

static wsraw first_c[N_CLIENTS];
static got first_g[N_CLIENTS];
static float tree0_x;

static void test_many_at_once(void)
{
    pthread_mutex_lock(&S->ctl_lock);
    tree0_x = S->winst[0].pos[0];
    pthread_mutex_unlock(&S->ctl_lock);
    welcome_all(first_c, first_g, N_CLIENTS);
    check_welcomes(first_g, N_CLIENTS, tree0_x);
    CHECK(strlen(scene_part(&first_g[0])) > 30 * N_TREES); /* the instances are in it */
    CHECK(builds() == 1); /* built at start, shared by all */
    /* the connections stay served: state frames follow */
    for (int k = 0; k < N_CLIENTS; k++) {
        uint8_t *m = NULL;
        size_t n = 0;
        CHECK(wsraw_recv(&first_c[k], &m, &n, 5000) == 2);
        free(m);
    }
}

/* A relayed connection's welcome (shared_ok false) is the same text in one piece. */
static void test_relayed(void)
{
    char hello[128], *reply = NULL, why[256] = "";
    size_t len = 0;
    snprintf(hello, sizeof hello, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"viewer\"}",
             WIRE_PROTOCOL_VERSION);
    net_peer p = { .id = 777, .addr = "relay" };
    CHECK(srv_remote_control(S, &p, hello, strlen(hello), &reply, &len, why, sizeof why) == 0);
    CHECK(p.reply_shared == NULL);
    CHECK(reply && len == strlen(reply));
    got g = { .text = (uint8_t *)reply, .len = len };
    CHECK(reply && !strcmp(scene_part(&g), scene_part(&first_g[0])));
    CHECK(reply && strstr(reply, "\"client_id\":777,"));
    srv_remote_closed(S, &p);
    free(reply);
    CHECK(builds() == 1);
}

/* A scene change: the next hellos get the new scene part, built once for them all; the
 * clients welcomed before keep their connections. */
static void test_scene_change(void)
{
    pthread_mutex_lock(&S->ctl_lock);
    S->winst[0].pos[0] += 1.5f;
    const float moved = S->winst[0].pos[0];
    srv_welcome_stale(S);
    pthread_mutex_unlock(&S->ctl_lock);
    wsraw c[N_CLIENTS];
    got g[N_CLIENTS];
    welcome_all(c, g, N_CLIENTS);
    check_welcomes(g, N_CLIENTS, moved);
    CHECK(g[0].ok && strcmp(scene_part(&g[0]), scene_part(&first_g[0])) != 0);
    CHECK(builds() == 2);
    for (int k = 0; k < N_CLIENTS; k++) {
        uint8_t *m = NULL;
        size_t n = 0;
        CHECK(wsraw_recv(&first_c[k], &m, &n, 5000) == 2);
        free(m);
        wsraw_close(&c[k]);
    }
    got_fini(g, N_CLIENTS);
}

int main(void)
{
    if (start_server()) {
        fprintf(stderr, "cannot start the server\n");
        return 1;
    }
    RUN(test_many_at_once);
    RUN(test_relayed);
    RUN(test_scene_change);
    net_metrics *nm = srv_metrics(S);
    CHECK(atomic_load(&nm->hello_timeouts) == 0);
    for (int k = 0; k < N_CLIENTS; k++) {
        wsraw_close(&first_c[k]);
    }
    got_fini(first_g, N_CLIENTS);
    stop_server();
    return check_report();
}
