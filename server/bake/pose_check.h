/* What the bake report says about the pose (PHYSICS.md "Length-true pose",
 * "Streamlining"): branch-length change of the linear and the length-true pose under a
 * static wind pose of all modes, the length-true pose's departure from the linear
 * response at small amplitude, and the static deflection against wind speed with and
 * without streamlining. All through asset_reconstruct, the form clients draw. */
#ifndef GALE_POSE_CHECK_H
#define GALE_POSE_CHECK_H

#include "asset.h"
#include "drag_law.h"

#define POSE_CHECK_SPEEDS 4

typedef struct pose_check {
    /* static wind pose along +x, all modes, scaled so the linear pose's largest node
     * displacement is 20 % (10 %) of the height: max relative branch-length change */
    double len_linear_20, len_pose_20, len_linear_10, len_pose_10;
    /* the same pose scaled to 0.1 % of the height: max |pose − linear| / max |linear| */
    double small_q_err;
    /* static deflection (largest node displacement of the pose) at speed_ms[k] at the
     * crown, rigid drag (∝ U²) and streamlined (the species' drag_law) [m] */
    double speed_ms[POSE_CHECK_SPEEDS];
    double defl_rigid_m[POSE_CHECK_SPEEDS], defl_stream_m[POSE_CHECK_SPEEDS];
} pose_check;

/* Static modal state for a steady wind of u_ms along +x: q_i = s(U) U² p_i,x / ω_i²,
 * s = drag_law_scale (d NULL: rigid). q[a->n_modes]. */
void pose_check_static_q(const asset *a, const drag_law *d, double u_ms, float *q);

/* Fills *pc for asset a (with its CORR fields) and drag law d; zeroes it when out of
 * memory. */
void pose_check_run(const asset *a, const drag_law *d, pose_check *pc);

#endif
