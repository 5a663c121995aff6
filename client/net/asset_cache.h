/* Client disk cache of downloaded assets, keyed by the content hash the server names
 * them by ($XDG_CACHE_HOME/gale or ~/.cache/gale). Writes are atomic (temporary file,
 * fsync, rename); every entry carries its own checksum and is verified on load. */
#ifndef GALE_ASSET_CACHE_H
#define GALE_ASSET_CACHE_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"

#define ASSET_CACHE_MAX_KEY   128          /* hash strings are far shorter */
#define ASSET_CACHE_MAX_BYTES (512u << 20) /* larger than any baked species asset */

typedef struct asset_cache_desc {
    const char *dir; /* NULL = $XDG_CACHE_HOME/gale, else $HOME/.cache/gale */
} asset_cache_desc;

typedef struct asset_cache asset_cache;

/* Opens (creating the directory and its parents) the cache. Returns NULL and fills err
 * when no directory can be made or $HOME is unset. */
asset_cache *asset_cache_create(const asset_cache_desc *d, gale_err *err);

/* Frees c (files stay). NULL is a no-op. */
void asset_cache_destroy(asset_cache *c);

/* The cache directory (owned by c). */
const char *asset_cache_dir(const asset_cache *c);

/* True when key is usable as a cache key: 1..ASSET_CACHE_MAX_KEY characters of
 * [0-9A-Za-z_.-], not starting with '.', so a key from the wire can never name a path
 * outside the cache. */
int asset_cache_key_ok(const char *key);

/* Loads the entry for key into *out (malloc'd, caller frees) of *len bytes. Returns 0 on a
 * hit, GALE_E_IO when absent, GALE_E_CHECKSUM or GALE_E_FORMAT when the stored entry is
 * damaged (the entry is then deleted, so the caller downloads it again), GALE_E_ARG for a
 * bad key. */
int asset_cache_load(asset_cache *c, const char *key, uint8_t **out, size_t *len, gale_err *err);

/* Stores len bytes (borrowed) under key, atomically: readers see the old entry or the
 * whole new one, never a part. Returns 0 or GALE_E_IO / GALE_E_ARG / GALE_E_RANGE. */
int asset_cache_store(asset_cache *c, const char *key, const uint8_t *buf, size_t len,
                      gale_err *err);

/* Checks len bytes against the content hash a welcome names them by (`hash`: 16
 * lowercase hex digits of hash64 over every byte of the asset file, protocol/ASSET.md
 * "Content hash"). Returns 0 when they match, else GALE_E_CHECKSUM with "what: content
 * hash H, expected E: refused" in err (GALE_E_ARG when want_hex is not 16 hex digits). */
int asset_cache_verify(const char *want_hex, const uint8_t *buf, size_t len, const char *what,
                       gale_err *err);

/* 64-bit FNV-1a of len bytes: the entry checksum. */
uint64_t asset_cache_hash(const uint8_t *buf, size_t len);

#endif
