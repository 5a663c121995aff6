/* A species: its JSON file under configs/species/ holds the L-system generator
 * parameters (lsystem.h), the wood and damping constants the bake needs, and the
 * look of bark and leaves. */
#ifndef GALE_SPECIES_H
#define GALE_SPECIES_H

#include "drag_law.h"
#include "damage_params.h"
#include "err.h"
#include "lsystem.h"

typedef struct species {
    char name[64];
    /* mechanics (Diener 2008 section 3; PHYSICS.md "Beam model") */
    double E_pa;           /* Young's modulus [Pa]; default 1e10 */
    double rho_kg_m3;      /* wood density [kg/m^3]; default 1000 */
    double G_pa;           /* shear modulus [Pa]; default E/2.6 */
    double rayleigh_alpha; /* [1/s]  C = alpha M + beta K (Diener eq. 9) */
    double rayleigh_beta;  /* [s] */
    double drag_c;         /* C of p_i = C ∫ D φ_i ds: ½ ρ_air C_D [kg/m^3]; D is the
                            * branch diameter only, so C lumps the foliage's frontal area
                            * too and may well exceed ½ ρ_air (shipped: 0.25-1.8) */
    drag_law drag;         /* streamlining of C_d with speed, the species file's "drag" */
    /* storm damage (PHYSICS.md "Storm damage"): the `damage` section */
    damage_params damage;
    /* generator */
    lsystem_params gen;
    /* look */
    float bark_rgb[3];
    float leaf_rgb[3];
    int leaf_shape;        /* 0 broad leaf, 1 palm frond leaflet, 2 needle tuft */
    float leaf_size_m;     /* blade length */
    int leaves_per_tip;    /* leaf slots on each terminal node */
    float leaf_spread_deg; /* how far blade normals stray from the twig's side [deg] */
} species;

/* The defaults every key falls back to (a plain broadleaf, E = 1e10 Pa, ρ = 1000). */
void species_default(species *sp);

/* Parses a species JSON document (text of `name`, for messages) into *sp. Unknown keys,
 * wrong types, out-of-range values and bytes after the object are errors naming the key
 * path or line. sp->gen.where gets `name`, so lsystem_generate's failures name the file
 * and the generator key. */
int species_parse(const char *text, size_t len, const char *name, species *sp, gale_err *err);

/* Reads and parses a species file. */
int species_load(const char *path, species *sp, gale_err *err);

#endif
