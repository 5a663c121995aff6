/* gale-client's view (PROTOCOL.md "view"): the cone around the last frame's frustum, sent
 * as the camera moves, so the server streams the trees this client draws and no others;
 * in a reduced view (client_hold.c) the circle of the trees held instead, once a
 * connection, whatever the camera does and with --view all too: a view is one shape, and
 * no tree past the circle can be drawn, so the frustum would only ask for less.
 * Past lod_m a tree is drawn thinned or as an impostor (lod_policy.h), which pose with no
 * more than the server's few modes (SERVER.md "Views and LOD"): lod_m is FULL's outer
 * distance at the frame's budget scale, widened by VIEW_LOD_MARGIN since the renderer
 * measures to a tree's middle and the server to its root; far_m the impostors' reach. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "client.h"
#include "lod_policy.h"
#include "render_cull.h"

#define VIEW_LOD_MARGIN 1.1f

void client_view_scene(client *c)
{
    c->view.sent = false; /* a new scene: ask again */
}

static bool differs(const client_view *v, const float eye[3], const float axis[3], float fov_deg,
                    float far_m, float lod_m)
{
    float dx = eye[0] - v->eye[0], dy = eye[1] - v->eye[1], dz = eye[2] - v->eye[2];
    float turn = axis[0] * v->axis[0] + axis[1] * v->axis[1] + axis[2] * v->axis[2];
    const float turn_cos = cosf(CLIENT_VIEW_TURN_DEG * (float)M_PI / 180.0f);
    return dx * dx + dy * dy + dz * dz > CLIENT_VIEW_MOVE_M * CLIENT_VIEW_MOVE_M ||
           turn < turn_cos || fabsf(fov_deg - v->fov_deg) > CLIENT_VIEW_TURN_DEG ||
           fabsf(far_m - v->far_m) > CLIENT_VIEW_MOVE_M ||
           fabsf(lod_m - v->lod_m) > 0.1f * v->lod_m; /* the budget's scale moved */
}

/* The reduced view's circle about the trees held, at full modes (the limit bounds the
 * stream), once a connection. */
static void send_circle(client *c, double now)
{
    ctl_msg m = { .type = CTL_VIEW };
    m.u.view = (ctl_view){ .kind = CTL_VIEW_CIRCLE,
                           .x = (float)c->hold.circle.cx,
                           .y = (float)c->hold.circle.cy,
                           .radius_m = c->hold.view_radius_m };
    gale_err err = { 0 };
    if (cli_net_send_ctl(c->net, &m, NULL, 0, &err) != 0) {
        return; /* the send queue is full or the connection went: the next frame retries */
    }
    c->view.sent = true;
    c->view.connects = cli_net_get_stats(c->net).connects;
    c->view.sent_s = now;
    c->view.n_sent++;
}

void client_view_update(client *c, double now)
{
    if ((c->a.view_all && !c->hold.reduced) || !c->scene_ready) {
        return;
    }
    cli_net_stats ns = cli_net_get_stats(c->net);
    if (ns.state != CLI_NET_LIVE) {
        return;
    }
    client_view *v = &c->view;
    if (!v->sent || ns.connects != v->connects) {
        v->sent = false; /* a new connection streams the whole scene until told */
    } else if (now - v->sent_s < CLIENT_VIEW_MIN_S || c->hold.reduced) {
        return;
    }
    if (c->hold.reduced) {
        send_circle(c, now);
        return;
    }
    float vp[16], eye[3], axis[3], fov_deg, far_m, full_m;
    render_last_view(c->r, vp, eye, &full_m);
    if (!render_cull_cone(vp, eye, axis, &fov_deg, &far_m)) {
        return;
    }
    far_m = fminf(far_m, VIEW_FAR_M * VIEW_LOD_MARGIN);
    const float lod_m = full_m * VIEW_LOD_MARGIN;
    if (v->sent && !differs(v, eye, axis, fov_deg, far_m, lod_m)) {
        return;
    }
    ctl_msg m = { .type = CTL_VIEW };
    if (fov_deg > 179.0f) {
        m.u.view.kind = CTL_VIEW_ALL; /* wider than a cone can say: everything */
    } else {
        m.u.view = (ctl_view){ .kind = CTL_VIEW_FRUSTUM,
                               .fov_deg = fmaxf(fov_deg, 1.0f),
                               .far_m = fminf(fmaxf(far_m, 0.001f), 1e6f),
                               .lod_m = lod_m };
        memcpy(m.u.view.eye, eye, sizeof eye);
        memcpy(m.u.view.dir, axis, sizeof axis);
    }
    gale_err err = { 0 };
    if (cli_net_send_ctl(c->net, &m, NULL, 0, &err) != 0) {
        return; /* the send queue is full or the connection went: the next frame retries */
    }
    v->sent = true;
    v->connects = ns.connects;
    v->sent_s = now;
    memcpy(v->eye, eye, sizeof eye);
    memcpy(v->axis, axis, sizeof axis);
    v->fov_deg = fov_deg;
    v->far_m = far_m;
    v->lod_m = m.u.view.lod_m;
    v->n_sent++;
}
