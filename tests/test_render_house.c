/* House meshes without a GL context: a box becomes 42 vertices (14 triangles) that stay
 * inside the box and touch all six of its faces, walls up to the eaves and a roof above
 * them with the ridge along the longer side at the box top, unit normals facing out of
 * the box, and the attributes shaders/house.vert reads (eave height, material). */
#include <math.h>
#include <string.h>

#include "check.h"
#include "render_house.h"

#define F  RENDER_HOUSE_FLOATS
#define NV RENDER_HOUSE_VERTS

static float mesh[2 * NV * F];

static void test_counts_and_bounds(void)
{
    /* 12 m along x, 8 m along y, 6 m high, from (2, -3, 0) */
    const float box[6] = { 2.0f, -3.0f, 0.0f, 14.0f, 5.0f, 6.0f };
    memset(mesh, 0, sizeof mesh);
    float *end = render_house_mesh(box, mesh);
    CHECK(end == mesh + NV * F);
    CHECK(NV == 42 && NV % 3 == 0);
    float lo[3] = { 1e9f, 1e9f, 1e9f }, hi[3] = { -1e9f, -1e9f, -1e9f };
    for (int v = 0; v < NV; v++) {
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], mesh[F * v + k]);
            hi[k] = fmaxf(hi[k], mesh[F * v + k]);
        }
    }
    for (int k = 0; k < 3; k++) {
        CHECK_NEAR(lo[k], box[k], 1e-5);
        CHECK_NEAR(hi[k], box[k + 3], 1e-5);
    }
    /* nothing written past the box's vertices */
    for (int i = NV * F; i < 2 * NV * F; i++) {
        CHECK(mesh[i] == 0.0f);
    }
}

static void test_roof_and_walls(void)
{
    const float box[6] = { 2.0f, -3.0f, 0.0f, 14.0f, 5.0f, 6.0f };
    render_house_mesh(box, mesh);
    /* eaves: the roof takes 40 % of the height unless the pitch (0.84 x half width) is
       lower; here min(2.4, 0.84 x 4 = 3.36) = 2.4, so the eaves are at 3.6 m */
    const float zw = 6.0f - 2.4f;
    int roof = 0, walls = 0, ridge = 0, gable_tips = 0;
    for (int v = 0; v < NV; v++) {
        const float *o = &mesh[F * v];
        float nlen = sqrtf(o[3] * o[3] + o[4] * o[4] + o[5] * o[5]);
        CHECK_NEAR(nlen, 1.0, 1e-5);
        CHECK_NEAR(o[8], zw - box[2], 1e-5); /* wall height attribute */
        if (o[10] == 1.0f) {
            roof++;
            CHECK(o[2] >= zw - 1e-5f);
            CHECK(o[5] > 0.0f); /* roof planes face up */
            if (o[2] == box[5]) {
                ridge++;
                CHECK_NEAR(o[1], 0.5f * (box[1] + box[4]), 1e-5); /* ridge along x, mid y */
            }
        } else {
            CHECK(o[10] == 0.0f);
            walls++;
            CHECK(fabsf(o[5]) < 1e-6f); /* walls are vertical */
            /* gable tips reach the ridge; every other wall vertex stays below the eaves */
            CHECK(o[2] <= zw + 1e-5f || (o[2] == box[5] && o[3] != 0.0f));
            if (o[2] == box[5]) {
                gable_tips++;
                CHECK_NEAR(o[1], 0.5f * (box[1] + box[4]), 1e-5); /* under the ridge */
            }
        }
    }
    CHECK(roof == 12);      /* two planes, two triangles each */
    CHECK(gable_tips == 2); /* one gable triangle on each end wall reaches the ridge */
    CHECK(walls == 30);     /* four walls of two triangles, two gable triangles */
    CHECK(ridge == 6);      /* three ridge vertices on each roof plane */
}

static void test_ridge_follows_longer_side(void)
{
    /* longer along y: the ridge runs along y, at mid x */
    const float box[6] = { 0.0f, 0.0f, 1.0f, 2.0f, 10.0f, 4.0f };
    render_house_mesh(box, mesh);
    int ridge = 0;
    for (int v = 0; v < NV; v++) {
        const float *o = &mesh[F * v];
        if (o[10] == 1.0f && o[2] == box[5]) {
            ridge++;
            CHECK_NEAR(o[0], 1.0, 1e-5);
        }
    }
    CHECK(ridge == 6);
    /* narrow box: the pitch limit sets the roof, 0.84 x 1 < 0.4 x 3; eaves 0.84 m below
       the top, 3 - 0.84 m above the base */
    CHECK_NEAR(mesh[8], 3.0 - 0.84, 1e-5);
}

int main(void)
{
    RUN(test_counts_and_bounds);
    RUN(test_roof_and_walls);
    RUN(test_ridge_follows_longer_side);
    return check_report();
}
