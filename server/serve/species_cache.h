/* Species assets for the server: each species of the scene is baked on start (species
 * JSON -> L-system skeleton -> bake.h -> asset) or loaded from a cache folder where baked
 * assets are kept by the hash of what they were baked from (the species file's bytes,
 * the mode count and the bake version, as gale-bake computes it). The file bytes are
 * served to clients by their own content hash (PHYSICS.md "Data flow": bake on first
 * use, cached by content hash). */
#ifndef GALE_SPECIES_CACHE_H
#define GALE_SPECIES_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "asset.h"
#include "drag_law.h"
#include "damage_table.h"
#include "err.h"
#include "wire.h"

typedef struct species_entry {
    asset a;                      /* decoded asset (arrays owned by it) */
    uint8_t *bytes;               /* owned: the asset file as served */
    size_t len;
    char hash[17];                /* content hash of bytes (hash64), 16 hex digits */
    uint64_t source_hash;         /* cache key: what it was baked from */
    float qstep[WIRE_MAX_MODES];  /* quantisation steps (quant_steps_derive) */
    drag_law drag;                /* the species file's streamlining (species.h) */
    bool baked;                   /* baked now rather than read from the cache */
    double seconds;               /* time to bake or load */
    char path[512];               /* cache file */
    damage_table damage;          /* storm damage (damage_table.h) from the asset, the wood's
                                     E and the species file's damage section */
} species_entry;

/* Fills *e for the species file with n_modes modes: from cache_dir when a valid entry
 * with the same source hash is there, else by baking it and storing the result (written
 * atomically: temporary file, then rename). cache_dir is created when missing. On
 * failure *e is left empty and err names the file and the stage. */
int species_cache_get(const char *species_file, int n_modes, const char *cache_dir,
                      species_entry *e, gale_err *err);

/* Frees what *e owns. NULL is a no-op. */
void species_entry_fini(species_entry *e);

#endif
