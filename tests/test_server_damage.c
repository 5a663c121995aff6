/* Storm damage on loopback (PROTOCOL.md "DAMAGE"): a client that watches from calm air
 * while a kiosk dials a gale, and one that joins after the damage, hold the same picture
 * of the broken forest (events against the whole state that follows a keyframe); a heal
 * gives both the intact forest. Trees are a hand-built two-element stem with one branch
 * and weak wood, so a 30 m/s wind breaks some of them. */
#include "check.h"
#include "server_wsraw.h"
#include "damage_table.h"
#include "damage_view.h"
#include "mono.h"
#include "srv.h"
#include "wire.h"

#include <pthread.h>

#ifndef N_TREES
#define N_TREES 40 /* test_server_damage_forest: 6000, more damaged trees than a DAMAGE holds */
#endif
#define N_MODES 6
#define AREA_M (N_TREES > 400 ? 200 : 40) /* half the side: room at 2 m spacing */

static float omega[N_MODES], gamma_[N_MODES], basis[N_MODES * 3], qstep[N_MODES];
static const uint8_t asset_bytes[] = "not a real asset";
static srv *S;
static pthread_t S_thread;
static scene SC;
static damage_table TB;

static int32_t parent[4] = { -1, 0, 1, 1 };
static float rest[12] = { 0, 0, 0, 0, 0, 1, 0, 0, 2, 1, 0, 1 };
static float radius[4] = { 0.2f, 0.15f, 0.1f, 0.05f };
static float phi[12], rot[12] = { 0, 0, 0, 0, 1e-3f, 0, 0, 0, 0, 0, 0, 0 };
static uint32_t leaf_node[4] = { 2, 2, 3, 3 };

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
             "{\"name\": \"test\", \"tick_hz\": 60, \"snapshot_hz\": 30,"
             " \"kiosk_token\": \"sesame\","
             " \"species\": [{\"name\": \"a\", \"file\": \"a.json\"}],"
             " \"forest\": [{\"species\": \"a\", \"count\": %d, \"area_min\": [-%d, -%d],"
             " \"area_max\": [%d, %d], \"min_spacing_m\": 2, \"seed\": 3}],"
             " \"wind\": {\"solver\": false, \"u10_ms\": 0, \"dir_deg\": 30}}",
             N_TREES, AREA_M, AREA_M, AREA_M, AREA_M);
    gale_err e;
    if (scene_parse(&SC, "test.json", cfg, strlen(cfg), NULL, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    asset a;
    memset(&a, 0, sizeof a);
    a.n_nodes = 4;
    a.parent = parent;
    a.rest = rest;
    a.radius = radius;
    a.n_modes = 1;
    a.phi = phi;
    a.phi_rot = rot;
    a.n_leaves = 4;
    a.leaf_node = leaf_node;
    damage_params p = damage_params_default();
    p.c_reg_nm_kg = 200;
    p.strength_sd = 0.5;
    if (damage_table_build(&a, 1e10, 0.0, &p, &TB, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    for (int m = 0; m < N_MODES; m++) {
        omega[m] = (float)(2 * M_PI * (0.4 + 0.37 * m));
        gamma_[m] = 0.2f * omega[m];
        basis[3 * m] = 0.02f / (float)(m + 1);
        basis[3 * m + 1] = 0.01f;
        qstep[m] = 1e-4f;
    }
    static srv_species sp;
    sp = (srv_species){ .modal = { .n_modes = N_MODES, .omega = omega, .gamma = gamma_,
                                   .wind_basis = basis, .height_m = 2, .n_leaves = 4,
                                   .damage = &TB },
                        .qstep = qstep,
                        .asset_bytes = asset_bytes,
                        .asset_len = sizeof asset_bytes - 1 };
    snprintf(sp.hash, sizeof sp.hash, "%016x", 0xabc0);
    S = srv_create(&(srv_desc){ .sc = &SC, .species = &sp, .port = -1, .iface = "127.0.0.1",
                                .quiet = 1, .keyframe_s = 1.0 },
                   &e);
    if (!S) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    return pthread_create(&S_thread, NULL, serve, NULL);
}

static int open_hello(wsraw *c, const char *role)
{
    if (wsraw_open(c, srv_port(S), 0)) {
        return -1;
    }
    char h[256];
    snprintf(h, sizeof h, "{\"type\": \"hello\", \"protocol\": %d, \"role\": \"%s\"%s}",
             WIRE_PROTOCOL_VERSION, role,
             strcmp(role, "kiosk") == 0 ? ", \"token\": \"sesame\"" : "");
    wsraw_text(c, h);
    uint8_t *m;
    size_t n;
    int op = wsraw_recv(c, &m, &n, 3000);
    free(m);
    return op == 1 ? 0 : -1;
}

/* Reads frames for ms milliseconds into v; returns the frames seen with DAMAGE or FOREST. */
static int read_damage(wsraw *c, wire_decoder *dec, damage_view *v, int ms)
{
    int frames = 0;
    uint64_t end = mono_us() + (uint64_t)ms * 1000u;
    while (mono_us() < end) {
        uint8_t *b = NULL;
        size_t n;
        int op = wsraw_recv(c, &b, &n, 500);
        if (op == 2) {
            wire_frame f;
            gale_err e;
            if (wire_decode(dec, b, n, &f, &e) == 0 &&
                (f.types & (1u << WIRE_MSG_DAMAGE | 1u << WIRE_MSG_FOREST))) {
                CHECK(damage_view_apply_frame(v, &f) == 0);
                frames++;
            }
        }
        free(b);
        if (op < 0 || op == 8) {
            break;
        }
    }
    return frames;
}

static int fallen(const damage_view *v)
{
    int n = 0;
    for (uint32_t t = 0; t < v->n_trees; t++) {
        n += v->tree[t].fallen != 0;
    }
    return n;
}

/* trees fallen or with leaves lost: each a DAMAGE event of the whole state or two */
static int damaged(const damage_view *v)
{
    int n = 0;
    for (uint32_t t = 0; t < v->n_trees; t++) {
        n += v->tree[t].fallen != 0 || v->tree[t].level < WIRE_DAMAGE_LEVELS;
    }
    return n;
}

static void test_watcher_and_late_joiner(void)
{
    wsraw watcher, kiosk, late;
    wire_decoder *d1 = wire_decoder_create(&(wire_decoder_desc){ N_TREES, N_MODES }, NULL);
    wire_decoder *d2 = wire_decoder_create(&(wire_decoder_desc){ N_TREES, N_MODES }, NULL);
    damage_view v1, v2, fresh;
    CHECK(damage_view_init(&v1, N_TREES, NULL) == 0 && damage_view_init(&v2, N_TREES, NULL) == 0 &&
          damage_view_init(&fresh, N_TREES, NULL) == 0);
    CHECK(open_hello(&watcher, "viewer") == 0);
    read_damage(&watcher, d1, &v1, 500);
    CHECK(fallen(&v1) == 0);
    CHECK(open_hello(&kiosk, "kiosk") == 0);
    wsraw_text(&kiosk, "{\"type\": \"wind\", \"token\": \"sesame\", \"speed_ms\": 30}");
    read_damage(&watcher, d1, &v1, 3000);
    /* calm again, so nothing more breaks while the late joiner comes in */
    wsraw_text(&kiosk, "{\"type\": \"wind\", \"token\": \"sesame\", \"speed_ms\": 0}");
    read_damage(&watcher, d1, &v1, 1500);
    CHECK(open_hello(&late, "viewer") == 0);
    int late_frames = read_damage(&late, d2, &v2, 1500);
    read_damage(&watcher, d1, &v1, 200);
    fprintf(stderr, "  after 30 m/s: %d of %d trees fallen, %d damaged, %u branches broken; "
                    "late joiner: %d frames with damage\n",
            fallen(&v1), N_TREES, damaged(&v1), v1.n_broken, late_frames);
    CHECK(fallen(&v1) > 0 && fallen(&v1) < N_TREES);
    /* the many trees' run: more trees damaged than one DAMAGE frame has events, so the
     * late joiner's picture is whole only by the FOREST */
    CHECK(N_TREES < 400 || damaged(&v1) > (int)WIRE_MAX_DAMAGE);
    CHECK(late_frames > 0);
    CHECK(damage_view_equal(&v1, &v2));
    /* heal: both get the whole, empty state */
    srv_heal(S);
    read_damage(&watcher, d1, &v1, 800);
    read_damage(&late, d2, &v2, 800);
    CHECK(damage_view_equal(&v1, &fresh));
    CHECK(damage_view_equal(&v2, &fresh));
    char *body = NULL;
    CHECK(wsraw_http_get(srv_port(S), "/metrics", &body) == 200 && body);
    if (body) {
        CHECK_STR_HAS(body, "gale_damage_heals_total 1");
        CHECK_STR_HAS(body, "gale_trees_uprooted_total");
        CHECK_STR_HAS(body, "gale_branches_broken_total");
        CHECK_STR_HAS(body, "gale_leaf_area_remaining_ratio");
    }
    free(body);
    wsraw_close(&watcher);
    wsraw_close(&kiosk);
    wsraw_close(&late);
    damage_view_fini(&v1);
    damage_view_fini(&v2);
    damage_view_fini(&fresh);
    wire_decoder_destroy(d1);
    wire_decoder_destroy(d2);
}

int main(void)
{
    if (start_server()) {
        fprintf(stderr, "cannot start the server\n");
        return 1;
    }
    RUN(test_watcher_and_late_joiner);
    srv_stop(S);
    pthread_join(S_thread, NULL);
    srv_destroy(S);
    scene_fini(&SC);
    damage_table_fini(&TB);
    return check_report();
}
