/* The modes' static response to a steady wind force vector w (tree frame, [m²/s²]: the
 * modal force is f_i = p_i·w, p_i the wind basis): q_i = p_i·w / ω_i², the balance of
 * q̈_i + γ_i q̇_i + ω_i² q_i = f_i at rest. The damage table's static residual and
 * check (damage_table.c) and the bake's static correction of the pose (bake/statics.c)
 * both take the modes' static share from here. Header-only. */
#ifndef GALE_MODAL_STATIC_H
#define GALE_MODAL_STATIC_H

#include <stdint.h>

/* G_i,k = p_i,k / ω_i²: q_i per unit w_k [kg^½ m per m²/s²]; 0 for ω_i = 0. */
static inline double modal_static_gain(const float *omega, const float *wind_basis, uint32_t i,
                                       int k)
{
    const double w2 = (double)omega[i] * (double)omega[i];
    return w2 > 0.0 ? (double)wind_basis[3 * i + k] / w2 : 0.0;
}

#endif
