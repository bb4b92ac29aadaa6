/* One Lua binding for both worlds (sim/lua/lua_scene.c, lua_bot.c,
 * lua_element.c over lua_dim2d.c and lua_dim3d.c; docs/lua.md, "Which
 * world has what"): one environment script, written once, builds a 2D
 * and a 3D scene and reads the same figures from both: a bot's pose and
 * position, its mind's last command, its counts, an element's state, the
 * bots by number and the layout stream, which before were one world's
 * only. A kind that sim/scene/kinds.c's row gives to the other world is
 * refused at the script's line, naming the kind and the scene's world;
 * docs/lua.md's table of which world has what is kinds.c's rows. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/rng.h"
#include "harness.h"
#include "lua/lua_evo.h"
#include "scene/kinds.h"
#include "support/cli.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

#define NEAR(a, b, eps) (fabs((a) - (b)) <= (eps))

/* A 2D bot model and a 3D one, each with an actuator M and a tracker B. */
static const char *const model2d = "return { build = function(bot)\n"
				   "  bot:wheel{ name = 'M', y = 1 }\n"
				   "  bot:bearing{ name = 'B' }\n"
				   "end }\n";
static const char *const model3d =
    "return {\n"
    "  hull = { shape = 'sphere', radius = 0.25, mass = 2, z = 2,\n"
    "           buoyancy = 1 },\n"
    "  build = function(bot)\n"
    "    bot:propeller{ name = 'M', x = -0.25, axis = { 1, 0, 0 } }\n"
    "    bot:azimuth{ name = 'B' }\n"
    "  end,\n"
    "}\n";

/* The environment both worlds run: a bot at (1, 2) turned 90 degrees, a
 * zone; reset reports the bot's pose (its last value: the turn), its
 * position, the zone's state, the first bot by number and a draw of the
 * layout stream; post_step what the mind asked of M and the bot's
 * collisions. */
static const char *const env =
    "local e, b, z, m = {}, nil, nil, {}\n"
    "function e.init(scene)\n"
    "  z = scene:zone{ name = 'goal', x = 4, y = 0 }\n"
    "  b = scene:bot{ x = 1, y = 2, %s = 90 }\n"
    "  for _, k in ipairs{ 'x', 'y', 'turn', 'n', 'active', 'first',\n"
    "                      'layout', 'cmd', 'coll', 'tracked' } do\n"
    "    m[k] = scene:metric(k)\n"
    "  end\n"
    "end\n"
    "function e.reset(scene)\n"
    "  local p = { b:pose() }\n"
    "  local x, y = b:pos()\n"
    "  m.x:set(x) m.y:set(y) m.turn:set(p[#p]) m.n:set(#p)\n"
    "  m.active:set(z:active() and 1 or 0)\n"
    "  m.first:set(scene:get_bot(1):name() == b:name() and 1 or 0)\n"
    "  m.layout:set(scene:layout_random(10, 20))\n"
    "  b:target('B', z)\n"
    "  m.tracked:set(#b:sensors('bearing', 'untargeted'))\n"
    "end\n"
    "function e.post_step(scene)\n"
    "  m.cmd:set(b:command('M'))\n"
    "  m.coll:set(b:counts().collisions)\n"
    "end\n"
    "return e\n";

static double metric(const evo_metric *m, int n, const char *name)
{
	for (int i = 0; i < n; i++)
		if (strcmp(m[i].name, name) == 0)
			return m[i].value;
	return NAN;
}

/* The layout stream's first draw in [10, 20) for grid seed 7, as
 * docs/lua.md says it is made: the grid seed's stream "obs". */
static double layout_draw(void)
{
	evo_rng r = evo_rng_for(7, 0x6f6273, 0, 0);
	return evo_rng_range(&r, 10, 20);
}

/* The environment's lua text for a world: its bot's turn option. */
static void write_files(int three)
{
	char text[4096];
	snprintf(text, sizeof text, env, three ? "yaw" : "angle");
	cli_write(text, "%s/Envs/E.lua", cli_tmp);
	cli_write(three ? model3d : model2d, "%s/Bots/Mover.lua", cli_tmp);
}

/* Both figures a world gives after its reset and one step with M's
 * command at 0.8: x, y, turn, n values in the pose, zone active, first
 * bot, layout draw, M's command, collisions, untargeted trackers. */
static void check_figures(const evo_metric *m, int n, int coords)
{
	CHECK(NEAR(metric(m, n, "x"), 1, 1e-9));
	CHECK(NEAR(metric(m, n, "y"), 2, 1e-9));
	/* Box2D keeps a body's angle in single precision */
	CHECK(NEAR(metric(m, n, "turn"), 90, coords == 2 ? 1e-5 : 1e-9));
	CHECK_EQ_INT((int)metric(m, n, "n"), coords + 1);
	CHECK_EQ_INT((int)metric(m, n, "active"), 1);
	CHECK_EQ_INT((int)metric(m, n, "first"), 1);
	CHECK(metric(m, n, "layout") == layout_draw());
	CHECK(metric(m, n, "cmd") == 0.8);
	CHECK_EQ_INT((int)metric(m, n, "coll"), 0);
	CHECK_EQ_INT((int)metric(m, n, "tracked"), 0);
}

/* A scene of either world (three: 3D) and its Lua state, built by
 * Envs/E.lua with the bot model Mover. */
typedef struct world {
	evo_scene *sc;
	evo_scene3d *sc3;
	evo_lua *l;
} world;

/* The world's scene and state, its environment's init run; 0, or -1 with
 * err set. */
static int open_world(world *w, int three, evo_err *err)
{
	evo_scene3d_def d = evo_default_scene3d_def();
	w->sc = three ? NULL : evo_scene_create();
	w->sc3 = three ? evo_scene3d_create(&d) : NULL;
	evo_lua_def ld = {.scene = w->sc,
			  .scene3d = w->sc3,
			  .mind_dir = cli_tmp,
			  .botmodel = "Mover"};
	w->l = evo_lua_create(&ld, err);
	return w->l && !evo_lua_init_env(w->l, "E", err) ? 0 : -1;
}

static void close_world(world *w)
{
	evo_lua_destroy(w->l);
	if (w->sc)
		evo_scene_destroy(w->sc);
	if (w->sc3)
		evo_scene3d_destroy(w->sc3);
}

/* Reset (grid seed 7), one tick with M's command at 0.8; 0, or -1 with
 * err set. */
static int reset_and_step(world *w, evo_err *err)
{
	if (w->sc)
		evo_scene_reset(w->sc, 7, 1);
	else if (evo_scene3d_reset(w->sc3, 7, 1))
		return -1;
	if (evo_lua_reset(w->l, 1, err))
		return -1;
	if (w->sc) {
		evo_scene_sense(w->sc);
		w->sc->bot[0].actuator[0].command = 0.8;
		return evo_scene_step(w->sc);
	}
	evo_scene3d_sense(w->sc3);
	w->sc3->bot[0].actuator[0].command = 0.8;
	return evo_scene3d_step(w->sc3);
}

TEST(one_environment_reads_the_same_figures_in_both_worlds)
{
	for (int three = 0; three <= 1; three++) {
		write_files(three);
		world w;
		evo_err err = {{0}};
		int ok =
		    !open_world(&w, three, &err) && !reset_and_step(&w, &err);
		CHECK(ok);
		if (!ok)
			printf("  %s\n", err.msg);
		else if (three)
			check_figures(w.sc3->metric, w.sc3->n_metrics, 3);
		else
			check_figures(w.sc->metric, w.sc->n_metrics, 2);
		close_world(&w);
	}
}

/* An init body that must fail in the world given (three: 3D), and what
 * its message must say. */
static void refused(int three, const char *body, const char *said)
{
	char text[1024];
	snprintf(text, sizeof text,
		 "local e = {}\nfunction e.init(scene) %s end\nreturn e\n",
		 body);
	cli_write(text, "%s/Envs/E.lua", cli_tmp);
	cli_write(three ? model3d : model2d, "%s/Bots/Mover.lua", cli_tmp);
	world w;
	evo_err err = {{0}};
	CHECK(open_world(&w, three, &err) != 0);
	if (!strstr(err.msg, said))
		printf("  %s\n", err.msg);
	CHECK_CONTAINS(err.msg, said);
	close_world(&w);
}

/* The other world's kinds and elements' ways, each refused at its line. */
static void refusals(void)
{
	refused(1, "local b = scene:bot{} b:claw{ name = 'C' }",
		"E.lua:2: bot:claw: claw is 2D only, and this is a 3D scene");
	refused(1, "scene:wall{ x1 = 0, y1 = 0, x2 = 1, y2 = 0 }",
		"E.lua:2: scene:wall: wall is 2D only, and this is a 3D scene");
	refused(0, "local b = scene:bot{} b:propeller{ name = 'P' }",
		"E.lua:2: bot:propeller: propeller is 3D only, and this is a "
		"2D scene");
	refused(0, "scene:sphere{ x = 1 }",
		"E.lua:2: scene:sphere: sphere is 3D only, and this is a 2D "
		"scene");
	refused(0, "local b = scene:bot{} b:elevation{ name = 'E' }",
		"E.lua:2: bot:elevation: elevation is 3D only");
	/* a kind of both worlds takes each world's own options */
	refused(0, "scene:zone{ x = 1, hx = 2 }",
		"E.lua:2: scene:zone: unknown option 'hx'; did you mean x? "
		"(known: x, y, size, angle, name)");
	/* and what the other world's elements do */
	refused(1,
		"local b = scene:bot{} b:distance{ name = 'D', target = "
		"'nearest_object' }",
		"E.lua:2: bot:distance: target must be an element; "
		"\"nearest_object\" and the other nearest targets are 2D only, "
		"and this is a 3D scene");
}

/* docs/lua.md's table "Which world has what" is sim/scene/kinds.c's rows:
 * a line for each piece, sensor and actuator kind, "yes" or "—" in each
 * world's column as its row says, and no line for a kind it lacks. */
static void docs_table(void)
{
	FILE *f = fopen("docs/lua.md", "r");
	CHECK(f != NULL);
	if (!f)
		return;
	char line[512];
	int in_table = 0, rows = 0, bad = 0;
	while (fgets(line, sizeof line, f)) {
		if (strncmp(line, "## Which world has what", 23) == 0)
			in_table = 1;
		else if (strncmp(line, "## ", 3) == 0)
			in_table = 0;
		char cls[16], name[64], c2[16], c3[16];
		if (!in_table ||
		    sscanf(line, "| `%15[a-z]:%63[a-z_]` | %15s | %15s |", cls,
			   name, c2, c3) != 4)
			continue;
		int scene = strcmp(cls, "scene") == 0;
		const evo_kind_row *row = NULL;
		int k;
		if (scene && (k = evo_piece_kind_by_name(name)) >= 0)
			row = evo_piece_kind_row(k);
		else if (!scene && (k = evo_sense_kind_by_name(name)) >= 0)
			row = evo_sense_kind_row(k);
		else if (!scene && (k = evo_act_kind_by_name(name)) >= 0)
			row = evo_act_kind_row(k);
		unsigned dims = (strcmp(c2, "yes") == 0 ? EVO_DIM_2D : 0) |
				(strcmp(c3, "yes") == 0 ? EVO_DIM_3D : 0);
		if (!row || strcmp(row->name, name) != 0 || row->dims != dims) {
			printf(
			    "  docs/lua.md: %s:%s: %s %s, not kinds.c's row\n",
			    cls, name, c2, c3);
			bad++;
		}
		rows++;
	}
	fclose(f);
	CHECK_EQ_INT(bad, 0);
	CHECK_EQ_INT(rows, EVO_PIECE_KIND_COUNT + EVO_SENSE_KIND_COUNT +
			       EVO_ACT_KIND_COUNT);
}

TEST(a_kind_of_the_other_world_is_refused_as_the_docs_table_says)
{
	refusals();
	docs_table();
}

int main(void)
{
	if (cli_setup("luadims"))
		return 1;
	cli_sh("mkdir -p %s/Bots %s/Envs", cli_tmp, cli_tmp);
	RUN(one_environment_reads_the_same_figures_in_both_worlds);
	RUN(a_kind_of_the_other_world_is_refused_as_the_docs_table_says);
	cli_cleanup();
	return test_summary();
}
