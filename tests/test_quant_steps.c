/* Tests of the server's quantisation-step derivation (server/sim/quant_steps.h): steps
 * follow eps * H / max |a b φ̂| per mode (|φ̂| where b = 0; φ̂ the drawn shape, phi with the
 * static correction's share), and a bad height is refused by name. */
#include <string.h>

#include "check.h"
#include "quant_steps.h"
#include "wire_limits.h"

/* A tiny asset: 2 nodes, 2 modes; steps follow eps * H / max |a b phi|. */
static void test_quant_steps(void)
{
    float phi[2 * 2 * 3] = { 0, 0, 0, 3, 4, 0, /* mode 0: |phi| max 5 */
                             0, 0, 0, 0, 0, 0 /* mode 1 moves nothing */ };
    float ca[2] = { 2.0f, 1.0f }, cb[2] = { 0.5f, 1.0f };
    asset a = { 0 };
    strcpy(a.species, "t");
    a.n_nodes = 2;
    a.n_modes = 2;
    a.height_m = 10.0f;
    a.phi = phi;
    float steps[WIRE_MAX_MODES];
    gale_err e;
    CHECK(quant_steps_derive(&a, 0.01f, steps, &e) == 0);
    CHECK_NEAR(steps[0], 0.01 * 10 / 5, 1e-7);
    CHECK_NEAR(steps[1], 0.01 * 10, 1e-7);
    a.corr_v = phi;
    a.corr_a = ca;
    a.corr_b = cb;
    CHECK(quant_steps_derive(&a, 0.0f, steps, &e) == 0);
    CHECK_NEAR(steps[0], 1e-3 * 10 / (5 * 2.0 * 0.5), 1e-8);
    /* b = 0: q~ = q, the slope is phi itself; the pose fields (rotations) are not lengths */
    float rot[12] = { 0, 0, 0, 0, 9, 0, 0, 0, 0, 0, 0, 0 };
    a.corr_v = rot;
    cb[0] = 0.0f;
    CHECK(quant_steps_derive(&a, 0.0f, steps, &e) == 0);
    CHECK_NEAR(steps[0], 1e-3 * 10 / 5, 1e-8);
    /* with the static correction (ASSET.md SRES) the slope is the drawn shape φ̂: here
     * ω = 2, 4 and p = x̂, ŷ give A = diag(4, 16) over x, y (z: no mode, dropped), so
     * φ̂_0 = (3, 4, 0) + 4 (0, 0, 3) = (3, 4, 12), |13|, and φ̂_1 = 16 (0.25, 0, 0), |4| */
    float om[2] = { 2.0f, 4.0f }, wb[6] = { 1, 0, 0, 0, 1, 0 };
    float res[3 * 2 * 3] = { 0, 0, 0, 0, 0, 3, /* r_x */
                             0, 0, 0, 0.25f, 0, 0, /* r_y */
                             0, 0, 0, 0, 0, 7 /* r_z: no mode sees a z load */ };
    a.omega = om;
    a.wind_basis = wb;
    a.static_res = res;
    CHECK(quant_steps_derive(&a, 0.0f, steps, &e) == 0);
    CHECK_NEAR(steps[0], 1e-3 * 10 / 13, 1e-8);
    CHECK_NEAR(steps[1], 1e-3 * 10 / 4, 1e-8);
    a.static_res = NULL;
    a.height_m = NAN;
    CHECK(quant_steps_derive(&a, 0.01f, steps, &e) == GALE_E_RANGE);
    CHECK_STR_HAS(e.msg, "quant_steps_derive: t: height_m: expected > 0, got nan");
}

int main(void)
{
    RUN(test_quant_steps);
    return check_report();
}
