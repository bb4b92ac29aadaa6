/* evo — the learning curve: best, best-ever and mean fitness per
 * generation, drawn into a PNG with evo's own raster and its built-in
 * font (no display needed): a title that names the task, its method and
 * seed, the axes labelled (generation, fitness) with their ranges, and a
 * legend. */
#ifndef EVO_CURVE_H
#define EVO_CURVE_H

#include "base/err.h"

/* Draw n generations of best[] and mean[] (either may be NULL), the best
 * so far (the running maximum of best[]), a title, the labelled axes and
 * their ranges, and save the PNG atomically at path. Values that are not
 * finite are left out. Returns 0 or -1 with err. */
int evo_curve_write(const char *path, const char *title, const double *best,
		    const double *mean, int n, evo_err *err);

/* Colours, for tests. */
#define EVO_CURVE_BEST 0x2F6FD0u
#define EVO_CURVE_MEAN 0xE0872Au
#define EVO_CURVE_BEST_EVER 0x2AA050u
#define EVO_CURVE_BACKGROUND 0xFFFFFFu
#define EVO_CURVE_TEXT 0x303030u
/* Where the title is written (its top-left corner) and its scale. */
#define EVO_CURVE_TITLE_X 90
#define EVO_CURVE_TITLE_Y 6
#define EVO_CURVE_TITLE_SCALE 2

#endif
