/* `evo run TASK.simbatch`: run a task (sim/cmd/run.h, docs/running.md). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/run.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/err.h"
#include "base/fileio.h"
#include "base/number.h"
#include "cmd/mindinfo.h"
#include "cmd/record.h"
#include "cluster/cluster.h"
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

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
	stop_requested = sig; /* a scene script stops too (lua_evo.h) */
}

#define RUN_MAX_NETS 64

typedef struct run_opts {
	const char *task;
	int headless;
	uint64_t seed;
	int seed_set;
	long episodes; /* 0 with the viewer: until the window is closed */
	long ticks; /* per episode; 0: until a control function ends it */
	const char *trace;
	const char *screenshot; /* viewer: save a PNG after `ticks` ticks */
	int trail;		/* viewer: draw the bot's path (--trail) */
	long env;		/* OPENENDED: show admitted environment N
				 * (--env N), 0: none */
	char env_net[1200];	/* its solver's .net (a --net SOURCE) */
	const char *record;	/* frames of the run: a folder or a video */
	long record_every;	/* a frame every N ticks (0: not given) */
	int camera; /* 0 not given (the scene), 1 the scene, 2 a point, 3
		     * the bot, as the viewer follows it */
	double camera_x, camera_y;
	double zoom; /* 0: not given (1) */
	const char *can;	/* DEMOREMOTE: the robot's CAN URL */
	long threads;		/* LEARNSIM: 0 for one per core */
	long generations;	/* LEARNSIM: 0 for NUMGEN */
	const char *run_dir;	/* LEARNSIM */
	int resume;
	int no_save; /* LEARNSIM: the champion stays in the run folder */
	evo_net_choice net[RUN_MAX_NETS]; /* --net SKILL=SOURCE */
	unsigned n_nets;
	char net_arg[RUN_MAX_NETS][EVO_NAME_MAX]; /* each SKILL */
} run_opts;

/* An argument evo run does not take: with the option it is nearest to,
 * when one is ("--tick": did you mean --ticks?), else the usage. */
static void unexpected(const char *a)
{
	static const char *const opts[] = {
	    "--headless", "-nog",	"--seed",	   "--episodes",
	    "--ticks",	  "--trace",	"--screenshot",	   "--trail",
	    "--record",	  "--record-every", "--camera",	   "--zoom",
	    "--net",	  "--can",	"--threads",	   "--generations",
	    "--run",	  "--resume",	"--no-save",	   "--env",
	    "--help"};
	unsigned dist;
	const char *near = evo_closest_name(
	    a, opts, sizeof opts / sizeof opts[0], &dist);
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

static int parse_args(int argc, char **argv, run_opts *o)
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
			if (parse_count(a, v, LONG_MAX, &o->ticks))
				return -1;
			/* 0 meant TICKLIM, unlike every other count */
			if (o->ticks < 1) {
				fprintf(stderr,
					"evo run: --ticks expects a whole "
					"number from 1, found '%s' (without "
					"--ticks an episode lasts the task's "
					"TICKLIM)\n",
					v);
				return -1;
			}
			i++;
		} else if (strcmp(a, "--trace") == 0 && v) {
			o->trace = v;
			i++;
		} else if (strcmp(a, "--generations") == 0) {
			/* it stands for NUMGEN: the same range */
			if (parse_count(a, v,
					(long)evo_simbatch_key_find("NUMGEN")->hi,
					&o->generations))
				return -1;
			if (o->generations < 1) {
				fprintf(stderr, "evo run: --generations expects a "
						"whole number from 1, found '%s'\n",
					v);
				return -1;
			}
			i++;
		} else if (strcmp(a, "--threads") == 0) {
			if (parse_count(a, v, EVO_EVAL_MAX_THREADS, &o->threads))
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
			if (parse_count(a, v, INT_MAX, &o->record_every))
				return -1;
			if (o->record_every < 1) {
				fprintf(stderr, "evo run: --record-every "
						"expects a whole number from "
						"1, found '0'\n");
				return -1;
			}
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

int evo_run_supports(const char *type)
{
	return strcmp(type, "DEMOSIM") == 0 || strcmp(type, "LEARNSIM") == 0 ||
	       strcmp(type, "DEMO3DSIM") == 0 ||
	       strcmp(type, "LEARN3DSIM") == 0 ||
	       strcmp(type, "LEARNSIMCONTINUOUS") == 0 ||
	       strcmp(type, "DEMO2DSIMMULTI") == 0 ||
	       strcmp(type, "LEARN2DSIMMULTI") == 0 ||
	       strcmp(type, "DEMOREMOTESIM") == 0 ||
	       strcmp(type, "LEARNREMOTESIM") == 0 ||
	       strcmp(type, "DEMOREMOTE") == 0 ||
	       strcmp(type, "OPENENDED") == 0;
}

/* The seeds of episode e: the grid's and the rest's, from (seed, e). */
static uint64_t grid_seed(uint64_t seed, long e)
{
	evo_rng r = evo_rng_for(seed, 1, (uint64_t)e, 0);
	return evo_rng_next(&r);
}

static uint64_t episode_seed(uint64_t seed, long e)
{
	evo_rng r = evo_rng_for(seed, 2, (uint64_t)e, 0);
	return evo_rng_next(&r);
}

/* A trace is written to a new file beside FILE (evo_create_beside, which
 * writes through no planted link) and renamed when the run ends well: a
 * failed run leaves nothing behind. */
typedef struct trace_file {
	FILE *f;
	char tmp[1100];
	const char *path;
} trace_file;

static int trace_open(trace_file *t, const char *path, evo_err *err)
{
	memset(t, 0, sizeof *t);
	if (!path)
		return 0;
	t->path = path;
	int fd = evo_create_beside(path, t->tmp, sizeof t->tmp, err);
	if (fd < 0)
		return -1;
	t->f = fdopen(fd, "w");
	if (!t->f) {
		evo_fail(err, "%s: cannot create: %s", t->tmp, strerror(errno));
		close(fd);
		unlink(t->tmp);
		return -1;
	}
	return 0;
}

static int trace_close(trace_file *t, int keep, evo_err *err)
{
	if (!t->f)
		return 0;
	int bad = ferror(t->f) | (fflush(t->f) != 0) |
		  (fsync(fileno(t->f)) != 0);
	bad |= fclose(t->f) != 0;
	t->f = NULL;
	if (keep && !bad && rename(t->tmp, t->path) == 0)
		return 0;
	unlink(t->tmp);
	if (keep)
		return evo_fail(err, "%s: cannot save the trace: %s", t->path,
				strerror(errno));
	return 0;
}

/* 1 when the scene can deliver objects: it has a Collect reward. */
static int delivers(const evo_scene *sc)
{
	for (int i = 0; i < sc->n_rewards; i++)
		if (sc->reward[i].def.kind == EVO_RW_COLLECT)
			return 1;
	return 0;
}

/* 1 when the scene has a reward of kind k. */
static int has_reward(const evo_scene *sc, evo_reward_kind k)
{
	for (int i = 0; i < sc->n_rewards; i++)
		if (sc->reward[i].def.kind == k)
			return 1;
	return 0;
}

/* A team task's lines after its episode's (docs/teams.md): each team's
 * reward, each bot's own, and whether it won. */
static void print_teams(const evo_sim *s)
{
	const evo_scene *sc = s->scene;
	for (int k = 0; s->has_teams && k < s->n_teams; k++) {
		const evo_sim_team *tm = &s->team[k];
		printf("  team %s: reward %.6f (", tm->name,
		       sc->team_reward[k]);
		for (int i = 0; i < tm->size; i++) {
			const evo_bot *b =
			    &sc->bot[s->agent[tm->first + i].bot];
			printf("%s%s %.6f", i ? ", " : "", b->name, b->reward);
		}
		printf(")%s\n", sc->winner == k ? ", won" : "");
	}
}

/* The environment's own metrics at the end of an episode line, in the
 * order it declared them: ", in_zone 123.000000". Nothing when it has
 * none, so such a line is as it always was. */
static void print_metrics(const evo_scene *sc)
{
	char v[64];
	for (int i = 0; i < sc->n_metrics; i++)
		printf(", %s %s", sc->metric[i].name,
		       evo_number_text(v, sizeof v, sc->metric[i].value, 1));
}

/* What the episode did, when the environment says it (docs/lua.md, "What
 * an episode did"): ", behaviour (0.2, 0.25)" for env.behaviour and
 * ", solved" or ", not solved" for env.solved, for a one-agent task.
 * Nothing when it has neither, so such a line is as it always was. */
static int print_outcome(evo_sim *s, evo_err *err)
{
	double b[EVO_SIM_MAX_BEHAVIOUR];
	char text[64];
	int solved;
	if (s->has_teams)
		return 0;
	int n = evo_lua_behaviour(s->lua, s->bot, b, EVO_SIM_MAX_BEHAVIOUR,
				  err);
	if (n < 0)
		return -1;
	for (int k = 0; k < n; k++)
		printf("%s%s%s", k ? ", " : ", behaviour (",
		       evo_number_text(text, sizeof text, b[k], 0),
		       k == n - 1 ? ")" : "");
	int rc = evo_lua_solved(s->lua, s->bot, &solved, err);
	if (rc > 0)
		printf(solved ? ", solved" : ", not solved");
	return rc < 0 ? -1 : 0;
}

/* The line that ends episode e after t ticks, the same headless, in the
 * viewer and under --record: its reward, collision ticks, deliveries,
 * metrics and what it did; a 3D episode's fault, if anything broke;
 * every team's counts. */
static int print_episode(evo_sim *s, long e, long t, evo_err *err)
{
	if (s->scene3d) {
		printf("episode %ld: reward %.6f over %ld ticks, %d "
		       "collision ticks",
		       e, evo_sim_episode_reward(s), t,
		       evo_sim_collisions(s, 0));
		if (print_outcome(s, err))
			return -1;
		printf("\n");
		if (evo_sim_fault(s)[0])
			printf("  fault: %s\n", evo_sim_fault(s));
		fflush(stdout);
		return 0;
	}
	/* the agents' counts: the one agent's, or every team's */
	int collisions = 0, delivered = 0, gathered = 0;
	for (int a = 0; a < s->n_agents; a++) {
		const evo_bot *b = &s->scene->bot[s->agent[a].bot];
		collisions += b->collisions;
		delivered += b->delivered;
		gathered += b->gathered;
	}
	printf("episode %ld: reward %.6f over %ld ticks, %d collision "
	       "ticks",
	       e, s->scene->episode_reward, t, collisions);
	/* deliveries only where a Collect reward can make them */
	if (delivers(s->scene))
		printf(", %d delivered", delivered);
	if (has_reward(s->scene, EVO_RW_GATHER))
		printf(", %d gathered", gathered);
	print_metrics(s->scene);
	if (print_outcome(s, err))
		return -1;
	printf("\n");
	print_teams(s);
	fflush(stdout);
	return 0;
}

static int run_headless(evo_sim *s, const run_opts *o, uint64_t seed,
			evo_err *err)
{
	for (long e = 1; e <= o->episodes && !stop_requested; e++) {
		if (evo_sim_reset(s, (int)e, grid_seed(seed, e),
				  episode_seed(seed, e), err))
			return -1;
		long t = 0;
		int r = 0;
		while (!stop_requested && (o->ticks == 0 || t < o->ticks)) {
			r = evo_sim_tick(s, err);
			t++;
			if (r != 0)
				break;
		}
		/* a script stopped by the signal fails its tick */
		if (r < 0)
			return stop_requested ? 0 : -1;
		if (print_episode(s, e, t, err))
			return -1;
	}
	return 0;
}

/* DEMOREMOTESIM: the mind here, the world in a remote simulator driven in
 * lockstep; the same episodes, seeds and lines as DEMOSIM headless. */
static int run_remote_sim(const evo_task *task, const run_opts *o,
			  uint64_t seed, FILE *trace, evo_err *err)
{
	evo_remote_opts ro;
	if (evo_remote_opts_from_task(task->sb, o->task, EVO_REMOTE_SIMULATOR,
				      &ro, err))
		return -1;
	ro.stop = &stop_requested;
	const evo_mind *m = &task->mind->mind;
	size_t need = (evo_state_size(m) + 7) & ~(size_t)7;
	void *mem = aligned_alloc(8, need);
	evo_state *state = NULL;
	if (!mem)
		return evo_fail(err, "out of memory");
	if (evo_state_init(m, mem, need, &state) != EVO_OK) {
		free(mem);
		return evo_fail(err, "mind state: cannot lay it out");
	}
	evo_remotes *r = evo_remote_connect(task->mind, &ro, err);
	if (!r) {
		free(mem);
		/* a stop while waiting for a remote ends the run, as it would
		 * end a DEMOSIM */
		return stop_requested ? 0 : -1;
	}
	const evo_wire_hello *h = &r->r[0]->hello;
	printf("remote %s: %s, %d environment%s\n", h->name,
	       h->kind == EVO_REMOTE_SIMULATOR ? "simulator" : "robot",
	       (int)h->environments, h->environments == 1 ? "" : "s");
	if (trace)
		evo_trace_header(trace, task->mind);
	int rc = 0;
	double in[EVO_MAX_SENSORS], out[EVO_MAX_ACTUATORS];
	evo_q16 qin[EVO_MAX_SENSORS], qout[EVO_MAX_ACTUATORS];
	for (long e = 1; e <= o->episodes && !stop_requested && rc == 0; e++) {
		evo_state_reset(m, state);
		if (evo_remote_reset(r, 0, e, grid_seed(seed, e),
				     episode_seed(seed, e), err)) {
			rc = -1;
			break;
		}
		long t = 0;
		int end = 0;
		while (!stop_requested && (o->ticks == 0 || t < o->ticks)) {
			evo_remote_sensors(r->r[0], 0, in);
			for (unsigned i = 0; i < m->n_sensors; i++)
				qin[i] = evo_q16_from_sensor(in[i]);
			evo_mind_step(m, state, qin, qout);
			for (unsigned i = 0; i < m->n_actuators; i++)
				out[i] = evo_q16_to_double(qout[i]);
			if (trace)
				evo_trace_tick(trace, t, m, qin, qout, state);
			end = evo_remote_step(r, 0, out, err);
			t++;
			if (end != 0)
				break;
		}
		if (end < 0) {
			/* a stop while waiting is a stop, not a failure */
			rc = stop_requested ? 0 : -1;
			break;
		}
		printf("episode %ld: reward %.6f over %ld ticks", e,
		       evo_remote_reward(r->r[0], 0), t);
		/* what the simulator says the episode did, when it says */
		const evo_wire_sensors *last = &r->r[0]->env[0].sensors;
		for (unsigned k = 0; k < last->n_behaviour; k++)
			printf("%s%.6f%s", k ? ", " : ", behaviour (",
			       last->behaviour[k],
			       k + 1 == last->n_behaviour ? ")" : "");
		printf("\n");
		fflush(stdout);
	}
	evo_remotes_close(r);
	free(mem);
	return rc;
}

static double now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void sleep_until(double t)
{
	double d = t - now();
	if (d <= 0)
		return;
	struct timespec ts = {(time_t)d, (long)((d - (double)(time_t)d) * 1e9)};
	nanosleep(&ts, NULL);
}

/* The viewer's window, and a screenshot drawn without one. */
#define VIEW_W 1024
#define VIEW_H 720

/* What the viewer's panel shows: the tick, the episode, the rewards and
 * each skill's live influence; in a team task, the teams, and the
 * selected bot's own sensors, actuators and influences. */
typedef struct panel_data {
	const char *names[256];
	double infl[256];
	const char *team_name[EVO_MAX_TEAMS];
	const char *sensor_name[EVO_MAX_SENSORS];
	double sensor[EVO_MAX_SENSORS];
	const char *actuator_name[EVO_MAX_ACTUATORS];
	double actuator[EVO_MAX_ACTUATORS];
} panel_data;

/* What the viewer shows of whom: the bot selected (-1: none) and whether
 * the camera follows it. A one-agent task follows its bot and selects
 * none until a click; a team task selects its first bot, camera free. */
typedef struct view_state {
	int selected;
	int follow;
} view_state;

static view_state view_start(const evo_sim *s)
{
	view_state vs = {-1, 1};
	if (s->has_teams) {
		vs.selected = s->agent[0].bot;
		vs.follow = 0;
	}
	return vs;
}

/* The bot the camera follows: the selected one, or the one agent's;
 * -1 for the free camera. */
static int view_follow(const evo_sim *s, const view_state *vs)
{
	if (!vs->follow)
		return -1;
	return vs->selected >= 0 ? vs->selected : s->bot;
}

/* The selected bot's part of the panel: its names and values. */
static void panel_bot(panel_data *pd, evo_viewer_panel *p, const evo_sim *s,
		      int bot)
{
	const evo_bot *b = &s->scene->bot[bot];
	int a = evo_sim_agent_of_bot(s, bot);
	p->bot_name = b->name;
	p->bot = bot;
	p->bot_team = b->team >= 0 && b->team < s->n_teams && s->has_teams
			  ? s->team[b->team].name
			  : NULL;
	p->bot_reward = b->reward;
	if (a < 0) {
		/* no mind: every sensor and actuator of the bot */
		int ns = b->n_sensors < EVO_MAX_SENSORS ? b->n_sensors
							: EVO_MAX_SENSORS;
		int na = b->n_actuators < EVO_MAX_ACTUATORS ? b->n_actuators
							    : EVO_MAX_ACTUATORS;
		for (int i = 0; i < ns; i++) {
			pd->sensor_name[i] = b->sensor[i].name;
			pd->sensor[i] = b->sensor[i].value;
		}
		for (int i = 0; i < na; i++) {
			pd->actuator_name[i] = b->actuator[i].name;
			pd->actuator[i] = b->actuator[i].command;
		}
		p->n_sensors = ns;
		p->n_actuators = na;
		p->n_influence = 0;
	} else {
		/* what its mind reads and writes, in botdesc order */
		const evo_sim_agent *ag = &s->agent[a];
		const evo_sim_team *tm = &s->team[ag->team];
		const evo_mind *m = &ag->mind->mind;
		for (unsigned i = 0; i < m->n_sensors; i++) {
			pd->sensor_name[i] = evo_mind_sensor_name(m, i);
			pd->sensor[i] = b->sensor[tm->sensor_map[i]].value;
		}
		for (unsigned i = 0; i < m->n_actuators; i++) {
			pd->actuator_name[i] = evo_mind_actuator_name(m, i);
			pd->actuator[i] =
			    b->actuator[tm->actuator_map[i]].command;
		}
		p->n_sensors = (int)m->n_sensors;
		p->n_actuators = (int)m->n_actuators;
		int n = m->n_skills < 256 ? (int)m->n_skills : 256;
		for (int i = 0; i < n; i++) {
			pd->names[i] = evo_mind_skill_name(m, (unsigned)i);
			pd->infl[i] =
			    evo_q16_to_double(ag->state->influence[i]);
		}
		p->n_influence = n;
	}
	p->sensor_name = pd->sensor_name;
	p->sensor = pd->sensor;
	p->actuator_name = pd->actuator_name;
	p->actuator = pd->actuator;
}

static evo_viewer_panel panel_for(panel_data *pd, const evo_sim *s, long e,
				  const char *title, const view_state *vs)
{
	const evo_mind *m = &s->mind->mind;
	int n = m->n_skills < 256 ? (int)m->n_skills : 256;
	for (int i = 0; i < n; i++) {
		pd->names[i] = evo_mind_skill_name(m, (unsigned)i);
		pd->infl[i] = evo_q16_to_double(s->state->influence[i]);
	}
	evo_viewer_panel p = {
	    .tick = s->scene->tick,
	    .episode = (int)e,
	    .step_reward = s->scene->step_reward,
	    .episode_reward = s->scene->episode_reward,
	    .n_influence = n,
	    .influence_name = pd->names,
	    .influence = pd->infl,
	    .title = title,
	    .following = vs->follow,
	};
	if (s->has_teams) {
		for (int k = 0; k < s->n_teams; k++)
			pd->team_name[k] = s->team[k].name;
		p.n_teams = s->n_teams;
		p.team_name = pd->team_name;
		p.team_reward = s->scene->team_reward;
	}
	if (vs->selected >= 0 && vs->selected < s->scene->n_bots)
		panel_bot(pd, &p, s, vs->selected);
	return p;
}

/* --trail: the path of the task's bot this episode, for the viewer to
 * draw. A trail that cannot grow (out of memory) stops growing. */
typedef struct trail {
	double *x, *y;
	int n, cap;
} trail;

static void trail_add(trail *tr, const evo_sim *s)
{
	if (s->scene3d || s->bot < 0 || s->bot >= s->scene->n_bots)
		return;
	if (tr->n == tr->cap) {
		int cap = tr->cap ? 2 * tr->cap : 1024;
		double *x = realloc(tr->x, (size_t)cap * sizeof *x);
		if (x)
			tr->x = x;
		double *y = x ? realloc(tr->y, (size_t)cap * sizeof *y) : NULL;
		if (!y)
			return;
		tr->y = y;
		tr->cap = cap;
	}
	tr->x[tr->n] = s->scene->bot[s->bot].x;
	tr->y[tr->n] = s->scene->bot[s->bot].y;
	tr->n++;
}

/* A new episode's trail: where the bot starts. */
static void trail_restart(trail *tr, const run_opts *o, const evo_sim *s)
{
	tr->n = 0;
	if (o->trail)
		trail_add(tr, s);
}

static void trail_show(const trail *tr, evo_viewer_panel *p)
{
	p->n_trail = tr->n;
	p->trail_x = tr->x;
	p->trail_y = tr->y;
}

static void trail_free(trail *tr)
{
	free(tr->x);
	free(tr->y);
	*tr = (trail){0};
}

/* The camera of a frame drawn off screen: --camera and --zoom over the
 * viewer's own choice. */
static evo_view_camera frame_camera(const evo_sim *s, const run_opts *o,
				    const view_state *vs)
{
	/* the scene as it starts, unless --camera bot: a picture of the
	 * world, not of the bot's surroundings, all of it when no --zoom
	 * says otherwise (a maze wider than zoom 1's 60 m) */
	int follow = o->camera == 3 ? view_follow(s, vs) : EVO_VIEW_SCENE_START;
	double zoom = o->zoom > 0 ? o->zoom : 1.0;
	if (!(o->zoom > 0) && (o->camera == 0 || o->camera == 1))
		zoom = evo_view_fit_zoom(s->scene, VIEW_W, VIEW_H);
	evo_view_camera cam =
	    evo_view_camera_for(s->scene, follow, zoom, VIEW_W, VIEW_H);
	if (o->camera == 2) {
		cam.x = o->camera_x;
		cam.y = o->camera_y;
	}
	return cam;
}

static evo_viewer_panel panel3d(panel_data *pd, const evo_sim *s, long e,
				const char *title, int follow);

/* Draw the frame the viewer would show into im, with the bot's path
 * (--trail); a 3D task's in v3, the 3D view off screen, as its window
 * shows it (the camera following the robot). */
static void draw_frame(evo_raster *im, evo_sim *s, const run_opts *o,
		       long e, const trail *tr, evo_view3d *v3)
{
	static panel_data pd;
	if (s->scene3d) {
		evo_viewer_panel p = panel3d(&pd, s, e, o->task, 1);
		p.speed = 1.0;
		evo_view3d_draw(v3, s->scene3d, 0, &p);
		evo_view3d_frame(v3, im);
		return;
	}
	view_state vs = view_start(s);
	evo_viewer_panel p = panel_for(&pd, s, e, o->task, &vs);
	trail_show(tr, &p);
	evo_view_camera cam = frame_camera(s, o, &vs);
	evo_view_render(im, s->scene, &cam, &p);
}

/* --record: the run's episodes drawn off screen, a frame at each
 * episode's start and every --record-every ticks, into a folder of PNG
 * files or a video. */
static int record_run(evo_sim *s, const run_opts *o, uint64_t seed,
		      evo_view3d *v3, evo_err *err)
{
	long every = o->record_every > 0 ? o->record_every : 1;
	evo_raster im;
	if (evo_raster_init(&im, VIEW_W, VIEW_H, err))
		return -1;
	evo_recorder *rec = evo_record_open(o->record, VIEW_W, VIEW_H, 30, err);
	int rc = rec ? 0 : -1;
	trail tr = {0};
	for (long e = 1; rc == 0 && e <= o->episodes && !stop_requested; e++) {
		if (evo_sim_reset(s, (int)e, grid_seed(seed, e),
				  episode_seed(seed, e), err)) {
			rc = -1;
			break;
		}
		trail_restart(&tr, o, s);
		draw_frame(&im, s, o, e, &tr, v3);
		rc = evo_record_frame(rec, &im, err);
		long t = 0;
		while (rc == 0 && !stop_requested &&
		       (o->ticks == 0 || t < o->ticks)) {
			int r = evo_sim_tick(s, err);
			if (r < 0)
				rc = -1;
			t++;
			if (o->trail)
				trail_add(&tr, s);
			if (rc == 0 && (t % every == 0 || r > 0)) {
				draw_frame(&im, s, o, e, &tr, v3);
				rc = evo_record_frame(rec, &im, err);
			}
			if (r > 0)
				break;
		}
		if (rc == 0 && print_episode(s, e, t, err))
			rc = -1;
	}
	long frames = 0;
	evo_err cerr = {{0}};
	if (evo_record_close(rec, &frames, &cerr) && rc == 0) {
		*err = cerr;
		rc = -1;
	}
	if (rc == 0)
		printf("recorded %ld frame%s in %s\n", frames,
		       frames == 1 ? "" : "s", o->record);
	evo_raster_free(&im);
	trail_free(&tr);
	return rc;
}

/* --screenshot without a window: episode 1 for --ticks ticks (without
 * them and TICKLIM, until the episode ends, as a headless run), then the
 * frame the viewer would show at its default size, drawn off screen, and
 * the episode's line. */
static int screenshot_headless(evo_sim *s, const run_opts *o, uint64_t seed,
			       evo_view3d *v3, evo_err *err)
{
	if (evo_sim_reset(s, 1, grid_seed(seed, 1), episode_seed(seed, 1), err))
		return -1;
	if (v3)
		evo_view3d_aim(v3, s->scene3d);
	trail tr = {0};
	trail_restart(&tr, o, s);
	long t = 0;
	while ((o->ticks == 0 || t < o->ticks) && !stop_requested) {
		int r = evo_sim_tick(s, err);
		if (r < 0) {
			trail_free(&tr);
			return -1;
		}
		t++;
		if (o->trail)
			trail_add(&tr, s);
		if (r > 0)
			break;
	}
	evo_raster im;
	if (evo_raster_init(&im, VIEW_W, VIEW_H, err)) {
		trail_free(&tr);
		return -1;
	}
	draw_frame(&im, s, o, 1, &tr, v3);
	int rc = evo_raster_save_png(&im, o->screenshot, err);
	evo_raster_free(&im);
	trail_free(&tr);
	if (rc == 0)
		printf("saved %s (tick %ld, drawn without a window)\n",
		       o->screenshot,
		       s->scene3d ? s->scene3d->tick : s->scene->tick);
	if (rc == 0 && print_episode(s, 1, t, err))
		return -1;
	return rc;
}

/* ---- DEMOREMOTE: a robot ------------------------------------------------ */

/* What the robot's frame shows (viewer.h, evo_view_remote). */
typedef struct robot_view {
	const char *sensor_name[EVO_MAX_SENSORS];
	const char *actuator_name[EVO_MAX_ACTUATORS];
	const char *skill_name[256];
	double sensor[EVO_MAX_SENSORS], actuator[EVO_MAX_ACTUATORS];
	double influence[256];
	evo_view_remote p;
} robot_view;

static void robot_view_init(robot_view *rv, const evo_mind *m,
			    const evo_robot_conn *r, const char *title)
{
	memset(rv, 0, sizeof *rv);
	for (unsigned i = 0; i < m->n_sensors; i++)
		rv->sensor_name[i] = evo_mind_sensor_name(m, i);
	for (unsigned i = 0; i < m->n_actuators; i++) {
		rv->actuator_name[i] = evo_mind_actuator_name(m, i);
		rv->actuator[i] = 0.5;
	}
	int n = m->n_skills < 256 ? (int)m->n_skills : 256;
	for (int i = 0; i < n; i++)
		rv->skill_name[i] = evo_mind_skill_name(m, (unsigned)i);
	evo_view_remote *p = &rv->p;
	p->title = title;
	p->remote = evo_robot_conn_name(r);
	p->period_ms = evo_robot_conn_period(r) * 1e3;
	p->tick = -1;
	p->n_sensors = (int)m->n_sensors;
	p->sensor_name = rv->sensor_name;
	p->sensor = rv->sensor;
	p->n_actuators = (int)m->n_actuators;
	p->actuator_name = rv->actuator_name;
	p->actuator = rv->actuator;
	p->n_influence = n;
	p->influence_name = rv->skill_name;
	p->influence = rv->influence;
}

/* The link's state and the counts, as they are now. */
static void robot_view_update(robot_view *rv, const evo_robot_conn *r,
			      long e)
{
	evo_view_remote *p = &rv->p;
	evo_robot_status st;
	evo_robot_conn_status(r, &st);
	double period = evo_robot_conn_period(r);
	double timeout = evo_robot_conn_timeout(r);
	p->episode = (int)e;
	p->quiet = st.quiet;
	p->reward = st.reward;
	p->in_time = st.in_time;
	p->late = st.late;
	p->missing = st.missing;
	p->link = st.done		  ? EVO_VIEW_LINK_ENDED
		  : st.tick < 0		  ? EVO_VIEW_LINK_WAITING
		  : st.quiet >= timeout	  ? EVO_VIEW_LINK_SILENT
		  : st.quiet > 3 * period ? EVO_VIEW_LINK_QUIET
					  : EVO_VIEW_LINK_LIVE;
}

/* The robot's frame: in the window, or drawn without one into a PNG. */
static int robot_screenshot(evo_viewer *v, const robot_view *rv,
			    const char *path, evo_err *err)
{
	if (v) {
		evo_viewer_draw_remote(v, &rv->p);
		if (evo_viewer_screenshot(v, path, err))
			return -1;
		printf("saved %s (tick %ld)\n", path, rv->p.tick);
		return 0;
	}
	evo_raster im;
	if (evo_raster_init(&im, VIEW_W, VIEW_H, err))
		return -1;
	evo_view_render_remote(&im, &rv->p);
	int rc = evo_raster_save_png(&im, path, err);
	evo_raster_free(&im);
	if (rc == 0)
		printf("saved %s (tick %ld, drawn without a window)\n", path,
		       rv->p.tick);
	return rc;
}

/* The window's keys: 1 to quit. */
static int robot_keys(evo_viewer *v, const robot_view *rv, evo_err *err)
{
	evo_view_action a;
	while ((a = evo_viewer_poll(v)) != EVO_VIEW_NONE) {
		if (a == EVO_VIEW_QUIT)
			return 1;
		if (a == EVO_VIEW_SCREENSHOT) {
			char path[64];
			snprintf(path, sizeof path, "evo-screenshot-%ld.png",
				 rv->p.tick);
			if (evo_viewer_screenshot(v, path, err))
				fprintf(stderr, "%s\n", err->msg);
			else
				printf("saved %s\n", path);
			err->msg[0] = 0;
		}
	}
	return 0;
}

/* DEMOREMOTE: the mind here, the body a robot that ticks at its own rate
 * (docs/remote.md, A robot: free running), over LCM or over CAN
 * (docs/can.md). Each tick's sensors are answered at once with that
 * tick's commands; an episode runs until --ticks, the robot's end, a stop
 * or the window's closing; the robot then gets a STOP and goes neutral. */
static int run_robot(const evo_task *task, const run_opts *o, uint64_t seed,
		     FILE *trace, evo_viewer *v, evo_err *err)
{
	const evo_mind *m = &task->mind->mind;
	size_t need = (evo_state_size(m) + 7) & ~(size_t)7;
	void *mem = aligned_alloc(8, need);
	evo_state *state = NULL;
	if (!mem)
		return evo_fail(err, "out of memory");
	if (evo_state_init(m, mem, need, &state) != EVO_OK) {
		free(mem);
		return evo_fail(err, "mind state: cannot lay it out");
	}
	evo_robot_conn_def def = {
	    .mind = task->mind,
	    .task = task->sb,
	    .task_path = o->task,
	    .can_url = o->can,
	    .stop = &stop_requested,
	};
	evo_robot_conn *r = evo_robot_conn_open(&def, err);
	if (!r) {
		free(mem);
		return stop_requested ? 0 : -1;
	}
	printf("%s\n", evo_robot_conn_about(r));
	fflush(stdout);
	if (trace)
		evo_trace_header(trace, task->mind);
	static robot_view rv;
	robot_view_init(&rv, m, r, o->task);
	double period = evo_robot_conn_period(r);
	evo_robot_status st = {.tick = -1};
	int rc = 0, quit = 0, shot = 0, started = 0;
	double drawn = 0;
	evo_q16 qin[EVO_MAX_SENSORS], qout[EVO_MAX_ACTUATORS];
	for (long e = 1; (o->episodes == 0 || e <= o->episodes) && !quit &&
			 !shot && !stop_requested && rc == 0;
	     e++) {
		evo_state_reset(m, state);
		if (evo_robot_conn_start(r, e, grid_seed(seed, e),
					 episode_seed(seed, e), err)) {
			rc = -1;
			break;
		}
		started = 1;
		long ticks = 0; /* the robot's tick count when it ended */
		int end = 0;
		while (!quit) {
			end = evo_robot_conn_next(r, v ? 15 : 200, err);
			evo_robot_conn_status(r, &st);
			if (end < 0 || end == 1)
				break;
			if (end == 0 && o->ticks && st.tick >= o->ticks)
				break; /* the tick after the last: its reward */
			if (end == 0) {
				evo_robot_conn_sensors(r, qin);
				for (unsigned i = 0; i < m->n_sensors; i++)
					rv.sensor[i] = evo_q16_to_double(qin[i]);
				evo_mind_step(m, state, qin, qout);
				for (unsigned i = 0; i < m->n_actuators; i++)
					rv.actuator[i] =
					    evo_q16_to_double(qout[i]);
				if (evo_robot_conn_answer(r, qout, err)) {
					end = -1;
					break;
				}
				if (trace)
					evo_trace_tick(trace, (long)st.tick, m,
						       qin, qout, state);
				for (int i = 0; i < rv.p.n_influence; i++)
					rv.influence[i] = evo_q16_to_double(
					    state->influence[i]);
				rv.p.tick = (long)st.tick;
				ticks = (long)st.tick + 1;
			}
			robot_view_update(&rv, r, e);
			if (v) {
				quit = robot_keys(v, &rv, err);
				double t = now();
				if (t - drawn >= 1.0 / 30) {
					evo_viewer_draw_remote(v, &rv.p);
					drawn = t;
				}
			}
			if (end == 0 && o->ticks && ticks >= o->ticks) {
				/* the tick after the last one answered, for
				 * the reward it carries; not answered */
				double until = now() + 4 * period + 0.25;
				while ((end = evo_robot_conn_next(r, 20,
								  err)) == 2 &&
				       now() < until)
					;
				evo_robot_conn_status(r, &st);
				break;
			}
		}
		if (end < 0 && !stop_requested) {
			rc = -1;
			break;
		}
		if (end == 1 || (end == 0 && st.tick >= ticks))
			ticks = (long)st.tick;
		robot_view_update(&rv, r, e);
		printf("episode %ld: reward %.6f over %ld ticks\n", e,
		       st.reward, ticks);
		fflush(stdout);
		if (o->screenshot) {
			if (robot_screenshot(v, &rv, o->screenshot, err))
				rc = -1;
			shot = 1;
		}
		if (end < 0)
			break; /* stopped */
	}
	if (started)
		evo_robot_conn_report(r);
	evo_robot_conn_close(r);
	free(mem);
	return rc;
}

/* The playback actions both views share: pause, one step, faster,
 * slower (1/16 to 64 times real time), the episode again (*t = -1).
 * 1 when a was one of them. */
static int playback(evo_view_action a, int *paused, int *steps,
		    double *speed, long *t)
{
	if (a == EVO_VIEW_PAUSE)
		*paused = !*paused;
	else if (a == EVO_VIEW_STEP)
		*steps = 1, *paused = 1;
	else if (a == EVO_VIEW_FASTER)
		*speed = *speed < 64 ? *speed * 2 : *speed;
	else if (a == EVO_VIEW_SLOWER)
		*speed = *speed > 1.0 / 16 ? *speed / 2 : *speed;
	else if (a == EVO_VIEW_RESET)
		*t = -1;
	else
		return 0;
	return 1;
}

static int run_viewer_trail(evo_sim *s, evo_viewer *v, const run_opts *o,
			    uint64_t seed, trail *tr, evo_err *err);

/* DEMOSIM in a window: real time (30 ticks a second) times the speed,
 * with pause, single step, speed and reset keys. */
static int run_viewer(evo_sim *s, evo_viewer *v, const run_opts *o,
		      uint64_t seed, evo_err *err)
{
	trail tr = {0};
	int rc = run_viewer_trail(s, v, o, seed, &tr, err);
	trail_free(&tr);
	return rc;
}

static int run_viewer_trail(evo_sim *s, evo_viewer *v, const run_opts *o,
			    uint64_t seed, trail *tr, evo_err *err)
{
	static panel_data pd;
	view_state vs = view_start(s);
	long e = 1, t = 0;
	if (evo_sim_reset(s, 1, grid_seed(seed, 1), episode_seed(seed, 1), err))
		return -1;
	trail_restart(tr, o, s);
	double speed = 1.0, next = now();
	int paused = 0;
	for (;;) {
		if (stop_requested)
			return 0;
		int steps = paused ? 0 : 1;
		evo_view_action a;
		while ((a = evo_viewer_poll(v)) != EVO_VIEW_NONE) {
			if (a == EVO_VIEW_QUIT)
				return 0;
			if (playback(a, &paused, &steps, &speed, &t))
				continue;
			if (a == EVO_VIEW_SELECT) {
				double x, y;
				evo_viewer_clicked(v, &x, &y);
				vs.selected = evo_view_bot_at(s->scene, x, y);
			} else if (a == EVO_VIEW_NEXT_BOT &&
				   s->scene->n_bots > 0)
				vs.selected =
				    (vs.selected + 1) % s->scene->n_bots;
			else if (a == EVO_VIEW_CAMERA)
				vs.follow = !vs.follow;
			else if (a == EVO_VIEW_FREE)
				vs.follow = 0;
			else if (a == EVO_VIEW_SCREENSHOT) {
				char path[64];
				snprintf(path, sizeof path,
					 "evo-screenshot-%ld.png",
					 s->scene->tick);
				if (evo_viewer_screenshot(v, path, err))
					fprintf(stderr, "%s\n", err->msg);
				else
					printf("saved %s\n", path);
				err->msg[0] = 0;
			}
		}
		if (t < 0 || (o->episodes && e > o->episodes)) {
			if (e > o->episodes && o->episodes)
				return 0;
			t = 0;
			if (evo_sim_reset(s, (int)e, grid_seed(seed, e),
					  episode_seed(seed, e), err))
				return -1;
			trail_restart(tr, o, s);
		}
		for (int k = 0; k < steps; k++) {
			int r = evo_sim_tick(s, err);
			if (r < 0)
				return -1;
			if (o->trail)
				trail_add(tr, s);
			t++;
			if (r > 0 || (o->ticks && t >= o->ticks && !o->screenshot)) {
				if (print_episode(s, e, t, err))
					return -1;
				e++;
				t = -1;
				break;
			}
		}
		evo_viewer_panel p = panel_for(&pd, s, e, o->task, &vs);
		p.speed = speed;
		p.paused = paused;
		trail_show(tr, &p);
		evo_viewer_draw(v, s->scene, view_follow(s, &vs), &p);
		if (o->screenshot && t >= o->ticks) {
			if (evo_viewer_screenshot(v, o->screenshot, err))
				return -1;
			printf("saved %s (tick %ld)\n", o->screenshot,
			       s->scene->tick);
			return 0;
		}
		next += 1.0 / (30.0 * speed);
		if (next < now() - 0.5)
			next = now();
		sleep_until(next);
	}
}

/* ---- DEMO3DSIM in the 3D view ------------------------------------------- */

static const char *const help3d[] = {
    "space pause   n step", "up/down speed r reset", "drag turn  right pan",
    "wheel/+- zoom s shot", "c follow      q quit"};

/* The panel of a 3D task: the tick, the rewards, each skill's influence,
 * and the robot's sensors and commands as its mind reads and writes them. */
static evo_viewer_panel panel3d(panel_data *pd, const evo_sim *s, long e,
				const char *title, int follow)
{
	const evo_scene3d *sc = s->scene3d;
	const evo_bot3d *b = &sc->bot[0];
	const evo_mind *m = &s->mind->mind;
	int n = m->n_skills < 256 ? (int)m->n_skills : 256;
	for (int i = 0; i < n; i++) {
		pd->names[i] = evo_mind_skill_name(m, (unsigned)i);
		pd->infl[i] = evo_q16_to_double(s->state->influence[i]);
	}
	for (unsigned i = 0; i < m->n_sensors; i++) {
		pd->sensor_name[i] = evo_mind_sensor_name(m, i);
		pd->sensor[i] = b->sensor[s->sensor_map[i]].value;
	}
	for (unsigned i = 0; i < m->n_actuators; i++) {
		pd->actuator_name[i] = evo_mind_actuator_name(m, i);
		pd->actuator[i] = b->actuator[s->actuator_map[i]].command;
	}
	evo_viewer_panel p = {
	    .title = title,
	    .tick = sc->tick,
	    .episode = (int)e,
	    .step_reward = sc->step_reward,
	    .episode_reward = sc->episode_reward,
	    .n_influence = n,
	    .influence_name = pd->names,
	    .influence = pd->infl,
	    .bot_name = b->name,
	    .bot_reward = sc->episode_reward,
	    .n_sensors = (int)m->n_sensors,
	    .sensor_name = pd->sensor_name,
	    .sensor = pd->sensor,
	    .n_actuators = (int)m->n_actuators,
	    .actuator_name = pd->actuator_name,
	    .actuator = pd->actuator,
	    .following = follow,
	    .n_help = 5,
	    .help = help3d,
	};
	return p;
}

/* DEMO3DSIM in a window: as run_viewer, real time (30 ticks a second)
 * times the speed; --screenshot saves the frame at --ticks and ends. */
static int run_viewer3d(evo_sim *s, evo_view3d *v, const run_opts *o,
			uint64_t seed, evo_err *err)
{
	static panel_data pd;
	long e = 1, t = 0;
	int follow = 1, paused = 0;
	if (evo_sim_reset(s, 1, grid_seed(seed, 1), episode_seed(seed, 1), err))
		return -1;
	evo_view3d_aim(v, s->scene3d);
	double speed = 1.0, next = now();
	for (;;) {
		if (stop_requested)
			return 0;
		int steps = paused ? 0 : 1;
		evo_view_action a;
		while ((a = evo_view3d_poll(v)) != EVO_VIEW_NONE) {
			if (a == EVO_VIEW_QUIT)
				return 0;
			if (playback(a, &paused, &steps, &speed, &t))
				continue;
			if (a == EVO_VIEW_CAMERA)
				follow = !follow;
			else if (a == EVO_VIEW_FREE)
				follow = 0;
			else if (a == EVO_VIEW_SCREENSHOT) {
				char path[64];
				snprintf(path, sizeof path,
					 "evo-screenshot-%ld.png",
					 s->scene3d->tick);
				if (evo_view3d_screenshot(v, path, err))
					fprintf(stderr, "%s\n", err->msg);
				else
					printf("saved %s\n", path);
				err->msg[0] = 0;
			}
		}
		if (t < 0) {
			t = 0;
			if (evo_sim_reset(s, (int)e, grid_seed(seed, e),
					  episode_seed(seed, e), err))
				return -1;
		}
		for (int k = 0; k < steps; k++) {
			int r = evo_sim_tick(s, err);
			if (r < 0)
				return -1;
			t++;
			if (r > 0 ||
			    (o->ticks && t >= o->ticks && !o->screenshot)) {
				if (print_episode(s, e, t, err))
					return -1;
				if (o->episodes && e >= o->episodes)
					return 0;
				e++;
				t = -1;
				break;
			}
		}
		evo_viewer_panel p = panel3d(&pd, s, e, o->task, follow);
		p.speed = speed;
		p.paused = paused;
		evo_view3d_draw(v, s->scene3d, follow ? 0 : -1, &p);
		if (o->screenshot && t >= o->ticks) {
			if (evo_view3d_screenshot(v, o->screenshot, err))
				return -1;
			printf("saved %s (tick %ld)\n", o->screenshot,
			       s->scene3d->tick);
			return 0;
		}
		next += 1.0 / (30.0 * speed);
		if (next < now() - 0.5)
			next = now();
		sleep_until(next);
	}
}

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
static int env_choice(const char *task_path, const evo_task *task,
		      run_opts *o, char *genome, size_t cap, evo_err *err)
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
				o->run_dir ? "" : ", or run the task first: "
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
	size_t n = 0;
	for (const char *c = q + 1; c < end - 1 && n + 1 < cap; c++) {
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
		return evo_fail(err, "%s: --env N needs LEARNINGSKILL and a "
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

static int run_main(int argc, char **argv)
{
	run_opts o;
	if (parse_args(argc, argv, &o))
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
		fprintf(stderr, "%s: --env N shows an environment an OPENENDED "
				"run admitted; this is a %s task\n",
			o.task, task.type);
		evo_task_free(&task);
		return 2;
	}
	if (o.env) {
		int r = env_choice(o.task, &task, &o, genome, sizeof genome,
				   &err);
		evo_task_free(&task);
		to.nets = o.net;
		to.n_nets = o.n_nets;
		if (r || evo_task_load_opts(o.task, &to, &task, &err)) {
			fprintf(stderr, "%s\n", err.msg);
			return 1;
		}
	}
	if (o.n_nets && !o.env && (strncmp(task.type, "LEARN", 5) == 0 ||
				   strcmp(task.type, "OPENENDED") == 0)) {
		fprintf(stderr,
			"%s: --net chooses the networks a DEMOSIM run shows; "
			"a %s task trains over the networks in Skills/\n",
			o.task, task.type);
		evo_task_free(&task);
		return 2;
	}
	if (strcmp(task.type, "LEARNSIM") == 0 ||
	    strcmp(task.type, "LEARN3DSIM") == 0 ||
	    strcmp(task.type, "LEARNSIMCONTINUOUS") == 0 ||
	    strcmp(task.type, "LEARN2DSIMMULTI") == 0 ||
	    strcmp(task.type, "LEARNREMOTESIM") == 0 ||
	    (strcmp(task.type, "OPENENDED") == 0 && !o.env)) {
		if (o.episodes >= 0) {
			/* it would be ignored: say so rather than run a task
			 * other than the one asked for */
			fprintf(stderr,
				"evo run: --episodes is for DEMO tasks; %s is a "
				"%s task, whose networks each play EVALREP "
				"episodes (docs/learning.md)\n",
				o.task, task.type);
			evo_task_free(&task);
			return 2;
		}
		/* --threads, else the task's THREADS, else one per core */
		const char *tv = evo_simbatch_get(task.sb, "THREADS");
		long threads = o.threads ? o.threads
			       : tv	 ? strtol(tv, NULL, 10)
					 : 0;
		evo_learn_opts lo = {
			.seed = seed,
			.threads = (int)threads,
			.generations = (int)o.generations,
			.ticks = o.ticks,
			.run_dir = o.run_dir,
			.resume = o.resume,
			.no_save = o.no_save,
			.argv0 = argv[0],
		};
		char dir[1024];
		if (o.resume &&
		    (evo_learn_run_dir(o.task, &task, &lo, dir, sizeof dir,
				       &err) ||
		     evo_run_record_restore(dir, &lo, o.seed_set, &err))) {
			fprintf(stderr, "%s\n", err.msg);
			evo_task_free(&task);
			return 2;
		}
		if (evo_cluster_launched()) {
			int rc = learn_on_cluster(o.task, &task, &lo);
			evo_task_free(&task);
			return rc;
		}
		int rc = evo_learn_run(o.task, &task, &lo, &err);
		if (rc)
			fprintf(stderr, "%s\n", err.msg);
		evo_task_free(&task);
		return rc ? 1 : 0;
	}
	if (o.can && strcmp(task.type, "DEMOREMOTE") != 0) {
		fprintf(stderr,
			"evo run: --can is for DEMOREMOTE tasks (a robot on a "
			"CAN bus); %s is a %s task\n",
			o.task, task.type);
		evo_task_free(&task);
		return 2;
	}
	if (evo_robot_task_check(task.sb, task.type, o.task, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		evo_task_free(&task);
		return 1;
	}
	if (!evo_run_supports(task.type)) {
		fprintf(stderr,
			"%s: evo run does not run %s tasks yet (it runs "
			"DEMOSIM, LEARNSIM, LEARNSIMCONTINUOUS, DEMO3DSIM, "
			"LEARN3DSIM, DEMO2DSIMMULTI, LEARN2DSIMMULTI, "
			"DEMOREMOTESIM, LEARNREMOTESIM and DEMOREMOTE)\n",
			o.task, task.type);
		evo_task_free(&task);
		return 1;
	}
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	evo_lua_watch_stop(&stop_requested);

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
		if (trace_open(&tf, o.trace, &err) == 0) {
			int r = run_remote_sim(&task, &o, seed, tf.f, &err);
			if (trace_close(&tf, r == 0, &err) == 0 && r == 0)
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
	    (o.camera || o.zoom > 0 || (o.trail && (o.screenshot || o.record)))) {
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
		if (trace_open(&tf, o.trace, &err))
			goto out;
		int r = run_robot(&task, &o, seed, tf.f, v, &err);
		if (trace_close(&tf, r == 0, &err) == 0 && r == 0)
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
	if (trace_open(&tf, o.trace, &err))
		goto out;
	s->trace = tf.f;
	if (s->trace)
		evo_sim_trace_header(s);
	int r = o.record       ? record_run(s, &o, seed, v3, &err)
		: window3d     ? run_viewer3d(s, v3, &o, seed, &err)
		: v	       ? run_viewer(s, v, &o, seed, &err)
		: o.screenshot ? screenshot_headless(s, &o, seed, v3, &err)
			       : run_headless(s, &o, seed, &err);
	s->trace = NULL;
	/* A failed run drops its trace; trace_close then leaves err alone. */
	if (trace_close(&tf, r == 0, &err) == 0 && r == 0)
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
