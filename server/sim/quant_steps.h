/* Quantisation steps of the snapshot stream (PROTOCOL.md "Quantisation of q"): per species and
 * mode, the step of q that keeps every node's error under a fraction of the tree height.
 * Server policy: the wire carries the steps in every keyframe, a client only applies them. */
#ifndef GALE_QUANT_STEPS_H
#define GALE_QUANT_STEPS_H

#include "asset.h"
#include "err.h"

/* Default relative node error per mode: step_i = eps * H / max_node |d u / d q_i|. */
#define QUANT_STEPS_DEFAULT_EPS 1.0e-3f

/* Quantisation steps for one species: steps[i] = eps * H / s_i with s_i the largest
 * displacement per unit q_i over all nodes at q = 0 (the length-true pose's slope there is
 * the drawn shape φ̂ (asset_pose_shapes: phi with the static correction's share) times
 * dq~/dq: |a_i b_i| max |φ̂_i| for q~ = a atan(b q), max |φ̂_i| where b_i = 0 or no pose
 * fields are baked). eps = 0 means QUANT_STEPS_DEFAULT_EPS. Writes a->n_modes steps into the
 * caller's steps (at least WIRE_MAX_MODES long). A mode that moves nothing gets
 * step = eps * H. Fails with GALE_E_ARG (eps outside (0, 1)), GALE_E_RANGE (n_modes or
 * height_m out of range) or GALE_E_NUMERIC (a step that is not finite and > 0); the
 * message names the species. Does not allocate. */
int quant_steps_derive(const asset *a, float eps, float *steps, gale_err *err);

#endif
