/* evo — the learning curve: best, best-ever and mean fitness per
 * generation (and any other series, e.g. an OPENENDED run's), drawn into
 * a PNG with evo's own raster and its built-in
 * font (no display needed): a title that names the task, its method and
 * seed, the axes labelled (generation, fitness) with their ranges, and a
 * legend. */
#ifndef EVO_CURVE_H
#define EVO_CURVE_H

#include <stdint.h>

#include "base/err.h"

/* Draw n generations of best[] and mean[] (either may be NULL), the best
 * so far (the running maximum of best[]), a title, the labelled axes and
 * their ranges, and save the PNG atomically at path. Values that are not
 * finite are left out. Returns 0 or -1 with err. */
int evo_curve_write(const char *path, const char *title, const double *best,
		    const double *mean, int n, evo_err *err);

/* Any curves on one pair of axes: a series is named in the legend and
 * drawn in its colour, value i at x = i (the x axis as long as the
 * longest series); values that are not finite are left out. */
typedef struct evo_curve_series {
	const char *name;
	uint32_t rgb;
	const double *v;
	int n;
} evo_curve_series;

typedef struct evo_curve_spec {
	const char *title, *x_label, *y_label;
	const evo_curve_series *series; /* the first is drawn on top */
	int n_series;
	/* marks: vertical lines at these x, each labelled mark_label (e.g.
	 * the batches where an OPENENDED run added a skill); may be NULL */
	const double *marks;
	int n_marks;
	const char *mark_label;
} evo_curve_spec;

/* Draws spec's series, its title and labelled axes with their ranges, and
 * saves the PNG atomically at path (at most 16 colours in all). Returns 0
 * or -1 with err. */
int evo_curve_plot(const char *path, const evo_curve_spec *spec, evo_err *err);

/* Colours, for tests. */
#define EVO_CURVE_BEST 0x2F6FD0u
#define EVO_CURVE_MEAN 0xE0872Au
#define EVO_CURVE_BEST_EVER 0x2AA050u
#define EVO_CURVE_BACKGROUND 0xFFFFFFu
#define EVO_CURVE_TEXT 0x303030u
#define EVO_CURVE_MARK 0x9A9A9Au
/* Where the title is written (its top-left corner) and its scale. */
#define EVO_CURVE_TITLE_X 90
#define EVO_CURVE_TITLE_Y 6
#define EVO_CURVE_TITLE_SCALE 2

#endif
