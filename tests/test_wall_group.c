/* Wall groups (server/serve/wall_group.h) as plain logic on a given clock, and the wall_*
 * control messages (protocol/ctl_wall.c): a barrier closes once when every tile reported,
 * a lagging tile is left out after the budget (or when another tile is on to the next
 * frame) and is in again at its next report, a late joiner gets the group's clock, a
 * leaving tile releases a barrier waiting on it, the camera reaches every tile stamped
 * with one frame; the messages round-trip and bad ones name their field. Counts only. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "ctl.h"
#include "wall_group.h"
#include "wire.h"

#define MAX_SENT 256

typedef struct sent {
    uint32_t conn;
    ctl_msg m;
} sent;

static sent S[MAX_SENT];
static int n_sent;

static void on_send(void *user, uint32_t conn, const char *text, size_t len)
{
    (void)user;
    if (n_sent < MAX_SENT) {
        gale_err e = { 0 };
        S[n_sent].conn = conn;
        CHECK(ctl_decode(text, len, CTL_MAX_SERVER_BYTES, &S[n_sent].m, NULL, &e) == 0);
        n_sent++;
    }
}

/* Swaps sent for frame since index `from`, and whether each went out with `drawn`. */
static int swaps(int from, uint32_t frame, uint32_t drawn)
{
    int n = 0;
    for (int i = from; i < n_sent; i++) {
        if (S[i].m.type == CTL_WALL_SWAP && S[i].m.u.wall_frame.frame == frame) {
            CHECK(S[i].m.u.wall_frame.drawn == drawn);
            n++;
        }
    }
    return n;
}

static const ctl_wall_join J = { .wall = "w", .tile = "t", .swap_lock = true, .rate_hz = 60,
                                 .budget_ms = 8, .delay_ms = 100 };

static void test_barrier(void)
{
    wall_groups *g = wall_groups_create(on_send, NULL);
    char why[128];
    ctl_wall_sync sy[4];
    for (uint32_t c = 1; c <= 4; c++) {
        CHECK(wall_groups_join(g, c, &J, 1000000 + c, &sy[c - 1], why, sizeof why) == 0);
    }
    CHECK(sy[0].epoch_us == 1000001 && sy[3].epoch_us == 1000001); /* one clock */
    CHECK(sy[0].period_us == 16667 && sy[3].members == 4 && sy[3].delay_us == 100000);
    /* all four report frame 10: one swap to each, all in */
    n_sent = 0;
    for (uint32_t c = 1; c <= 4; c++) {
        CHECK(wall_groups_drawn(g, c, 10, 2000000, why, sizeof why) == 0);
        CHECK(n_sent == (c < 4 ? 0 : 4));
    }
    CHECK(swaps(0, 10, 4) == 4);
    /* frame 11: tile 4 lags; before the budget nothing, after it the other three swap */
    n_sent = 0;
    for (uint32_t c = 1; c <= 3; c++) {
        CHECK(wall_groups_drawn(g, c, 11, 2016000, why, sizeof why) == 0);
    }
    wall_groups_poll(g, 2016000 + 7999);
    CHECK(n_sent == 0);
    wall_groups_poll(g, 2016000 + 8000);
    CHECK(swaps(0, 11, 3) == 4);
    /* its late report of 11 changes nothing; it is in again at 12 */
    int before = n_sent;
    CHECK(wall_groups_drawn(g, 4, 11, 2030000, why, sizeof why) == 0);
    CHECK(n_sent == before);
    for (uint32_t c = 1; c <= 4; c++) {
        CHECK(wall_groups_drawn(g, c, 12, 2033000, why, sizeof why) == 0);
    }
    CHECK(swaps(before, 12, 4) == 4);
    /* frame 13: tiles 1-3 in, then tile 1 reports 14: 13 closes without tile 4 */
    before = n_sent;
    for (uint32_t c = 1; c <= 3; c++) {
        CHECK(wall_groups_drawn(g, c, 13, 2050000, why, sizeof why) == 0);
    }
    CHECK(wall_groups_drawn(g, 1, 14, 2051000, why, sizeof why) == 0);
    CHECK(swaps(before, 13, 3) == 4);
    /* frame 14 open with tile 1 in: tiles 2 and 3 report, tile 4 leaves: 14 closes */
    before = n_sent;
    CHECK(wall_groups_drawn(g, 2, 14, 2052000, why, sizeof why) == 0);
    CHECK(wall_groups_drawn(g, 3, 14, 2052000, why, sizeof why) == 0);
    CHECK(n_sent == before);
    wall_groups_leave(g, 4, 2053000);
    CHECK(swaps(before, 14, 3) == 3);
    wall_group_stats st = wall_groups_get_stats(g);
    CHECK(st.swaps == 5 && st.complete == 3 && st.left_out == 2 && st.late == 1);
    CHECK(st.members == 3);
    /* tile 4 restarts: the same clock, four members again */
    ctl_wall_sync again;
    CHECK(wall_groups_join(g, 5, &J, 9000000, &again, why, sizeof why) == 0);
    CHECK(again.epoch_us == sy[0].epoch_us && again.members == 4);
    /* a report before joining is out of order */
    CHECK(wall_groups_drawn(g, 99, 1, 9000000, why, sizeof why) == WIRE_CLOSE_ORDER);
    CHECK_STR_HAS(why, "wall_drawn: before wall_join");
    wall_groups_destroy(g);
}

static void test_camera(void)
{
    wall_groups *g = wall_groups_create(on_send, NULL);
    char why[128];
    ctl_wall_sync sy;
    for (uint32_t c = 1; c <= 3; c++) {
        CHECK(wall_groups_join(g, c, &J, 0, &sy, why, sizeof why) == 0);
    }
    n_sent = 0;
    ctl_wall_camera cam = { .wall = "w", .target_m = { 1, 2, 3 }, .distance_m = 30,
                            .yaw_deg = 45, .pitch_deg = -20 };
    CHECK(wall_groups_camera(g, &cam, 1000000, why, sizeof why) == 0);
    CHECK(n_sent == 3);
    /* 1.1 s after the epoch (the lead) at 16.667 ms a frame is within frame 65: from 66 */
    for (int i = 0; i < n_sent; i++) {
        CHECK(S[i].m.type == CTL_WALL_CAMERA && S[i].m.u.wall_camera.frame == 66);
        CHECK(S[i].m.u.wall_camera.distance_m == 30.0f);
    }
    /* a late joiner gets the camera with the same frame */
    n_sent = 0;
    CHECK(wall_groups_join(g, 4, &J, 2000000, &sy, why, sizeof why) == 0);
    CHECK(n_sent == 1 && S[0].conn == 4 && S[0].m.u.wall_camera.frame == 66);
    cam.wall[0] = 'x';
    CHECK(wall_groups_camera(g, &cam, 1000000, why, sizeof why) == WIRE_CLOSE_BAD_FIELD);
    CHECK_STR_HAS(why, "wall_camera.wall: no tile of \"x\" has joined");
    wall_groups_destroy(g);
}

static void round_trip(const ctl_msg *m)
{
    char *text = NULL;
    size_t len = 0;
    gale_err e = { 0 };
    CHECK(ctl_encode(m, &text, &len, &e) == 0);
    ctl_msg back;
    CHECK(text && ctl_decode(text, len, CTL_MAX_SERVER_BYTES, &back, NULL, &e) == 0);
    CHECK(back.type == m->type);
    CHECK(memcmp(&back.u, &m->u, sizeof back.u) == 0);
    free(text);
}

static void test_messages(void)
{
    ctl_msg m;
    memset(&m, 0, sizeof m);
    m.type = CTL_WALL_JOIN;
    m.u.wall_join = J;
    round_trip(&m);
    memset(&m, 0, sizeof m);
    m.type = CTL_WALL_SYNC;
    m.u.wall_sync = (ctl_wall_sync){ .wall = "w", .epoch_us = 123456789012, .period_us = 16667,
                                     .delay_us = 100000, .budget_ms = 8, .swap_lock = true,
                                     .members = 4 };
    round_trip(&m);
    memset(&m, 0, sizeof m);
    m.type = CTL_WALL_SWAP;
    m.u.wall_frame = (ctl_wall_frame){ .frame = 77, .drawn = 3, .members = 4 };
    round_trip(&m);
    memset(&m, 0, sizeof m);
    m.type = CTL_WALL_DRAWN;
    m.u.wall_frame.frame = 78;
    round_trip(&m);
    memset(&m, 0, sizeof m);
    m.type = CTL_WALL_CAMERA;
    m.u.wall_camera = (ctl_wall_camera){ .wall = "w", .frame = 9, .target_m = { 1.5f, -2, 4 },
                                         .distance_m = 40, .yaw_deg = 55, .pitch_deg = -25 };
    round_trip(&m);
    CHECK(ctl_from_client(CTL_WALL_JOIN) && ctl_from_client(CTL_WALL_DRAWN) &&
          ctl_from_client(CTL_WALL_CAMERA));
    CHECK(!ctl_from_client(CTL_WALL_SYNC) && !ctl_from_client(CTL_WALL_SWAP));
    struct {
        const char *text, *msg;
    } bad[] = {
        { "{\"type\":\"wall_join\",\"wall\":\"w\",\"tile\":\"t\",\"rate_hz\":500}",
          "ctl: wall_join.rate_hz: expected" },
        { "{\"type\":\"wall_join\",\"wall\":\"w\",\"rate_hz\":60}",
          "ctl: wall_join.tile: missing" },
        { "{\"type\":\"wall_drawn\",\"frame\":-1}", "ctl: wall_drawn.frame: expected" },
        { "{\"type\":\"wall_drawn\",\"frame\":1,\"x\":2}", "ctl: wall_drawn: unknown key \"x\"" },
        { "{\"type\":\"wall_camera\",\"wall\":\"w\",\"target_m\":[0,0],\"distance_m\":5,"
          "\"yaw_deg\":0,\"pitch_deg\":0}",
          "ctl: wall_camera.target_m" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ctl_msg x;
        gale_err e = { 0 };
        CHECK(ctl_decode(bad[i].text, strlen(bad[i].text), 0, &x, NULL, &e) != 0);
        CHECK_STR_HAS(e.msg, bad[i].msg);
    }
}

int main(void)
{
    RUN(test_barrier);
    RUN(test_camera);
    RUN(test_messages);
    return check_report();
}
