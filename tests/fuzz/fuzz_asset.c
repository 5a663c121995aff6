/* Fuzz target for asset_decode. Each input is decoded as is, then again with magic,
 * version, payload length and both CRCs repaired, so that mutations reach the section
 * parser instead of stopping at the checksum. A decoded asset must re-encode and decode
 * to the same bytes. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "asset.h"
#include "hash.h"

static void put32(uint8_t *b, uint32_t v)
{
    for (int i = 0; i < 4; i++) {
        b[i] = (uint8_t)(v >> (8 * i));
    }
}

static void check_stable(const asset *a)
{
    uint8_t *buf = NULL, *buf2 = NULL;
    size_t len = 0, len2 = 0;
    asset b;
    if (asset_encode(a, &buf, &len, NULL) != 0) {
        abort(); /* a decoded asset is always encodable */
    }
    if (asset_decode(buf, len, "fuzz", &b, NULL) != 0) {
        abort();
    }
    if (asset_encode(&b, &buf2, &len2, NULL) != 0 || len2 != len || memcmp(buf, buf2, len) != 0) {
        abort();
    }
    asset_fini(&b);
    free(buf);
    free(buf2);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    asset a;
    if (asset_decode(data, size, "fuzz", &a, NULL) == 0) {
        check_stable(&a);
        asset_fini(&a);
    }
    if (size < 24) {
        return 0;
    }
    uint8_t *copy = malloc(size);
    if (!copy) {
        return 0;
    }
    memcpy(copy, data, size);
    memcpy(copy, "GAST", 4);
    put32(copy + 4, ASSET_VERSION);
    put32(copy + 8, (uint32_t)(size - 24));
    put32(copy + 12, 0);
    put32(copy + 16, hash_crc32(copy + 24, size - 24));
    put32(copy + 20, hash_crc32(copy, 20));
    if (asset_decode(copy, size, "fuzz", &a, NULL) == 0) {
        check_stable(&a);
        asset_fini(&a);
    }
    free(copy);
    return 0;
}
