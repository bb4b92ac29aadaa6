/* evo — the DEMO3DSIM view: a window on SDL2 with an OpenGL context (Mesa;
 * llvmpipe under Xvfb) that shows a 3D scene as it runs, shaded, with its
 * proximity rays, and beside it the 2D viewer's panel (the tick, the
 * rewards and each skill's live influence), drawn by evo_view_render_panel
 * and put on screen as pixels.
 *
 * Camera: it orbits a point (left drag turns it, the wheel or + and -
 * bring it nearer or farther), pans (right drag, which frees it) and
 * follows the robot (c: follow, or stay free where it is). The keys are
 * the 2D viewer's (viewer.h, evo_view_action); docs/world3d.md lists them.
 *
 * The camera's pose: it looks at its target (the followed bot's centre,
 * which so shows at the middle of the 3D area, left of the panel) from
 * dist metres away, pitch radians above the ground and from the bearing
 * yaw (its eye at target + dist (cos pitch cos yaw, cos pitch sin yaw,
 * sin pitch)), z up, with a vertical field of view of 50 degrees. It
 * starts at pitch 0.45, yaw -2.4 and dist 4; where the scene has a target,
 * aimed from beyond the robot as the episode starts: yaw = the bearing
 * from the target to the robot, dist 1.5 times their distance + 3 m.
 *
 * Without a window (evo_view3d_open_offscreen), the same frames are drawn
 * by the same code into Mesa's EGL off screen (viewer/egl_offscreen.h):
 * a 3D --screenshot or --record needs no display.
 *
 * The calling loop owns the pace, as with the 2D viewer:
 *
 *     evo_view3d *v = evo_view3d_open(1024, 720, &err);
 *     for (a = evo_view3d_poll(v); a; a = evo_view3d_poll(v)) ...
 *     evo_view3d_draw(v, sc, follow, &panel);
 *     evo_view3d_close(v); */
#ifndef EVO_VIEW3D_H
#define EVO_VIEW3D_H

#include "base/err.h"
#include "viewer/raster.h"
#include "viewer/viewer.h"
#include "world3d/scene3d.h"

typedef struct evo_view3d evo_view3d;

/* Open a width x height window with an OpenGL context (0 or less: 1024 x
 * 720). NULL with err set when there is no display or no OpenGL. */
evo_view3d *evo_view3d_open(int width, int height, evo_err *err);
/* The same view without a window: frames of width x height drawn off
 * screen (0 or less: 1024 x 720); NULL with err saying which library or
 * step is missing and the Debian packages that bring it. */
evo_view3d *evo_view3d_open_offscreen(int width, int height, evo_err *err);
void evo_view3d_close(evo_view3d *v);

/* Aim the camera as the scene stands (once per view: its first call, or
 * the first frame's, does it; see the pose above). Called as an episode
 * starts, so every frame of it has the same camera with a window or
 * without. */
void evo_view3d_aim(evo_view3d *v, const evo_scene3d *sc);

/* Draw one frame and show it: the camera on bot `follow` (its centre),
 * or, with follow -1, where it was left; p may be NULL. */
void evo_view3d_draw(evo_view3d *v, const evo_scene3d *sc, int follow,
		     const evo_viewer_panel *p);

/* The next pending action (viewer.h), EVO_VIEW_NONE when there is none;
 * never waits. Mouse drags and the wheel move the camera inside;
 * a pan returns EVO_VIEW_FREE. */
evo_view_action evo_view3d_poll(evo_view3d *v);

/* Save the last frame shown as an RGB PNG: the pixels read back from
 * OpenGL as it was drawn. 0, or -1 with err set. */
int evo_view3d_screenshot(evo_view3d *v, const char *png_path, evo_err *err);

/* Copy the last frame drawn into im (rows top first, as evo_raster has
 * them). 0, or -1 when no frame of im's size was drawn. */
int evo_view3d_frame(const evo_view3d *v, evo_raster *im);

/* Colours it draws in, for tests that look for them. The rays are drawn
 * without shading, in EVO_VIEW_RAY_HIT where they hit something and
 * EVO_VIEW3D_RAY_CLEAR where they do not; the bodies are shaded, so a
 * test looks for their hue. */
#define EVO_VIEW3D_SKY	     0xCFDCE8u
#define EVO_VIEW3D_BOT	     0x2F6FD0u
#define EVO_VIEW3D_OBSTACLE  0x8C8C8Cu
#define EVO_VIEW3D_TARGET    0xF0B41Eu
#define EVO_VIEW3D_RAY_CLEAR 0xF0B4B4u
#define EVO_VIEW3D_BUMP	     0xC9BFA0u /* uneven ground */

/* The swarm's world (sim/scene/swarm.h) as the 3D view draws it: each
 * floor patch flat on the ground in its grey level (evo_view_grey),
 * shaded as the ground is; each light a sphere without shading, in its
 * colour (evo_view_blob_colour; EVO_VIEW_LIGHT with none), of radius a
 * quarter of the square root of its intensity (where a light sensor
 * facing it reads 1) within [EVO_VIEW3D_LIGHT_MIN, _MAX] metres; a bot,
 * target, object or zone given a colour (scene:colour), shaded in it. */
#define EVO_VIEW3D_LIGHT_MIN 0.02
#define EVO_VIEW3D_LIGHT_MAX 0.5

#endif
