/* gale-client as a wall tile: the wall file of --wall and its tile (wall.h), the tile's
 * view and projection, and the HUD's size on its glass (configs/walls/README.md). */
#include <stdio.h>
#include <stdlib.h>

#include "client.h"
#include "wall.h"

int client_wall_setup(client *c)
{
    if (!c->a.wall_path) {
        return 0;
    }
    c->wall = malloc(sizeof *c->wall);
    if (!c->wall) {
        fprintf(stderr, "gale-client: --wall: out of memory\n");
        return -1;
    }
    gale_err err = { 0 };
    if (wall_load(c->wall, c->a.wall_path, &err) != 0) {
        fprintf(stderr, "gale-client: --wall: %s\n", err.msg);
        return -1;
    }
    if (c->a.role == CTL_ROLE_KIOSK && !c->a.list_tiles) {
        c->wall_tile = -1; /* the operator: no tile of its own */
        return 0;
    }
    if (c->a.list_tiles) {
        for (int i = 0; i < c->wall->n_tiles; i++) {
            printf("%s\n", c->wall->tiles[i].name);
        }
        return 1;
    }
    if (!c->a.tile_name) {
        fprintf(stderr, "gale-client: --wall %s: --tile NAME is required (one of the file's "
                        "tiles; --list-tiles lists them)\n",
                c->a.wall_path);
        return -1;
    }
    c->wall_tile = wall_find_tile(c->wall, c->a.tile_name);
    if (c->wall_tile < 0) {
        fprintf(stderr, "gale-client: --tile: %s has no tile \"%s\" (--list-tiles lists them)\n",
                c->a.wall_path, c->a.tile_name);
        return -1;
    }
    if (!c->a.size_set) {
        c->a.width = c->wall->tiles[c->wall_tile].px[0];
        c->a.height = c->wall->tiles[c->wall_tile].px[1];
    }
    return 0;
}

float client_wall_hud_px(const client *c, float default_px)
{
    if (!c->wall) {
        if (c->a.role == CTL_ROLE_WALL_TILE && (c->a.tile[0] != 0 || c->a.tile[1] != 0)) {
            return 0.0f; /* --tile C,R,COLS,ROWS: the HUD on tile 0,0 only */
        }
        return default_px;
    }
    if (c->wall_tile < 0) {
        return default_px; /* the operator's own screen */
    }
    /* at this tile's framebuffer height (--size may differ from the file's px) */
    return wall_hud_px(c->wall, c->wall_tile, c->a.height);
}

void client_wall_matrices(const client *c, int fb_w, int fb_h, float z_near, float z_far,
                          float view[16], float proj[16])
{
    float cam_view[16];
    camera_view(&c->cam, cam_view);
    if (c->wall) {
        wall_tile_matrices(c->wall, c->wall_tile, cam_view, z_near, z_far, view, proj);
        return;
    }
    for (int k = 0; k < 16; k++) {
        view[k] = cam_view[k];
    }
    camera_tile_proj(&c->cam, c->a.tile[0], c->a.tile[1], c->a.tile[2], c->a.tile[3],
                     (float)fb_w / (float)fb_h, c->a.bezel, z_near, z_far, proj);
}
