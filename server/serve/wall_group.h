/* Wall groups (protocol/PROTOCOL.md "Wall groups"): the tiles of one wall share a frame
 * clock (frame N shows server time epoch + N period − delay), and in swap-lock mode a
 * barrier per frame: when every member has reported frame N drawn, or the budget since the
 * first report has passed, or a member reports a later frame, every member is told
 * "swap N"; members that had not reported are left out of that frame and counted, and take
 * part again from their next report. The wall's camera (from a kiosk) goes to every member
 * stamped with the frame they first draw it at. Plain logic over connection ids: the
 * caller (srv_control.c, lws thread) passes the clock and a send function. */
#ifndef GALE_WALL_GROUP_H
#define GALE_WALL_GROUP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ctl.h"
#include "metric.h"

#define WALL_GROUP_MAX        8   /* walls served at once */
#define WALL_GROUP_MAX_TILES  128 /* members of one wall */
#define WALL_GROUP_CAMERA_LEAD_US 100000 /* a camera applies this far ahead of the frame
                                            being presented, so every tile has it first */

/* Sends text (len bytes) to connection conn; failures are the caller's to handle. */
typedef void (*wall_send_fn)(void *user, uint32_t conn, const char *text, size_t len);

typedef struct wall_group_stats {
    uint64_t swaps;       /* barriers closed */
    uint64_t complete;    /* ... with every member in */
    uint64_t left_out;    /* member-frames left out of a swap */
    uint64_t late;        /* reports of a frame already swapped */
    uint64_t cameras;     /* cameras broadcast */
    uint32_t members;     /* tiles in all groups now */
} wall_group_stats;

typedef struct wall_groups wall_groups;

wall_groups *wall_groups_create(wall_send_fn send, void *user);
void wall_groups_destroy(wall_groups *g);

/* conn joins j->wall (created with j's rate, budget, delay and swap-lock on the first join;
 * later joins take the group's). *sync: the reply. Sends the wall's camera, when it has
 * one, after. A conn already in a group moves. 0, or a close code (enum wire_close) with
 * why (the group is full, too many walls). */
int wall_groups_join(wall_groups *g, uint32_t conn, const ctl_wall_join *j, uint64_t now_us,
                     ctl_wall_sync *sync, char *why, size_t why_cap);
/* conn drew frame; may close barriers (sends wall_swap). 0, or a close code with why
 * (conn is in no group). */
int wall_groups_drawn(wall_groups *g, uint32_t conn, uint32_t frame, uint64_t now_us,
                      char *why, size_t why_cap);
/* A kiosk's camera for wall c->wall: stamped with the frame at now + the lead and sent to
 * every member. 0, or a close code with why (no such wall). */
int wall_groups_camera(wall_groups *g, const ctl_wall_camera *c, uint64_t now_us, char *why,
                       size_t why_cap);
/* conn left (closed): removed from its group; a barrier waiting only on it closes. */
void wall_groups_leave(wall_groups *g, uint32_t conn, uint64_t now_us);
/* Closes every barrier whose budget has passed (called on every control message). */
void wall_groups_poll(wall_groups *g, uint64_t now_us);

wall_group_stats wall_groups_get_stats(const wall_groups *g);

/* The groups' rows (gale_wall_swaps_total, gale_wall_swaps_complete_total,
 * gale_wall_left_out_total, gale_wall_late_reports_total, gale_wall_cameras_total,
 * gale_wall_tiles) into r; filled on the thread that renders /metrics, which is the lws
 * thread the groups live on. */
int wall_groups_register(wall_groups *g, metric_reg *r, gale_err *err);

#endif
