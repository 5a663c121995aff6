/* Attract mode of a kiosk: after idle_s without a touch (mouse = touch under
 * GLFW) the kiosk lets go of its dial and the camera tours (camera_preset.h); the next
 * touch wakes it and is not taken as a control. Time is the caller's clock [s]. */
#ifndef GALE_ATTRACT_H
#define GALE_ATTRACT_H

#include <stdbool.h>

#define ATTRACT_DEFAULT_IDLE_S 90.0
/* Attract mode's cards, each shown this long in turn over the tour: the invitation to touch
 * and the fact that water, not wind, takes most lives in a hurricane (configs/lang
 * kiosk.touch, attract.water), long enough to read the longer one aloud. */
#define ATTRACT_CARD_S 8.0
#define ATTRACT_CARDS  2
enum attract_card { ATTRACT_CARD_TOUCH = 0, ATTRACT_CARD_WATER = 1 };

typedef struct attract {
    double idle_s;       /* > 0 */
    double last_input_s; /* the last touch, key or wheel */
    bool active;
} attract;

/* Awake, idle from now_s; idle_s 0 → ATTRACT_DEFAULT_IDLE_S. */
void attract_init(attract *a, double idle_s, double now_s);
/* True exactly once, when attract mode begins at now_s. */
bool attract_tick(attract *a, double now_s);
/* A touch at now_s: true when it woke the kiosk (the caller drops that touch). */
bool attract_input(attract *a, double now_s);
/* The card shown at now_s (enum attract_card), counted from when attract mode began; -1
 * when awake. */
int attract_card(const attract *a, double now_s);

#endif
