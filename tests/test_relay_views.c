/* Views through gale-relay (server/SERVER.md "Views through a relay"), live on loopback:
 * a real nats-server, gale-server --nats and a gale-relay, all started here, and raw
 * WebSocket clients. A client of the relay that sends a frustum view (in its hello) gets
 * only the trees in it, with the modes the server gives a direct client with the same
 * view (full inside lod_m, the server's few past it) and the same state at the same seqs;
 * when it turns its view (a `view` message) it decodes the new view's trees within
 * TURN_BOUND_S, again the same as the direct client's; it keeps its view through a
 * restart of gale-server. Palm scene of 60 trees. */
#include "check.h"
#include "hash.h"
#include "mono.h"
#include "relay_fixture.h"
#include "server_wsraw.h"
#include "wire.h"

#define TURN_BOUND_S 1.0 /* a turned view's trees decoded within this [s] */
#define RECS         600

/* A client: its socket, decoder and the states it decoded. */
typedef struct cli {
    wsraw ws;
    wire_decoder *dec;
    int bad, gaps, keys;
    uint32_t seqs[RECS];
    uint64_t sel[RECS];   /* hash of the per-tree mode counts */
    uint64_t state[RECS]; /* hash of the modes sent */
    int n_rec;
} cli;

/* The selection (n_modes of every tree) and the values sent, hashed. */
static uint64_t sel_hash(const wire_state *s)
{
    return hash64(s->n_modes, s->n_trees);
}

static uint64_t state_hash(const wire_state *s)
{
    uint64_t h = sel_hash(s);
    for (uint32_t t = 0; t < s->n_trees; t++) {
        h = hash64_update(h, s->q + (size_t)t * s->stride, sizeof(int16_t) * s->n_modes[t]);
    }
    return h;
}

static int cli_open(cli *c, int port, const char *view_json)
{
    memset(c, 0, sizeof *c);
    c->dec = wire_decoder_create(&(wire_decoder_desc){ 0 }, NULL);
    if (wsraw_open(&c->ws, port, 0)) {
        return -1;
    }
    char hello[512];
    snprintf(hello, sizeof hello, "{\"type\":\"hello\",\"protocol\":1,\"role\":\"viewer\"%s%s}",
             view_json ? ",\"view\":" : "", view_json ? view_json : "");
    wsraw_text(&c->ws, hello);
    for (int i = 0; i < 20; i++) {
        uint8_t *b;
        size_t n;
        int op = wsraw_recv(&c->ws, &b, &n, 3000);
        int welcome = op == 1 && strstr((char *)b, "\"welcome\"");
        free(b);
        if (welcome) {
            return 0;
        }
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
}

/* Takes what arrives within timeout_ms; 1 when a state frame decoded (recorded), else 0.
 * A gap asks for a keyframe as gale-client does. */
static int cli_step(cli *c, int timeout_ms)
{
    uint8_t *b;
    size_t n;
    int op = wsraw_recv(&c->ws, &b, &n, timeout_ms);
    if (op != 2) {
        free(b);
        return 0;
    }
    wire_frame f;
    gale_err e;
    int rc = wire_decode(c->dec, b, n, &f, &e);
    free(b);
    if (rc == GALE_E_STATE) {
        c->gaps++;
        wsraw_text(&c->ws, "{\"type\":\"resync\",\"seq\":0}");
        return 0;
    }
    if (rc) {
        fprintf(stderr, "  decode: %s\n", e.msg);
        c->bad++;
        return 0;
    }
    if (!(f.types & ((1u << WIRE_MSG_KEYFRAME) | (1u << WIRE_MSG_DELTA)))) {
        return 0;
    }
    c->keys += (f.types & (1u << WIRE_MSG_KEYFRAME)) != 0;
    wire_state s = wire_decoder_state(c->dec);
    int k = c->n_rec < RECS ? c->n_rec++ : RECS - 1;
    c->seqs[k] = f.seq;
    c->sel[k] = sel_hash(&s);
    c->state[k] = state_hash(&s);
    return 1;
}

/* Reads both clients in turn for secs. */
static void read_both(cli *a, cli *b, double secs)
{
    double until = mono_s() + secs;
    while (mono_s() < until) {
        cli_step(a, 5);
        cli_step(b, 5);
    }
}

/* Seqs both decoded with the same selection since a's record from_a and b's from_b, and
 * of those how many differ in state. */
static int compare(const cli *a, int from_a, const cli *b, int from_b, int *differ)
{
    int common = 0;
    *differ = 0;
    for (int i = from_a; i < a->n_rec; i++) {
        for (int j = from_b; j < b->n_rec; j++) {
            if (a->seqs[i] == b->seqs[j] && a->sel[i] == b->sel[j]) {
                common++;
                *differ += a->state[i] != b->state[j];
            }
        }
    }
    return common;
}

/* Trees sent, and of those sent with fewer modes than the palm's 8 (LOD). */
static void count_sent(const cli *c, uint32_t *sent, uint32_t *lod, uint32_t *n_trees)
{
    wire_state s = wire_decoder_state(c->dec);
    *sent = *lod = 0;
    *n_trees = s.n_trees;
    for (uint32_t t = 0; t < s.n_trees; t++) {
        *sent += s.n_modes[t] > 0;
        *lod += s.n_modes[t] > 0 && s.n_modes[t] < 8;
    }
}

static proc nats, server, relay_a;

/* Looking north-east from the south-west corner, and then back from the north-east one:
 * each sees part of the forest, some trees past lod_m. */
#define VIEW_SW                                                                   \
    "{\"kind\":\"frustum\",\"eye\":[-70,-70,2],\"dir\":[1,0.6,0],\"fov_deg\":30," \
    "\"far_m\":150,\"lod_m\":60}"
#define VIEW_NE                                                                   \
    "{\"kind\":\"frustum\",\"eye\":[70,70,2],\"dir\":[-0.6,-1,0],\"fov_deg\":30," \
    "\"far_m\":150,\"lod_m\":60}"

static void test_view_and_turn(void)
{
    cli d, r;
    CHECK(cli_open(&d, server.port, VIEW_SW) == 0);
    CHECK(cli_open(&r, relay_a.port, VIEW_SW) == 0);
    read_both(&d, &r, 3.0);
    int differ = 0;
    int common = compare(&d, 0, &r, 0, &differ);
    uint32_t sent_d, lod_d, sent_r, lod_r, n_trees;
    count_sent(&d, &sent_d, &lod_d, &n_trees);
    count_sent(&r, &sent_r, &lod_r, &n_trees);
    fprintf(stderr,
            "  view: the relay's client has %u of %u trees (%u past lod_m), the server's %u "
            "(%u); %d seqs decoded by both, %d differ\n",
            sent_r, n_trees, lod_r, sent_d, lod_d, common, differ);
    CHECK(n_trees == 60 && sent_r > 0 && sent_r < n_trees && lod_r > 0 && lod_r < sent_r);
    CHECK(d.n_rec > 0 && r.n_rec > 0 && d.sel[d.n_rec - 1] == r.sel[r.n_rec - 1]);
    CHECK(common >= 30 && differ == 0);
    const uint64_t sel_sw = r.sel[r.n_rec - 1];
    uint8_t modes_sw[64] = { 0 };
    wire_state st = wire_decoder_state(r.dec);
    memcpy(modes_sw, st.n_modes, st.n_trees < 64 ? st.n_trees : 64);

    /* turning: the new view's trees within TURN_BOUND_S */
    const int from_d = d.n_rec, from_r = r.n_rec;
    wsraw_text(&d.ws, "{\"type\":\"view\",\"view\":" VIEW_NE "}");
    wsraw_text(&r.ws, "{\"type\":\"view\",\"view\":" VIEW_NE "}");
    const double t0 = mono_s();
    double dt = -1.0;
    while (mono_s() - t0 < 3.0 && dt < 0) {
        if (cli_step(&r, 5) && r.sel[r.n_rec - 1] != sel_sw) {
            dt = mono_s() - t0;
        }
        cli_step(&d, 0);
    }
    read_both(&d, &r, 2.0);
    const uint32_t old_sent = sent_r;
    count_sent(&d, &sent_d, &lod_d, &n_trees);
    count_sent(&r, &sent_r, &lod_r, &n_trees);
    common = compare(&d, from_d, &r, from_r, &differ);
    st = wire_decoder_state(r.dec);
    uint32_t gained = 0;
    for (uint32_t t = 0; t < st.n_trees && t < 64; t++) {
        gained += st.n_modes[t] > 0 && !modes_sw[t];
    }
    fprintf(stderr,
            "  turned: the new view's %u trees (%u past lod_m, %u not in the old view of %u) "
            "decoded %.3f s after the view was sent; the server's client has %u (%u); %d seqs "
            "decoded by both since, %d differ\n",
            sent_r, lod_r, gained, old_sent, dt, sent_d, lod_d, common, differ);
    CHECK(dt >= 0 && dt <= TURN_BOUND_S);
    CHECK(r.sel[r.n_rec - 1] != sel_sw && d.sel[d.n_rec - 1] == r.sel[r.n_rec - 1]);
    CHECK(sent_r > 0 && sent_r < n_trees && gained > 0);
    CHECK(common >= 20 && differ == 0);
    CHECK(d.bad == 0 && r.bad == 0);
    cli_fini(&d);
    cli_fini(&r);
}

/* A restarted gale-server: the relay's client keeps its view (the relay's) and is back on
 * a keyframe of it within 2 s of the new server listening, without reconnecting. */
static void test_server_restart_keeps_view(void)
{
    cli r;
    CHECK(cli_open(&r, relay_a.port, VIEW_SW) == 0);
    double until = mono_s() + 3.0;
    while (r.n_rec < 10 && mono_s() < until) {
        cli_step(&r, 20);
    }
    CHECK(r.n_rec >= 10);
    const uint64_t sel = r.n_rec ? r.sel[r.n_rec - 1] : 0;
    end(&server, SIGTERM);
    until = mono_s() + 0.3;
    while (mono_s() < until) {
        cli_step(&r, 20); /* what was in flight before the kill */
    }
    CHECK(start_server(&server) == 0);
    const double t0 = mono_s();
    const int keys = r.keys;
    while (r.keys == keys && mono_s() - t0 < 4.0) {
        cli_step(&r, 20);
    }
    const double dt = mono_s() - t0;
    fprintf(stderr,
            "  gale-server restarted: the relay's view client on a keyframe %.3f s after it "
            "listened, %s view\n",
            dt, r.sel[r.n_rec - 1] == sel ? "the same" : "another");
    CHECK(r.keys > keys && dt <= 2.0);
    CHECK(r.sel[r.n_rec - 1] == sel && r.bad == 0);
    cli_fini(&r);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    fx_prefix = "relay_views";
    FILE *f = fopen("relay_views_scene.json", "w");
    if (f) {
        fprintf(f,
                "{\"name\": \"relay-views\", \"species\": [{\"name\": \"palm\", \"file\": "
                "\"%s/configs/species/palm.json\", \"modes\": 8}],"
                " \"forest\": [{\"species\": \"palm\", \"count\": 60, \"area_min\": [-80, -80],"
                " \"area_max\": [80, 80], \"min_spacing_m\": 4}],"
                " \"wind\": {\"solver\": false, \"u10_ms\": 12}}",
                GALE_SOURCE_DIR);
        fclose(f);
    }
    f = fopen("relay_views_token", "w");
    if (f) {
        fputs("relay-views-token\n", f);
        fclose(f);
    }
    int nats_rc = start_nats_fresh(&nats);
    snprintf(nats_url, sizeof nats_url, "nats://127.0.0.1:%d", nats_port);
    if (nats_rc || start_server(&server) || start_relay(&relay_a)) {
        fprintf(stderr, "test_relay_views: could not start nats-server, gale-server and a "
                        "relay\n");
        end(&relay_a, SIGKILL);
        end(&server, SIGKILL);
        end(&nats, SIGKILL);
        return 1;
    }
    RUN(test_view_and_turn);
    RUN(test_server_restart_keeps_view);
    end(&relay_a, SIGTERM);
    end(&server, SIGTERM);
    end(&nats, SIGTERM);
    return check_report();
}
