/* The 3D view without a display (sim/viewer/view3d.c off screen, through
 * sim/viewer/egl_offscreen.c): with DISPLAY unset, a 3D task's
 * `--screenshot` and `--record` draw the scene with Mesa's EGL.
 *
 * The scene is a blimp at (0, 0, 3) and its target at (4, 0, 3) (an
 * environment written here), so the camera's pose as view3d.h documents
 * it is known by hand at tick 0: it follows the blimp from beyond it,
 * yaw pi (looking along +x), pitch 0.45 rad, 1.5 * 4 + 3 = 9 m away, and
 * the pixels where the sky, the ground, the blimp and the target show,
 * and their shaded colours, are worked out below from that pose and the
 * view's one light. The frame at tick 60 differs (the blimp closed on its
 * target); `--screenshot` at a tick is `--record`'s frame of that tick;
 * the same frame drawn in a window (Xvfb) is the same, byte for byte; a
 * run that draws nothing in 3D never loads EGL, and a missing library is
 * named with its Debian package. A light, a floor patch and a bot's
 * colour (sim/scene/swarm.h) show where worked out the same way. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/view3d.h"
#include "viewer/viewer.h"

static char out[65536];

#define W 1024
#define H 720

#define TASK "%s/m/Blimp3D/Tasks/Ahead.simbatch"
#define NOX  "env -u DISPLAY -u WAYLAND_DISPLAY "

/* The blimp and its target 4 m ahead, at the same height, nothing else. */
static void make_task(void)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/m && cp -r minds/Blimp3D %s/m/ && "
			    "mkdir -p %s/m/Blimp3D/Envs",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(
	    cli_write(
		"local env = {}\n"
		"function env.init(scene, task)\n"
		"  local t = scene:target{ name = 'goal', x = 4, y = 0, z = 3,"
		" radius = 0.2 }\n"
		"  local bot = scene:bot{ x = 0, y = 0, z = 3 }\n"
		"  bot:target('TARG_AZIM', t)\n"
		"  bot:target('TARG_ELEV', t)\n"
		"  bot:target('DIST', t)\n"
		"  scene:reward('ClosingOnTarget', { bot = bot, target = t,"
		" k = 10 })\n"
		"  scene:control('NextOnTimeout', { bot = bot, ticks = 300 })\n"
		"end\n"
		"return env\n",
		"%s/m/Blimp3D/Envs/Ahead.lua", cli_tmp),
	    0);
	CHECK_EQ_INT(cli_write("TYPE:DEMO3DSIM\nBOTMODEL:Blimp3D\n"
			       "MASTERSKILL:GoToTarget\nENV:Ahead\n",
			       TASK, cli_tmp),
		     0);
}

static const uint8_t *px(const evo_png_image *im, int x, int y)
{
	return im->pixels + 3 * ((size_t)y * im->w + x);
}

/* Pixel (x, y) is rgb * k (each channel clamped to 255), within tol;
 * say: print it when it is not. */
static int near_say(const evo_png_image *im, int x, int y, uint32_t rgb,
		    double k, int tol, int say)
{
	const uint8_t *p = px(im, x, y);
	for (int c = 0; c < 3; c++) {
		double want = ((rgb >> (16 - 8 * c)) & 255) * k;
		want = want > 255 ? 255 : want;
		if (fabs(p[c] - want) > tol) {
			if (say)
				printf("  pixel (%d, %d) is %d,%d,%d; expected "
				       "%06X x %.4f\n",
				       x, y, p[0], p[1], p[2], (unsigned)rgb,
				       k);
			return 0;
		}
	}
	return 1;
}

static int near(const evo_png_image *im, int x, int y, uint32_t rgb, double k,
		int tol)
{
	return near_say(im, x, y, rgb, k, tol, 1);
}

/* The light of a surface of normal n (unit): the view's ambient 0.45 and
 * its one directional light of 0.65 from (0.4, 0.3, 1). */
static double light(const double n[3])
{
	double l = sqrt(0.4 * 0.4 + 0.3 * 0.3 + 1);
	double d = (0.4 * n[0] + 0.3 * n[1] + n[2]) / l;
	return 0.45 + 0.65 * (d > 0 ? d : 0);
}

/* Where the camera of tick 0 is, and where a point on its axis' vertical
 * plane (y = 0) ahead of it projects: the row of a point at x, z. */
static const double PITCH = 0.45, DIST = 9, BOT_Z = 3;
static int row_of(double x, double z)
{
	double eye_x = -DIST * cos(PITCH), eye_z = BOT_Z + DIST * sin(PITCH);
	double below = atan2(eye_z - z, x - eye_x); /* below the horizon */
	double up = PITCH - below;		    /* above the axis */
	return (int)lround(H / 2.0 - tan(up) / tan(25 * M_PI / 180) * H / 2.0);
}

/* The frame of tick 0 drawn without a display, checked pixel by pixel
 * against the pose; tick 60's differs where the target was. */
TEST(a_3d_recording_without_a_display_shows_the_scene_where_worked_out)
{
	make_task();
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 NOX "%s run " TASK " --ticks 60 --record "
				     "%s/fr --record-every 30 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "recorded 3 frames in");
	evo_png_image a = {0}, b = {0};
	evo_err err = {{0}};
	char path[512];
	snprintf(path, sizeof path, "%s/fr/frame-000001.png", cli_tmp);
	CHECK_EQ_INT(evo_png_read(path, &a, &err), 0);
	snprintf(path, sizeof path, "%s/fr/frame-000003.png", cli_tmp);
	CHECK_EQ_INT(evo_png_read(path, &b, &err), 0);
	if (!a.pixels || !b.pixels) {
		printf("  %s\n", err.msg);
		return;
	}
	CHECK_EQ_INT(a.w, W);
	CHECK_EQ_INT(a.h, H);
	/* the 3D area left of the panel; the camera's target, the blimp's
	 * centre, at its middle */
	int cx = (W - EVO_VIEW_PANEL_W) / 2, cy = H / 2;
	/* top left: above the horizon (0.45 - 25 degrees is 0.8 degree below
	 * it, and the ground ends 20 m out), the sky's clear colour */
	CHECK(near(&a, 0, 0, EVO_VIEW3D_SKY, 1, 0));
	/* bottom left: the ground, a light or a dark tile, lit from above
	 * (normal (0, 0, 1)) */
	double up[3] = {0, 0, 1}, k = light(up);
	CHECK(near_say(&a, 0, H - 1, 0xE4E1D6u, k, 2, 0) ||
	      near(&a, 0, H - 1, 0xD8D4C6u, k, 2));
	/* the blimp's centre: its sphere faces the eye there, normal (cos
	 * pitch cos yaw, cos pitch sin yaw, sin pitch) with yaw pi; the
	 * sphere is facets, shaded between its corners: within 4 */
	double n_bot[3] = {-cos(PITCH), 0, sin(PITCH)};
	CHECK(near(&a, cx, cy, EVO_VIEW3D_BOT, light(n_bot), 4));
	/* the target, straight ahead beyond it: on the middle column, at the
	 * row worked out from the pose, facing the eye */
	int ty = row_of(4, 3);
	CHECK_EQ_INT(ty, 253);
	double ex = 4 + DIST * cos(PITCH), ez = BOT_Z + DIST * sin(PITCH) - 3;
	double n_t[3] = {-ex / hypot(ex, ez), 0, ez / hypot(ex, ez)};
	CHECK(near(&a, cx, ty, EVO_VIEW3D_TARGET, light(n_t), 4));
	/* tick 60: the blimp moved on towards its target; the camera that
	 * follows it shows the target elsewhere and the ground where it was */
	CHECK(!near_say(&b, cx, ty, EVO_VIEW3D_TARGET, light(n_t), 40, 0));
	long differ = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W - EVO_VIEW_PANEL_W; x++)
			differ += memcmp(px(&a, x, y), px(&b, x, y), 3) != 0;
	printf("  tick 0 and tick 60: %ld pixels differ\n", differ);
	CHECK(differ > 1000);
	evo_png_image_free(&a);
	evo_png_image_free(&b);
}

/* --screenshot at tick 60 without a display is --record's frame of tick
 * 60; drawn in a window under Xvfb it is the same, byte for byte: the
 * same drawing, only the context differs. */
TEST(a_3d_screenshot_without_a_display_is_the_windows_frame)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 NOX "%s run " TASK " --ticks 60 --screenshot "
				     "%s/off.png 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "(tick 60, drawn without a window)");
	CHECK_EQ_INT(cli_sh("cmp -s %s/off.png %s/fr/frame-000003.png", cli_tmp,
			    cli_tmp),
		     0);
	int rc = cli_capture(out, sizeof out,
			     "xvfb-run -a -s '-screen 0 1280x800x24' sh -c "
			     "'%s run " TASK " --ticks 60 --screenshot "
			     "%s/win.png' 2>&1",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		printf("  %s\n", out);
	CHECK_CONTAINS(out, "(tick 60)");
	CHECK_EQ_INT(cli_sh("cmp -s %s/off.png %s/win.png", cli_tmp, cli_tmp),
		     0);
}

/* EGL is loaded only to draw: a headless run of the same task never maps
 * it (nor OpenGL); a screenshot does. */
TEST(a_3d_run_that_draws_nothing_never_loads_egl)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 NOX "LD_DEBUG=files %s run " TASK
				     " --ticks 5 --headless 2>&1",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "episode 1:");
	CHECK(!strstr(out, "file=libEGL"));
	CHECK(!strstr(out, "file=libOpenGL"));
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 NOX "LD_DEBUG=files %s run " TASK
				     " --ticks 5 --screenshot %s/5.png 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "file=libEGL.so.1");
	CHECK_CONTAINS(out, "file=libOpenGL.so.0");
}

/* Where a library is missing (here an empty file stands for it) or Mesa's
 * EGL is not installed (GLVND finds no vendor), the message names it and
 * the Debian packages to install, and no PNG is written. */
TEST(a_missing_library_is_named_with_its_debian_package)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/nolib %s/nogl && "
			    ": > %s/nolib/libEGL.so.1 && "
			    ": > %s/nogl/libOpenGL.so.0",
			    cli_tmp, cli_tmp, cli_tmp, cli_tmp),
		     0);
	static const char *const env[3] = {
	    "LD_LIBRARY_PATH=%s/nolib", "LD_LIBRARY_PATH=%s/nogl",
	    "__EGL_VENDOR_LIBRARY_FILENAMES=%s/none.json"};
	static const char *const says[3][2] = {
	    {"cannot draw 3D without a window: libEGL.so.1 cannot be loaded",
	     "install Debian's libegl1 libegl-mesa0 libgl1-mesa-dri"},
	    {"libOpenGL.so.0 cannot be loaded", "install Debian's libopengl0"},
	    {"libEGL.so.1 has no surfaceless platform",
	     "install Debian's libegl1 libegl-mesa0 libgl1-mesa-dri"}};
	for (int i = 0; i < 3; i++) {
		char e[512];
		snprintf(e, sizeof e, env[i], cli_tmp);
		CHECK_EQ_INT(cli_capture(out, sizeof out,
					 NOX "%s %s run " TASK " --ticks 5 "
					     "--screenshot %s/lib%d.png 2>&1",
					 e, cli_evo, cli_tmp, cli_tmp, i),
			     1);
		CHECK_CONTAINS(out, says[i][0]);
		CHECK_CONTAINS(out, says[i][1]);
		CHECK_EQ_INT(cli_sh("test -e %s/lib%d.png", cli_tmp, i), 1);
	}
}

/* The swarm's world in 3D: the scene of make_task with a light at (2, 0,
 * 0.5), a patch of grey 0.25 and radius 1 on the ground at (-2, 0) and
 * the blimp given the colour red, and a 2 m box at (8, 0, 1) given the
 * colour blue. At tick 0 (the camera of
 * a_3d_recording_...), the light shows on the middle column at the row
 * worked out from the pose, unshaded in EVO_VIEW_LIGHT; the patch at
 * (-2, 0, 0) in its grey, lit from above as the ground is; the blimp's
 * centre in red (evo_view_blob_colour), shaded as its blue was; the
 * box's top face in blue, lit from above. */
TEST(a_3d_frame_shows_lights_patches_and_colours)
{
	CHECK_EQ_INT(
	    cli_write(
		"local env = {}\n"
		"function env.init(scene, task)\n"
		"  local t = scene:target{ name = 'goal', x = 4, y = 0, z = 3,"
		" radius = 0.2 }\n"
		"  local bot = scene:bot{ x = 0, y = 0, z = 3 }\n"
		"  bot:target('TARG_AZIM', t)\n"
		"  bot:target('TARG_ELEV', t)\n"
		"  bot:target('DIST', t)\n"
		"  scene:light{ x = 2, y = 0, z = 0.5, intensity = 10 }\n"
		"  scene:patch{ x = -2, y = 0, radius = 1, grey = 0.25 }\n"
		"  scene:colour(bot, 'red')\n"
		"  local b = scene:box{ x = 8, y = 0, z = 1, hx = 1, hy = 1,"
		" hz = 1 }\n"
		"  scene:colour(b, 'blue')\n"
		"  scene:control('NextOnTimeout', { bot = bot, ticks = 300 })\n"
		"end\n"
		"return env\n",
		"%s/m/Blimp3D/Envs/Swarm.lua", cli_tmp),
	    0);
	CHECK_EQ_INT(cli_write("TYPE:DEMO3DSIM\nBOTMODEL:Blimp3D\n"
			       "MASTERSKILL:GoToTarget\nENV:Swarm\n",
			       "%s/m/Blimp3D/Tasks/Swarm.simbatch", cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 NOX "%s run %s/m/Blimp3D/Tasks/Swarm.simbatch "
				     "--ticks 1 --record %s/sw --record-every "
				     "1 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	evo_png_image a = {0};
	evo_err err = {{0}};
	char path[512];
	snprintf(path, sizeof path, "%s/sw/frame-000001.png", cli_tmp);
	CHECK_EQ_INT(evo_png_read(path, &a, &err), 0);
	if (!a.pixels) {
		printf("  %s\n%s\n", err.msg, out);
		return;
	}
	int cx = (W - EVO_VIEW_PANEL_W) / 2, cy = H / 2;
	double up[3] = {0, 0, 1};
	double n_bot[3] = {-cos(PITCH), 0, sin(PITCH)};
	CHECK(near(&a, cx, row_of(2, 0.5), EVO_VIEW_LIGHT, 1, 2));
	CHECK(near(&a, cx, row_of(-2, 0), evo_view_grey(0.25), light(up), 2));
	CHECK(near(&a, cx, cy, evo_view_blob_colour(EVO_COLOUR_RED),
		   light(n_bot), 4));
	/* the box's top face, at (8, 0, 2), in blue lit from above */
	CHECK(near(&a, cx, row_of(8, 2), evo_view_blob_colour(EVO_COLOUR_BLUE),
		   light(up), 2));
	evo_png_image_free(&a);
}

/* --camera, --zoom and --trail place 2D frames: a 3D task refuses them
 * with the reason. */
TEST(a_3d_frame_refuses_the_2d_camera_options)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 NOX "%s run " TASK " --ticks 5 --zoom 2 "
				     "--screenshot %s/z.png 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "Ahead.simbatch: --camera, --zoom and --trail "
			    "are for 2D frames");
	CHECK_EQ_INT(cli_sh("test -e %s/z.png", cli_tmp), 1);
}

int main(void)
{
	if (cli_setup("view3d"))
		return 1;
	RUN(a_3d_recording_without_a_display_shows_the_scene_where_worked_out);
	RUN(a_3d_screenshot_without_a_display_is_the_windows_frame);
	RUN(a_3d_frame_shows_lights_patches_and_colours);
	RUN(a_3d_run_that_draws_nothing_never_loads_egl);
	RUN(a_missing_library_is_named_with_its_debian_package);
	RUN(a_3d_frame_refuses_the_2d_camera_options);
	cli_cleanup();
	return test_summary();
}
