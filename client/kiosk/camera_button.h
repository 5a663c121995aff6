/* The kiosk's camera button (issue "cameras that show the trees"): a touch target in the
 * HUD's right-hand corner, under the wind arrow, that steps through the camera presets
 * (camera_preset.h); the C key does the same. Layout and hit-testing only, no GL: sizes are
 * fractions of the framebuffer height, so the button covers the same share of a 1080p and a
 * 4K screen. */
#ifndef GALE_CAMERA_BUTTON_H
#define GALE_CAMERA_BUTTON_H

#include <stdbool.h>

#define CAMERA_BUTTON_H_FRAC      0.07f /* height / framebuffer height: 76 px at 1080p */
#define CAMERA_BUTTON_ASPECT      3.6f  /* width / height: "Camera: aerial" fits */
#define CAMERA_BUTTON_MARGIN_FRAC 0.02f /* gap to the right edge / framebuffer height */
#define CAMERA_BUTTON_TOP_FRAC    0.16f /* top edge / framebuffer height: below the arrow */

typedef struct camera_button_rect {
    float x0, y0, x1, y1; /* framebuffer pixels, y down, x1 and y1 exclusive */
} camera_button_rect;

/* The button's rectangle in a framebuffer of fb_w × fb_h pixels (all zero when empty). */
camera_button_rect camera_button_layout(int fb_w, int fb_h);

/* Whether a cursor at (x, y) in window coordinates of a win_w × win_h window (GLFW's, which
 * differ from framebuffer pixels on a scaled display) is on the button of a fb_w × fb_h
 * framebuffer. */
bool camera_button_hit(int fb_w, int fb_h, int win_w, int win_h, double x, double y);

/* The preset after preset in the order street, garden, roof, aerial, tour, street ...; from
 * the fitted view (-1) or anything out of range: street. */
int camera_button_next(int preset);

/* "Camera: street" for the button's face in a language (lang.h) into buf (cap bytes);
 * "Camera" for the fitted view. */
void camera_button_label(int lang, int preset, char *buf, unsigned cap);

#endif
