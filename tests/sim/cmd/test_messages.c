/* What evo says to a newcomer (issue 31, "Messages and options"): every
 * command answers --help with its own page on stdout and exit 0, before
 * looking at its other arguments; evo --version and evo version name
 * evo's and Lua's versions; `evo run --ticks 0` is refused with the way
 * to get TICKLIM instead of silently meaning it. A learning run's
 * progress line is rewritten in place ('\r') only when the output ends
 * at a terminal, by the same rule with and without mpirun: `mpirun ...
 * > file` writes plain lines as `evo run > file` does (a rank's own
 * stdout is a terminal mpirun made), and both rewrite under a terminal
 * (script(1) gives them one). The run's curve.png is titled with the
 * skill, task, method and seed. `evo info MIND --dot` draws the hierarchy
 * and `--dot SKILL` a network as Graphviz DOT, which -o FILE.png and
 * FILE.svg render with Graphviz's dot (make deps installs graphviz).
 * `evo run --record` saves a run's frames without a window, as PNG files
 * (the last one the --screenshot of the same tick) or as a video made by
 * ffmpeg, with --camera and --zoom. A --screenshot taken in the viewer's
 * window (under xvfb-run) names the file it wrote, as a headless one
 * does. evo check warns of HIDDEN on a NEAT task, at its line, as evo
 * run does, and evo run says it once. A Lua reward that returns a string
 * that reads as a number ("1.5") ends the run at the function's line.
 * A misspelt ENV, BOTMODEL or MASTERSKILL (in the wrong case too) is
 * reported at the task's line, with the name meant; so are a misspelt
 * scene:control or scene:reward name and a sensor bot:target names, at
 * the environment's line; an unknown option of a bot model's body table
 * is reported at the body's line in the model's file, with the option
 * meant. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"
#include "learn/curve.h"
#include "viewer/png.h"
#include "viewer/raster.h"

static char out[1 << 15];

/* `evo CMD --help` (and with other arguments before it) prints a page
 * that starts with usage and names the command. */
static void help_of(const char *cmd, const char *args)
{
	char want[64];
	int rc = cli_capture(out, sizeof out, "%s %s %s --help 2>/dev/null",
			     cli_evo, cmd, args);
	CHECK_EQ_INT(rc, 0);
	CHECK(strncmp(out, "usage", 5) == 0);
	snprintf(want, sizeof want, "evo %s", cmd);
	CHECK_CONTAINS(out, want);
	if (rc != 0 || strncmp(out, "usage", 5) != 0)
		fprintf(stderr, "    evo %s %s --help: %s\n", cmd, args, out);
}

TEST(every_command_has_help)
{
	const char *cmds[] = {"run",   "serve", "info",  "check",
			      "tick",  "export", "flash"};
	for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
		help_of(cmds[i], "");
		help_of(cmds[i], "minds/Avoid");
		help_of(cmds[i], "no/such/thing.simbatch");
	}
	/* the page is the command's, not evo's whole list */
	cli_capture(out, sizeof out, "%s info --help", cli_evo);
	CHECK(strstr(out, "evo serve") == NULL);
	CHECK_CONTAINS(out, "--master SKILL");
	cli_capture(out, sizeof out, "%s help tick", cli_evo);
	CHECK_CONTAINS(out, "--sensor NAME=VALUE");
	/* the tutorial's form is evo run's */
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s -nog --help", cli_evo),
		     0);
	CHECK_CONTAINS(out, "usage: evo run");
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s help nope", cli_evo), 2);
	CHECK_CONTAINS(out, "unknown command 'nope'");
}

TEST(version_is_printed)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s --version", cli_evo), 0);
	CHECK(strncmp(out, "evo 0.", 6) == 0);
	CHECK_CONTAINS(out, "Lua 5.4");
	char again[256];
	snprintf(again, sizeof again, "%.200s", out);
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s version", cli_evo), 0);
	CHECK_EQ_STR(out, again);
}

TEST(ticks_zero_is_refused)
{
	int rc = cli_capture(out, sizeof out,
			     "%s run minds/Avoid/Tasks/Avoid-NEAT.simbatch "
			     "--headless --ticks 0",
			     cli_evo);
	CHECK_EQ_INT(rc, 2);
	CHECK_CONTAINS(out, "--ticks expects a whole number from 1, found "
			    "'0' (without --ticks an episode lasts the "
			    "task's TICKLIM)");
	CHECK(strstr(out, "reward") == NULL); /* no episode ran */
}

/* A copy of Avoid with a 3-generation NEAT task of 8 candidates. */
static void small_mind(void)
{
	CHECK_EQ_INT(cli_sh("cp -r minds/Avoid %s/ && printf 'TYPE:LEARNSIM\\n"
			    "BOTMODEL:BotType8\\nMASTERSKILL:Avoid\\n"
			    "LEARNINGSKILL:Avoid\\nENV:EXP_Avoid\\n"
			    "LEARNINGMETHOD:NEAT\\nNUMGEN:3\\nEVALREP:1\\n"
			    "TICKLIM:50\\nNEAT_POPSIZE:8\\n' > "
			    "%s/Avoid/Tasks/Small.simbatch",
			    cli_tmp, cli_tmp),
		     0);
}

/* Train the small task with `launch` before evo, through `wrap` ("%s"
 * or a script(1) line around it), its output in FILE; 1 when the file
 * holds a '\r' or an escape code. */
static int rewrites(const char *launch, int terminal, const char *file)
{
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "%s %s run %s/Avoid/Tasks/Small.simbatch --seed 3 "
		 "--threads 1 --run %s/run-%s",
		 launch, cli_evo, cli_tmp, cli_tmp, file);
	int rc = terminal ? cli_sh("script -qec '%s' /dev/null > %s/%s 2>&1",
				   cmd, cli_tmp, file)
			  : cli_sh("%s > %s/%s 2>&1", cmd, cli_tmp, file);
	CHECK_EQ_INT(rc, 0);
	char *t = cli_read("%s/%s", cli_tmp, file);
	CHECK(t != NULL);
	if (!t)
		return -1;
	CHECK_CONTAINS(t, "champion saved in");
	int r = strchr(t, '\r') != NULL || strchr(t, '\033') != NULL;
	/* script(1) turns each newline into \r\n: only a \r before
	 * something else is a rewrite */
	if (terminal) {
		r = 0;
		for (const char *p = t; (p = strchr(p, '\r')); p++)
			r |= p[1] != '\n';
	}
	free(t);
	return r;
}

/* The pixels at the curve's title are those of `title` drawn alone. */
static int curve_titled(const char *png, const char *title)
{
	evo_png_image img;
	evo_raster t;
	evo_err err = {{0}};
	int w = evo_raster_text_width(title, EVO_CURVE_TITLE_SCALE);
	int h = EVO_FONT_CELL_H * EVO_CURVE_TITLE_SCALE;
	if (evo_png_read(png, &img, &err))
		return 0;
	if (evo_raster_init(&t, w, h, &err)) {
		evo_png_image_free(&img);
		return 0;
	}
	evo_raster_clear(&t, EVO_CURVE_BACKGROUND);
	evo_raster_text(&t, 0, 0, title, EVO_CURVE_TEXT, EVO_CURVE_TITLE_SCALE);
	int same = 1;
	for (int y = 0; y < h - 2 * EVO_CURVE_TITLE_SCALE; y++)
		for (int x = 0; x < w; x++) {
			const uint8_t *p =
			    img.pixels + ((size_t)(EVO_CURVE_TITLE_Y + y) *
					      (size_t)img.w +
					  (size_t)(EVO_CURVE_TITLE_X + x)) *
					     (size_t)img.channels;
			uint32_t c = (uint32_t)p[0] << 16 |
				     (uint32_t)p[1] << 8 | p[2];
			same &= c == evo_raster_get(&t, x, y);
		}
	evo_raster_free(&t);
	evo_png_image_free(&img);
	return same;
}

TEST(progress_rewrites_only_at_a_terminal)
{
	small_mind();
	CHECK_EQ_INT(rewrites("", 0, "plain.txt"), 0);
	char png[256];
	snprintf(png, sizeof png, "%s/run-plain.txt/curve.png", cli_tmp);
	CHECK(curve_titled(png, "Avoid: Small (NEAT, seed 3)"));
	CHECK_EQ_INT(rewrites("mpirun --oversubscribe -np 1", 0, "mpi.txt"), 0);
	CHECK_EQ_INT(rewrites("", 1, "plain-tty.txt"), 1);
	CHECK_EQ_INT(rewrites("mpirun --oversubscribe -np 1", 1, "mpi-tty.txt"),
		     1);
}

TEST(info_draws_the_hierarchy_as_dot)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s info minds/Collect --dot",
				 cli_evo),
		     0);
	CHECK(strncmp(out, "digraph \"Collect\" {", 19) == 0);
	/* the master influences its three sub-skills */
	CHECK_CONTAINS(out, "\"skill:Collect\" -> \"skill:GTO+Avoid\"");
	CHECK_CONTAINS(out, "\"skill:Collect\" -> \"skill:GTDZ+Avoid\"");
	CHECK_CONTAINS(out, "\"skill:Collect\" -> \"skill:ClawControl\"");
	CHECK_CONTAINS(out, "\"skill:MoveForward\" [label=\"MoveForward\" + "
			    "\"\\nhardCoded MoveForward\"");
	CHECK_CONTAINS(out, "\"skill:ClawControl\" -> \"variable:HOLD\"");
	CHECK_CONTAINS(out, "\"skill:ClawControl\" -> \"actuator:EMAG\"");
	CHECK_CONTAINS(out, "\"sensor:RADOBJ\" -> \"skill:GTO+Avoid\"");
	/* sensors no skill reads are left out */
	CHECK(strstr(out, "\"sensor:S3\"") == NULL);
	CHECK(out[strlen(out) - 2] == '}');
}

TEST(info_draws_a_network_as_dot)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s info minds/Collect --dot GTO+Avoid",
				 cli_evo),
		     0);
	CHECK_CONTAINS(out, "GTO+Avoid: 4 inputs, 1 hidden, 3 outputs, 16 "
			    "links");
	/* node defaults, the hidden node 7 and the 16 links */
	CHECK_EQ_INT(cli_count_lines(out, "  n"), 1 + 1 + 16);
	CHECK_CONTAINS(out, "n0 [label=\"SE:S1\"");
	CHECK_CONTAINS(out, "n3 [label=\"SE:RADOBJ\"");
	CHECK_CONTAINS(out, "n5 [label=\"SK:TurnLeft\\nneat_sigmoid "
			    "-0.245\"");
	/* link:0:5:7.085906 and link:3:7:-5.49065 of the .net file */
	CHECK_CONTAINS(out, "n0 -> n5 [label=\"7.09\", color=\"#2F6FD0\"");
	CHECK_CONTAINS(out, "n3 -> n7 [label=\"-5.49\", color=\"#D03030\"");
	/* a hard-coded skill has no network; an unknown one is named */
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s info minds/Collect --dot TurnLeft",
				 cli_evo),
		     1);
	CHECK_CONTAINS(out, "TurnLeft is a hard-coded skill (class "
			    "TurnLeft); it has no network to draw");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s info minds/Collect --dot GTO", cli_evo),
		     1);
	CHECK_CONTAINS(out, "minds/Collect has no skill 'GTO' (its skills: "
			    "Collect");
}

TEST(info_renders_png_and_svg_with_graphviz)
{
	CHECK_EQ_INT(cli_sh("command -v dot > /dev/null"), 0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s info minds/Collect --dot -o %s/h.png",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "h.png: the hierarchy of minds/Collect");
	char *png = cli_read("%s/h.png", cli_tmp);
	CHECK(png && memcmp(png, "\x89PNG\r\n", 6) == 0);
	free(png);
	CHECK_EQ_INT(cli_sh("%s info minds/Collect --dot GTO+Avoid -o "
			    "%s/n.svg > /dev/null",
			    cli_evo, cli_tmp),
		     0);
	char *svg = cli_read("%s/n.svg", cli_tmp);
	CHECK(svg != NULL);
	CHECK_CONTAINS(svg, "<svg");
	CHECK_CONTAINS(svg, "SK:TurnLeft");
	free(svg);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s info minds/Collect --dot -o %s/h.jpeg",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "ends in .dot (DOT text) or .png, .svg or .pdf");
}


/* A skill not trained yet is drawn as its shape, every weight 0, and
 * evo says so (a newcomer took the drawing for a network). */
TEST(dot_of_an_untrained_skill_says_it_is_a_shape)
{
	CHECK_EQ_INT(cli_sh("cp -r minds/Collect %s/ && rm "
			    "%s/Collect/Skills/ClawControl/ClawControl.net",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s info %s/Collect --dot ClawControl",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "ClawControl has no network yet; this is its "
			    "shape, every weight 0");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s info minds/Collect --dot ClawControl",
				 cli_evo),
		     0);
	CHECK(strstr(out, "no network yet") == NULL);
}

/* A misspelt option of evo run names the one meant, not fifty lines of
 * usage; an option like none still gets the usage. */
TEST(a_misspelt_run_option_gets_a_did_you_mean)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run minds/Avoid/Tasks/Avoid-DEMO.simbatch "
				 "--tick 10",
				 cli_evo),
		     2);
	CHECK_CONTAINS(out, "unexpected argument '--tick'; did you mean "
			    "--ticks?");
	CHECK(strstr(out, "usage:") == NULL);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run minds/Avoid/Tasks/Avoid-DEMO.simbatch "
				 "--frobnicate",
				 cli_evo),
		     2);
	CHECK_CONTAINS(out, "usage: evo run");
}

#define DEMO "minds/Avoid/Tasks/Avoid-DEMO.simbatch"
#define MAZE_DEMO "minds/Maze/Tasks/MediumMaze-DEMO.simbatch"

/* Pixels of the world area (left of the panel) that differ between two
 * frames of the same size; -1 when one cannot be read. */
static long frames_differ(const char *a, const char *b)
{
	evo_png_image ia, ib;
	evo_err err = {{0}};
	if (evo_png_read(a, &ia, &err))
		return -1;
	if (evo_png_read(b, &ib, &err)) {
		evo_png_image_free(&ia);
		return -1;
	}
	long n = -1;
	if (ia.w == ib.w && ia.h == ib.h && ia.channels == ib.channels) {
		n = 0;
		for (int y = 0; y < ia.h; y++)
			for (int x = 0; x < 700 && x < ia.w; x++) {
				size_t k = ((size_t)y * (size_t)ia.w + (size_t)x) *
					   (size_t)ia.channels;
				n += memcmp(ia.pixels + k, ib.pixels + k, 3) != 0;
			}
	}
	evo_png_image_free(&ia);
	evo_png_image_free(&ib);
	return n;
}

/* --camera scene stays on the middle of the scene as it started: the
 * medium maze's robot drives 300 ticks, and frames 1 and 300 differ where
 * it was and is (about as much as with a camera fixed on a point), not
 * everywhere, as with the camera that follows the bot. It used to pan
 * with the robot, the middle of the walls' ends and the robot as it
 * was. */
TEST(camera_scene_holds_still_while_the_bot_drives)
{
	const char *cams[3] = {"scene", "2,2", "bot"};
	long diff[3];
	for (int c = 0; c < 3; c++) {
		for (int t = 1; t <= 300; t += 299)
			CHECK_EQ_INT(cli_sh("%s run " MAZE_DEMO " -nog --ticks %d "
					    "--camera %s --screenshot "
					    "%s/cam%d-%d.png > /dev/null",
					    cli_evo, t, cams[c], cli_tmp, c, t),
				     0);
		char a[256], b[256];
		snprintf(a, sizeof a, "%s/cam%d-1.png", cli_tmp, c);
		snprintf(b, sizeof b, "%s/cam%d-300.png", cli_tmp, c);
		diff[c] = frames_differ(a, b);
	}
	printf("  pixels changed, tick 1 to 300: scene %ld, a fixed point "
	       "%ld, following the bot %ld\n",
	       diff[0], diff[1], diff[2]);
	CHECK(diff[0] >= 0 && diff[1] >= 0 && diff[2] >= 0);
	CHECK(diff[0] <= 2 * diff[1]);
	CHECK(5 * diff[0] < diff[2]);
}

TEST(record_saves_frames_and_video)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run " DEMO " --ticks 60 --record %s/f "
				 "--record-every 10 --zoom 2",
				 cli_evo, cli_tmp),
		     0);
	/* ticks 0, 10, ..., 60 */
	CHECK_CONTAINS(out, "recorded 7 frames in");
	CHECK_EQ_INT(cli_sh("test $(ls %s/f | wc -l) = 7 && test -f "
			    "%s/f/frame-000007.png",
			    cli_tmp, cli_tmp),
		     0);
	/* the last frame is the screenshot of tick 60 */
	CHECK_EQ_INT(cli_sh("%s run " DEMO " -nog --ticks 60 --zoom 2 "
			    "--screenshot %s/s60.png > /dev/null && cmp -s "
			    "%s/s60.png %s/f/frame-000007.png",
			    cli_evo, cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_sh("%s run " DEMO " -nog --ticks 60 --screenshot "
			    "%s/z1.png > /dev/null && ! cmp -s %s/z1.png "
			    "%s/s60.png",
			    cli_evo, cli_tmp, cli_tmp, cli_tmp),
		     0);
	/* a camera far from everything sees only the floor */
	CHECK_EQ_INT(cli_sh("%s run " DEMO " -nog --ticks 1 --camera "
			    "5000,5000 --screenshot %s/far.png > /dev/null",
			    cli_evo, cli_tmp),
		     0);
	char path[256];
	snprintf(path, sizeof path, "%s/far.png", cli_tmp);
	evo_png_image img;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_png_read(path, &img, &err), 0);
	/* the world area holds two colours: the floor and its grid */
	uint32_t seen[8];
	int colours = 0;
	for (int y = 0; y < 600 && img.pixels; y++)
		for (int x = 100; x < 700; x++) {
			const uint8_t *p =
			    img.pixels + ((size_t)y * (size_t)img.w + (size_t)x) *
					     (size_t)img.channels;
			uint32_t c = (uint32_t)p[0] << 16 |
				     (uint32_t)p[1] << 8 | p[2];
			int k = 0;
			while (k < colours && seen[k] != c)
				k++;
			if (k == colours && colours < 8)
				seen[colours++] = c;
		}
	evo_png_image_free(&img);
	CHECK(colours == 2);
	/* a video through ffmpeg: 91 frames for 90 ticks */
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run " DEMO " --ticks 90 --record %s/a.mp4 "
				 "--camera scene",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "recorded 91 frames in");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "ffprobe -v error -count_frames "
				 "-select_streams v:0 -show_entries "
				 "stream=nb_read_frames,width,height -of "
				 "csv=p=0 %s/a.mp4",
				 cli_tmp),
		     0);
	CHECK_CONTAINS(out, "1024,720,91");
	/* the options are for frames drawn off screen */
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s run " DEMO " -nog --zoom 2",
				 cli_evo),
		     1);
	CHECK_CONTAINS(out, "--camera and --zoom set the frames of "
			    "--screenshot and --record");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run " DEMO " --camera 1 --record %s/x",
				 cli_evo, cli_tmp),
		     2);
	CHECK_CONTAINS(out, "--camera expects X,Y (metres), scene or bot");
}

TEST(windowed_screenshot_says_where)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "timeout -k 30 60 xvfb-run -a %s run " DEMO
				 " --ticks 5 --screenshot %s/w.png",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "/w.png (tick 5)");
	CHECK(strstr(out, "without a window") == NULL);
	CHECK_EQ_INT(cli_sh("test -s %s/w.png", cli_tmp), 0);
}

TEST(check_warns_of_hidden_on_neat)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/h && cp -r minds/Avoid %s/h/ && printf "
			    "'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\n"
			    "MASTERSKILL:Avoid\\nLEARNINGSKILL:Avoid\\n"
			    "ENV:EXP_Avoid\\nLEARNINGMETHOD:NEAT\\nNUMGEN:1\\n"
			    "EVALREP:1\\nTICKLIM:20\\nNEAT_POPSIZE:4\\n"
			    "HIDDEN:5\\n' > %s/h/Avoid/Tasks/H.simbatch",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	const char *want = "H.simbatch:11: HIDDEN is the width of the hidden "
			   "layers of GENETIC, ANNEALING and CMAES; NEAT grows "
			   "its own and ignores it";
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/h/Avoid/Tasks/H.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out, want);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/h/Avoid/Tasks/H.simbatch --run "
				 "%s/h/run",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	CHECK_CONTAINS(out, want);
	CHECK(strstr(strstr(out, want) + 1, want) == NULL); /* once */
}

TEST(reward_as_a_string_is_refused)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/r && cp -r minds/Avoid %s/r/ && printf "
			    "'TYPE:DEMOSIM\\nBOTMODEL:BotType8\\n"
			    "MASTERSKILL:Avoid\\nENV:Str\\n' > "
			    "%s/r/Avoid/Tasks/S.simbatch",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_write("local env = {}\n"
			       "function env.init(scene, task)\n"
			       "  scene:bot{ x = 0, y = 0 }\n"
			       "  scene:reward(function(scene)\n"
			       "    return \"1.5\"\n"
			       "  end)\n"
			       "end\n"
			       "return env\n",
			       "%s/r/Avoid/Envs/Str.lua", cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/r/Avoid/Tasks/S.simbatch -nog "
				 "--ticks 5",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "Str.lua:4: the reward function written here "
			    "returned the string \"1.5\" at tick");
	CHECK_CONTAINS(out, "not a finite number");
}

/* evo check of a copy of Avoid's DEMO task with `line` in place of its
 * line `key`: exit 1 and the message in out. */
static void check_with(const char *key, const char *value)
{
	CHECK_EQ_INT(cli_sh("rm -rf %s/n && mkdir -p %s/n && cp -r minds/Avoid "
			    "%s/n/ && printf 'TYPE:DEMOSIM\\nBOTMODEL:%s\\n"
			    "MASTERSKILL:%s\\nENV:%s\\n' > "
			    "%s/n/Avoid/Tasks/N.simbatch",
			    cli_tmp, cli_tmp, cli_tmp,
			    strcmp(key, "BOTMODEL") ? "BotType8" : value,
			    strcmp(key, "MASTERSKILL") ? "Avoid" : value,
			    strcmp(key, "ENV") ? "EXP_Avoid" : value, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/n/Avoid/Tasks/N.simbatch",
				 cli_evo, cli_tmp),
		     1);
}

TEST(misspelt_names_are_reported_at_the_task_line)
{
	check_with("ENV", "EXP_Avoi");
	CHECK_CONTAINS(out, "N.simbatch:4: ENV: environment 'EXP_Avoi' not "
			    "found: looked for ");
	CHECK_CONTAINS(out, "; did you mean EXP_Avoid?");
	check_with("ENV", "Roma");
	CHECK_CONTAINS(out, "; did you mean Roam?"); /* the mind's own Envs */
	check_with("BOTMODEL", "BotType9");
	CHECK_CONTAINS(out, "N.simbatch:2: BOTMODEL: bot model 'BotType9' not "
			    "found: looked for ");
	CHECK_CONTAINS(out, "; did you mean BotType8?");
	check_with("MASTERSKILL", "avoid");
	CHECK_CONTAINS(out, "N.simbatch:3: MASTERSKILL: no skill 'avoid' in ");
	CHECK_CONTAINS(out, "; did you mean Avoid?");
	check_with("ENV", "Nothing_like_it");
	CHECK(strstr(out, "did you mean") == NULL);
}

/* evo check of Avoid with environment `body` (the lines of env.init,
 * after a bot `b` is made): exit 1 and the message in out. */
static void env_check(const char *body)
{
	char lua[1024];
	snprintf(lua, sizeof lua,
		 "local env = {}\n"
		 "function env.init(scene, task)\n"
		 "  local b = scene:bot{ x = 0, y = 0 }\n"
		 "%s\n"
		 "end\n"
		 "return env\n",
		 body);
	CHECK_EQ_INT(cli_sh("mkdir -p %s/e && (test -d %s/e/Avoid || cp -r "
			    "minds/Avoid %s/e/) && printf 'TYPE:DEMOSIM\\n"
			    "BOTMODEL:BotType8\\nMASTERSKILL:Avoid\\nENV:Mine"
			    "\\n' > %s/e/Avoid/Tasks/M.simbatch",
			    cli_tmp, cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_write(lua, "%s/e/Avoid/Envs/Mine.lua", cli_tmp), 0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/e/Avoid/Tasks/M.simbatch",
				 cli_evo, cli_tmp),
		     1);
}

TEST(misspelt_names_in_an_environment_get_a_hint)
{
	env_check("  scene:control('NextOnTimout', { ticks = 10 })");
	CHECK_CONTAINS(out, "Mine.lua:4: scene:control: unknown control "
			    "function 'NextOnTimout'; did you mean "
			    "NextOnTimeout?");
	env_check("  scene:reward('ForwardSped', { bot = b })");
	CHECK_CONTAINS(out, "Mine.lua:4: scene:reward: unknown reward function "
			    "'ForwardSped'; did you mean ForwardSpeed?");
	env_check("  scene:reward('Nothing_like_any', { bot = b })");
	CHECK(strstr(out, "did you mean") == NULL);
	CHECK_CONTAINS(out, "unknown reward function 'Nothing_like_any'");
	/* a misspelt method, not Lua's "attempt to call a nil value" */
	env_check("  scene:zonee{ x = 1, y = 1, radius = 2 }");
	CHECK_CONTAINS(out, "Mine.lua:4: scene:zonee: a scene has no method "
			    "'zonee'; did you mean scene:zone?");
	env_check("  local x = b:poze()");
	CHECK_CONTAINS(out, "Mine.lua:4: bot:poze: a bot has no method "
			    "'poze'; did you mean bot:pose?");
	env_check("  scene:frobnicate_everything()");
	CHECK(strstr(out, "did you mean") == NULL);
	env_check("  b:target('DISTZ', nil)");
	CHECK_CONTAINS(out, "Mine.lua:4: bot:target: bot 'bot1' has no sensor "
			    "'DISTZ'; did you mean DISTDZ?");
}

TEST(a_body_option_is_reported_at_its_line)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/e/Avoid/Bots", cli_tmp), 0);
	CHECK_EQ_INT(cli_write("-- a round bot\n"
			       "return {\n"
			       "  body = { radus = 0.5, density = 1 },\n"
			       "  build = function(bot) end,\n"
			       "}\n",
			       "%s/e/Avoid/Bots/Round.lua", cli_tmp),
		     0);
	env_check("  scene:bot{ x = 2, y = 2, model = 'Round' }");
	CHECK_CONTAINS(out, "Bots/Round.lua:3: body: unknown option 'radus'; "
			    "did you mean radius? (known: shape, radius,");
}

/* evo check of a task whose own skill has no network yet says the task
 * trains it, not that it "has its network"; a task over sub-skills that
 * all have theirs is ok. */
TEST(check_says_the_task_trains_its_skill)
{
	CHECK_EQ_INT(cli_sh("rm -rf %s/u && mkdir -p %s/u && cp -r "
			    "minds/Collect %s/u/ && rm %s/u/Collect/Skills/*/*.net",
			    cli_tmp, cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/u/Collect/Tasks/Collect-NEAT.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "Collect          no network yet: this task trains "
			    "it");
	CHECK_CONTAINS(out, "network: none yet, this task trains it");
	CHECK(strstr(out, "has its network") == NULL);
	/* the skills to train first, the task's own not among them */
	CHECK_CONTAINS(out, "not trained yet (no Skills/S/S.net): GTO+Avoid, "
			    "GTDZ+Avoid, ClawControl\n");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/u/Collect/Tasks/GTO+Avoid-NEAT.simbatch",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "master skill GTO+Avoid: ok\n");
}

/* A misspelt key is a warning that evo run goes on without: evo check,
 * asked to find such things, ends with their count and exits 1, and evo
 * run repeats the count after its own output. */
TEST(check_fails_on_a_misspelt_key)
{
	CHECK_EQ_INT(cli_sh("rm -rf %s/k && mkdir -p %s/k && cp -r minds/Avoid "
			    "%s/k/ && printf 'TYPE:DEMOSIM\\nBOTMODEL:BotType8\\n"
			    "MASTERSKILL:Avoid\\nENV:EXP_Avoid\\nTICKLIN:20\\n' > "
			    "%s/k/Avoid/Tasks/K.simbatch",
			    cli_tmp, cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/k/Avoid/Tasks/K.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "K.simbatch:5: unknown key 'TICKLIN' ignored; did "
			    "you mean TICKLIM?");
	CHECK_CONTAINS(out, "master skill Avoid: not ok, 1 warning above (evo "
			    "run would run it without what it names)\n");
	CHECK(strstr(out, ": ok") == NULL);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/k/Avoid/Tasks/K.simbatch -nog "
				 "--ticks 5",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "evo run: 1 warning at the start (above): the run "
			    "went on without what it names; evo check fails "
			    "on it\n");
}

/* A GIF of 51 frames is a file a user would mail, not ffmpeg's default
 * 14 MB (a palette of the run's colours, each frame only what changed),
 * and still holds every frame at full size. */
TEST(a_recorded_gif_is_small)
{
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run " DEMO " --ticks 50 --record %s/g.gif",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "recorded 51 frames in");
	CHECK_EQ_INT(cli_capture(out, sizeof out, "stat -c %%s %s/g.gif",
				 cli_tmp),
		     0);
	long bytes = atol(out);
	printf("  a GIF of 51 frames (Avoid-DEMO --ticks 50): %.1f MB\n",
	       bytes / 1e6);
	CHECK(bytes > 0 && bytes < 2000000);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "ffprobe -v error -count_frames "
				 "-select_streams v:0 -show_entries "
				 "stream=nb_read_frames,width,height -of "
				 "csv=p=0 %s/g.gif",
				 cli_tmp),
		     0);
	CHECK_CONTAINS(out, "1024,720,51");
}

/* --record ends each episode with the line a headless run prints: its
 * collision ticks and what it did (Kheperax's env.behaviour). */
TEST(record_prints_the_headless_episode_line)
{
	static char headless[4096];
	CHECK_EQ_INT(cli_capture(headless, sizeof headless,
				 "%s run minds/Kheperax/Tasks/"
				 "Kheperax-DEMO.simbatch --headless --ticks 20",
				 cli_evo),
		     0);
	CHECK_CONTAINS(headless, "episode 1: reward ");
	CHECK_CONTAINS(headless, " collision ticks, behaviour (");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run minds/Kheperax/Tasks/"
				 "Kheperax-DEMO.simbatch --ticks 20 --record "
				 "%s/kh-frames --record-every 10",
				 cli_evo, cli_tmp),
		     0);
	CHECK(strncmp(out, headless, strlen(headless)) == 0);
	CHECK_CONTAINS(out, "recorded 3 frames in");
}

/* A --screenshot shows the scene as it starts unless --camera says
 * otherwise, and its panel's title names the task whole: the same
 * picture whether the task is given as a long path or from its folder
 * (the title was "minds/Avoid/Tasks/A~", the file name cut off). */
TEST(screenshot_frames_the_scene_and_names_the_task)
{
	CHECK_EQ_INT(cli_sh("%s run " DEMO " -nog --ticks 30 --screenshot "
			    "%s/d.png > /dev/null && %s run " DEMO " -nog "
			    "--ticks 30 --camera scene --screenshot %s/sc.png "
			    "> /dev/null && cmp -s %s/d.png %s/sc.png",
			    cli_evo, cli_tmp, cli_evo, cli_tmp, cli_tmp,
			    cli_tmp),
		     0);
	char evo[512];
	snprintf(evo, sizeof evo, "%s", cli_evo);
	CHECK_EQ_INT(cli_sh("EVO=$(realpath %s) && T=$(realpath %s) && cd "
			    "minds/Avoid/Tasks && $EVO run Avoid-DEMO.simbatch "
			    "-nog --ticks 30 --screenshot $T/short.png > "
			    "/dev/null && cmp -s $T/d.png $T/short.png",
			    evo, cli_tmp),
		     0);
}

/* Whether pixel (x, y) has the walls' colour (the viewer's obstacle
 * edge, 0x5E5E5E; the scale bar's 0x555555 is not). */
static int wall_pixel(const evo_png_image *im, int x, int y)
{
	const uint8_t *p =
	    im->pixels + ((size_t)y * (size_t)im->w + (size_t)x) *
			     (size_t)im->channels;
	return p[0] == 0x5E && p[1] == 0x5E && p[2] == 0x5E;
}

/* Wall pixels of row y (dx 1) or column x (dx 0) between a and b. */
static int wall_run(const evo_png_image *im, int fixed, int a, int b, int dx)
{
	int n = 0;
	for (int i = a; i <= b; i++)
		n += dx ? wall_pixel(im, i, fixed) : wall_pixel(im, fixed, i);
	return n;
}

/* Kheperax's maze is 67 m wide, more than zoom 1's 60 m: a screenshot
 * with the default camera shows all of it, its four outer walls inside
 * the world area (1024 - 264 = 760 pixels wide, left of the panel) with
 * room to spare, none cut by the frame's edge or under the panel. The
 * camera used to show 60 m, centred on the scene's elements, not on its
 * walls, and a robot near a corner was out of the picture. */
TEST(screenshot_frames_a_maze_wider_than_zoom_one)
{
	char png[600];
	snprintf(png, sizeof png, "%s/kheperax.png", cli_tmp);
	CHECK_EQ_INT(cli_sh("%s run minds/Kheperax/Tasks/Kheperax-DEMO.simbatch"
			    " -nog --ticks 1 --screenshot %s > /dev/null",
			    cli_evo, png),
		     0);
	evo_png_image im;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_png_read(png, &im, &err), 0);
	if (!im.pixels)
		return;
	const int world_w = 760;
	CHECK_EQ_INT(im.w, 1024);
	/* the box of the wall pixels in the world area */
	int x0 = im.w, y0 = im.h, x1 = -1, y1 = -1;
	for (int y = 0; y < im.h; y++)
		for (int x = 0; x < world_w && x < im.w; x++)
			if (wall_pixel(&im, x, y)) {
				x0 = x < x0 ? x : x0;
				x1 = x > x1 ? x : x1;
				y0 = y < y0 ? y : y0;
				y1 = y > y1 ? y : y1;
			}
	/* a margin on every side: nothing cut by the frame or the panel */
	CHECK(x0 >= 8 && y0 >= 8);
	CHECK(x1 <= world_w - 9 && y1 <= im.h - 9);
	/* the maze fills most of the smaller side (720 px): not a speck */
	CHECK(x1 - x0 >= 600 && y1 - y0 >= 600);
	/* centred in the world area, not in the whole frame */
	CHECK(abs((x0 + x1) / 2 - world_w / 2) <= 8);
	/* the four outer walls: full rows and columns of wall pixels at
	 * the box's edges (each a 3-pixel line: the box's edge or next) */
	int w = x1 - x0 + 1, h = y1 - y0 + 1;
	int top = 0, bottom = 0, left = 0, right = 0;
	for (int k = 0; k < 3; k++) {
		top |= wall_run(&im, y0 + k, x0, x1, 1) >= w * 9 / 10;
		bottom |= wall_run(&im, y1 - k, x0, x1, 1) >= w * 9 / 10;
		left |= wall_run(&im, x0 + k, y0, y1, 0) >= h * 9 / 10;
		right |= wall_run(&im, x1 - k, y0, y1, 0) >= h * 9 / 10;
	}
	CHECK(top && bottom && left && right);
	evo_png_image_free(&im);
}

int main(void)
{
	if (cli_setup("messages"))
		return 1;
	RUN(every_command_has_help);
	RUN(version_is_printed);
	RUN(ticks_zero_is_refused);
	RUN(info_draws_the_hierarchy_as_dot);
	RUN(info_draws_a_network_as_dot);
	RUN(info_renders_png_and_svg_with_graphviz);
	RUN(dot_of_an_untrained_skill_says_it_is_a_shape);
	RUN(a_misspelt_run_option_gets_a_did_you_mean);
	RUN(record_saves_frames_and_video);
	RUN(camera_scene_holds_still_while_the_bot_drives);
	RUN(windowed_screenshot_says_where);
	RUN(check_warns_of_hidden_on_neat);
	RUN(reward_as_a_string_is_refused);
	RUN(misspelt_names_are_reported_at_the_task_line);
	RUN(misspelt_names_in_an_environment_get_a_hint);
	RUN(a_body_option_is_reported_at_its_line);
	RUN(check_says_the_task_trains_its_skill);
	RUN(check_fails_on_a_misspelt_key);
	RUN(a_recorded_gif_is_small);
	RUN(record_prints_the_headless_episode_line);
	RUN(screenshot_frames_the_scene_and_names_the_task);
	RUN(screenshot_frames_a_maze_wider_than_zoom_one);
	setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
	setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
	RUN(progress_rewrites_only_at_a_terminal);
	cli_cleanup();
	return test_summary();
}
