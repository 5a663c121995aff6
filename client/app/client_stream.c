/* gale-client network events (cli_net handler): the welcome's scene kept as owned copies
 * for client_scene.c, decoded state into the jitter buffer, shed leaves and the coarse
 * wind into the renderer (protocol/PROTOCOL.md message types). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "client.h"

void client_stream_on_welcome(void *user, const ctl_welcome *w)
{
    client *c = user;
    free(c->w_species);
    free(c->w_instances);
    free(c->w_boxes);
    c->w = *w;
    c->w.obstacles = NULL; /* kept as c->w_boxes */
    c->w.scenarios = NULL; /* kept as the kiosk panel's buttons */
    c->w.n_scenarios = 0;
    client_kiosk_on_welcome(c, w);
    c->w_instances = NULL;
    c->w.instances = NULL;
    c->w_species = malloc((w->n_species ? w->n_species : 1) * sizeof *c->w_species);
    c->w_boxes = malloc((w->n_obstacles ? w->n_obstacles : 1) * 6 * sizeof *c->w_boxes);
    if (!c->w_species || !c->w_boxes || w->n_species > CLIENT_MAX_SPECIES) {
        fprintf(stderr, "gale-client: welcome: cannot hold %u species, %u trees\n", w->n_species,
                w->n_instances);
        c->w.n_species = c->w.n_instances = c->w.n_obstacles = 0;
        return;
    }
    for (uint32_t i = 0; i < w->n_obstacles; i++) {
        memcpy(&c->w_boxes[6 * i], w->obstacles[i].min, 3 * sizeof(float));
        memcpy(&c->w_boxes[6 * i + 3], w->obstacles[i].max, 3 * sizeof(float));
    }
    memcpy(c->w_species, w->species, w->n_species * sizeof *c->w_species);
    c->w.species = c->w_species;
    c->scene_ready = false;
    /* the trees this client holds of the scene's, and the damage view of those */
    gale_err err = { 0 };
    if (client_hold_welcome(c, w, &err) != 0) {
        fprintf(stderr, "gale-client: welcome: cannot hold %u trees: %s\n", w->n_instances,
                err.msg);
        c->w.n_species = c->w.n_instances = c->w.n_obstacles = 0;
        return;
    }
    c->scene_pending = true;
    c->live_since_welcome = false;
    fprintf(stderr,
            "gale-client: %s: welcome as %s, %u species, %u trees, %u houses, %.0f Hz snapshots\n",
            cli_net_server_name(c->net), ctl_role_name(w->role) ? ctl_role_name(w->role) : "?",
            w->n_species, w->n_instances, w->n_obstacles, (double)w->snapshot_hz);
}

static void take_state(client *c, const wire_frame *f, const wire_decoder *dec, double recv_s)
{
    wire_state st = wire_decoder_state(dec);
    if (st.n_trees != c->hold.n_scene) {
        c->frames_mismatch++;
        return;
    }
    uint32_t sent = 0;
    for (uint32_t t = 0; t < st.n_trees; t++) {
        sent += st.n_modes[t] > 0;
    }
    c->hold.trees_sent = sent;
    /* the trees held, in their order (a reduced view's are some of the stream's) */
    for (uint32_t k = 0; k < c->w.n_instances; k++) {
        const uint32_t t = c->hold.reduced ? c->hold.held[k] : k;
        wire_decoder_q(dec, t, c->snap + (size_t)k * c->stride, c->stride);
    }
    gale_err err = { 0 };
    if (jitter_insert(c->jit, f->hdr.tick, (double)f->hdr.server_time_us * 1e-6, c->snap, &err) <
        0) {
        fprintf(stderr, "gale-client: %s\n", err.msg);
        return;
    }
    if (!c->live_since_welcome) {
        c->live_since_welcome = true;
        fprintf(stderr, "gale-client: receiving state from tick %u\n", f->hdr.tick);
    }
    if (!c->got_state) {
        /* the stream's rate is measured from the first state on (main.c's summary) */
        c->state_t0_s = recv_s;
        c->state_bytes0 = cli_net_get_stats(c->net).bytes_rx;
    }
    c->got_state = true;
}

static void take_leaves(client *c, const wire_frame *f)
{
    const double tick_hz = c->w.tick_hz > 0.0f ? (double)c->w.tick_hz : 60.0;
    const double t_hdr = (double)f->hdr.server_time_us * 1e-6;
    for (uint32_t i = 0; i < f->n_leaves; i++) {
        const wire_leaf *l = &f->leaves[i];
        const uint32_t tree = client_hold_tree(c, l->instance);
        if (tree == UINT32_MAX) {
            continue; /* a tree not held sheds no leaf here */
        }
        if (c->leaves_frame >= CLIENT_LEAVES_PER_FRAME) {
            c->leaves_thinned += f->n_leaves - i;
            return;
        }
        c->leaves_frame++;
        render_leaf_seed s = {
            .tree = tree,
            .slot = l->slot,
            .spawn_time_s =
                t_hdr - (double)((int64_t)f->hdr.tick - (int64_t)l->spawn_tick) / tick_hz,
            .seed = l->seed,
        };
        if (render_add_falling_leaf(c->r, &s, NULL) != 0) {
            c->leaves_bad++;
        }
    }
}

static void take_wind(client *c, const wire_wind *w)
{
    const uint32_t n = (uint32_t)w->nx * w->ny;
    double sum_speed = 0.0, mean[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < n; i++) {
        float v[3];
        for (int k = 0; k < 3; k++) {
            v[k] = (float)w->v[3 * i + k] * w->scale_ms;
            c->wind_v[3 * i + k] = v[k];
            mean[k] += (double)v[k];
        }
        sum_speed += sqrt((double)(v[0] * v[0] + v[1] * v[1]));
    }
    c->wind_ms = n ? (float)(sum_speed / n) : 0.0f;
    c->have_wind = n > 0;
    render_wind rw = {
        .uniform = { n ? (float)(mean[0] / n) : 0, n ? (float)(mean[1] / n) : 0,
                     n ? (float)(mean[2] / n) : 0 },
        .nx = w->nx,
        .ny = w->ny,
        .nz = 1,
        .origin = { w->x0_m, w->y0_m, 0.0f },
        .cell = { w->cell_m, w->cell_m, 2.0f * w->z_m > 1.0f ? 2.0f * w->z_m : 1.0f },
        .v = c->wind_v,
    };
    if (c->r) {
        render_set_wind(c->r, &rw, NULL);
    }
}

void client_stream_on_frame(void *user, const wire_frame *f, const wire_decoder *dec, double recv_s)
{
    client *c = user;
    /* f->types: one frame, or every frame of a BUNDLE (PROTOCOL.md "BUNDLE") */
    if (f->types & (1u << WIRE_MSG_WIND)) {
        take_wind(c, &f->wind);
    }
    if (f->types & (1u << WIRE_MSG_FOREST)) {
        client_damage_take_forest(c, f); /* with the frame's DAMAGE, if any (client_damage.c) */
    } else if (f->types & (1u << WIRE_MSG_DAMAGE)) {
        wire_frame held;
        client_damage_take(c, client_hold_damage(c, f, &held)); /* client_damage.c */
    }
    if (f->types & (1u << WIRE_MSG_WEATHER)) {
        c->wx = f->weather; /* the HUD names the server's figures, never an average */
        c->have_wx = true;
    }
    if (!c->scene_ready) {
        return; /* the decoder keeps its state; the jitter buffer starts once assets are in */
    }
    if (f->types & ((1u << WIRE_MSG_KEYFRAME) | (1u << WIRE_MSG_DELTA))) {
        take_state(c, f, dec, recv_s);
    }
    if (f->types & (1u << WIRE_MSG_LEAVES)) {
        take_leaves(c, f);
    }
}

void client_stream_on_lost(void *user, int close_code, const char *why)
{
    client *c = user;
    (void)close_code;
    (void)why;
    /* keep drawing the last state; the stream resumes from the next keyframe */
    if (c->jit) {
        jitter_reset(c->jit);
    }
}
