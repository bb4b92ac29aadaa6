/* A small RGB raster: see raster.h for the pixel conventions. */
#include "viewer/raster.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/png.h"

int evo_raster_init(evo_raster *im, int w, int h, evo_err *err)
{
	im->w = im->h = 0;
	im->pixels = NULL;
	if (w < 1 || h < 1 || w > EVO_RASTER_MAX_SIDE || h > EVO_RASTER_MAX_SIDE)
		return evo_fail(err,
				"image of %d x %d pixels: each side must be "
				"in [1, %d]",
				w, h, EVO_RASTER_MAX_SIDE);
	im->pixels = calloc((size_t)w * (size_t)h, 3);
	if (!im->pixels)
		return evo_fail(err, "image of %d x %d pixels: out of memory",
				w, h);
	im->w = w;
	im->h = h;
	return 0;
}

void evo_raster_free(evo_raster *im)
{
	free(im->pixels);
	im->pixels = NULL;
	im->w = im->h = 0;
}

int evo_raster_save_png(const evo_raster *im, const char *path, evo_err *err)
{
	return evo_png_write(path, im->pixels, im->w, im->h, 3, err);
}

uint32_t evo_raster_get(const evo_raster *im, int x, int y)
{
	if (x < 0 || y < 0 || x >= im->w || y >= im->h)
		return 0;
	const uint8_t *p = im->pixels + 3 * ((size_t)y * im->w + x);
	return (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
}

void evo_raster_clear(evo_raster *im, uint32_t rgb)
{
	uint8_t c[3] = {(uint8_t)(rgb >> 16), (uint8_t)(rgb >> 8),
			(uint8_t)rgb};
	size_t n = (size_t)im->w * im->h;
	for (size_t i = 0; i < n; i++)
		memcpy(im->pixels + 3 * i, c, 3);
}

/* Paint pixels [x0, x1] of row y, already clipped. */
static void span(evo_raster *im, int y, int x0, int x1, uint32_t rgb,
		 int alpha)
{
	uint8_t *p = im->pixels + 3 * ((size_t)y * im->w + x0);
	int r = (int)(rgb >> 16 & 0xFF), g = (int)(rgb >> 8 & 0xFF),
	    b = (int)(rgb & 0xFF);
	if (alpha >= 255) {
		for (int x = x0; x <= x1; x++, p += 3) {
			p[0] = (uint8_t)r;
			p[1] = (uint8_t)g;
			p[2] = (uint8_t)b;
		}
		return;
	}
	/* Rounded integer blend: the same inputs give the same pixels on
	 * every machine, which screenshots compared in tests rely on. */
	int na = 255 - alpha;
	for (int x = x0; x <= x1; x++, p += 3) {
		p[0] = (uint8_t)((r * alpha + p[0] * na + 127) / 255);
		p[1] = (uint8_t)((g * alpha + p[1] * na + 127) / 255);
		p[2] = (uint8_t)((b * alpha + p[2] * na + 127) / 255);
	}
}

/* Clip [x0, x1] of row y to the image and paint it. */
static void clipped_span(evo_raster *im, long long y, long long x0,
			 long long x1, uint32_t rgb, int alpha)
{
	if (alpha <= 0 || y < 0 || y >= im->h)
		return;
	if (x0 < 0)
		x0 = 0;
	if (x1 >= im->w)
		x1 = im->w - 1;
	if (x0 > x1)
		return;
	span(im, (int)y, (int)x0, (int)x1, rgb, alpha);
}

void evo_raster_pixel(evo_raster *im, int x, int y, uint32_t rgb, int alpha)
{
	clipped_span(im, y, x, x, rgb, alpha);
}

void evo_raster_fill_rect(evo_raster *im, int x, int y, int w, int h,
			  uint32_t rgb, int alpha)
{
	if (w <= 0 || h <= 0)
		return;
	long long y0 = y < 0 ? 0 : y, y1 = (long long)y + h - 1;
	if (y1 >= im->h)
		y1 = im->h - 1;
	for (long long j = y0; j <= y1; j++)
		clipped_span(im, j, x, (long long)x + w - 1, rgb, alpha);
}

void evo_raster_rect(evo_raster *im, int x, int y, int w, int h,
		     uint32_t rgb, int alpha)
{
	if (w <= 0 || h <= 0)
		return;
	if (w <= 2 || h <= 2) {
		evo_raster_fill_rect(im, x, y, w, h, rgb, alpha);
		return;
	}
	/* Sides without the corners, so a translucent border is even. */
	evo_raster_fill_rect(im, x, y, w, 1, rgb, alpha);
	evo_raster_fill_rect(im, x, y + h - 1, w, 1, rgb, alpha);
	evo_raster_fill_rect(im, x, y + 1, 1, h - 2, rgb, alpha);
	evo_raster_fill_rect(im, x + w - 1, y + 1, 1, h - 2, rgb, alpha);
}

/* Liang-Barsky: clip the segment to [lo, hi] on one axis. */
static int clip_axis(double p, double q, double *t0, double *t1)
{
	if (p == 0)
		return q >= 0;
	double t = q / p;
	if (p < 0) {
		if (t > *t1)
			return 0;
		if (t > *t0)
			*t0 = t;
	} else {
		if (t < *t0)
			return 0;
		if (t < *t1)
			*t1 = t;
	}
	return 1;
}

void evo_raster_line(evo_raster *im, int x0, int y0, int x1, int y1,
		     uint32_t rgb, int alpha)
{
	if (alpha <= 0)
		return;
	/* An end off the image: clip first, so a line to a point far away
	 * (a world point far off screen) costs what its visible part
	 * costs. Lines wholly inside keep the exact Bresenham path. */
	if (x0 < 0 || y0 < 0 || x1 < 0 || y1 < 0 || x0 >= im->w ||
	    x1 >= im->w || y0 >= im->h || y1 >= im->h) {
		double dx = (double)x1 - x0, dy = (double)y1 - y0;
		double t0 = 0, t1 = 1;
		if (!clip_axis(-dx, x0 - 0.0, &t0, &t1) ||
		    !clip_axis(dx, im->w - 1.0 - x0, &t0, &t1) ||
		    !clip_axis(-dy, y0 - 0.0, &t0, &t1) ||
		    !clip_axis(dy, im->h - 1.0 - y0, &t0, &t1) || t0 > t1)
			return;
		int nx0 = (int)lround(x0 + t0 * dx),
		    ny0 = (int)lround(y0 + t0 * dy);
		int nx1 = (int)lround(x0 + t1 * dx),
		    ny1 = (int)lround(y0 + t1 * dy);
		x0 = nx0, y0 = ny0, x1 = nx1, y1 = ny1;
	}
	int dx = abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
	int dy = -abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
	int e = dx + dy;
	for (;;) {
		clipped_span(im, y0, x0, x0, rgb, alpha);
		if (x0 == x1 && y0 == y1)
			break;
		int e2 = 2 * e;
		if (e2 >= dy) {
			e += dy;
			x0 += sx;
		}
		if (e2 <= dx) {
			e += dx;
			y0 += sy;
		}
	}
}

/* Shapes in doubles clip to this box before any conversion to int: a
 * projected point may be anywhere, and casting an out-of-range double is
 * undefined. */
#define FAR 1e7

static int finite_all(const double *v, int n)
{
	for (int i = 0; i < n; i++)
		if (!isfinite(v[i]) || fabs(v[i]) > FAR)
			return 0;
	return 1;
}

/* First and last pixel whose centre lies in [a, b]. */
static void centres_in(double a, double b, long long *i0, long long *i1)
{
	*i0 = (long long)ceil(a - 0.5);
	*i1 = (long long)floor(b - 0.5);
}

void evo_raster_fill_polygon(evo_raster *im, const double *x,
			     const double *y, int n, uint32_t rgb, int alpha)
{
	if (n < 3 || alpha <= 0 || !finite_all(x, n) || !finite_all(y, n))
		return;
	double ymin = y[0], ymax = y[0];
	for (int k = 1; k < n; k++) {
		ymin = fmin(ymin, y[k]);
		ymax = fmax(ymax, y[k]);
	}
	long long j0, j1;
	centres_in(ymin, ymax, &j0, &j1);
	if (j0 < 0)
		j0 = 0;
	if (j1 >= im->h)
		j1 = im->h - 1;
	for (long long j = j0; j <= j1; j++) {
		double yc = (double)j + 0.5, xl = INFINITY, xr = -INFINITY;
		/* Half-open crossing rule: a vertex on the scan line counts
		 * for one of its two edges only. */
		for (int k = 0; k < n; k++) {
			int m = (k + 1) % n;
			double ya = y[k], yb = y[m];
			if ((ya <= yc && yb > yc) || (yb <= yc && ya > yc)) {
				double xc = x[k] + (yc - ya) / (yb - ya) *
						       (x[m] - x[k]);
				xl = fmin(xl, xc);
				xr = fmax(xr, xc);
			}
		}
		if (xl > xr)
			continue;
		/* Centres in [xl, xr): two polygons sharing an edge do not
		 * both paint its pixels. */
		long long i0 = (long long)ceil(xl - 0.5);
		long long i1 = (long long)ceil(xr - 0.5) - 1;
		clipped_span(im, j, i0, i1, rgb, alpha);
	}
}

void evo_raster_polygon(evo_raster *im, const double *x, const double *y,
			int n, uint32_t rgb, int alpha)
{
	if (n < 2 || !finite_all(x, n) || !finite_all(y, n))
		return;
	for (int k = 0; k < n; k++) {
		int m = (k + 1) % n;
		evo_raster_line(im, (int)floor(x[k]), (int)floor(y[k]),
				(int)floor(x[m]), (int)floor(y[m]), rgb, alpha);
	}
}

void evo_raster_thick_line(evo_raster *im, double x0, double y0, double x1,
			   double y1, double width, uint32_t rgb, int alpha)
{
	double v[4] = {x0, y0, x1, y1};
	if (!finite_all(v, 4) || !isfinite(width))
		return;
	double dx = x1 - x0, dy = y1 - y0, len = hypot(dx, dy);
	if (width < 1 || len == 0) {
		if (len == 0 && width >= 1) {
			evo_raster_fill_circle(im, x0, y0, width / 2, rgb,
					       alpha);
			return;
		}
		evo_raster_line(im, (int)floor(x0), (int)floor(y0),
				(int)floor(x1), (int)floor(y1), rgb, alpha);
		return;
	}
	/* Half the width along the normal and past each end. */
	double ux = dx / len * width / 2, uy = dy / len * width / 2;
	double px[4] = {x0 - ux - uy, x1 + ux - uy, x1 + ux + uy, x0 - ux + uy};
	double py[4] = {y0 - uy + ux, y1 + uy + ux, y1 + uy - ux, y0 - uy - ux};
	evo_raster_fill_polygon(im, px, py, 4, rgb, alpha);
}

/* Row j's span of centres within r of (cx, cy); 0 when there is none. */
static int circle_row(double cx, double cy, double r, long long j,
		      long long *i0, long long *i1)
{
	double dy = (double)j + 0.5 - cy;
	if (dy * dy > r * r)
		return 0;
	double half = sqrt(r * r - dy * dy);
	centres_in(cx - half, cx + half, i0, i1);
	return *i0 <= *i1;
}

void evo_raster_circle(evo_raster *im, double cx, double cy, double r,
		       double width, uint32_t rgb, int alpha)
{
	double v[3] = {cx, cy, r};
	if (alpha <= 0 || !finite_all(v, 3) || r <= 0 || !(width > 0))
		return;
	double ri = r - width;
	long long j0, j1;
	centres_in(cy - r, cy + r, &j0, &j1);
	if (j0 < 0)
		j0 = 0;
	if (j1 >= im->h)
		j1 = im->h - 1;
	for (long long j = j0; j <= j1; j++) {
		long long a0, a1, b0, b1;
		if (!circle_row(cx, cy, r, j, &a0, &a1))
			continue;
		/* The ring is the outer span less the inner disc's span,
		 * whose centres lie strictly within ri. */
		if (ri <= 0 || !circle_row(cx, cy, ri, j, &b0, &b1)) {
			clipped_span(im, j, a0, a1, rgb, alpha);
			continue;
		}
		double dy = (double)j + 0.5 - cy;
		double half = sqrt(fmax(ri * ri - dy * dy, 0));
		/* Centres exactly on the inner edge belong to the ring. */
		if ((double)b0 + 0.5 == cx - half)
			b0++;
		if ((double)b1 + 0.5 == cx + half)
			b1--;
		clipped_span(im, j, a0, b0 - 1, rgb, alpha);
		clipped_span(im, j, b1 + 1, a1, rgb, alpha);
	}
}

void evo_raster_fill_circle(evo_raster *im, double cx, double cy, double r,
			    uint32_t rgb, int alpha)
{
	evo_raster_circle(im, cx, cy, r, r + 1, rgb, alpha);
}

/* ---- text ----------------------------------------------------------- */

/* evo's own 5x7 font, ASCII 32-126, drawn for legibility at scale 1:
 * a row per byte, bit 4 the leftmost column. Lower-case descenders (g, j,
 * p, q, y) sit inside the 7 rows, so lines never overlap. */
static const uint8_t font[95][EVO_FONT_H] = {
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /* space */
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04}, /* ! */
    {0x0A, 0x0A, 0x0A, 0x00, 0x00, 0x00, 0x00}, /* " */
    {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}, /* # */
    {0x04, 0x0F, 0x14, 0x0E, 0x05, 0x1E, 0x04}, /* $ */
    {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}, /* % */
    {0x0C, 0x12, 0x14, 0x08, 0x15, 0x12, 0x0D}, /* & */
    {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}, /* ' */
    {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}, /* ( */
    {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}, /* ) */
    {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00}, /* star */
    {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}, /* + */
    {0x00, 0x00, 0x00, 0x00, 0x06, 0x04, 0x08}, /* , */
    {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}, /* - */
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}, /* . */
    {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}, /* slash */
    {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}, /* 0 */
    {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}, /* 1 */
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}, /* 2 */
    {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}, /* 3 */
    {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}, /* 4 */
    {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}, /* 5 */
    {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}, /* 6 */
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}, /* 7 */
    {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}, /* 8 */
    {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}, /* 9 */
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}, /* : */
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x04, 0x08}, /* ; */
    {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}, /* < */
    {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}, /* = */
    {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}, /* > */
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}, /* ? */
    {0x0E, 0x11, 0x01, 0x0D, 0x15, 0x15, 0x0E}, /* @ */
    {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, /* A */
    {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}, /* B */
    {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}, /* C */
    {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}, /* D */
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}, /* E */
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}, /* F */
    {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}, /* G */
    {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, /* H */
    {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}, /* I */
    {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}, /* J */
    {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}, /* K */
    {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}, /* L */
    {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}, /* M */
    {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}, /* N */
    {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, /* O */
    {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}, /* P */
    {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}, /* Q */
    {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}, /* R */
    {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}, /* S */
    {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, /* T */
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, /* U */
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}, /* V */
    {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}, /* W */
    {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}, /* X */
    {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04}, /* Y */
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}, /* Z */
    {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}, /* [ */
    {0x00, 0x10, 0x08, 0x04, 0x02, 0x01, 0x00}, /* backslash */
    {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}, /* ] */
    {0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00}, /* ^ */
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}, /* _ */
    {0x08, 0x04, 0x02, 0x00, 0x00, 0x00, 0x00}, /* ` */
    {0x00, 0x00, 0x0E, 0x01, 0x0F, 0x11, 0x0F}, /* a */
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1E}, /* b */
    {0x00, 0x00, 0x0E, 0x10, 0x10, 0x11, 0x0E}, /* c */
    {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F}, /* d */
    {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E}, /* e */
    {0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08}, /* f */
    {0x00, 0x0F, 0x11, 0x11, 0x0F, 0x01, 0x0E}, /* g */
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11}, /* h */
    {0x04, 0x00, 0x0C, 0x04, 0x04, 0x04, 0x0E}, /* i */
    {0x02, 0x00, 0x06, 0x02, 0x02, 0x12, 0x0C}, /* j */
    {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12}, /* k */
    {0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}, /* l */
    {0x00, 0x00, 0x1A, 0x15, 0x15, 0x11, 0x11}, /* m */
    {0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11}, /* n */
    {0x00, 0x00, 0x0E, 0x11, 0x11, 0x11, 0x0E}, /* o */
    {0x00, 0x00, 0x1E, 0x11, 0x1E, 0x10, 0x10}, /* p */
    {0x00, 0x00, 0x0D, 0x13, 0x0F, 0x01, 0x01}, /* q */
    {0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10}, /* r */
    {0x00, 0x00, 0x0E, 0x10, 0x0E, 0x01, 0x1E}, /* s */
    {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06}, /* t */
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0D}, /* u */
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x0A, 0x04}, /* v */
    {0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0A}, /* w */
    {0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11}, /* x */
    {0x00, 0x00, 0x11, 0x11, 0x0F, 0x01, 0x0E}, /* y */
    {0x00, 0x00, 0x1F, 0x02, 0x04, 0x08, 0x1F}, /* z */
    {0x02, 0x04, 0x04, 0x08, 0x04, 0x04, 0x02}, /* { */
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, /* | */
    {0x08, 0x04, 0x04, 0x02, 0x04, 0x04, 0x08}, /* } */
    {0x00, 0x00, 0x08, 0x15, 0x02, 0x00, 0x00}, /* ~ */
};

/* What a byte without a glyph draws: a hollow box. */
static const uint8_t no_glyph[EVO_FONT_H] = {0x1F, 0x11, 0x11, 0x11,
					     0x11, 0x11, 0x1F};

const uint8_t *evo_font_glyph(unsigned char c)
{
	if (c < 32 || c > 126)
		return no_glyph;
	return font[c - 32];
}

/* Scales past this draw glyphs larger than any image evo makes, and
 * keep pixel arithmetic far from overflowing. */
#define MAX_SCALE 64

static int clamp_scale(int scale)
{
	return scale < 1 ? 1 : scale > MAX_SCALE ? MAX_SCALE : scale;
}

int evo_raster_text(evo_raster *im, int x, int y, const char *s,
		    uint32_t rgb, int scale)
{
	scale = clamp_scale(scale);
	/* Pen positions in long long: a long string or many lines run
	 * far past the image without overflowing. */
	long long cx = x, cy = y, widest = 0;
	int cw = EVO_FONT_CELL_W * scale, ch = EVO_FONT_CELL_H * scale;
	for (; *s; s++) {
		if (*s == '\n') {
			cx = x;
			cy += ch;
			continue;
		}
		if (cx > -cw && cx < im->w && cy > -ch && cy < im->h) {
			const uint8_t *g = evo_font_glyph((unsigned char)*s);
			for (int row = 0; row < EVO_FONT_H; row++)
				for (int col = 0; col < EVO_FONT_W; col++)
					if (g[row] >> (EVO_FONT_W - 1 - col) &
					    1)
						evo_raster_fill_rect(
						    im, (int)cx + col * scale,
						    (int)cy + row * scale,
						    scale, scale, rgb, 255);
		}
		cx += cw;
		if (cx - x > widest)
			widest = cx - x;
	}
	return widest > INT_MAX ? INT_MAX : (int)widest;
}

int evo_raster_text_width(const char *s, int scale)
{
	scale = clamp_scale(scale);
	long long n = 0, widest = 0;
	for (; *s; s++) {
		n = *s == '\n' ? 0 : n + 1;
		if (n > widest)
			widest = n;
	}
	widest *= EVO_FONT_CELL_W * scale;
	return widest > INT_MAX ? INT_MAX : (int)widest;
}

int evo_raster_text_height(const char *s, int scale)
{
	scale = clamp_scale(scale);
	long long lines = *s ? 1 : 0;
	for (; *s; s++)
		if (*s == '\n')
			lines++;
	lines *= EVO_FONT_CELL_H * scale;
	return lines > INT_MAX ? INT_MAX : (int)lines;
}
