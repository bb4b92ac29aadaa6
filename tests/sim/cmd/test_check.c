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

TEST(check_knows_openended_and_3d_tasks)
{
	/* OPENENDED (docs/openended.md): LEARNINGSKILL required, its OPEN_
	 * keys checked at their lines */
	avoid_with_task("T.simbatch", "TYPE:OPENENDED\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1, "OPENENDED task needs the key LEARNINGSKILL");
	avoid_with_task("T.simbatch", "TYPE:OPENENDED\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nLEARNINGSKILL:Avoid\n"
				      "NUMGEN:3\nENV:Roam\nOPEN_ENVZ:3\n");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1, "T.simbatch:7: unknown key OPEN_ENVZ; did you "
			     "mean OPEN_ENVS? (OPENENDED takes ");
	/* a 3D task runs, and a 2D environment in it says what is wrong */
	avoid_with_task("T.simbatch", "TYPE:DEMO3DSIM\nBOTMODEL:BotType8\n"
				      "MASTERSKILL:Avoid\nENV:Roam\n");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s/Avoid/Tasks/"
						    "T.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out1, "Roam.lua:20: scene:grid: grid is 2D only, and "
			     "this is a 3D scene (docs/lua.md, \"Which world "
			     "has what\")");
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
	/* a warning fails evo check, which ends with the count */
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out1, "T.simbatch:5: BOTNAME is T6-NEAT, but the "
			     "task's mind folder is Avoid");
	CHECK_CONTAINS(out1, "master skill Avoid: not ok, 1 warning above");
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
	 * up, until SIGTERM closes it (timeout's 124). Under the sanitizers
	 * the leak check is off for this one process: LeakSanitizer's
	 * stop-the-world at the exit of a SIGTERMed viewer has hung there
	 * (its tracer waiting on a thread that never stopped), and -k makes
	 * any hang a failure, not a stalled test run. */
	int rc = cli_capture(out1, sizeof out1,
			     "xvfb-run -a sh -c 'ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}"
			     "detect_leaks=0 timeout -k 30 -s TERM 3 %s run " DEMO
			     " --ticks 5; echo \"exit $?\"'",
			     cli_evo);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out1, "episode 1: reward ");
	CHECK_CONTAINS(out1, "episode 3: reward ");
	CHECK_CONTAINS(out1, "exit 124");
	/* --episodes still bounds it */
	rc = cli_capture(out1, sizeof out1,
			 "xvfb-run -a sh -c 'timeout -k 30 -s TERM 20 %s run " DEMO
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
	CHECK_CONTAINS(out1, "G.simbatch:9: HIDDEN is the width of the "
			     "hidden layers of GENETIC, ANNEALING and CMAES");
	/* and 0 is no width */
	cli_sh("sed -i 's/HIDDEN:3/HIDDEN:0/' %s", path);
	CHECK(cli_capture(out1, sizeof out1, "%s check %s", cli_evo, path) !=
	      0);
	CHECK_CONTAINS(out1, "HIDDEN");
}

/* ---- every key's range, one check for evo check and evo run ---------- */

/* A learning task of minds/XOR (no world: quick) with METHOD and, on its
 * line 8, LINE. Its path is in path (cap bytes). */
static void xor_task(char *path, size_t cap, const char *method,
		     const char *line)
{
	cli_sh("rm -rf %s/XOR %s/r && cp -r minds/XOR %s/", cli_tmp, cli_tmp,
	       cli_tmp);
	snprintf(path, cap, "%s/XOR/Tasks/K.simbatch", cli_tmp);
	char text[1024];
	snprintf(text, sizeof text,
		 "TYPE:LEARNSIM\nBOTMODEL:none\nMASTERSKILL:XOR\n"
		 "LEARNINGSKILL:XOR\nENV:XOR\nLEARNINGMETHOD:%s\nNUMGEN:1\n"
		 "%s\n",
		 method, line);
	cli_write(text, "%s", path);
}

/* evo check accepts LINE in a METHOD task. */
static int accepted(const char *method, const char *line)
{
	char path[512];
	xor_task(path, sizeof path, method, line);
	int rc = cli_capture(out1, sizeof out1, "%s check %s", cli_evo, path);
	if (rc != 0)
		printf("  %s: %s", line, out1);
	return rc == 0;
}

/* evo check and evo run both refuse LINE in a METHOD task, at its line
 * with what, and evo run does so at once: within seconds, before a run
 * folder exists (so before a thread, a population or an episode). */
static int refused(const char *method, const char *line, const char *what)
{
	char path[512], want[600];
	xor_task(path, sizeof path, method, line);
	snprintf(want, sizeof want, "K.simbatch:8: %s", what);
	int ok = 1;
	int rc = cli_capture(out1, sizeof out1, "%s check %s", cli_evo, path);
	if (rc != 1 || !strstr(out1, want)) {
		printf("  evo check, %s: exit %d: %s", line, rc, out1);
		ok = 0;
	}
	rc = cli_capture(out2, sizeof out2,
			 "timeout 20 %s run %s --run %s/r --threads 1",
			 cli_evo, path, cli_tmp);
	if (rc != 1 || !strstr(out2, want)) {
		printf("  evo run, %s: exit %d: %s", line, rc, out2);
		ok = 0;
	}
	char *log = cli_read("%s/r/log.csv", cli_tmp);
	if (log) {
		printf("  evo run, %s: a run folder was made\n", line);
		free(log);
		ok = 0;
	}
	return ok;
}

/* The issue's values: each stopped evo run only after it had grown to
 * all the machine's memory (HIDDEN, NEAT_POPSIZE) or hung
 * (NEAT_ADD_LINK_TRIES), or after the threads had started (THREADS),
 * naming no line, while evo check passed them. */
TEST(the_issues_huge_keys_are_refused_at_their_line)
{
	CHECK(refused("GENETIC", "HIDDEN:2147483647",
		      "HIDDEN: expected a whole number from 1 to 256, found "
		      "'2147483647'"));
	CHECK(refused("NEAT", "NEAT_POPSIZE:99999999999",
		      "NEAT_POPSIZE: expected a whole number from 1 to 10000, "
		      "found '99999999999'"));
	CHECK(refused("NEAT", "NEAT_ADD_LINK_TRIES:99999999999",
		      "NEAT_ADD_LINK_TRIES: expected a whole number from 0 to "
		      "1000, found '99999999999'"));
	CHECK(refused("NEAT", "THREADS:2147483647",
		      "THREADS: expected a whole number from 1 to 1024, found "
		      "'2147483647'"));
	CHECK(refused("NEAT", "REMOTETIMEOUT:soon",
		      "REMOTETIMEOUT: expected a number above 0 and at most "
		      "3600, found 'soon'"));
	CHECK(refused("NEAT", "REMOTENAME:a/b",
		      "REMOTENAME: expected names of 1 to 63 letters, digits, "
		      "'_' or '-', joined by ',', found 'a/b'"));
}

/* Each kind of key, a value just inside its range and one just outside. */
TEST(every_kind_of_key_is_checked_just_inside_and_outside_its_range)
{
	/* a whole number of the task: 1..1024 threads, 1..10000 networks */
	CHECK(accepted("NEAT", "THREADS:1024"));
	CHECK(refused("NEAT", "THREADS:1025", "THREADS: expected a whole"));
	CHECK(refused("NEAT", "THREADS:0", "THREADS: expected a whole"));
	CHECK(accepted("NEAT", "POPSIZE:10000"));
	CHECK(refused("NEAT", "POPSIZE:10001", "POPSIZE: expected a whole"));
	CHECK(accepted("NEAT", "EVALREP:1000"));
	CHECK(refused("NEAT", "EVALREP:1001", "EVALREP: expected a whole"));
	/* a number of the task: seconds, more than 0, at most an hour */
	CHECK(accepted("NEAT", "REMOTETIMEOUT:3600"));
	CHECK(accepted("NEAT", "REMOTETIMEOUT:0.000001"));
	CHECK(refused("NEAT", "REMOTETIMEOUT:3600.000001",
		      "REMOTETIMEOUT: expected a number above 0"));
	CHECK(refused("NEAT", "REMOTETIMEOUT:0", "REMOTETIMEOUT: expected"));
	CHECK(accepted("NEAT", "TARGETFITNESS:-15.5"));
	CHECK(refused("NEAT", "TARGETFITNESS:9.x",
		      "TARGETFITNESS: expected a number from"));
	/* a name: 63 characters, not 64 */
	char line[128];
	snprintf(line, sizeof line, "REMOTENAME:%.63s",
		 "sim-0123456789abcdefghijklmnopqrstuvwxyz_ABCDEFGHIJKLMNOPQRSTUVW"
		 "XYZ");
	CHECK(accepted("NEAT", line));
	snprintf(line, sizeof line, "REMOTENAME:%.64s",
		 "sim-0123456789abcdefghijklmnopqrstuvwxyz_ABCDEFGHIJKLMNOPQRSTUVW"
		 "XYZ");
	CHECK(refused("NEAT", line, "REMOTENAME: expected names"));
	/* a word */
	CHECK(accepted("NEAT", "TEAMFITNESS:own"));
	CHECK(refused("NEAT", "TEAMFITNESS:MINE",
		      "TEAMFITNESS: expected TEAM or OWN, found 'MINE'"));
	/* a learning method's own keys */
	CHECK(accepted("NEAT", "NEAT_POPSIZE:10000"));
	CHECK(refused("NEAT", "NEAT_POPSIZE:10001", "NEAT_POPSIZE: expected"));
	CHECK(accepted("NEAT", "NEAT_ADD_LINK_TRIES:1000"));
	CHECK(refused("NEAT", "NEAT_ADD_LINK_TRIES:1001",
		      "NEAT_ADD_LINK_TRIES: expected"));
	CHECK(accepted("GENETIC", "GA_TOURNAMENT:10000"));
	CHECK(refused("GENETIC", "GA_TOURNAMENT:10001",
		      "GA_TOURNAMENT: expected a whole number from 1 to 10000"));
	CHECK(accepted("ANNEALING", "SA_STEPS_PER_GENERATION:10000"));
	CHECK(refused("ANNEALING", "SA_STEPS_PER_GENERATION:10001",
		      "SA_STEPS_PER_GENERATION: expected a whole number from 1 "
		      "to 10000"));
	CHECK(refused("ANNEALING", "SA_ALPHA:1.5",
		      "SA_ALPHA: expected a number above 0 and at most 1"));
	CHECK(accepted("CMAES", "CMAES_POPSIZE:10000"));
	CHECK(refused("CMAES", "CMAES_POPSIZE:10001",
		      "CMAES_POPSIZE: expected a whole number from 1 to 10000"));
	CHECK(accepted("CMAES", "CMAES_SIGMA:0.000001"));
	CHECK(refused("CMAES", "CMAES_SIGMA:0",
		      "CMAES_SIGMA: expected a number above 0, found '0'"));
	CHECK(refused("CMAES", "CMAES_SIGMA_MIN:0.6",
		      "CMAES_SIGMA_MIN: 0.6 is more than the initial step "
		      "size CMAES_SIGMA (0.5)"));
	CHECK(refused("CMAES", "CMAES_HIDDEN_ACT:relu",
		      "CMAES_HIDDEN_ACT: expected sigmoid, tanh, found 'relu'"));
	CHECK(refused("CMAES", "CMAES_SEPARABLE:maybe",
		      "CMAES_SEPARABLE: expected auto, false, true, found "
		      "'maybe'"));
	CHECK(refused("CMAES", "CMAES_RESTARTS:1001",
		      "CMAES_RESTARTS: expected a whole number from 0 to 1000"));
}

/* HIDDEN within its range can still make a network larger than evo's
 * networks hold: refused at HIDDEN's line before a population of such
 * networks is made. XOR with layers:2 has 2 inputs and 1 output: HIDDEN
 * W gives 2W + W^2 + W links, 4030 for 62 (at most 4096) and 4158 for
 * 63. */
/* A remote task's connection keys: evo check refuses what evo run would
 * (a URL that is no multicast group, a key file it cannot read, a task
 * that names no remote and has no key), and passes the shipped one. */
TEST(check_refuses_a_remote_tasks_url_key_file_and_missing_names)
{
	const char *cases[][2] = {
	    {"REMOTENAME:corridor\nLCMURL:file:///tmp/x?mode=w", "LCMURL: "},
	    {"REMOTENAME:corridor\nLCMKEYFILE:no-such.key", "LCMKEYFILE: "},
	    {"", "names its remotes (REMOTENAME"},
	};
	char path[512];
	snprintf(path, sizeof path, "%s/Corridor/Tasks/K.simbatch", cli_tmp);
	for (unsigned i = 0; i < sizeof cases / sizeof *cases; i++) {
		cli_sh("rm -rf %s/Corridor && cp -r minds/Corridor %s/", cli_tmp,
		       cli_tmp);
		char text[512];
		snprintf(text, sizeof text,
			 "TYPE:DEMOREMOTESIM\nMASTERSKILL:Corridor\n%s\n",
			 cases[i][0]);
		cli_write(text, "%s", path);
		int rc = cli_capture(out1, sizeof out1, "%s check %s", cli_evo,
				     path);
		CHECK_EQ_INT(rc, 1);
		CHECK_CONTAINS(out1, cases[i][1]);
		rc = cli_capture(out2, sizeof out2, "timeout 20 %s run %s", cli_evo,
				 path);
		CHECK_EQ_INT(rc, 1);
		CHECK_CONTAINS(out2, cases[i][1]);
	}
	/* the last case's message, word for word as docs/remote.md shows it */
	CHECK_CONTAINS(out1,
		       "K.simbatch: a remote task names its remotes "
		       "(REMOTENAME:sim1 or REMOTENAME:sim1,sim2) or shares a "
		       "key with them (LCMKEYFILE); without either, any process "
		       "on udpm://239.255.76.67:7667?ttl=0 could pass for its "
		       "remote (docs/remote.md)");
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s", cli_evo,
				 "minds/Corridor/Tasks/Corridor-DEMO.simbatch"),
		     0);
}

TEST(hidden_that_makes_too_large_a_network_is_refused_at_its_line)
{
	char path[512];
	xor_task(path, sizeof path, "GENETIC", "HIDDEN:62");
	cli_sh("sed -i 's/layers:0/layers:2/' %s/XOR/Skills/XOR/XOR.ades && "
	       "rm -f %s/XOR/Skills/XOR/XOR.net",
	       cli_tmp, cli_tmp);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s", cli_evo,
				 path),
		     0);
	cli_sh("sed -i 's/HIDDEN:62/HIDDEN:63/' %s", path);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s check %s", cli_evo,
				 path),
		     1);
	CHECK_CONTAINS(out1, "K.simbatch:8: HIDDEN:63: XOR's network, 2 "
			     "inputs, 2 hidden layers of 63 nodes and 1 "
			     "output, is larger than a network of evo holds");
	CHECK_EQ_INT(cli_capture(out2, sizeof out2,
				 "timeout 20 %s run %s --run %s/r", cli_evo,
				 path, cli_tmp),
		     1);
	CHECK_CONTAINS(out2, "K.simbatch:8: HIDDEN:63: XOR's network");
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
	RUN(check_knows_openended_and_3d_tasks);
	RUN(type_is_read_in_any_case);
	RUN(a_botname_of_another_agent_is_warned_at_its_line);
	RUN(a_tasks_threads_key_sets_the_workers);
	RUN(hidden_sets_the_width_of_genetic_networks);
	RUN(the_issues_huge_keys_are_refused_at_their_line);
	RUN(every_kind_of_key_is_checked_just_inside_and_outside_its_range);
	RUN(hidden_that_makes_too_large_a_network_is_refused_at_its_line);
	RUN(check_refuses_a_remote_tasks_url_key_file_and_missing_names);
	RUN(the_viewer_runs_episodes_until_it_is_closed);
	RUN(a_screenshot_without_a_window_is_drawn_off_screen);
	RUN(a_demo_episode_lasts_ticklim_ticks);
	cli_cleanup();
	return test_summary();
}
