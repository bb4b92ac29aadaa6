/* Teams in the 3D world (DEMO3DSIMMULTI, LEARN3DSIMMULTI; docs/teams.md)
 * end to end through `evo run` and `evo check`: a short 3D team episode's
 * rewards (the scene's, each team's, each bot's) and its winner against
 * values worked out by hand; the shipped Teams3D-DEMO task's team lines
 * adding up; the shipped Teams3D-NEAT task giving the same log and
 * champion with one thread and with two, its champion beating untrained
 * teams; the demo's screenshot, drawn without a display, with its second
 * team in that team's colour; a bad TEAM line, a bad LEARNINGTEAM and a misspelt 3D team type
 * reported at their lines. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/viewer.h"

static char out[65536];

/* A copy of minds/Wheeled3D in Minds/ of folder `name`. */
static void copy_mind(const char *name)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s/Minds && cp -r minds/Wheeled3D "
			    "%s/%s/Minds/",
			    cli_tmp, name, cli_tmp, name),
		     0);
}

/* Three bots, Red1 and Red2 of team Red and Blue1 of team Blue, paid by
 * Step rewards and a Lua reward of team Blue as a whole, for 4 ticks; Blue
 * wins. By hand: Red1 earns 4 x 0.25 (the team's Step) + 4 x 1 (its own)
 * = 5, Red2 4 x 0.25 = 1, so team Red 6; Blue1 4 x -0.5 = -2, and team
 * Blue that and the Lua reward's 4 x 0.5, 0; the scene 6 + 0 = 6. */
static const char step_env[] =
    "local env = {}\n"
    "function env.init(scene)\n"
    "\tscene:bot{ team = \"Red\", x = -2, y = 0 }\n"
    "\tscene:bot{ team = \"Red\", x = 0, y = 0 }\n"
    "\tscene:bot{ team = \"Blue\", x = 2, y = 2 }\n"
    "\tscene:reward(\"Step\", { team = \"Red\", k = 0.25 })\n"
    "\tscene:reward(\"Step\", { team = \"Blue\", k = -0.5 })\n"
    "\tscene:reward(\"Step\", { bot = scene:get_bot(\"Red1\"), k = 1 })\n"
    "\tscene:reward(function() return 0.5 end, { team = \"Blue\" })\n"
    "\tscene:control(\"NextOnTimeout\", { ticks = 4 })\n"
    "end\n"
    "function env.reset(scene)\n"
    "\tassert(#scene:bots(\"Red\") == 2 and #scene:bots() == 3)\n"
    "\tassert(scene:bots(\"Blue\")[1]:team() == \"Blue\")\n"
    "\tassert(scene:winner() == nil)\n"
    "\tscene:winner(\"Blue\")\n"
    "\tassert(scene:winner() == \"Blue\")\n"
    "end\n"
    "return env\n";

TEST(a_3d_team_episode_pays_bots_teams_and_scene_as_worked_out_by_hand)
{
	copy_mind("step");
	CHECK_EQ_INT(cli_sh("mkdir -p %s/step/Minds/Wheeled3D/Envs", cli_tmp),
		     0);
	CHECK_EQ_INT(cli_write(step_env, "%s/step/Minds/Wheeled3D/Envs/Step.lua",
			       cli_tmp),
		     0);
	CHECK_EQ_INT(cli_write("TYPE:DEMO3DSIMMULTI\nENV:Step\n"
			       "TEAM:Red:Wheeled3D:Wheeled3D:2:Roam3D\n"
			       "TEAM:Blue:Wheeled3D:Wheeled3D:1:Avoid3D\n"
			       "TICKLIM:100\n",
			       "%s/step/Minds/Wheeled3D/Tasks/S.simbatch",
			       cli_tmp),
		     0);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/step/Minds/Wheeled3D/Tasks/S.simbatch "
			     "--headless --episodes 2 2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 6.000000 over 4 ticks");
	CHECK_CONTAINS(out, "episode 2: reward 6.000000 over 4 ticks");
	CHECK_CONTAINS(out, "  team Red: reward 6.000000 (Red1 5.000000, "
			    "Red2 1.000000)\n");
	CHECK_CONTAINS(out, "  team Blue: reward 0.000000 (Blue1 "
			    "-2.000000), won\n");
	CHECK_EQ_INT(cli_count_lines(out, "  team Red: reward 6.000000"), 2);
	if (rc)
		printf("%s\n", out);
}

/* The sum of the figures after each "Red1 ", "Red2 " in a team line. */
static double bots_sum(const char *line, const char *end)
{
	double sum = 0;
	const char *p = strchr(line, '(');
	while (p && p < end) {
		const char *sp = strchr(p, ' ');
		if (!sp || sp > end)
			break;
		sum += strtod(sp + 1, NULL);
		p = strstr(sp, ", ");
		if (p)
			p += 2;
	}
	return sum;
}

/* The shipped demo: one line a team after each episode, each team's
 * reward the sum of its bots'. */
TEST(the_shipped_3d_team_demo_prints_teams_whose_bots_add_up)
{
	int rc = cli_capture(out, sizeof out,
			     "%s run minds/Wheeled3D/Tasks/Teams3D-DEMO.simbatch "
			     "--headless --seed 3 --ticks 60 2>&1",
			     cli_evo);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward ");
	const char *names[2] = {"  team Rovers: reward ",
				"  team Scouts: reward "};
	double total = 0;
	for (int k = 0; k < 2; k++) {
		const char *l = strstr(out, names[k]);
		CHECK(l != NULL);
		if (!l)
			continue;
		const char *end = strchr(l, '\n');
		double team = strtod(l + strlen(names[k]), NULL);
		CHECK(fabs(team - bots_sum(l, end)) < 2e-6);
		total += team;
	}
	const char *e = strstr(out, "episode 1: reward ");
	CHECK(e && fabs(strtod(e + 18, NULL) - total) < 2e-6);
	CHECK_CONTAINS(out, "(Rovers1 ");
	CHECK_CONTAINS(out, "(Scouts1 ");
}

/* Pixels of the second team's red (evo_view_team_colour(1), shaded) in
 * the world's part of a frame: none in a one-agent task's. */
static long team_red(const char *png)
{
	evo_png_image im;
	evo_err err = {{0}};
	if (evo_png_read(png, &im, &err))
		return -1;
	long n = 0;
	for (int y = 0; y < im.h; y++)
		for (int x = 0; x < im.w - EVO_VIEW_PANEL_W; x++) {
			const uint8_t *p = im.pixels + 3 * ((size_t)y * im.w + x);
			n += p[0] > 140 && p[0] < 235 && p[1] > 20 &&
			     p[1] < 80 && p[2] > 20 && p[2] < 80 &&
			     abs(p[1] - p[2]) < 15;
		}
	evo_png_image_free(&im);
	return n;
}

/* The demo drawn off screen: its second team's bot is red; the
 * one-agent Avoid3D demo's robot is not. */
TEST(the_3d_team_demo_draws_each_team_in_its_colour_without_a_display)
{
	const char *task[2] = {"Teams3D-DEMO", "Avoid3D-DEMO"};
	long n[2];
	for (int k = 0; k < 2; k++) {
		int rc = cli_capture(out, sizeof out,
				     "env -u DISPLAY -u WAYLAND_DISPLAY %s run "
				     "minds/Wheeled3D/Tasks/%s.simbatch "
				     "--ticks 30 --screenshot %s/shot%d.png "
				     "2>&1",
				     cli_evo, task[k], cli_tmp, k);
		CHECK_EQ_INT(rc, 0);
		CHECK_CONTAINS(out, "(tick 30, drawn without a window)");
		char png[256];
		snprintf(png, sizeof png, "%s/shot%d.png", cli_tmp, k);
		n[k] = team_red(png);
	}
	printf("  team red pixels: %ld with teams, %ld without\n", n[0], n[1]);
	CHECK(n[0] > 1000);
	CHECK(n[1] >= 0 && n[1] < 100);
}

static int train(const char *name, int threads)
{
	copy_mind(name);
	return cli_capture(out, sizeof out,
			   "%s run %s/%s/Minds/Wheeled3D/Tasks/"
			   "Teams3D-NEAT.simbatch --seed 1 --threads %d --run "
			   "%s/%s/run 2>&1",
			   cli_evo, cli_tmp, name, threads, cli_tmp, name);
}

/* The figure after `label` and "reward" in the replay report. */
static double figure(const char *text, const char *label)
{
	const char *p = strstr(text, label);
	if (!p)
		return -1e300;
	p = strstr(p, "reward");
	return p ? strtod(p + 6, NULL) : -1e300;
}

/* One thread and two: the same log and champion; the champion team,
 * replayed on episodes it never saw, earns more than untrained teams. */
TEST(learn3dsimmulti_threads_agree_and_the_champion_beats_untrained_teams)
{
	CHECK_EQ_INT(train("t1", 1), 0);
	double champ = figure(out, "team Rovers, champion:");
	double fresh = figure(out, "team Rovers, untrained teams");
	printf("  champion %.1f, untrained teams %.1f\n", champ, fresh);
	CHECK(champ > -1e300 && fresh > -1e300);
	CHECK(champ > fresh);
	CHECK_EQ_INT(train("t2", 2), 0);
	char d1[256], d2[256];
	snprintf(d1, sizeof d1, "%s/t1/run", cli_tmp);
	snprintf(d2, sizeof d2, "%s/t2/run", cli_tmp);
	char *a = cli_fitness_log(d1), *b = cli_fitness_log(d2);
	CHECK(a && b);
	if (a && b) {
		CHECK(cli_count_lines(a, "") == 5);
		CHECK_EQ_STR(a, b);
	}
	free(a);
	free(b);
	const char *net = "Minds/Wheeled3D/Skills/Roam3D/Roam3D.net";
	a = cli_read("%s/t1/%s", cli_tmp, net);
	b = cli_read("%s/t2/%s", cli_tmp, net);
	char *shipped = cli_read("minds/Wheeled3D/Skills/Roam3D/Roam3D.net");
	CHECK(a && b && shipped);
	if (a && b && shipped) {
		CHECK_EQ_STR(a, b);
		CHECK(strcmp(a, shipped) != 0);
	}
	free(a);
	free(b);
	free(shipped);
}

/* evo check of a 3D team task with the given lines, which must fail. */
static void refused(const char *lines)
{
	CHECK_EQ_INT(cli_write(lines, "%s/bad/Minds/Wheeled3D/Tasks/T.simbatch",
			       cli_tmp),
		     0);
	int rc = cli_capture(out, sizeof out,
			     "%s check %s/bad/Minds/Wheeled3D/Tasks/T.simbatch "
			     "2>&1",
			     cli_evo, cli_tmp);
	CHECK(rc != 0);
}

TEST(mistakes_in_a_3d_team_task_are_reported_at_their_line)
{
	copy_mind("bad");
	refused("TYPE:DEMO3DSIMMULTI\nENV:EXP3D_Teams\nTICKLIM:60\n"
		"TEAM:Red:Wheeled3D:4\n");
	CHECK_CONTAINS(out, "/T.simbatch:4: TEAM: expected "
			    "NAME:MIND:BOTMODEL:SIZE:MASTERSKILL"
			    "[:LEARNINGSKILL], found 'Red:Wheeled3D:4'");
	refused("TYPE:LEARN3DSIMMULTI\nENV:EXP3D_Teams\n"
		"TEAM:Red:Wheeled3D:Wheeled3D:2:Roam3D\n"
		"TEAM:Blue:Wheeled3D:Wheeled3D:1:Avoid3D\n"
		"LEARNINGSKILL:Roam3D\nLEARNINGMETHOD:NEAT\nNUMGEN:1\n"
		"LEARNINGTEAM:Rd\n");
	CHECK_CONTAINS(out, "/T.simbatch:8: LEARNINGTEAM: no team named Rd; "
			    "the teams are Red and Blue (did you mean Red?)");
	refused("TYPE:DEMO3DSIMMULTI\nENV:EXP3D_Teams\n"
		"TEAM:Red:Wheeled3D:Wheeled3D:0:Roam3D\n");
	CHECK_CONTAINS(out, "/T.simbatch:3: TEAM Red: expected a size of "
			    "1..4096 bots, found '0'");
	refused("TYPE:DEMO3DSIMULTI\nENV:EXP3D_Teams\n"
		"TEAM:Red:Wheeled3D:Wheeled3D:2:Roam3D\n");
	CHECK_CONTAINS(out, "/T.simbatch:1: TYPE:");
	CHECK_CONTAINS(out, "did you mean DEMO3DSIMMULTI?");
	refused("TYPE:DEMO3DSIMMULTI\nENV:EXP3D_Teams\n");
	CHECK_CONTAINS(out, "a DEMO3DSIMMULTI task needs the key TEAM");
}

int main(void)
{
	if (cli_setup("teams3d"))
		return 1;
	RUN(a_3d_team_episode_pays_bots_teams_and_scene_as_worked_out_by_hand);
	RUN(the_shipped_3d_team_demo_prints_teams_whose_bots_add_up);
	RUN(the_3d_team_demo_draws_each_team_in_its_colour_without_a_display);
	RUN(learn3dsimmulti_threads_agree_and_the_champion_beats_untrained_teams);
	RUN(mistakes_in_a_3d_team_task_are_reported_at_their_line);
	cli_cleanup();
	return test_summary();
}
