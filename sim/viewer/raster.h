/* evo — a small RGB raster and the drawing evo needs without SDL: pixels,
 * lines, rectangles, circles, convex polygons and text in a built-in 5x7
 * bitmap font. The viewer draws every frame into one and blits it, so a
 * screenshot is exactly what was shown; the learning loop draws its
 * learning curve into one and saves it as a PNG (sim/viewer/png.h).
 *
 * Coordinates are pixels, x to the right and y downward, (0, 0) the
 * top-left corner. Pixel (i, j) covers [i, i + 1) x [j, j + 1); shapes
 * given in doubles cover the pixels whose centres (i + 0.5, j + 0.5) they
 * contain, so a shape drawn twice in the same place covers the same
 * pixels. Everything clips to the image: drawing off it is allowed and
 * does nothing.
 *
 * Colours are 0xRRGGBB. Every drawing call takes an alpha in [0, 255]:
 * 255 paints, less blends over what is there (translucent zones, faint
 * rays). */
#ifndef EVO_RASTER_H
#define EVO_RASTER_H

#include <stdint.h>

#include "base/err.h"

/* A w x h raster, 3 bytes per pixel (R, G, B), rows top first, no padding:
 * pixel (x, y) starts at pixels[3 * (y * w + x)]. */
typedef struct evo_raster {
	int w, h;
	uint8_t *pixels; /* owned when made by evo_raster_init */
} evo_raster;

/* Largest side evo_raster_init accepts; keeps w * h * 3 far from
 * overflowing and a typo from allocating gigabytes. */
#define EVO_RASTER_MAX_SIDE 16384

/* Allocate a w x h raster filled with black. Returns 0, or -1 with err set
 * (a side not in [1, EVO_RASTER_MAX_SIDE], out of memory). */
int evo_raster_init(evo_raster *im, int w, int h, evo_err *err);
/* Free the pixels and zero the struct; safe on a zeroed struct. */
void evo_raster_free(evo_raster *im);
/* Save as an 8-bit RGB PNG, atomically (sim/viewer/png.h). */
int evo_raster_save_png(const evo_raster *im, const char *path, evo_err *err);

/* 0xRRGGBB of pixel (x, y); 0 outside the image. */
uint32_t evo_raster_get(const evo_raster *im, int x, int y);
/* Paint the whole image. */
void evo_raster_clear(evo_raster *im, uint32_t rgb);
void evo_raster_pixel(evo_raster *im, int x, int y, uint32_t rgb, int alpha);
/* A one-pixel line from (x0, y0) to (x1, y1), both ends included
 * (Bresenham): each pixel is painted once, so a translucent line has an
 * even tone. */
void evo_raster_line(evo_raster *im, int x0, int y0, int x1, int y1,
		     uint32_t rgb, int alpha);
/* A line `width` pixels wide with square ends, as a filled quadrilateral;
 * widths below 1 draw a one-pixel line. */
void evo_raster_thick_line(evo_raster *im, double x0, double y0, double x1,
			   double y1, double width, uint32_t rgb, int alpha);
/* The w x h pixels from (x, y); nothing when w or h is not positive. */
void evo_raster_fill_rect(evo_raster *im, int x, int y, int w, int h,
			  uint32_t rgb, int alpha);
/* The one-pixel border of that rectangle. */
void evo_raster_rect(evo_raster *im, int x, int y, int w, int h,
		     uint32_t rgb, int alpha);
/* Pixels whose centres lie within r of (cx, cy). */
void evo_raster_fill_circle(evo_raster *im, double cx, double cy, double r,
			    uint32_t rgb, int alpha);
/* A ring `width` pixels wide just inside radius r. */
void evo_raster_circle(evo_raster *im, double cx, double cy, double r,
		       double width, uint32_t rgb, int alpha);
/* A convex polygon of n >= 3 vertices (either winding). Each pixel is
 * painted at most once. */
void evo_raster_fill_polygon(evo_raster *im, const double *x,
			     const double *y, int n, uint32_t rgb, int alpha);
/* Its outline, one pixel wide. */
void evo_raster_polygon(evo_raster *im, const double *x, const double *y,
			int n, uint32_t rgb, int alpha);

/* ---- text ----------------------------------------------------------- */

/* The font: glyphs 5 x 7 pixels in cells of EVO_FONT_CELL_W x
 * EVO_FONT_CELL_H (a column and two rows of spacing), all scaled by an
 * integer `scale` in [1, 64] (clamped). ASCII 32-126 have glyphs; any
 * other byte draws as a hollow box, so a wrong character shows instead
 * of vanishing. */
#define EVO_FONT_W	5
#define EVO_FONT_H	7
#define EVO_FONT_CELL_W 6
#define EVO_FONT_CELL_H 9

/* The 7 rows of a character's glyph, bit 4 the leftmost column. */
const uint8_t *evo_font_glyph(unsigned char c);

/* Draw s with its cell's top-left corner at (x, y); '\n' starts a new
 * line at x. Returns the width in pixels of the widest line. */
int evo_raster_text(evo_raster *im, int x, int y, const char *s,
		    uint32_t rgb, int scale);
/* The width and height s would take, without drawing. */
int evo_raster_text_width(const char *s, int scale);
int evo_raster_text_height(const char *s, int scale);

#endif
