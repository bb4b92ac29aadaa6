/* DEMO3DSIM and LEARN3DSIM end to end through `evo run` (docs/world3d.md):
 * both built-in 3D tasks run headless and the same seed gives the same
 * trace; LEARN3DSIM gives the same log and champion with one thread and
 * with two, a SIGKILLed run resumes to the same result, and the champion
 * beats untrained networks on unseen episodes; a body that explodes ends
 * its episode with a message and a penalty; a wrong key in a 3D option
 * table is an error naming the file, the line and the known keys; the
 * shipped waypoint course, scored by a Lua reward and post_step, pays what
 * its rules say. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/view3d.h"
#include "viewer/viewer.h"

static char out[65536];

/* A copy of mind folder `mind` under `name`, with task Small.simbatch of
 * the given lines. */
static void make_task(const char *name, const char *mind, const char *lines)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/%s %s/%s/ && "
			    "printf '%s' > %s/%s/%s/Tasks/Small.simbatch",
			    cli_tmp, name, mind, cli_tmp, name, lines, cli_tmp,
			    name, mind),
		     0);
}

static int run(const char *name, const char *mind, const char *extra)
{
	return cli_capture(out, sizeof out,
			   "%s run %s/%s/%s/Tasks/Small.simbatch %s 2>&1",
			   cli_evo, cli_tmp, name, mind, extra);
}

#define AVOID_DEMO                                                             \
	"TYPE:DEMO3DSIM\\nBOTMODEL:Wheeled3D\\nMASTERSKILL:Avoid3D\\n"         \
	"ENV:EXP3D_Avoid\\nTICKLIM:300\\n"
#define GTT_DEMO                                                               \
	"TYPE:DEMO3DSIM\\nBOTMODEL:Blimp3D\\nMASTERSKILL:GoToTarget\\n"        \
	"ENV:EXP3D_GoToTarget\\nTICKLIM:300\\n"

/* Both tasks headless: one line an episode, and a trace that two runs of
 * one seed give byte for byte and another seed changes. */
TEST(both_3d_tasks_run_headless_and_one_seed_gives_one_trace)
{
	const char *mind[2] = {"Wheeled3D", "Blimp3D"};
	const char *task[2] = {AVOID_DEMO, GTT_DEMO};
	for (int i = 0; i < 2; i++) {
		make_task("demo", mind[i], task[i]);
		char extra[512];
		snprintf(extra, sizeof extra,
			 "--headless --episodes 2 --trace %s/demo/a.trace",
			 cli_tmp);
		CHECK_EQ_INT(run("demo", mind[i], extra), 0);
		CHECK_CONTAINS(out, "episode 1: reward ");
		CHECK_CONTAINS(out, "episode 2: reward ");
		CHECK(strstr(out, " over 300 ticks") || strstr(out, "over "));
		snprintf(extra, sizeof extra,
			 "--headless --episodes 2 --trace %s/demo/b.trace",
			 cli_tmp);
		CHECK_EQ_INT(run("demo", mind[i], extra), 0);
		snprintf(extra, sizeof extra,
			 "--headless --episodes 2 --seed 7 --trace "
			 "%s/demo/c.trace",
			 cli_tmp);
		CHECK_EQ_INT(run("demo", mind[i], extra), 0);
		char *a = cli_read("%s/demo/a.trace", cli_tmp);
		char *b = cli_read("%s/demo/b.trace", cli_tmp);
		char *c = cli_read("%s/demo/c.trace", cli_tmp);
		CHECK(a && b && c);
		if (a && b && c) {
			CHECK(cli_count_lines(a, "") > 300);
			CHECK_EQ_STR(a, b);
			CHECK(strcmp(a, c) != 0);
		}
		free(a);
		free(b);
		free(c);
		CHECK_EQ_INT(cli_sh("rm -rf %s/demo", cli_tmp), 0);
	}
}

#define GTT_LEARN                                                              \
	"TYPE:LEARN3DSIM\\nBOTMODEL:Blimp3D\\nMASTERSKILL:GoToTarget\\n"       \
	"LEARNINGSKILL:GoToTarget\\nENV:EXP3D_GoToTarget\\n"                   \
	"LEARNINGMETHOD:NEAT\\nNEAT_POPSIZE:20\\nNUMGEN:%d\\nEVALREP:2\\n"     \
	"TICKLIM:%d\\n"

static void make_learn(const char *name, int gens, int ticks)
{
	char lines[512];
	snprintf(lines, sizeof lines, GTT_LEARN, gens, ticks);
	make_task(name, "Blimp3D", lines);
}

static int train(const char *name, const char *extra)
{
	char more[512];
	snprintf(more, sizeof more, "--seed 5 --run %s/%s/run %s", cli_tmp,
		 name, extra);
	return run(name, "Blimp3D", more);
}

static char *log_of(const char *name)
{
	char dir[256];
	snprintf(dir, sizeof dir, "%s/%s/run", cli_tmp, name);
	return cli_fitness_log(dir);
}

static char *champion_of(const char *name)
{
	return cli_read("%s/%s/Blimp3D/Skills/GoToTarget/GoToTarget.net",
			cli_tmp, name);
}

/* The figure after `label` in the replay report, e.g. "champion:". */
static double figure(const char *text, const char *label)
{
	const char *p = strstr(text, label);
	if (!p)
		return -1e300;
	p = strstr(p, "fitness");
	return p ? strtod(p + 7, NULL) : -1e300;
}

/* One thread and two: the same log and champion; the champion, replayed
 * on episodes it never saw, scores above the untrained networks' mean. */
TEST(learn3dsim_threads_agree_and_the_champion_beats_untrained_networks)
{
	make_learn("t1", 3, 150);
	make_learn("t2", 3, 150);
	CHECK_EQ_INT(train("t1", "--threads 1"), 0);
	CHECK_EQ_INT(train("t2", "--threads 2"), 0);
	double champ = figure(out, "champion:");
	double untrained = figure(out, "untrained networks");
	printf("  replay: champion %.1f, untrained %.1f\n", champ, untrained);
	CHECK(champ > -1e300 && untrained > -1e300);
	CHECK(champ > untrained);
	char *a = log_of("t1"), *b = log_of("t2");
	CHECK(a && b);
	if (a && b) {
		CHECK_CONTAINS(a, "\n2,");
		CHECK_EQ_STR(a, b);
	}
	char *ca = champion_of("t1"), *cb = champion_of("t2");
	CHECK(ca && cb);
	if (ca && cb) {
		CHECK_CONTAINS(ca, "trained by evo: NEAT, seed 5");
		CHECK_EQ_STR(ca, cb);
	}
	free(a);
	free(b);
	free(ca);
	free(cb);
}

static int rows(const char *name)
{
	char *t = cli_read("%s/%s/run/log.csv", cli_tmp, name);
	int n = -1;
	for (const char *p = t; p && *p; p++)
		n += *p == '\n';
	free(t);
	return n;
}

/* Killed with SIGKILL once generation 1 is logged, then resumed: the
 * same log and champion as the run never interrupted. */
TEST(a_sigkilled_learn3dsim_run_resumes_to_the_same_result)
{
	make_learn("kr", 5, 400);
	make_learn("k", 5, 400);
	CHECK_EQ_INT(train("kr", "--threads 2"), 0);
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/k/Blimp3D/Tasks/Small.simbatch --seed 5 "
		 "--threads 2 --run %s/k/run > %s/k/out1.txt 2>&1",
		 cli_evo, cli_tmp, cli_tmp, cli_tmp);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	struct timespec ms = {0, 2000000};
	for (int i = 0; i < 20000 && rows("k") < 2; i++)
		nanosleep(&ms, NULL);
	kill(pid, SIGKILL);
	int st;
	waitpid(pid, &st, 0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	CHECK(rows("k") >= 2 && rows("k") < 5); /* it really was cut short */
	CHECK_EQ_INT(train("k", "--threads 2 --resume"), 0);
	CHECK_CONTAINS(out, "resuming after generation");
	char *a = log_of("kr"), *b = log_of("k");
	CHECK(a && b);
	if (a && b)
		CHECK_EQ_STR(b, a);
	char *ca = champion_of("kr"), *cb = champion_of("k");
	CHECK(ca && cb);
	if (ca && cb)
		CHECK_EQ_STR(cb, ca);
	free(a);
	free(b);
	free(ca);
	free(cb);
}

/* A bot model whose propellers push 1e7 N: the body runs away in the
 * first tick; the episode ends there, says so, and pays the penalty. */
TEST(an_exploding_robot_ends_its_episode_with_a_message_and_a_penalty)
{
	make_task("boom", "Blimp3D", GTT_DEMO);
	CHECK_EQ_INT(cli_sh("mkdir -p %s/boom/Blimp3D/Bots && sed "
			    "'s/max_thrust = 6/max_thrust = 1e7/' "
			    "lua/bots/Blimp3D.lua > "
			    "%s/boom/Blimp3D/Bots/Blimp3D.lua",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(run("boom", "Blimp3D", "--headless --episodes 2"), 0);
	CHECK_CONTAINS(out, "episode 1: reward -10");
	CHECK_CONTAINS(out, "over 1 ticks");
	CHECK_CONTAINS(out, "fault: bot1 exploded at tick 1: it ");
	CHECK_CONTAINS(out, "the episode ends with a penalty of -1000");
	CHECK_EQ_INT(cli_count_lines(out, "  fault: "), 2);
}

/* A wrong key in an environment's or a bot model's option table. */
TEST(a_wrong_key_in_a_3d_option_table_names_file_line_and_keys)
{
	make_task("keys", "Blimp3D", GTT_DEMO);
	CHECK_EQ_INT(
	    cli_sh("mkdir -p %s/keys/Blimp3D/Envs && printf "
		   "'local e = {}\\nfunction e.init(scene)\\n  "
		   "scene:bot{ x = 0, hight = 2 }\\nend\\nreturn e\\n' "
		   "> %s/keys/Blimp3D/Envs/EXP3D_GoToTarget.lua",
		   cli_tmp, cli_tmp),
	    0);
	CHECK_EQ_INT(run("keys", "Blimp3D", "--headless"), 1);
	CHECK_CONTAINS(out,
		       "EXP3D_GoToTarget.lua:3: scene:bot: unknown "
		       "option 'hight' (known: name, x, y, z, yaw, model, team)");
	CHECK_EQ_INT(cli_sh("rm -r %s/keys/Blimp3D/Envs && mkdir -p "
			    "%s/keys/Blimp3D/Bots && sed 's/drag_linear/drag/' "
			    "lua/bots/Blimp3D.lua > "
			    "%s/keys/Blimp3D/Bots/Blimp3D.lua",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(run("keys", "Blimp3D", "--headless"), 1);
	CHECK_CONTAINS(out, "Bots/Blimp3D.lua: hull: unknown option 'drag'");
}

/* Pixels of the world area (left of the panel) that `is` accepts. */
static long count(const evo_png_image *im, int (*is)(int r, int g, int b))
{
	long n = 0;
	for (int y = 0; y < im->h; y++)
		for (int x = 0; x < im->w - EVO_VIEW_PANEL_W; x++) {
			const uint8_t *p =
			    im->pixels + 3 * ((size_t)y * im->w + x);
			n += is(p[0], p[1], p[2]);
		}
	return n;
}

/* The rays are unshaded: EVO_VIEW_RAY_HIT exactly where they hit,
 * EVO_VIEW3D_RAY_CLEAR where they do not. */
static int ray(int r, int g, int b)
{
	uint32_t c = (uint32_t)r << 16 | (uint32_t)g << 8 | (uint32_t)b;
	return c == EVO_VIEW_RAY_HIT || c == EVO_VIEW3D_RAY_CLEAR;
}
/* The shaded bodies by their hue: the robot blue, obstacles a mid grey
 * (the ground is lighter, the wheels darker), the target amber. */
static int robot(int r, int g, int b)
{
	return b > r + 60 && b > g + 30;
}
static int obstacle(int r, int g, int b)
{
	return abs(r - g) < 8 && abs(g - b) < 8 && r > 60 && r < 170;
}
static int target(int r, int g, int b)
{
	return r > 150 && g > 90 && g < r - 30 && b < 90;
}

/* Both tasks in the 3D view under a virtual X display (Mesa's llvmpipe):
 * the screenshot at tick 45 shows the robot, its rays and obstacles (the
 * wheeled robot's), the robot, its rays and its target (the blimp's), and
 * the panel's sensor bars; without a display the screenshot is drawn off
 * screen (tests/sim/viewer/test_view3d.c looks at it). */
TEST(both_3d_tasks_show_in_the_3d_view)
{
	static const char *const task[2] = {
	    "minds/Wheeled3D/Tasks/Avoid3D-DEMO.simbatch",
	    "minds/Blimp3D/Tasks/GoToTarget-DEMO.simbatch"};
	for (int k = 0; k < 2; k++) {
		char png[512];
		snprintf(png, sizeof png, "%s/view%d.png", cli_tmp, k);
		int rc = cli_capture(out, sizeof out,
				     "xvfb-run -a -s '-screen 0 1280x800x24' "
				     "sh -c '%s run %s --ticks 45 "
				     "--screenshot %s' 2>&1",
				     cli_evo, task[k], png);
		CHECK_EQ_INT(rc, 0);
		if (rc)
			printf("  %s\n", out);
		CHECK_CONTAINS(out, "(tick 45)");
		evo_png_image im;
		evo_err err = {{0}};
		CHECK_EQ_INT(evo_png_read(png, &im, &err), 0);
		if (!im.pixels)
			continue;
		long n_robot = count(&im, robot), n_ray = count(&im, ray);
		long n_obst = count(&im, obstacle), n_targ = count(&im, target);
		printf("  %s: robot %ld, ray %ld, obstacle %ld, target %ld "
		       "pixels\n",
		       task[k], n_robot, n_ray, n_obst, n_targ);
		CHECK(n_robot > 300);
		CHECK(n_ray > 20);
		if (k == 0) {
			CHECK(n_obst > 1000);
		} else {
			CHECK(n_targ > 20);
		}
		long bars = 0;
		for (int y = 0; y < im.h; y++)
			for (int x = im.w - EVO_VIEW_PANEL_W; x < im.w; x++) {
				const uint8_t *p =
				    im.pixels + 3 * ((size_t)y * im.w + x);
				bars += ((uint32_t)p[0] << 16 |
					 (uint32_t)p[1] << 8 | p[2]) ==
					EVO_VIEW_SENSOR_BAR;
			}
		CHECK(bars > 100);
		evo_png_image_free(&im);
	}
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "env -u DISPLAY -u WAYLAND_DISPLAY %s run %s "
				 "--ticks 5 --screenshot %s/x.png 2>&1",
				 cli_evo, task[0], cli_tmp),
		     0);
	CHECK_CONTAINS(out, "(tick 5, drawn without a window)");
}

/* The shipped waypoint course (minds/Blimp3D/Envs/EXP3D_Waypoints.lua: a
 * Lua reward, a Lua control and post_step). Hand-worked: the robot starts
 * inside the first waypoint, so tick 1 pays 10 - 0.01 = 9.99; post_step
 * then moves the target 4 m away, so ticks 2 to 5 pay the clock alone:
 * 9.95 after 5 (without post_step every tick would pay 10 more: 49.95).
 * The whole course: the Lua control ends it once the 4 waypoints are
 * passed (the metric `waypoints` counts them), before TICKLIM, with 4 x
 * 10 - 0.01 a tick paid. */
TEST(a_3d_course_scored_by_lua_and_post_step_pays_hand_worked_values)
{
	const char *task = "minds/Blimp3D/Tasks/Waypoints-DEMO.simbatch";
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s --headless "
				 "--ticks 1 2>&1",
				 cli_evo, task),
		     0);
	CHECK_CONTAINS(out, "episode 1: reward 9.990000 over 1 ticks, 0 "
			    "collision ticks, waypoints 1");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s --headless "
				 "--ticks 5 2>&1",
				 cli_evo, task),
		     0);
	CHECK_CONTAINS(out, "episode 1: reward 9.950000 over 5 ticks, 0 "
			    "collision ticks, waypoints 1");
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s run %s --headless 2>&1",
				 cli_evo, task),
		     0);
	double reward = 0;
	long ticks = 0;
	int passed = 0, hits = 0;
	CHECK_EQ_INT(sscanf(out,
			    "episode 1: reward %lf over %ld ticks, %d "
			    "collision ticks, waypoints %d",
			    &reward, &ticks, &hits, &passed),
		     4);
	printf("  the course: %.6f over %ld ticks, %d waypoints\n", reward,
	       ticks, passed);
	CHECK_EQ_INT(passed, 4);
	CHECK(ticks > 5 && ticks < 1800);
	CHECK(fabs(reward - (40 - 0.01 * (double)ticks)) < 1e-6);
}

int main(void)
{
	if (cli_setup("run3d"))
		return 1;
	RUN(both_3d_tasks_run_headless_and_one_seed_gives_one_trace);
	RUN(both_3d_tasks_show_in_the_3d_view);
	RUN(a_3d_course_scored_by_lua_and_post_step_pays_hand_worked_values);
	RUN(learn3dsim_threads_agree_and_the_champion_beats_untrained_networks);
	RUN(a_sigkilled_learn3dsim_run_resumes_to_the_same_result);
	RUN(an_exploding_robot_ends_its_episode_with_a_message_and_a_penalty);
	RUN(a_wrong_key_in_a_3d_option_table_names_file_line_and_keys);
	cli_cleanup();
	return test_summary();
}
