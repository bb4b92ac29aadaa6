/* evo — the heatmap of a MAP-Elites archive: a 2-D grid of cells, each
 * coloured by its elite's fitness, empty cells grey, drawn into a PNG
 * with evo's own raster (no display needed), as the learning curve is. */
#ifndef EVO_HEATMAP_H
#define EVO_HEATMAP_H

#include <stdint.h>

#include "base/err.h"

/* Draw the nx x ny grid (nx, ny from 1 to 1000) of values[x + nx * y]
 * (y = 0 at the bottom; NaN: an empty cell) with a title, the descriptor
 * axes from 0 to 1 and a colour bar from the lowest value to the highest,
 * and save the PNG atomically at path. Returns 0 or -1 with err. */
int evo_heatmap_write(const char *path, const char *title, int nx, int ny,
		      const double *values, evo_err *err);

/* The colour of t in [0, 1] on the heatmap's scale (dark blue, through
 * teal and green, to yellow), and of an empty cell; for tests. */
uint32_t evo_heatmap_colour(double t);
#define EVO_HEATMAP_EMPTY 0xD8D8D8u
#define EVO_HEATMAP_BACKGROUND 0xFFFFFFu

#endif
