/* Storm damage on screen (PROTOCOL.md "DAMAGE", server/PHYSICS.md "Storm damage"): a
 * snapped or uprooted tree lies on the ground, tipped over its root plate towards the way
 * it fell; a stripped crown shows only the leaf slots its level keeps; a heal restores
 * both. */
#include "client.h"

void client_damage_draw(client *c)
{
    if (!c->r || !c->dmg.tree) {
        return;
    }
    const uint32_t n = c->w.n_instances < c->dmg.n_trees ? c->w.n_instances : c->dmg.n_trees;
    for (uint32_t t = 0; t < n; t++) {
        const damage_view_tree *d = &c->dmg.tree[t];
        /* lying: the stem 88° from upright, its crown resting on the ground */
        float fall = d->fallen ? 1.536f : 0.0f;
        render_set_damage(c->r, t, fall, (float)d->fall_az * (6.2831853f / 256.0f),
                          WIRE_DAMAGE_LEVELS - d->level);
    }
    render_trees_commit(c->r);
}
