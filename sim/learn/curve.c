/* The learning curve (sim/learn/curve.h). */
#include "learn/curve.h"

#include <math.h>
#include <stdio.h>

#include "viewer/raster.h"

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

/* A round step (1, 2 or 5 times a power of ten) that cuts span into
 * about `parts` pieces. */
static double nice_step(double span, int parts)
{
	double raw = span / parts;
	double p = pow(10, floor(log10(raw)));
	double f = raw / p;
	return (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * p;
}

static double px_x(int i, int n)
{
	return LEFT + (n > 1 ? (double)i / (n - 1) : 0.5) * (W - LEFT - RIGHT);
}

static double px_y(double v, double lo, double hi)
{
	return TOP + (hi - v) / (hi - lo) * (H - TOP - BOTTOM);
}

static void plot(evo_raster *im, const double *v, int n, double lo,
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
	evo_raster im;
	if (evo_raster_init(&im, W, H, err))
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
	/* Round the range out to whole steps, with the grid on each. */
	double step = nice_step(hi - lo, 5);
	lo = floor(lo / step) * step;
	hi = ceil(hi / step) * step;
	if (hi - lo < step / 2)
		hi = lo + step;
	char label[64];
	for (double v = lo; v <= hi + step / 2; v += step) {
		int y = (int)px_y(v, lo, hi);
		evo_raster_line(&im, LEFT, y, W - RIGHT, y, GRID, 255);
		/* a step's rounding error must not print as 1e-13 */
		double shown = fabs(v) < step / 1e6 ? 0 : v;
		snprintf(label, sizeof label, "%.6g", shown);
		evo_raster_text(&im, LEFT - 8 - evo_raster_text_width(label, 1),
				y - 4, label, AXIS, 1);
	}
	/* Generation marks on round numbers. */
	if (n > 1) {
		double gstep = nice_step(n - 1, 8);
		gstep = gstep < 1 ? 1 : gstep;
		for (double g = 0; g <= n - 1; g += gstep) {
			int x = (int)px_x((int)g, n);
			evo_raster_line(&im, x, H - BOTTOM, x, H - BOTTOM + 4,
					AXIS, 255);
			snprintf(label, sizeof label, "%d", (int)g);
			evo_raster_text(&im,
					x - evo_raster_text_width(label, 1) / 2,
					H - BOTTOM + 8, label, AXIS, 1);
		}
	}
	evo_raster_line(&im, LEFT, TOP, LEFT, H - BOTTOM, AXIS, 255);
	evo_raster_line(&im, LEFT, H - BOTTOM, W - RIGHT, H - BOTTOM, AXIS,
			255);
	evo_raster_text(&im, (LEFT + W - RIGHT) / 2 - 40, H - BOTTOM + 24,
			"generation", AXIS, 1);
	evo_raster_text(&im, LEFT, 12, title ? title : "", AXIS, 2);
	evo_raster_fill_rect(&im, W - 200, 14, 14, 4, EVO_CURVE_BEST, 255);
	evo_raster_text(&im, W - 180, 11, "best", AXIS, 1);
	evo_raster_fill_rect(&im, W - 120, 14, 14, 4, EVO_CURVE_MEAN, 255);
	evo_raster_text(&im, W - 100, 11, "mean", AXIS, 1);
	plot(&im, mean, n, lo, hi, EVO_CURVE_MEAN);
	plot(&im, best, n, lo, hi, EVO_CURVE_BEST);
	int rc = evo_raster_save_png(&im, path, err);
	evo_raster_free(&im);
	return rc;
}
