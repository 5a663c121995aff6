/* The frame-time governor (client/render/governor.h) on made-up frame times: it steps down
 * while frames are well over the target, back up while well under, waits longer before a
 * step up than a step down, holds between the two thresholds (no flip-flop on a frame time
 * just over a step's worth of room), starts low on a software renderer and stays off
 * without a target. */
#include "check.h"
#include "governor.h"

/* Feeds frames of ms at 1/fps s apart from t for s seconds; returns the end time. */
static double feed(governor *g, double ms, double t, double s)
{
    for (double end = t + s; t < end; t += ms * 1e-3) {
        governor_frame(g, ms, t);
    }
    return t;
}

static void test_steps_down_and_up(void)
{
    governor g;
    governor_init(&g, 33.0, false, 0.0);
    CHECK(g.step == 0);
    CHECK_NEAR(governor_lod_scale(&g), 1.0f, 1e-6f);
    CHECK_NEAR(governor_res_scale(&g), 1.0f, 1e-6f);
    double t = feed(&g, 80.0, 0.0, 3.5); /* well over: a step a second after the first */
    CHECK(g.step == 3);
    CHECK_NEAR(governor_lod_scale(&g), 0.421875f, 1e-6f);
    CHECK_NEAR(governor_res_scale(&g), 0.7f, 1e-6f);
    t = feed(&g, 80.0, t, 10.0);
    CHECK(g.step == GOVERNOR_MAX_STEP);
    CHECK_NEAR(governor_res_scale(&g), GOVERNOR_RES_MIN, 1e-6f); /* never below */
    /* well under: a step up once 8 frames say so, the next 4 s later */
    t = feed(&g, 10.0, t, 3.5);
    CHECK(g.step == GOVERNOR_MAX_STEP - 1);
    t = feed(&g, 10.0, t, 1.0);
    CHECK(g.step == GOVERNOR_MAX_STEP - 2);
    t = feed(&g, 10.0, t, 40.0);
    CHECK(g.step == 0);
    (void)t;
}

static void test_holds_in_the_band(void)
{
    governor g;
    governor_init(&g, 33.0, false, 0.0);
    double t = feed(&g, 60.0, 0.0, 1.5);
    CHECK(g.step == 1);
    unsigned changes = g.changes;
    /* 25 ms: under the target, not under 0.6 of it; 36 ms: over, not 1.15 over */
    t = feed(&g, 25.0, t, 30.0);
    t = feed(&g, 36.0, t, 30.0);
    CHECK(g.step == 1 && g.changes == changes);
    (void)t;
}

static void test_software_and_off(void)
{
    governor g;
    CHECK(governor_software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
    CHECK(governor_software_renderer("Google SwiftShader"));
    CHECK(!governor_software_renderer("NVIDIA GeForce RTX 3060/PCIe/SSE2"));
    CHECK(!governor_software_renderer(NULL));
    governor_init(&g, 33.0, true, 0.0);
    CHECK(g.step == GOVERNOR_SOFTWARE_STEP);
    governor_init(&g, 0.0, true, 0.0);
    CHECK(g.step == 0);
    feed(&g, 500.0, 0.0, 20.0);
    CHECK(g.step == 0 && g.changes == 0);
    /* a frame time that is no number changes nothing */
    governor_init(&g, 33.0, false, 0.0);
    CHECK(!governor_frame(&g, -1.0, 5.0) && g.smooth_ms == 0.0);
}

int main(void)
{
    RUN(test_steps_down_and_up);
    RUN(test_holds_in_the_band);
    RUN(test_software_and_off);
    return check_report();
}
