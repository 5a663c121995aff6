/* --fall-shots: pictures of a fall caught live by a headless gale-client (client/CLIENT.md
 * "Pictures of a fall, live"). Which tree falls is the server's: the first fall this client
 * sees begin (of those starting together, the one with the clearest view) is framed from
 * the side (camera_preset_fall) and shot at the chosen times after its stem gave way, on the
 * server clock the frames are drawn at. Also --screenshot-every's numbered frames. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera_preset.h"
#include "client.h"

/* --screenshot without ".png", else "gale" */
static void shot_prefix(const client *c, char *buf, size_t cap)
{
    snprintf(buf, cap, "%s", c->a.screenshot ? c->a.screenshot : "gale");
    size_t n = strlen(buf);
    if (n > 4 && strcmp(buf + n - 4, ".png") == 0) {
        buf[n - 4] = '\0';
    }
}

int client_fall_shots_parse(const char *spec, client_args *a)
{
    const int cap = (int)(sizeof a->fall_shot_s / sizeof a->fall_shot_s[0]);
    a->n_fall_shots = 0;
    const char *p = spec ? spec : "";
    while (*p) {
        char *end;
        double t = strtod(p, &end);
        if (end == p || !(t >= 0.0 && t <= 600.0) || (*end && *end != ',') ||
            a->n_fall_shots == cap ||
            (a->n_fall_shots > 0 && t <= a->fall_shot_s[a->n_fall_shots - 1])) {
            fprintf(stderr,
                    "gale-client: --fall-shots: expected 1..%d ascending seconds 0..600, "
                    "comma-separated, got \"%s\"\n",
                    cap, spec ? spec : "");
            return -1;
        }
        a->fall_shot_s[a->n_fall_shots++] = t;
        p = *end ? end + 1 : end;
    }
    if (a->n_fall_shots == 0) {
        fprintf(stderr, "gale-client: --fall-shots: expected seconds, got \"\"\n");
        return -1;
    }
    return 0;
}

/* Among the falls seen begin under a second ago, the one with the fewest trees in the way
 * of its side view; the camera is placed for it. UINT32_MAX: none. */
static uint32_t pick_fall(client *c)
{
    uint32_t best = UINT32_MAX, best_in_way = UINT32_MAX;
    for (uint32_t t = 0; t < c->w.n_instances; t++) {
        double t0, now;
        float az;
        if (!client_damage_live_fall(c, t, &t0, &now, &az) || now - t0 > 1.0) {
            continue;
        }
        camera cam = c->cam;
        uint32_t n = camera_preset_fall(&cam, c->w_instances, c->w.n_instances, t,
                                        render_tree_height_m(c->r, t), az);
        if (n < best_in_way) {
            best = t;
            best_in_way = n;
        }
    }
    if (best != UINT32_MAX) {
        double t0, now;
        float az;
        client_damage_live_fall(c, best, &t0, &now, &az);
        camera_preset_fall(&c->cam, c->w_instances, c->w.n_instances, best,
                           render_tree_height_m(c->r, best), az);
        fprintf(stderr, "gale-client: fall caught live: tree %u (%s) towards %.0f deg, %u trees "
                        "in the way\n",
                best, c->dmg.tree[best].fallen == WIRE_DAMAGE_UPROOT ? "uprooted" : "snapped",
                (double)az * 57.29578, best_in_way);
    }
    return best;
}

int client_fall_shots_step(client *c)
{
    if (c->a.n_fall_shots == 0 || !c->scene_ready) {
        return 0;
    }
    if (!c->fall_framed) {
        /* the camera moves for the next frame; this one still shows the old view */
        c->fall_tree = pick_fall(c);
        c->fall_framed = c->fall_tree != UINT32_MAX;
        return 0;
    }
    double t0, now;
    float az;
    if (!client_damage_live_fall(c, c->fall_tree, &t0, &now, &az)) {
        return 0; /* healed: a reset; wait for it to fall again */
    }
    const double age = now - t0;
    if (c->fall_shot_next >= c->a.n_fall_shots || age < c->a.fall_shot_s[c->fall_shot_next]) {
        return c->fall_shot_next >= c->a.n_fall_shots;
    }
    /* one picture for every time this frame has passed: its own age in the name */
    while (c->fall_shot_next < c->a.n_fall_shots && age >= c->a.fall_shot_s[c->fall_shot_next]) {
        c->fall_shot_next++;
    }
    char prefix[400], name[448];
    shot_prefix(c, prefix, sizeof prefix);
    snprintf(name, sizeof name, "%s-fall-%04.1fs.png", prefix, age);
    gale_err err = { 0 };
    if (render_write_png(c->r, name, &err) == 0) {
        fprintf(stderr, "gale-client: fall shot %s (%.2f s after the stem gave way)\n", name,
                age);
    } else {
        fprintf(stderr, "gale-client: fall shot: %s\n", err.msg);
    }
    return c->fall_shot_next >= c->a.n_fall_shots;
}

void client_shot_numbered(client *c)
{
    /* the frame log's number: a wall tile's group frame, else the frames presented before;
     * a tile's frames before it joined its group have none (nor a line in the log) */
    const client_wall_group *g = &c->wg;
    if (c->wall && c->wall_tile >= 0 && !g->have_frame) {
        return;
    }
    const uint32_t frame = g->have_frame ? g->frame : (uint32_t)g->presented;
    const int64_t server_us = g->have_frame ? g->render_us : (int64_t)llround(g->render_t * 1e6);
    char prefix[400], name[448];
    shot_prefix(c, prefix, sizeof prefix);
    snprintf(name, sizeof name, "%s-%06" PRIu32 ".png", prefix, frame);
    gale_err err = { 0 };
    if (render_write_png(c->r, name, &err) == 0) {
        fprintf(stderr, "gale-client: screenshot %s frame %" PRIu32 " server_us %" PRId64 "\n",
                name, frame, server_us);
    } else {
        fprintf(stderr, "gale-client: screenshot: %s\n", err.msg);
    }
}
