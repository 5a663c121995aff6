/* Display walls (configs/walls/README.md): a wall file names tiles, each a rectangle in
 * space (centre, normal, up, visible size, bezels, pixel size), and the viewer's eye; a
 * tile's view and projection come from the generalized perspective projection (Kooima,
 * "Generalized Perspective Projection", 2008, eqs. 1-10), so flat grids, angled walls and
 * cylinders all show one picture. Wall frame: metres, x right, y up, z towards the viewer;
 * its axes are the camera's (the camera looks along -z) and the camera stands at the
 * wall's eye point, so the scene appears behind the glass as through a window. */
#ifndef GALE_WALL_H
#define GALE_WALL_H

#include <stdbool.h>
#include <stddef.h>

#include "err.h"

#define WALL_MAX_TILES 128
#define WALL_MAX_NAME  32
#define WALL_MAX_TOUR  64

typedef struct wall_tile {
    char name[WALL_MAX_NAME];
    int px[2];          /* framebuffer width, height [px] */
    float size_m[2];    /* visible area width, height [m] */
    float bezel_m[4];   /* hidden glass left, right, top, bottom [m] (placement accounts
                           for it: centres lie a bezel pair apart from their neighbours) */
    float centre_m[3];  /* centre of the visible area, wall frame [m] */
    float normal[3];    /* unit, towards the viewer */
    float up[3];        /* unit, in the tile plane, orthogonal to normal */
} wall_tile;

/* One stop of a scripted camera tour: the orbit camera at time t_s after the tour starts
 * (looped); between stops the camera moves linearly. */
typedef struct wall_stop {
    float t_s;
    float target_m[3];
    float distance_m;
    float yaw_deg, pitch_deg;
} wall_stop;

typedef struct wall {
    char name[64];
    float eye_m[3];     /* viewer's eye, wall frame [m] */
    int n_tiles;
    wall_tile tiles[WALL_MAX_TILES];
    int hud_tile;       /* tile index that draws the HUD; -1 = no HUD on this wall */
    float hud_text_mm;  /* HUD text height on the glass [mm] */
    int n_stops;        /* scripted tour; 0 = none */
    wall_stop stops[WALL_MAX_TOUR];
} wall;

/* Parses a wall file's text (len bytes) named `name` for messages into *w. Failures read
 * "name:line:col: ..." for bad JSON, "name: tiles[2].normal: ..." for a bad value. */
int wall_parse(wall *w, const char *name, const char *text, size_t len, gale_err *err);
/* Reads and parses the file at path. */
int wall_load(wall *w, const char *path, gale_err *err);

/* Index of the tile called name, -1 if none. */
int wall_find_tile(const wall *w, const char *name);

/* HUD text size [px] on tile `tile` drawn fb_h pixels high: hud_text_mm on its glass
 * (size_m[1] tall), within 8..256 px; 0 on every tile but hud_tile (and on all with "off"). */
float wall_hud_px(const wall *w, int tile, int fb_h);

/* The tour's camera at time t_s (looped over the last stop's time, linear between stops)
 * into *out (t_s set to the looped time); w must have a tour (n_stops >= 2). */
void wall_tour_at(const wall *w, double t_s, wall_stop *out);

/* Corners of tile t's visible area: lower left, lower right, upper left (Kooima's pa, pb,
 * pc), wall frame [m]. */
void wall_tile_corners(const wall_tile *t, float pa[3], float pb[3], float pc[3]);

/* Off-axis frustum of the screen rectangle pa (lower left), pb (lower right), pc (upper
 * left) seen from pe (Kooima eqs. 1-10). rot: the column-major rotation taking the wall
 * frame into the screen's (x along pb - pa, y along pc - pa, z the normal) with the
 * translation by -pe; proj: glFrustum of the extents at z_near. */
void wall_offaxis(const float pa[3], const float pb[3], const float pc[3], const float pe[3],
                  float z_near, float z_far, float rot[16], float proj[16]);

/* View and projection of tile `tile` for a camera whose world-to-camera matrix is
 * cam_view (column-major): view = rot · T(eye) · cam_view (the wall frame is the camera
 * frame moved so the camera sits at the eye), proj from wall_offaxis. */
void wall_tile_matrices(const wall *w, int tile, const float cam_view[16], float z_near,
                        float z_far, float view[16], float proj[16]);

/* out = a · b, column-major 4 × 4. */
void wall_mat_mul(const float a[16], const float b[16], float out[16]);

#endif
