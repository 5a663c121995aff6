/* Tests of the JSON control messages (protocol/ctl.h): golden text per message type,
 * round trips, every truncation rejected, the exact error text and close code of each
 * kind of bad input, and the encoder's self-check: what it writes, the decoder accepts. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "ctl.h"
#include "wire.h"

/* Encodes m and compares with the golden text; decodes the golden text back. */
static void golden(const ctl_msg *m, const char *want)
{
    char *s = NULL;
    size_t n = 0;
    gale_err e;
    int rc = ctl_encode(m, &s, &n, &e);
    CHECK(rc == 0);
    if (rc) {
        fprintf(stderr, "  encode: %s\n", e.msg);
        return;
    }
    if (strcmp(s, want) != 0) {
        fprintf(stderr, "  got  %s\n  want %s\n", s, want);
    }
    CHECK(strcmp(s, want) == 0);
    CHECK(n == strlen(want));
    char small[512];
    size_t n2 = 0;
    if (n < sizeof small - 8) {
        CHECK(ctl_encode_into(m, small, sizeof small, &n2, &e) == 0);
        CHECK(n2 == n && strcmp(small, want) == 0);
    }
    ctl_msg back;
    int close = -1;
    CHECK(ctl_decode(want, strlen(want), CTL_MAX_SERVER_BYTES, &back, &close, &e) == 0);
    CHECK(close == 0);
    CHECK(back.type == m->type);
    /* Every proper prefix is rejected as bad JSON. */
    bool all = true;
    for (size_t k = 0; k < n; k++) {
        ctl_msg t;
        int c = 0;
        all &= ctl_decode(want, k, CTL_MAX_SERVER_BYTES, &t, &c, &e) != 0 &&
               c == WIRE_CLOSE_BAD_JSON;
    }
    CHECK(all);
    ctl_msg_fini(&back);
    free(s);
}

static void test_golden(void)
{
    ctl_msg m = { .type = CTL_HELLO };
    m.u.hello.protocol = WIRE_PROTOCOL_VERSION;
    m.u.hello.role = CTL_ROLE_VIEWER;
    golden(&m, "{\"type\":\"hello\",\"protocol\":1,\"role\":\"viewer\"}");

    m.u.hello.role = CTL_ROLE_KIOSK;
    strcpy(m.u.hello.token, "s3cret");
    m.u.hello.view = (ctl_view){ .kind = CTL_VIEW_CIRCLE, .x = 10.5f, .y = -3.0f,
                                 .radius_m = 80.0f, .lod_m = 40.0f };
    golden(&m, "{\"type\":\"hello\",\"protocol\":1,\"role\":\"kiosk\",\"view\":{\"kind\":"
               "\"circle\",\"x\":10.5,\"y\":-3,\"radius_m\":80,\"lod_m\":40},\"token\":\"s3cret\"}");

    m = (ctl_msg){ .type = CTL_VIEW };
    m.u.view = (ctl_view){ .kind = CTL_VIEW_FRUSTUM, .eye = { 0.0f, -50.0f, 1.7f },
                           .dir = { 0.0f, 1.0f, 0.0f }, .fov_deg = 60.0f, .far_m = 500.0f };
    golden(&m, "{\"type\":\"view\",\"view\":{\"kind\":\"frustum\",\"eye\":[0,-50,1.7],"
               "\"dir\":[0,1,0],\"fov_deg\":60,\"far_m\":500}}");

    m = (ctl_msg){ .type = CTL_WIND };
    strcpy(m.u.wind.token, "s3cret");
    m.u.wind.has_speed = true;
    m.u.wind.speed_ms = 42.5f;
    m.u.wind.has_dir = true;
    m.u.wind.dir_deg = 270.0f;
    m.u.wind.has_scenario = true;
    strcpy(m.u.wind.scenario, "andrew-1992");
    golden(&m, "{\"type\":\"wind\",\"token\":\"s3cret\",\"speed_ms\":42.5,\"dir_deg\":270,"
               "\"scenario\":\"andrew-1992\"}");

    /* kiosk controls: a pause, and reset with its token alone */
    m = (ctl_msg){ .type = CTL_WIND };
    strcpy(m.u.wind.token, "s3cret");
    m.u.wind.has_replay_paused = true;
    m.u.wind.replay_paused = false;
    golden(&m, "{\"type\":\"wind\",\"token\":\"s3cret\",\"replay_paused\":false}");
    m.u.wind.replay_paused = true;
    golden(&m, "{\"type\":\"wind\",\"token\":\"s3cret\",\"replay_paused\":true}");
    m = (ctl_msg){ .type = CTL_RESET };
    strcpy(m.u.reset.token, "s3cret");
    golden(&m, "{\"type\":\"reset\",\"token\":\"s3cret\"}");
    CHECK(ctl_from_client(CTL_RESET));

    m = (ctl_msg){ .type = CTL_RESYNC, .u.resync_seq = 41 };
    golden(&m, "{\"type\":\"resync\",\"seq\":41}");

    m = (ctl_msg){ .type = CTL_PING, .u.ping = { 7, 1234567890123ull } };
    golden(&m, "{\"type\":\"ping\",\"id\":7,\"client_us\":1234567890123}");

    m = (ctl_msg){ .type = CTL_PONG, .u.pong = { 7, 1234567890123ull, 5000000ull, 300 } };
    golden(&m, "{\"type\":\"pong\",\"id\":7,\"client_us\":1234567890123,\"server_us\":5000000,"
               "\"tick\":300}");
    /* integers up to 2^53 come back with every digit (PROTOCOL.md "Control messages") */
    m = (ctl_msg){ .type = CTL_PONG,
                   .u.pong = { UINT32_MAX, 9007199254740991ull, 9007199254740992ull, UINT32_MAX } };
    golden(&m, "{\"type\":\"pong\",\"id\":4294967295,\"client_us\":9007199254740991,"
               "\"server_us\":9007199254740992,\"tick\":4294967295}");
    {
        const char *pj = "{\"type\":\"pong\",\"id\":1,\"client_us\":9007199254740991,"
                         "\"server_us\":9007199254740992,\"tick\":2}";
        ctl_msg back;
        int close = 0;
        gale_err e;
        CHECK(ctl_decode(pj, strlen(pj), CTL_MAX_SERVER_BYTES, &back, &close, &e) == 0);
        CHECK(back.u.pong.client_us == 9007199254740991ull);
        CHECK(back.u.pong.server_us == 9007199254740992ull);
        ctl_msg_fini(&back);
    }
    m = (ctl_msg){ .type = CTL_PING, .u.ping = { 1, 9007199254740991ull } };
    golden(&m, "{\"type\":\"ping\",\"id\":1,\"client_us\":9007199254740991}");

    m = (ctl_msg){ .type = CTL_ERROR };
    m.u.error.code = WIRE_CLOSE_VERSION;
    strcpy(m.u.error.message, "ctl: hello.protocol: expected 1, got 2");
    golden(&m, "{\"type\":\"error\",\"code\":4003,\"message\":\"ctl: hello.protocol: expected 1, "
               "got 2\"}");

    ctl_species sp[2] = { { "oak", "/assets/oak-0123456789abcdef.gasset", "0123456789abcdef", 32 },
                          { "palm", "/assets/palm-fedcba9876543210.gasset", "fedcba9876543210",
                            16 } };
    ctl_instance in[2] = { { 0, { 1.5f, 2.0f, 0.0f }, 0.25f, 1.0f },
                           { 1, { -30.0f, 12.75f, 0.5f }, 3.0f, 1.25f } };
    ctl_obstacle ob[2] = { { { -4.0f, 6.0f, 0.0f }, { 4.0f, 12.5f, 5.0f } },
                           { { 20.0f, -3.0f, 0.0f }, { 26.0f, 3.0f, 7.25f } } };
    m = (ctl_msg){ .type = CTL_WELCOME };
    m.u.welcome = (ctl_welcome){ .protocol = 1, .client_id = 9, .role = CTL_ROLE_WALL_TILE,
                                 .tick_hz = 60.0f, .snapshot_hz = 30.0f, .server_us = 123456,
                                 .tick = 88, .n_species = 2, .species = sp, .n_instances = 2,
                                 .instances = in, .n_obstacles = 2, .obstacles = ob };
    const char *wel =
        "{\"type\":\"welcome\",\"protocol\":1,\"client_id\":9,\"role\":\"wall-tile\","
        "\"tick_hz\":60,\"snapshot_hz\":30,\"server_us\":123456,\"tick\":88,\"species\":["
        "{\"name\":\"oak\",\"url\":\"/assets/oak-0123456789abcdef.gasset\",\"hash\":"
        "\"0123456789abcdef\",\"n_modes\":32},{\"name\":\"palm\",\"url\":"
        "\"/assets/palm-fedcba9876543210.gasset\",\"hash\":\"fedcba9876543210\",\"n_modes\":16}],"
        "\"instances\":[[0,1.5,2,0,0.25,1],[1,-30,12.75,0.5,3,1.25]],"
        "\"obstacles\":[[-4,6,0,4,12.5,5],[20,-3,0,26,3,7.25]]}";
    golden(&m, wel);
    ctl_msg back;
    gale_err e;
    CHECK(ctl_decode(wel, strlen(wel), CTL_MAX_SERVER_BYTES, &back, NULL, &e) == 0);
    CHECK(back.u.welcome.n_species == 2 && back.u.welcome.n_instances == 2);
    CHECK(strcmp(back.u.welcome.species[1].name, "palm") == 0);
    CHECK(back.u.welcome.species[1].n_modes == 16);
    CHECK(back.u.welcome.instances[1].species == 1);
    CHECK(back.u.welcome.instances[1].pos[1] == 12.75f);
    CHECK(back.u.welcome.instances[1].scale == 1.25f);
    CHECK(back.u.welcome.role == CTL_ROLE_WALL_TILE && back.u.welcome.tick == 88);
    CHECK(back.u.welcome.n_obstacles == 2);
    CHECK(back.u.welcome.obstacles[0].min[0] == -4.0f && back.u.welcome.obstacles[0].max[1] == 12.5f);
    CHECK(back.u.welcome.obstacles[1].max[2] == 7.25f && back.u.welcome.obstacles[1].min[1] == -3.0f);
    ctl_msg_fini(&back);
    /* No obstacles: the key is left out, and its absence decodes as none. */
    m.u.welcome.n_obstacles = 0;
    m.u.welcome.obstacles = NULL;
    golden(&m,
           "{\"type\":\"welcome\",\"protocol\":1,\"client_id\":9,\"role\":\"wall-tile\","
           "\"tick_hz\":60,\"snapshot_hz\":30,\"server_us\":123456,\"tick\":88,\"species\":["
           "{\"name\":\"oak\",\"url\":\"/assets/oak-0123456789abcdef.gasset\",\"hash\":"
           "\"0123456789abcdef\",\"n_modes\":32},{\"name\":\"palm\",\"url\":"
           "\"/assets/palm-fedcba9876543210.gasset\",\"hash\":\"fedcba9876543210\",\"n_modes\":16}],"
           "\"instances\":[[0,1.5,2,0,0.25,1],[1,-30,12.75,0.5,3,1.25]]}");
    /* The scenarios a kiosk may choose follow the rows. */
    ctl_scenario_info sc[2] = { { "gusty", "Gusty afternoon", CTL_SCENARIO_STEADY, 9.5f },
                                { "andrew1992", "Andrew 1992", CTL_SCENARIO_REPLAY, 0.0f } };
    m.u.welcome.n_scenarios = 2;
    m.u.welcome.scenarios = sc;
    const char *wsc =
        "{\"type\":\"welcome\",\"protocol\":1,\"client_id\":9,\"role\":\"wall-tile\","
        "\"tick_hz\":60,\"snapshot_hz\":30,\"server_us\":123456,\"tick\":88,\"species\":["
        "{\"name\":\"oak\",\"url\":\"/assets/oak-0123456789abcdef.gasset\",\"hash\":"
        "\"0123456789abcdef\",\"n_modes\":32},{\"name\":\"palm\",\"url\":"
        "\"/assets/palm-fedcba9876543210.gasset\",\"hash\":\"fedcba9876543210\",\"n_modes\":16}],"
        "\"instances\":[[0,1.5,2,0,0.25,1],[1,-30,12.75,0.5,3,1.25]],"
        "\"scenarios\":[{\"name\":\"gusty\",\"title\":\"Gusty afternoon\",\"kind\":\"steady\","
        "\"sustained_ms\":9.5},{\"name\":\"andrew1992\",\"title\":\"Andrew 1992\","
        "\"kind\":\"replay\",\"sustained_ms\":0}]}";
    golden(&m, wsc);
    CHECK(ctl_decode(wsc, strlen(wsc), CTL_MAX_SERVER_BYTES, &back, NULL, &e) == 0);
    CHECK(back.u.welcome.n_scenarios == 2);
    CHECK(strcmp(back.u.welcome.scenarios[0].title, "Gusty afternoon") == 0);
    CHECK(back.u.welcome.scenarios[0].sustained_ms == 9.5f);
    CHECK(back.u.welcome.scenarios[1].kind == CTL_SCENARIO_REPLAY);
    CHECK(strcmp(back.u.welcome.scenarios[1].name, "andrew1992") == 0);
    ctl_msg_fini(&back);
    {
        char *t = NULL;
        size_t tl = 0;
        sc[1].kind = 2;
        CHECK(ctl_encode(&m, &t, &tl, &e) == GALE_E_ARG && t == NULL);
        CHECK_STR_HAS(e.msg, "welcome.scenarios[1].kind: expected a ctl_scenario_kind, got 2");
        sc[1].kind = CTL_SCENARIO_REPLAY;
        strcpy(sc[0].title, "Gusty\nafternoon");
        CHECK(ctl_encode(&m, &t, &tl, &e) == GALE_E_RANGE && t == NULL);
        CHECK_STR_HAS(e.msg, "welcome.scenarios[0].title: expected printable text, got byte 0x0a");
        strcpy(sc[0].title, "Gusty afternoon");
        sc[0].sustained_ms = 101.0f;
        CHECK(ctl_encode(&m, &t, &tl, &e) == GALE_E_RANGE && t == NULL);
        CHECK_STR_HAS(e.msg, "welcome.scenarios[0].sustained_ms");
    }
    m.u.welcome.n_scenarios = 0;
    m.u.welcome.scenarios = NULL;
    /* The encoder refuses a box the decoder would reject. */
    ctl_obstacle flat = { { 0.0f, 0.0f, 5.0f }, { 1.0f, 1.0f, 3.0f } };
    m.u.welcome.n_obstacles = 1;
    m.u.welcome.obstacles = &flat;
    char *txt = NULL;
    size_t tn = 0;
    CHECK(ctl_encode(&m, &txt, &tn, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "ctl_encode: ctl: welcome.obstacles[0]: expected min <= max on axis z, got 5 > 3");
    CHECK(txt == NULL);
    CHECK(back.type == CTL_NONE);
    ctl_msg_fini(NULL);
}

static void round_trip_fields(void)
{
    const char *s = "{\"type\":\"hello\",\"protocol\":1,\"role\":\"load\",\"view\":{\"kind\":"
                    "\"frustum\",\"eye\":[1,2,3],\"dir\":[0,0,-1],\"fov_deg\":90,\"far_m\":"
                    "100,\"lod_m\":25}}";
    ctl_msg m;
    gale_err e;
    CHECK(ctl_decode(s, strlen(s), 0, &m, NULL, &e) == 0);
    CHECK(m.type == CTL_HELLO && m.u.hello.role == CTL_ROLE_LOAD);
    CHECK(m.u.hello.view.kind == CTL_VIEW_FRUSTUM && m.u.hello.view.eye[2] == 3.0f);
    CHECK(m.u.hello.view.dir[2] == -1.0f && m.u.hello.view.fov_deg == 90.0f);
    CHECK(m.u.hello.view.lod_m == 25.0f && m.u.hello.token[0] == '\0');
    s = " {\"type\":\"wind\",\"token\":\"t\",\"gust\":0.3}\n";
    CHECK(ctl_decode(s, strlen(s), 0, &m, NULL, &e) == 0);
    CHECK(m.u.wind.has_gust && !m.u.wind.has_speed && m.u.wind.gust == 0.3f);
    CHECK(ctl_from_client(CTL_PING) && !ctl_from_client(CTL_WELCOME));
    CHECK(strcmp(ctl_role_name(CTL_ROLE_WALL_TILE), "wall-tile") == 0);
    CHECK(ctl_role_name(9) == NULL && ctl_type_name(0) == NULL);
    CHECK(strcmp(wire_close_name(WIRE_CLOSE_BAD_TOKEN), "bad-token") == 0);
}

/* Bad input: exact message and close code. */
static void bad(const char *text, size_t len, int want_close, const char *want_msg)
{
    ctl_msg m;
    int close = 0;
    gale_err e;
    int rc = ctl_decode(text, len, 0, &m, &close, &e);
    CHECK(rc < 0);
    CHECK(close == want_close);
    if (close != want_close) {
        fprintf(stderr, "  close %d, want %d for %.60s\n", close, want_close, text);
    }
    CHECK_STR_HAS(e.msg, want_msg);
    CHECK(m.type == CTL_NONE);
}

#define BAD(text, close, msg) bad(text, sizeof text - 1, close, msg)

static void test_errors(void)
{
    BAD("{\"type\":", WIRE_CLOSE_BAD_JSON, "ctl: 1:8: invalid JSON near \":\"");
    BAD("{\"type\":\"ping\",\n \"id\": 1,,}", WIRE_CLOSE_BAD_JSON,
        "ctl: 2:11: invalid JSON near \"}\"");
    BAD("", WIRE_CLOSE_BAD_JSON, "ctl: 1:1: invalid JSON near \"\"");
    BAD("{} x", WIRE_CLOSE_BAD_JSON,
        "ctl: 1:4: trailing characters after the JSON value near \"x\"");
    BAD("{\"type\":\"ping\"}\0{}", WIRE_CLOSE_BAD_JSON, "ctl: 1:16: trailing characters");
    BAD("[1]", WIRE_CLOSE_BAD_JSON, "ctl: message: expected an object, got an array");
    BAD("{\"type\":\"ping\",\"x\":[[[[[[[[[1]]]]]]]]]}", WIRE_CLOSE_BAD_JSON,
        "ctl: message: nesting: expected <= 8 levels, got more");
    BAD("{\"id\":1}", WIRE_CLOSE_UNKNOWN_TYPE,
        "ctl: type: missing: expected a string, got nothing");
    BAD("{\"type\":3}", WIRE_CLOSE_UNKNOWN_TYPE,
        "ctl: type: wrong type: expected a string, got a number");
    BAD("{\"type\":\"launch\"}", WIRE_CLOSE_UNKNOWN_TYPE,
        "ctl: type: expected one of hello|view|wind|resync|ping|welcome|pong|error|wall_*|reset|kiosk_state|schedule, got \"launch\"");
    BAD("{\"type\":\"hello\",\"protocol\":2,\"role\":\"viewer\"}", WIRE_CLOSE_VERSION,
        "ctl: hello.protocol: expected 1, got 2");
    BAD("{\"type\":\"hello\",\"protocol\":\"1\",\"role\":\"viewer\"}", WIRE_CLOSE_BAD_FIELD,
        "ctl: hello.protocol: expected a number, got a string");
    BAD("{\"type\":\"hello\",\"protocol\":1.5,\"role\":\"viewer\"}", WIRE_CLOSE_BAD_FIELD,
        "ctl: hello.protocol: expected an integer in [0, 65535], got 1.5");
    BAD("{\"type\":\"hello\",\"role\":\"viewer\"}", WIRE_CLOSE_BAD_FIELD,
        "ctl: hello.protocol: missing: expected a number");
    BAD("{\"type\":\"hello\",\"protocol\":1,\"role\":\"admin\"}", WIRE_CLOSE_BAD_FIELD,
        "ctl: hello.role: expected one of viewer|kiosk|wall-tile|load, got \"admin\"");
    BAD("{\"type\":\"hello\",\"protocol\":1,\"role\":\"viewer\",\"colour\":1}", WIRE_CLOSE_BAD_FIELD,
        "ctl: hello: unknown key \"colour\"");
    BAD("{\"type\":\"hello\",\"protocol\":1,\"role\":\"viewer\",\"view\":{\"kind\":\"circle\","
        "\"x\":0,\"y\":0,\"radius_m\":-5}}",
        WIRE_CLOSE_BAD_FIELD, "ctl: hello.view.radius_m: expected a number in [0.001, 1000000], got -5");
    BAD("{\"type\":\"view\",\"view\":{\"kind\":\"frustum\",\"eye\":[0,0],\"dir\":[1,0,0],"
        "\"fov_deg\":60,\"far_m\":10}}",
        WIRE_CLOSE_BAD_FIELD, "ctl: view.view.eye: expected an array of 3 numbers, got an array of another length");
    BAD("{\"type\":\"view\",\"view\":{\"kind\":\"frustum\",\"eye\":[0,0,0],\"dir\":[0,0,0],"
        "\"fov_deg\":60,\"far_m\":10}}",
        WIRE_CLOSE_BAD_FIELD, "ctl: view.view.dir: expected a nonzero vector, got [0, 0, 0]");
    BAD("{\"type\":\"view\"}", WIRE_CLOSE_BAD_FIELD, "ctl: view.view: missing: expected an object");
    BAD("{\"type\":\"reset\"}", WIRE_CLOSE_BAD_FIELD, "ctl: reset.token: missing: expected a string");
    /* the exhibit's operation (ctl_ops.c) */
    BAD("{\"type\":\"kiosk_state\",\"token\":\"t\",\"lang\":\"e n\",\"audio\":\"none\"}",
        WIRE_CLOSE_BAD_FIELD, "ctl: kiosk_state.lang: expected a language tag (a letter, then "
                              "letters, digits or '-'), got \"e n\"");
    BAD("{\"type\":\"kiosk_state\",\"token\":\"t\",\"lang\":\"\",\"audio\":\"none\"}",
        WIRE_CLOSE_BAD_FIELD, "ctl: kiosk_state.lang: expected a language tag");
    BAD("{\"type\":\"kiosk_state\",\"token\":\"t\",\"lang\":\"en-GB-oxendict-x\",\"audio\":\"a\"}",
        WIRE_CLOSE_BAD_FIELD, "ctl: kiosk_state.lang: ");
    BAD("{\"type\":\"kiosk_state\",\"token\":\"t\",\"lang\":\"en\",\"audio\":\"hw:0\\u0007\"}",
        WIRE_CLOSE_BAD_FIELD, "ctl: kiosk_state.audio: expected a device name");
    BAD("{\"type\":\"kiosk_state\",\"token\":\"t\",\"lang\":\"en\"}", WIRE_CLOSE_BAD_FIELD,
        "ctl: kiosk_state.audio: missing: expected a string");
    BAD("{\"type\":\"schedule\",\"open\":false,\"next_change\":\"9:30\",\"next_in_s\":60}",
        WIRE_CLOSE_BAD_FIELD, "ctl: schedule.next_change: expected \"HH:MM\", \"HH:MM:SS\" or \"\"");
    BAD("{\"type\":\"schedule\",\"open\":false,\"next_change\":\"24:00\",\"next_in_s\":60}",
        WIRE_CLOSE_BAD_FIELD, "ctl: schedule.next_change: ");
    BAD("{\"type\":\"schedule\",\"open\":true,\"next_change\":\"\",\"next_in_s\":60}",
        WIRE_CLOSE_BAD_FIELD, "ctl: schedule.next_in_s: expected 0 exactly when next_change is");
    BAD("{\"type\":\"schedule\",\"open\":true,\"next_change\":\"17:00\",\"next_in_s\":604801}",
        WIRE_CLOSE_BAD_FIELD, "ctl: schedule.next_in_s: ");
    BAD("{\"type\":\"reset\",\"token\":\"t\",\"hard\":true}", WIRE_CLOSE_BAD_FIELD,
        "ctl: reset: unknown key \"hard\"");
    BAD("{\"type\":\"wind\",\"token\":\"t\",\"replay_paused\":1}", WIRE_CLOSE_BAD_FIELD,
        "ctl: wind.replay_paused: ");
    BAD("{\"type\":\"wind\",\"speed_ms\":10}", WIRE_CLOSE_BAD_FIELD,
        "ctl: wind.token: missing: expected a string");
    BAD("{\"type\":\"wind\",\"token\":\"t\",\"speed_ms\":1e999}", WIRE_CLOSE_BAD_FIELD,
        "ctl: wind.speed_ms: expected a number in [0, 100], got inf");
    BAD("{\"type\":\"wind\",\"token\":\"t\",\"speed_ms\":101}", WIRE_CLOSE_BAD_FIELD,
        "ctl: wind.speed_ms: expected a number in [0, 100], got 101");
    BAD("{\"type\":\"wind\",\"token\":\"0123456789012345678901234567890123456789012345678901234567890123\"}",
        WIRE_CLOSE_BAD_FIELD, "ctl: wind.token: expected at most 63 bytes, got 64");
    BAD("{\"type\":\"ping\",\"id\":-1,\"client_us\":0}", WIRE_CLOSE_BAD_FIELD,
        "ctl: ping.id: expected an integer in [0, 4294967295], got -1");
    BAD("{\"type\":\"resync\",\"seq\":null}", WIRE_CLOSE_BAD_FIELD,
        "ctl: resync.seq: expected a number, got null");
    BAD("{\"type\":\"welcome\",\"protocol\":1,\"client_id\":1,\"role\":\"viewer\",\"tick_hz\":60,"
        "\"snapshot_hz\":30,\"server_us\":0,\"tick\":0,\"species\":[{\"name\":\"oak\",\"url\":"
        "\"/a\",\"hash\":\"XYZ\",\"n_modes\":32}],\"instances\":[]}",
        WIRE_CLOSE_BAD_FIELD, "ctl: welcome.species[0].hash: expected 16 lowercase hex digits, got \"XYZ\"");
    BAD("{\"type\":\"welcome\",\"protocol\":1,\"client_id\":1,\"role\":\"viewer\",\"tick_hz\":60,"
        "\"snapshot_hz\":30,\"server_us\":0,\"tick\":0,\"species\":[{\"name\":\"oak\",\"url\":"
        "\"/a\",\"hash\":\"0123456789abcdef\",\"n_modes\":32}],\"instances\":[[1,0,0,0,0,1]]}",
        WIRE_CLOSE_BAD_FIELD, "ctl: welcome.instances[0][0]: species: expected an integer in [0, 0], got 1");
    /* Obstacles: wrong types, a short row, min > max, too many boxes. */
#define WEL_HEAD "{\"type\":\"welcome\",\"protocol\":1,\"client_id\":1,\"role\":\"viewer\"," \
                 "\"tick_hz\":60,\"snapshot_hz\":30,\"server_us\":0,\"tick\":0,\"species\":" \
                 "[{\"name\":\"oak\",\"url\":\"/a\",\"hash\":\"0123456789abcdef\",\"n_modes\":32}]," \
                 "\"instances\":[]"
    BAD(WEL_HEAD ",\"obstacles\":{}}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.obstacles: wrong type: expected an array, got an object");
    BAD(WEL_HEAD ",\"obstacles\":[[0,0,0,1,1,1],7]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.obstacles[1]: expected [min_x, min_y, min_z, max_x, max_y, max_z], got a number");
    BAD(WEL_HEAD ",\"obstacles\":[[0,0,0,1,1]]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.obstacles[0]: expected [min_x, min_y, min_z, max_x, max_y, max_z], got an array of another length");
    BAD(WEL_HEAD ",\"obstacles\":[[0,0,\"0\",1,1,1]]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.obstacles[0][2]: expected a number, got a string");
    BAD(WEL_HEAD ",\"obstacles\":[[0,0,0,1,1,2e6]]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.obstacles[0][5]: expected |value| <= 1e6, got 2000000");
    BAD(WEL_HEAD ",\"obstacles\":[[0,0,0,1,1,1],[3,0,0,2,1,1]]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.obstacles[1]: expected min <= max on axis x, got 3 > 2");
    /* Scenarios: wrong type, a bad kind, an empty name, a control byte, a wind too strong. */
    BAD(WEL_HEAD ",\"scenarios\":{}}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.scenarios: wrong type: expected an array, got an object");
    BAD(WEL_HEAD ",\"scenarios\":[{\"name\":\"a\",\"title\":\"A\",\"kind\":\"loop\","
        "\"sustained_ms\":0}]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.scenarios[0].kind: expected one of steady|replay, got \"loop\"");
    BAD(WEL_HEAD ",\"scenarios\":[{\"name\":\"\",\"title\":\"A\",\"kind\":\"steady\","
        "\"sustained_ms\":0}]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.scenarios[0].name: expected a non-empty string, got \"\"");
    BAD(WEL_HEAD ",\"scenarios\":[{\"name\":\"a\",\"title\":\"A\\u0007\",\"kind\":\"steady\","
        "\"sustained_ms\":0}]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.scenarios[0].title: expected printable text, got byte 0x07");
    BAD(WEL_HEAD ",\"scenarios\":[{\"name\":\"a\",\"title\":\"A\",\"kind\":\"steady\","
        "\"sustained_ms\":120}]}", WIRE_CLOSE_BAD_FIELD,
        "ctl: welcome.scenarios[0].sustained_ms: expected a number in [0, 100], got 120");
    BAD(WEL_HEAD ",\"scenarios\":[{\"name\":\"a\",\"title\":\"A\",\"kind\":\"steady\"}]}",
        WIRE_CLOSE_BAD_FIELD, "ctl: welcome.scenarios[0].sustained_ms: missing");
    {
        /* WIRE_MAX_OBSTACLES + 1 boxes. */
        size_t cap = sizeof WEL_HEAD + 32 + (WIRE_MAX_OBSTACLES + 1) * 16;
        char *t = malloc(cap);
        CHECK(t != NULL);
        if (t) {
            size_t n = (size_t)snprintf(t, cap, "%s,\"obstacles\":[", WEL_HEAD);
            for (unsigned i = 0; i <= WIRE_MAX_OBSTACLES; i++) {
                n += (size_t)snprintf(t + n, cap - n, "%s[0,0,0,1,1,1]", i ? "," : "");
            }
            n += (size_t)snprintf(t + n, cap - n, "]}");
            ctl_msg m;
            gale_err e;
            int close = 0;
            CHECK(ctl_decode(t, n, CTL_MAX_SERVER_BYTES, &m, &close, &e) == GALE_E_RANGE);
            CHECK(close == WIRE_CLOSE_BAD_FIELD);
            CHECK_STR_HAS(e.msg, "ctl: welcome.obstacles: expected <= 1024 entries, got 1025");
            CHECK(m.type == CTL_NONE);
            /* Exactly at the limit decodes. */
            n -= strlen(",[0,0,0,1,1,1]]}");
            memcpy(t + n, "]}", 3);
            n += 2;
            CHECK(ctl_decode(t, n, CTL_MAX_SERVER_BYTES, &m, &close, &e) == 0);
            CHECK(m.u.welcome.n_obstacles == WIRE_MAX_OBSTACLES);
            ctl_msg_fini(&m);
            free(t);
        }
    }
#undef WEL_HEAD
    /* Oversized: rejected before parsing. */
    static char big[CTL_MAX_CLIENT_BYTES + 2];
    memset(big, ' ', sizeof big);
    bad(big, CTL_MAX_CLIENT_BYTES + 1, WIRE_CLOSE_TOO_BIG,
        "ctl: message: expected <= 4096 bytes, got 4097");
    /* Exactly at the limit is fine. */
    const char *ping = "{\"type\":\"ping\",\"id\":1,\"client_us\":2}";
    memcpy(big, ping, strlen(ping));
    ctl_msg m;
    gale_err e;
    CHECK(ctl_decode(big, CTL_MAX_CLIENT_BYTES, 0, &m, NULL, &e) == 0);
    /* Encoder refuses values a decoder would reject. */
    m = (ctl_msg){ .type = CTL_WIND };
    strcpy(m.u.wind.token, "t");
    m.u.wind.has_speed = true;
    m.u.wind.speed_ms = NAN;
    char *out = NULL;
    size_t n = 0;
    CHECK(ctl_encode(&m, &out, &n, &e) == GALE_E_RANGE);
    CHECK(out == NULL);
    m = (ctl_msg){ .type = 77 };
    CHECK(ctl_encode(&m, &out, &n, &e) == GALE_E_ARG);
    CHECK_STR_HAS(e.msg, "ctl_encode: type: expected a ctl_type, got 77");
    char tiny[8];
    m = (ctl_msg){ .type = CTL_RESYNC };
    CHECK(ctl_encode_into(&m, tiny, sizeof tiny, &n, &e) == GALE_E_RANGE);
}


/* ---- the encoder's self-check, kept here rather than on the send path ---------------- */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint32_t rnd(uint32_t n)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)((rng_state >> 33) % n);
}

/* A float near the limits the decoder checks, or an ordinary one. */
static float edge_float(void)
{
    static const float edges[] = { 0.0f,   -0.0f, 1e-45f, 1e-3f,  0.9e-3f, 0.1f,  0.09f,
                                   1.0f,   0.5f,  179.0f, 180.0f, 100.0f,  101.0f, 360.0f,
                                   1000.0f, 1001.0f, 1e6f, 1.0000001e6f, -1e6f, -1.0000001e6f,
                                   NAN,    INFINITY, -INFINITY, -1.0f };
    if (rnd(3) == 0) {
        return (float)rnd(2000000) / 100.0f - 10000.0f;
    }
    return edges[rnd(sizeof edges / sizeof edges[0])];
}

static void fill_str(char *s, size_t cap)
{
    static const char chars[] = "abcXYZ019 -_/\"\\\t\n\x01\xc3\xa9";
    size_t n = rnd(4) == 0 ? cap - 1 : rnd((uint32_t)cap);
    for (size_t i = 0; i < n; i++) {
        s[i] = chars[rnd(sizeof chars - 1)];
    }
    s[n] = '\0';
}

static void fill_view(ctl_view *v)
{
    v->kind = (int)rnd(4) - (rnd(8) == 0 ? 1 : 0); /* now and then not a kind */
    v->x = edge_float();
    v->y = edge_float();
    v->radius_m = edge_float();
    for (int k = 0; k < 3; k++) {
        v->eye[k] = edge_float();
        v->dir[k] = rnd(3) ? edge_float() : 0.0f;
    }
    v->fov_deg = edge_float();
    v->far_m = edge_float();
    v->lod_m = rnd(2) ? edge_float() : 0.0f;
}

/* A random message of a random type, often with a value a decoder rejects. Arrays point
 * into the caller's storage. */
static void fill_msg(ctl_msg *m, ctl_species *sp, ctl_instance *in, ctl_obstacle *ob,
                     ctl_scenario_info *sc)
{
    memset(m, 0, sizeof *m);
    m->type = 1 + (int)rnd(11);
    if (m->type >= 9) { /* the types past CTL_PONG/CTL_ERROR that this test fills */
        m->type = (int[]){ CTL_RESET, CTL_KIOSK_STATE, CTL_SCHEDULE }[m->type - 9];
    }
    static const uint64_t us[] = { 0, 1, 9007199254740992ull, 9007199254740993ull,
                                   9007199254740994ull, UINT64_MAX, 123456789 };
    switch (m->type) {
    case CTL_HELLO:
        m->u.hello.protocol = rnd(8) ? WIRE_PROTOCOL_VERSION : 2;
        m->u.hello.role = (int)rnd(5);
        fill_view(&m->u.hello.view);
        fill_str(m->u.hello.token, sizeof m->u.hello.token);
        break;
    case CTL_VIEW:
        fill_view(&m->u.view);
        break;
    case CTL_WIND:
        fill_str(m->u.wind.token, sizeof m->u.wind.token);
        m->u.wind.has_speed = rnd(2);
        m->u.wind.speed_ms = edge_float();
        m->u.wind.has_dir = rnd(2);
        m->u.wind.dir_deg = edge_float();
        m->u.wind.has_gust = rnd(2);
        m->u.wind.gust = rnd(2) ? (float)rnd(100) / 80.0f : edge_float();
        m->u.wind.has_scenario = rnd(2);
        fill_str(m->u.wind.scenario, sizeof m->u.wind.scenario);
        m->u.wind.has_replay_paused = rnd(2);
        m->u.wind.replay_paused = rnd(2);
        break;
    case CTL_RESET:
        fill_str(m->u.reset.token, sizeof m->u.reset.token);
        break;
    case CTL_KIOSK_STATE:
        fill_str(m->u.kiosk_state.token, sizeof m->u.kiosk_state.token);
        fill_str(m->u.kiosk_state.lang, sizeof m->u.kiosk_state.lang);
        if (rnd(2)) {
            snprintf(m->u.kiosk_state.lang, sizeof m->u.kiosk_state.lang, "de-CH");
        }
        fill_str(m->u.kiosk_state.audio, sizeof m->u.kiosk_state.audio);
        if (rnd(2)) {
            snprintf(m->u.kiosk_state.audio, sizeof m->u.kiosk_state.audio, "none");
        }
        break;
    case CTL_SCHEDULE:
        m->u.schedule.open = rnd(2);
        snprintf(m->u.schedule.next_change, sizeof m->u.schedule.next_change, "%s",
                 (const char *[]){ "", "09:30", "23:59:59", "24:00", "9:3" }[rnd(5)]);
        m->u.schedule.next_in_s = rnd(2) ? 0 : rnd(3) ? 3600 : 604801;
        break;
    case CTL_RESYNC:
        m->u.resync_seq = rnd(2) ? UINT32_MAX : rnd(1000);
        break;
    case CTL_PING:
        m->u.ping = (ctl_ping){ rnd(2) ? UINT32_MAX : rnd(9), us[rnd(7)] };
        break;
    case CTL_PONG:
        m->u.pong = (ctl_pong){ rnd(9), us[rnd(7)], us[rnd(7)], rnd(2) ? UINT32_MAX : 7 };
        break;
    case CTL_ERROR:
        m->u.error.code = rnd(2) ? 4000 + (int)rnd(12) : (int)rnd(6000);
        fill_str(m->u.error.message, sizeof m->u.error.message);
        break;
    default: { /* CTL_WELCOME */
        ctl_welcome *w = &m->u.welcome;
        w->protocol = rnd(8) ? WIRE_PROTOCOL_VERSION : 0;
        w->client_id = rnd(100);
        w->role = (int)rnd(5);
        w->tick_hz = rnd(2) ? 60.0f : edge_float();
        w->snapshot_hz = rnd(2) ? 30.0f : edge_float();
        w->server_us = us[rnd(7)];
        w->tick = rnd(1000);
        w->n_species = rnd(4);
        w->species = sp;
        for (uint32_t i = 0; i < 3; i++) {
            fill_str(sp[i].name, sizeof sp[i].name);
            fill_str(sp[i].url, sizeof sp[i].url);
            snprintf(sp[i].hash, sizeof sp[i].hash, "%s",
                     rnd(4) ? "0123456789abcdef" : rnd(2) ? "0123456789ABCDEF" : "0123");
            sp[i].n_modes = rnd(4) ? 1 + rnd(64) : rnd(2) ? 0 : 65;
        }
        w->n_instances = rnd(4);
        w->instances = in;
        for (uint32_t i = 0; i < 3; i++) {
            in[i] = (ctl_instance){ rnd(4), { edge_float(), edge_float(), edge_float() },
                                    edge_float(), rnd(2) ? 1.0f : edge_float() };
        }
        w->n_obstacles = rnd(3);
        w->obstacles = ob;
        for (uint32_t i = 0; i < 2; i++) {
            for (int k = 0; k < 3; k++) {
                ob[i].min[k] = rnd(2) ? (float)rnd(10) : edge_float();
                ob[i].max[k] = rnd(2) ? ob[i].min[k] + (float)rnd(10) : edge_float();
            }
        }
        w->n_scenarios = rnd(3);
        w->scenarios = sc;
        for (uint32_t i = 0; i < 2; i++) {
            fill_str(sc[i].name, sizeof sc[i].name);
            fill_str(sc[i].title, sizeof sc[i].title);
            sc[i].kind = (int)rnd(3);
            sc[i].sustained_ms = rnd(2) ? (float)rnd(100) : edge_float();
        }
        break;
    }
    }
}

/* Whatever ctl_encode and ctl_encode_into write, ctl_decode accepts, and the decoded
 * message encodes again; a refusal is a range or argument error with the same text from
 * both encoders. Both outcomes must occur often. */
static void test_encode_self_check(void)
{
    int accepted = 0, refused = 0;
    bool all = true;
    for (int it = 0; it < 40000; it++) {
        ctl_species sp[3];
        ctl_instance in[3];
        ctl_obstacle ob[2];
        ctl_scenario_info sc[2];
        ctl_msg m;
        fill_msg(&m, sp, in, ob, sc);
        char *s = NULL;
        size_t n = 0;
        gale_err e = { 0 };
        int rc = ctl_encode(&m, &s, &n, &e);
        char small[8192];
        size_t n2 = 0;
        gale_err e2 = { 0 };
        int rc2 = ctl_encode_into(&m, small, sizeof small, &n2, &e2);
        if (rc) {
            refused++;
            bool ok = (rc == GALE_E_RANGE || rc == GALE_E_ARG) && s == NULL &&
                      strncmp(e.msg, "ctl_encode: ", 12) == 0 && rc2 == rc &&
                      strcmp(e.msg, e2.msg) == 0;
            if (!ok) {
                fprintf(stderr, "  type %d refused with %d: %s\n", m.type, rc, e.msg);
            }
            all &= ok;
            continue;
        }
        accepted++;
        ctl_msg back;
        int close = -1;
        bool ok = rc2 == 0 && n2 == n && strcmp(small, s) == 0;
        ok = ok && ctl_decode(s, n, CTL_MAX_SERVER_BYTES, &back, &close, &e) == 0 &&
             close == 0 && back.type == m.type;
        if (ok) {
            /* The decoded message encodes again: to the same text, except that a
             * direction of 360 degrees decodes as 0. */
            char *again = NULL;
            size_t n3 = 0;
            ok = ctl_encode(&back, &again, &n3, &e) == 0 &&
                 ((n3 == n && strcmp(again, s) == 0) || (m.type == CTL_WIND && m.u.wind.has_dir));
            free(again);
            ctl_msg_fini(&back);
        }
        if (!ok) {
            fprintf(stderr, "  encoded but not decoded back alike: %s (%s)\n", s, e.msg);
        }
        all &= ok;
        free(s);
    }
    CHECK(all);
    CHECK(accepted > 5000 && refused > 5000);
}

int main(void)
{
    RUN(test_golden);
    RUN(round_trip_fields);
    RUN(test_errors);
    RUN(test_encode_self_check);
    return check_report();
}
