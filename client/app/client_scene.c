/* gale-client scene setup: from the welcome's copies to the GPU (species loaded once per
 * content hash over a session, instances, houses), the jitter buffer sized to the scene,
 * and the camera fitted to the trees once per run. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "client.h"
#include "lod_policy.h"

void client_scene_reset_camera(client *c)
{
    if (c->a.camera_preset >= 0) {
        camera_preset_apply(&c->cam, c->a.camera_preset, c->w_instances, c->w.n_instances,
                            c->w_species, c->w.n_species);
        return;
    }
    float centre[3] = { 0, 0, 0 }, radius = 10.0f;
    uint32_t n = c->w.n_instances;
    for (uint32_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            centre[k] += c->w_instances[i].pos[k] / (float)n;
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        float dx = c->w_instances[i].pos[0] - centre[0], dy = c->w_instances[i].pos[1] - centre[1];
        radius = fmaxf(radius, sqrtf(dx * dx + dy * dy));
    }
    centre[2] += 4.0f; /* about crown height of the default species */
    camera_init(&c->cam, centre, fminf(1.6f * radius + 22.0f, 1500.0f));
}

int client_scene_setup(client *c, gale_err *err)
{
    c->scene_pending = false;
    for (uint32_t s = 0; s < c->w.n_species; s++) {
        const ctl_species *sp = &c->w_species[s];
        c->species_id[s] = -1;
        for (uint32_t k = 0; k < c->n_loaded; k++) {
            if (strcmp(c->loaded[k].hash, sp->hash) == 0) {
                c->species_id[s] = c->loaded[k].render_id;
            }
        }
        if (c->species_id[s] >= 0) {
            continue; /* already on the GPU (a reconnection to the same scene) */
        }
        if (c->n_loaded == CLIENT_MAX_SPECIES) {
            return gale_errf(err, GALE_E_RANGE, "more than %u species over this session",
                             CLIENT_MAX_SPECIES);
        }
        asset a = { 0 };
        int rc = client_assets_load(c, sp, &a, err);
        if (rc != 0) {
            return rc;
        }
        int id = render_add_species(c->r, &a, err);
        client_audio_species(c, id, &a); /* its diameter classes, for the sound */
        const float height_m = a.height_m;
        asset_fini(&a);
        if (id < 0) {
            return id;
        }
        c->species_id[s] = id;
        snprintf(c->loaded[c->n_loaded].hash, sizeof c->loaded[c->n_loaded].hash, "%s", sp->hash);
        c->loaded[c->n_loaded].height_m = height_m;
        c->loaded[c->n_loaded++].render_id = id;
    }
    if (c->hold.reduced) {
        /* the circle view's radius: the server widens it by the tallest tree */
        float height_m[CLIENT_MAX_SPECIES] = { 0 };
        for (uint32_t s = 0; s < c->w.n_species; s++) {
            for (uint32_t k = 0; k < c->n_loaded; k++) {
                if (c->loaded[k].render_id == c->species_id[s]) {
                    height_m[s] = c->loaded[k].height_m;
                }
            }
        }
        client_hold_margin(c, height_m);
    }
    uint32_t n = c->w.n_instances;
    render_instance *inst = calloc(n ? n : 1, sizeof *inst);
    if (!inst) {
        return gale_errf(err, GALE_E_NOMEM, "no memory for %u trees", n);
    }
    for (uint32_t i = 0; i < n; i++) {
        const ctl_instance *w = &c->w_instances[i];
        if (w->species >= c->w.n_species) {
            free(inst);
            return gale_errf(err, GALE_E_RANGE,
                             "welcome.instances[%u].species: expected < %u, got %u", i,
                             c->w.n_species, w->species);
        }
        inst[i] = (render_instance){ .species = (uint32_t)c->species_id[w->species],
                                     .pos = { w->pos[0], w->pos[1], w->pos[2] },
                                     .yaw = w->yaw_rad,
                                     .scale = w->scale };
    }
    int rc = render_set_instances(c->r, n, inst, err);
    free(inst);
    float lo[2] = { 0.0f, 0.0f }, hi[2] = { 0.0f, 0.0f };
    for (uint32_t i = 0; i < n; i++) {
        for (int k = 0; k < 2; k++) {
            lo[k] = i == 0 || c->w_instances[i].pos[k] < lo[k] ? c->w_instances[i].pos[k] : lo[k];
            hi[k] = i == 0 || c->w_instances[i].pos[k] > hi[k] ? c->w_instances[i].pos[k] : hi[k];
        }
    }
    render_set_fog_dist(c->r, fog_for_scene(lo, hi));
    if (rc == 0) {
        rc = render_set_obstacles(c->r, c->w.n_obstacles, c->w_boxes, err);
    }
    if (rc != 0) {
        return rc;
    }
    uint32_t stride = 0;
    render_q_staging(c->r, &stride);
    c->stride = stride ? stride : 1;
    c->n_values = (n ? n : 1) * c->stride;
    jitter_destroy(c->jit);
    free(c->snap);
    c->snap = calloc(c->n_values, sizeof(float));
    size_t fit = CLIENT_JITTER_BYTES / ((size_t)c->n_values * sizeof(float));
    uint32_t held =
        fit < CLIENT_JITTER_SNAPSHOTS
            ? (fit > CLIENT_JITTER_MIN_SNAPSHOTS ? (uint32_t)fit : CLIENT_JITTER_MIN_SNAPSHOTS)
            : CLIENT_JITTER_SNAPSHOTS;
    c->jit = jitter_create(
        &(jitter_desc){ .n_values = c->n_values, .capacity = held, .playout_delay_s = c->a.delay_s },
        err);
    if (!c->snap || !c->jit) {
        return err && err->code ? err->code : GALE_E_NOMEM;
    }
    if (!c->camera_set) {
        client_scene_reset_camera(c);
        c->camera_set = true;
    }
    client_view_scene(c);
    c->scene_ready = true;
    client_damage_draw(c);
    fprintf(stderr, "gale-client: scene ready: %u species on the GPU, %u trees, %u q per tree\n",
            c->n_loaded, n, c->stride);
    client_hold_say(c);
    return 0;
}
