/* `evo run` and `evo check` of team tasks (DEMO2DSIMMULTI, docs/teams.md):
 * every bot of every team runs its team's mind with a state of its own;
 * the episode's line is followed by each team's, whose bots' own rewards
 * add up to the team's; a seed gives one run; traces are version 3, a
 * line per bot and tick; the Lua side (scene:teams, scene:bot{team},
 * team rewards, scene:winner) works; and a team the environment does not
 * make, or whose botdesc its bot model does not fit, stops the run before
 * its first tick with the file and line; the swarm of minds/Phototaxis
 * shows its light and floor patch in a screenshot. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/viewer.h"

static char out[1 << 16], out2[1 << 16];

/* The Minds folder of the test: copies of minds/Forager. */
static const char *minds(void)
{
	static char m[256];
	snprintf(m, sizeof m, "%s/Minds", cli_tmp);
	return m;
}

static int write_task(const char *name, const char *text)
{
	return cli_write(text, "%s/Forager/Tasks/%s.simbatch", minds(), name);
}

static int write_env(const char *name, const char *text)
{
	return cli_write(text, "%s/Forager/Envs/%s.lua", minds(), name);
}

static int run(char *buf, const char *task, const char *args)
{
	return cli_capture(buf, sizeof out,
			   "%s run %s/Forager/Tasks/%s.simbatch "
			   "--headless %s",
			   cli_evo, minds(), task, args);
}

/* Sum of the numbers after each bot's name on a team line. */
static double bots_sum(const char *line)
{
	const char *p = strchr(line, '(');
	double sum = 0;
	while (p && *p && *p != ')') {
		const char *sp = strchr(p, ' ');
		if (!sp)
			break;
		sum += strtod(sp + 1, NULL);
		p = strchr(sp + 1, ',');
		if (!p)
			break;
		p += 2; /* ", " */
	}
	return sum;
}

TEST(every_bot_forages_and_the_team_line_adds_up)
{
	int rc = run(out, "Forage-DEMO", "--seed 3 --ticks 400");
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward ");
	CHECK_CONTAINS(out, "  team Foragers: reward ");
	CHECK_CONTAINS(out, "Foragers1 ");
	CHECK_CONTAINS(out, "Foragers4 ");
	const char *team = strstr(out, "  team Foragers: reward ");
	if (!team)
		return;
	double total = strtod(team + strlen("  team Foragers: reward "), NULL);
	CHECK(total > 0);
	CHECK(fabs(total - bots_sum(team)) < 1e-6);
	/* more than one bot gathered: each runs the mind */
	int gatherers = 0;
	for (const char *p = strchr(team, '('); p && *p != ')'; p++)
		if (p[0] == ' ' && p[1] >= '1' && p[1] <= '9')
			gatherers++;
	CHECK(gatherers >= 2);
	if (rc)
		printf("%s\n", out);
}

TEST(a_seed_gives_one_run)
{
	CHECK_EQ_INT(
	    run(out, "Forage-DEMO", "--seed 5 --ticks 300 --episodes 2"), 0);
	CHECK_EQ_INT(
	    run(out2, "Forage-DEMO", "--seed 5 --ticks 300 --episodes 2"), 0);
	CHECK_EQ_STR(out, out2);
	CHECK_CONTAINS(out, "episode 2: ");
	CHECK_EQ_INT(
	    run(out2, "Forage-DEMO", "--seed 6 --ticks 300 --episodes 2"), 0);
	CHECK(strcmp(out, out2) != 0);
}

TEST(a_team_trace_has_a_line_per_bot_and_tick)
{
	char args[600];
	snprintf(args, sizeof args, "--seed 3 --ticks 25 --trace %s/t.trace",
		 cli_tmp);
	CHECK_EQ_INT(run(out, "Forage-DEMO", args), 0);
	char *t = cli_read("%s/t.trace", cli_tmp);
	CHECK(t != NULL);
	if (!t)
		return;
	CHECK(strncmp(t, "evo-trace 3\nteam Foragers mind Forager names ",
		      44) == 0);
	CHECK_CONTAINS(t, " bots 4 Foragers1 Foragers2 Foragers3 Foragers4\n"
			  "sensors 6 S1 S2 S10 ACTOBJ DISTOBJ RADOBJ\n"
			  "actuators 2 MotL MotR\nskills 1 Forage\n");
	CHECK_EQ_INT(cli_count_lines(t, "0 Foragers"), 4);
	CHECK_EQ_INT(cli_count_lines(t, "24 Foragers3 "), 1);
	CHECK_EQ_INT(cli_count_lines(t, "25 "), 0);
	/* 5 header lines, 25 ticks of 4 bots */
	int lines = 0;
	for (const char *p = t; *p; p++)
		lines += *p == '\n';
	CHECK_EQ_INT(lines, 5 + 100);
	free(t);
}

/* An environment of the test's own, through the Lua side of teams. */
static const char ENV[] =
    "local env = {}\n"
    "function env.init(scene, task)\n"
    "  local t = scene:teams()\n"
    "  assert(#t == 2 and t[1].name == 'Red' and t[1].size == 2)\n"
    "  assert(t[2].model == 'BotType8' and t[2].index == 2)\n"
    "  for _, team in ipairs(t) do\n"
    "    for i = 1, team.size do\n"
    "      scene:bot{ team = team.name, x = 5 * i, y = 5 * team.index }\n"
    "    end\n"
    "  end\n"
    "  assert(#scene:bots('Red') == 2 and #scene:bots() == 3)\n"
    "  assert(scene:bots('Blue')[1]:team() == 'Blue')\n"
    "  assert(scene:bots('Blue')[1]:name() == 'Blue1')\n"
    "  scene:reward('Step', { team = 'Red', k = 1 })\n"
    "  scene:reward(function(scene) return 10 end, { team = 'Blue' })\n"
    "  scene:reward(function(scene) return 100 end)\n"
    "  scene:control(function(scene)\n"
    "    if scene:tick() == 5 then scene:winner('Blue') end\n"
    "    return false\n"
    "  end)\n"
    "end\n"
    "return env\n";

TEST(the_lua_side_of_teams)
{
	CHECK_EQ_INT(write_env("Two", ENV), 0);
	CHECK_EQ_INT(write_task("Two", "TYPE:DEMO2DSIMMULTI\nENV:Two\n"
				       "TEAM:Red:Forager:BotType8:2:Forage\n"
				       "TEAM:Blue:Forager:BotType8:1:Forage\n"),
		     0);
	int rc = run(out, "Two", "--ticks 10");
	CHECK_EQ_INT(rc, 0);
	/* each Red bot 1 a tick; Blue 10 a tick as a team; the scene 100 */
	CHECK_CONTAINS(out, "episode 1: reward 1120.000000 over 10 ticks");
	CHECK_CONTAINS(out, "  team Red: reward 20.000000 (Red1 10.000000, "
			    "Red2 10.000000)\n");
	CHECK_CONTAINS(out, "  team Blue: reward 100.000000 (Blue1 "
			    "0.000000), won\n");
	if (rc)
		printf("%s\n", out);
}

TEST(lua_mistakes_with_teams_are_errors_at_their_line)
{
	static const struct {
		const char *body, *want;
	} cases[] = {
	    {"scene:bot{ team = 'Redd' }", "Bad.lua:2: scene:bot: no team Redd "
					   "in the task (did you mean Red?)"},
	    {"scene:bot{ team = 'Red', model = 'BotType6' }",
	     "Bad.lua:2: scene:bot: a bot of team Red is of its model"},
	    {"for i = 1, 3 do scene:bot{ team = 'Red' } end",
	     "Bad.lua:2: scene:bot: team Red has its 2 bots already"},
	    {"scene:bot{}", "Bad.lua:2: scene:bot: in a team task, a bot "
			    "belongs to a team"},
	    {"scene:bot{ team = 'Red' } scene:reward('Gather', { team = 'Blue' "
	     "})",
	     "Bad.lua:2: scene:reward: team Blue has no bots yet"},
	};
	CHECK_EQ_INT(write_task("Bad", "TYPE:DEMO2DSIMMULTI\nENV:Bad\n"
				       "TEAM:Red:Forager:BotType8:2:Forage\n"
				       "TEAM:Blue:Forager:BotType8:1:Forage\n"),
		     0);
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char env[512];
		snprintf(env, sizeof env,
			 "local env = {}\nfunction env.init(scene) %s end\n"
			 "return env\n",
			 cases[i].body);
		write_env("Bad", env);
		CHECK_EQ_INT(run(out, "Bad", "--ticks 5"), 1);
		CHECK_CONTAINS(out, cases[i].want);
	}
}

TEST(a_team_the_environment_does_not_make_stops_the_run)
{
	CHECK_EQ_INT(write_env("Short",
			       "local env = {}\nfunction env.init(scene)\n"
			       "  scene:bot{ team = 'Red' }\n"
			       "  scene:bot{ team = 'Blue' }\nend\n"
			       "return env\n"),
		     0);
	CHECK_EQ_INT(write_task("Short",
				"TYPE:DEMO2DSIMMULTI\nENV:Short\n"
				"TEAM:Red:Forager:BotType8:2:Forage\n"
				"TEAM:Blue:Forager:BotType8:1:Forage\n"),
		     0);
	char trace[600];
	snprintf(trace, sizeof trace, "--trace %s/short.trace", cli_tmp);
	CHECK_EQ_INT(run(out, "Short", trace), 1);
	char want[1200];
	snprintf(want, sizeof want,
		 "%s/Forager/Tasks/Short.simbatch:3: TEAM Red: the "
		 "environment made 1 of its 2 bots (%s/Forager/Envs/Short.lua)",
		 minds(), minds());
	CHECK_CONTAINS(out, want);
	/* nothing ran: no trace */
	char *t = cli_read("%s/short.trace", cli_tmp);
	CHECK(t == NULL);
	free(t);
	/* evo check says the same */
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/Forager/Tasks/Short.simbatch",
				 cli_evo, minds()),
		     1);
	CHECK_CONTAINS(out, want);
}

TEST(a_mind_folder_its_bot_model_does_not_fit_stops_the_run)
{
	/* Other's botdesc names a sensor BotType8 does not have */
	CHECK_EQ_INT(cli_sh("rm -rf %s/Other && cp -r %s/Forager %s/Other && "
			    "sed 's/^S10:/SX:/' %s/Other/Forager.botdesc > "
			    "%s/Other/Other.botdesc && rm "
			    "%s/Other/Forager.botdesc",
			    minds(), minds(), minds(), minds(), minds(),
			    minds()),
		     0);
	CHECK_EQ_INT(write_task("Misfit",
				"TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
				"TEAM:Red:Forager:BotType8:2:Forage\n"
				"TEAM:Blue:Other:BotType8:1:Forage\n"),
		     0);
	/* the Forage skill reads S10, so Other's must too: edit its ades */
	CHECK_EQ_INT(cli_sh("sed -i 's/SE:S10/SE:SX/' "
			    "%s/Other/Skills/Forage/Forage.ades",
			    minds()),
		     0);
	CHECK_EQ_INT(run(out, "Misfit", "--ticks 5"), 1);
	char want[1200];
	snprintf(want, sizeof want,
		 "%s/Other/Other.botdesc:8: sensor 'SX' is not on the bot "
		 "(model ",
		 minds());
	CHECK_CONTAINS(out, want);
	snprintf(want, sizeof want,
		 "(team Blue, %s/Forager/Tasks/Misfit.simbatch:4)", minds());
	CHECK_CONTAINS(out, want);
	CHECK_EQ_INT(cli_capture(out2, sizeof out2,
				 "%s check %s/Forager/Tasks/Misfit.simbatch",
				 cli_evo, minds()),
		     1);
	CHECK_CONTAINS(out2, want);
}

/* Pixels of colour rgb in columns [x0, x1) of a PNG. */
static long count_rgb(const evo_png_image *im, int x0, int x1, uint32_t rgb)
{
	long n = 0;
	for (int y = 0; y < im->h; y++)
		for (int x = x0; x < x1 && x < im->w; x++) {
			const uint8_t *px =
			    im->pixels + ((size_t)y * im->w + x) * im->channels;
			n += ((uint32_t)px[0] << 16 | (uint32_t)px[1] << 8 |
			      px[2]) == rgb;
		}
	return n;
}

/* A shipped team task's screenshot, in the viewer under a virtual X
 * display and drawn without one: each team's bots in its colour, the
 * first bot selected (ringed, its sensors in the panel). */
static void check_screenshot(const char *task, int teams)
{
	static const char *const how[] = {
	    "xvfb-run -a sh -c '%s run %s --ticks 30 --screenshot %s'",
	    "%s -nog %s --ticks 30 --screenshot %s"};
	for (int k = 0; k < 2; k++) {
		char png[512];
		snprintf(png, sizeof png, "%s/shot%d.png", cli_tmp, k);
		int rc =
		    cli_capture(out, sizeof out, how[k], cli_evo, task, png);
		CHECK_EQ_INT(rc, 0);
		if (rc)
			printf("  %s\n", out);
		if (k == 1)
			CHECK_CONTAINS(out, "drawn without a window");
		evo_png_image im;
		evo_err err = {{0}};
		CHECK_EQ_INT(evo_png_read(png, &im, &err), 0);
		if (!im.pixels)
			continue;
		int world = im.w - EVO_VIEW_PANEL_W;
		for (int t = 0; t < teams; t++) {
			long n =
			    count_rgb(&im, 0, world, evo_view_team_colour(t));
			if (n <= 50)
				printf("  %s: team %d: %ld pixels of its "
				       "colour\n",
				       task, t, n);
			CHECK(n > 50);
		}
		CHECK(count_rgb(&im, 0, world, EVO_VIEW_SELECTED) > 20);
		CHECK(count_rgb(&im, world, im.w, EVO_VIEW_SENSOR_BAR) > 100);
		evo_png_image_free(&im);
	}
}

TEST(the_shipped_team_tasks_show_in_the_viewer)
{
	check_screenshot("minds/Forager/Tasks/Forage-DEMO.simbatch", 1);
	check_screenshot("minds/Pursuer/Tasks/Pursuit-DEMO.simbatch", 2);
}

/* The swarm of minds/Phototaxis in a frame drawn without a window, its
 * camera on the light at (0, 0) at zoom 32 (32 * 720 px / 60 m = 384
 * pixels a metre; the world area 1024 - 264 = 760 wide, its middle at
 * (380, 360)): the light, yellow, at the middle; its black patch (radius
 * 0.2 m) at (-0.1, -0.05) m, pixel (341, 340), bots starting 0.45 m out
 * at least. Left to choose its zoom, the frame shows the arena of 1.6 m
 * zoomed in: its black patch more than 1,000 pixels (some 4,500 at
 * zoom 16, a disc of 38 pixels), not the 20 or so of zoom 1. */
TEST(the_phototaxis_swarm_shows_its_light_and_patch)
{
	static const char *const how[] = {
	    "%s run %s -nog --ticks 1 --camera 0,0 --zoom 32 --screenshot %s",
	    "%s run %s -nog --ticks 1 --screenshot %s"};
	for (int k = 0; k < 2; k++) {
		char png[512];
		snprintf(png, sizeof png, "%s/swarm%d.png", cli_tmp, k);
		int rc = cli_capture(out, sizeof out, how[k], cli_evo,
				     "minds/Phototaxis/Tasks/"
				     "Phototaxis-DEMO.simbatch",
				     png);
		CHECK_EQ_INT(rc, 0);
		evo_png_image im;
		evo_err err = {{0}};
		CHECK_EQ_INT(evo_png_read(png, &im, &err), 0);
		if (!im.pixels)
			continue;
		const uint8_t *c = im.pixels + (360 * (size_t)im.w + 380) * 3;
		const uint8_t *g = im.pixels + (340 * (size_t)im.w + 341) * 3;
		uint32_t light = (uint32_t)c[0] << 16 | c[1] << 8 | c[2];
		uint32_t patch = (uint32_t)g[0] << 16 | g[1] << 8 | g[2];
		long black = count_rgb(&im, 0, im.w - EVO_VIEW_PANEL_W, 0);
		printf("  frame %d: light pixel %06X, patch pixel %06X, %ld "
		       "black pixels\n",
		       k, (unsigned)light, (unsigned)patch, black);
		if (k == 0) {
			CHECK_EQ_INT(light, EVO_VIEW_LIGHT);
			CHECK_EQ_INT(patch, evo_view_grey(0));
		}
		CHECK(black > 1000);
		evo_png_image_free(&im);
	}
}

/* The competitive task runs headless: one team wins each episode. */
TEST(pursuit_names_a_winner_every_episode)
{
	int rc = cli_capture(out, sizeof out,
			     "%s run minds/Pursuer/Tasks/Pursuit-DEMO.simbatch "
			     "--headless --seed 2 --episodes 4",
			     cli_evo);
	CHECK_EQ_INT(rc, 0);
	int won = 0;
	for (const char *p = out; (p = strstr(p, ", won\n")); p++)
		won++;
	CHECK_EQ_INT(won, 4);
	CHECK_CONTAINS(out, "  team Pursuers: reward ");
	CHECK_CONTAINS(out, "  team Evaders: reward ");
	/* it needs two teams */
	CHECK_EQ_INT(write_task("OneTeam",
				"TYPE:DEMO2DSIMMULTI\nENV:EXP_Pursuit\n"
				"TEAM:Red:Forager:BotType8:2:Forage\n"),
		     0);
	CHECK_EQ_INT(run(out, "OneTeam", "--ticks 5"), 1);
	CHECK_CONTAINS(out, "EXP_Pursuit needs two teams (TEAM lines), the "
			    "pursuers first; the task has 1");
}

TEST(evo_check_passes_the_shipped_team_tasks)
{
	/* the one-agent keys are the teams' business: a warning each */
	CHECK_EQ_INT(write_task("Extra",
				"TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
				"BOTMODEL:BotType8\n"
				"TEAM:Red:Forager:BotType8:2:Forage\n"),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/Forager/Tasks/Extra.simbatch",
				 cli_evo, minds()),
		     1);
	CHECK_CONTAINS(out, "1 team: not ok, 1 warning above");
	CHECK_CONTAINS(out, "Extra.simbatch:3: BOTMODEL is ignored in a "
			    "DEMO2DSIMMULTI task: each TEAM line names its "
			    "own\n");
	CHECK_CONTAINS(out, "  team Red: 2 bots of BotType8, mind folder ");
	static const char *const tasks[] = {
	    "minds/Forager/Tasks/Forage-DEMO.simbatch",
	    "minds/Forager/Tasks/Forage-NEAT.simbatch",
	    "minds/Forager/Tasks/Forage-NEAT-HETERO.simbatch",
	    "minds/Pursuer/Tasks/Pursuit-DEMO.simbatch",
	    "minds/Pursuer/Tasks/Pursuit-NEAT.simbatch",
	    "minds/Pursuer/Tasks/Pursuit-COEVO.simbatch"};
	for (size_t i = 0; i < sizeof tasks / sizeof tasks[0]; i++) {
		int rc = cli_capture(out, sizeof out, "%s check %s", cli_evo,
				     tasks[i]);
		CHECK_EQ_INT(rc, 0);
		if (rc)
			printf("  %s\n", out);
		CHECK_CONTAINS(out, "2DSIMMULTI, ");
		CHECK_CONTAINS(out, ": ok");
	}
}

int main(void)
{
	if (cli_setup("teams") ||
	    cli_sh("mkdir -p %s/Minds && cp -r minds/Forager %s/Minds/ && "
		   "mkdir -p %s/Minds/Forager/Envs",
		   cli_tmp, cli_tmp, cli_tmp) != 0)
		return 1;
	RUN(every_bot_forages_and_the_team_line_adds_up);
	RUN(a_seed_gives_one_run);
	RUN(a_team_trace_has_a_line_per_bot_and_tick);
	RUN(the_lua_side_of_teams);
	RUN(lua_mistakes_with_teams_are_errors_at_their_line);
	RUN(a_team_the_environment_does_not_make_stops_the_run);
	RUN(a_mind_folder_its_bot_model_does_not_fit_stops_the_run);
	RUN(the_shipped_team_tasks_show_in_the_viewer);
	RUN(the_phototaxis_swarm_shows_its_light_and_patch);
	RUN(pursuit_names_a_winner_every_episode);
	RUN(evo_check_passes_the_shipped_team_tasks);
	cli_cleanup();
	return test_summary();
}
