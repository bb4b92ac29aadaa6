/* `evo run`'s options (cmd/run_internal.h, docs/running.md): the usage,
 * and each argument read and checked, with the nearest option named for
 * one it does not take. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/run_internal.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/number.h"
#include "cmd/run.h"
#include "learn/evaluate.h"

/* An argument evo run does not take: with the option it is nearest to,
 * when one is ("--tick": did you mean --ticks?), else the usage. */
static void unexpected(const char *a)
{
	static const char *const opts[] = {
	    "--headless", "-nog",	    "--seed",	    "--episodes",
	    "--ticks",	  "--trace",	    "--screenshot", "--trail",
	    "--record",	  "--record-every", "--camera",	    "--zoom",
	    "--net",	  "--can",	    "--threads",    "--generations",
	    "--run",	  "--resume",	    "--no-save",    "--env",
	    "--help"};
	unsigned dist;
	const char *near =
	    evo_closest_name(a, opts, sizeof opts / sizeof opts[0], &dist);
	size_t n = strlen(a);
	if (a[0] == '-' && near && dist > 0 && dist <= (n < 8 ? 1u : 2u)) {
		fprintf(stderr,
			"evo run: unexpected argument '%s'; did you mean %s? "
			"(evo run --help lists the options)\n",
			a, near);
		return;
	}
	fprintf(stderr, "evo run: unexpected argument '%s'\n", a);
	evo_run_usage(stderr);
}

void evo_run_usage(FILE *f)
{
	fputs("usage: evo run TASK.simbatch [options]\n"
	      "  --headless, -nog   no window; run as fast as possible and\n"
	      "                     print each episode's reward\n"
	      "  --seed N           seed of the obstacle grids and of every\n"
	      "                     random choice (default: SEED or 1)\n"
	      "  --episodes N       episodes to run (default: 1 headless;\n"
	      "                     with the viewer, until it is closed)\n"
	      "  --ticks N          at most N ticks per episode (default:\n"
	      "                     the task's TICKLIM)\n"
	      "  --trace FILE       record each tick's sensor and actuator\n"
	      "                     values (docs/running.md)\n"
	      "  --screenshot FILE  save a PNG of what the viewer shows after\n"
	      "                     the first --ticks ticks and quit (drawn\n"
	      "                     without a window when headless)\n"
	      "  --trail            the viewer draws the path the bot took\n"
	      "                     this episode\n"
	      "  --record PATH      record the run without a window: a frame\n"
	      "                     every --record-every N ticks (default 1)\n"
	      "                     as PNG files in folder PATH, or a video\n"
	      "                     made by ffmpeg when PATH ends in .mp4,\n"
	      "                     .webm, .mkv, .avi or .gif (30 frames a\n"
	      "                     second)\n"
	      "  --camera X,Y|scene|bot  centre --screenshot's and --record's\n"
	      "                     frames on the point (X, Y) in metres, on\n"
	      "                     the middle of the scene as it starts\n"
	      "                     (default), or on the bot, as the viewer\n"
	      "                     follows it\n"
	      "  --zoom Z           their zoom, 1/16 to 64 (default 1: 60 m\n"
	      "                     across; 2 shows half as much)\n"
	      "  --net SKILL=NET    run neural skill SKILL with another\n"
	      "                     network: a .net file (a run folder's\n"
	      "                     best/gen-NNNN.net or champion.net),\n"
	      "                     random (from the seed) or zero; Skills/\n"
	      "                     is left as it is (DEMOSIM; repeatable)\n"
	      "DEMOREMOTE (a robot): --ticks N ends the episode after N of\n"
	      "  the robot's ticks; without it, it runs until stopped\n"
	      "  --can URL          the robot is a body on this CAN bus\n"
	      "                     (socketcan:IFACE, slcan:DEVICE,\n"
	      "                     cannelloni:HOST:PORT, ...; docs/can.md)\n"
	      "                     instead of the task's CANURL or LCM\n"
	      "LEARNSIM, LEARN3DSIM, LEARNSIMCONTINUOUS (--ticks N bounds\n"
	      "  each evaluation's episodes too):\n"
	      "  --generations N    train N generations instead of NUMGEN\n"
	      "                     (LEARNSIMCONTINUOUS: in each turn)\n"
	      "  --threads N        worker threads (default: one per core;\n"
	      "                     under mpirun, each rank's own)\n"
	      "  --run DIR          run folder (default MIND/Runs/TASK-seedN)\n"
	      "  --resume           go on from the run folder's checkpoint,\n"
	      "                     with the --seed, --ticks, --generations\n"
	      "                     and --no-save the run was started with\n"
	      "  --no-save          leave Skills/ as it is: the champion\n"
	      "                     stays in the run folder (without it, a\n"
	      "                     network it replaces is kept there as\n"
	      "                     replaced-SKILL.net)\n"
	      "  under `mpirun -np N evo run ...` rank 0 learns and every\n"
	      "  rank evaluates (docs/cluster.md)\n"
	      "OPENENDED (docs/openended.md):\n"
	      "  --env N            show admitted environment N of the run\n"
	      "                     folder (--run DIR, or the default one)\n"
	      "                     with the agent that solved it then\n",
	      f);
}

/* --net SKILL=SOURCE, kept in o->net. */
static int parse_net(const char *v, run_opts *o)
{
	const char *eq = v ? strchr(v, '=') : NULL;
	if (!eq || eq == v || !eq[1]) {
		fprintf(stderr,
			"evo run: --net expects SKILL=NET (NET a .net file, "
			"random or zero), found '%s'\n",
			v ? v : "nothing");
		return -1;
	}
	size_t n = (size_t)(eq - v);
	if (n >= EVO_NAME_MAX) {
		fprintf(stderr,
			"evo run: --net '%s': a skill name has at most %d "
			"characters\n",
			v, EVO_NAME_MAX - 1);
		return -1;
	}
	if (o->n_nets == RUN_MAX_NETS) {
		fprintf(stderr, "evo run: at most %d --net options\n",
			RUN_MAX_NETS);
		return -1;
	}
	char *name = o->net_arg[o->n_nets];
	memcpy(name, v, n);
	name[n] = 0;
	o->net[o->n_nets].skill = name;
	o->net[o->n_nets].source = eq + 1;
	o->n_nets++;
	return 0;
}

/* A whole number 0..max: one that the int or long it goes into holds,
 * so that no count is silently cut (--threads 4294967297 was 1). */
static int parse_count(const char *flag, const char *v, long max, long *out)
{
	char *end;
	errno = 0;
	long n = v ? strtol(v, &end, 10) : -1;
	if (!v || *end || errno || n < 0 || n > max) {
		fprintf(stderr,
			"evo run: %s expects a whole number 0..%ld, found "
			"'%s'\n",
			flag, max, v ? v : "nothing");
		return -1;
	}
	*out = n;
	return 0;
}

/* A count of at least 1 (parse_count's, then 0 refused, with note after
 * the message). */
static int parse_from_one(const char *flag, const char *v, long max,
			  long *out, const char *note)
{
	if (parse_count(flag, v, max, out))
		return -1;
	if (*out < 1) {
		fprintf(stderr,
			"evo run: %s expects a whole number from 1, found "
			"'%s'%s\n",
			flag, v, note);
		return -1;
	}
	return 0;
}

/* --camera X,Y, scene or bot. */
static int parse_camera(const char *v, run_opts *o)
{
	char *end;
	if (v && strcmp(v, "bot") == 0) {
		o->camera = 3;
		return 0;
	}
	if (v && strcmp(v, "scene") == 0) {
		o->camera = 1;
		return 0;
	}
	o->camera = 2;
	o->camera_x = v ? strtod(v, &end) : 0;
	if (v && end != v && *end == ',') {
		const char *y = end + 1;
		o->camera_y = strtod(y, &end);
		if (end != y && !*end && isfinite(o->camera_x) &&
		    isfinite(o->camera_y))
			return 0;
	}
	fprintf(stderr,
		"evo run: --camera expects X,Y (metres), scene or bot, found "
		"'%s'\n",
		v ? v : "nothing");
	return -1;
}

int evo_run_parse_args(int argc, char **argv, run_opts *o)
{
	memset(o, 0, sizeof *o);
	o->episodes = -1; /* not given */
	for (int i = 2; i < argc; i++) {
		const char *a = argv[i];
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		long n;
		if (strcmp(a, "--headless") == 0 || strcmp(a, "-nog") == 0) {
			o->headless = 1;
		} else if (strcmp(a, "--seed") == 0) {
			if (parse_count(a, v, LONG_MAX, &n))
				return -1;
			o->seed = (uint64_t)n;
			o->seed_set = 1;
			i++;
		} else if (strcmp(a, "--episodes") == 0) {
			if (parse_count(a, v, INT_MAX, &o->episodes))
				return -1;
			i++;
		} else if (strcmp(a, "--ticks") == 0) {
			/* 0 meant TICKLIM, unlike every other count */
			if (parse_from_one(a, v, LONG_MAX, &o->ticks,
					   " (without --ticks an episode lasts "
					   "the task's TICKLIM)"))
				return -1;
			i++;
		} else if (strcmp(a, "--trace") == 0 && v) {
			o->trace = v;
			i++;
		} else if (strcmp(a, "--generations") == 0) {
			/* it stands for NUMGEN: the same range */
			if (parse_from_one(
				a, v, (long)evo_simbatch_key_find("NUMGEN")->hi,
				&o->generations, ""))
				return -1;
			i++;
		} else if (strcmp(a, "--threads") == 0) {
			if (parse_count(a, v, EVO_EVAL_MAX_THREADS,
					&o->threads))
				return -1;
			i++;
		} else if (strcmp(a, "--run") == 0 && v) {
			o->run_dir = v;
			i++;
		} else if (strcmp(a, "--resume") == 0) {
			o->resume = 1;
		} else if (strcmp(a, "--no-save") == 0) {
			o->no_save = 1;
		} else if (strcmp(a, "--env") == 0) {
			if (parse_count(a, v, LONG_MAX, &o->env))
				return -1;
			i++;
		} else if (strcmp(a, "--net") == 0) {
			if (parse_net(v, o))
				return -1;
			i++;
		} else if (strcmp(a, "--trail") == 0) {
			o->trail = 1;
		} else if (strcmp(a, "--screenshot") == 0 && v) {
			o->screenshot = v;
			i++;
		} else if (strcmp(a, "--can") == 0 && v) {
			o->can = v;
			i++;
		} else if (strcmp(a, "--record") == 0 && v) {
			o->record = v;
			i++;
		} else if (strcmp(a, "--record-every") == 0) {
			if (parse_from_one(a, v, INT_MAX, &o->record_every,
					   ""))
				return -1;
			i++;
		} else if (strcmp(a, "--camera") == 0) {
			if (parse_camera(v, o))
				return -1;
			i++;
		} else if (strcmp(a, "--zoom") == 0) {
			char *end;
			o->zoom = v ? strtod(v, &end) : 0;
			if (!v || end == v || *end ||
			    !(o->zoom >= 1.0 / 16 && o->zoom <= 64)) {
				fprintf(stderr,
					"evo run: --zoom expects a number from "
					"0.0625 to 64, found '%s'\n",
					v ? v : "nothing");
				return -1;
			}
			i++;
		} else if (a[0] == '-' || o->task) {
			unexpected(a);
			return -1;
		} else {
			o->task = a;
		}
	}
	if (!o->task) {
		evo_run_usage(stderr);
		return -1;
	}
	return 0;
}
