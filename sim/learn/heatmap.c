/* The archive's heatmap (sim/learn/heatmap.h). */
#include "learn/heatmap.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "viewer/raster.h"

#define PLOT 500 /* the grid's side in pixels */
#define LEFT 60
#define TOP 40
#define BAR_GAP 20
#define BAR_W 18
#define RIGHT 110
#define BOTTOM 50
#define W (LEFT + PLOT + BAR_GAP + BAR_W + RIGHT)
#define H (TOP + PLOT + BOTTOM)
#define AXIS 0x303030u

/* Five stops of a perceptually ordered ramp, evenly spaced. */
static const uint32_t stops[5] = {0x440154u, 0x3B528Bu, 0x21908Cu,
				  0x5DC963u, 0xFDE725u};

static uint32_t mix(uint32_t a, uint32_t b, double f)
{
	uint32_t out = 0;
	for (int s = 16; s >= 0; s -= 8) {
		double ca = (a >> s) & 0xFF, cb = (b >> s) & 0xFF;
		out |= (uint32_t)lround(ca + (cb - ca) * f) << s;
	}
	return out;
}

uint32_t evo_heatmap_colour(double t)
{
	if (!(t > 0))
		return stops[0];
	if (t >= 1)
		return stops[4];
	double x = t * 4;
	int i = (int)x;
	return mix(stops[i], stops[i + 1], x - i);
}

/* The pixel column where cell x (of n) starts. */
static int edge(int x, int n) { return (int)((long)x * PLOT / n); }

static void axes(evo_raster *im)
{
	char label[16];
	for (int k = 0; k <= 4; k++) {
		double v = k / 4.0;
		int x = LEFT + (int)(v * PLOT), y = TOP + PLOT - (int)(v * PLOT);
		snprintf(label, sizeof label, "%.2g", v);
		evo_raster_line(im, x, TOP + PLOT, x, TOP + PLOT + 4, AXIS, 255);
		evo_raster_text(im, x - evo_raster_text_width(label, 1) / 2,
				TOP + PLOT + 8, label, AXIS, 1);
		evo_raster_line(im, LEFT - 4, y, LEFT, y, AXIS, 255);
		evo_raster_text(im, LEFT - 8 - evo_raster_text_width(label, 1),
				y - 4, label, AXIS, 1);
	}
	evo_raster_rect(im, LEFT, TOP, PLOT, PLOT, AXIS, 255);
	evo_raster_text(im, LEFT + PLOT / 2 - 40, TOP + PLOT + 26,
			"descriptor 1", AXIS, 1);
	evo_raster_text(im, 4, TOP - 14, "descriptor 2", AXIS, 1);
}

static void colour_bar(evo_raster *im, double lo, double hi, int any)
{
	int x0 = LEFT + PLOT + BAR_GAP;
	for (int y = 0; y < PLOT; y++) {
		double t = 1.0 - (double)y / (PLOT - 1);
		evo_raster_line(im, x0, TOP + y, x0 + BAR_W - 1, TOP + y,
				evo_heatmap_colour(t), 255);
	}
	evo_raster_rect(im, x0, TOP, BAR_W, PLOT, AXIS, 255);
	char label[64];
	if (!any) {
		evo_raster_text(im, x0 + BAR_W + 6, TOP, "empty", AXIS, 1);
		return;
	}
	snprintf(label, sizeof label, "%.6g", hi);
	evo_raster_text(im, x0 + BAR_W + 6, TOP, label, AXIS, 1);
	snprintf(label, sizeof label, "%.6g", lo);
	evo_raster_text(im, x0 + BAR_W + 6, TOP + PLOT - 8, label, AXIS, 1);
	evo_raster_text(im, x0 + BAR_W + 6, TOP + PLOT / 2 - 4, "fitness",
			AXIS, 1);
}

int evo_heatmap_write(const char *path, const char *title, int nx, int ny,
		      const double *values, evo_err *err)
{
	if (nx < 1 || ny < 1 || nx > 1000 || ny > 1000) {
		evo_fail(err, "%s: a heatmap of %d x %d cells (each side 1 "
				 "to 1000)",
			    path, nx, ny);
		return -1;
	}
	double lo = INFINITY, hi = -INFINITY;
	for (int i = 0; i < nx * ny; i++) {
		if (isfinite(values[i])) {
			lo = values[i] < lo ? values[i] : lo;
			hi = values[i] > hi ? values[i] : hi;
		}
	}
	int any = lo <= hi;
	evo_raster im;
	if (evo_raster_init(&im, W, H, err))
		return -1;
	evo_raster_clear(&im, EVO_HEATMAP_BACKGROUND);
	for (int y = 0; y < ny; y++) {
		int y0 = TOP + PLOT - edge(y + 1, ny), y1 = TOP + PLOT - edge(y, ny);
		for (int x = 0; x < nx; x++) {
			double v = values[x + nx * y];
			uint32_t c = EVO_HEATMAP_EMPTY;
			if (isfinite(v))
				c = evo_heatmap_colour(hi > lo ? (v - lo) / (hi - lo)
							       : 1.0);
			int x0 = LEFT + edge(x, nx), x1 = LEFT + edge(x + 1, nx);
			evo_raster_fill_rect(&im, x0, y0, x1 - x0, y1 - y0, c,
					     255);
		}
	}
	axes(&im);
	colour_bar(&im, lo, hi, any);
	evo_raster_text(&im, LEFT, 12, title ? title : "", AXIS, 2);
	int rc = evo_raster_save_png(&im, path, err);
	evo_raster_free(&im);
	return rc;
}
