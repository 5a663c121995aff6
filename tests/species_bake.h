/* Test helper: a shipped species (configs/species/NAME.json) baked at 32 modes, as the
 * server bakes it, with its damage table. */
#ifndef GALE_TEST_SPECIES_BAKE_H
#define GALE_TEST_SPECIES_BAKE_H

#include <stdio.h>
#include <string.h>

#include "bake.h"
#include "damage_table.h"
#include "lsystem.h"
#include "species.h"

/* Bakes NAME into *a and builds *t from it; *sp holds the species file (drag law,
 * drag_c). 0, or the error code with the message printed, naming the species. */
static inline int bake_shipped_species(const char *name, species *sp, asset *a, damage_table *t)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, name);
    gale_err err;
    memset(&err, 0, sizeof err);
    skeleton s;
    memset(&s, 0, sizeof s);
    bake_desc d = { .n_modes = 32 };
    int rc = species_load(path, sp, &err);
    rc = rc ? rc : lsystem_generate(&sp->gen, &s, &err);
    rc = rc ? rc : bake_run(&s, sp, &d, a, NULL, &err);
    rc = rc ? rc : damage_table_build(a, sp->E_pa, sp->drag_c, &sp->damage, t, &err);
    skeleton_fini(&s);
    if (rc) {
        fprintf(stderr, "%s: %s\n", name, err.msg);
    }
    return rc;
}

#endif
