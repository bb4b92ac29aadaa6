/* The learning curve (sim/learn/curve.c): the PNG reads back, and the curves
 * are where the values put them; the best-ever line stays up where the
 * generation's best falls back; the title is written where the header
 * says, in the built-in font (curve_has_title, which test_messages uses
 * on a real run's curve). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "harness.h"
#include "support/cli.h"
#include "learn/curve.h"
#include "viewer/png.h"
#include "viewer/raster.h"

static uint32_t pixel(const evo_png_image *img, int x, int y)
{
	const uint8_t *p = img->pixels + ((size_t)y * (size_t)img->w + (size_t)x) *
						 (size_t)img->channels;
	return (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
}

/* Does column x hold colour rgb in its top or bottom half? */
static int colour_in_column(const evo_png_image *img, int x, uint32_t rgb,
			    int top_half)
{
	int y0 = top_half ? 0 : img->h / 2, y1 = top_half ? img->h / 2 : img->h;
	for (int y = y0; y < y1; y++)
		if (pixel(img, x, y) == rgb)
			return 1;
	return 0;
}

TEST(rising_best_is_drawn_rising)
{
	char path[512];
	snprintf(path, sizeof path, "%s/evo-curve-XXXXXX", cli_tmp_root());
	int fd = mkstemp(path);
	CHECK(fd >= 0);
	close(fd);
	double best[50], mean[50];
	for (int i = 0; i < 50; i++) {
		best[i] = 10.0 * i;
		mean[i] = 2.0 * i;
	}
	mean[20] = NAN; /* left out, not drawn as garbage */
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_curve_write(path, "Avoid NEAT", best, mean, 50, &err),
		     0);
	evo_png_image img;
	CHECK_EQ_INT(evo_png_read(path, &img, &err), 0);
	CHECK_EQ_INT(img.w, 800);
	CHECK_EQ_INT(img.h, 500);
	/* Best starts low on the left and ends high on the right; the mean
	 * stays in the lower half. */
	CHECK(colour_in_column(&img, 92, EVO_CURVE_BEST, 0));
	CHECK(!colour_in_column(&img, 92, EVO_CURVE_BEST, 1));
	CHECK(colour_in_column(&img, 778, EVO_CURVE_BEST, 1));
	CHECK(colour_in_column(&img, 778, EVO_CURVE_MEAN, 0));
	CHECK(!colour_in_column(&img, 778, EVO_CURVE_MEAN, 1));
	evo_png_image_free(&img);
	unlink(path);
}

/* The title's pixels are those of the text drawn alone. */
static int curve_has_title(const evo_png_image *img, const char *title)
{
	evo_raster t;
	evo_err err = {{0}};
	int w = evo_raster_text_width(title, EVO_CURVE_TITLE_SCALE);
	int h = EVO_FONT_CELL_H * EVO_CURVE_TITLE_SCALE;
	if (evo_raster_init(&t, w, h, &err))
		return 0;
	evo_raster_clear(&t, EVO_CURVE_BACKGROUND);
	evo_raster_text(&t, 0, 0, title, EVO_CURVE_TEXT, EVO_CURVE_TITLE_SCALE);
	int same = 1;
	for (int y = 0; y < h - 2 * EVO_CURVE_TITLE_SCALE; y++)
		for (int x = 0; x < w; x++)
			same &= pixel(img, EVO_CURVE_TITLE_X + x,
				      EVO_CURVE_TITLE_Y + y) ==
				evo_raster_get(&t, x, y);
	evo_raster_free(&t);
	return same;
}

TEST(best_ever_and_title_are_drawn)
{
	char path[512];
	snprintf(path, sizeof path, "%s/evo-curve-XXXXXX", cli_tmp_root());
	int fd = mkstemp(path);
	CHECK(fd >= 0);
	close(fd);
	/* best climbs to 100 by generation 10, falls to 0 and stays */
	double best[40];
	for (int i = 0; i < 40; i++)
		best[i] = i <= 10 ? 10.0 * i : 0;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_curve_write(path, "Avoid: Small (NEAT, seed 3)", best,
				     NULL, 40, &err),
		     0);
	evo_png_image img;
	CHECK_EQ_INT(evo_png_read(path, &img, &err), 0);
	/* on the right the best is at the bottom, the best ever at the top */
	CHECK(!colour_in_column(&img, 760, EVO_CURVE_BEST, 1));
	CHECK(colour_in_column(&img, 760, EVO_CURVE_BEST, 0));
	CHECK(colour_in_column(&img, 760, EVO_CURVE_BEST_EVER, 1));
	CHECK(curve_has_title(&img, "Avoid: Small (NEAT, seed 3)"));
	CHECK(!curve_has_title(&img, "Avoid: Small (NEAT, seed 4)"));
	evo_png_image_free(&img);
	unlink(path);
}

TEST(empty_and_flat_curves_still_write)
{
	char path[512];
	snprintf(path, sizeof path, "%s/evo-curve-XXXXXX", cli_tmp_root());
	int fd = mkstemp(path);
	close(fd);
	evo_err err = {{0}};
	double flat[3] = {5, 5, 5};
	CHECK_EQ_INT(evo_curve_write(path, "flat", flat, NULL, 3, &err), 0);
	CHECK_EQ_INT(evo_curve_write(path, NULL, NULL, NULL, 0, &err), 0);
	evo_png_image img;
	CHECK_EQ_INT(evo_png_read(path, &img, &err), 0);
	evo_png_image_free(&img);
	unlink(path);
}

TEST(unwritable_path_is_an_error)
{
	evo_err err = {{0}};
	double v[2] = {1, 2};
	CHECK_EQ_INT(evo_curve_write("/nonexistent-dir/x.png", "t", v, v, 2,
				     &err),
		     -1);
	CHECK_CONTAINS(err.msg, "/nonexistent-dir/x.png");
}

int main(void)
{
	RUN(rising_best_is_drawn_rising);
	RUN(best_ever_and_title_are_drawn);
	RUN(empty_and_flat_curves_still_write);
	RUN(unwritable_path_is_an_error);
	return test_summary();
}
