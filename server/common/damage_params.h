/* Storm-damage constants of one species (PHYSICS.md "Storm damage"): green-wood strength,
 * the ForestGALES critical-moment coefficients (Gardiner et al. 2000, 2008; Hale et al.
 * 2012), the spread of per-tree strength and the leaf-stripping law. Read from the
 * `damage` section of a species file (species.h), used by the simulation (damage.h). */
#ifndef GALE_DAMAGE_PARAMS_H
#define GALE_DAMAGE_PARAMS_H

typedef struct damage_params {
    double mor_pa;             /* modulus of rupture, green wood [Pa] */
    double f_knot;             /* knot factor of M_break, 0..1 (ForestGALES) */
    double stem_density_kg_m3; /* green stem density for the stem mass of M_over */
    double c_reg_nm_kg;        /* overturning regression coefficient [N m / kg] */
    double strength_sd;        /* sd of the log of the per-tree strength multiplier */
    double leaf_drag_share;    /* fraction of a crown's drag the leaves carry, 0..1 */
    double strip_max;          /* leaf area a storm strips at most (Hugo plateau), 0..1 */
} damage_params;

/* Defaults: a temperate broadleaf (ForestGALES oak row: MOR 59 MPa, f_knot 1, 1158
 * kg/m³, C_reg 230.8 N m/kg on deep free-draining soil). */
static inline damage_params damage_params_default(void)
{
    return (damage_params){ .mor_pa = 59e6,
                            .f_knot = 1.0,
                            .stem_density_kg_m3 = 1158.0,
                            .c_reg_nm_kg = 230.8,
                            .strength_sd = 0.2,
                            .leaf_drag_share = 0.6,
                            .strip_max = 0.8 };
}

#endif
