/* Every test vector of protocol/PROTOCOL.md ("Test vectors"), read from the spec file
 * itself (tests/spec_vectors.h): each binary frame is decoded with gale's decoder and its
 * values checked, and the inputs the spec states encode to exactly its bytes; each control
 * message decodes to the stated values and encodes back to exactly its text. A vector in
 * the file that this test does not know, one it knows that the file lacks, or a byte that
 * differs fails. The Saffir-Simpson and Beaufort tables of "WEATHER" are checked against
 * protocol/wind_scale.c the same way. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "ctl.h"
#include "spec_vectors.h"
#include "wind_scale.h"
#include "wire.h"

static spec_file spec;
static const char *spec_path; /* the file read */
static uint8_t buf[4096];

/* The vector's bytes, or (failing) an empty one. */
static const spec_vector *vec(const char *name)
{
    static const spec_vector none;
    const spec_vector *v = spec_find(&spec, name);
    if (!v) {
        fprintf(stderr, "  vector %s: missing from %s\n", name, spec_path);
    }
    CHECK(v != NULL);
    return v ? v : &none;
}

/* got[n] equals the vector's bytes; if not, prints got as the spec's hex dump. */
static void same_bytes(const spec_vector *v, const uint8_t *got, size_t n)
{
    int same = n == v->len && memcmp(got, v->bytes, n) == 0;
    CHECK(same);
    if (!same) {
        fprintf(stderr, "  vector %s (line %d): %zu bytes in the spec, encoded %zu:\n", v->name,
                v->line, v->len, n);
        for (size_t i = 0; i < n; i++) {
            fprintf(stderr, "%s%02zx:", i ? "\n" : "", i);
            for (size_t k = i; k < n && k < i + 16; k++) {
                fprintf(stderr, " %02x", got[k]);
            }
            i += 15;
        }
        fprintf(stderr, "\n");
    }
}

/* ---- the scene of the state vectors --------------------------------------------------- */

static const uint8_t species3[3] = { 0, 1, 0 };

static wire_scene scene3(void)
{
    wire_scene sc = { .n_trees = 3, .n_species = 2, .species = species3 };
    sc.n_modes[0] = 2;
    sc.n_modes[1] = 1;
    sc.step[0][0] = 0.001f;
    sc.step[0][1] = 0.002f;
    sc.step[1][0] = 0.0005f;
    return sc;
}

static uint8_t nm3[3] = { 2, 0, 1 }; /* tree 1 out of view, tree 2 at 1 of its 2 modes */
static int16_t q5[6] = { 3, -2, 0, 0, 7, 0 }, q6[6] = { 4, -2, 0, 0, 7, 0 };

static wire_decoder *decoder(void)
{
    wire_decoder *d = wire_decoder_create(&(wire_decoder_desc){ 8, 8 }, NULL);
    CHECK(d != NULL);
    return d;
}

/* A decoder that decoded the KEYFRAME vector. */
static wire_decoder *keyed(void)
{
    wire_decoder *d = decoder();
    wire_frame f;
    const spec_vector *k = vec("KEYFRAME");
    CHECK(d && wire_decode(d, k->bytes, k->len, &f, NULL) == 0);
    return d;
}

static void check_keyframe_state(const wire_decoder *d)
{
    float q[8];
    CHECK(wire_decoder_seq(d) == 5);
    CHECK(wire_decoder_q(d, 0, q, 8) == 2 && q[0] == 3 * 0.001f && q[1] == -2 * 0.002f);
    CHECK(wire_decoder_q(d, 1, q, 8) == 0);
    CHECK(wire_decoder_q(d, 2, q, 8) == 1 && q[0] == 7 * 0.001f);
    const wire_scene *sc = wire_decoder_scene(d);
    CHECK(sc->n_trees == 3 && sc->n_species == 2 && sc->n_modes[0] == 2 && sc->n_modes[1] == 1);
    CHECK(sc->step[0][0] == 0.001f && sc->step[0][1] == 0.002f && sc->step[1][0] == 0.0005f);
    CHECK(sc->species[0] == 0 && sc->species[1] == 1 && sc->species[2] == 0);
}

static void v_keyframe(const spec_vector *v)
{
    wire_scene sc = scene3();
    wire_state s5 = { 3, 2, nm3, q5 };
    size_t len = 0;
    CHECK(wire_encode_keyframe(&(wire_header){ .tick = 120, .server_time_us = 2000000 }, 5, &sc,
                               &s5, buf, sizeof buf, &len, NULL) == 0);
    same_bytes(v, buf, len);
    wire_decoder *d = decoder();
    wire_frame f;
    CHECK(d && wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == 1u << WIRE_MSG_KEYFRAME && f.hdr.tick == 120 && f.seq == 5);
    CHECK(f.hdr.server_time_us == 2000000);
    check_keyframe_state(d);
    wire_decoder_destroy(d);
}

static void v_delta(const spec_vector *v)
{
    wire_scene sc = scene3();
    wire_state s5 = { 3, 2, nm3, q5 }, s6 = { 3, 2, nm3, q6 };
    size_t len = 0;
    CHECK(wire_encode_delta(&(wire_header){ .tick = 122, .server_time_us = 2033333 }, 6, &sc, &s6,
                            &s5, NULL, buf, sizeof buf, &len, NULL) == 0);
    same_bytes(v, buf, len);
    wire_decoder *d = keyed();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == 1u << WIRE_MSG_DELTA && f.seq == 6 && f.hdr.tick == 122);
    CHECK(f.hdr.server_time_us == 2033333);
    wire_state st = wire_decoder_state(d);
    CHECK(st.q[0] == 4 && st.q[1] == -2 && st.q[st.stride * 2] == 7 && st.n_modes[1] == 0);
    wire_decoder_destroy(d);
}

static const wire_header h123 = { .tick = 123, .server_time_us = 2050000 };

static void check_leaves(const wire_frame *f)
{
    CHECK(f->n_leaves == 1 && f->leaves[0].instance == 2 && f->leaves[0].slot == 17 &&
          f->leaves[0].spawn_tick == 118 && f->leaves[0].seed == 0xdeadbeefu);
}

static void v_leaves(const spec_vector *v)
{
    wire_leaf lf = { 2, 17, 118, 0xdeadbeefu };
    size_t len = 0;
    CHECK(wire_encode_leaves(&h123, &lf, 1, buf, sizeof buf, &len, NULL) == 0);
    same_bytes(v, buf, len);
    wire_decoder *d = decoder();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == 1u << WIRE_MSG_LEAVES && f.hdr.tick == 123 && f.hdr.server_time_us == 2050000);
    check_leaves(&f);
    wire_decoder_destroy(d);
}

static void check_wind(const wire_frame *f)
{
    const wire_wind *w = &f->wind;
    CHECK(w->nx == 2 && w->ny == 1 && w->x0_m == -64 && w->y0_m == -64 && w->z_m == 4 &&
          w->cell_m == 8 && w->scale_ms == 0.1f);
    CHECK(w->v && w->v[0] == 10 && w->v[1] == -5 && w->v[2] == 0 && w->v[3] == 127 &&
          w->v[4] == -127 && w->v[5] == 1);
}

static void v_wind(const spec_vector *v)
{
    const int8_t cells[6] = { 10, -5, 0, 127, -127, 1 };
    wire_wind w = { -64, -64, 4, 8, 0.1f, 2, 1, cells };
    size_t len = 0;
    CHECK(wire_encode_wind(&h123, &w, buf, sizeof buf, &len, NULL) == 0);
    same_bytes(v, buf, len);
    wire_decoder *d = decoder();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == 1u << WIRE_MSG_WIND && f.hdr.tick == 123);
    check_wind(&f);
    wire_decoder_destroy(d);
}

/* Andrew near landfall (vector WEATHER). */
static wire_weather andrew(void)
{
    wire_weather w;
    memset(&w, 0, sizeof w);
    w.sustained_ms = 50.0f;
    w.gust_ms = 62.5f;
    w.dir_from_deg = 45.0f;
    w.ss_class = 4;
    w.beaufort = 12;
    w.flags = WIRE_WEATHER_STORM | WIRE_WEATHER_CLOCK;
    w.storm_class = 5;
    w.pressure_hpa = 950.0f;
    w.central_hpa = 922.0f;
    w.distance_km = 20.0f;
    w.bearing_deg = 90.0f;
    w.utc_min = 11910785u; /* 1992-08-24 09:05Z */
    w.utc_offset_min = -240;
    w.storm_min = -10.0f;
    w.replay_pos_s = 180.0f;
    w.replay_len_s = 402.0f;
    w.replay_speed = 50.0f;
    snprintf(w.name, sizeof w.name, "Andrew 1992");
    return w;
}

/* A kiosk's dial on a steady scenario (vector WEATHER-STEADY): no storm, no clock. */
static wire_weather steady(void)
{
    wire_weather w;
    memset(&w, 0, sizeof w);
    w.sustained_ms = 20.0f;
    w.gust_ms = 26.5f;
    w.dir_from_deg = 270.0f;
    w.ss_class = 1; /* 20 m/s = 39 kt: tropical storm */
    w.beaufort = 8;
    w.flags = WIRE_WEATHER_DIAL;
    w.storm_class = 255;
    w.pressure_hpa = 1013.0f;
    w.distance_km = -1.0f;
    snprintf(w.name, sizeof w.name, "gale");
    return w;
}

static void weather_vector(const spec_vector *v, const wire_weather *w, uint32_t tick)
{
    size_t len = 0;
    CHECK(wire_encode_weather(&(wire_header){ .tick = tick, .server_time_us = 2000000 }, w, buf,
                              sizeof buf, &len, NULL) == 0);
    same_bytes(v, buf, len);
    wire_decoder *d = decoder();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == 1u << WIRE_MSG_WEATHER && f.hdr.tick == tick);
    CHECK(memcmp(&f.weather, w, sizeof *w) == 0);
    wire_decoder_destroy(d);
}

static void v_weather(const spec_vector *v)
{
    wire_weather w = andrew();
    weather_vector(v, &w, 120);
}

static void v_weather_steady(const spec_vector *v)
{
    wire_weather w = steady();
    weather_vector(v, &w, 120);
}

static const wire_damage dmg_events[2] = {
    { .tree = 2, .node = 17, .kind = WIRE_DAMAGE_BRANCH, .value = 0, .tick = 118 },
    { .tree = 5, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_UPROOT, .value = 64, .tick = 120 },
};
static const wire_damage dmg_state[2] = {
    { .tree = 0, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_STRIP, .value = 20, .tick = 110 },
    { .tree = 1, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_SNAP, .value = 200, .tick = 115 },
};

static void check_damage(const wire_frame *f, bool full, const wire_damage *ev, uint32_t n)
{
    CHECK(f->damage_full == full && f->n_damage == n);
    for (uint32_t i = 0; i < n && i < f->n_damage && f->damage; i++) {
        /* field by field: the struct has padding */
        CHECK(f->damage[i].tree == ev[i].tree && f->damage[i].node == ev[i].node &&
              f->damage[i].kind == ev[i].kind && f->damage[i].value == ev[i].value &&
              f->damage[i].tick == ev[i].tick);
    }
}

static void damage_vector(const spec_vector *v, bool full, const wire_damage *ev, uint32_t n,
                          const wire_header *h)
{
    size_t len = 0;
    CHECK(wire_encode_damage(h, full, ev, n, buf, sizeof buf, &len, NULL) == 0);
    same_bytes(v, buf, len);
    wire_decoder *d = decoder();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == 1u << WIRE_MSG_DAMAGE && f.hdr.tick == h->tick);
    check_damage(&f, full, ev, n);
    wire_decoder_destroy(d);
}

static void v_damage(const spec_vector *v)
{
    damage_vector(v, false, dmg_events, 2, &h123);
}

static void v_damage_full(const spec_vector *v)
{
    damage_vector(v, true, dmg_state, 2,
                  &(wire_header){ .tick = 120, .server_time_us = 2000000 });
}

/* FOREST: three trees listed; the bytes from wire_encode_forest, the decoded fields, and
 * the DAMAGE events the spec says they stand for */
static void v_forest(const spec_vector *v)
{
    static const uint8_t state[3] = { 0x14, 0xa0, 0xc8 };
    static const wire_forest_fall fall[2] = { { 200, 115 }, { 64, 118 } };
    static const wire_damage as_events[4] = {
        { .tree = 0, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_STRIP, .value = 20, .tick = 120 },
        { .tree = 1, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_SNAP, .value = 200, .tick = 115 },
        { .tree = 2, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_UPROOT, .value = 64, .tick = 118 },
        { .tree = 2, .node = WIRE_DAMAGE_WHOLE, .kind = WIRE_DAMAGE_STRIP, .value = 8, .tick = 120 },
    };
    const wire_header h = { .tick = 120, .server_time_us = 2000000 };
    size_t len = 0;
    CHECK(wire_encode_forest(&h, 0, 3, state, fall, 2, buf, sizeof buf, &len, NULL) == 0);
    CHECK(len == wire_forest_bytes(3, 2));
    same_bytes(v, buf, len);
    wire_decoder *d = decoder();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == 1u << WIRE_MSG_FOREST && f.hdr.tick == 120);
    CHECK(f.forest_first == 0 && f.forest_count == 3 && f.n_forest_fall == 2);
    CHECK(f.forest_count == 3 && memcmp(f.forest_state, state, 3) == 0);
    wire_damage ev[4];
    CHECK(wire_forest_events(&f, ev, 4) == 4);
    f.damage = ev;
    f.n_damage = 4;
    check_damage(&f, false, as_events, 4);
    wire_decoder_destroy(d);
}

/* The BUNDLE of the vectors named, built with wire_bundle_wrap from the spec's own bytes. */
static size_t wrap(const char *const *names, uint32_t n)
{
    const spec_vector *first = vec(names[0]);
    const uint8_t *more[8];
    size_t more_len[8], len = first->len;
    memcpy(buf, first->bytes, first->len);
    for (uint32_t i = 1; i < n; i++) {
        more[i - 1] = vec(names[i])->bytes;
        more_len[i - 1] = vec(names[i])->len;
    }
    CHECK(wire_bundle_wrap(buf, sizeof buf, &len, more, more_len, n - 1, NULL) == 0);
    return len;
}

static void v_bundle(const spec_vector *v)
{
    static const char *const names[] = { "DELTA", "LEAVES" };
    same_bytes(v, buf, wrap(names, 2));
    wire_decoder *d = keyed();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == ((1u << WIRE_MSG_DELTA) | (1u << WIRE_MSG_LEAVES)));
    CHECK(f.hdr.type == WIRE_MSG_DELTA && f.hdr.tick == 122 && f.seq == 6);
    check_leaves(&f);
    wire_state st = wire_decoder_state(d);
    CHECK(wire_decoder_seq(d) == 6 && st.q[0] == 4 && st.q[1] == -2 && st.q[st.stride * 2] == 7);
    wire_decoder_destroy(d);
}

static void v_bundle_keyframe(const spec_vector *v)
{
    static const char *const names[] = { "KEYFRAME", "LEAVES", "WIND", "DAMAGE-FULL", "WEATHER" };
    same_bytes(v, buf, wrap(names, 5));
    wire_decoder *d = decoder();
    wire_frame f;
    CHECK(wire_decode(d, v->bytes, v->len, &f, NULL) == 0);
    CHECK(f.types == ((1u << WIRE_MSG_KEYFRAME) | (1u << WIRE_MSG_LEAVES) | (1u << WIRE_MSG_WIND) |
                      (1u << WIRE_MSG_DAMAGE) | (1u << WIRE_MSG_WEATHER)));
    CHECK(f.hdr.type == WIRE_MSG_KEYFRAME && f.hdr.tick == 120 && f.seq == 5);
    check_keyframe_state(d);
    check_leaves(&f);
    check_wind(&f);
    check_damage(&f, true, dmg_state, 2);
    wire_weather w = andrew();
    CHECK(memcmp(&f.weather, &w, sizeof w) == 0);
    wire_decoder_destroy(d);
}

/* ---- control messages ------------------------------------------------------------------ */

/* The vector's text decodes to *want (compared as bytes: both start zeroed), and *want and
 * the decoded message both encode to exactly that text. */
static void json_vector(const spec_vector *v, const ctl_msg *want, size_t max_len)
{
    char *out = NULL;
    size_t len = 0;
    gale_err e = { 0 };
    CHECK(ctl_encode(want, &out, &len, &e) == 0);
    int same = out && len == v->len && memcmp(out, v->bytes, len) == 0;
    CHECK(same);
    if (!same) {
        fprintf(stderr, "  vector %s (line %d): the spec has\n%s\n  encoded: %s\n%s\n", v->name,
                v->line, (const char *)v->bytes, e.msg, out ? out : "(nothing)");
    }
    free(out);
    ctl_msg m;
    int close = 0;
    CHECK(ctl_decode((const char *)v->bytes, v->len, max_len, &m, &close, &e) == 0);
    if (m.type != want->type) {
        fprintf(stderr, "  vector %s: %s\n", v->name, e.msg);
    }
    CHECK(m.type == want->type);
    if (m.type != CTL_WELCOME) {
        CHECK(memcmp(&m, want, sizeof m) == 0);
    }
    out = NULL;
    CHECK(ctl_encode(&m, &out, &len, &e) == 0);
    CHECK(out && len == v->len && memcmp(out, v->bytes, len) == 0);
    free(out);
    if (m.type == CTL_WELCOME) {
        const ctl_welcome *a = &m.u.welcome, *b = &want->u.welcome;
        CHECK(a->protocol == b->protocol && a->client_id == b->client_id && a->role == b->role &&
              a->tick_hz == b->tick_hz && a->snapshot_hz == b->snapshot_hz &&
              a->server_us == b->server_us && a->tick == b->tick);
        CHECK(a->n_species == b->n_species && a->n_instances == b->n_instances &&
              a->n_obstacles == b->n_obstacles && a->n_scenarios == b->n_scenarios);
        if (a->n_species == b->n_species && a->n_instances == b->n_instances &&
            a->n_obstacles == b->n_obstacles && a->n_scenarios == b->n_scenarios) {
            CHECK(!memcmp(a->species, b->species, a->n_species * sizeof *a->species));
            CHECK(!memcmp(a->instances, b->instances, a->n_instances * sizeof *a->instances));
            CHECK(!memcmp(a->obstacles, b->obstacles, a->n_obstacles * sizeof *a->obstacles));
            CHECK(!memcmp(a->scenarios, b->scenarios, a->n_scenarios * sizeof *a->scenarios));
        }
    }
    ctl_msg_fini(&m);
}

/* A zeroed message of type t (unions compared as bytes need zeroed padding). */
static ctl_msg msg(int t)
{
    ctl_msg m;
    memset(&m, 0, sizeof m);
    m.type = t;
    return m;
}

static void v_hello(const spec_vector *v)
{
    ctl_msg m = msg(CTL_HELLO);
    m.u.hello.protocol = 1;
    m.u.hello.role = CTL_ROLE_KIOSK;
    m.u.hello.view.kind = CTL_VIEW_CIRCLE;
    m.u.hello.view.x = 10.5f;
    m.u.hello.view.y = -3.0f;
    m.u.hello.view.radius_m = 80.0f;
    m.u.hello.view.lod_m = 40.0f;
    snprintf(m.u.hello.token, sizeof m.u.hello.token, "s3cret");
    json_vector(v, &m, 0);
}

static void v_view(const spec_vector *v)
{
    ctl_msg m = msg(CTL_VIEW);
    ctl_view *w = &m.u.view;
    w->kind = CTL_VIEW_FRUSTUM;
    w->eye[1] = -60.0f;
    w->eye[2] = 1.75f;
    w->dir[1] = 1.0f;
    w->dir[2] = 0.125f;
    w->fov_deg = 60.0f;
    w->far_m = 300.0f;
    w->lod_m = 120.0f;
    json_vector(v, &m, 0);
}

static void v_wind_msg(const spec_vector *v)
{
    ctl_msg m = msg(CTL_WIND);
    ctl_wind *w = &m.u.wind;
    snprintf(w->token, sizeof w->token, "s3cret");
    w->has_speed = w->has_dir = true;
    w->speed_ms = 42.5f;
    w->dir_deg = 90.0f;
    json_vector(v, &m, 0);
}

static void v_wind_replay(const spec_vector *v)
{
    ctl_msg m = msg(CTL_WIND);
    ctl_wind *w = &m.u.wind;
    snprintf(w->token, sizeof w->token, "s3cret");
    w->has_scenario = true;
    snprintf(w->scenario, sizeof w->scenario, "andrew1992");
    w->has_replay_at = w->has_replay_speed = w->has_replay_paused = true;
    w->replay_at_min = -30.0f;
    w->replay_speed = 50.0f;
    w->replay_paused = false;
    json_vector(v, &m, 0);
}

static void v_reset(const spec_vector *v)
{
    ctl_msg m = msg(CTL_RESET);
    snprintf(m.u.reset.token, sizeof m.u.reset.token, "s3cret");
    json_vector(v, &m, 0);
}

static void v_kiosk_state(const spec_vector *v)
{
    ctl_msg m = msg(CTL_KIOSK_STATE);
    ctl_kiosk_state *k = &m.u.kiosk_state;
    snprintf(k->token, sizeof k->token, "s3cret");
    snprintf(k->lang, sizeof k->lang, "en");
    snprintf(k->audio, sizeof k->audio, "none");
    json_vector(v, &m, 0);
}

static void v_schedule(const spec_vector *v)
{
    ctl_msg m = msg(CTL_SCHEDULE);
    ctl_schedule *k = &m.u.schedule;
    k->open = false;
    snprintf(k->next_change, sizeof k->next_change, "09:30");
    k->next_in_s = 5400;
    json_vector(v, &m, 0);
}

static void v_resync(const spec_vector *v)
{
    ctl_msg m = msg(CTL_RESYNC);
    m.u.resync_seq = 6;
    json_vector(v, &m, 0);
}

static void v_ping(const spec_vector *v)
{
    ctl_msg m = msg(CTL_PING);
    m.u.ping.id = 7;
    m.u.ping.client_us = 9007199254740991ull; /* 2^53 - 1: every digit survives */
    json_vector(v, &m, 0);
}

static void v_pong(const spec_vector *v)
{
    ctl_msg m = msg(CTL_PONG);
    m.u.pong.id = 7;
    m.u.pong.client_us = 9007199254740991ull;
    m.u.pong.server_us = 2000000;
    m.u.pong.tick = 120;
    json_vector(v, &m, CTL_MAX_SERVER_BYTES);
}

static void v_error(const spec_vector *v)
{
    ctl_msg m = msg(CTL_ERROR);
    m.u.error.code = WIRE_CLOSE_BAD_FIELD;
    snprintf(m.u.error.message, sizeof m.u.error.message,
             "ctl: hello.role: expected one of viewer|kiosk|wall-tile|load, got \"admin\"");
    json_vector(v, &m, CTL_MAX_SERVER_BYTES);
}

static void v_welcome(const spec_vector *v)
{
    ctl_species sp[2];
    ctl_instance in[3];
    ctl_obstacle ob[1];
    ctl_scenario_info sc[2];
    memset(sp, 0, sizeof sp);
    memset(in, 0, sizeof in);
    memset(ob, 0, sizeof ob);
    memset(sc, 0, sizeof sc);
    snprintf(sp[0].name, sizeof sp[0].name, "oak");
    snprintf(sp[0].hash, sizeof sp[0].hash, "0123456789abcdef");
    snprintf(sp[0].url, sizeof sp[0].url, "/assets/%s.gasset", sp[0].hash);
    sp[0].n_modes = 2;
    snprintf(sp[1].name, sizeof sp[1].name, "palm");
    snprintf(sp[1].hash, sizeof sp[1].hash, "fedcba9876543210");
    snprintf(sp[1].url, sizeof sp[1].url, "/assets/%s.gasset", sp[1].hash);
    sp[1].n_modes = 1;
    const float rows[3][6] = { { 0, -10, 5, 0, 0, 1 }, { 1, 40, 5, 0.5f, 1.5f, 1.25f },
                               { 0, 12.5f, -20, 0, 3, 0.75f } };
    for (int i = 0; i < 3; i++) {
        in[i].species = (uint32_t)rows[i][0];
        in[i].pos[0] = rows[i][1];
        in[i].pos[1] = rows[i][2];
        in[i].pos[2] = rows[i][3];
        in[i].yaw_rad = rows[i][4];
        in[i].scale = rows[i][5];
    }
    ob[0] = (ctl_obstacle){ { 20, -4, 0 }, { 28, 4, 6.5f } };
    snprintf(sc[0].name, sizeof sc[0].name, "gale");
    snprintf(sc[0].title, sizeof sc[0].title, "Gale");
    sc[0].kind = CTL_SCENARIO_STEADY;
    sc[0].sustained_ms = 20.0f;
    snprintf(sc[1].name, sizeof sc[1].name, "andrew1992");
    snprintf(sc[1].title, sizeof sc[1].title, "Andrew 1992");
    sc[1].kind = CTL_SCENARIO_REPLAY;
    ctl_msg m = msg(CTL_WELCOME);
    m.u.welcome = (ctl_welcome){ .protocol = 1, .client_id = 3, .role = CTL_ROLE_KIOSK,
                                 .tick_hz = 60.0f, .snapshot_hz = 30.0f, .server_us = 2000000,
                                 .tick = 120, .n_species = 2, .species = sp, .n_instances = 3,
                                 .instances = in, .n_obstacles = 1, .obstacles = ob,
                                 .n_scenarios = 2, .scenarios = sc };
    json_vector(v, &m, CTL_MAX_SERVER_BYTES);
}

static void v_wall_join(const spec_vector *v)
{
    ctl_msg m = msg(CTL_WALL_JOIN);
    ctl_wall_join *j = &m.u.wall_join;
    snprintf(j->wall, sizeof j->wall, "lobby");
    snprintf(j->tile, sizeof j->tile, "left");
    j->swap_lock = true;
    j->rate_hz = 60.0f;
    j->budget_ms = 8;
    j->delay_ms = 100;
    json_vector(v, &m, 0);
}

static void v_wall_sync(const spec_vector *v)
{
    ctl_msg m = msg(CTL_WALL_SYNC);
    ctl_wall_sync *s = &m.u.wall_sync;
    snprintf(s->wall, sizeof s->wall, "lobby");
    s->epoch_us = 2000000;
    s->period_us = 16667; /* round(1e6 / 60) */
    s->delay_us = 100000;
    s->budget_ms = 8;
    s->swap_lock = true;
    s->members = 2;
    json_vector(v, &m, CTL_MAX_SERVER_BYTES);
}

static void v_wall_drawn(const spec_vector *v)
{
    ctl_msg m = msg(CTL_WALL_DRAWN);
    m.u.wall_frame.frame = 42;
    json_vector(v, &m, 0);
}

static void v_wall_swap(const spec_vector *v)
{
    ctl_msg m = msg(CTL_WALL_SWAP);
    m.u.wall_frame = (ctl_wall_frame){ .frame = 42, .drawn = 2, .members = 2 };
    json_vector(v, &m, CTL_MAX_SERVER_BYTES);
}

static ctl_msg camera(uint32_t frame)
{
    ctl_msg m = msg(CTL_WALL_CAMERA);
    ctl_wall_camera *c = &m.u.wall_camera;
    snprintf(c->wall, sizeof c->wall, "lobby");
    c->frame = frame;
    c->target_m[2] = 8.0f;
    c->distance_m = 90.0f;
    c->yaw_deg = -45.0f;
    c->pitch_deg = 12.5f;
    return m;
}

static void v_wall_camera(const spec_vector *v)
{
    ctl_msg m = camera(0);
    json_vector(v, &m, 0);
}

static void v_wall_camera_frame(const spec_vector *v)
{
    ctl_msg m = camera(49);
    json_vector(v, &m, CTL_MAX_SERVER_BYTES);
}

/* ---- the list ------------------------------------------------------------------------- */

typedef struct known {
    const char *name;
    int json;
    void (*check)(const spec_vector *v);
} known;

static const known vectors[] = {
    { "KEYFRAME", 0, v_keyframe },
    { "DELTA", 0, v_delta },
    { "LEAVES", 0, v_leaves },
    { "WIND", 0, v_wind },
    { "WEATHER", 0, v_weather },
    { "WEATHER-STEADY", 0, v_weather_steady },
    { "DAMAGE", 0, v_damage },
    { "DAMAGE-FULL", 0, v_damage_full },
    { "FOREST", 0, v_forest },
    { "BUNDLE", 0, v_bundle },
    { "BUNDLE-KEYFRAME", 0, v_bundle_keyframe },
    { "HELLO", 1, v_hello },
    { "VIEW", 1, v_view },
    { "WIND-DIAL", 1, v_wind_msg },
    { "WIND-REPLAY", 1, v_wind_replay },
    { "RESET", 1, v_reset },
    { "KIOSK-STATE", 1, v_kiosk_state },
    { "SCHEDULE", 1, v_schedule },
    { "RESYNC", 1, v_resync },
    { "PING", 1, v_ping },
    { "WELCOME", 1, v_welcome },
    { "PONG", 1, v_pong },
    { "ERROR", 1, v_error },
    { "WALL-JOIN", 1, v_wall_join },
    { "WALL-SYNC", 1, v_wall_sync },
    { "WALL-DRAWN", 1, v_wall_drawn },
    { "WALL-SWAP", 1, v_wall_swap },
    { "WALL-CAMERA", 1, v_wall_camera },
    { "WALL-CAMERA-FRAME", 1, v_wall_camera_frame },
};
#define N_KNOWN (sizeof vectors / sizeof vectors[0])

/* Every vector of the file is one this test knows, of the kind it expects, and every one
 * it knows is in the file; each is checked. */
static void test_every_vector(void)
{
    bool seen[N_KNOWN] = { false };
    for (int i = 0; i < spec.n; i++) {
        const spec_vector *v = &spec.v[i];
        size_t k = 0;
        while (k < N_KNOWN && strcmp(vectors[k].name, v->name) != 0) {
            k++;
        }
        if (k == N_KNOWN || vectors[k].json != v->json) {
            fprintf(stderr, "  %s:%d: vector %s (%s): not one this test knows\n", spec_path,
                    v->line, v->name, v->json ? "gale-json" : "gale-hex");
            CHECK(!"an unknown vector in the spec");
            continue;
        }
        int before = check_failures;
        vectors[k].check(v);
        seen[k] = true;
        fprintf(stderr, "  %-20s %4zu %s  %s\n", v->name, v->len, v->json ? "chars" : "bytes",
                check_failures == before ? "ok" : "FAIL");
    }
    for (size_t k = 0; k < N_KNOWN; k++) {
        if (!seen[k]) {
            fprintf(stderr, "  vector %s: missing from %s\n", vectors[k].name, spec_path);
        }
        CHECK(seen[k]);
    }
}

/* The row of the spec's markdown table whose first cell is head, copied into row; 0 if
 * found once. */
static int table_row(const char *head, char *row, size_t cap)
{
    FILE *fp = fopen(spec_path, "r");
    char line[1024];
    int found = 0;
    while (fp && fgets(line, sizeof line, fp)) {
        if (!strncmp(line, head, strlen(head))) {
            found++;
            snprintf(row, cap, "%s", line + strlen(head));
        }
    }
    if (fp) {
        fclose(fp);
    }
    return found == 1 ? 0 : -1;
}

/* PROTOCOL.md "WEATHER", "Classes": the Saffir-Simpson knots and the Beaufort limits in the
 * spec's tables are those protocol/wind_scale.c classifies by, limit for limit. */
static void test_class_tables(void)
{
    char row[1024];
    CHECK(table_row("| kt |", row, sizeof row) == 0);
    /* "| ≤ 33 | 34-63 | ... | ≥ 137 |": each class's first knot (class 0 from 0) */
    int c = 0;
    for (const char *p = row; p && *p != '\n' && c < WIND_SCALE_SS_COUNT; c++) {
        int lo = 0, hi = 0;
        if (c == 0) {
            CHECK(sscanf(p, " \xe2\x89\xa4 %d |", &hi) == 1 && hi == 33);
            lo = 0;
        } else if (c == WIND_SCALE_SS_COUNT - 1) {
            CHECK(sscanf(p, " \xe2\x89\xa5 %d |", &lo) == 1);
        } else {
            CHECK(sscanf(p, " %d-%d |", &lo, &hi) == 2);
        }
        p = strchr(p, '|');
        p = p ? p + 1 : NULL;
        /* the class starts half a knot below its first whole knot (rounding to knots) */
        double want = c == 0 ? 0.0 : (lo - 0.5) * WIND_SCALE_MS_PER_KT;
        CHECK_NEAR(wind_scale_ss_lower_ms(c), want, 1e-9);
        if (c > 0) {
            CHECK(wind_scale_ss_class(want + 1e-6) == c && wind_scale_ss_class(want - 1e-6) == c - 1);
        }
    }
    CHECK(c == WIND_SCALE_SS_COUNT);
    CHECK(table_row("| upper limit [m/s] |", row, sizeof row) == 0);
    int b = 0;
    for (const char *p = row; p && *p != '\n' && b < 12; b++) {
        double up = 0;
        CHECK(sscanf(p, " %lf |", &up) == 1);
        p = strchr(p, '|');
        p = p ? p + 1 : NULL;
        /* force b ends at its limit; b + 1 starts half a tenth above it (rounding to 0.1) */
        CHECK(wind_scale_beaufort(up) == b && wind_scale_beaufort(up + 0.1) == b + 1);
        CHECK_NEAR(wind_scale_beaufort_lower_ms(b + 1), up + 0.05, 1e-9);
    }
    CHECK(b == 12);
}

/* The reader itself: a changed byte, a missing marker, a bad offset are noticed. */
static void test_reader(void)
{
    static spec_file f;
    char path[512];
    snprintf(path, sizeof path, "%s/spec_vectors_scratch.md", GALE_TEST_DIR);
    static const struct {
        const char *text;
        const char *err; /* NULL: loads */
    } cases[] = {
        { "```gale-hex A\n00: 01 02\n```\n", NULL },
        { "```gale-hex A\n00: 01 02\n01: 03\n```\n", "offset: expected 2, got 1" },
        { "```\n00: 01 02\n```\n", "without a \"gale-hex NAME\" marker" },
        { "```gale-hex a\n00: 01\n```\n", "vector name" },
        { "```gale-bin A\n00: 01\n```\n", "marker" },
        { "```gale-hex A\n00: 01 2\n```\n", "byte 1" },
        { "```gale-hex A\n00: 01\n```\n```gale-json A\n{}\n```\n", "named twice" },
        { "```gale-json A\n{}\n{}\n```\n", "one line" },
        { "```gale-hex A\n00: 01\n", "left open" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        FILE *fp = fopen(path, "w");
        CHECK(fp != NULL);
        if (!fp) {
            return;
        }
        fputs(cases[i].text, fp);
        fclose(fp);
        int rc = spec_load(&f, path);
        if (!cases[i].err) {
            CHECK(rc == 0 && f.n == 1 && f.v[0].len == 2 && f.v[0].bytes[1] == 2);
        } else {
            CHECK(rc == -1);
            CHECK_STR_HAS(f.err, cases[i].err);
        }
    }
    remove(path);
}

int main(int argc, char **argv)
{
    if (argc > 2 || (argc == 2 && !strcmp(argv[1], "--help"))) {
        printf("usage: test_spec_vectors [SPEC.md]\n  decodes and re-encodes every test vector "
               "of SPEC.md (default %s)\n", SPEC_PROTOCOL_PATH);
        return argc > 2;
    }
    spec_path = argc == 2 ? argv[1] : SPEC_PROTOCOL_PATH;
    if (spec_load(&spec, spec_path)) {
        fprintf(stderr, "test_spec_vectors: %s\n", spec.err);
        return 1;
    }
    RUN(test_reader);
    RUN(test_every_vector);
    RUN(test_class_tables);
    return check_report();
}
