/* The bake pipeline (PHYSICS.md "Data flow"): skeleton + species -> frame elements -> lowest
 * modes -> wind projection basis -> length-true pose fields -> tube mesh -> asset, with a
 * report of what it found and how long each stage took. */
#ifndef GALE_BAKE_H
#define GALE_BAKE_H

#include <stdint.h>
#include <stdio.h>

#include "asset.h"
#include "err.h"
#include "pose_check.h"
#include "skeleton.h"
#include "species.h"

/* 2: CORR holds the length-true pose's fields (PHYSICS.md "Length-true pose"); 3: they
 * carry the static correction of the truncated modes (PHYSICS.md "Static correction") */
#define BAKE_VERSION 3
#define BAKE_MAX_MODES 256

typedef struct bake_desc {
    int n_modes;            /* modes kept, 1..BAKE_MAX_MODES; 0: 32 */
    const char *params_json; /* borrowed: what the asset was baked from (copied); NULL: "{}" */
    uint64_t source_hash;   /* stored in the asset as given */
} bake_desc;

typedef struct bake_report {
    int nodes, modes;
    double mass_kg;         /* total mass of the frame model (root element included) */
    double seconds;         /* wall time of the whole bake */
    double seconds_fem, seconds_eigen, seconds_basis, seconds_correction, seconds_mesh;
    int eigen_dense;        /* 1: dense LAPACK path (small model), 0: ARPACK shift-invert */
    int eigen_iterations;   /* Lanczos restart cycles */
    int eigen_solves;       /* solves with the tree Cholesky of K */
    double eigen_residual;  /* max |K φ - ω² M φ| / |K φ| */
    double ortho_error;     /* max |Φ^T M Φ - I| */
    double static_residual_m; /* largest node translation of the static correction r_k over
                                 nodes and k, per unit w_k [m per m²/s²] */
    pose_check pose;        /* branch lengths, small-q error, deflection against wind speed */
} bake_report;

/* Bakes skeleton s with species sp (mechanics, drag, look) into *a (caller-owned struct,
 * arrays owned by it afterwards: asset_fini). rep may be NULL. On failure *a is left empty
 * and err names the stage. */
int bake_run(const skeleton *s, const species *sp, const bake_desc *d, asset *a,
             bake_report *rep, gale_err *err);

/* The report as JSON text (malloc'd, caller frees; NULL when out of memory): nodes, modes,
 * frequencies_hz, damping_ratios, seconds, branch_length_error, eigen, timings. */
char *bake_report_json(const asset *a, const bake_report *rep);

/* A readable report on out. */
void bake_report_print(FILE *out, const asset *a, const bake_report *rep);

/* 64-bit FNV-1a of n bytes, continuing from h (start with BAKE_HASH_SEED). */
#define BAKE_HASH_SEED 0xcbf29ce484222325ull
uint64_t bake_hash(uint64_t h, const void *data, size_t n);

#endif
