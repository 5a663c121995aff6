/* gale-client's reduced view (CLIENT.md "Reduced view"): a scene with more trees than this
 * client holds keeps the trees nearest one point (client/playout/hold.h), as many as fit.
 * Those become the client's scene (c->w_instances: tree indices from here on are theirs),
 * the stream's tree indices are mapped onto them as frames arrive, and the server is asked
 * for a circle that holds them alone. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "client.h"

/* The most modes a tree of the welcome's species has: q values a tree takes. */
static uint32_t welcome_stride(const client *c)
{
    uint32_t m = 1;
    for (uint32_t s = 0; s < c->w.n_species; s++) {
        m = c->w_species[s].n_modes > m ? c->w_species[s].n_modes : m;
    }
    return m;
}

/* The trees this client holds of the scene at most, and what sets that, into why. */
static uint32_t hold_limit(const client *c, char *why, size_t cap)
{
    const uint32_t stride = welcome_stride(c);
    uint32_t lim = UINT32_MAX;
    snprintf(why, cap, "no limit");
    if (c->a.max_trees > 0) {
        lim = c->a.max_trees;
        snprintf(why, cap, "--max-trees %u", c->a.max_trees);
    }
    const uint32_t gpu = c->r ? render_max_trees(c->r, stride) : UINT32_MAX;
    if (gpu < lim) {
        lim = gpu;
        snprintf(why, cap, "the GPU's texture buffers take %u trees of %u modes", gpu, stride);
    }
    const uint64_t snaps = (uint64_t)CLIENT_JITTER_BYTES /
                           ((uint64_t)CLIENT_JITTER_MIN_SNAPSHOTS * stride * sizeof(float));
    if (snaps < lim) {
        lim = (uint32_t)snaps;
        snprintf(why, cap, "%u MiB holds %u snapshots of %u trees of %u modes",
                 CLIENT_JITTER_BYTES >> 20, CLIENT_JITTER_MIN_SNAPSHOTS, lim, stride);
    }
    if (c->hold.nomem_limit > 0 && c->hold.nomem_limit < lim) {
        lim = c->hold.nomem_limit;
        snprintf(why, cap, "%s", c->hold.nomem_why);
    }
    return lim;
}

/* The point to hold the trees about: the one held about before (a reconnection, or fewer
 * trees after an allocation failed), else the ground point of a camera already fitted to
 * a scene, else the scene's centre (where the camera will look). */
static void hold_point(client *c, double p[2])
{
    if (c->hold.have_centre) {
        p[0] = c->hold.centre[0];
        p[1] = c->hold.centre[1];
    } else if (c->camera_set) {
        float eye[3];
        camera_eye(&c->cam, eye);
        const float *g = c->cam.mode == CAMERA_ORBIT ? c->cam.target : eye;
        p[0] = (double)g[0];
        p[1] = (double)g[1];
    } else {
        hold_centre(c->hold.scene, c->hold.n_scene, p);
    }
    c->hold.centre[0] = p[0];
    c->hold.centre[1] = p[1];
    c->hold.have_centre = true;
}

int client_hold_select(client *c, gale_err *err)
{
    client_hold *h = &c->hold;
    const uint32_t n = h->n_scene;
    free(h->held);
    free(h->slot);
    h->held = NULL;
    h->slot = NULL;
    h->limit = hold_limit(c, h->why, sizeof h->why);
    h->reduced = h->limit < n;
    uint32_t k = n;
    if (h->reduced) {
        double p[2];
        hold_point(c, p);
        h->held = malloc(((size_t)h->limit + 1) * sizeof *h->held);
        h->slot = malloc(((size_t)n + 1) * sizeof *h->slot);
        int rc = h->held && h->slot
                     ? hold_nearest(h->scene, n, p[0], p[1], h->limit, h->held, &h->circle, err)
                     : gale_errf(err, GALE_E_NOMEM, "no memory to map %u trees", n);
        if (rc != 0) {
            return rc;
        }
        k = h->circle.n_held;
        for (uint32_t t = 0; t < n; t++) {
            h->slot[t] = -1;
        }
        for (uint32_t i = 0; i < k; i++) {
            h->slot[h->held[i]] = (int32_t)i;
        }
        /* a FOREST stands for up to two events a tree of the scene */
        const uint32_t cap = WIRE_MAX_DAMAGE > 2 * n ? WIRE_MAX_DAMAGE : 2 * n;
        if (h->damage_cap < cap) {
            wire_damage *dmg = realloc(h->damage, (size_t)cap * sizeof *dmg);
            if (!dmg) {
                return gale_errf(err, GALE_E_NOMEM, "no memory for a frame's damage");
            }
            h->damage = dmg;
            h->damage_cap = cap;
        }
    }
    ctl_instance *inst = realloc(c->w_instances, ((size_t)k + 1) * sizeof *inst);
    if (!inst) {
        return gale_errf(err, GALE_E_NOMEM, "no memory for %u trees", k);
    }
    for (uint32_t i = 0; i < k; i++) {
        inst[i] = h->scene[h->held ? h->held[i] : i];
    }
    c->w_instances = inst;
    c->w.instances = inst;
    c->w.n_instances = k;
    damage_view_fini(&c->dmg);
    client_damage_free(c);
    if (damage_view_init(&c->dmg, k ? k : 1, NULL) != 0) {
        fprintf(stderr, "gale-client: no memory for the damage of %u trees\n", k);
    }
    return 0;
}

int client_hold_welcome(client *c, const ctl_welcome *w, gale_err *err)
{
    client_hold *h = &c->hold;
    const bool same = h->scene && h->n_scene == w->n_instances &&
                      memcmp(h->scene, w->instances, w->n_instances * sizeof *h->scene) == 0;
    if (!same) {
        /* another scene: its own point, and what failed for the last one is no guide */
        h->have_centre = false;
        h->nomem_limit = 0;
        h->said = false;
        free(h->scene);
        h->scene = malloc(((size_t)w->n_instances + 1) * sizeof *h->scene);
        h->n_scene = 0;
        if (!h->scene) {
            return gale_errf(err, GALE_E_NOMEM, "no memory for %u trees", w->n_instances);
        }
        memcpy(h->scene, w->instances, w->n_instances * sizeof *h->scene);
        h->n_scene = w->n_instances;
    }
    return client_hold_select(c, err);
}

int client_hold_fewer(client *c, const char *what)
{
    client_hold *h = &c->hold;
    const uint32_t n = c->w.n_instances;
    if (n < 2) {
        return -1;
    }
    h->nomem_limit = n / 2;
    snprintf(h->nomem_why, sizeof h->nomem_why, "no memory for %u trees: %s", n, what);
    fprintf(stderr, "gale-client: scene: %s; trying %u trees\n", h->nomem_why, h->nomem_limit);
    gale_err err = { 0 };
    if (client_hold_select(c, &err) != 0) {
        fprintf(stderr, "gale-client: scene: %s\n", err.msg);
        return -1;
    }
    c->scene_pending = true;
    return 0;
}

void client_hold_margin(client *c, const float *height_m)
{
    client_hold *h = &c->hold;
    float m = 0.0f;
    for (uint32_t t = 0; t < h->n_scene; t++) {
        const ctl_instance *in = &h->scene[t];
        const float hgt = in->species < c->w.n_species ? height_m[in->species] * in->scale : 0.0f;
        m = hgt > m ? hgt : m;
    }
    h->view_radius_m = (float)hold_view_radius_m(&h->circle, (double)m);
}

void client_hold_say(client *c)
{
    client_hold *h = &c->hold;
    if (!h->reduced || h->said) {
        return;
    }
    h->said = true;
    fprintf(stderr,
            "gale-client: %s: the scene has %u trees, more than this client holds (%s): "
            "holding the %u nearest (%.2f, %.2f), within %.2f m; the others are not drawn, and "
            "the server is asked for these alone (a circle view of %.1f m)\n",
            cli_net_server_name(c->net), h->n_scene, h->why, h->circle.n_held, h->circle.cx,
            h->circle.cy, h->circle.radius_m, (double)h->view_radius_m);
}

uint32_t client_hold_tree(const client *c, uint32_t t)
{
    if (!c->hold.reduced) {
        return t;
    }
    return t < c->hold.n_scene && c->hold.slot[t] >= 0 ? (uint32_t)c->hold.slot[t] : UINT32_MAX;
}

const wire_frame *client_hold_damage(client *c, const wire_frame *f, wire_frame *tmp)
{
    if (!c->hold.reduced || !(f->types & (1u << WIRE_MSG_DAMAGE))) {
        return f;
    }
    *tmp = *f;
    uint32_t k = 0;
    for (uint32_t i = 0; i < f->n_damage && k < c->hold.damage_cap; i++) {
        const uint32_t t = f->damage[i].tree;
        const uint32_t held = client_hold_tree(c, t);
        if (held != UINT32_MAX || t >= c->hold.n_scene) {
            /* a tree past the scene stays past it: damage_view counts it */
            c->hold.damage[k] = f->damage[i];
            c->hold.damage[k++].tree = held;
        }
    }
    tmp->damage = c->hold.damage;
    tmp->n_damage = k;
    return tmp;
}

void client_hold_free(client *c)
{
    free(c->hold.scene);
    free(c->hold.held);
    free(c->hold.slot);
    free(c->hold.damage);
    memset(&c->hold, 0, sizeof c->hold);
}
