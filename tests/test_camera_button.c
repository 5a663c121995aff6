/* The kiosk's camera button (client/kiosk/camera_button.c): its rectangle scales with the
 * framebuffer height (twice the pixels at 4K as at 1080p, the same share of the screen),
 * sits in the right-hand corner on screen, is hit inside and missed outside in window
 * coordinates (also on a HiDPI window whose framebuffer is twice its size), and each press
 * steps street → garden → roof → aerial → tour → street. */
#include <string.h>

#include "camera_button.h"
#include "lang.h"
#include "camera_preset.h"
#include "check.h"

static void test_layout(void)
{
    camera_button_rect a = camera_button_layout(1920, 1080), b = camera_button_layout(3840, 2160);
    CHECK(a.x0 > 960.0f && a.x1 <= 1920.0f && a.y0 > 0.0f && a.y1 < 540.0f); /* top right */
    CHECK_NEAR(b.x1 - b.x0, 2.0f * (a.x1 - a.x0), 1e-3);
    CHECK_NEAR(b.y1 - b.y0, 2.0f * (a.y1 - a.y0), 1e-3);
    CHECK_NEAR(b.x0, 2.0f * a.x0, 1e-3);
    CHECK_NEAR(b.y0, 2.0f * a.y0, 1e-3);
    CHECK(a.y1 - a.y0 >= 60.0f); /* a finger's width at 1080p */
    camera_button_rect z = camera_button_layout(0, 0);
    CHECK(z.x1 == 0.0f && z.y1 == 0.0f);
    camera_button_rect n = camera_button_layout(100, 1080); /* narrower than the button */
    CHECK(n.x0 >= 0.0f);
}

static void test_hit(void)
{
    camera_button_rect a = camera_button_layout(1920, 1080);
    double cx = 0.5 * (double)(a.x0 + a.x1), cy = 0.5 * (double)(a.y0 + a.y1);
    CHECK(camera_button_hit(1920, 1080, 1920, 1080, cx, cy));
    CHECK(camera_button_hit(1920, 1080, 1920, 1080, (double)a.x0, (double)a.y0));
    CHECK(!camera_button_hit(1920, 1080, 1920, 1080, (double)a.x1, cy)); /* exclusive edges */
    CHECK(!camera_button_hit(1920, 1080, 1920, 1080, cx, (double)a.y1));
    CHECK(!camera_button_hit(1920, 1080, 1920, 1080, (double)a.x0 - 1.0, cy));
    CHECK(!camera_button_hit(1920, 1080, 1920, 1080, cx, (double)a.y0 - 1.0));
    CHECK(!camera_button_hit(1920, 1080, 1920, 1080, 10.0, 10.0)); /* the HUD panel */
    /* 4K framebuffer behind a 1920x1080 window (scale 2): the same window point hits */
    CHECK(camera_button_hit(3840, 2160, 1920, 1080, cx, cy));
    CHECK(!camera_button_hit(3840, 2160, 1920, 1080, 2.0 * cx, 2.0 * cy));
    /* 4K window: the 4K rectangle's centre */
    camera_button_rect b = camera_button_layout(3840, 2160);
    CHECK(camera_button_hit(3840, 2160, 3840, 2160, 0.5 * (double)(b.x0 + b.x1),
                            0.5 * (double)(b.y0 + b.y1)));
    CHECK(!camera_button_hit(1920, 1080, 0, 0, cx, cy)); /* minimised */
}

static void test_cycle(void)
{
    const char *order[] = { "street", "garden", "roof", "aerial", "tour", "street" };
    int p = -1; /* the fitted view */
    for (int i = 0; i < 6; i++) {
        p = camera_button_next(p);
        CHECK(strcmp(camera_preset_name(p), order[i]) == 0);
    }
    CHECK(camera_button_next(CAMERA_PRESET_COUNT) == CAMERA_PRESET_STREET);
    char buf[32];
    camera_button_label(LANG_EN, CAMERA_PRESET_AERIAL, buf, sizeof buf);
    CHECK(strcmp(buf, "Camera: aerial") == 0);
    camera_button_label(LANG_EN, -1, buf, sizeof buf);
    CHECK(strcmp(buf, "Camera") == 0);
    camera_button_label(LANG_EN, CAMERA_PRESET_TOUR, buf, sizeof buf);
    CHECK(strcmp(buf, "Camera: tour") == 0);
}

int main(void)
{
    RUN(test_layout);
    RUN(test_hit);
    RUN(test_cycle);
    return check_report();
}
