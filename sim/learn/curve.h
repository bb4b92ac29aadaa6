/* evo — the learning curve: best and mean fitness per generation, drawn
 * into a PNG with evo's own raster (no display needed). */
#ifndef EVO_CURVE_H
#define EVO_CURVE_H

#include "base/err.h"

/* Draw n generations of best[] and mean[] (either may be NULL) with a
 * title, axes and their ranges, and save the PNG atomically at path.
 * Values that are not finite are left out. Returns 0 or -1 with err. */
int evo_curve_write(const char *path, const char *title, const double *best,
		    const double *mean, int n, evo_err *err);

/* Colours, for tests. */
#define EVO_CURVE_BEST 0x2F6FD0u
#define EVO_CURVE_MEAN 0xE0872Au
#define EVO_CURVE_BACKGROUND 0xFFFFFFu

#endif
