/* Quantisation steps of q from each mode's largest node displacement per unit q at rest:
 * see quant_steps.h. */
#include "quant_steps.h"

#include <math.h>

#include "wire_limits.h"

int quant_steps_derive(const asset *a, float eps, float *steps, gale_err *err)
{
    if (eps == 0.0f) {
        eps = QUANT_STEPS_DEFAULT_EPS;
    }
    if (!(eps > 0.0f && eps < 1.0f)) {
        return gale_errf(err, GALE_E_ARG, "quant_steps_derive: eps: expected (0, 1), got %g",
                         (double)eps);
    }
    if (a->n_modes == 0 || a->n_modes > WIRE_MAX_MODES) {
        return gale_errf(err, GALE_E_RANGE,
                         "quant_steps_derive: %s: n_modes: expected 1..%u, got %u", a->species,
                         WIRE_MAX_MODES, a->n_modes);
    }
    if (!(a->height_m > 0.0f) || !isfinite(a->height_m)) {
        return gale_errf(err, GALE_E_RANGE,
                         "quant_steps_derive: %s: height_m: expected > 0, got %g", a->species,
                         (double)a->height_m);
    }
    const float h_m = a->height_m;
    /* the drawn shapes φ̂_m = φ_m + Σ_k r_k A_k,m (asset_pose_shapes) node by node, without
     * a copy: the static correction's share of each mode (ASSET.md "SRES") */
    double A[3 * WIRE_MAX_MODES];
    const float *res = a->static_res && a->omega && a->wind_basis ? a->static_res : NULL;
    if (res) {
        asset_static_map(a->omega, a->wind_basis, a->n_modes, A);
    }
    const size_t nc = 3 * (size_t)a->n_nodes;
    for (uint32_t m = 0; m < a->n_modes; m++) {
        /* Largest node displacement per unit q_m at q = 0: the length-true pose's slope
         * there is φ̂ times dq̃/dq = a b (q̃ = a atan(b q); 1 where b = 0, q̃ = q), see
         * PHYSICS.md "Length-true pose". */
        const float *v = a->phi;
        float gain = 1.0f;
        if (a->corr_a && a->corr_b && a->corr_b[m] != 0.0f) {
            gain = fabsf(a->corr_a[m] * a->corr_b[m]);
        }
        float smax = 0.0f;
        if (v) {
            const float *vm = v + (size_t)m * a->n_nodes * 3;
            for (uint32_t i = 0; i < a->n_nodes; i++) {
                float d[3];
                for (size_t c = 0; c < 3; c++) {
                    double x = (double)vm[3 * i + c];
                    for (size_t k = 0; res && k < 3; k++) {
                        x += (double)res[k * nc + 3 * i + c] * A[k * a->n_modes + m];
                    }
                    d[c] = (float)x;
                }
                float s2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                smax = s2 > smax ? s2 : smax;
            }
        }
        smax = sqrtf(smax) * gain;
        float step = eps * h_m;
        if (smax > 0.0f && isfinite(smax)) {
            step = eps * h_m / smax;
        }
        if (!(step > 0.0f) || !isfinite(step)) {
            return gale_errf(err, GALE_E_NUMERIC,
                             "quant_steps_derive: %s: mode %u: step: expected finite > 0, got %g",
                             a->species, m, (double)step);
        }
        steps[m] = step;
    }
    return 0;
}
