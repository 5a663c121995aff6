/* Content hashes: FNV-1a 64 (Fowler, Noll, Vo) finished with the splitmix64 avalanche,
 * the splitmix64 generator itself, and the reflected CRC-32 with polynomial 0xEDB88320, a nibble table at a time. */
#include "hash.h"

uint64_t hash64_update(uint64_t h, const void *data, size_t len)
{
    const uint8_t *p = data;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull; /* the 64-bit FNV prime */
    }
    return h;
}

uint64_t hash64(const void *data, size_t len)
{
    return hash64_final(hash64_update(HASH64_INIT, data, len));
}

/* CRC-32 a nibble at a time: entry n is the CRC register after shifting the 4-bit value n
 * through the polynomial 0xEDB88320; constant, so the function is thread-safe. */
static const uint32_t crc_nibble[16] = {
    0x00000000u, 0x1db71064u, 0x3b6e20c8u, 0x26d930acu, 0x76dc4190u, 0x6b6b51f4u,
    0x4db26158u, 0x5005713cu, 0xedb88320u, 0xf00f9344u, 0xd6d6a3e8u, 0xcb61b38cu,
    0x9b64c2b0u, 0x86d3d2d4u, 0xa00ae278u, 0xbdbdf21cu,
};

uint32_t hash_crc32_update(uint32_t crc, const void *data, size_t len)
{
    const uint8_t *p = data;
    uint32_t c = crc ^ 0xffffffffu;
    for (size_t i = 0; i < len; i++) {
        c ^= p[i];
        c = crc_nibble[c & 0xfu] ^ (c >> 4);
        c = crc_nibble[c & 0xfu] ^ (c >> 4);
    }
    return c ^ 0xffffffffu;
}

uint32_t hash_crc32(const void *data, size_t len)
{
    return hash_crc32_update(0, data, len);
}
