/* evo — private to the viewer's files (sim/viewer/viewer.c,
 * viewer_panel.c, viewer_window.c): what one gives another beyond
 * viewer.h. No other file may use it. */
#ifndef EVO_VIEWER_INTERNAL_H
#define EVO_VIEWER_INTERNAL_H

#include "viewer/viewer.h"

/* The panel beside the world's view (viewer_panel.c), for evo_view_render. */
void view_draw_panel(evo_raster *im, const evo_scene *sc,
		       const evo_view_camera *cam, const evo_viewer_panel *p);

#endif
