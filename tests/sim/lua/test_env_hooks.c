/* When the scene scripts' own code runs (sim/lua/lua_hooks.c,
 * sim/world2d/step.c), seen through `evo run` on environments written for
 * the test: post_step runs after the step's rewards, as EvoAgents'
 * postStepOps, and reads this tick's sensor values; a Lua reward's or
 * control's reset function runs at every episode's start and, for a reward,
 * at scene:reset_rewards; a Lua reward that returns no number is reported
 * at the line where the function was written, with the tick; an
 * environment can make its own obstacles each episode (env.obstacles),
 * makes no elements in reset, and each element takes its own options; an
 * environment's own metrics (scene:metric) are 0 at every episode's start,
 * follow the episode line in the order they were declared, and a bad
 * name, one too many, a value that is not finite or a metric not declared
 * in init is reported at its line. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"

static char out[1 << 15];
/* When set, run_env also writes it as the bot model Bots/Mine.lua. */
static const char *bot_lua;

/* A copy of minds/Avoid running environment Envs/Test.lua = lua, for
 * `episodes` episodes; its exit status, the output in out. */
static int run_env(const char *lua, int episodes)
{
	cli_sh("rm -rf %s/Avoid && cp -r minds/Avoid %s/", cli_tmp, cli_tmp);
	char path[512];
	if (cli_write(lua, "%s/Avoid/Envs/Test.lua", cli_tmp))
		return -1;
	if (bot_lua && (cli_sh("mkdir -p %s/Avoid/Bots", cli_tmp) ||
			cli_write(bot_lua, "%s/Avoid/Bots/Mine.lua", cli_tmp)))
		return -1;
	snprintf(path, sizeof path, "%s/Avoid/Tasks/T.simbatch", cli_tmp);
	if (cli_write("TYPE:DEMOSIM\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		      "ENV:Test\nTICKLIM:30\n",
		      "%s", path))
		return -1;
	return cli_capture(out, sizeof out,
			   "timeout -s KILL 60 %s run %s --headless "
			   "--episodes %d",
			   cli_evo, path, episodes);
}

TEST(post_step_runs_after_the_rewards)
{
	/* StepReward pays 1 a tick: after the rewards, the episode's reward
	 * at post_step is the tick count; before them, one less */
	int rc = run_env(
	    "local env = {}\n"
	    "function env.init(scene, task)\n"
	    "  env.bot = scene:bot{ x = 0, y = 0 }\n"
	    "  scene:reward(\"StepReward\", { bot = env.bot, k = 1 })\n"
	    "  scene:control(\"NextOnTimeout\", { bot = env.bot, ticks = 30 })\n"
	    "end\n"
	    "function env.post_step(scene)\n"
	    "  if scene:episode_reward() ~= scene:tick() then\n"
	    "    error(string.format('post_step at tick %d saw %g', "
	    "scene:tick(), scene:episode_reward()))\n"
	    "  end\n"
	    "  -- this tick's readings: what the mind read this tick\n"
	    "  local v = env.bot:value(\"S1\")\n"
	    "  assert(v >= 0 and v <= 1)\n"
	    "end\n"
	    "return env\n",
	    2);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 30.000000 over 30 ticks");
	CHECK_CONTAINS(out, "episode 2: reward 30.000000 over 30 ticks");
	if (rc != 0)
		printf("  said: %s\n", out);
}

TEST(lua_rewards_and_controls_are_reset)
{
	/* The reward counts its calls since its reset and pays the count;
	 * the control ends the episode at its own tenth call since reset.
	 * Reset at every episode's start, each episode pays 1 + 2 + ... +
	 * 10 = 55; without, episode 2 would start counting at 11. The
	 * environment resets the rewards at tick 5 of episode 3: then 1..5
	 * and 1..5 again = 30. */
	int rc = run_env(
	    "local env = {}\n"
	    "local n, c, episode = 0, 0, 0\n"
	    "function env.init(scene, task)\n"
	    "  env.bot = scene:bot{ x = 0, y = 0 }\n"
	    "  scene:reward(function() n = n + 1; return n end,\n"
	    "    { reset = function(s) n = 0 end })\n"
	    "  scene:control(function() c = c + 1; return c >= 10 end,\n"
	    "    { reset = function(s) c = 0 end })\n"
	    "end\n"
	    "function env.reset(scene, e) episode = e end\n"
	    "function env.post_step(scene)\n"
	    "  if episode == 3 and scene:tick() == 5 then "
	    "scene:reset_rewards() end\n"
	    "end\n"
	    "return env\n",
	    3);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 55.000000 over 10 ticks");
	CHECK_CONTAINS(out, "episode 2: reward 55.000000 over 10 ticks");
	CHECK_CONTAINS(out, "episode 3: reward 30.000000 over 10 ticks");
	if (rc != 0)
		printf("  said: %s\n", out);
	/* a reset that is not a function, or an unknown option */
	rc = run_env("local env = {}\n"
		     "function env.init(scene, task)\n"
		     "  env.bot = scene:bot{ x = 0, y = 0 }\n"
		     "  scene:reward(function() return 0 end, { reste = 1 })\n"
		     "end\n"
		     "return env\n",
		     1);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Test.lua:4: scene:reward: unknown option 'reste'");
}

TEST(a_reward_that_returns_no_number_is_reported_where_written)
{
	const char *gave[] = {"nil", "'ten'", "0/0", "'1.5'"};
	const char *said[] = {"returned nil", "returned the string \"ten\"",
			      "returned -nan", "returned the string \"1.5\""};
	for (int i = 0; i < 4; i++) {
		char lua[1024];
		snprintf(lua, sizeof lua,
			 "local env = {}\n"
			 "function env.init(scene, task)\n"
			 "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			 "  scene:reward(function(scene)\n"
			 "    if scene:tick() < 7 then return 1 end\n"
			 "    return %s\n"
			 "  end)\n"
			 "end\n"
			 "return env\n",
			 gave[i]);
		int rc = run_env(lua, 1);
		CHECK_EQ_INT(rc, 1);
		CHECK_CONTAINS(out, "Envs/Test.lua:4: the reward function "
				    "written here ");
		CHECK_CONTAINS(out, "at tick 7, not a finite number");
		/* NaN prints as nan or -nan */
		CHECK(strstr(out, said[i]) ||
		      (i == 2 && strstr(out, "returned nan")));
	}
}

/* The first value of column col (0: the tick) on the tick-0 line of
 * episode e (from 1) of the trace at path; -1 when absent. */
static long tick0_value(const char *path, int e, int col)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	char line[4096];
	int seen = 0;
	long v = -1;
	while (fgets(line, sizeof line, f))
		if (strncmp(line, "0 ", 2) == 0 && ++seen == e) {
			char *p = line;
			for (int c = 0; c < col && p; c++) {
				p = strchr(p, ' ');
				p = p ? p + 1 : NULL;
			}
			v = p ? atol(p) : -1;
			break;
		}
	fclose(f);
	return v;
}

TEST(an_environment_makes_its_own_obstacles)
{
	/* env.obstacles replaces the grid: episode 1 has one cylinder
	 * ahead of the bot, episode 2 one box behind it, and the first is
	 * gone by then */
	int rc = run_env(
	    "local env = {}\n"
	    "function env.init(scene, task)\n"
	    "  env.bot = scene:bot{ x = 0, y = 0 }\n"
	    "  scene:grid{ x0 = -40, y0 = -40, x1 = 40, y1 = 40, spacing = 5 }\n"
	    "end\n"
	    "function env.obstacles(scene, random, episode)\n"
	    "  local r = random(0, 1)\n"
	    "  assert(r >= 0 and r < 1)\n"
	    "  if episode == 1 then return { { x = 3, y = 0, size = 1 } } end\n"
	    "  return { { x = -3, y = 0, size = 1, shape = 'box', angle = 45 } }\n"
	    "end\n"
	    "return env\n",
	    0);
	(void)rc;
	char trace[512];
	snprintf(trace, sizeof trace, "%s/obs.trace", cli_tmp);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/T.simbatch --headless "
			 "--episodes 2 --ticks 2 --trace %s",
			 cli_evo, cli_tmp, trace);
	CHECK_EQ_INT(rc, 0);
	/* S1 looks ahead, S6 behind (BotType8); range 12: the cylinder's
	 * surface is 3 - 1 - 1 (the bot's radius) = 1 away, 1/12 of the
	 * range */
	long s1 = tick0_value(trace, 1, 1), s6 = tick0_value(trace, 1, 6);
	CHECK(s1 > 65536 / 12 - 600 && s1 < 65536 / 12 + 600);
	CHECK_EQ_INT(s6, 65536); /* no grid: nothing else around */
	CHECK_EQ_INT(tick0_value(trace, 2, 1), 65536);
	CHECK(tick0_value(trace, 2, 6) < 65536);
	/* a bad obstacle says which and where */
	rc = run_env("local env = {}\n"
		     "function env.init(scene, task)\n"
		     "  env.bot = scene:bot{ x = 0, y = 0 }\n"
		     "end\n"
		     "function env.obstacles(scene, random, episode)\n"
		     "  return { { x = 9, y = 9 }, { x = 1, y = 1, shape = 'star' } }\n"
		     "end\n"
		     "return env\n",
		     1);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Envs/Test.lua: env.obstacles: obstacle 2: shape "
			    "must be \"circle\" or \"box\"");
}

TEST(elements_are_not_made_in_reset)
{
	int rc = run_env("local env = {}\n"
			 "function env.init(scene, task)\n"
			 "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			 "end\n"
			 "function env.reset(scene, episode)\n"
			 "  scene:cylinder{ x = 5, y = 5, radius = 1 }\n"
			 "end\n"
			 "return env\n",
			 2);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Test.lua:6: scene:cylinder: elements are made in "
			    "init and placed in reset");
}

/* The swarm sensors' names and values are checked like the others: at
 * the script's line, a near name offered (docs/world.md, "Swarm
 * sensors"). */
static void swarm_error(const char *line, const char *said)
{
	char lua[1024];
	snprintf(lua, sizeof lua,
		 "local env = {}\n"
		 "function env.init(scene, task)\n"
		 "  local bot = scene:bot{ x = 0, y = 0 }\n"
		 "  %s\n"
		 "end\n"
		 "return env\n",
		 line);
	CHECK_EQ_INT(run_env(lua, 1), 1);
	CHECK_CONTAINS(out, said);
}

TEST(swarm_sensors_are_checked_at_their_line)
{
	swarm_error("bot:rab{ name = 'R', read = 'bearng' }",
		    "Test.lua:4: bot:rab: read is \"range\", \"bearing\", "
		    "\"value\" or \"count\", found \"bearng\" (did you mean "
		    "bearing?)");
	swarm_error("bot:rab{ name = 'R', range = -1 }",
		    "Test.lua:4: bot:rab: aperture must be 0 or more, range and "
		    "scale above 0");
	swarm_error("bot:rab{ name = 'R', slot = 0 }",
		    "Test.lua:4: bot:rab: slot must be a whole number from 1 "
		    "to 16, found 0");
	swarm_error("bot:light{ name = 'L', apperture = 30 }",
		    "Test.lua:4: bot:light: unknown option 'apperture'; did "
		    "you mean aperture?");
	swarm_error("bot:lihgt{ name = 'L' }", "did you mean bot:light?");
	swarm_error("scene:patch{ x = 1, grey = 2 }",
		    "Test.lua:4: scene:patch: grey must be in [0, 1], found 2");
	swarm_error("scene:patch{ radius = 1, half_width = 2 }",
		    "Test.lua:4: scene:patch: a patch is a circle (radius) or "
		    "a rectangle (half_width, half_height), not both");
	swarm_error("bot:camera{ name = 'C', colour = 'purple' }",
		    "Test.lua:4: bot:camera: colour: unknown colour 'purple' "
		    "(known: red, yellow, green, cyan, blue, magenta, white, "
		    "black)");
	swarm_error("scene:colour(bot, 'gren')",
		    "Test.lua:4: scene:colour: its colour: unknown colour "
		    "'gren'; did you mean green?");
	swarm_error("bot:camera{ name = 'C', read = 'value' }",
		    "Test.lua:4: bot:camera: read is \"range\", \"bearing\", "
		    "\"colour\" or \"count\", found \"value\"");
	swarm_error("scene:colour(3, 'red')",
		    "Test.lua:4: scene:colour: a bot or an element, found "
		    "number");
	swarm_error("scene:light{ x = 1, intensity = -3 }",
		    "Test.lua:4: scene:light: intensity must be above 0, "
		    "found -3");
	int rc = run_env("local env = {}\n"
			 "function env.init(scene, task)\n"
			 "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			 "end\n"
			 "function env.reset(scene, episode)\n"
			 "  scene:light{ x = 5, y = 5 }\n"
			 "end\n"
			 "return env\n",
			 1);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Test.lua:6: scene:light: lights and patches are "
			    "made in init");
}

TEST(each_element_takes_its_own_options)
{
	/* a zone has a size, not a radius; the message lists the zone's */
	int rc = run_env("local env = {}\n"
			 "function env.init(scene, task)\n"
			 "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			 "  scene:zone{ x = 5, y = 5, radius = 2.5 }\n"
			 "end\n"
			 "return env\n",
			 1);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Test.lua:4: scene:zone: unknown option 'radius' "
			    "(known: x, y, size, angle, name)");
}

TEST(a_bot_models_mistakes_are_its_own)
{
	const char *env = "local env = {}\n"
			  "function env.init(scene, task)\n"
			  "  env.bot = scene:bot{ x = 0, y = 0, model = 'Mine' }\n"
			  "end\n"
			  "return env\n";
	/* a body typo: the bot model's file at its body's line, not the
	 * environment's line */
	bot_lua = "return {\n"
		  "  body = { shape = 'circle', radius = 1, dnsity = 2 },\n"
		  "  build = function(bot) end,\n"
		  "}\n";
	CHECK_EQ_INT(run_env(env, 1), 1);
	CHECK_CONTAINS(out, "Bots/Mine.lua:2: body: unknown option 'dnsity'; "
			    "did you mean density?");
	CHECK(!strstr(out, "Test.lua:3"));
	/* a sensor's options are its kind's, and the message says which */
	bot_lua = "return {\n"
		  "  build = function(bot)\n"
		  "    bot:zone{ name = 'Z', range = 12 }\n"
		  "  end,\n"
		  "}\n";
	CHECK_EQ_INT(run_env(env, 1), 1);
	CHECK_CONTAINS(out, "Bots/Mine.lua:3: bot:zone: unknown option 'range' "
			    "(known: name, target)");
	bot_lua = NULL;
}

/* A number that is no number (0/0) or an infinity, given to a sensor,
 * is refused where the bot model gives it (docs/mind.md, "Sensor values":
 * a value a script or a person writes is refused, not mapped); it once
 * said "must be a number, found number". */
TEST(a_sensor_option_that_is_not_finite_is_refused)
{
	const char *env = "local env = {}\n"
			  "function env.init(scene, task)\n"
			  "  env.bot = scene:bot{ x = 0, y = 0, model = 'Mine' }\n"
			  "end\n"
			  "return env\n";
	const char *given[] = {"0/0", "math.huge", "-math.huge"};
	const char *said[] = {"nan", "inf", "-inf"};
	for (int i = 0; i < 3; i++) {
		char lua[512];
		snprintf(lua, sizeof lua,
			 "return {\n"
			 "  build = function(bot)\n"
			 "    bot:constant{ name = 'C', value = %s }\n"
			 "  end,\n"
			 "}\n",
			 given[i]);
		bot_lua = lua;
		CHECK_EQ_INT(run_env(env, 1), 1);
		CHECK_CONTAINS(out, "Bots/Mine.lua:3: bot:constant: option "
				    "'value' must be a finite number, found ");
		CHECK_CONTAINS(out, said[i]);
		CHECK(!strstr(out, "episode 1"));
	}
	bot_lua = NULL;
}

TEST(numbers_past_an_int_are_no_index)
{
	/* scene:get_bot(4294967297) once wrapped round to bot 1, and
	 * -2147483648 overflowed (UBSan, make test-asan) */
	int rc = run_env("local env = {}\n"
			 "function env.init(scene, task)\n"
			 "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			 "  assert(scene:get_bot(1) ~= nil)\n"
			 "  assert(scene:get_bot(4294967297) == nil, 'wrapped')\n"
			 "  assert(scene:get_bot(-2147483648) == nil)\n"
			 "  assert(scene:get_bot(0) == nil)\n"
			 "end\n"
			 "return env\n",
			 1);
	CHECK_EQ_INT(rc, 0);
	if (rc != 0)
		printf("  said: %s\n", out);
}

TEST(metrics_follow_the_episode_line)
{
	/* The zone is the whole world, so the bot is in it at every tick:
	 * in_zone counts the 30 ticks; every_third the ticks 3, 6, .., 30;
	 * the Lua reward adds 0.5 at each of its 30 calls; reset sets
	 * episode to twice the episode's number, after every metric went
	 * back to 0; never is never reported. Episode 2 gives the same, not
	 * twice as much. */
	int rc = run_env(
	    "local env = {}\n"
	    "function env.init(scene, task)\n"
	    "  env.bot = scene:bot{ x = 0, y = 0 }\n"
	    "  env.zone = scene:zone{ x = 0, y = 0, size = 1000 }\n"
	    "  env.bot:target('SENSDZ', env.zone)\n"
	    "  env.in_zone = scene:metric('in_zone')\n"
	    "  scene:metric('never')\n"
	    "  env.third = scene:metric('every_third')\n"
	    "  env.episode = scene:metric('episode')\n"
	    "  assert(scene:metric('in_zone'):name() == 'in_zone')\n"
	    "  scene:metric('paid')\n"
	    "  scene:reward(function(scene)\n"
	    "    scene:metric('paid'):add(0.5)\n"
	    "    return 1\n"
	    "  end)\n"
	    "end\n"
	    "function env.reset(scene, e)\n"
	    "  assert(env.in_zone:value() == 0 and env.episode:value() == 0)\n"
	    "  env.episode:set(2 * e)\n"
	    "end\n"
	    "function env.post_step(scene)\n"
	    "  if env.bot:value('SENSDZ') > 0.5 then env.in_zone:add() end\n"
	    "  if scene:tick() % 3 == 0 then env.third:add(1) end\n"
	    "end\n"
	    "return env\n",
	    2);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 30.000000 over 30 ticks, ");
	/* counts print as whole numbers */
	CHECK_CONTAINS(out, " collision ticks, in_zone 30, never 0, "
			    "every_third 10, episode 2, paid 15\nepisode 2: ");
	CHECK_CONTAINS(out, " collision ticks, in_zone 30, never 0, "
			    "every_third 10, episode 4, paid 15\n");
	if (rc != 0)
		printf("  said: %s\n", out);
	/* without metrics the line ends as it always did */
	rc = run_env("local env = {}\n"
		     "function env.init(scene, task)\n"
		     "  env.bot = scene:bot{ x = 0, y = 0 }\n"
		     "end\n"
		     "return env\n",
		     1);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 0.000000 over 30 ticks, 0 "
			    "collision ticks\n");
}

/* Runs an environment whose init declares metric m and whose post_step
 * is `step`; its exit status, the output in out. */
static int run_step(const char *step)
{
	char lua[2048];
	snprintf(lua, sizeof lua,
		 "local env = {}\n"
		 "function env.init(scene, task)\n"
		 "  env.bot = scene:bot{ x = 0, y = 0 }\n"
		 "  env.m = scene:metric('in_zone')\n"
		 "end\n"
		 "function env.post_step(scene)\n"
		 "  %s\n"
		 "end\n"
		 "return env\n",
		 step);
	return run_env(lua, 1);
}

TEST(a_bad_metric_is_reported_at_its_line)
{
	/* names go into episode lines and log.csv headers */
	const char *names[] = {"in zone", "9lives", "a,b", ""};
	for (int i = 0; i < 4; i++) {
		char lua[512];
		snprintf(lua, sizeof lua,
			 "local env = {}\n"
			 "function env.init(scene, task)\n"
			 "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			 "  scene:metric('%s')\n"
			 "end\n"
			 "return env\n",
			 names[i]);
		CHECK_EQ_INT(run_env(lua, 1), 1);
		CHECK_CONTAINS(out, "Envs/Test.lua:4: scene:metric: '");
		CHECK_CONTAINS(out, "' is not a metric name: use letters, "
				    "digits and '_', not starting with a "
				    "digit");
	}
	CHECK_EQ_INT(run_env("local env = {}\n"
			     "function env.init(scene, task)\n"
			     "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			     "  scene:metric(string.rep('x', 32))\n"
			     "end\n"
			     "return env\n",
			     1),
		     1);
	CHECK_CONTAINS(out, "Envs/Test.lua:4: scene:metric: metric name "
			    "'xxxx");
	CHECK_CONTAINS(out, "' is longer than 31 characters");
	/* at most 16 */
	CHECK_EQ_INT(run_env("local env = {}\n"
			     "function env.init(scene, task)\n"
			     "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			     "  for i = 1, 17 do\n"
			     "    scene:metric('m' .. i)\n"
			     "  end\n"
			     "end\n"
			     "return env\n",
			     1),
		     1);
	CHECK_CONTAINS(out, "Envs/Test.lua:5: scene:metric: metric 'm17' is "
			    "one too many: an environment has at most 16");
	/* a value that is not finite: where, what and when */
	CHECK_EQ_INT(run_step("if scene:tick() == 7 then env.m:set(0/0) end"),
		     1);
	CHECK_CONTAINS(out, "Envs/Test.lua:7: metric 'in_zone': set(");
	CHECK_CONTAINS(out, "nan) at tick 7: not a finite number");
	CHECK_EQ_INT(run_step("env.m:add(math.huge)"), 1);
	CHECK_CONTAINS(out, "Envs/Test.lua:7: metric 'in_zone': add(inf) at "
			    "tick 1: not a finite number");
	CHECK_EQ_INT(run_step("env.m:add(1e308)"), 1);
	CHECK_CONTAINS(out, "Envs/Test.lua:7: metric 'in_zone': add(1e+308) at "
			    "tick 2 makes it inf, not a finite number");
	CHECK_EQ_INT(run_step("env.m:set('ten')"), 1);
	CHECK_CONTAINS(out, "Envs/Test.lua:7: bad argument #1 to 'set' (number "
			    "expected, got string)");
	/* declared in init, and only there */
	CHECK_EQ_INT(run_step("scene:metric('in_zon'):add()"), 1);
	CHECK_CONTAINS(out, "Envs/Test.lua:7: scene:metric: no metric 'in_zon' "
			    "was declared; metrics are declared in env.init "
			    "(closest: in_zone)");
	/* a value given to scene:metric itself would be lost: refused */
	CHECK_EQ_INT(run_step("scene:metric('in_zone', 3)"), 1);
	CHECK_CONTAINS(out, "Envs/Test.lua:7: scene:metric takes a metric's "
			    "name only; change its value through the handle "
			    "it returns: scene:metric(\"in_zone\"):set(x) or "
			    ":add(x)");
	/* a value set in init would be 0 again when the first episode starts */
	CHECK_EQ_INT(run_env("local env = {}\n"
			     "function env.init(scene, task)\n"
			     "  env.bot = scene:bot{ x = 0, y = 0 }\n"
			     "  scene:metric('in_zone'):set(3)\n"
			     "end\n"
			     "return env\n",
			     1),
		     1);
	CHECK_CONTAINS(out, "Envs/Test.lua:4: metric 'in_zone': set in "
			    "env.init, before any episode");
	/* and none of these printed an episode line */
	CHECK(!strstr(out, "episode 1:"));
}

int main(void)
{
	if (cli_setup("hooks"))
		return 1;
	RUN(post_step_runs_after_the_rewards);
	RUN(lua_rewards_and_controls_are_reset);
	RUN(a_reward_that_returns_no_number_is_reported_where_written);
	RUN(an_environment_makes_its_own_obstacles);
	RUN(elements_are_not_made_in_reset);
	RUN(each_element_takes_its_own_options);
	RUN(swarm_sensors_are_checked_at_their_line);
	RUN(a_bot_models_mistakes_are_its_own);
	RUN(a_sensor_option_that_is_not_finite_is_refused);
	RUN(numbers_past_an_int_are_no_index);
	RUN(metrics_follow_the_episode_line);
	RUN(a_bad_metric_is_reported_at_its_line);
	cli_cleanup();
	return test_summary();
}
