/* gale-client in its wall's group (protocol/PROTOCOL.md "Wall groups"): joins on every
 * connection, draws the next frame N ahead of its instant, presents it when the server
 * clock reaches the group's epoch + N period and shows server time of that instant minus
 * the delay (the same for every tile, not each
 * tile's own estimate), in swap-lock mode reports "frame N drawn" and presents on "swap N"
 * (or after the budget), takes the wall's camera at the frame it is stamped with, else the
 * wall file's tour, and writes the frame log. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <epoxy/gl.h>

#include "client.h"
#include "mono.h"
#include "wall.h"

static void set_orbit(camera *cam, const float target[3], float distance_m, float yaw_deg,
                      float pitch_deg)
{
    const float fov = cam->fov_y_deg;
    camera_init(cam, target, distance_m);
    cam->fov_y_deg = fov;
    cam->yaw = yaw_deg * 0.017453293f;
    cam->pitch = pitch_deg * 0.017453293f;
    camera_eye(cam, cam->eye);
}

/* The tour's camera at server time t_s (wall_tour_at): a pure function of the frame's
 * time, so every tile agrees on every frame. */
static void tour_camera(const wall *w, double t_s, camera *cam)
{
    wall_stop s;
    wall_tour_at(w, t_s, &s);
    set_orbit(cam, s.target_m, s.distance_m, s.yaw_deg, s.pitch_deg);
}

void client_wall_group_on_wall(void *user, const ctl_msg *m)
{
    client *c = user;
    client_wall_group *g = &c->wg;
    if (m->type == CTL_SCHEDULE) {
        client_closed_on_schedule(c, &m->u.schedule); /* not a wall's, but every role's */
    } else if (m->type == CTL_WALL_SYNC) {
        g->sync = m->u.wall_sync;
        g->have_sync = true;
        fprintf(stderr, "gale-client: wall %s: joined at mono_us %" PRIu64 ", %u tile(s), %.1f Hz%s\n",
                g->sync.wall, mono_us(), g->sync.members, 1e6 / g->sync.period_us,
                g->sync.swap_lock ? ", swap-lock" : "");
    } else if (m->type == CTL_WALL_SWAP) {
        if (!g->have_swap || m->u.wall_frame.frame > g->swap) {
            g->swap = m->u.wall_frame.frame;
            g->have_swap = true;
        }
    } else if (m->type == CTL_WALL_CAMERA) {
        g->camera = m->u.wall_camera;
        g->have_camera = true;
    }
}

static double server_now_s(client *c)
{
    double s = mono_s();
    jitter_clock_server_time(cli_net_clock(c->net), s, &s);
    return s;
}

static void join(client *c, uint32_t connects)
{
    client_wall_group *g = &c->wg;
    ctl_msg m = { .type = CTL_WALL_JOIN };
    ctl_wall_join *j = &m.u.wall_join;
    snprintf(j->wall, sizeof j->wall, "%s", c->wall->name);
    snprintf(j->tile, sizeof j->tile, "%s", c->wall->tiles[c->wall_tile].name);
    j->swap_lock = c->a.swap_lock;
    j->rate_hz = c->a.rate_hz;
    j->budget_ms = (uint32_t)c->a.budget_ms;
    j->delay_ms = (uint32_t)(c->a.delay_s * 1e3 + 0.5);
    gale_err err = { 0 };
    if (cli_net_send_wall(c->net, &m, &err) != 0) {
        fprintf(stderr, "gale-client: wall_join: %s\n", err.msg);
        return;
    }
    /* a new connection may be a new server: a new clock, frames from its numbering */
    g->joined_connects = connects;
    g->have_sync = g->have_last = g->have_swap = g->have_camera = false;
}

/* The operator (a kiosk with --wall): its camera to the wall, at most 5 times a second and
 * only when it moved (the kiosk's message budget, PROTOCOL.md). */
static void operate(client *c)
{
    client_wall_group *g = &c->wg;
    const double now = mono_s();
    if (now < g->next_camera_s || cli_net_get_stats(c->net).state != CLI_NET_LIVE) {
        return;
    }
    ctl_msg m = { .type = CTL_WALL_CAMERA };
    ctl_wall_camera *w = &m.u.wall_camera;
    snprintf(w->wall, sizeof w->wall, "%s", c->wall->name);
    float f[3], eye[3];
    camera_forward(&c->cam, f);
    camera_eye(&c->cam, eye);
    w->distance_m = c->cam.mode == CAMERA_ORBIT ? c->cam.distance : 10.0f;
    for (int k = 0; k < 3; k++) {
        w->target_m[k] = eye[k] + f[k] * w->distance_m;
    }
    w->yaw_deg = remainderf(c->cam.yaw * 57.29578f, 720.0f);
    w->pitch_deg = c->cam.pitch * 57.29578f;
    if (g->sent_camera && !memcmp(&g->last_sent, w, sizeof *w)) {
        return;
    }
    gale_err err = { 0 };
    if (cli_net_send_wall(c->net, &m, &err) == 0) {
        g->last_sent = *w;
        g->sent_camera = true;
        g->next_camera_s = now + 0.2;
    }
}

bool client_wall_group_begin(client *c)
{
    client_wall_group *g = &c->wg;
    g->have_frame = false;
    if (!c->wall) {
        return false;
    }
    if (c->wall_tile < 0) {
        if (c->camera_set) {
            operate(c);
        }
        return false;
    }
    cli_net_stats ns = cli_net_get_stats(c->net);
    if (ns.state == CLI_NET_LIVE && g->joined_connects != ns.connects) {
        join(c, ns.connects);
    }
    if (!g->have_sync || ns.state != CLI_NET_LIVE) {
        return false;
    }
    const double epoch_s = (double)g->sync.epoch_us * 1e-6;
    const double period_s = (double)g->sync.period_us * 1e-6;
    /* the next frame whose instant is still ahead: drawn now, presented at its instant
     * (client_wall_group_before_present), never one frame twice */
    double n = floor((server_now_s(c) - epoch_s) / period_s) + 1.0;
    if (g->have_last && n <= (double)g->last_frame) {
        n = (double)g->last_frame + 1.0;
    } else if (g->have_last) {
        g->skipped += (uint64_t)(n - (double)g->last_frame - 1.0);
    }
    if (n < 0.0) {
        n = 0.0;
    }
    g->frame = (uint32_t)n;
    g->have_frame = true;
    g->render_us = (int64_t)g->sync.epoch_us + (int64_t)g->frame * g->sync.period_us -
                   (int64_t)g->sync.delay_us;
    g->render_t = (double)g->render_us * 1e-6;
    if (g->have_camera && g->frame >= g->camera.frame) {
        set_orbit(&c->cam, g->camera.target_m, g->camera.distance_m, g->camera.yaw_deg,
                  g->camera.pitch_deg);
        g->have_camera = false;
        g->camera_from_server = true;
        c->camera_set = true;
        fprintf(stderr, "gale-client: wall camera stamped frame %" PRIu32 " taken at frame %" PRIu32 "\n",
                g->camera.frame, g->frame);
    } else if (!g->camera_from_server && c->wall->n_stops >= 2) {
        tour_camera(c->wall, epoch_s + n * period_s, &c->cam);
        c->camera_set = true;
    }
    return true;
}

void client_wall_group_before_present(client *c)
{
    client_wall_group *g = &c->wg;
    if (!g->have_frame) {
        return;
    }
    glFinish(); /* the frame is drawn: what is left is waiting for its instant */
    bool reported = false;
    if (g->sync.swap_lock) {
        ctl_msg m = { .type = CTL_WALL_DRAWN };
        m.u.wall_frame.frame = g->frame;
        gale_err err = { 0 };
        reported = cli_net_send_wall(c->net, &m, &err) == 0;
    }
    /* the frame's instant on the server clock (at most a second away, whatever the clock
     * estimate does meanwhile) */
    const double due = ((double)g->sync.epoch_us + (double)g->frame * g->sync.period_us) * 1e-6;
    const double give_up = mono_s() + 1.0;
    for (double left; (left = due - server_now_s(c)) > 0.0 && mono_s() < give_up;) {
        cli_net_poll(c->net);
        left = due - server_now_s(c);
        if (left > 0.0) {
            usleep((useconds_t)(fmin(left, 1e-3) * 1e6));
        }
    }
    /* swap-lock: then "swap N", at most the budget later */
    const double until = mono_s() + (double)g->sync.budget_ms * 1e-3;
    while (reported && !(g->have_swap && g->swap >= g->frame)) {
        double now = mono_s();
        if (now >= until) {
            g->swap_timeouts++;
            break;
        }
        cli_net_poll(c->net);
        if (!(g->have_swap && g->swap >= g->frame)) {
            usleep(100);
        }
    }
}

void client_wall_group_after_present(client *c)
{
    client_wall_group *g = &c->wg;
    const uint64_t at_us = mono_us();
    uint32_t frame = (uint32_t)g->presented;
    if (g->have_frame) {
        frame = g->frame;
        g->last_frame = g->frame;
        g->have_last = true;
    }
    g->presented++;
    /* a wall tile logs group frames only: before its wall_sync it has no frame number */
    if (g->log && (g->have_frame || !c->wall)) {
        fprintf(g->log, "%" PRIu64 " %" PRId64 " %" PRIu32 "\n", at_us,
                g->have_frame ? g->render_us : (int64_t)llround(g->render_t * 1e6), frame);
    }
}
