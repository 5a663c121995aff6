/* Storm damage on screen (PROTOCOL.md "DAMAGE", server/PHYSICS.md "Storm damage"): a
 * snapped or uprooted tree tips over its base towards the way it fell (tip_fall.h, a rigid
 * pole) and lies; a broken branch is gone from its tree (render_set_broken) and falls as
 * tumbling debris in the streamed wind (debris_path.h), lands, lies and sinks away; a
 * stripped crown shows only the leaf slots its level keeps; a heal restores all of it.
 * Only events younger than DAMAGE_RECENT_S animate (damage_clock.h): a late joiner sees
 * fallen trees lying and broken branches gone, never falling. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "client.h"
#include "damage_clock.h"
#include "debris_path.h"
#include "tip_fall.h"

struct client_damage_fx {
    uint32_t n_trees;
    double *fall_t0_s;   /* [n_trees] when the stem gave way (server clock [s]); NaN: not
                            seen, so lying at once if it has fallen */
    uint32_t n_tipping;  /* trees whose fall is under way */
    debris_path debris[RENDER_MAX_DEBRIS];
    float centre[RENDER_MAX_DEBRIS][3]; /* each piece's centre in its tree frame, unit scale */
    uint32_t n_debris;
    uint32_t generation; /* of the damage view last given to render_set_broken */
    bool have_broken;
    double now_s;        /* the instant of the last frame drawn (server clock [s]) */
    wire_damage *forest_ev; /* owned [forest_cap]: a FOREST read as events */
    uint32_t forest_cap;
};

static client_damage_fx *fx_get(client *c)
{
    client_damage_fx *x = c->dfx;
    if (x && x->n_trees == c->dmg.n_trees) {
        return x;
    }
    client_damage_free(c);
    x = calloc(1, sizeof *x);
    double *t0 = x ? malloc((size_t)c->dmg.n_trees * sizeof *t0 + 1) : NULL;
    if (!t0) {
        free(x);
        return NULL;
    }
    for (uint32_t t = 0; t < c->dmg.n_trees; t++) {
        t0[t] = (double)NAN;
    }
    x->n_trees = c->dmg.n_trees;
    x->fall_t0_s = t0;
    x->now_s = (double)NAN;
    c->dfx = x;
    return x;
}

void client_damage_free(client *c)
{
    if (c->dfx) {
        free(c->dfx->fall_t0_s);
        free(c->dfx->forest_ev);
        free(c->dfx);
        c->dfx = NULL;
    }
}

/* Where a fallen tree pivots [m up the stem, tree frame at unit scale]: a snapped stem at
 * its break above the stump, an uprooted one at its base (shaders/common.glsl
 * tree_pivot_m). */
static float fall_pivot_m(const client *c, uint32_t t)
{
    return c->dmg.tree[t].fallen == WIRE_DAMAGE_SNAP ? tip_fall_break_m(t) : 0.0f;
}

/* The stem's angle from upright at server time now_s: the pole is the stem above the pivot. */
static float fall_angle(const client *c, const client_damage_fx *x, uint32_t t, double now_s)
{
    if (!c->dmg.tree[t].fallen) {
        return 0.0f;
    }
    double t0 = x ? x->fall_t0_s[t] : (double)NAN;
    if (isnan(t0) || isnan(now_s)) {
        return (float)TIP_FALL_LYING_RAD;
    }
    const float sc = t < c->w.n_instances ? c->w_instances[t].scale : 1.0f;
    return (float)tip_fall_angle(now_s - t0,
                                 render_tree_height_m(c->r, t) - sc * fall_pivot_m(c, t));
}

static float fall_az(const client *c, uint32_t t)
{
    return (float)c->dmg.tree[t].fall_az * (6.2831853f / 256.0f);
}

/* A piece of tree t from node leaves the tree where it broke, at t0_s. */
static void spawn_debris(client *c, client_damage_fx *x, uint32_t t, uint32_t node, double t0_s)
{
    float centre[3], axis[3], ext;
    if (!c->scene_ready || t >= c->w.n_instances ||
        render_piece_shape(c->r, t, node, centre, axis, &ext, NULL) != 0) {
        return;
    }
    uint32_t k = x->n_debris;
    if (k == RENDER_MAX_DEBRIS) {
        k = 0; /* full: the oldest piece goes */
        for (uint32_t i = 1; i < x->n_debris; i++) {
            k = x->debris[i].t0_s < x->debris[k].t0_s ? i : k;
        }
    } else {
        x->n_debris++;
    }
    const ctl_instance *in = &c->w_instances[t];
    float r0[9], c0[3];
    debris_frame_matrix(in->yaw_rad, fall_angle(c, x, t, t0_s), fall_az(c, t), r0);
    /* where the tree draws the piece's centre: turned about the fall's pivot */
    const float piv = fall_pivot_m(c, t), d[3] = { centre[0], centre[1], centre[2] - piv };
    for (int i = 0; i < 3; i++) {
        c0[i] = in->pos[i] + in->scale * (r0[i] * d[0] + r0[3 + i] * d[1] + r0[6 + i] * d[2] +
                                          (i == 2 ? piv : 0.0f));
    }
    debris_path_start(&x->debris[k], t, node, t0_s, c0, r0, axis, ext * in->scale);
    memcpy(x->centre[k], centre, sizeof centre);
}

/* f's events new to the picture start, then f applies: after a heal of everything when
 * it is a whole state (damage_full), of the trees' fall and level when heal_trees. */
static void take(client *c, const wire_frame *f, bool heal_trees)
{
    client_damage_fx *x = fx_get(c);
    /* what is new to this picture (events are idempotent), before it is applied */
    for (uint32_t i = 0; x && i < f->n_damage; i++) {
        const wire_damage *e = &f->damage[i];
        if (e->tree >= c->dmg.n_trees) {
            continue;
        }
        const double t0 =
            damage_event_start_s(f->hdr.tick, f->hdr.server_time_us, e->tick, (double)c->w.tick_hz);
        if ((e->kind == WIRE_DAMAGE_SNAP || e->kind == WIRE_DAMAGE_UPROOT) &&
            !c->dmg.tree[e->tree].fallen) {
            x->fall_t0_s[e->tree] = t0; /* NaN: an old fall, lying at once */
            x->n_tipping += !isnan(t0);
            client_audio_event(c, e->tree, e->kind, t0);
        } else if (e->kind == WIRE_DAMAGE_BRANCH && !isnan(t0) &&
                   !damage_view_broken(&c->dmg, e->tree, e->node)) {
            spawn_debris(c, x, e->tree, e->node, t0);
            client_audio_event(c, e->tree, e->kind, t0);
        }
    }
    if (heal_trees) {
        damage_view_heal_trees(&c->dmg);
    }
    if (damage_view_apply(&c->dmg, f->damage_full, f->damage, f->n_damage)) {
        c->leaves_bad++; /* events for trees outside the scene */
    }
    if (x && f->damage_full) {
        /* a heal: what no longer stands broken stops moving */
        uint32_t kept = 0;
        for (uint32_t k = 0; k < x->n_debris; k++) {
            const debris_path *p = &x->debris[k];
            if (damage_view_broken(&c->dmg, p->tree, p->node)) {
                x->debris[kept] = *p;
                memcpy(x->centre[kept], x->centre[k], sizeof x->centre[k]);
                kept++;
            }
        }
        x->n_debris = kept;
    }
    if (x && (f->damage_full || heal_trees)) {
        for (uint32_t t = 0; t < x->n_trees; t++) {
            if (!c->dmg.tree[t].fallen) {
                x->fall_t0_s[t] = (double)NAN;
            }
        }
    }
    if (c->scene_ready) {
        client_damage_draw(c);
    }
}

void client_damage_take(client *c, const wire_frame *f)
{
    if (c->dmg.tree) {
        take(c, f, false);
    }
}

void client_damage_take_forest(client *c, const wire_frame *f)
{
    client_damage_fx *x = c->dmg.tree ? fx_get(c) : NULL;
    if (!x) {
        return;
    }
    /* the frame's DAMAGE (a whole state's heal and branches) and its FOREST as one: a fall
     * under way is then seen as one this picture holds, not as new after the heal */
    const uint32_t nd = (f->types & (1u << WIRE_MSG_DAMAGE)) ? f->n_damage : 0;
    const uint32_t n = nd + wire_forest_events(f, NULL, 0);
    if (n > x->forest_cap) {
        wire_damage *ev = realloc(x->forest_ev, (size_t)n * sizeof *ev);
        if (!ev) {
            fprintf(stderr, "gale-client: no memory for the state of %u trees: the forest "
                            "drawn as it was\n", f->forest_count);
            return;
        }
        x->forest_ev = ev;
        x->forest_cap = n;
    }
    if (nd) {
        memcpy(x->forest_ev, f->damage, (size_t)nd * sizeof *f->damage);
    }
    wire_forest_events(f, x->forest_ev + nd, n - nd);
    const wire_frame ev = { .hdr = f->hdr, .types = 1u << WIRE_MSG_DAMAGE, .n_damage = n,
                            .damage = x->forest_ev, .damage_full = nd && f->damage_full };
    wire_frame held;
    take(c, client_hold_damage(c, &ev, &held), true);
}

void client_damage_draw(client *c)
{
    if (!c->r || !c->dmg.tree) {
        return;
    }
    client_damage_fx *x = fx_get(c);
    const double now = x ? x->now_s : (double)NAN;
    const uint32_t n = c->w.n_instances < c->dmg.n_trees ? c->w.n_instances : c->dmg.n_trees;
    uint32_t tipping = 0;
    for (uint32_t t = 0; t < n; t++) {
        const damage_view_tree *d = &c->dmg.tree[t];
        float fall = fall_angle(c, x, t, now);
        if (d->fallen && fall < (float)TIP_FALL_LYING_RAD) {
            tipping++;
        }
        render_set_damage(c->r, t, fall, fall_az(c, t), WIRE_DAMAGE_LEVELS - d->level);
        render_set_uprooted(c->r, t, d->fallen == WIRE_DAMAGE_UPROOT);
    }
    render_trees_commit(c->r);
    if (x) {
        x->n_tipping = tipping;
        if (x->generation != c->dmg.generation || !x->have_broken) {
            gale_err err = { 0 };
            if (render_set_broken(c->r, c->dmg.n_broken, c->dmg.broken, &err) != 0) {
                fprintf(stderr, "gale-client: broken branches: %s\n", err.msg);
            }
            x->generation = c->dmg.generation;
            x->have_broken = true;
        }
    }
}

static void wind_at(void *user, const float p[3], float out[3])
{
    render_wind_sample(user, p, out);
}

void client_damage_frame(client *c, double now_s)
{
    client_damage_fx *x = c->scene_ready && c->dmg.tree ? fx_get(c) : NULL;
    if (!x) {
        return;
    }
    x->now_s = now_s;
    if (x->n_tipping > 0) {
        client_damage_draw(c); /* the falls under way move on; the others keep their angle */
    }
    uint32_t kept = 0;
    render_debris out[RENDER_MAX_DEBRIS];
    for (uint32_t k = 0; k < x->n_debris; k++) {
        debris_path *p = &x->debris[k];
        debris_path_advance(p, now_s, wind_at, c->r);
        if (debris_path_done(p) || p->tree >= c->w.n_instances) {
            continue;
        }
        float r[9];
        debris_path_rotation(p, r);
        const float *ce = x->centre[k], s = c->w_instances[p->tree].scale;
        render_debris *d = &out[kept];
        d->tree = p->tree;
        d->node = p->node;
        for (int i = 0; i < 3; i++) {
            d->pos[i] = p->c[i] - s * (r[i] * ce[0] + r[3 + i] * ce[1] + r[6 + i] * ce[2]);
        }
        d->pos[2] -= debris_path_sink_m(p);
        debris_frame_angles(r, &d->yaw, &d->fall_rad, &d->fall_az_rad);
        x->debris[kept] = *p;
        memcpy(x->centre[kept], ce, sizeof x->centre[kept]);
        kept++;
    }
    if (kept > 0 || x->n_debris > 0) { /* nothing to send while no piece flies or lies */
        render_set_debris(c->r, kept, out, NULL);
    }
    x->n_debris = kept;
}

uint32_t client_damage_debris_count(const client *c)
{
    return c->dfx ? c->dfx->n_debris : 0;
}

bool client_damage_live_fall(const client *c, uint32_t t, double *t0_s, double *now_s,
                             float *az_rad)
{
    const client_damage_fx *x = c->dfx;
    if (!x || t >= x->n_trees || !c->dmg.tree[t].fallen || isnan(x->fall_t0_s[t]) ||
        isnan(x->now_s)) {
        return false; /* standing, an old fall, or healed since */
    }
    *t0_s = x->fall_t0_s[t];
    *now_s = x->now_s;
    *az_rad = fall_az(c, t);
    return true;
}
