/* The evo command around a task (sim/cmd/evo_main.c): the tutorial's own
 * command line (`evo TASK.simbatch`, `evo -nog TASK.simbatch`) runs the
 * task as `evo run` does; `evo check` fails on what `evo run` would fail on
 * (a misspelled bot model, environment or botdesc sensor, a task type evo
 * cannot run yet); TYPE is read in any case; a BOTNAME naming another
 * agent than the mind folder gets a warning at its line; a learning
 * task's THREADS key sets its workers unless --threads does, and HIDDEN
 * the width of GENETIC's and ANNEALING's hidden layers; the DEMOSIM viewer
 * runs episodes until its window is closed, and --screenshot without a
 * window draws the frame off screen; a demo episode lasts TICKLIM ticks. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/viewer.h"

static char out1[1 << 15], out2[1 << 15];

#define DEMO "minds/Avoid/Tasks/Avoid-DEMO.simbatch"

/* The episode lines of a run's output (stdout and stderr together). */
static const char *episodes(const char *out)
{
	const char *e = strstr(out, "episode 1: reward ");
	return e ? e : "";
}

TEST(nog_is_evo_run_headless)
{
	int a = cli_capture(out1, sizeof out1,
			    "%s run " DEMO " --headless --seed 7 --ticks 60",
			    cli_evo);
	int b = cli_capture(out2, sizeof out2,
			    "%s -nog " DEMO " --seed 7 --ticks 60", cli_evo);
	CHECK_EQ_INT(a, 0);
	CHECK_EQ_INT(b, 0);
	CHECK_CONTAINS(out1, "episode 1: reward ");
	CHECK_EQ_STR(episodes(out2), episodes(out1));
}

TEST(a_task_path_alone_is_evo_run)
{
	/* no display here: the viewer is not available and the run goes on
	 * headless, as `evo run` without --headless does */
	int a = cli_capture(out1, sizeof out1,
			    "%s run " DEMO " --headless --seed 5 --ticks 40",
			    cli_evo);
	int b = cli_capture(out2, sizeof out2,
			    "env -u DISPLAY -u WAYLAND_DISPLAY %s " DEMO
			    " --seed 5 --ticks 40",
			    cli_evo);
	CHECK_EQ_INT(a, 0);
	CHECK_EQ_INT(b, 0);
	CHECK_CONTAINS(out2, "running headless");
	CHECK_EQ_STR(episodes(out2), episodes(out1));
	/* a path that is no task is still an unknown command */
	CHECK(cli_capture(out1, sizeof out1, "%s minds/Avoid", cli_evo) != 0);
	CHECK_CONTAINS(out1, "unknown command");
}

/* A copy of minds/Avoid in cli_tmp with one task, TEXT. */
static void avoid_with_task(const char *name, const char *text)
{
	cli_sh("rm -rf %s/Avoid && cp -r minds/Avoid %s/", cli_tmp, cli_tmp);
	cli_write(text, "%s/Avoid/Tasks/%s", cli_tmp, name);
}

TEST(check_passes_the_shipped_tasks)
{
	const char *tasks[] = {DEMO, "minds/Avoid/Tasks/Avoid-NEAT.simbatch",
			       "minds/Collect/Tasks/Collect-DEMO.simbatch",
			       "minds/GTO/Tasks/GTOA-DEMO.simbatch",
			       "minds/XOR/Tasks/XOR-NEAT.simbatch"};
	for (unsigned i = 0; i < sizeof tasks / sizeof *tasks; i++) {
		int rc = cli_capture(out1, sizeof out1, "%s check %s", cli_evo,
				     tasks[i]);
		CHECK_EQ_INT(rc, 0);
		CHECK_CONTAINS(out1, ": ok");
	}
}

TEST(check_fails_on_a_misspelled_bot_model_or_environment)
{
	avoid_with_task("T.simbatch", "TYPE:DEMOSIM\nBOTMODEL:BotType88\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1, "bot model 'BotType88' not found");

	avoid_with_task("T.simbatch", "TYPE:LEARNSIM\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nLEARNINGSKILL:Avoid\n"
				      "LEARNINGMETHOD:NEAT\nNUMGEN:2\n"
				      "ENV:EXP_Avoidd\n");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1, "environment 'EXP_Avoidd' not found");
}

TEST(check_fails_on_a_botdesc_sensor_the_bot_lacks)
{
	avoid_with_task("T.simbatch", "TYPE:DEMOSIM\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n");
	/* S10 becomes S11 in the botdesc, and so in the skill that reads it */
	cli_sh("sed -i 's/\\bS10\\b/S11/' %s/Avoid/Avoid.botdesc "
	       "%s/Avoid/Skills/Avoid/Avoid.ades",
	       cli_tmp, cli_tmp);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1, "S11");
}

TEST(check_refuses_a_type_evo_run_cannot_run_yet)
{
	avoid_with_task("T.simbatch", "TYPE:OPENENDED\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1, "evo run does not run OPENENDED tasks yet");
	/* a 3D task runs, and a 2D environment in it says what is wrong */
	avoid_with_task("T.simbatch", "TYPE:DEMO3DSIM\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1,
		       "Roam.lua:20: scene:grid is not a method of a "
		       "3D scene (DEMO3DSIM, LEARN3DSIM: docs/world3d.md)");
}

TEST(type_is_read_in_any_case)
{
	avoid_with_task("T.simbatch", "TYPE:demosim\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n");
	int rc = cli_capture(out1, sizeof out1,
			     "%s run %s/Avoid/Tasks/T.simbatch --headless "
			     "--ticks 20",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out1, "episode 1: reward ");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1,
				 "%s check %s/Avoid/Tasks/T.simbatch", cli_evo,
				 cli_tmp),
		     0);
	CHECK_CONTAINS(out1, "task DEMOSIM");
}

TEST(a_botname_of_another_agent_is_warned_at_its_line)
{
	avoid_with_task("T.simbatch", "TYPE:DEMOSIM\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n"
				      "BOTNAME:T6-NEAT\n");
	int rc = cli_capture(out1, sizeof out1,
			     "%s check %s/Avoid/Tasks/T.simbatch", cli_evo,
			     cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out1, "T.simbatch:5: BOTNAME is T6-NEAT, but the "
			     "task's mind folder is Avoid");
	/* the folder's own name: no warning */
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check " DEMO, cli_evo),
		     0);
	CHECK(!strstr(out1, "BOTNAME"));
}

TEST(a_tasks_threads_key_sets_the_workers)
{
	cli_sh("rm -rf %s/XOR && cp -r minds/XOR %s/", cli_tmp, cli_tmp);
	const char *task = "TYPE:LEARNSIM\nBOTMODEL:none\nMASTERSKILL:XOR\n"
			   "LEARNINGSKILL:XOR\nENV:XOR\nLEARNINGMETHOD:NEAT\n"
			   "POPSIZE:20\nNUMGEN:1\nTHREADS:1\n";
	char path[512];
	snprintf(path, sizeof path, "%s/XOR/Tasks/T.simbatch", cli_tmp);
	CHECK_EQ_INT(cli_write(task, "%s", path), 0);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s run %s --run %s/r1",
				 cli_evo, path, cli_tmp),
		     0);
	CHECK_CONTAINS(out1, ", 1 thread, run folder");
	/* --threads wins over the task's key */
	CHECK_EQ_INT(cli_capture(out1, sizeof out1,
				 "%s run %s --run %s/r2 --threads 2", cli_evo,
				 path, cli_tmp),
		     0);
	CHECK_CONTAINS(out1, ", 2 threads, run folder");
}

TEST(the_viewer_runs_episodes_until_it_is_closed)
{
	/* 5-tick episodes in real time (30 ticks a second) under a virtual
	 * display: after 3 s, many episodes have run and the viewer is still
	 * up, until SIGTERM closes it (timeout's 124) */
	int rc = cli_capture(out1, sizeof out1,
			     "xvfb-run -a sh -c 'timeout -s TERM 3 %s run " DEMO
			     " --ticks 5; echo \"exit $?\"'",
			     cli_evo);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out1, "episode 1: reward ");
	CHECK_CONTAINS(out1, "episode 3: reward ");
	CHECK_CONTAINS(out1, "exit 124");
	/* --episodes still bounds it */
	rc = cli_capture(out1, sizeof out1,
			 "xvfb-run -a sh -c 'timeout -s TERM 20 %s run " DEMO
			 " --ticks 5 --episodes 2; echo \"exit $?\"'",
			 cli_evo);
	CHECK_CONTAINS(out1, "episode 2: reward ");
	CHECK(!strstr(out1, "episode 3:"));
	CHECK_CONTAINS(out1, "exit 0");
}

TEST(a_screenshot_without_a_window_is_drawn_off_screen)
{
	char png[512];
	snprintf(png, sizeof png, "%s/shot.png", cli_tmp);
	int rc = cli_capture(out1, sizeof out1,
			     "%s -nog minds/Collect/Tasks/Collect-DEMO.simbatch "
			     "--ticks 30 --screenshot %s",
			     cli_evo, png);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out1, "(tick 30, drawn without a window)");
	evo_png_image im;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_png_read(png, &im, &err), 0);
	CHECK_EQ_INT(im.w, 1024);
	CHECK_EQ_INT(im.h, 720);
	/* the bot is drawn in the viewer's colour, the panel on the right */
	long bot = 0;
	for (long i = 0; im.pixels && i < (long)im.w * im.h; i++) {
		const uint8_t *px = im.pixels + i * im.channels;
		bot += ((uint32_t)px[0] << 16 | (uint32_t)px[1] << 8 | px[2]) ==
		       EVO_VIEW_BOT;
	}
	CHECK(bot > 20);
	evo_png_image_free(&im);
	/* no display and no -nog: the same, after saying so */
	rc = cli_capture(out1, sizeof out1,
			 "env -u DISPLAY -u WAYLAND_DISPLAY %s run " DEMO
			 " --ticks 10 --screenshot %s",
			 cli_evo, png);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out1, "running headless");
	CHECK_CONTAINS(out1, "drawn without a window");
}

TEST(a_demo_episode_lasts_ticklim_ticks)
{
	/* Roam ends an episode with NextOnTimeout(TICKLIM), which fires at
	 * its (TICKLIM + 1)th check, as the tutorial's does; the run stops
	 * the episode at TICKLIM ticks, as learning does */
	cli_sh("rm -rf %s/Avoid && cp -r minds/Avoid %s/ && sed -i "
	       "'s/^TICKLIM:15000$/TICKLIM:50/' %s/Avoid/Tasks/Avoid-DEMO.simbatch",
	       cli_tmp, cli_tmp, cli_tmp);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1,
				 "%s -nog %s/Avoid/Tasks/Avoid-DEMO.simbatch "
				 "--episodes 2",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out1, "episode 1: reward ");
	CHECK_CONTAINS(out1, " over 50 ticks");
	CHECK(!strstr(out1, " over 51 ticks"));
	/* --ticks still shortens it */
	CHECK_EQ_INT(cli_capture(out1, sizeof out1,
				 "%s -nog %s/Avoid/Tasks/Avoid-DEMO.simbatch "
				 "--ticks 20",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out1, " over 20 ticks");
}

TEST(hidden_sets_the_width_of_genetic_networks)
{
	cli_sh("rm -rf %s/XOR && cp -r minds/XOR %s/ && sed -i "
	       "'s/layers:0/layers:2/' %s/XOR/Skills/XOR/XOR.ades && "
	       "rm -f %s/XOR/Skills/XOR/XOR.net",
	       cli_tmp, cli_tmp, cli_tmp, cli_tmp);
	char path[512];
	snprintf(path, sizeof path, "%s/XOR/Tasks/G.simbatch", cli_tmp);
	CHECK_EQ_INT(cli_write("TYPE:LEARNSIM\nBOTMODEL:none\nMASTERSKILL:XOR\n"
			       "LEARNINGSKILL:XOR\nENV:XOR\n"
			       "LEARNINGMETHOD:GENETIC\nGA_POPSIZE:10\n"
			       "NUMGEN:2\nHIDDEN:3\n",
			       "%s", path),
		     0);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s run %s --run %s/g",
				 cli_evo, path, cli_tmp),
		     0);
	/* two hidden layers of HIDDEN:3 nodes, then the output (the default
	 * width would be max(2, 1) = 2) */
	char *net = cli_read("%s/g/champion.net", cli_tmp);
	CHECK(net != NULL);
	CHECK_EQ_INT(cli_count_lines(net, "node:"), 3 + 3 + 1);
	CHECK_EQ_INT(cli_count_lines(net, "link:"), 3 * 2 + 3 * 3 + 1 * 3);
	free(net);
	/* NEAT grows its own hidden nodes: a warning at HIDDEN's line */
	cli_sh("sed -i 's/GENETIC/NEAT/; s/GA_POPSIZE/POPSIZE/' %s", path);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s run %s --run %s/n",
				 cli_evo, path, cli_tmp),
		     0);
	CHECK_CONTAINS(out1, "G.simbatch:9: HIDDEN is the width of "
			     "GENETIC's and ANNEALING's hidden layers");
	/* and 0 is no width */
	cli_sh("sed -i 's/HIDDEN:3/HIDDEN:0/' %s", path);
	CHECK(cli_capture(out1, sizeof out1, "%s check %s", cli_evo, path) !=
	      0);
	CHECK_CONTAINS(out1, "HIDDEN");
}

int main(void)
{
	if (cli_setup("check"))
		return 1;
	RUN(nog_is_evo_run_headless);
	RUN(a_task_path_alone_is_evo_run);
	RUN(check_passes_the_shipped_tasks);
	RUN(check_fails_on_a_misspelled_bot_model_or_environment);
	RUN(check_fails_on_a_botdesc_sensor_the_bot_lacks);
	RUN(check_refuses_a_type_evo_run_cannot_run_yet);
	RUN(type_is_read_in_any_case);
	RUN(a_botname_of_another_agent_is_warned_at_its_line);
	RUN(a_tasks_threads_key_sets_the_workers);
	RUN(hidden_sets_the_width_of_genetic_networks);
	RUN(the_viewer_runs_episodes_until_it_is_closed);
	RUN(a_screenshot_without_a_window_is_drawn_off_screen);
	RUN(a_demo_episode_lasts_ticklim_ticks);
	cli_cleanup();
	return test_summary();
}
