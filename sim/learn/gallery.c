/* evo — the gallery of an OPENENDED run: admitted environments drawn by
 * the viewer's renderer off screen, one thumbnail each, in a grid. */
#include "learn/gallery.h"

#include <stdio.h>
#include <string.h>

#include "lua/lua_evo.h"
#include "tasksim/tasksim.h"
#include "viewer/raster.h"
#include "viewer/viewer.h"

#define PAD 8	      /* pixels around and between the cells */
#define CAPTION 14    /* the caption strip under a thumbnail */
#define TITLE 22      /* the title strip at the top */
#define INK 0xD8DCE2u /* captions and title */

/* The frame whose world area is EVO_GALLERY_THUMB wide: the viewer puts
 * its panel in the frame's right third, a narrow frame's. */
#define FRAME_W (EVO_GALLERY_THUMB * 3 / 2)

/* Copy the world area of frame (its left EVO_GALLERY_THUMB columns) into
 * im at (x0, y0). */
static void blit(evo_raster *im, const evo_raster *frame, int x0, int y0)
{
	for (int y = 0; y < EVO_GALLERY_THUMB && y < frame->h; y++)
		for (int x = 0; x < EVO_GALLERY_THUMB && x < frame->w; x++)
			evo_raster_pixel(im, x0 + x, y0 + y,
					 evo_raster_get(frame, x, y), 255);
}

/* Text cut to `chars` characters, drawn at (x, y). */
static void caption(evo_raster *im, int x, int y, const char *text,
		    int chars)
{
	char line[128];
	snprintf(line, sizeof line, "%.*s", chars < 127 ? chars : 127, text);
	char *nl = strchr(line, '\n');
	if (nl)
		*nl = 0;
	evo_raster_text(im, x, y, line, INK, 1);
}

/* Item k's scene at its episode's start, drawn into frame. */
static int draw_item(evo_sim *s, const evo_gallery_item *it, int k,
		     evo_raster *frame, evo_err *err)
{
	evo_lua_set_genome(s->lua, it->genome);
	if (evo_sim_reset(s, 1, 1, 1, err)) {
		evo_err inner = *err;
		return evo_fail(err, "the gallery's environment %d (%s): %s",
				k + 1, it->caption, inner.msg);
	}
	double zoom = evo_view_fit_zoom(s->scene, frame->w, frame->h);
	evo_view_camera cam = evo_view_camera_for(
	    s->scene, EVO_VIEW_SCENE_START, zoom, frame->w, frame->h);
	evo_view_render(frame, s->scene, &cam, NULL);
	return 0;
}

static int draw_all(evo_sim *s, const char *title,
		    const evo_gallery_item *items, int n, evo_raster *im,
		    evo_err *err)
{
	evo_raster frame;
	if (evo_raster_init(&frame, FRAME_W, EVO_GALLERY_THUMB, err))
		return -1;
	evo_raster_clear(im, EVO_VIEW_PANEL);
	caption(im, PAD, (TITLE - EVO_FONT_CELL_H) / 2 + 1, title,
		(im->w - 2 * PAD) / EVO_FONT_CELL_W);
	int rc = 0;
	for (int k = 0; k < n && rc == 0; k++) {
		int x = PAD + (k % EVO_GALLERY_COLUMNS) *
				  (EVO_GALLERY_THUMB + PAD);
		int y = TITLE + (k / EVO_GALLERY_COLUMNS) *
				    (EVO_GALLERY_THUMB + CAPTION + PAD);
		rc = draw_item(s, &items[k], k, &frame, err);
		if (rc == 0) {
			blit(im, &frame, x, y);
			caption(im, x, y + EVO_GALLERY_THUMB + 3,
				items[k].caption,
				EVO_GALLERY_THUMB / EVO_FONT_CELL_W);
		}
	}
	evo_raster_free(&frame);
	return rc;
}

int evo_gallery_write(const char *task_path, const evo_task_opts *to,
		      const char *title, const evo_gallery_item *items, int n,
		      const char *png_path, evo_err *err)
{
	if (n < 1 || n > EVO_GALLERY_MAX)
		return evo_fail(err, "%s: a gallery of %d environments (1 to %d)",
				png_path, n, EVO_GALLERY_MAX);
	evo_task t;
	if (evo_task_load_opts(task_path, to, &t, err))
		return -1;
	evo_sim *s = evo_sim_create_task(&t, task_path, err);
	int rc = s ? 0 : -1;
	if (rc == 0 && (!s->lua || !s->scene))
		rc = evo_fail(err, "%s: the gallery draws a 2D Lua "
				   "environment's scenes; this task has none",
			      task_path);
	int cols = n < EVO_GALLERY_COLUMNS ? n : EVO_GALLERY_COLUMNS;
	int rows = (n + EVO_GALLERY_COLUMNS - 1) / EVO_GALLERY_COLUMNS;
	evo_raster im = {0};
	if (rc == 0)
		rc = evo_raster_init(&im, PAD + cols * (EVO_GALLERY_THUMB + PAD),
				     TITLE + rows * (EVO_GALLERY_THUMB +
						     CAPTION + PAD),
				     err);
	if (rc == 0)
		rc = draw_all(s, title, items, n, &im, err);
	if (rc == 0)
		rc = evo_raster_save_png(&im, png_path, err);
	evo_raster_free(&im);
	evo_sim_destroy(s);
	evo_task_free(&t);
	return rc;
}
