/* The baked species asset file (ASSET.md): a 24-byte header (magic, version, payload
 * length, payload CRC-32, header CRC-32), seven sections in fixed order and, from version
 * 2, optional sections (SRID: source node ids; SRES: the static correction); every
 * field little-endian and fixed-width, written and read byte by byte. Counts are checked
 * against the limits below and against the bytes left before anything is allocated.
 * asset_reconstruct (asset_pose.c) is the length-true pose of PHYSICS.md.
 *
 * Private to the file's writer (asset_enc.c) and reader (asset_dec.c), what both must
 * agree on: the limits, the header's size, the magic and the section tags. Included by
 * those two only. */
#ifndef GALE_ASSET_INT_H
#define GALE_ASSET_INT_H

#include <stdint.h>

#include "asset.h"

/* Limits, each with its reason. A count above one is refused before any allocation. */
/* 2^18 nodes: 25 times the largest benchmark tree (10^4 nodes); FEM bakes beyond that
 * are not interactive material. */
#define ASSET_MAX_NODES 262144u
/* 256 modes: eight times the default 32; the client's uniform budget is far smaller. */
#define ASSET_MAX_MODES 256u
/* modes x nodes <= 2^23: the four per-mode arrays (phi, phi_rot, corr_v, corr_w) then
 * stay under 400 MB. */
#define ASSET_MAX_MODE_NODES 8388608u
/* 2^22 vertices and 2^24 indices: an 8-sided tube of 2^18 nodes needs ~2.4 M and 12 M. */
#define ASSET_MAX_VERTS   4194304u
#define ASSET_MAX_INDICES 16777216u
/* 2^20 leaf slots: 64 per tip on 16 K tips. */
#define ASSET_MAX_LEAVES 1048576u
/* 1 MiB of parameter JSON: a species file is a few kB. */
#define ASSET_MAX_PARAMS 1048576u

#define ASSET_HEADER_BYTES 24u
/* The seven required sections, then the optional ones a reader knows. */
#define ASSET_SECTIONS     7
#define ASSET_SECTION_SRID 7
#define ASSET_SECTION_SRES 8
#define ASSET_TAGS         9

static const uint8_t asset_magic[4] = { 'G', 'A', 'S', 'T' };

/* Section tags, in file order (the four characters read as a little-endian u32). */
#define TAG(a, b, c, d) \
    ((uint32_t)(a) | (uint32_t)(b) << 8 | (uint32_t)(c) << 16 | (uint32_t)(d) << 24)
static const uint32_t asset_tags[ASSET_TAGS] = {
    TAG('M', 'E', 'T', 'A'), TAG('S', 'K', 'E', 'L'), TAG('M', 'O', 'D', 'E'),
    TAG('C', 'O', 'R', 'R'), TAG('M', 'E', 'S', 'H'), TAG('L', 'E', 'A', 'F'),
    TAG('L', 'O', 'O', 'K'), TAG('S', 'R', 'I', 'D'), TAG('S', 'R', 'E', 'S'),
};
static const char *const asset_tag_names[ASSET_TAGS] = { "META", "SKEL", "MODE", "CORR",
                                                         "MESH", "LEAF", "LOOK", "SRID",
                                                         "SRES" };

#endif
