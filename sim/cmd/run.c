/* `evo run TASK.simbatch`: run a task (sim/cmd/run.h, docs/running.md).
 * This file loads the task and picks the run its type asks for: learning
 * (on one machine or a cluster), a remote simulator, a robot, the viewer,
 * the 3D view, frames off screen or headless; the other run_*.c files
 * hold each (cmd/run_internal.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/run.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/err.h"
#include "base/fileio.h"
#include "base/number.h"
#include "cluster/cluster.h"
#include "cmd/mindinfo.h"
#include "cmd/record.h"
#include "cmd/run_internal.h"
#include "learn/evaluate.h"
#include "learn/learn.h"
#include "learn/runopts.h"
#include "lua/lua_evo.h"
#include "mind/task.h"
#include "mind/trace.h"
#include "remote/robot.h"
#include "remote/session.h"
#include "tasksim/tasksim.h"
#include "viewer/view3d.h"
#include "viewer/viewer.h"

/* A learning run started by mpirun (docs/cluster.md): rank 0 learns as a
 * plain run does, with its batches spread over the ranks; the others
 * evaluate what it sends them. One rank is a plain run. */
static int learn_on_cluster(const char *task_path, evo_task *task,
			    evo_learn_opts *lo)
{
	evo_err err = {{0}};
	evo_cluster *c = evo_cluster_join(&err);
	if (!c) {
		fprintf(stderr, "%s\n", err.msg);
		return 1;
	}
	int rc = 0, rank = evo_cluster_rank(c);
	/* one thread per core the rank may use, not per core of the machine:
	 * mpirun may have bound it to one */
	if (lo->threads == 0)
		lo->threads = evo_cluster_cores();
	if (evo_cluster_size(c) > 1 && strcmp(task->type, "LEARNSIM") != 0 &&
	    strcmp(task->type, "LEARN3DSIM") != 0 &&
	    strcmp(task->type, "OPENENDED") != 0) {
		if (rank == 0)
			fprintf(stderr,
				"%s: a %s task runs in one process; mpirun "
				"with more than one rank spreads LEARNSIM, "
				"LEARN3DSIM and OPENENDED tasks "
				"(docs/cluster.md)\n",
				task_path, task->type);
		rc = 2;
	} else if (rank == 0) {
		if (evo_cluster_size(c) > 1)
			lo->spread = evo_cluster_spread(c, lo->seed);
		rc = evo_learn_run(task_path, task, lo, &err) ? 1 : 0;
		if (rc)
			fprintf(stderr, "%s\n", err.msg);
	} else {
		evo_eval_def def = {
		    .task_path = task_path,
		    .threads = lo->threads,
		    .seed = lo->seed,
		    .ticks = lo->ticks,
		};
		/* what goes wrong here, rank 0 says */
		rc = evo_cluster_serve(c, &def, &err) ? 1 : 0;
	}
	evo_cluster_leave(c);
	return rc;
}

/* --env N of an OPENENDED task: environment N of the run folder's
 * envs.csv, its genome into genome (the text scene:genome() gives), and
 * the agent that solved it when it was admitted (solvers/env-NNNN.net) as
 * a --net choice for LEARNINGSKILL. 0, or -1 with err. */
static int env_choice(const char *task_path, const evo_task *task, run_opts *o,
		      char *genome, size_t cap, evo_err *err)
{
	evo_learn_opts lo = {.seed = task->seed, .run_dir = o->run_dir};
	char dir[1024], path[1200];
	if (evo_learn_run_dir(task_path, task, &lo, dir, sizeof dir, err) ||
	    evo_path_fmt(path, sizeof path, err, "%s/envs.csv", dir))
		return -1;
	char *text;
	size_t len;
	if (!evo_file_exists(path))
		return evo_fail(err,
				"%s: no OPENENDED run here (--env N shows an "
				"environment a run admitted: give its folder "
				"with --run DIR%s)",
				path,
				o->run_dir ? ""
					   : ", or run the task first: "
					     "this is its default folder");
	if (evo_read_file(path, &text, &len, err))
		return -1;
	char head[32];
	int hn = snprintf(head, sizeof head, "\n%ld,", o->env);
	const char *row = strstr(text, head);
	const char *q = row ? strchr(row + hn, '"') : NULL;
	const char *nl = q ? strchr(q, '\n') : NULL;
	const char *end = q ? (nl ? nl : text + len) : NULL;
	while (end && end > q && end[-1] != '"')
		end--;
	if (!row || !q || end <= q + 1) {
		free(text);
		return evo_fail(err,
				"%s: no environment %ld (envs.csv lists the "
				"environments the run admitted)",
				path, o->env);
	}
	/* the skills the run had added when it admitted N (the column
	 * before the genome): its solver's hierarchy is Mind-K's */
	long skills = 0;
	const char *f = row + hn;
	for (int k = 0; k < 2 && f && f < q; k++) {
		f = strchr(f, ',');
		f = f ? f + 1 : NULL;
	}
	if (f && f < q)
		skills = strtol(f, NULL, 10);
	if (skills > 0) {
		const char *base = strrchr(task_path, '/');
		if (evo_path_fmt(o->env_task, sizeof o->env_task, err,
				 "%s/Mind-%ld/Tasks/%s", dir, skills,
				 base ? base + 1 : task_path)) {
			free(text);
			return -1;
		}
		if (!evo_file_exists(o->env_task)) {
			free(text);
			return evo_fail(err,
					"%s: environment %ld was admitted with "
					"%ld skill(s) added, and %s is missing",
					path, o->env, skills, o->env_task);
		}
	}
	size_t n = 0;
	for (const char *c = q + 1; c < end - 1; c++) {
		if (n + 1 >= cap) {
			free(text);
			return evo_fail(err,
					"%s: environment %ld's genome is longer "
					"than the %zu bytes --env shows",
					path, o->env, cap - 1);
		}
		genome[n++] = *c;
		if (c[0] == '"' && c[1] == '"')
			c++; /* a quote doubled in CSV */
	}
	genome[n] = 0;
	printf("environment %ld of %s, with solvers/env-%04ld.net\n", o->env,
	       dir, o->env);
	free(text);
	const char *skill = evo_simbatch_get(task->sb, "LEARNINGSKILL");
	if (!skill || o->n_nets == RUN_MAX_NETS)
		return evo_fail(err,
				"%s: --env N needs LEARNINGSKILL and a "
				"--net of its own",
				task_path);
	if (evo_path_fmt(o->env_net, sizeof o->env_net, err,
			 "%s/solvers/env-%04ld.net", dir, o->env))
		return -1;
	snprintf(o->net_arg[o->n_nets], sizeof o->net_arg[o->n_nets], "%s",
		 skill);
	o->net[o->n_nets].skill = o->net_arg[o->n_nets];
	o->net[o->n_nets].source = o->env_net;
	o->n_nets++;
	return 0;
}

/* A task that stopped at a neural skill with no trained network: loaded
 * again as evo check loads it, every such skill is named with the
 * bottom-up order to train them in, as evo check says it. */
static void untrained_report(const char *path, const evo_task_opts *to)
{
	evo_task_opts again = *to;
	again.untrained_ok = 1;
	evo_task t;
	evo_err e2;
	if (evo_task_load_opts(path, &again, &t, &e2) != 0)
		return;
	if (t.n_teams == 0)
		evo_untrained_report(t.mind, stderr);
	evo_task_free(&t);
}

/* A task run refuses: the reason on stderr, the task freed, code. */
static int refuse(evo_task *task, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int refuse(evo_task *task, int code, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	evo_task_free(task);
	return code;
}

/* LEARNSIM and the other learning tasks: trained here, or with the ranks
 * of an mpirun (learn_on_cluster). The task is freed. */
static int run_learning(const run_opts *o, evo_task *task, uint64_t seed,
			const char *argv0)
{
	evo_err err = {{0}};
	/* --threads, else the task's THREADS, else one per core */
	const char *tv = evo_simbatch_get(task->sb, "THREADS");
	long threads = o->threads ? o->threads : tv ? strtol(tv, NULL, 10) : 0;
	evo_learn_opts lo = {
	    .seed = seed,
	    .threads = (int)threads,
	    .generations = (int)o->generations,
	    .ticks = o->ticks,
	    .run_dir = o->run_dir,
	    .resume = o->resume,
	    .no_save = o->no_save,
	    .argv0 = argv0,
	};
	char dir[1024];
	if (o->resume &&
	    (evo_learn_run_dir(o->task, task, &lo, dir, sizeof dir, &err) ||
	     evo_run_record_restore(dir, &lo, o->seed_set, &err))) {
		return refuse(task, 2, "%s\n", err.msg);
	}
	if (evo_cluster_launched()) {
		int rc = learn_on_cluster(o->task, task, &lo);
		evo_task_free(task);
		return rc;
	}
	int rc = evo_learn_run(o->task, task, &lo, &err);
	if (rc)
		fprintf(stderr, "%s\n", err.msg);
	evo_task_free(task);
	return rc ? 1 : 0;
}

static int run_main(int argc, char **argv)
{
	run_opts o;
	if (evo_run_parse_args(argc, argv, &o))
		return 2;
	evo_err err = {{0}};
	/* --resume --run DIR: the seed the run was started with, before the
	 * task is loaded with it (the default folder's name holds it) */
	if (o.resume && o.run_dir && !o.seed_set) {
		evo_run_record r;
		if (evo_run_record_read(o.run_dir, &r, &err)) {
			fprintf(stderr, "%s\n", err.msg);
			return 1;
		}
		o.seed = r.seed;
		o.seed_set = r.found;
	}
	evo_task task;
	evo_task_opts to = {
	    .seed_set = o.seed_set,
	    .seed = o.seed,
	    .nets = o.net,
	    .n_nets = o.n_nets,
	};
	if (evo_task_load_opts(o.task, &to, &task, &err) != 0) {
		fprintf(stderr, "%s\n", err.msg);
		if (strstr(err.msg, "has no trained network"))
			untrained_report(o.task, &to);
		return 1;
	}
	uint64_t seed = task.seed;
	/* OPENENDED --env N: the task shown as a demo, on that environment,
	 * with its solver: the task loaded again with the solver's net */
	static char genome[65536];
	genome[0] = 0;
	if (o.env && strcmp(task.type, "OPENENDED") != 0) {
		return refuse(&task, 2,
			      "%s: --env N shows an environment an OPENENDED "
			      "run admitted; this is a %s task\n",
			      o.task, task.type);
	}
	if (o.env) {
		int r =
		    env_choice(o.task, &task, &o, genome, sizeof genome, &err);
		evo_task_free(&task);
		to.nets = o.net;
		to.n_nets = o.n_nets;
		if (!r && o.env_task[0]) {
			printf("the hierarchy it was solved with: %s\n",
			       o.env_task);
			o.task = o.env_task;
		}
		if (r || evo_task_load_opts(o.task, &to, &task, &err)) {
			fprintf(stderr, "%s\n", err.msg);
			return 1;
		}
	}
	if (o.n_nets && !o.env &&
	    (strncmp(task.type, "LEARN", 5) == 0 ||
	     strcmp(task.type, "OPENENDED") == 0)) {
		return refuse(
		    &task, 2,
		    "%s: --net chooses the networks a DEMOSIM run shows; "
		    "a %s task trains over the networks in Skills/\n",
		    o.task, task.type);
	}
	if (strcmp(task.type, "LEARNSIM") == 0 ||
	    strcmp(task.type, "LEARN3DSIM") == 0 ||
	    strcmp(task.type, "LEARNSIMCONTINUOUS") == 0 ||
	    strcmp(task.type, "LEARN2DSIMMULTI") == 0 ||
	    strcmp(task.type, "LEARN3DSIMMULTI") == 0 ||
	    strcmp(task.type, "LEARNREMOTESIM") == 0 ||
	    (strcmp(task.type, "OPENENDED") == 0 && !o.env)) {
		if (o.episodes >= 0) {
			/* it would be ignored: say so rather than run a task
			 * other than the one asked for */
			return refuse(
			    &task, 2,
			    "evo run: --episodes is for DEMO tasks; %s is a "
			    "%s task, whose networks each play EVALREP "
			    "episodes (docs/learning.md)\n",
			    o.task, task.type);
		}
		return run_learning(&o, &task, seed, argv[0]);
	}
	if (o.can && strcmp(task.type, "DEMOREMOTE") != 0) {
		return refuse(
		    &task, 2,
		    "evo run: --can is for DEMOREMOTE tasks (a robot on a "
		    "CAN bus); %s is a %s task\n",
		    o.task, task.type);
	}
	if (evo_robot_task_check(task.sb, task.type, o.task, &err)) {
		return refuse(&task, 1, "%s\n", err.msg);
	}
	if (!evo_run_supports(task.type)) {
		return refuse(
		    &task, 1,
		    "%s: evo run does not run %s tasks yet (it runs "
		    "DEMOSIM, LEARNSIM, LEARNSIMCONTINUOUS, DEMO3DSIM, "
		    "LEARN3DSIM, DEMO2DSIMMULTI, LEARN2DSIMMULTI, "
		    "DEMO3DSIMMULTI, LEARN3DSIMMULTI, "
		    "DEMOREMOTESIM, LEARNREMOTESIM and DEMOREMOTE)\n",
		    o.task, task.type);
	}
	evo_cmd_catch_stop();

	int rc = 1;
	evo_viewer *v = NULL;
	evo_view3d *v3 = NULL;
	trace_file tf;
	if (strcmp(task.type, "DEMOREMOTESIM") == 0) {
		const char *tl = evo_simbatch_get(task.sb, "TICKLIM");
		if (o.ticks == 0 && tl)
			o.ticks = strtol(tl, NULL, 10);
		if (o.episodes < 0)
			o.episodes = 1;
		if (evo_run_trace_open(&tf, o.trace, &err) == 0) {
			int r = evo_run_remote_sim(&task, &o, seed, tf.f, &err);
			if (evo_run_trace_close(&tf, r == 0, &err) == 0 &&
			    r == 0)
				rc = 0;
		}
		if (rc != 0 && err.msg[0])
			fprintf(stderr, "%s\n", err.msg);
		evo_task_free(&task);
		return rc;
	}
	evo_sim *s = NULL;
	int robot = strcmp(task.type, "DEMOREMOTE") == 0;
	if ((o.camera || o.zoom > 0) && !o.record && !o.screenshot) {
		evo_fail(&err, "evo run: --camera and --zoom set the frames of "
			       "--screenshot and --record (in the viewer, the "
			       "mouse and the keys move the camera)");
		goto out;
	}
	if (!robot && !(s = evo_sim_create_task(&task, o.task, &err)))
		goto out;
	if (s && genome[0])
		evo_lua_set_genome(s->lua, genome);
	if (o.record && robot) {
		evo_fail(&err,
			 "%s: --record draws the 2D world; a %s task has none "
			 "to draw",
			 o.task, task.type);
		goto out;
	}
	if (o.record)
		o.headless = 1; /* drawn off screen */
	int window3d = 0;
	if (s && s->scene3d &&
	    (o.camera || o.zoom > 0 ||
	     (o.trail && (o.screenshot || o.record)))) {
		evo_fail(&err,
			 "%s: --camera, --zoom and --trail are for 2D frames; "
			 "a 3D frame's camera follows the robot as the 3D "
			 "view's does",
			 o.task);
		goto out;
	}
	if (s && s->scene3d && (!o.headless || o.screenshot || o.record)) {
		/* a window where there is a display; frames without one
		 * (--screenshot, --record) drawn off screen by Mesa's EGL */
		const char *d = getenv("DISPLAY");
		const char *w = getenv("WAYLAND_DISPLAY");
		if (!o.headless && ((d && d[0]) || (w && w[0])))
			v3 = evo_view3d_open(VIEW_W, VIEW_H, &err);
		window3d = v3 != NULL;
		if (!v3 && (o.screenshot || o.record)) {
			err.msg[0] = 0;
			v3 = evo_view3d_open_offscreen(VIEW_W, VIEW_H, &err);
			if (!v3)
				goto out;
		}
		if (!v3) {
			fprintf(stderr,
				"evo run: no 3D view (%s); running headless\n",
				err.msg[0] ? err.msg : "DISPLAY is not set");
			err.msg[0] = 0;
		}
		o.headless = 1;
	}
	if (!o.headless) {
		const char *d = getenv("DISPLAY");
		const char *w = getenv("WAYLAND_DISPLAY");
		if ((d && d[0]) || (w && w[0]))
			v = evo_viewer_open(VIEW_W, VIEW_H, &err);
		if (!v) {
			fprintf(stderr,
				"evo run: no display (%s); running headless\n",
				err.msg[0] ? err.msg : "DISPLAY is not set");
			err.msg[0] = 0;
		}
	}
	if (robot) {
		/* A robot's episode runs until it is stopped (or --ticks, or
		 * the robot ends it): TICKLIM bounds simulated episodes. */
		if (o.episodes < 0)
			o.episodes = v ? 0 : 1;
		if (evo_run_trace_open(&tf, o.trace, &err))
			goto out;
		int r = evo_run_robot(&task, &o, seed, tf.f, v, &err);
		if (evo_run_trace_close(&tf, r == 0, &err) == 0 && r == 0)
			rc = 0;
		goto out;
	}
	/* An episode lasts at most TICKLIM ticks, as in learning, unless
	 * --ticks says otherwise: a timeout control ends it one check later
	 * (the tutorial's CF_NextOnTimeout), which would make a demo's
	 * episodes one tick longer than the ones the skill was trained on. */
	const char *tl = evo_simbatch_get(task.sb, "TICKLIM");
	if (o.ticks == 0 && tl)
		o.ticks = strtol(tl, NULL, 10);
	/* Not given: one episode headless; with the viewer, episodes until
	 * the window is closed, as EvoAgents' viewer ran them. */
	if (o.episodes < 0)
		o.episodes = v ? 0 : 1;
	if (evo_run_trace_open(&tf, o.trace, &err))
		goto out;
	s->trace = tf.f;
	if (s->trace)
		evo_sim_trace_header(s);
	int r = o.record   ? evo_run_record_frames(s, &o, seed, v3, &err)
		: window3d ? evo_run_viewer3d(s, v3, &o, seed, &err)
		: v	   ? evo_run_viewer(s, v, &o, seed, &err)
		: o.screenshot
		    ? evo_run_screenshot_headless(s, &o, seed, v3, &err)
		    : evo_run_headless(s, &o, seed, &err);
	s->trace = NULL;
	/* A failed run drops its trace; trace_close then leaves err alone. */
	if (evo_run_trace_close(&tf, r == 0, &err) == 0 && r == 0)
		rc = 0;
out:
	if (rc != 0 && err.msg[0])
		fprintf(stderr, "%s\n", err.msg);
	evo_viewer_close(v);
	evo_view3d_close(v3);
	evo_sim_destroy(s);
	evo_task_free(&task);
	return rc;
}

/* The run, and then the count of the task's warnings, which the run's own
 * output may have pushed out of sight (evo check fails on them). */
int evo_run_main(int argc, char **argv)
{
	int rc = run_main(argc, argv);
	unsigned warned = evo_warning_count();
	if (warned && !evo_cluster_launched())
		fprintf(stderr,
			"evo run: %u warning%s at the start (above): the run "
			"went on without what %s; evo check fails on %s\n",
			warned, warned == 1 ? "" : "s",
			warned == 1 ? "it names" : "they name",
			warned == 1 ? "it" : "them");
	return rc;
}
