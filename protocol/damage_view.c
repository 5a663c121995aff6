/* A receiver's picture of the storm damage: see damage_view.h. */
#include "damage_view.h"

#include <stdlib.h>
#include <string.h>

int damage_view_init(damage_view *v, uint32_t n_trees, gale_err *err)
{
    memset(v, 0, sizeof *v);
    if (n_trees == 0 || n_trees > WIRE_MAX_TREES) {
        return gale_errf(err, GALE_E_ARG, "damage_view_init: n_trees: expected 1..%u, got %u",
                         WIRE_MAX_TREES, n_trees);
    }
    v->n_trees = n_trees;
    v->tree = calloc(n_trees, sizeof *v->tree);
    v->broken = calloc(DAMAGE_VIEW_MAX_BROKEN, sizeof *v->broken);
    v->broken_tick = calloc(DAMAGE_VIEW_MAX_BROKEN, sizeof *v->broken_tick);
    if (!v->tree || !v->broken || !v->broken_tick) {
        damage_view_fini(v);
        return gale_errf(err, GALE_E_NOMEM, "damage_view_init: no memory for %u trees", n_trees);
    }
    damage_view_heal(v);
    return GALE_OK;
}

void damage_view_fini(damage_view *v)
{
    if (!v) {
        return;
    }
    free(v->tree);
    free(v->broken);
    free(v->broken_tick);
    memset(v, 0, sizeof *v);
}

void damage_view_heal_trees(damage_view *v)
{
    for (uint32_t t = 0; t < v->n_trees; t++) {
        v->tree[t] = (damage_view_tree){ .level = WIRE_DAMAGE_LEVELS };
    }
    v->generation++;
}

void damage_view_heal(damage_view *v)
{
    damage_view_heal_trees(v);
    v->n_broken = 0;
}

/* First index whose key is >= k. */
static uint32_t lower(const damage_view *v, uint64_t k)
{
    uint32_t lo = 0, hi = v->n_broken;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (v->broken[mid] < k) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

uint32_t damage_view_apply(damage_view *v, bool full, const wire_damage *ev, uint32_t n)
{
    uint32_t skipped = 0;
    if (full) {
        damage_view_heal(v);
    }
    for (uint32_t i = 0; i < n; i++) {
        const wire_damage *e = &ev[i];
        if (e->tree >= v->n_trees) {
            skipped++;
            continue;
        }
        damage_view_tree *t = &v->tree[e->tree];
        switch (e->kind) {
        case WIRE_DAMAGE_SNAP:
        case WIRE_DAMAGE_UPROOT:
            if (!t->fallen) {
                t->fallen = e->kind;
                t->fall_az = e->value;
                t->fall_tick = e->tick;
            }
            break;
        case WIRE_DAMAGE_STRIP:
            t->level = e->value < t->level ? e->value : t->level;
            break;
        default: { /* WIRE_DAMAGE_BRANCH */
            uint64_t k = (uint64_t)e->tree << 32 | e->node;
            uint32_t at = lower(v, k);
            if (at < v->n_broken && v->broken[at] == k) {
                break;
            }
            if (v->n_broken >= DAMAGE_VIEW_MAX_BROKEN) {
                skipped++;
                break;
            }
            memmove(v->broken + at + 1, v->broken + at, sizeof(uint64_t) * (v->n_broken - at));
            memmove(v->broken_tick + at + 1, v->broken_tick + at,
                    sizeof(uint32_t) * (v->n_broken - at));
            v->broken[at] = k;
            v->broken_tick[at] = e->tick;
            v->n_broken++;
            break;
        }
        }
    }
    v->generation++;
    return skipped;
}

uint32_t damage_view_apply_frame(damage_view *v, const wire_frame *f)
{
    uint32_t skipped = 0;
    if (f->types & (1u << WIRE_MSG_DAMAGE)) {
        skipped += damage_view_apply(v, f->damage_full, f->damage, f->n_damage);
    }
    if (f->types & (1u << WIRE_MSG_FOREST)) {
        /* the FOREST's events a tree at a time (at most two each), so nothing is allocated */
        damage_view_heal_trees(v);
        wire_frame one = *f;
        for (uint32_t i = 0; i < f->forest_count; i++) {
            wire_damage ev[2];
            const uint8_t fell = f->forest_state[i] >> WIRE_FOREST_FALL_SHIFT;
            one.forest_first = f->forest_first + i;
            one.forest_count = 1;
            one.forest_state = f->forest_state + i;
            const uint32_t n = wire_forest_events(&one, ev, 2);
            one.forest_fall += fell != 0;
            one.n_forest_fall -= fell != 0;
            skipped += damage_view_apply(v, false, ev, n);
        }
    }
    return skipped;
}

bool damage_view_broken(const damage_view *v, uint32_t t, uint32_t node)
{
    uint64_t k = (uint64_t)t << 32 | node;
    uint32_t at = lower(v, k);
    return at < v->n_broken && v->broken[at] == k;
}

bool damage_view_equal(const damage_view *a, const damage_view *b)
{
    if (a->n_trees != b->n_trees || a->n_broken != b->n_broken) {
        return false;
    }
    for (uint32_t t = 0; t < a->n_trees; t++) {
        const damage_view_tree *x = &a->tree[t], *y = &b->tree[t];
        if (x->fallen != y->fallen || x->fall_az != y->fall_az || x->level != y->level ||
            x->fall_tick != y->fall_tick) {
            return false;
        }
    }
    return memcmp(a->broken, b->broken, sizeof(uint64_t) * a->n_broken) == 0 &&
           memcmp(a->broken_tick, b->broken_tick, sizeof(uint32_t) * a->n_broken) == 0;
}
