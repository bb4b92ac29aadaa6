/* The 3D scene's Lua methods (sim/lua/lua_scene3d.c, docs/world3d.md): an
 * environment and a bot model written here build a 3D scene whose sensors
 * read what hand-worked placements say; every option table is checked by
 * key, and misplaced calls are refused with their line. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "lua/lua_evo.h"
#include "support/cli.h"
#include "world3d/scene3d.h"

#define NEAR(a, b, eps) (fabs((a) - (b)) <= (eps))

/* A bot model: a floating sphere with one sensor of each kind. */
static const char *const model =
    "return {\n"
    "  hull = { shape = 'sphere', radius = 0.25, mass = 2, z = 2,\n"
    "           buoyancy = 1 },\n"
    "  build = function(bot)\n"
    "    bot:proximity{ name = 'P', x = 0.25, range = 4 }\n"
    "    bot:target_sensor{ name = 'AZ', axis = 1 }\n"
    "    bot:target_sensor{ name = 'EL', axis = 2 }\n"
    "    bot:bearing{ name = 'BR' }\n"
    "    bot:distance{ name = 'D', scale = 10 }\n"
    "    bot:zone{ name = 'Z' }\n"
    "    bot:constant{ name = 'C', value = 0.3 }\n"
    "    bot:presence{ name = 'PR' }\n"
    "    bot:movement{ name = 'MV', scale = 2 }\n"
    "    bot:radar{ name = 'RD', yaw = 90, arc = 30 }\n"
    "    bot:propeller{ name = 'M', x = -0.25, axis = { 1, 0, 0 } }\n"
    "  end,\n"
    "}\n";

/* Scene and Lua state of environment `env` (text) with the model above;
 * NULL with err filled when it fails. */
static evo_lua *build(const char *env, evo_scene3d **sc, evo_err *err)
{
	cli_write(model, "%s/Bots/Floater.lua", cli_tmp);
	cli_write(env, "%s/Envs/E.lua", cli_tmp);
	evo_scene3d_def d = evo_default_scene3d_def();
	*sc = evo_scene3d_create(&d);
	evo_lua_def ld = {
	    .scene3d = *sc, .mind_dir = cli_tmp, .botmodel = "Floater"};
	evo_lua *l = evo_lua_create(&ld, err);
	if (l && (evo_lua_init_env(l, "E", err) ||
		  evo_scene3d_reset(*sc, 1, 1) || evo_lua_reset(l, 1, err))) {
		evo_lua_destroy(l);
		l = NULL;
	}
	if (!l) {
		evo_scene3d_destroy(*sc);
		*sc = NULL;
	}
	return l;
}

static double value(const evo_scene3d *sc, const char *name)
{
	const evo_bot *b = &sc->bot[0];
	int k = evo_bot_find_sensor(b, name);
	return k >= 0 ? b->sensor[k].value : -1;
}

/* A target up 3 and ahead 4, then moved by reset to the left; a box 2.25
 * ahead (its face 1.75 from the bot's centre, 1.5 from the ray's start);
 * a zone around the start. */
TEST(sensors_built_from_lua_read_hand_worked_values)
{
	const char *env =
	    "local e, t = {}\n"
	    "function e.init(scene)\n"
	    "  scene:physics{ substeps = 2 }\n"
	    "  t = scene:target{ name = 'goal', x = 4, y = 0, z = 5 }\n"
	    "  local z = scene:zone{ x = 0, y = 0, z = 2, hx = 1, hy = 1, "
	    "hz = 1 }\n"
	    "  scene:box{ x = 2.25, y = 0, z = 2, hx = 0.5, hy = 0.5, hz = 0.5 "
	    "}\n"
	    "  local b = scene:bot{}\n"
	    "  for _, s in ipairs{ 'AZ', 'EL', 'BR', 'D', 'RD' } do "
	    "b:target(s, t) end\n"
	    "  b:target('Z', z)\n"
	    "end\n"
	    "function e.reset(scene, episode)\n"
	    "  if episode == 2 then t:place{ x = 0, y = 3, z = 2 } end\n"
	    "  scene:obstacle{ shape = 'sphere', x = -3, y = 0, z = 2, "
	    "radius = scene:layout_random(0.2, 0.4) }\n"
	    "end\n"
	    "return e\n";
	evo_scene3d *sc;
	evo_err err = {{0}};
	evo_lua *l = build(env, &sc, &err);
	CHECK(l != NULL);
	if (!l) {
		printf("  %s\n", err.msg);
		return;
	}
	evo_scene3d_sense(sc);
	CHECK(NEAR(value(sc, "AZ"), 0.5, 1e-9));
	CHECK(NEAR(value(sc, "EL"), 0.5 + atan2(3, 4) / M_PI, 1e-9));
	CHECK(NEAR(value(sc, "BR"), 0.5, 1e-9));
	CHECK(NEAR(value(sc, "D"), 0.5, 1e-9));
	CHECK(value(sc, "RD") == EVO3D_FALSE); /* ahead: not in 60..120 */
	CHECK(NEAR(value(sc, "P"), 1.5 / 4, 1e-6));
	CHECK(value(sc, "Z") == EVO3D_TRUE);
	CHECK(NEAR(value(sc, "C"), 0.3, 1e-12));
	/* no target yet; a bot that has not moved; movement's own scale */
	CHECK(value(sc, "PR") == EVO3D_FALSE);
	CHECK(value(sc, "MV") == 0);
	{
		const evo_bot *b = &sc->bot[0];
		CHECK(b->sensor[evo_bot_find_sensor(b, "MV")].def.scale == 2);
	}
	CHECK_EQ_INT(sc->n_obstacles, 2); /* the box, and reset's sphere */
	/* episode 2: the target 3 to the left, level */
	CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 2), 0);
	CHECK_EQ_INT(evo_lua_reset(l, 2, &err), 0);
	evo_scene3d_sense(sc);
	CHECK(NEAR(value(sc, "AZ"), 0.75, 1e-9));
	CHECK(NEAR(value(sc, "EL"), 0.5, 1e-9));
	CHECK(value(sc, "RD") == EVO3D_TRUE); /* 90 to the left */
	CHECK(NEAR(value(sc, "D"), 0.3, 1e-9));
	CHECK_EQ_INT(sc->n_obstacles, 2); /* the last episode's is gone */
	evo_lua_destroy(l);
	evo_scene3d_destroy(sc);
}

/* The swarm sensors from Lua in 3D (docs/world3d.md): bot A at (0, 0, 2)
 * with a light of 10 at (4, 3, 2), 5 away and 36.9 degrees to its left
 * (10 / 25); a patch of grey 0.25 under it; bot B at (3, 4, 2), 5 away,
 * broadcasting its neutral 0.5. */
TEST(swarm_sensors_from_lua_read_hand_worked_values)
{
	const char *env = "local e = {}\n"
			  "function e.init(scene)\n"
			  "  scene:light{ x = 4, y = 3, z = 2, intensity = 10 }\n"
			  "  scene:patch{ x = 0, y = 0, radius = 1, grey = 0.25 }\n"
			  "  local a = scene:bot{}\n"
			  "  local b = scene:bot{ x = 3, y = 4 }\n"
			  "  a:light{ name = 'L' }\n"
			  "  a:ground{ name = 'G' }\n"
			  "  a:rab{ name = 'RR', range = 10 }\n"
			  "  a:rab{ name = 'RB', range = 10, read = 'bearing' }\n"
			  "  a:rab{ name = 'RV', range = 10, read = 'value' }\n"
			  "  b:broadcast{ name = 'TX' }\n"
			  "end\n"
			  "return e\n";
	evo_scene3d *sc;
	evo_err err = {{0}};
	evo_lua *l = build(env, &sc, &err);
	CHECK(l != NULL);
	if (!l) {
		printf("  %s\n", err.msg);
		return;
	}
	evo_scene3d_sense(sc);
	CHECK(NEAR(value(sc, "L"), 0.4, 1e-9));
	CHECK(NEAR(value(sc, "G"), 0.25, 1e-12));
	CHECK(NEAR(value(sc, "RR"), 0.5, 1e-9));
	CHECK(NEAR(value(sc, "RB"), 0.5 + atan2(4, 3) / (2 * M_PI), 1e-9));
	CHECK(NEAR(value(sc, "RV"), 0.5, 1e-12));
	evo_lua_destroy(l);
	evo_scene3d_destroy(sc);
}

/* element:set_active in 3D (docs/lua.md, "Elements"): episode 1 sees a
 * target 4 ahead (distance 4 / 10 = 0.4, a Distance reward of -1 per
 * metre pays -4), a zone around the bot (TRUE) and a ball object of
 * radius 0.5 at 2.25 ahead, whose near side is 1.5 from the proximity
 * ray's start at 0.25 (1.5 / 4). Episode 2's reset switches all three
 * off: the target is no one's (the distance sensor reads 1 as with no
 * target, the reward pays 0), the zone holds nothing (FALSE), presence
 * sensors on the target and the ball read FALSE, not TRUE, the ball
 * leaves the world (the ray reads clear, 1, and the ball does not fall
 * while the world steps). Episode 3 has them back: every reset switches
 * every element on. */
TEST(elements_set_off_in_3d_leave_sensors_rewards_and_the_world)
{
	const char *env =
	    "local e, t, z, o, m = {}\n"
	    "function e.init(scene)\n"
	    "  t = scene:target{ x = 4, y = 0, z = 2 }\n"
	    "  z = scene:zone{ x = 0, y = 0, z = 2, hx = 1, hy = 1, hz = 1 }\n"
	    "  o = scene:object{ x = 2.25, y = 0, z = 2, radius = 0.5 }\n"
	    "  local b = scene:bot{}\n"
	    "  b:target('D', t)\n"
	    "  b:target('Z', z)\n"
	    "  b:target('PR', t)\n"
	    "  b:presence{ name = 'PO', target = o }\n"
	    "  scene:reward('Distance', { bot = b, target = t, k = -1 })\n"
	    "  m = scene:metric('on')\n"
	    "end\n"
	    "function e.reset(scene, episode)\n"
	    "  if episode == 2 then\n"
	    "    for _, x in ipairs{ t, z, o } do x:set_active(false) end\n"
	    "  end\n"
	    "  m:set((t:active() and 1 or 0) + (z:active() and 2 or 0) +\n"
	    "        (o:active() and 4 or 0))\n"
	    "end\n"
	    "return e\n";
	evo_scene3d *sc;
	evo_err err = {{0}};
	evo_lua *l = build(env, &sc, &err);
	CHECK(l != NULL);
	if (!l) {
		printf("  %s\n", err.msg);
		return;
	}
	static const struct {
		double on, d, z, p, reward;
	} want[] = {{7, 0.4, EVO3D_TRUE, 1.5 / 4, -4},
		    {0, 1, EVO3D_FALSE, 1, 0},
		    {7, 0.4, EVO3D_TRUE, 1.5 / 4, -4}};
	for (int ep = 1; ep <= 3; ep++) {
		if (ep > 1) {
			CHECK_EQ_INT(evo_scene3d_reset(sc, 1, ep), 0);
			CHECK_EQ_INT(evo_lua_reset(l, ep, &err), 0);
		}
		const evo_element *ball = &sc->element[2];
		evo_scene3d_sense(sc);
		CHECK(NEAR(sc->metric[0].value, want[ep - 1].on, 0));
		CHECK(NEAR(value(sc, "D"), want[ep - 1].d, 1e-9));
		CHECK(value(sc, "Z") == want[ep - 1].z);
		CHECK(value(sc, "PR") == want[ep - 1].z); /* the target's */
		CHECK(value(sc, "PO") == want[ep - 1].z); /* the object's */
		CHECK(NEAR(value(sc, "P"), want[ep - 1].p, 1e-6));
		CHECK(evo_scene3d_step(sc) >= 0);
		CHECK(NEAR(sc->step_reward, want[ep - 1].reward, 1e-3));
		for (int i = 0; i < 10; i++)
			evo_scene3d_step(sc);
		/* 11 ticks of 1/30 s: a falling ball drops g t^2 / 2, 0.66 m */
		if (ep == 2)
			CHECK(ball->pos[2] == 2);
		else
			CHECK(ball->pos[2] < 1.5);
	}
	evo_lua_destroy(l);
	evo_scene3d_destroy(sc);
}

/* Each line is an environment's init body that must fail, and what its
 * message must say. */
TEST(bad_options_and_misplaced_calls_are_refused_at_their_line)
{
	static const char *const bad[][2] = {
	    {"scene:bot{ x = 0, hieght = 1 }",
	     "E.lua:2: scene:bot: unknown option 'hieght' (known: name, x, y, "
	     "z, yaw, model, team)"},
	    {"scene:box{ x = 0, size = 1 }",
	     "E.lua:2: scene:box: unknown option 'size' (known: name, x, y, "
	     "z, yaw, hx, hy, hz, friction, ground)"},
	    {"scene:cylinder{ radius = 0 }", "E.lua:2: a radius must be > 0"},
	    {"scene:obstacle{ shape = 'box' }",
	     "E.lua:2: scene:obstacle: an episode's obstacles are added in "
	     "the environment's reset"},
	    {"scene:bot{} scene:physics{ substeps = 3 }",
	     "E.lua:2: scene:physics: set the physics first"},
	    {"scene:physics{ substeps = 0 }",
	     "E.lua:2: scene:physics: substeps must be a whole number, 1 to "
	     "100"},
	    {"local b = scene:bot{} scene:reward('ClosingOnTraget', { bot = b "
	     "})",
	     "E.lua:2: scene:reward: unknown reward function "
	     "'ClosingOnTraget'; did you mean ClosingOnTarget?"},
	    {"local b = scene:bot{} scene:reward('Collect', { bot = b })",
	     "E.lua:2: scene:reward: reward 'Collect' is 2D only "
	     "(docs/world3d.md)"},
	    {"local b = scene:bot{} local z = scene:zone{} scene:control("
	     "'CF_NextOnCollisionWithTarget', { bot = b, target = z })",
	     "E.lua:2: control NextOnCollisionWithTarget needs an element a "
	     "bot can touch: a cylinder, box or object (or a 3D sphere)"},
	    {"local b = scene:bot{} b:object_detector{ name = 'O' }",
	     "E.lua:2: bot:object_detector: object_detector is 2D only, and "
	     "this is a 3D scene (docs/lua.md, \"Which world has what\")"},
	    {"local b = scene:bot{} scene:reward('Lua', { bot = b })",
	     "E.lua:2: scene:reward: for a reward of your own, pass a Lua "
	     "function, not the name 'Lua'"},
	    {"local b = scene:bot{} scene:reward(function() return 1 end, "
	     "{ team = 'red' })",
	     "E.lua:2: scene:reward: no team red: the task has no teams "
	     "(TEAM lines, docs/teams.md)"},
	    {"local b = scene:bot{} scene:control('NextOnTimeout', { tick = 5 "
	     "})",
	     "E.lua:2: scene:control: unknown option 'tick'"},
	    {"local b = scene:bot{} b:wheel{ name = 'W', mode = 'fast' }",
	     "E.lua:2: bot:wheel: mode is \"velocity\" or \"torque\", found "
	     "\"fast\""},
	    {"local b = scene:bot{} b:target_sensor{ name = 'T', axis = 3 }",
	     "E.lua:2: bot:target_sensor: axis is 1 (azimuth) or 2 "
	     "(elevation)"},
	    {"local b = scene:bot{} b:proximity{ name = 'Q', rays = 40 }",
	     "E.lua:2: bot:proximity: rays must be a whole number, 1 to 32"},
	    {"local b = scene:bot{} b:propeller{ name = 'Q', axis = { 1, 0 } }",
	     "E.lua:2: bot:propeller: axis must be a list of three numbers"},
	    {"local b = scene:bot{} b:proximity{ name = 'Q', sees = { 'walls' "
	     "} }",
	     "E.lua:2: bot:proximity: sees lists \"ground\", \"bots\", "
	     "\"obstacles\" or \"objects\", found walls"},
	    {"scene:sphere{ ground = 'yes' }",
	     "E.lua:2: scene:sphere: ground must be true or false, found "
	     "string"},
	    {"scene:grid{}",
	     "E.lua:2: scene:grid: grid is 2D only, and this is a 3D scene"},
	    {"local b = scene:bot{} b:rab{ name = 'R', read = 'rnage' }",
	     "E.lua:2: bot:rab: read is \"range\", \"bearing\", \"value\" "
	     "or \"count\", found \"rnage\" (did you mean range?)"},
	    {"scene:patch{ hx = 0 }",
	     "E.lua:2: scene:patch: hx and hy must be above 0"},
	    {"scene:light{ half_width = 1 }",
	     "E.lua:2: scene:light: unknown option 'half_width'"},
	};
	for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		char env[512];
		snprintf(env, sizeof env,
			 "local e = {}\nfunction e.init(scene) %s end\n"
			 "return e\n",
			 bad[i][0]);
		evo_scene3d *sc;
		evo_err err = {{0}};
		evo_lua *l = build(env, &sc, &err);
		CHECK(l == NULL);
		if (!strstr(err.msg, bad[i][1]))
			printf("  case %u: %s\n", i, err.msg);
		CHECK_CONTAINS(err.msg, bad[i][1]);
		evo_lua_destroy(l);
		evo_scene3d_destroy(sc);
	}
}

/* A Lua reward (half the tick, reset by its own reset function), Step
 * (2 a tick), a Lua control that ends the episode once post_step has
 * counted 3 steps, and Distance (-1 a metre) to a target 5 m away (3 up, 4
 * ahead) from a bot that floats where it is: hand-worked, tick t pays
 * 0.5 t + 2 - 5, and the third step ends the episode with 1.5 + 3 + 4.5 -
 * 15 = -6 paid. */
TEST(lua_rewards_controls_and_post_step_run_in_3d)
{
	const char *env =
	    "local e, n, resets = {}, 0, 0\n"
	    "function e.init(scene)\n"
	    "  local t = scene:target{ x = 4, y = 0, z = 5 }\n"
	    "  local b = scene:bot{}\n"
	    "  scene:reward(function(s) return s:tick() * 0.5 end,\n"
	    "    { reset = function() resets = resets + 1 end })\n"
	    "  scene:reward('Step', { bot = b, k = 2 })\n"
	    "  scene:reward('Distance', { bot = b, target = t, k = -1 })\n"
	    "  scene:control(function() return n >= 3 end)\n"
	    "end\n"
	    "function e.reset(scene) n = 0 end\n"
	    "function e.post_step(scene) n = n + 1 end\n"
	    "return e\n";
	evo_scene3d *sc;
	evo_err err = {{0}};
	evo_lua *l = build(env, &sc, &err);
	CHECK(l != NULL);
	if (!l) {
		printf("  %s\n", err.msg);
		return;
	}
	for (int episode = 1; episode <= 2; episode++) {
		if (episode == 2) {
			CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 2), 0);
			CHECK_EQ_INT(evo_lua_reset(l, 2, &err), 0);
		}
		double want[3] = {0.5 + 2 - 5, 1 + 2 - 5, 1.5 + 2 - 5};
		for (int t = 0; t < 3; t++) {
			evo_scene3d_sense(sc);
			int r = evo_scene3d_step(sc);
			CHECK_EQ_INT(r, t == 2);
			CHECK(NEAR(sc->step_reward, want[t], 1e-6));
		}
		CHECK(NEAR(sc->episode_reward, -6, 1e-6));
		CHECK(NEAR(sc->reward[0].total, 3, 1e-12));
	}
	evo_lua_destroy(l);
	evo_scene3d_destroy(sc);
}

/* A Lua reward that returns no number fails the step with the line it
 * was written at and the tick. */
TEST(a_3d_lua_reward_that_returns_no_number_fails_the_step)
{
	const char *env = "local e = {}\n"
			  "function e.init(scene)\n"
			  "  scene:bot{}\n"
			  "  scene:reward(function(s) return 'x' end)\n"
			  "end\n"
			  "return e\n";
	evo_scene3d *sc;
	evo_err err = {{0}};
	evo_lua *l = build(env, &sc, &err);
	CHECK(l != NULL);
	if (!l)
		return;
	evo_scene3d_sense(sc);
	CHECK_EQ_INT(evo_scene3d_step(sc), -1);
	CHECK_CONTAINS(sc->err.msg,
		       "E.lua:4: the reward function written here returned "
		       "the string \"x\" at tick 1, not a finite number");
	evo_lua_destroy(l);
	evo_scene3d_destroy(sc);
}

/* env.obstacles in 3D (docs/lua.md, "Obstacles of your own"): each entry
 * is what scene:obstacle takes, added for the episode before env.reset.
 * Episode 1: a box whose face is 2.25 - 0.5 = 1.75 from the bot's centre
 * ahead, 1.5 from the ray's start: P reads 1.5 / 4; episode 2 moves it
 * 1 m further: 2.5 / 4; each episode has its box alone. An entry of no
 * known shape is refused, naming the environment and the entry. */
TEST(env_obstacles_add_an_episodes_obstacles_in_3d)
{
	const char *env =
	    "local e = {}\n"
	    "function e.init(scene) scene:bot{} end\n"
	    "function e.obstacles(scene, random, episode)\n"
	    "  local x = episode == 1 and 2.25 or 3.25\n"
	    "  return { { shape = 'box', x = x, y = 0, z = 2, hx = 0.5,"
	    " hy = 0.5, hz = 0.5 } }\n"
	    "end\n"
	    "return e\n";
	evo_scene3d *sc;
	evo_err err = {{0}};
	evo_lua *l = build(env, &sc, &err);
	CHECK(l != NULL);
	if (!l) {
		printf("  %s\n", err.msg);
		return;
	}
	evo_scene3d_sense(sc);
	CHECK(NEAR(value(sc, "P"), 1.5 / 4, 1e-6));
	CHECK_EQ_INT(sc->n_obstacles, 1);
	CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 2), 0);
	CHECK_EQ_INT(evo_lua_reset(l, 2, &err), 0);
	evo_scene3d_sense(sc);
	CHECK(NEAR(value(sc, "P"), 2.5 / 4, 1e-6));
	CHECK_EQ_INT(sc->n_obstacles, 1);
	evo_lua_destroy(l);
	evo_scene3d_destroy(sc);

	const char *bad = "local e = {}\n"
			  "function e.init(scene) scene:bot{} end\n"
			  "function e.obstacles(scene, random, episode)\n"
			  "  return { { shape = 'box' }, { shape = 'cone' } }\n"
			  "end\n"
			  "return e\n";
	l = build(bad, &sc, &err);
	CHECK(l == NULL);
	CHECK_CONTAINS(err.msg, "Envs/E.lua: env.obstacles: obstacle 2: ");
	CHECK_CONTAINS(err.msg, "shape is \"box\", \"cylinder\" or "
				"\"sphere\", found \"cone\"");
}

int main(void)
{
	if (cli_setup("lua3d") ||
	    cli_sh("mkdir -p %s/Bots %s/Envs", cli_tmp, cli_tmp))
		return 1;
	RUN(sensors_built_from_lua_read_hand_worked_values);
	RUN(swarm_sensors_from_lua_read_hand_worked_values);
	RUN(elements_set_off_in_3d_leave_sensors_rewards_and_the_world);
	RUN(bad_options_and_misplaced_calls_are_refused_at_their_line);
	RUN(lua_rewards_controls_and_post_step_run_in_3d);
	RUN(a_3d_lua_reward_that_returns_no_number_fails_the_step);
	RUN(env_obstacles_add_an_episodes_obstacles_in_3d);
	cli_cleanup();
	return test_summary();
}
