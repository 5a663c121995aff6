/* A tree skeleton: rooted nodes with rest positions and radii, in topological order
 * (every parent before its children). Built by the L-system generator (lsystem.h) or
 * imported from CSV (id,parent,x,y,z,radius). */
#ifndef GALE_SKELETON_H
#define GALE_SKELETON_H

#include <stddef.h>

#include "err.h"

typedef struct skeleton {
    int n;         /* nodes; node 0 is the root */
    int *parent;   /* owned [n]; -1 for the root, else parent[i] < i */
    float *pos;    /* owned [3n] rest position [m], tree frame, z up, root at the origin */
    float *radius; /* owned [n] [m], > 0; an element's radius is the mean of its two nodes' */
    int *order;    /* owned [n] branch order: 0 trunk, 1 first branches, ... */
    int *src_id;   /* owned [n] or NULL: the node's id in the source file, for messages and
                    * the asset's SRID section (protocol/ASSET.md) */
    float src_origin[3]; /* with src_id: the root's position in the source file [m]; pos is
                          * relative to it */
} skeleton;

/* Parses CSV text `id,parent,x,y,z,radius` (header line first, one node a line,
 * parent -1 for the single root) into *s, reordered parents-first (breadth-first from the
 * root, children in file order) and moved so the root is at the origin; src_id and
 * src_origin keep the ids and the root's position (protocol/ASSET.md "Node numbering").
 * `name` is the file name used in messages ("trees/oak.csv:14: duplicate id 7"). On
 * failure *s is left empty and err says the line and the fault. */
int skeleton_parse_csv(const char *text, size_t len, const char *name, skeleton *s,
                       gale_err *err);

/* Reads and parses a CSV file; see skeleton_parse_csv. */
int skeleton_load_csv(const char *path, skeleton *s, gale_err *err);

/* Allocates the arrays of an n-node skeleton (zeroed, parent = -1). */
int skeleton_alloc(skeleton *s, int n, gale_err *err);

/* Frees the arrays; the struct is zeroed. NULL or an empty skeleton is a no-op. */
void skeleton_fini(skeleton *s);

#endif
