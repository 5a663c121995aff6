/* Which trees a client holds of a scene past what it can hold (client/CLIENT.md "Reduced
 * view"): the ones nearest a point of the ground plane, as many as fit, and the circle
 * about that point that holds exactly them, which the client asks the server to stream
 * (PROTOCOL.md "view", kind circle). web/hold.js is the same rule, held to this one by
 * tests/web/test_hold_js.mjs: both work in double over the float positions a welcome
 * gives, in the same order, so both pick the same trees. */
#ifndef GALE_HOLD_H
#define GALE_HOLD_H

#include <stdint.h>

#include "ctl.h"
#include "err.h"

/* The trees held about a point. */
typedef struct hold_circle {
    double cx, cy;   /* [m] the point the trees are nearest to */
    uint32_t n_held; /* min(limit, trees) */
    double radius_m; /* 2D distance of the farthest tree held; 0 for none */
    double edge_m;   /* midway between it and the nearest tree not held (radius_m when every
                        tree is held): a circle of this radius holds the trees held and, but
                        for ties, no other */
} hold_circle;

/* The mean x and y of n instances [m] (the scene's centre, where the default camera
 * looks), summed in index order in double; (0, 0) for none. */
void hold_centre(const ctl_instance *inst, uint32_t n, double c[2]);

/* The min(limit, n) instances nearest (cx, cy) in 2D, a tie going to the lower index, into
 * held[] (the caller's, room for min(limit, n)) in ascending index order, and their circle
 * into *out. Allocates scratch of n entries and frees it. 0, or GALE_E_NOMEM with err set. */
int hold_nearest(const ctl_instance *inst, uint32_t n, double cx, double cy, uint32_t limit,
                 uint32_t *held, hold_circle *out, gale_err *err);

/* The radius a circle view asks for so that the server, which widens a circle by the
 * height of the scene's tallest tree (margin_m, PROTOCOL.md "view"), streams the trees
 * held and no others: edge_m less the margin, within PROTOCOL.md's [0.001, 1e6] m. An
 * edge inside the margin gives 0.001 m: then the server streams every tree within the
 * margin, more than are held. */
double hold_view_radius_m(const hold_circle *h, double margin_m);

#endif
