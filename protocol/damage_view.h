/* A receiver's picture of the storm damage (PROTOCOL.md "DAMAGE"): per tree whether it
 * stands, snapped or was uprooted (and which way it fell), its leaf level, and the set of
 * branches broken off, built from DAMAGE frames. Events are idempotent, so a client that
 * watched every event and one that joined late and got the whole state hold the same
 * picture. */
#ifndef GALE_DAMAGE_VIEW_H
#define GALE_DAMAGE_VIEW_H

#include <stdbool.h>
#include <stdint.h>

#include "err.h"
#include "wire.h"

#define DAMAGE_VIEW_MAX_BROKEN 65536u /* broken branches remembered over the scene */

typedef struct damage_view_tree {
    uint8_t fallen;    /* 0 standing, WIRE_DAMAGE_SNAP or WIRE_DAMAGE_UPROOT */
    uint8_t fall_az;   /* fall azimuth, 1/256 turns (world) */
    uint8_t level;     /* leaf level, 0..WIRE_DAMAGE_LEVELS */
    uint32_t fall_tick;
} damage_view_tree;

typedef struct damage_view {
    uint32_t n_trees;
    damage_view_tree *tree;  /* owned [n_trees] */
    uint64_t *broken;        /* owned [DAMAGE_VIEW_MAX_BROKEN] (tree << 32 | node), sorted */
    uint32_t n_broken;
    uint32_t *broken_tick;   /* owned [DAMAGE_VIEW_MAX_BROKEN] tick of each, same order */
    uint32_t generation;     /* counts changes: a renderer rebuilds what it derived */
} damage_view;

/* Allocates an intact picture of n_trees trees into *v (caller-owned struct). */
int damage_view_init(damage_view *v, uint32_t n_trees, gale_err *err);
void damage_view_fini(damage_view *v); /* NULL or an empty view is a no-op */

/* Every tree intact. */
void damage_view_heal(damage_view *v);
/* Every tree standing with its full crown; the broken branches kept (a FOREST frame's
 * state replaces the trees' fall and level only: PROTOCOL.md "FOREST"). */
void damage_view_heal_trees(damage_view *v);

/* Applies a decoded DAMAGE frame: full heals first. Events naming a tree outside the
 * scene are skipped and counted in the return value (0 = all applied). */
uint32_t damage_view_apply(damage_view *v, bool full, const wire_damage *ev, uint32_t n);

/* Applies what a decoded frame f holds of the damage: its DAMAGE (damage_view_apply), then
 * its FOREST: every tree's fall and level healed, then set as the frame says (PROTOCOL.md
 * "FOREST"). Returns the events skipped, as damage_view_apply. */
uint32_t damage_view_apply_frame(damage_view *v, const wire_frame *f);

/* Whether branch `node` of tree t is broken off (the node itself, not its sub-tree). */
bool damage_view_broken(const damage_view *v, uint32_t t, uint32_t node);

/* The same picture: every tree's fields and the broken set. */
bool damage_view_equal(const damage_view *a, const damage_view *b);

#endif
