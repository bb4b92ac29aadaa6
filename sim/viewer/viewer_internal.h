/* evo — private to the viewer's files (sim/viewer/viewer.c,
 * viewer_panel.c, viewer_window.c, view3d.c): what one gives another
 * beyond viewer.h. No other file may use it. */
#ifndef EVO_VIEWER_INTERNAL_H
#define EVO_VIEWER_INTERNAL_H

#include "viewer/sdl_load.h"
#include "viewer/viewer.h"

/* The panel beside the world's view (viewer_panel.c), for evo_view_render. */
void view_draw_panel(evo_raster *im, const evo_scene *sc,
		       const evo_view_camera *cam, const evo_viewer_panel *p);

/* The start of opening the window of `what` ("the viewer", "the 3D
 * view"): a size of 0 or less made 1024 x 720, SDL loaded (with OpenGL
 * when gl) and its video started, and the window's struct of `size`
 * bytes, zeroed (free it, and SDL_QuitSubSystem(SDL_INIT_VIDEO), on a
 * later failure). NULL with err set ("cannot open the viewer: ... (no
 * display? ...)"). */
void *view_start_sdl(int gl, const char *what, int *w, int *h, size_t size,
		     evo_err *err);

/* What an event asks of the calling loop in both windows: QUIT for
 * closing the window, a shared key's action (evo_view_key), else
 * EVO_VIEW_NONE. */
evo_view_action view_action_of(const SDL_Event *ev);

/* What an event asks of the zoom, the same in the 2D and 3D windows
 * (viewer_window.c): nearer (+, =, keypad +, the wheel turned up),
 * farther (-, keypad -, the wheel down), back to the start (0, keypad 0),
 * or nothing. */
typedef enum view_zoom {
	VIEW_ZOOM_NONE = 0,
	VIEW_ZOOM_IN,
	VIEW_ZOOM_OUT,
	VIEW_ZOOM_HOME,
} view_zoom;
view_zoom view_zoom_of(const SDL_Event *ev);

#endif
