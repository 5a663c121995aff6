/* A fallen tree tipping over (PROTOCOL.md "DAMAGE" SNAP/UPROOT): the stem as a rigid
 * pole of length L pivoting at its base, θ'' = (3g / 2L) sin θ (a uniform rod about one
 * end: torque m g (L/2) sin θ, inertia m L² / 3). Started from a small lean θ0 with the
 * speed of a pole that left upright at rest (the energy of the upright pole:
 * θ'² = 2ω² (1 - cos θ), ω² = 3g / 2L), the motion has the closed form
 *     θ(t) = 4 atan(tan(θ0 / 4) e^(ω t)),
 * and stops where the crown meets the ground (TIP_FALL_LYING_RAD). */
#ifndef GALE_TIP_FALL_H
#define GALE_TIP_FALL_H

#include <stdint.h>

#define TIP_FALL_G_MS2 9.81
#define TIP_FALL_LEAN0_RAD 0.05    /* the lean the storm gave it when the stem gave way */
#define TIP_FALL_LYING_RAD 1.536   /* 88°: the crown resting on the ground */

/* θ [rad] t_s seconds after the stem gave way, for a stem height_m tall: 0 before
 * (t_s < 0), then the closed form above, then lying. */
double tip_fall_angle(double t_s, double height_m);

/* Seconds from giving way to lying. */
double tip_fall_duration_s(double height_m);

/* Where a snapped stem breaks: a hashed height per tree between these [m, tree frame at
 * unit scale], low on the stem where the base moment is largest (PHYSICS.md "Storm damage"
 * → "On screen": the stump stands, the part above tips about the break). */
#define TIP_FALL_BREAK_MIN_M 0.5f
#define TIP_FALL_BREAK_SPAN_M 1.0f

/* The break height [m, tree frame at unit scale] of tree `tree` when it snaps; an
 * uprooted tree pivots at 0. shaders/common.glsl stump_break_m is the same bits
 * (tests/test_render_damage.c holds the GPU to it). */
float tip_fall_break_m(uint32_t tree);

#endif
