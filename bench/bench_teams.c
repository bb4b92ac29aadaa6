/* make bench: many bots, each with its own mind, beside the physics floor
 * of the same world, measured in the same run (docs/teams.md, Scale).
 *
 * A team of N bots (10, 100 and 1,000) in a walled square whose side grows
 * with the square root of N, so the bots are as crowded in each: every bot
 * carries one proximity sensor of 8 rays (obstacles and the other bots)
 * and runs a small hierarchy of its own (a neural master skill reading the
 * sensor and giving influence to two hard-coded skills that drive the
 * wheels). The full tick is DEMO2DSIMMULTI's: every bot senses, every
 * mind steps, the actuators act, the physics steps. The floor is Box2D
 * alone with the same bodies (the wall's cylinders and the bots' circles,
 * at the same places), each bot pushed by constant wheel forces.
 *
 * Printed for each N: both rates, their ratio, and the cost of a bot-tick
 * (the full tick's time over N), with evo's own share of it (the full
 * tick's time less the floor's, over N). Bars: at 1,000 bots the full
 * tick reaches at least 0.4 of the floor, and a bot-tick at 1,000 bots
 * costs at most twice what it costs at 10. Exits 1 when a bar is missed.
 *
 * usage: bench_teams [--quick] */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench_proc.h"
#include "base/fileio.h"
#include "base/number.h"
#include "mind/task.h"
#include "tasksim/tasksim.h"
#include "world2d/scene.h"

#define RATIO_BAR 0.40
#define COST_BAR  2.0

static char dir[256];

static int put(const char *rel, const char *text)
{
	char path[512];
	evo_err err;
	snprintf(path, sizeof path, "%s/%s", dir, rel);
	if (evo_write_file_atomic(path, text, strlen(text), &err)) {
		fprintf(stderr, "%s\n", err.msg);
		return -1;
	}
	return 0;
}

/* The mind folder Swarm: its bot model, environment, hierarchy and one
 * task per N. */
static int make_mind(void)
{
	static const char *const sub[] = {"Swarm",
					  "Swarm/Bots",
					  "Swarm/Envs",
					  "Swarm/Tasks",
					  "Swarm/Skills",
					  "Swarm/Skills/Drive",
					  "Swarm/Skills/MoveForward",
					  "Swarm/Skills/TurnLeft"};
	for (size_t i = 0; i < sizeof sub / sizeof sub[0]; i++) {
		char p[512];
		snprintf(p, sizeof p, "mkdir -p %s/%s", dir, sub[i]);
		if (system(p) != 0)
			return -1;
	}
	return put("Swarm/Swarm.botdesc",
		   "SENSORS\nPROX:proxSensor\nACTUATORS\nMotL:wheel\n"
		   "MotR:wheel\n") ||
	       put("Swarm/Bots/SwarmBot.lua",
		   "return {\n"
		   "  body = { shape = 'circle', radius = 0.5 },\n"
		   "  build = function(bot)\n"
		   "    bot:proximity{ name = 'PROX', x = 0.5, range = 4, arc "
		   "= "
		   "60, rays = 8, sees = { 'obstacles', 'bots' } }\n"
		   "    bot:wheel{ name = 'MotL', y = -0.5, max_force = 20 }\n"
		   "    bot:wheel{ name = 'MotR', y = 0.5, max_force = 20 }\n"
		   "  end,\n"
		   "}\n") ||
	       /* bots on a grid of 4 m, a wall of touching cylinders */
	       put("Swarm/Envs/Swarm.lua",
		   "local env = {}\n"
		   "function env.init(scene, task)\n"
		   "  local t = scene:teams()[1]\n"
		   "  local side = math.ceil(math.sqrt(t.size))\n"
		   "  local half = side * 2 + 2\n"
		   "  for v = -half, half, 2 do\n"
		   "    scene:cylinder{ x = v, y = -half, radius = 1 }\n"
		   "    scene:cylinder{ x = v, y = half, radius = 1 }\n"
		   "    if v > -half and v < half then\n"
		   "      scene:cylinder{ x = -half, y = v, radius = 1 }\n"
		   "      scene:cylinder{ x = half, y = v, radius = 1 }\n"
		   "    end\n"
		   "  end\n"
		   "  for i = 0, t.size - 1 do\n"
		   "    scene:bot{ team = t.name, x = -half + 3 + 4 * (i % "
		   "side),\n"
		   "      y = -half + 3 + 4 * (i // side), angle = (i * 137) % "
		   "360 }\n"
		   "  end\n"
		   "end\n"
		   "return env\n") ||
	       /* the master: ahead clear, forward; something near, turn */
	       put("Swarm/Skills/Drive/Drive.ades",
		   "Drive\ninput:1\nSE:PROX\noutput:2\nSK:MoveForward\n"
		   "SK:TurnLeft\nneural\nlayers:0\n") ||
	       put("Swarm/Skills/Drive/Drive.net",
		   "inputs:1\noutputs:2\nnode:1:sigmoid:-2\nnode:2:sigmoid:2\n"
		   "output:1\noutput:2\nlink:0:1:6\nlink:0:2:-6\n") ||
	       put("Swarm/Skills/MoveForward/MoveForward.ades",
		   "MoveForward\ninput:0\noutput:2\nMO:MotL\nMO:MotR\n"
		   "hardCoded\nclass:MoveForward\n") ||
	       put("Swarm/Skills/TurnLeft/TurnLeft.ades",
		   "TurnLeft\ninput:0\noutput:2\nMO:MotL\nMO:MotR\nhardCoded\n"
		   "class:TurnLeft\n");
}

/* The same world in plain Box2D: the wall's obstacles and the bots'
 * bodies where they start. */
static evo_world *floor_world(const evo_scene *sc, evo_body_id *bots)
{
	evo_world *w = evo_world_create(NULL);
	for (int i = 0; i < sc->n_obstacles; i++) {
		const evo_obstacle *o = &sc->obstacle[i];
		evo_world_add_static_circle(w, o->x, o->y, o->radius);
	}
	for (int b = 0; b < sc->n_bots; b++) {
		evo_bbody_def d = sc->bot[b].def.body;
		d.pos[0] = sc->bot[b].def.x;
		d.pos[1] = sc->bot[b].def.y;
		d.yaw = sc->bot[b].def.yaw;
		bots[b] = evo_backend_box2d.add_body((evo_bworld *)w, &d);
	}
	return w;
}

/* Constant wheel commands 0.9 and 0.8 on every bot: they drive in wide
 * circles and meet one another and the wall, as a moving swarm does. */
static double run_floor(const evo_scene *sc, long ticks)
{
	evo_body_id *bots = malloc((size_t)sc->n_bots * sizeof *bots);
	evo_world *w = floor_world(sc, bots);
	const double fl = (2 * 0.9 - 1) * 20, fr = (2 * 0.8 - 1) * 20;
	double t0 = bench_now();
	for (long t = 0; t < ticks; t++) {
		for (int b = 0; b < sc->n_bots; b++) {
			evo_pose p = evo_body_pose(w, bots[b]);
			double c = cos(p.angle), s = sin(p.angle);
			double hs = 0.5 * s, hc = 0.5 * c;
			evo_body_apply_force(w, bots[b], c * fl, s * fl,
					     p.x + hs, p.y - hc);
			evo_body_apply_force(w, bots[b], c * fr, s * fr,
					     p.x - hs, p.y + hc);
		}
		evo_world_step(w);
	}
	double dt = bench_now() - t0;
	evo_world_destroy(w);
	free(bots);
	return (double)ticks / dt;
}

static double run_full(evo_sim *s, long ticks)
{
	evo_err err;
	double t0 = bench_now();
	for (long t = 0; t < ticks; t++)
		if (evo_sim_tick(s, &err) < 0) {
			fprintf(stderr, "%s\n", err.msg);
			exit(1);
		}
	return (double)ticks / (bench_now() - t0);
}

typedef struct figures {
	int bots;
	double floor, full; /* ticks per second */
} figures;

static int measure(int n, long ticks, int rounds, figures *f)
{
	char task[512], text[256];
	snprintf(text, sizeof text,
		 "TYPE:DEMO2DSIMMULTI\nENV:Swarm\n"
		 "TEAM:Swarm:Swarm:SwarmBot:%d:Drive\n",
		 n);
	snprintf(task, sizeof task, "Swarm/Tasks/S%d.simbatch", n);
	if (put(task, text))
		return -1;
	snprintf(task, sizeof task, "%s/Swarm/Tasks/S%d.simbatch", dir, n);
	evo_err err = {{0}};
	evo_task t;
	if (evo_task_load(task, &t, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		return -1;
	}
	evo_sim *s = evo_sim_create_task(&t, task, &err);
	if (!s || evo_sim_reset(s, 1, 1, 1, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		evo_sim_destroy(s);
		evo_task_free(&t);
		return -1;
	}
	/* the swarm under way first: bots spread and meet */
	run_full(s, ticks / 4 + 1);
	f->bots = n;
	f->floor = f->full = 0;
	/* alternated, best of `rounds` each: the machine's noise hits both
	 * alike */
	for (int r = 0; r < rounds; r++) {
		double a = run_floor(s->scene, ticks);
		double b = run_full(s, ticks);
		f->floor = a > f->floor ? a : f->floor;
		f->full = b > f->full ? b : f->full;
	}
	evo_sim_destroy(s);
	evo_task_free(&t);
	return 0;
}

int main(int argc, char **argv)
{
	int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
	const char *tmp = getenv("TMPDIR");
	snprintf(dir, sizeof dir, "%s/evo-bench-teams-XXXXXX",
		 tmp && tmp[0] ? tmp : "/tmp");
	if (!mkdtemp(dir) || make_mind()) {
		fprintf(stderr, "bench_teams: cannot make its mind folder\n");
		return 1;
	}
	static const int sizes[] = {10, 100, 1000};
	/* about the same bot-ticks for each size */
	static const long ticks[] = {20000, 2000, 200};
	figures f[3];
	int rc = 0;
	/* BENCH_TEAMS_ONLY=N measures N bots alone (for a profiler) */
	const char *only = getenv("BENCH_TEAMS_ONLY");
	long long only_n = 0;
	if (only && evo_parse_whole(only, NULL, 1, 1000, &only_n)) {
		fprintf(stderr, "bench_teams: BENCH_TEAMS_ONLY expects 10, 100 "
				"or 1000, found '%s'\n",
			only);
		return 2;
	}
	for (int k = 0; k < 3 && rc == 0; k++) {
		if (only && only_n != sizes[k]) {
			f[k] = (figures){sizes[k], 1, 1};
			continue;
		}
		rc = measure(sizes[k], quick ? ticks[k] / 10 : ticks[k],
			     quick ? 3 : 7, &f[k]);
	}
	char rm[300];
	snprintf(rm, sizeof rm, "rm -rf %s", dir);
	if (system(rm) != 0)
		fprintf(stderr, "bench_teams: could not remove %s\n", dir);
	if (rc)
		return 1;
	printf("a team of N bots, 8 proximity rays and a mind of 3 skills "
	       "each, best of %d runs:\n",
	       quick ? 3 : 7);
	printf("  %5s %14s %14s %6s %16s %16s\n", "bots", "floor ticks/s",
	       "evo ticks/s", "ratio", "us per bot-tick", "evo's own share");
	for (int k = 0; k < 3; k++) {
		double cost = 1e6 / f[k].full / f[k].bots;
		double own = (1e6 / f[k].full - 1e6 / f[k].floor) / f[k].bots;
		printf("  %5d %14.0f %14.0f %6.2f %16.3f %16.3f\n", f[k].bots,
		       f[k].floor, f[k].full, f[k].full / f[k].floor, cost,
		       own);
	}
	double ratio = f[2].full / f[2].floor;
	double growth = (f[0].full * f[0].bots) / (f[2].full * f[2].bots);
	printf("  at 1,000 bots: %.2f of the floor (bar: at least %.2f): %s\n",
	       ratio, RATIO_BAR, ratio >= RATIO_BAR ? "met" : "NOT MET");
	printf("  a bot-tick at 1,000 bots costs %.2f times one at 10 (bar: at "
	       "most %.1f): %s\n",
	       growth, COST_BAR, growth <= COST_BAR ? "met" : "NOT MET");
	return ratio >= RATIO_BAR && growth <= COST_BAR ? 0 : 1;
}
