/* evo — the gallery of an OPENENDED run (docs/openended.md): a grid of
 * thumbnails of admitted environments, each its scene at the episode's
 * start as the viewer draws it from above (viewer/viewer.h,
 * evo_view_render, off screen as `evo run --screenshot` draws without a
 * window), with a caption under it, saved as one PNG. */
#ifndef EVO_GALLERY_H
#define EVO_GALLERY_H

#include "base/err.h"
#include "mind/task.h"

/* One thumbnail: the environment's genome (the text scene:genome()
 * gives) and its caption (one line; cut to the thumbnail's width). */
typedef struct evo_gallery_item {
	const char *genome;
	const char *caption;
} evo_gallery_item;

/* Thumbnails' world area and the grid's columns, in pixels. */
#define EVO_GALLERY_THUMB 180
#define EVO_GALLERY_COLUMNS 6
/* Items at most (a larger n is an error). */
#define EVO_GALLERY_MAX 64

/* Build task_path's scene (loaded with `to`) once, and for each of
 * items[0 .. n-1] reset it with that genome and draw it into its cell,
 * EVO_GALLERY_COLUMNS to a row, under a title line; save the PNG
 * atomically at png_path. Returns 0 or -1 with err (a scene's error
 * names the item). */
int evo_gallery_write(const char *task_path, const evo_task_opts *to,
		      const char *title, const evo_gallery_item *items, int n,
		      const char *png_path, evo_err *err);

#endif
