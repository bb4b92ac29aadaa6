/* The DEMOSIM viewer (sim/viewer/viewer.c): a scene drawn where its pieces are,
 * in a real window under X. When DISPLAY is not set the test starts its
 * own Xvfb (the display number from -displayfd, never a fixed one) and
 * stops it at the end; when Xvfb cannot start, the window tests fail and
 * say why.
 *
 * The scene: a bot at the origin facing +x, a proximity sensor on its
 * nose whose rays hit a cylinder 6 m ahead, a second one looking back at
 * nothing, a box, a zone and an object. The checks look up pixels at the
 * projections of those pieces. */
#define _GNU_SOURCE /* prctl, setenv, RTLD_NODELETE */
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/sdl_load.h"
#include "viewer/viewer.h"

#define PI 3.14159265358979323846

/* Element indices of the scene below. */
enum { CYLINDER, BOX, ZONE, OBJECT };

/* Where the bot starts; everything else is placed relative to it. Off
 * the 10 m background grid, whose lines would otherwise run under the
 * rays and change their blended colour. */
#define BX 3.0
#define BY 4.0

static evo_scene *make_scene(void)
{
	evo_scene *sc = evo_scene_create();
	if (!sc)
		return NULL;
	evo_element_def e =
	    evo_default_element_def(EVO_PIECE_CYLINDER, EVO_DIM_2D);
	e.name = "pillar";
	e.x = BX + 6;
	e.y = BY;
	e.size = 1.5;
	int ok = evo_scene_add_element(sc, &e) == CYLINDER;
	e = evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_2D);
	e.name = "crate";
	e.x = BX - 8;
	e.y = BY + 5;
	e.angle = 0.3;
	e.half_w = 2;
	e.half_h = 1;
	ok &= evo_scene_add_element(sc, &e) == BOX;
	e = evo_default_element_def(EVO_PIECE_ZONE, EVO_DIM_2D);
	e.name = "nest";
	e.x = BX;
	e.y = BY - 10;
	e.size = 3;
	ok &= evo_scene_add_element(sc, &e) == ZONE;
	e = evo_default_element_def(EVO_PIECE_OBJECT, EVO_DIM_2D);
	e.name = "food";
	e.x = BX - 6;
	e.y = BY - 4;
	e.size = 0.7;
	ok &= evo_scene_add_element(sc, &e) == OBJECT;

	evo_bot_def b = evo_default_bot_def();
	b.name = "bot";
	b.x = BX;
	b.y = BY;
	ok &= evo_scene_add_bot(sc, &b) == 0;
	evo_sensor_def s = evo_default_sensor_def(EVO_SENSE_PROXIMITY);
	s.name = "ProxFront";
	s.x = 1;
	ok &= evo_scene_add_sensor(sc, 0, &s) == 0;
	s.name = "ProxBack";
	s.x = -1;
	s.angle = PI;
	ok &= evo_scene_add_sensor(sc, 0, &s) == 1;
	evo_actuator_def a = evo_default_actuator_def(EVO_ACT_CLAW);
	a.name = "Claw";
	a.x = 1;
	ok &= evo_scene_add_actuator(sc, 0, &a) == 0;
	if (!ok) {
		printf("    cannot build the scene: %s\n", sc->err.msg);
		evo_scene_destroy(sc);
		return NULL;
	}
	evo_scene_reset(sc, 1, 1);
	evo_scene_sense(sc);
	return sc;
}

static const char *const skill_names[] = {"Collect", "GoToObject", "Avoid"};
static const double skill_influence[] = {1.0, 0.25, 0.0};

static evo_viewer_panel make_panel(void)
{
	evo_viewer_panel p;
	memset(&p, 0, sizeof p);
	p.title = "Collect-DEMO";
	p.tick = 42;
	p.episode = 3;
	p.step_reward = 0.125;
	p.episode_reward = 7.5;
	p.influence.n = 3;
	p.influence.name = skill_names;
	p.influence.value = skill_influence;
	p.speed = 2;
	p.paused = 1;
	return p;
}

/* An 8-bit blend as the raster makes it. */
static uint32_t blend(uint32_t src, uint32_t dst, int a)
{
	uint32_t out = 0;
	for (int sh = 16; sh >= 0; sh -= 8) {
		int s = (int)(src >> sh & 0xFF), d = (int)(dst >> sh & 0xFF);
		out |= (uint32_t)((s * a + d * (255 - a) + 127) / 255) << sh;
	}
	return out;
}

/* Pixels of an image as the viewer's tests read them: a raster or a
 * decoded PNG, both RGB. */
typedef struct view {
	const uint8_t *px;
	int w, h;
} view;

static uint32_t at(view im, int x, int y)
{
	if (x < 0 || y < 0 || x >= im.w || y >= im.h)
		return 0xFFFFFFFFu;
	const uint8_t *p = im.px + 3 * ((size_t)y * im.w + x);
	return (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
}

/* The colour at world point (BX + x, BY + y); reports it when it is not
 * `want`. */
static uint32_t world_at(view im, const evo_view_camera *cam, double x,
			 double y)
{
	double sx, sy;
	evo_view_to_screen(cam, BX + x, BY + y, &sx, &sy);
	return at(im, (int)floor(sx), (int)floor(sy));
}

static int world_is(view im, const evo_view_camera *cam, double x, double y,
		    uint32_t want, const char *what)
{
	double sx, sy;
	evo_view_to_screen(cam, BX + x, BY + y, &sx, &sy);
	uint32_t got = world_at(im, cam, x, y);
	if (got != want)
		printf("    %s at (%g, %g) -> pixel (%d, %d): 0x%06X, want "
		       "0x%06X\n",
		       what, x, y, (int)floor(sx), (int)floor(sy), got, want);
	return got == want;
}

static int count(view im, int x0, int y0, int x1, int y1, uint32_t rgb)
{
	int n = 0;
	for (int y = y0; y < y1; y++)
		for (int x = x0; x < x1; x++)
			n += at(im, x, y) == rgb;
	return n;
}

/* Everything the viewer must show, at its place: what both the window
 * and the windowless tests check. */
static void check_frame(view im, const evo_scene *sc,
			const evo_view_camera *cam)
{
	/* The bot, behind its centre (the heading line runs ahead). */
	CHECK(world_is(im, cam, -0.5, 0.3, EVO_VIEW_BOT, "bot"));
	CHECK(world_is(im, cam, 0.1, 0.6, EVO_VIEW_BOT, "bot"));
	/* Its heading: white from the centre towards +x. */
	CHECK(world_is(im, cam, 0.6, 0, EVO_VIEW_HEADING, "heading"));
	/* The obstacles: the cylinder (beside where the rays end) and
	 * the turned box, at its centre and at a point of its long side
	 * that only the turn brings in. */
	CHECK(world_is(im, cam, 6.4, 0.8, EVO_VIEW_OBSTACLE, "cylinder"));
	CHECK(world_is(im, cam, -8, 5, EVO_VIEW_OBSTACLE, "box"));
	double c = cos(0.3), s = sin(0.3);
	CHECK(world_is(im, cam, -8 + 1.8 * c - 0.8 * s, 5 + 1.8 * s + 0.8 * c,
		       EVO_VIEW_OBSTACLE, "box corner"));
	/* ... and not where the box would be without its turn. */
	CHECK(world_at(im, cam, -8 + 1.8, 5 - 0.8) != EVO_VIEW_OBSTACLE);
	/* The front sensor's middle ray hits the cylinder: red halfway
	 * along, from the nose (x = 1) to the cylinder's edge (x = 4.5). */
	const evo_sensor *front = &sc->bot[0].sensor[0];
	CHECK(front->ray[4] > 0.28 && front->ray[4] < 0.30);
	CHECK(world_is(im, cam, 2.75, 0, EVO_VIEW_RAY_HIT, "hit ray"));
	/* No red past the hit point along the middle ray. */
	CHECK(world_at(im, cam, 5.0, 0) == EVO_VIEW_OBSTACLE);
	/* The back sensor sees nothing: a faint ray, its full length. */
	const evo_sensor *back = &sc->bot[0].sensor[1];
	CHECK(back->ray[4] == 1.0f);
	uint32_t faint = blend(EVO_VIEW_RAY_HIT, EVO_VIEW_BACKGROUND,
			       EVO_VIEW_RAY_CLEAR_ALPHA);
	CHECK(world_is(im, cam, -7, 0, faint, "clear ray"));
	CHECK(world_is(im, cam, -12.7, 0, faint, "clear ray's end"));
	CHECK(world_is(im, cam, -13.5, 0, EVO_VIEW_BACKGROUND, "past it"));
	/* The zone, translucent green; the object, orange. */
	CHECK(world_is(
	    im, cam, 1.3, -8.4,
	    blend(EVO_VIEW_ZONE, EVO_VIEW_BACKGROUND, EVO_VIEW_ZONE_ALPHA),
	    "zone"));
	CHECK(world_is(im, cam, -6, -4, EVO_VIEW_OBJECT, "object"));
	CHECK(world_is(im, cam, 5, 9, EVO_VIEW_BACKGROUND, "background"));
}

/* The panel: text, a bar per skill (the first full, the second a
 * quarter, the third empty), the paused state. */
static void check_panel(view im, const evo_view_camera *cam)
{
	int x0 = cam->world_w;
	CHECK(x0 > im.w / 2 && x0 < im.w);
	CHECK(at(im, x0 + 2, im.h / 2) == EVO_VIEW_PANEL ||
	      at(im, x0 + 2, im.h / 2) == EVO_VIEW_TEXT);
	CHECK(count(im, x0, 0, im.w, im.h, EVO_VIEW_TEXT) > 500);
	CHECK(count(im, x0, 0, im.w, im.h, 0xFFC23D) > 20); /* PAUSED */
	/* Bar rows: the longest run of bar colour in each row, grouped. */
	int full = 0, quarter = 0, rows = 0;
	for (int y = 0; y < im.h; y++) {
		int n = count(im, x0, y, im.w, y + 1, EVO_VIEW_BAR);
		if (n > 0)
			rows++;
		if (n > 150)
			full++;
		else if (n > 30 && n < 80)
			quarter++;
	}
	CHECK(full >= 5);
	CHECK(quarter >= 5);
	CHECK(rows == full + quarter);
}

TEST(render_draws_the_scene_without_a_window)
{
	evo_scene *sc = make_scene();
	CHECK(sc != NULL);
	if (!sc)
		return;
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 900, 640, &err), 0);
	evo_viewer_panel p = make_panel();
	evo_view_camera cam = evo_view_camera_for(sc, 0, 1.5, im.w, im.h);
	CHECK_EQ_INT(cam.world_w, 900 - EVO_VIEW_PANEL_W);
	CHECK(fabs(cam.scale - 1.5 * 636 / 60.0) < 1e-9);
	CHECK(fabs(cam.x - BX) < 1e-6 && fabs(cam.y - BY) < 1e-6);
	evo_view_render(&im, sc, &cam, &p);
	view v = {im.pixels, im.w, im.h};
	check_frame(v, sc, &cam);
	check_panel(v, &cam);

	/* A claw holding the object: drawn over the bot, ringed. */
	sc->bot[0].actuator[0].held = OBJECT;
	sc->element[OBJECT].held_by = 0;
	evo_view_render(&im, sc, &cam, &p);
	CHECK(count(v, 0, 0, cam.world_w, im.h, EVO_VIEW_HELD) > 20);
	/* Delivered: only a faint outline is left. */
	sc->bot[0].actuator[0].held = -1;
	sc->element[OBJECT].held_by = -1;
	sc->element[OBJECT].active = 0;
	evo_view_render(&im, sc, &cam, &p);
	CHECK(count(v, 0, 0, cam.world_w, im.h, EVO_VIEW_OBJECT) == 0);
	CHECK(count(v, 0, 0, cam.world_w, im.h, EVO_VIEW_HELD) == 0);

	/* Following no bot looks at the middle of the scene; a narrow
	 * frame keeps a third for the panel; far-off zoom draws without
	 * trouble. */
	cam = evo_view_camera_for(sc, -1, 1, im.w, im.h);
	CHECK(fabs(cam.x - (BX - 1)) < 1e-9 && fabs(cam.y - (BY - 2.5)) < 1e-9);
	cam = evo_view_camera_for(sc, 7, 1, 300, 200);
	CHECK_EQ_INT(cam.world_w, 200);
	cam = evo_view_camera_for(sc, 0, 1e-9, im.w, im.h);
	evo_view_render(&im, sc, &cam, NULL);
	cam = evo_view_camera_for(sc, 0, 1e9, im.w, im.h);
	evo_view_render(&im, sc, &cam, NULL);
	evo_raster_free(&im);
	evo_scene_destroy(sc);
}

/* ---- the mazes: walls and the bot's trail ----------------------------- */

TEST(walls_and_the_trail_are_drawn)
{
	/* A wall from (BX + 4, BY - 6) to (BX + 4, BY + 6); a trail from the
	 * bot's start 5 m up, then 3 m left. */
	evo_scene *sc = evo_scene_create();
	evo_bot_def b = evo_default_bot_def();
	b.x = BX;
	b.y = BY;
	evo_scene_add_bot(sc, &b);
	CHECK(evo_scene_add_wall(sc, BX + 4, BY - 6, BX + 4, BY + 6) >= 0);
	evo_scene_reset(sc, 1, 1);
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 900, 640, &err), 0);
	evo_view_camera cam = evo_view_camera_for(sc, 0, 1.5, im.w, im.h);
	view v = {im.pixels, im.w, im.h};
	evo_viewer_panel p = make_panel();
	evo_view_render(&im, sc, &cam, &p);
	CHECK(world_is(v, &cam, 4, 3.3, EVO_VIEW_WALL, "wall"));
	CHECK(world_is(v, &cam, 4.5, 3.3, EVO_VIEW_BACKGROUND, "beside it"));
	CHECK(world_is(v, &cam, 4, 6.5, EVO_VIEW_BACKGROUND, "past its end"));
	CHECK(count(v, 0, 0, cam.world_w, im.h, EVO_VIEW_TRAIL) == 0);
	const double tx[] = {BX, BX, BX - 3}, ty[] = {BY, BY - 5, BY - 5};
	p.n_trail = 3;
	p.trail_x = tx;
	p.trail_y = ty;
	evo_view_render(&im, sc, &cam, &p);
	CHECK(world_is(v, &cam, 0, -3.3, EVO_VIEW_TRAIL, "trail going up"));
	CHECK(world_is(v, &cam, -1.7, -5, EVO_VIEW_TRAIL, "trail going left"));
	CHECK(world_is(v, &cam, -1.7, -3.3, EVO_VIEW_BACKGROUND, "off it"));
	evo_raster_free(&im);
	evo_scene_destroy(sc);
}

/* ---- teams (docs/teams.md) ------------------------------------------ */

/* Three bots: team 0 at (0, 0), team 1 at (6, 0), no team at (-6, 0). */
static evo_scene *team_scene(void)
{
	evo_scene *sc = evo_scene_create();
	static const struct {
		int team;
		double x;
		const char *name;
	} bots[] = {{0, 0, "Red1"}, {1, 6, "Blue1"}, {-1, -6, "loner"}};
	for (int i = 0; i < 3; i++) {
		evo_bot_def b = evo_default_bot_def();
		b.team = bots[i].team;
		b.x = bots[i].x;
		b.name = bots[i].name;
		if (evo_scene_add_bot(sc, &b) != i) {
			evo_scene_destroy(sc);
			return NULL;
		}
	}
	evo_scene_reset(sc, 1, 1);
	return sc;
}

TEST(teams_are_coloured_and_the_selected_bot_shown)
{
	CHECK(evo_view_team_colour(-1) == EVO_VIEW_BOT);
	for (int a = 0; a < EVO_SCENE_MAX_TEAMS; a++)
		for (int b = a + 1; b < EVO_SCENE_MAX_TEAMS; b++)
			CHECK(evo_view_team_colour(a) !=
			      evo_view_team_colour(b));
	evo_scene *sc = team_scene();
	CHECK(sc != NULL);
	if (!sc)
		return;
	/* a point on a bot or within half a metre of it finds it */
	CHECK_EQ_INT(evo_view_bot_at(sc, 6.2, 0.3), 1);
	CHECK_EQ_INT(evo_view_bot_at(sc, 0, 1.4), 0);
	CHECK_EQ_INT(evo_view_bot_at(sc, 3, 0), -1);
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 900, 640, &err), 0);
	static const char *const teams[] = {"Red", "Blue"};
	static const double rewards[] = {3, 4};
	static const char *const sn[] = {"S1", "S2"};
	static const double sv[] = {0.25, 1};
	static const char *const an[] = {"MotL"};
	static const double av[] = {0.75};
	evo_viewer_panel p = make_panel();
	p.paused = 0;
	p.n_teams = 2;
	p.team_name = teams;
	p.team_reward = rewards;
	p.bot_name = "Blue1";
	p.bot = 1;
	p.bot_team = "Blue";
	p.sensors.n = 2;
	p.sensors.name = sn;
	p.sensors.value = sv;
	p.actuators.n = 1;
	p.actuators.name = an;
	p.actuators.value = av;
	evo_view_camera cam = evo_view_camera_for(sc, -1, 1, im.w, im.h);
	evo_view_render(&im, sc, &cam, &p);
	view v = {im.pixels, im.w, im.h};
	double sx, sy;
	evo_view_to_screen(&cam, -0.5, 0.3, &sx, &sy);
	CHECK(at(v, (int)sx, (int)sy) == evo_view_team_colour(0));
	evo_view_to_screen(&cam, 5.5, 0.3, &sx, &sy);
	CHECK(at(v, (int)sx, (int)sy) == evo_view_team_colour(1));
	evo_view_to_screen(&cam, -6.5, 0.3, &sx, &sy);
	CHECK(at(v, (int)sx, (int)sy) == EVO_VIEW_BOT);
	/* the selected bot is ringed, in the world only */
	CHECK(count(v, 0, 0, cam.world_w, im.h, EVO_VIEW_SELECTED) > 20);
	evo_view_to_screen(&cam, 6, 0, &sx, &sy);
	CHECK(count(v, (int)sx - 20, (int)sy - 20, (int)sx + 20, (int)sy + 20,
		    EVO_VIEW_SELECTED) > 20);
	/* the panel: both swatches, its name, its sensor and actuator bars */
	int x0 = cam.world_w;
	CHECK(count(v, x0, 0, im.w, im.h, evo_view_team_colour(0)) >= 81);
	CHECK(count(v, x0, 0, im.w, im.h, evo_view_team_colour(1)) >= 81);
	CHECK(count(v, x0, 0, im.w, im.h, EVO_VIEW_SELECTED) > 20);
	CHECK(count(v, x0, 0, im.w, im.h, EVO_VIEW_SENSOR_BAR) > 100);
	CHECK(count(v, x0, 0, im.w, im.h, EVO_VIEW_ACTUATOR_BAR) > 50);
	/* nothing selected: no ring, no bars */
	p.bot_name = NULL;
	evo_view_render(&im, sc, &cam, &p);
	CHECK(count(v, 0, 0, im.w, im.h, EVO_VIEW_SELECTED) == 0);
	CHECK(count(v, x0, 0, im.w, im.h, EVO_VIEW_SENSOR_BAR) == 0);
	evo_raster_free(&im);
	evo_scene_destroy(sc);
}

/* ---- a remote robot's frame (DEMOREMOTE) ------------------------------ */

/* Every sensor at s, every actuator at a, every skill at k, drawn into im. */
static void render_remote(evo_raster *im, double s, double a, double k,
			  evo_view_link link, int n_sensors)
{
	static const char *names[40] = {"S1", "S2", "S3", "S4", "S5", "S6",
					"S7", "S8", "S9", "S10", "DOF"};
	double sv[40], av[2] = {a, a}, kv[3] = {k, k, k};
	for (int i = 0; i < 40; i++)
		sv[i] = s;
	evo_view_remote p = {
	    .title = "Avoid-ROBOT.simbatch",
	    .remote = "bot-1",
	    .period_ms = 33.333,
	    .link = link,
	    .quiet = 2.5,
	    .episode = 1,
	    .tick = 1234,
	    .reward = 56.5,
	    .in_time = 1230,
	    .late = 3,
	    .missing = 1,
	    .sensors.n = n_sensors,
	    .sensors.name = names,
	    .sensors.value = sv,
	    .actuators.n = 2,
	    .actuators.name = names,
	    .actuators.value = av,
	    .influence.n = 3,
	    .influence.name = names,
	    .influence.value = kv,
	};
	evo_view_render_remote(im, &p);
}

/* With no world to draw, the frame is the panel: the link's state in its
 * colour, and one bar per sensor, actuator and skill, as long as its
 * value. */
TEST(remote_frame_shows_values_and_the_link_without_a_window)
{
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 1024, 720, &err), 0);
	view v = {im.pixels, im.w, im.h};
	render_remote(&im, 0.25, 0.25, 0.25, EVO_VIEW_LINK_LIVE, 11);
	int s1 = count(v, 0, 0, im.w, im.h, EVO_VIEW_SENSOR_BAR);
	int a1 = count(v, 0, 0, im.w, im.h, EVO_VIEW_ACTUATOR_BAR);
	int k1 = count(v, 0, 0, im.w, im.h, EVO_VIEW_BAR);
	CHECK(count(v, 0, 0, im.w, im.h, EVO_VIEW_LINK_OK) > 100);
	CHECK_EQ_INT(count(v, 0, 0, im.w, im.h, EVO_VIEW_LINK_BAD), 0);
	render_remote(&im, 0.75, 0.75, 0.75, EVO_VIEW_LINK_SILENT, 11);
	int s3 = count(v, 0, 0, im.w, im.h, EVO_VIEW_SENSOR_BAR);
	int a3 = count(v, 0, 0, im.w, im.h, EVO_VIEW_ACTUATOR_BAR);
	int k3 = count(v, 0, 0, im.w, im.h, EVO_VIEW_BAR);
	CHECK(count(v, 0, 0, im.w, im.h, EVO_VIEW_LINK_BAD) > 100);
	CHECK_EQ_INT(count(v, 0, 0, im.w, im.h, EVO_VIEW_LINK_OK), 0);
	/* three times the value, three times the bar (to a pixel a row;
	 * the actuators' mark at neutral takes one column from each) */
	CHECK(s1 > 11 * 9 * 10);
	CHECK(abs(s3 - 3 * s1) <= 11 * 9 * 3);
	CHECK(a1 > 0 && abs(a3 - 3 * a1) <= 2 * 11 * 3);
	CHECK(k1 > 0 && abs(k3 - 3 * k1) <= 3 * 9 * 3);
	/* values out of [0, 1] are clamped: nothing below 0, full at 1 */
	render_remote(&im, -1, 2, NAN, EVO_VIEW_LINK_QUIET, 11);
	CHECK_EQ_INT(count(v, 0, 0, im.w, im.h, EVO_VIEW_SENSOR_BAR), 0);
	CHECK(count(v, 0, 0, im.w, im.h, EVO_VIEW_ACTUATOR_BAR) > a3);
	CHECK_EQ_INT(count(v, 0, 0, im.w, im.h, EVO_VIEW_BAR), 0);
	CHECK(count(v, 0, 0, im.w, im.h, EVO_VIEW_LINK_WARN) > 100);
	/* more sensors than fit: the rows that fit, and a note; a tiny
	 * frame and no data at all draw without trouble */
	render_remote(&im, 1, 1, 1, EVO_VIEW_LINK_WAITING, 40);
	CHECK(count(v, 0, 0, im.w, im.h, EVO_VIEW_SENSOR_BAR) >
	      count(v, 0, 0, im.w, im.h, EVO_VIEW_ACTUATOR_BAR));
	evo_view_render_remote(&im, NULL);
	evo_raster_free(&im);
	CHECK_EQ_INT(evo_raster_init(&im, 60, 40, &err), 0);
	render_remote(&im, 1, 1, 1, EVO_VIEW_LINK_ENDED, 11);
	evo_raster_free(&im);
}

/* ---- a display ------------------------------------------------------- */

static pid_t xvfb_pid = -1;
static char xvfb_log[64];

/* Start Xvfb on a display it picks and point DISPLAY at it. Returns 0,
 * or -1 with why filled. */
static int start_xvfb(char *why, size_t n)
{
	int fds[2];
	if (pipe(fds)) {
		snprintf(why, n, "pipe: %s", strerror(errno));
		return -1;
	}
	snprintf(xvfb_log, sizeof xvfb_log, "%s/evo-test-xvfb-%ld.log",
		 cli_tmp_root(), (long)getpid());
	pid_t pid = fork();
	if (pid < 0) {
		snprintf(why, n, "fork: %s", strerror(errno));
		close(fds[0]);
		close(fds[1]);
		return -1;
	}
	if (pid == 0) {
		/* Xvfb goes when the test goes, even if it crashes. */
		prctl(PR_SET_PDEATHSIG, SIGTERM);
		close(fds[0]);
		int log = open(xvfb_log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
		if (log >= 0) {
			dup2(log, 1);
			dup2(log, 2);
			close(log);
		}
		char fd[16];
		snprintf(fd, sizeof fd, "%d", fds[1]);
		/* -noreset: by default the server resets when its last
		 * client leaves and refuses connections meanwhile, which
		 * fails the next window a test opens. */
		execlp("Xvfb", "Xvfb", "-displayfd", fd, "-screen", "0",
		       "1024x768x24", "-nolisten", "tcp", "-noreset",
		       (char *)NULL);
		fprintf(stderr, "cannot run Xvfb: %s\n", strerror(errno));
		_exit(127);
	}
	close(fds[1]);
	xvfb_pid = pid;
	/* Xvfb writes the display number and a newline once it accepts
	 * connections; 20 s is plenty even under sanitizers. */
	char buf[32];
	size_t got = 0;
	while (got < sizeof buf - 1 && !memchr(buf, '\n', got)) {
		struct pollfd pf = {fds[0], POLLIN, 0};
		int r = poll(&pf, 1, 20000);
		if (r <= 0)
			break;
		ssize_t k = read(fds[0], buf + got, sizeof buf - 1 - got);
		if (k <= 0)
			break;
		got += (size_t)k;
	}
	close(fds[0]);
	buf[got] = 0;
	char *end;
	long display = strtol(buf, &end, 10);
	if (got == 0 || end == buf || *end != '\n' || display < 0) {
		char tail[200] = "";
		FILE *f = fopen(xvfb_log, "r");
		if (f) {
			size_t k = fread(tail, 1, sizeof tail - 1, f);
			tail[k] = 0;
			fclose(f);
		}
		snprintf(why, n,
			 "Xvfb did not report a display (is the xvfb package "
			 "installed?); its output: %s",
			 tail);
		return -1;
	}
	char name[32];
	snprintf(name, sizeof name, ":%ld", display);
	setenv("DISPLAY", name, 1);
	return 0;
}

static void stop_xvfb(void)
{
	if (xvfb_pid > 0) {
		kill(xvfb_pid, SIGTERM);
		waitpid(xvfb_pid, NULL, 0);
		xvfb_pid = -1;
		unlink(xvfb_log);
	}
}

static int have_display;
static char display_why[512];

/* Without a display the viewer says so instead of crashing: the evo
 * command then runs headless. */
TEST(no_display_is_a_clear_error)
{
	char *saved = getenv("DISPLAY") ? strdup(getenv("DISPLAY")) : NULL;
	setenv("DISPLAY", "", 1);
	evo_err err = {{0}};
	evo_viewer *v = evo_viewer_open(320, 200, &err);
	CHECK(v == NULL);
	CHECK_CONTAINS(err.msg, "cannot open the viewer");
	evo_viewer_close(v);
	if (saved)
		setenv("DISPLAY", saved, 1);
	else
		unsetenv("DISPLAY");
	free(saved);
}

TEST(viewer_under_x_draws_robot_obstacles_and_rays)
{
	if (!have_display) {
		printf("    no X display: %s\n", display_why);
		CHECK(have_display);
		return;
	}
	evo_scene *sc = make_scene();
	CHECK(sc != NULL);
	if (!sc)
		return;
	evo_err err;
	evo_viewer *v = evo_viewer_open(800, 600, &err);
	if (!v)
		printf("    %s\n", err.msg);
	CHECK(v != NULL);
	if (!v) {
		evo_scene_destroy(sc);
		return;
	}
	char dir[512], path[600];
	snprintf(dir, sizeof dir, "%s/evo-test-viewer-XXXXXX", cli_tmp_root());
	CHECK(mkdtemp(dir) != NULL);
	snprintf(path, sizeof path, "%s/shot.png", dir);
	CHECK_EQ_INT(evo_viewer_screenshot(v, path, &err), -1);
	CHECK_CONTAINS(err.msg, "no frame drawn yet");

	evo_viewer_panel p = make_panel();
	evo_viewer_zoom(v, 2);
	evo_viewer_draw(v, sc, 0, &p);
	int rc = evo_viewer_screenshot(v, path, &err);
	if (rc)
		printf("    %s\n", err.msg);
	CHECK_EQ_INT(rc, 0);
	evo_png_image img;
	rc = evo_png_read(path, &img, &err);
	if (rc)
		printf("    %s\n", err.msg);
	CHECK_EQ_INT(rc, 0);
	evo_view_camera cam = evo_viewer_camera(v);
	if (rc == 0) {
		CHECK_EQ_INT(img.w, 800);
		CHECK_EQ_INT(img.h, 600);
		CHECK_EQ_INT(img.channels, 3);
		CHECK(fabs(cam.scale - 2 * 536 / 60.0) < 1e-9);
		view shot = {img.pixels, img.w, img.h};
		check_frame(shot, sc, &cam);
		check_panel(shot, &cam);
		/* What the window shows is the frame evo drew, pixel for
		 * pixel: the same scene rendered off screen matches. */
		evo_raster ref;
		CHECK_EQ_INT(evo_raster_init(&ref, 800, 600, &err), 0);
		evo_view_render(&ref, sc, &cam, &p);
		CHECK(memcmp(ref.pixels, img.pixels, 800 * 600 * 3) == 0);
		evo_raster_free(&ref);
		evo_png_image_free(&img);
	}
	unlink(path);
	rmdir(dir);

	/* The camera follows the bot where it goes. */
	evo_scene_place_bot(sc, 0, 3, 2, 1.0);
	evo_scene_sense(sc);
	evo_viewer_draw(v, sc, 0, NULL);
	evo_view_camera after = evo_viewer_camera(v);
	CHECK(fabs(after.x - 3) < 1e-6 && fabs(after.y - 2) < 1e-6);
	evo_viewer_close(v);
	evo_scene_destroy(sc);
}

/* The next action within a few polls: SDL 2.24+ ends each poll round at
 * a sentinel it queues when it pumps, so an event pushed after a round
 * comes out one poll later (a frame later in the calling loop). */
static evo_view_action next_action(evo_viewer *v)
{
	for (int k = 0; k < 4; k++) {
		evo_view_action a = evo_viewer_poll(v);
		if (a != EVO_VIEW_NONE)
			return a;
	}
	return EVO_VIEW_NONE;
}

static void push_key(SDL_Keycode key, int repeat)
{
	SDL_Event ev;
	memset(&ev, 0, sizeof ev);
	ev.type = SDL_KEYDOWN;
	ev.key.state = SDL_PRESSED;
	ev.key.repeat = (Uint8)repeat;
	ev.key.keysym.sym = key;
	SDL_PushEvent(&ev);
}

TEST(keys_become_actions)
{
	if (!have_display) {
		CHECK(have_display);
		return;
	}
	evo_err err;
	evo_viewer *v = evo_viewer_open(320, 240, &err);
	if (!v)
		printf("    %s\n", err.msg);
	CHECK(v != NULL);
	if (!v)
		return;
	/* Whatever the window manager queued at opening goes first. */
	while (next_action(v) != EVO_VIEW_NONE)
		;
	static const struct {
		SDL_Keycode key;
		int repeat;
		evo_view_action want;
	} keys[] = {
	    {SDLK_SPACE, 0, EVO_VIEW_PAUSE},
	    {SDLK_n, 0, EVO_VIEW_STEP},
	    {SDLK_RIGHT, 1, EVO_VIEW_STEP},
	    {SDLK_UP, 0, EVO_VIEW_FASTER},
	    {SDLK_RIGHTBRACKET, 0, EVO_VIEW_FASTER},
	    {SDLK_DOWN, 0, EVO_VIEW_SLOWER},
	    {SDLK_LEFTBRACKET, 0, EVO_VIEW_SLOWER},
	    {SDLK_r, 0, EVO_VIEW_RESET},
	    {SDLK_s, 0, EVO_VIEW_SCREENSHOT},
	    {SDLK_TAB, 0, EVO_VIEW_NEXT_BOT},
	    {SDLK_c, 0, EVO_VIEW_CAMERA},
	    {SDLK_q, 0, EVO_VIEW_QUIT},
	    {SDLK_ESCAPE, 0, EVO_VIEW_QUIT},
	};
	for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
		push_key(keys[k].key, keys[k].repeat);
		CHECK_EQ_INT(next_action(v), keys[k].want);
	}
	/* A held space bar does not toggle the pause again and again, nor
	 * do zoom keys reach the caller. */
	push_key(SDLK_SPACE, 1);
	push_key(SDLK_PLUS, 0);
	push_key(SDLK_x, 0);
	CHECK_EQ_INT(next_action(v), EVO_VIEW_NONE);
	evo_scene *sc = make_scene();
	if (sc) {
		evo_viewer_draw(v, sc, 0, NULL);
		double s1 = evo_viewer_camera(v).scale;
		push_key(SDLK_MINUS, 0);
		CHECK_EQ_INT(next_action(v), EVO_VIEW_NONE);
		evo_viewer_draw(v, sc, 0, NULL);
		CHECK(fabs(evo_viewer_camera(v).scale - s1 * 0.8) < 1e-9);
		evo_scene_destroy(sc);
	}
	SDL_Event quit;
	memset(&quit, 0, sizeof quit);
	quit.type = SDL_QUIT;
	SDL_PushEvent(&quit);
	CHECK_EQ_INT(next_action(v), EVO_VIEW_QUIT);
	CHECK_EQ_INT(next_action(v), EVO_VIEW_NONE);
	evo_viewer_close(v);
}

static void push_mouse(Uint32 type, int x, int y, int xrel, int yrel)
{
	SDL_Event ev;
	memset(&ev, 0, sizeof ev);
	ev.type = type;
	if (type == SDL_MOUSEMOTION) {
		ev.motion.x = x;
		ev.motion.y = y;
		ev.motion.xrel = xrel;
		ev.motion.yrel = yrel;
		ev.motion.state = SDL_BUTTON_LMASK;
	} else {
		ev.button.button = SDL_BUTTON_LEFT;
		ev.button.state =
		    type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
		ev.button.x = x;
		ev.button.y = y;
	}
	SDL_PushEvent(&ev);
}

/* A click on a bot selects it (where it fell, in the world); a drag frees
 * the camera and moves it with the mouse. */
TEST(the_mouse_selects_bots_and_drags_the_free_camera)
{
	if (!have_display) {
		CHECK(have_display);
		return;
	}
	evo_err err;
	evo_viewer *v = evo_viewer_open(640, 480, &err);
	CHECK(v != NULL);
	evo_scene *sc = team_scene();
	CHECK(sc != NULL);
	if (!v || !sc) {
		evo_viewer_close(v);
		evo_scene_destroy(sc);
		return;
	}
	while (next_action(v) != EVO_VIEW_NONE)
		;
	evo_viewer_draw(v, sc, -1, NULL);
	evo_view_camera cam = evo_viewer_camera(v);
	double sx, sy;
	evo_view_to_screen(&cam, 6, 0, &sx, &sy);
	push_mouse(SDL_MOUSEBUTTONDOWN, (int)sx, (int)sy, 0, 0);
	push_mouse(SDL_MOUSEBUTTONUP, (int)sx, (int)sy, 0, 0);
	CHECK_EQ_INT(next_action(v), EVO_VIEW_SELECT);
	double x, y;
	evo_viewer_clicked(v, &x, &y);
	CHECK(fabs(x - 6) < 0.2 && fabs(y) < 0.2);
	CHECK_EQ_INT(evo_view_bot_at(sc, x, y), 1);
	/* a drag of 50 pixels to the right moves the view 50 pixels left */
	push_mouse(SDL_MOUSEBUTTONDOWN, 100, 100, 0, 0);
	push_mouse(SDL_MOUSEMOTION, 120, 100, 20, 0);
	push_mouse(SDL_MOUSEMOTION, 150, 100, 30, 0);
	push_mouse(SDL_MOUSEBUTTONUP, 150, 100, 0, 0);
	CHECK_EQ_INT(next_action(v), EVO_VIEW_FREE);
	CHECK_EQ_INT(next_action(v), EVO_VIEW_NONE);
	evo_viewer_draw(v, sc, -1, NULL);
	evo_view_camera moved = evo_viewer_camera(v);
	CHECK(fabs(moved.x - (cam.x - 50 / cam.scale)) < 1e-9);
	CHECK(fabs(moved.y - cam.y) < 1e-9);
	/* following a bot, then free again: the camera stays where the bot
	 * was */
	evo_viewer_draw(v, sc, 1, NULL);
	evo_viewer_draw(v, sc, -1, NULL);
	CHECK(fabs(evo_viewer_camera(v).x - 6) < 1e-6);
	evo_viewer_look_at(v, -6, 0);
	evo_viewer_draw(v, sc, -1, NULL);
	CHECK(fabs(evo_viewer_camera(v).x + 6) < 1e-9);
	evo_viewer_close(v);
	evo_scene_destroy(sc);
}

/* A headless run never loads SDL2 (some fifty libraries, the larger part
 * of the start of a short `evo run`): the drawing without a window did
 * not load it; opening a window loads it, once. */
TEST(sdl_is_loaded_only_when_a_window_opens)
{
	CHECK(dlopen(EVO_SDL_LIB, RTLD_LAZY | RTLD_NOLOAD) == NULL);
	CHECK(dlopen(EVO_GL_LIB, RTLD_LAZY | RTLD_NOLOAD) == NULL);
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_sdl_load(0, "the viewer", &err), 0);
	void *h = dlopen(EVO_SDL_LIB, RTLD_LAZY | RTLD_NOLOAD);
	CHECK(h != NULL);
	if (h)
		dlclose(h);
	/* OpenGL only for the 3D view */
	CHECK(dlopen(EVO_GL_LIB, RTLD_LAZY | RTLD_NOLOAD) == NULL);
	CHECK_EQ_INT(evo_sdl_load(0, "the viewer", &err), 0);
}

/* SDL loads libX11 and its kin with dlopen and unloads them when the
 * viewer closes; what they leak is then reported from an "<unknown
 * module>" that no suppression can name. Held here for the life of the
 * process, they keep their names and tests/lsan.supp matches them; the
 * leaks of evo's own code are still reported. */
static void keep_x_libraries_loaded(void)
{
	static const char *const libs[] = {
	    "libX11.so.6",     "libX11-xcb.so.1", "libXext.so.6",
	    "libXcursor.so.1", "libXi.so.6",	  "libXfixes.so.3",
	    "libXrandr.so.2",  "libXss.so.1",	  "libxkbcommon.so.0"};
	for (size_t k = 0; k < sizeof libs / sizeof libs[0]; k++)
		dlopen(libs[k], RTLD_NOW | RTLD_GLOBAL | RTLD_NODELETE);
}

int main(void)
{
	keep_x_libraries_loaded();
	/* X11 only: the test is about X (Xvfb); a Wayland session must not
	 * pick another backend. */
	setenv("SDL_VIDEODRIVER", "x11", 1);
	RUN(render_draws_the_scene_without_a_window);
	RUN(walls_and_the_trail_are_drawn);
	RUN(teams_are_coloured_and_the_selected_bot_shown);
	RUN(remote_frame_shows_values_and_the_link_without_a_window);
	RUN(sdl_is_loaded_only_when_a_window_opens);
	RUN(no_display_is_a_clear_error);
	const char *d = getenv("DISPLAY");
	if (d && *d)
		have_display = 1;
	else
		have_display = start_xvfb(display_why, sizeof display_why) == 0;
	RUN(viewer_under_x_draws_robot_obstacles_and_rays);
	RUN(keys_become_actions);
	RUN(the_mouse_selects_bots_and_drags_the_free_camera);
	stop_xvfb();
	return test_summary();
}
