/* The learning curve (sim/curve.h). */
#include "curve.h"

#include <math.h>
#include <stdio.h>

#include "raster.h"

#define W 800
#define H 500
#define LEFT 90 /* room for the fitness labels */
#define RIGHT 20
#define TOP 40
#define BOTTOM 50
#define AXIS 0x303030u
#define GRID 0xE4E4E4u

static void range_of(const double *v, int n, double *lo, double *hi)
{
	for (int i = 0; v && i < n; i++) {
		if (!isfinite(v[i]))
			continue;
		*lo = v[i] < *lo ? v[i] : *lo;
		*hi = v[i] > *hi ? v[i] : *hi;
	}
}

static double px_x(int i, int n)
{
	return LEFT + (n > 1 ? (double)i / (n - 1) : 0.5) * (W - LEFT - RIGHT);
}

static double px_y(double v, double lo, double hi)
{
	return TOP + (hi - v) / (hi - lo) * (H - TOP - BOTTOM);
}

static void plot(evo_image_rgb *im, const double *v, int n, double lo,
		 double hi, uint32_t rgb)
{
	int have = 0;
	double x0 = 0, y0 = 0;
	for (int i = 0; v && i < n; i++) {
		if (!isfinite(v[i])) {
			have = 0;
			continue;
		}
		double x = px_x(i, n), y = px_y(v[i], lo, hi);
		if (have)
			evo_raster_thick_line(im, x0, y0, x, y, 2.0, rgb, 255);
		else
			evo_raster_fill_circle(im, x, y, 2.0, rgb, 255);
		x0 = x;
		y0 = y;
		have = 1;
	}
}

int evo_curve_write(const char *path, const char *title, const double *best,
		    const double *mean, int n, evo_err *err)
{
	evo_image_rgb im;
	if (evo_image_rgb_init(&im, W, H, err))
		return -1;
	evo_raster_clear(&im, EVO_CURVE_BACKGROUND);
	double lo = INFINITY, hi = -INFINITY;
	range_of(best, n, &lo, &hi);
	range_of(mean, n, &lo, &hi);
	if (!(lo <= hi)) {
		lo = 0;
		hi = 1;
	}
	if (hi - lo < 1e-9) {
		lo -= 0.5;
		hi += 0.5;
	}
	/* A little room above and below the curves. */
	double pad = (hi - lo) * 0.05;
	lo -= pad;
	hi += pad;
	char label[64];
	for (int k = 0; k <= 4; k++) {
		double v = lo + (hi - lo) * k / 4;
		int y = (int)px_y(v, lo, hi);
		evo_raster_line(&im, LEFT, y, W - RIGHT, y, GRID, 255);
		snprintf(label, sizeof label, "%.4g", v);
		evo_raster_text(&im, LEFT - 8 - evo_raster_text_width(label, 1),
				y - 4, label, AXIS, 1);
	}
	evo_raster_line(&im, LEFT, TOP, LEFT, H - BOTTOM, AXIS, 255);
	evo_raster_line(&im, LEFT, H - BOTTOM, W - RIGHT, H - BOTTOM, AXIS,
			255);
	snprintf(label, sizeof label, "generation 0 .. %d", n > 0 ? n - 1 : 0);
	evo_raster_text(&im, LEFT, H - BOTTOM + 12, label, AXIS, 1);
	evo_raster_text(&im, LEFT, 12, title ? title : "", AXIS, 2);
	evo_raster_fill_rect(&im, W - 200, 14, 14, 4, EVO_CURVE_BEST, 255);
	evo_raster_text(&im, W - 180, 11, "best", AXIS, 1);
	evo_raster_fill_rect(&im, W - 120, 14, 14, 4, EVO_CURVE_MEAN, 255);
	evo_raster_text(&im, W - 100, 11, "mean", AXIS, 1);
	plot(&im, mean, n, lo, hi, EVO_CURVE_MEAN);
	plot(&im, best, n, lo, hi, EVO_CURVE_BEST);
	int rc = evo_image_rgb_save_png(&im, path, err);
	evo_image_rgb_free(&im);
	return rc;
}
