/* Camera presets (client/kiosk/camera_preset.c): names, and where each puts the eye over a small
 * scene of palms (south) and oaks (north): street level 1.7 m up outside the planting
 * looking north at a palm, the garden view looking south at an oak, roof height about
 * 12 m, aerial high above; the tour moves to the next stop every CAMERA_TOUR_STOP_S; the
 * fall view looks across a fall from the side without trees in the way. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "camera_preset.h"
#include "check.h"

static ctl_species sp[2];
static ctl_instance inst[6];

static void scene(void)
{
    snprintf(sp[0].name, sizeof sp[0].name, "oak");
    snprintf(sp[1].name, sizeof sp[1].name, "palm");
    const float pos[6][2] = { { -10, 20 }, { 10, 25 }, { 0, 30 }, { -6, -20 }, { 0, -25 }, { 6, -20 } };
    for (int i = 0; i < 6; i++) {
        inst[i] = (ctl_instance){ .species = i < 3 ? 0u : 1u, .pos = { pos[i][0], pos[i][1], 0 },
                                  .scale = 1 };
    }
}

static void test_names(void)
{
    for (int p = 0; p < CAMERA_PRESET_COUNT; p++) {
        CHECK(camera_preset_find(camera_preset_name(p)) == p);
    }
    CHECK(camera_preset_find("street") == CAMERA_PRESET_STREET);
    CHECK(camera_preset_find("lobby") == -1);
    CHECK(camera_preset_find(NULL) == -1);
    CHECK(strcmp(camera_preset_name(99), "?") == 0);
}

static void test_places(void)
{
    camera c;
    float eye[3], f[3];
    camera_preset_apply(&c, CAMERA_PRESET_STREET, inst, 6, sp, 2);
    camera_eye(&c, eye);
    camera_forward(&c, f);
    CHECK_NEAR(eye[2], 1.7, 0.05);
    CHECK(eye[1] < -25.0f); /* south of every tree */
    CHECK(f[1] > 0.9f);     /* looking north */
    CHECK_NEAR(c.target[1], -25.0, 1e-4); /* the palm nearest the south edge */
    camera_preset_apply(&c, CAMERA_PRESET_GARDEN, inst, 6, sp, 2);
    camera_eye(&c, eye);
    camera_forward(&c, f);
    CHECK(eye[1] > 30.0f);
    CHECK(f[1] < -0.9f);
    CHECK_NEAR(c.target[1], 30.0, 1e-4); /* the oak nearest the north edge */
    camera_preset_apply(&c, CAMERA_PRESET_ROOF, inst, 6, sp, 2);
    camera_eye(&c, eye);
    CHECK_NEAR(eye[2], 12.0, 0.5);
    camera_preset_apply(&c, CAMERA_PRESET_AERIAL, inst, 6, sp, 2);
    camera_eye(&c, eye);
    CHECK(eye[2] > 50.0f);
}

static void test_tour(void)
{
    camera a, b;
    camera_preset_tour(&a, 1.0, inst, 6, sp, 2);
    camera_preset_apply(&b, CAMERA_PRESET_STREET, inst, 6, sp, 2);
    CHECK_NEAR(a.target[1], b.target[1], 1e-5);
    CHECK_NEAR(a.yaw - b.yaw, 1.0 * 0.0174533, 1e-4); /* one degree a second */
    camera_preset_tour(&a, CAMERA_TOUR_STOP_S + 1.0, inst, 6, sp, 2);
    camera_preset_apply(&b, CAMERA_PRESET_GARDEN, inst, 6, sp, 2);
    CHECK_NEAR(a.target[1], b.target[1], 1e-5);
    camera_preset_tour(&a, 4 * CAMERA_TOUR_STOP_S + 1.0, inst, 6, sp, 2); /* wraps */
    camera_preset_apply(&b, CAMERA_PRESET_STREET, inst, 6, sp, 2);
    CHECK_NEAR(a.target[1], b.target[1], 1e-5);
}

/* the fall view: across the fall, at the middle of the stem's arc, from the side without
 * trees in the way */
static void test_fall(void)
{
    /* tree 0 falls east (+x); a row of trees just north of it, none to the south */
    ctl_instance f[5] = { { .pos = { 0, 0, 0 }, .scale = 1 } };
    for (int i = 1; i < 5; i++) {
        f[i] = (ctl_instance){ .pos = { 2.0f + 3.0f * (float)i, 8.0f, 0 }, .scale = 1 };
    }
    camera c;
    CHECK(camera_preset_fall(&c, f, 5, 0, 20.0f, 0.0f) == 0);
    float fw[3], eye[3];
    camera_forward(&c, fw);
    camera_eye(&c, eye);
    fprintf(stderr, "fall view: eye %.1f %.1f %.1f, target %.1f %.1f %.1f\n", (double)eye[0],
            (double)eye[1], (double)eye[2], (double)c.target[0], (double)c.target[1],
            (double)c.target[2]);
    CHECK(fabsf(fw[0]) < 0.05f);                 /* across the fall */
    CHECK(eye[1] < -10.0f);                      /* from the south, the clear side */
    CHECK(fabsf(c.target[0] - 9.0f) < 0.5f && fabsf(c.target[2] - 6.0f) < 0.5f);
    /* the same trees to the south: the view turns to the north */
    for (int i = 1; i < 5; i++) {
        f[i].pos[1] = -8.0f;
    }
    camera_preset_fall(&c, f, 5, 0, 20.0f, 0.0f);
    camera_eye(&c, eye);
    CHECK(eye[1] > 10.0f);
    /* a tree outside the scene leaves the camera as it was */
    camera before = c;
    CHECK(camera_preset_fall(&c, f, 5, 7, 20.0f, 0.0f) == UINT32_MAX);
    CHECK(memcmp(&before, &c, sizeof c) == 0);
}

int main(void)
{
    scene();
    RUN(test_names);
    RUN(test_places);
    RUN(test_tour);
    RUN(test_fall);
    return check_report();
}
