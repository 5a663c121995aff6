/* Streamlining drag (server/common/drag_law.h, PHYSICS.md "Streamlining") through the
 * modal tick: the force grows as U^(2+B) between U_0 and the fit's top, as U² below U_0,
 * as U² again above the top with "hold"; a tree's drag factor scales its force; the
 * shipped species carry their Vogel exponents, and a bad "drag" section is refused by
 * key path. drag_pow against pow, and the tick's force scale against drag_law_scale. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "drag_law.h"
#include "modal.h"
#include "species.h"

/* q after one step from rest under a steady wind u along x: b1 · f, so q ∝ the force */
static double force_q(const drag_law *d, float u, float mult)
{
    const float omega[1] = { 3.0f }, gamma[1] = { 0.2f }, p[3] = { 0.7f, 0.0f, 0.0f };
    const float step[1] = { 1e-4f };
    modal_species sp = { .n_modes = 1, .omega = omega, .gamma = gamma, .wind_basis = p,
                         .qstep = step };
    uint8_t ts[1] = { 0 };
    gale_err e;
    modal *m = modal_create(&(modal_desc){ .n_trees = 1, .n_species = 1, .species = &sp,
                                           .tree_species = ts, .species_drag = d,
                                           .dt_s = 0.01, .n_threads = 1 },
                            &e);
    CHECK(m != NULL);
    if (!m) {
        return 0.0;
    }
    if (mult != 1.0f) {
        modal_set_drag_mult(m, 0, mult);
        CHECK(modal_drag_mult(m, 0) == mult);
    }
    const float wind[3] = { u, 0.0f, 0.0f };
    modal_tick(m, wind, NULL);
    float q;
    modal_get(m, 0, &q, NULL);
    modal_destroy(m);
    return (double)q;
}

static void test_exponent(void)
{
    const float bs[4] = { -0.5f, -0.75f, -0.85f, -0.9f };
    for (int k = 0; k < 4; k++) {
        const drag_law d = { .vogel_b = bs[k], .u0_ms = 10.0f, .fit_max_ms = 25.0f };
        const double f1 = force_q(&d, 12.0f, 1.0f), f2 = force_q(&d, 22.0f, 1.0f);
        const double want = pow(22.0 / 12.0, 2.0 + (double)bs[k]);
        CHECK(f1 > 0.0);
        CHECK_NEAR(f2 / f1, want, 0.01 * want);
        /* "extend" carries the exponent above the fit's top */
        const double f3 = force_q(&d, 60.0f, 1.0f);
        const double want3 = pow(60.0 / 22.0, 2.0 + (double)bs[k]);
        CHECK_NEAR(f3 / f2, want3, 0.01 * want3);
    }
}

static void test_rigid_below_u0_and_hold(void)
{
    const drag_law d = { .vogel_b = -0.85f, .u0_ms = 10.0f, .fit_max_ms = 25.0f,
                         .hold_above_fit = 1 };
    /* below U_0: rigid, ∝ U² (a breeze as with drag_c alone) */
    CHECK_NEAR(force_q(&d, 8.0f, 1.0f) / force_q(&d, 4.0f, 1.0f), 4.0, 0.04);
    const drag_law rigid = { 0 };
    CHECK_NEAR(force_q(&d, 9.0f, 1.0f), force_q(&rigid, 9.0f, 1.0f), 1e-12);
    /* above the top with "hold": C_d frozen at its value there, ∝ U² again */
    CHECK_NEAR(force_q(&d, 60.0f, 1.0f) / force_q(&d, 30.0f, 1.0f), 4.0, 0.04);
    /* no species_drag at all: rigid */
    CHECK_NEAR(force_q(NULL, 40.0f, 1.0f) / force_q(NULL, 20.0f, 1.0f), 4.0, 0.04);
}

static void test_tree_factor(void)
{
    const drag_law d = { .vogel_b = -0.75f, .u0_ms = 10.0f, .fit_max_ms = 25.0f };
    const double f = force_q(&d, 30.0f, 1.0f), h = force_q(&d, 30.0f, 0.4f);
    CHECK_NEAR(h / f, 0.4, 1e-5);
    CHECK(force_q(&d, 30.0f, 0.0f) == 0.0);
}

static void test_species_files(void)
{
    const char *names[3] = { "oak", "pine", "palm" };
    const float want[3] = { -0.85f, -0.75f, -0.75f };
    for (int k = 0; k < 3; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, names[k]);
        species sp;
        gale_err e;
        CHECK(species_load(path, &sp, &e) == GALE_OK);
        CHECK(sp.drag.vogel_b == want[k]);
        CHECK(sp.drag.u0_ms == 10.0f && sp.drag.fit_max_ms == 25.0f && sp.drag.hold_above_fit);
    }
    static const char bad_mode[] =
        "{\"name\": \"t\", \"drag\": {\"vogel_b\": -0.5, \"above_fit\": \"stop\"}}";
    static const char bad_b[] = "{\"name\": \"t\", \"drag\": {\"vogel_b\": 0.5}}";
    static const char bad_key[] = "{\"name\": \"t\", \"drag\": {\"vogel\": -0.5}}";
    static const char bad_top[] =
        "{\"name\": \"t\", \"drag\": {\"u0_ms\": 20, \"fit_max_ms\": 15}}";
    species sp;
    gale_err e;
    CHECK(species_parse(bad_mode, strlen(bad_mode), "t.json", &sp, &e) != GALE_OK);
    CHECK_STR_HAS(e.msg, "drag.above_fit");
    CHECK(species_parse(bad_b, strlen(bad_b), "t.json", &sp, &e) != GALE_OK);
    CHECK_STR_HAS(e.msg, "drag.vogel_b");
    CHECK(species_parse(bad_key, strlen(bad_key), "t.json", &sp, &e) != GALE_OK);
    CHECK_STR_HAS(e.msg, "vogel");
    CHECK(species_parse(bad_top, strlen(bad_top), "t.json", &sp, &e) != GALE_OK);
    CHECK_STR_HAS(e.msg, "drag.fit_max_ms");
}

/* drag_pow against double pow: x from 1 to 2^16 (every float in [1, 1 + 2^-10], then a
 * dense geometric sweep) and B over [-1.5, 0]: within 5e-7, exactly 1 at x = 1 or B = 0
 * (continuous at U_0), and never rising with x for B < 0. */
static void test_pow_accuracy(void)
{
    double worst = 0.0;
    int bad_one = 0, rising = 0;
    for (int kb = 0; kb <= 60; kb++) {
        const float b = -1.5f * (float)kb / 60.0f;
        float last = 2.0f;
        for (int i = 0; i < 200000; i++) {
            const float x = i < 8192 ? 1.0f + (float)i * 0x1p-23f
                                     : (float)pow(2.0, 16.0 * (i - 8192) / (200000.0 - 8192.0));
            const float got = drag_pow(x, b);
            const double want = pow((double)x, (double)b);
            worst = fmax(worst, fabs((double)got - want) / want);
            rising += b < 0.0f && i != 8192 && got > last; /* the sweep starts again at 1 */
            last = got;
        }
        bad_one += drag_pow(1.0f, b) != 1.0f;
        bad_one += drag_pow(3.7f, 0.0f) != 1.0f;
    }
    CHECK(worst <= 5e-7);
    CHECK(bad_one == 0);
    CHECK(rising == 0);
    fprintf(stderr, "  drag_pow: worst relative error %.2e, %d steps up\n", worst, rising);
}

/* The tick's force scale (the block's powers in vectors) is drag_law_scale's, float for
 * float, for trees of two species over speeds across U_0 and the fit's top, in a count
 * that leaves a partial block. */
static void test_tick_scale(void)
{
    enum { NT = 203 };
    const float omega[2] = { 3.0f, 4.0f }, gamma[2] = { 0.2f, 0.2f };
    const float p[6] = { 0.7f, 0.1f, 0.0f, 0.5f, 0.2f, 0.1f }, step[2] = { 1e-4f, 1e-4f };
    const modal_species sp[2] = { { .n_modes = 1, .omega = omega, .gamma = gamma,
                                    .wind_basis = p, .qstep = step },
                                  { .n_modes = 1, .omega = omega + 1, .gamma = gamma + 1,
                                    .wind_basis = p + 3, .qstep = step + 1 } };
    const drag_law dl[2] = { { .vogel_b = -0.85f, .u0_ms = 10.0f, .fit_max_ms = 25.0f,
                               .hold_above_fit = 1 },
                             { .vogel_b = -0.6f, .u0_ms = 8.0f, .fit_max_ms = 30.0f } };
    uint8_t ts[NT];
    static float wind[3 * NT];
    for (int t = 0; t < NT; t++) {
        ts[t] = (uint8_t)(t % 3 == 0);
        const float u = 0.37f * (float)t;
        wind[3 * t] = 0.8f * u;
        wind[3 * t + 1] = -0.6f * u;
        wind[3 * t + 2] = 0.01f * u;
    }
    gale_err e;
    modal *m = modal_create(&(modal_desc){ .n_trees = NT, .n_species = 2, .species = sp,
                                           .tree_species = ts, .species_drag = dl,
                                           .dt_s = 0.01, .n_threads = 1 },
                            &e);
    CHECK(m != NULL);
    if (!m) {
        return;
    }
    modal_tick(m, wind, NULL);
    int differ = 0;
    for (int t = 0; t < NT; t++) {
        const float *w = wind + 3 * t;
        const float u = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        differ += modal_get_rows(m).force_scale[t] != u * drag_law_scale(&dl[ts[t]], u);
    }
    CHECK(differ == 0);
    modal_destroy(m);
}

int main(void)
{
    RUN(test_pow_accuracy);
    RUN(test_tick_scale);
    RUN(test_exponent);
    RUN(test_rigid_below_u0_and_hold);
    RUN(test_tree_factor);
    RUN(test_species_files);
    return check_report();
}
