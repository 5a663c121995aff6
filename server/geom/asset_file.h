/* Asset files on disk: asset_encode/asset_decode (protocol/asset.h) plus atomic writes,
 * so a reader never sees a half-written file. */
#ifndef GALE_ASSET_FILE_H
#define GALE_ASSET_FILE_H

#include "asset.h"
#include "err.h"

/* Encodes a and writes it to path atomically: a temporary file beside it is written,
 * flushed to disk and renamed over path. On failure path is untouched and no temporary
 * file is left. */
int asset_save(const asset *a, const char *path, gale_err *err);

/* Reads and decodes path into *a (caller-owned struct, arrays owned by it; free with
 * asset_fini). Errors name the path; *a is left empty on failure. */
int asset_load(const char *path, asset *a, gale_err *err);

#endif
