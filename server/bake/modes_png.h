/* A figure of the first mode shapes of a baked tree, like Diener 2008 figure 4: side view,
 * rest skeleton in grey, each mode's deformed skeleton in colour, one panel per mode. */
#ifndef GALE_MODES_PNG_H
#define GALE_MODES_PNG_H

#include "asset.h"
#include "err.h"

/* Writes up to six modes of a (three panels a row) as a PNG at path. Each mode is drawn
 * at ±q where its largest node displacement is 12% of the tree height, through the
 * corrected reconstruction (eq. 16-17). I/O errors name the path. */
int modes_png_write(const asset *a, const char *path, gale_err *err);

#endif
