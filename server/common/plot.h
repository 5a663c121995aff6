/* A small software raster for figures written as PNG: anti-aliased lines, filled
 * rectangles, arrows, a perceptual colour map. Used for mode-shape and wind-slice
 * pictures. */
#ifndef GALE_PLOT_H
#define GALE_PLOT_H

#include <stdint.h>

#include "err.h"

typedef struct plot {
    int w, h;
    uint8_t *rgb; /* owned [3 w h], row 0 at the top */
} plot;

/* Allocates a w×h image filled with bg. */
int plot_init(plot *p, int w, int h, const uint8_t bg[3], gale_err *err);
/* Frees the pixels. NULL is a no-op. */
void plot_fini(plot *p);
/* A line of the given width [px] in pixel coordinates (x right, y down). */
void plot_line(plot *p, float x0, float y0, float x1, float y1, float width,
               const uint8_t c[3]);
/* A filled rectangle [x0, x1) × [y0, y1), clipped. */
void plot_rect(plot *p, int x0, int y0, int x1, int y1, const uint8_t c[3]);
/* An arrow from (x0, y0) to (x1, y1) with a head. */
void plot_arrow(plot *p, float x0, float y0, float x1, float y1, float width,
                const uint8_t c[3]);
/* Text in a built-in 8x8 pixel font, scale ≥ 1. */
void plot_text(plot *p, int x, int y, int scale, const char *s, const uint8_t c[3]);
/* Perceptual colour map (viridis-like) for t in [0, 1] (clamped). */
void plot_colormap(float t, uint8_t out[3]);
/* Writes the image as PNG; I/O errors name the path. */
int plot_write_png(const plot *p, const char *path, gale_err *err);

#endif
