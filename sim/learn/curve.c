/* The learning curve (sim/learn/curve.h). */
#include "learn/curve.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "viewer/png.h"
#include "viewer/raster.h"

#define W 800
#define H 500
#define LEFT 90 /* room for the fitness labels */
#define RIGHT 20
#define TOP 40
#define BOTTOM 50
#define AXIS EVO_CURVE_TEXT
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

/* Series v of n values on an x axis of `of` values. */
static void plot(evo_raster *im, const double *v, int n, int of, double lo,
		 double hi, uint32_t rgb)
{
	int have = 0;
	double x0 = 0, y0 = 0;
	for (int i = 0; v && i < n; i++) {
		if (!isfinite(v[i])) {
			have = 0;
			continue;
		}
		double x = px_x(i, of), y = px_y(v[i], lo, hi);
		if (have)
			evo_raster_thick_line(im, x0, y0, x, y, 2.0, rgb, 255);
		else
			evo_raster_fill_circle(im, x, y, 2.0, rgb, 255);
		x0 = x;
		y0 = y;
		have = 1;
	}
}

/* Text turned a quarter left (read bottom to top), its left end at
 * (x, y_bottom): the fitness axis's label. */
static void text_up(evo_raster *im, int x, int y_bottom, const char *s)
{
	int w = evo_raster_text_width(s, 1), h = EVO_FONT_CELL_H;
	evo_raster t;
	evo_err err = {{0}};
	if (w < 1 || evo_raster_init(&t, w, h, &err))
		return;
	evo_raster_clear(&t, EVO_CURVE_BACKGROUND);
	evo_raster_text(&t, 0, 0, s, AXIS, 1);
	for (int j = 0; j < h; j++)
		for (int i = 0; i < w; i++) {
			uint32_t c = evo_raster_get(&t, i, j);
			if (c != EVO_CURVE_BACKGROUND)
				evo_raster_pixel(im, x + j, y_bottom - i, c,
						 255);
		}
	evo_raster_free(&t);
}

/* The running maximum of best[] (NaN until the first finite value), in a
 * new array, or NULL. */
static double *best_ever_of(const double *best, int n)
{
	double *v = best && n > 0 ? malloc((size_t)n * sizeof *v) : NULL;
	double m = NAN;
	for (int i = 0; v && i < n; i++) {
		if (isfinite(best[i]) && !(best[i] <= m))
			m = best[i];
		v[i] = m;
	}
	return v;
}

static void legend(evo_raster *im, const evo_curve_series *s, int ns)
{
	int x = W - RIGHT;
	for (int k = ns - 1; k >= 0; k--) {
		x -= evo_raster_text_width(s[k].name, 1) + 30;
		evo_raster_fill_rect(im, x, TOP - 10, 14, 4, s[k].rgb, 255);
		evo_raster_text(im, x + 18, TOP - 13, s[k].name, AXIS, 1);
	}
}

int evo_curve_write(const char *path, const char *title, const double *best,
		    const double *mean, int n, evo_err *err)
{
	double *ever = best_ever_of(best, n);
	evo_curve_series s[3] = {{"best", EVO_CURVE_BEST, best, n},
				 {"best ever", EVO_CURVE_BEST_EVER, ever, n},
				 {"mean", EVO_CURVE_MEAN, mean, n}};
	evo_curve_spec spec = {title, "generation", "fitness", s, 3, NULL, 0, NULL};
	int rc = evo_curve_plot(path, &spec, err);
	free(ever);
	return rc;
}

int evo_curve_plot(const char *path, const evo_curve_spec *spec, evo_err *err)
{
	evo_raster im;
	if (evo_raster_init(&im, W, H, err))
		return -1;
	evo_raster_clear(&im, EVO_CURVE_BACKGROUND);
	double lo = INFINITY, hi = -INFINITY;
	int n = 0;
	for (int k = 0; k < spec->n_series; k++) {
		const evo_curve_series *sk = &spec->series[k];
		range_of(sk->v, sk->n, &lo, &hi);
		n = sk->n > n ? sk->n : n;
	}
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
	evo_raster_text(&im, (LEFT + W - RIGHT) / 2 - 30, H - BOTTOM + 24,
			spec->x_label, AXIS, 1);
	text_up(&im, 8, (TOP + H - BOTTOM) / 2 + 20, spec->y_label);
	evo_raster_text(&im, EVO_CURVE_TITLE_X, EVO_CURVE_TITLE_Y,
			spec->title ? spec->title : "", AXIS,
			EVO_CURVE_TITLE_SCALE);
	legend(&im, spec->series, spec->n_series);
	for (int k = 0; k < spec->n_marks && n > 1; k++) {
		double m = spec->marks[k];
		if (!(m >= 0 && m <= n - 1))
			continue;
		int x = (int)px_x((int)m, n);
		for (int y = TOP; y < H - BOTTOM; y += 6) /* dashed */
			evo_raster_line(&im, x, y, x, y + 2, EVO_CURVE_MARK, 255);
		if (spec->mark_label)
			evo_raster_text(&im, x + 3, TOP + 4 + 12 * (k % 3),
					spec->mark_label, EVO_CURVE_MARK, 1);
	}
	/* the first series drawn last, on top */
	for (int k = spec->n_series - 1; k >= 0; k--)
		plot(&im, spec->series[k].v, spec->series[k].n, n, lo, hi,
		     spec->series[k].rgb);
	/* a few colours: a palette image deflates a sixth of the bytes */
	int rc = evo_png_write_indexed(path, im.pixels, im.w, im.h, err);
	evo_raster_free(&im);
	return rc;
}
