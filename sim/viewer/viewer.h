/* evo — the DEMOSIM viewer: a window on SDL2 that shows a scene as it
 * runs, with a panel of what the mind is doing; for a remote robot
 * (DEMOREMOTE), with no world to draw, the panel alone.
 *
 * Each frame is drawn by evo's own code into an RGB raster (sim/viewer/raster.h)
 * and blitted with one streaming texture, so it needs no GPU (it runs
 * under Xvfb) and a screenshot is exactly the frame on screen. The
 * drawing itself (evo_view_render) needs no window, for tests and for
 * frames saved without a display.
 *
 * Frame: world x to the right and y downward on screen, with no flip, as
 * in EvoAgents (scene.h); a world point (x, y) is drawn at
 *     sx = cx + (x - camx) * scale,  sy = cy + (y - camy) * scale,
 * so angles grow clockwise on screen.
 *
 * The calling loop (the evo command's DEMOSIM task) owns the pace:
 *
 *     evo_viewer *v = evo_viewer_open(1024, 720, &err);
 *     for (;;) {
 *             for (a = evo_viewer_poll(v); a; a = evo_viewer_poll(v))
 *                     ... act on a ...
 *             if (!paused) ... tick ...
 *             evo_viewer_draw(v, sc, 0, &panel);  // also while paused
 *     }
 *     evo_viewer_close(v);
 *
 * Zoom (+, -, 0, the mouse wheel) and window resizes are handled inside
 * and show at the next draw, which is why a paused loop still draws. */
#ifndef EVO_VIEWER_H
#define EVO_VIEWER_H

#include "base/err.h"
#include "viewer/raster.h"
#include "world2d/scene.h"

/* A column of n bars, one for each name, of values in [0, 1] (clamped
 * when drawn); either pointer may be NULL. */
typedef struct evo_view_bars {
	int n;
	const char *const *name;
	const double *value;
} evo_view_bars;

/* What the panel shows beside the world. Every pointer may be NULL. */
typedef struct evo_viewer_panel {
	const char *title; /* the task's name; also the window's title */
	long tick;
	int episode;
	double step_reward, episode_reward;
	/* The live influence of each skill of the hierarchy, one bar
	 * each, named. */
	evo_view_bars influence;
	double speed; /* simulated time per real time; 0 hides it */
	int paused;
	/* Teams (docs/teams.md): their names and rewards, listed with the
	 * colour their bots are drawn in (evo_view_team_colour). */
	int n_teams;
	const char *const *team_name;
	const double *team_reward;
	/* The bot selected (a click, Tab): NULL bot_name when none. It is
	 * ringed in the world, and the panel shows its name, team, reward
	 * and live sensor values and actuator commands; the influences
	 * above are then its own. */
	const char *bot_name;
	int bot;	      /* its index in the scene */
	const char *bot_team; /* NULL: no team */
	double bot_reward;
	evo_view_bars sensors, actuators;
	int following; /* the camera follows it (else: free) */
	/* The path a bot took this episode (`evo run --trail`), n_trail world
	 * points, oldest first, drawn as a line under the bots; none when 0. */
	int n_trail;
	const double *trail_x, *trail_y;
	/* The key help at the panel's foot; NULL: the 2D viewer's. */
	int n_help;
	const char *const *help;
} evo_viewer_panel;

/* What a key (or closing the window) asks of the calling loop. */
typedef enum evo_view_action {
	EVO_VIEW_NONE = 0,   /* no pending action */
	EVO_VIEW_QUIT,	     /* q, Esc, closing the window, Ctrl-C */
	EVO_VIEW_PAUSE,	     /* space or p: toggle pause */
	EVO_VIEW_STEP,	     /* n or right arrow: one tick while paused */
	EVO_VIEW_FASTER,     /* up arrow or ] */
	EVO_VIEW_SLOWER,     /* down arrow or [ */
	EVO_VIEW_RESET,	     /* r: restart the episode */
	EVO_VIEW_SCREENSHOT, /* s: the caller picks a path and calls
				evo_viewer_screenshot */
	EVO_VIEW_SELECT,     /* a click on the world: evo_viewer_clicked says
				where */
	EVO_VIEW_NEXT_BOT,   /* Tab: select the next bot */
	EVO_VIEW_CAMERA,     /* c: follow the selected bot, or free the
				camera */
	EVO_VIEW_FREE,	     /* the mouse dragged the world: the camera is
				free from now on */
} evo_view_action;

/* ---- drawing without a window --------------------------------------- */

/* Half the side of the world square shown at zoom 1, in metres: +-30 m
 * around the followed bot shows the obstacles its 12 m rays can reach and
 * the zone it heads for. */
#define EVO_VIEW_HALF_SPAN 30.0
/* Width of the panel at the right of the frame, in pixels (at most a
 * third of a narrow frame). */
#define EVO_VIEW_PANEL_W 264

typedef struct evo_view_camera {
	double x, y;   /* world point at the centre of the world area */
	double scale;  /* pixels per metre */
	double cx, cy; /* that centre, in pixels */
	int world_w;   /* width of the world area; the panel follows */
} evo_view_camera;

/* follow_bot for a camera that stays on the middle of the scene as it
 * started: its elements and where its bots started (--camera scene). */
#define EVO_VIEW_SCENE_START (-2)

/* The camera for a w x h frame: centred on bot follow_bot; for
 * EVO_VIEW_SCENE_START, on the middle of the scene as it started; for any
 * other index that is not a bot's, on the middle of everything in the
 * scene, bots where they are now; zoom 1
 * shows +-EVO_VIEW_HALF_SPAN metres across the smaller side of the world
 * area, zoom 2 half as much. */
evo_view_camera evo_view_camera_for(const evo_scene *sc, int follow_bot,
				    double zoom, int w, int h);

/* The zoom at which the scene as it starts (its elements, bots' starts,
 * fixed obstacles and walls) fits in the world area of a w x h frame
 * with a small margin: less than 1 where it does not fit at zoom 1; for a
 * scene that spans less than a quarter of zoom 1's view (an e-puck arena
 * of a few metres), the largest power of two at which it fits (at most
 * 64); 1 otherwise. */
double evo_view_fit_zoom(const evo_scene *sc, int w, int h);

/* Where world point (x, y) falls in a frame drawn with cam, in pixels
 * (pixel (i, j) covers [i, i + 1) x [j, j + 1)). */
void evo_view_to_screen(const evo_view_camera *cam, double x, double y,
			double *sx, double *sy);

/* Draw sc into im as cam sees it, with the panel (p may be NULL: the
 * scene's own tick and rewards are shown). Colours: floor patches in
 * their grey level under everything else, obstacles grey, zones
 * translucent green, objects orange (a faint outline once delivered),
 * bots blue (a team's in its colour) with a white heading line,
 * proximity rays red up to what they hit and faint where clear, a claw's
 * grip dark with the object it holds ringed; a bot, object or element
 * given a colour (scene:colour) in that colour; each light a disc of
 * EVO_VIEW_LIGHT_RADIUS pixels in its colour (EVO_VIEW_LIGHT with none)
 * over everything, ringed where a light sensor facing it reads 1 (the
 * square root of its intensity, in metres). */
void evo_view_render(evo_raster *im, const evo_scene *sc,
		     const evo_view_camera *cam, const evo_viewer_panel *p);

/* The panel alone, drawn from column x0 to the right edge of im: what
 * evo_view_render puts beside the world, for a view that draws its world
 * by other means (the 3D view, sim/viewer/view3d.h). */
void evo_view_render_panel(evo_raster *im, int x0, const evo_viewer_panel *p);

/* The bot of sc nearest to world point (x, y) within half a metre of
 * its body, or -1. */
int evo_view_bot_at(const evo_scene *sc, double x, double y);

/* The colour of team k's bots (a palette of 12), EVO_VIEW_BOT for a bot
 * of no team (k < 0). */
uint32_t evo_view_team_colour(int k);

/* The swarm's world (sim/scene/swarm.h, docs/world.md "Swarm sensors"),
 * as both views draw it: the colour a blob of evo_colour k is drawn in
 * (EVO_VIEW_LIGHT for a number that is no colour); the colour given to
 * the light, bot or element `index` of `kind` (evo_swarm_set_colour),
 * -1 when it has none; the colour of a floor patch's grey level in
 * [0, 1] (clamped), 0 black to 1 white. */
uint32_t evo_view_blob_colour(int colour);
int evo_view_colour_of(const evo_swarm *w, evo_blob_kind kind, int index);
uint32_t evo_view_grey(double grey);

/* The colours evo_view_render uses, for tests that look for them. */
#define EVO_VIEW_BACKGROUND	 0xF2F1ECu
#define EVO_VIEW_OBSTACLE	 0x8C8C8Cu
#define EVO_VIEW_ZONE		 0x3CB44Bu /* drawn at EVO_VIEW_ZONE_ALPHA */
#define EVO_VIEW_ZONE_ALPHA	 80
#define EVO_VIEW_OBJECT		 0xF08C1Eu
#define EVO_VIEW_BOT		 0x2F6FD0u
#define EVO_VIEW_HEADING	 0xFFFFFFu
#define EVO_VIEW_RAY_HIT	 0xE02828u /* a clear ray: EVO_VIEW_RAY_CLEAR_ALPHA */
#define EVO_VIEW_RAY_CLEAR_ALPHA 50
#define EVO_VIEW_HELD		 0xFFD21Fu /* ring around an object a claw holds */
#define EVO_VIEW_PANEL		 0x23262Bu
#define EVO_VIEW_TEXT		 0xE8E8E8u
#define EVO_VIEW_BAR		 0x4FB0E8u
#define EVO_VIEW_SELECTED	 0xFF3CC8u /* the ring around the selected bot */
#define EVO_VIEW_TRAIL		 0xD2287Eu /* the bot's path (--trail) */
#define EVO_VIEW_WALL		 0x5E5E5Eu /* a wall of no thickness (mazes) */
#define EVO_VIEW_LIGHT		 0xFFD21Fu /* a light given no colour */
#define EVO_VIEW_LIGHT_RADIUS	 6 /* pixels: the 2D view's mark of a light */

/* ---- a remote robot, with no world to draw (DEMOREMOTE) -------------- */

/* The link to a robot, as the panel names it. */
typedef enum evo_view_link {
	EVO_VIEW_LINK_WAITING = 0, /* no tick of the episode yet */
	EVO_VIEW_LINK_LIVE,	   /* ticks coming */
	EVO_VIEW_LINK_QUIET,	   /* nothing for a few periods */
	EVO_VIEW_LINK_SILENT,	   /* nothing for the timeout: evo said so */
	EVO_VIEW_LINK_ENDED,	   /* the episode ended */
} evo_view_link;

/* What the whole frame shows for a robot: the link, the counts of
 * docs/remote.md, and three columns of bars, the live sensor values, the
 * actuator commands (a mark at neutral, 0.5) and the skills' influences,
 * each value in [0, 1] (clamped when drawn). Every pointer may be NULL. */
typedef struct evo_view_remote {
	const char *title;  /* the task; also the window's title */
	const char *remote; /* the robot's name */
	double period_ms;   /* the robot's tick period */
	evo_view_link link;
	double quiet;	    /* seconds since the robot was last heard */
	int episode;
	long tick;	    /* the robot's tick last answered */
	double reward;	    /* the last sensors_t's */
	unsigned long in_time, late, missing;
	evo_view_bars sensors, actuators, influence;
} evo_view_remote;

/* Draw the robot's frame into im (any size; rows that do not fit are left
 * out). */
void evo_view_render_remote(evo_raster *im, const evo_view_remote *p);

/* The colours it uses beside the panel's, for tests that look for them. */
#define EVO_VIEW_SENSOR_BAR   0x9B7FE0u
#define EVO_VIEW_ACTUATOR_BAR 0xF08C1Eu
#define EVO_VIEW_LINK_OK      0x3CB44Bu /* live */
#define EVO_VIEW_LINK_WARN    0xFFC23Du /* quiet */
#define EVO_VIEW_LINK_BAD     0xE02828u /* silent */
#define EVO_VIEW_LINK_IDLE    0x6B717Au /* waiting, ended */

/* ---- the window ------------------------------------------------------ */

typedef struct evo_viewer evo_viewer;

/* Open a width x height window (0 or less: 1024 x 720). NULL with err set
 * when there is no display or SDL cannot make a renderer; the caller then
 * runs headless. */
evo_viewer *evo_viewer_open(int width, int height, evo_err *err);
/* Close the window and release SDL's video subsystem; NULL is fine. */
void evo_viewer_close(evo_viewer *v);

/* Draw one frame and show it. follow_bot as in evo_view_camera_for, but
 * -1 is the free camera (evo_viewer_look_at); p may be NULL. */
void evo_viewer_draw(evo_viewer *v, const evo_scene *sc, int follow_bot,
		     const evo_viewer_panel *p);

/* Draw and show the robot's frame (evo_view_render_remote). */
void evo_viewer_draw_remote(evo_viewer *v, const evo_view_remote *p);

/* The next pending action, EVO_VIEW_NONE when there is none; never
 * waits. Call until NONE once per frame: SDL (2.24 on) ends each round
 * of polling at a marker it queues, so an event that arrives during a
 * round comes out in the next frame's round, never lost. */
evo_view_action evo_viewer_poll(evo_viewer *v);

/* The action of a key the 2D and 3D views share (quit, pause, step,
 * speed, reset, screenshot, camera), given SDL's key code and whether it
 * is a repeat of a held key; EVO_VIEW_NONE for any other key. A held key
 * repeats what is meant to repeat (stepping, speed), never a toggle, a
 * reset or quitting. */
evo_view_action evo_view_key(int sym, int repeat);

/* The camera of the last frame drawn (to find a world point on it). */
evo_view_camera evo_viewer_camera(const evo_viewer *v);

/* Where the last click (EVO_VIEW_SELECT) fell, in world coordinates of the
 * last frame drawn. */
void evo_viewer_clicked(const evo_viewer *v, double *x, double *y);

/* A free camera (evo_viewer_draw with follow_bot -1) looks at where the
 * last followed bot was, or at first at the middle of the scene, and the
 * mouse drags it; this moves it. */
void evo_viewer_look_at(evo_viewer *v, double x, double y);
/* Multiply the zoom (as the keys do); clamped to [1/16, 64]. */
void evo_viewer_zoom(evo_viewer *v, double factor);

/* Save the last frame as an RGB PNG, read back from the renderer: the
 * pixels shown, not a redraw. Returns 0, or -1 with err set (nothing
 * drawn yet, the window resized since the last draw, SDL cannot read
 * back, the file cannot be written). */
int evo_viewer_screenshot(evo_viewer *v, const char *png_path, evo_err *err);

#endif
