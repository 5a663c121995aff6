/* Content hashes: a 64-bit hash that names what an asset was baked from (the bake
 * cache key), and CRC-32 (IEEE 802.3, the zlib/PNG polynomial) for file checksums. */
#ifndef GALE_HASH_H
#define GALE_HASH_H

#include <stddef.h>
#include <stdint.h>

/* Start value of an incremental 64-bit hash. */
#define HASH64_INIT 0xcbf29ce484222325ull

/* Folds len bytes into the running 64-bit hash h (FNV-1a, 64-bit) and returns it. */
uint64_t hash64_update(uint64_t h, const void *data, size_t len);
/* Finishes a running hash with an avalanche step, so that near inputs differ in every bit
 * (inline: the per-tree draws call it 100 000 times a tick, in loops that vectorise). */
static inline uint64_t hash64_final(uint64_t h)
{
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return h ^ (h >> 31);
}
/* One-shot: hash64_final(hash64_update(HASH64_INIT, data, len)). */
uint64_t hash64(const void *data, size_t len);
/* splitmix64 (Steele, Lea, Flood 2014): advances *state by the golden-ratio gamma and
 * returns its avalanche (hash64_final). Full period 2^64, the same sequence on every
 * machine: the one generator behind gale's seeded forests, leaves, gusts and jitter. */
static inline uint64_t hash64_splitmix(uint64_t *state)
{
    *state += 0x9e3779b97f4a7c15ull;
    return hash64_final(*state);
}

/* A 32-bit avalanche (lowbias32, C. Wellons' hash prospector): the hash behind gale's
 * per-tree and per-leaf draws that the GPU repeats, so shaders/common.glsl's hash_u is the
 * same function bit for bit. */
static inline uint32_t hash_mix32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* CRC-32 of len bytes continuing from crc (0 to start): crc32("123456789") = 0xcbf43926. */
uint32_t hash_crc32_update(uint32_t crc, const void *data, size_t len);
/* One-shot CRC-32. */
uint32_t hash_crc32(const void *data, size_t len);

#endif
