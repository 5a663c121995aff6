/* Wall groups: membership, the frame clock, the swap barrier and the camera broadcast
 * (wall_group.h, protocol/PROTOCOL.md "Wall groups"). */
#include "wall_group.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wire.h"

typedef struct member {
    uint32_t conn;
    bool in;         /* reported the open frame */
} member;

typedef struct group {
    bool used;
    ctl_wall_sync sync;     /* the frame clock as sent to joiners (members updated) */
    member m[WALL_GROUP_MAX_TILES];
    int n;
    uint32_t open;          /* frame of the open barrier; valid when is_open */
    bool is_open;
    int n_in;
    uint64_t first_us;      /* first report of the open frame */
    uint32_t swapped;       /* last frame swapped */
    bool any_swapped;
    bool has_camera;
    ctl_wall_camera camera; /* the last camera, with its frame */
} group;

struct wall_groups {
    wall_send_fn send;
    void *user;
    group g[WALL_GROUP_MAX];
    wall_group_stats st;
};

wall_groups *wall_groups_create(wall_send_fn send, void *user)
{
    wall_groups *g = calloc(1, sizeof *g);
    if (g) {
        g->send = send;
        g->user = user;
    }
    return g;
}

void wall_groups_destroy(wall_groups *g)
{
    free(g);
}

static void send_msg(wall_groups *g, uint32_t conn, const ctl_msg *m)
{
    char buf[512];
    size_t len = 0;
    if (ctl_encode_into(m, buf, sizeof buf, &len, NULL) == 0) {
        g->send(g->user, conn, buf, len);
    }
}

static void close_barrier(wall_groups *g, group *gr)
{
    if (!gr->is_open) {
        return;
    }
    ctl_msg m = { .type = CTL_WALL_SWAP };
    m.u.wall_frame = (ctl_wall_frame){ .frame = gr->open, .drawn = (uint32_t)gr->n_in,
                                       .members = (uint32_t)gr->n };
    for (int i = 0; i < gr->n; i++) {
        send_msg(g, gr->m[i].conn, &m);
        gr->m[i].in = false;
    }
    g->st.swaps++;
    g->st.complete += gr->n_in >= gr->n;
    g->st.left_out += (uint64_t)(gr->n > gr->n_in ? gr->n - gr->n_in : 0);
    gr->swapped = gr->open;
    gr->any_swapped = true;
    gr->is_open = false;
    gr->n_in = 0;
}

static group *find(wall_groups *g, uint32_t conn, int *idx)
{
    for (int k = 0; k < WALL_GROUP_MAX; k++) {
        group *gr = &g->g[k];
        for (int i = 0; gr->used && i < gr->n; i++) {
            if (gr->m[i].conn == conn) {
                *idx = i;
                return gr;
            }
        }
    }
    return NULL;
}

static group *by_name(wall_groups *g, const char *wall)
{
    for (int k = 0; k < WALL_GROUP_MAX; k++) {
        if (g->g[k].used && strcmp(g->g[k].sync.wall, wall) == 0) {
            return &g->g[k];
        }
    }
    return NULL;
}

static void remove_member(wall_groups *g, group *gr, int i)
{
    bool was_in = gr->m[i].in;
    gr->m[i] = gr->m[--gr->n];
    g->st.members--;
    if (was_in) {
        gr->n_in--;
    }
    if (gr->n == 0) {
        gr->used = false; /* the next join starts a new clock */
    } else if (gr->is_open && gr->n_in >= gr->n) {
        close_barrier(g, gr);
    }
}

int wall_groups_join(wall_groups *g, uint32_t conn, const ctl_wall_join *j, uint64_t now_us,
                     ctl_wall_sync *sync, char *why, size_t why_cap)
{
    int idx;
    group *old = find(g, conn, &idx);
    if (old) {
        remove_member(g, old, idx);
    }
    group *gr = by_name(g, j->wall);
    for (int k = 0; !gr && k < WALL_GROUP_MAX; k++) {
        if (!g->g[k].used) {
            gr = &g->g[k];
            memset(gr, 0, sizeof *gr);
            gr->used = true;
            snprintf(gr->sync.wall, sizeof gr->sync.wall, "%s", j->wall);
            gr->sync.epoch_us = now_us;
            gr->sync.period_us = (uint32_t)(1e6 / (double)j->rate_hz + 0.5);
            gr->sync.delay_us = j->delay_ms * 1000u;
            gr->sync.budget_ms = j->budget_ms;
            gr->sync.swap_lock = j->swap_lock;
        }
    }
    if (!gr) {
        snprintf(why, why_cap, "wall_join.wall: \"%.40s\": expected one of %d walls at most",
                 j->wall, WALL_GROUP_MAX);
        return WIRE_CLOSE_BAD_FIELD;
    }
    if (gr->n >= WALL_GROUP_MAX_TILES) {
        snprintf(why, why_cap, "wall_join: wall \"%.40s\" is full (%d tiles)", j->wall,
                 WALL_GROUP_MAX_TILES);
        return WIRE_CLOSE_BAD_FIELD;
    }
    gr->m[gr->n++] = (member){ .conn = conn };
    g->st.members++;
    gr->sync.members = (uint32_t)gr->n;
    *sync = gr->sync;
    if (gr->has_camera) {
        ctl_msg m = { .type = CTL_WALL_CAMERA };
        m.u.wall_camera = gr->camera;
        send_msg(g, conn, &m);
    }
    return 0;
}

int wall_groups_drawn(wall_groups *g, uint32_t conn, uint32_t frame, uint64_t now_us, char *why,
                      size_t why_cap)
{
    int i;
    group *gr = find(g, conn, &i);
    if (!gr) {
        snprintf(why, why_cap, "wall_drawn: before wall_join");
        return WIRE_CLOSE_ORDER;
    }
    if (gr->any_swapped && frame <= gr->swapped) {
        g->st.late++; /* left out of that frame already: it swaps on the swap it holds */
        return 0;
    }
    if (gr->is_open && frame > gr->open) {
        close_barrier(g, gr); /* a member is on to the next frame: the open one is done */
    }
    if (gr->is_open && frame < gr->open) {
        g->st.late++;
        return 0;
    }
    if (!gr->is_open) {
        gr->is_open = true;
        gr->open = frame;
        gr->first_us = now_us;
        gr->n_in = 0;
    }
    if (!gr->m[i].in) {
        gr->m[i].in = true;
        gr->n_in++;
    }
    if (gr->n_in >= gr->n) {
        close_barrier(g, gr);
    }
    return 0;
}

int wall_groups_camera(wall_groups *g, const ctl_wall_camera *c, uint64_t now_us, char *why,
                       size_t why_cap)
{
    group *gr = by_name(g, c->wall);
    if (!gr) {
        snprintf(why, why_cap, "wall_camera.wall: no tile of \"%.40s\" has joined", c->wall);
        return WIRE_CLOSE_BAD_FIELD;
    }
    uint64_t at = now_us + WALL_GROUP_CAMERA_LEAD_US - gr->sync.epoch_us;
    gr->camera = *c;
    gr->camera.frame = (uint32_t)(at / gr->sync.period_us + 1);
    gr->has_camera = true;
    ctl_msg m = { .type = CTL_WALL_CAMERA };
    m.u.wall_camera = gr->camera;
    for (int i = 0; i < gr->n; i++) {
        send_msg(g, gr->m[i].conn, &m);
    }
    g->st.cameras++;
    return 0;
}

void wall_groups_leave(wall_groups *g, uint32_t conn, uint64_t now_us)
{
    (void)now_us;
    int i;
    group *gr = find(g, conn, &i);
    if (gr) {
        remove_member(g, gr, i);
    }
}

void wall_groups_poll(wall_groups *g, uint64_t now_us)
{
    for (int k = 0; k < WALL_GROUP_MAX; k++) {
        group *gr = &g->g[k];
        if (gr->used && gr->is_open &&
            now_us - gr->first_us >= (uint64_t)gr->sync.budget_ms * 1000u) {
            close_barrier(g, gr);
        }
    }
}

wall_group_stats wall_groups_get_stats(const wall_groups *g)
{
    return g->st;
}

static const metric_row rows[] = {
    { "gale_wall_swaps_total", NULL, "wall-group swap barriers closed", METRIC_COUNTER, 0 },
    { "gale_wall_swaps_complete_total", NULL, "swap barriers closed with every tile in",
      METRIC_COUNTER, 0 },
    { "gale_wall_left_out_total", NULL, "tile-frames left out of a swap (late past the budget)",
      METRIC_COUNTER, 0 },
    { "gale_wall_late_reports_total", NULL, "frame reports after their frame was swapped",
      METRIC_COUNTER, 0 },
    { "gale_wall_cameras_total", NULL, "wall cameras broadcast", METRIC_COUNTER, 0 },
    { "gale_wall_tiles", NULL, "tiles in wall groups now", METRIC_GAUGE, 0 },
};

static void fill(void *ctx, double *v)
{
    const wall_group_stats *st = &((const wall_groups *)ctx)->st;
    v[0] = (double)st->swaps;
    v[1] = (double)st->complete;
    v[2] = (double)st->left_out;
    v[3] = (double)st->late;
    v[4] = (double)st->cameras;
    v[5] = st->members;
}

int wall_groups_register(wall_groups *g, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, rows, (int)(sizeof rows / sizeof rows[0]), fill, g, err);
}
