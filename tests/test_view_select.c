/* Tests of the server's interest and LOD selection (server/serve/view_select.h): circle
 * and frustum views with LOD and margins, against positions worked out by hand. */
#include "check.h"
#include "view_select.h"

/* Circle and frustum interest with LOD, against positions worked out by hand. */
static void test_view_select(void)
{
    const float pos[5 * 3] = { 0, 0, 0, 50, 0, 0, 0, 120, 0, -10, 0, 0, 0, 104, 0 };
    const uint8_t full[5] = { 32, 32, 16, 32, 32 };
    uint8_t n[5];
    ctl_view all = { .kind = CTL_VIEW_ALL };
    view_select(&all, 5, pos, full, 0, 8, n);
    CHECK(n[0] == 32 && n[2] == 16 && n[4] == 32);
    /* Circle at the origin, radius 100, LOD beyond 40 m, 5 m margin. */
    ctl_view c = { .kind = CTL_VIEW_CIRCLE, .radius_m = 100, .lod_m = 40 };
    view_select(&c, 5, pos, full, 5, 8, n);
    CHECK(n[0] == 32);  /* centre */
    CHECK(n[1] == 8);   /* 50 m: inside, beyond LOD */
    CHECK(n[2] == 0);   /* 120 m: outside */
    CHECK(n[3] == 32);  /* 10 m */
    CHECK(n[4] == 8);   /* 104 m: outside the radius, inside the margin */
    /* Frustum from (0, -10, 0) looking +y, 90 degrees, far 150. */
    ctl_view f = { .kind = CTL_VIEW_FRUSTUM, .eye = { 0, -10, 0 }, .dir = { 0, 2, 0 },
                   .fov_deg = 90, .far_m = 150 };
    view_select(&f, 5, pos, full, 0, 8, n);
    CHECK(n[0] == 32);  /* on the axis, 10 m ahead */
    CHECK(n[1] == 0);   /* (50, 10): 78.7 degrees off axis */
    CHECK(n[2] == 16);  /* 130 m ahead */
    CHECK(n[3] == 32);  /* (-10, 10): exactly on the 45 degree edge */
    f.far_m = 100;
    view_select(&f, 5, pos, full, 0, 8, n);
    CHECK(n[2] == 0 && n[4] == 0);
    view_select(&f, 5, pos, full, 20, 8, n);
    CHECK(n[4] == 32 && n[1] == 0); /* 114 m within far + margin; 50 m across is not */
}

int main(void)
{
    RUN(test_view_select);
    return check_report();
}
