/* make bench: evo's full 3D tick on EXP3D_Avoid beside ODE alone stepping
 * the same world, measured in the same run.
 *
 * The floor is ODE by itself: the scene's own worlds (the walls, each
 * episode's 24 obstacles, the Wheeled3D robot's chassis, caster and two
 * hinged wheels) stepped as a tick steps them, `substeps` physics steps,
 * with the wheels turned at the rates the mind commanded in the full
 * tick's run, tick by tick, so the robot takes the same paths and meets
 * the same contacts; no rays, mind, rewards, controls or Lua, and its
 * resets are not timed. The full tick is what `evo run --headless` does: the 8
 * proximity rays, the mind, the wheels, the physics, the rewards and the
 * controls, and an episode's reset (its world made again, the environment's
 * reset in Lua) when one ends. Bar (issue 20): the full tick reaches at least
 * 0.5 of the floor.
 *
 * usage: bench_world3d [TASK.simbatch] [--ticks N] */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_proc.h"
#include "bench_args.h"
#include "mind/task.h"
#include "tasksim/tasksim.h"
#include "world3d/scene3d.h"
#include "world3d/world3d.h"

#define ROUNDS 9
#define BAR    0.50

/* Where the robot's hull is now, from the world itself. */
static void hull_position(const evo_scene3d *sc, double pos[3])
{
	double R[9];
	evo_body3d_pose(sc->world, sc->bot[0].body.index, pos, R);
}

/* What the full tick's run did, for the floor to do again: each tick's
 * wheel commands, and the ticks after which an episode began anew. */
typedef struct replay {
	double (*cmd)[2];
	char *reset_after;
	uint64_t first_episode;
	double end[3]; /* where the robot was at the end */
} replay;

static void reset(evo_sim *s, uint64_t episode)
{
	evo_err err;
	if (evo_sim_reset(s, (int)episode, episode, episode, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		exit(1);
	}
}

/* The full tick, recording the wheel commands the mind gave. */
static double run_full(evo_sim *s, long ticks, uint64_t *episode, replay *rp)
{
	evo_err err;
	rp->first_episode = *episode;
	reset(s, *episode);
	const evo_bot *b = &s->scene3d->bot[0];
	double t0 = bench_now(), paused = 0;
	for (long t = 0; t < ticks; t++) {
		int r = evo_sim_tick(s, &err);
		if (r < 0) {
			fprintf(stderr, "%s\n", err.msg);
			exit(1);
		}
		double p0 = bench_now();
		rp->cmd[t][0] = b->actuator[0].command;
		rp->cmd[t][1] = b->actuator[1].command;
		rp->reset_after[t] = r > 0;
		paused += bench_now() - p0;
		if (r > 0)
			reset(s, ++*episode);
	}
	double rate = (double)ticks / (bench_now() - t0 - paused);
	hull_position(s->scene3d, rp->end);
	return rate;
}

/* ODE alone on the same worlds (made by the same resets, untimed), the
 * wheels at the rates the mind commanded tick by tick: the same bodies
 * on the same paths, with no rays, mind, rewards, controls or Lua. */
static double run_floor(evo_sim *s, long ticks, const replay *rp)
{
	uint64_t episode = rp->first_episode;
	reset(s, episode);
	evo_scene3d *sc = s->scene3d;
	double total = 0;
	double t0 = bench_now();
	for (long t = 0; t < ticks; t++) {
		const evo_bot *b = &sc->bot[0];
		for (int k = 0; k < sc->def.substeps; k++) {
			for (int a = 0; a < 2; a++) {
				const evo_actuator *w = &b->actuator[a];
				evo_world3d_hinge_velocity(
				    sc->world, w->hinge,
				    (2 * rp->cmd[t][a] - 1) * w->def.max_rate,
				    w->def.max_torque);
			}
			evo_bfault f;
			if (evo_world3d_step(sc->world, &f)) {
				fprintf(stderr, "bench_world3d: the floor's "
						"world exploded\n");
				exit(1);
			}
		}
		if (rp->reset_after[t]) {
			total += bench_now() - t0;
			reset(s, ++episode);
			t0 = bench_now();
		}
	}
	total += bench_now() - t0;
	/* the same path, or the floor measured something else */
	double end[3];
	hull_position(sc, end);
	for (int i = 0; i < 3; i++)
		if (end[i] != rp->end[i]) {
			fprintf(stderr, "bench_world3d: the floor's robot "
					"ended elsewhere than the full "
					"tick's\n");
			exit(1);
		}
	return (double)ticks / total;
}

int main(int argc, char **argv)
{
	const char *task_path = "minds/Wheeled3D/Tasks/Avoid3D-DEMO.simbatch";
	long ticks = 6000;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--ticks") == 0 && i + 1 < argc) {
			long long n;
			if (bench_ticks_arg("bench_world3d", argv[++i], &n))
				return 2;
			ticks = (long)n;
		} else
			task_path = argv[i];
	}
	evo_err err = {{0}};
	evo_task task;
	if (evo_task_load(task_path, &task, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		return 1;
	}
	evo_sim *s = evo_sim_create(task.mind, task.sb, task_path, &err);
	if (!s || !s->scene3d) {
		fprintf(stderr, "%s\n",
			s ? "bench_world3d: not a 3D task" : err.msg);
		return 1;
	}
	if (s->scene3d->bot[0].n_actuators < 2 ||
	    s->scene3d->bot[0].actuator[0].def.kind != EVO_ACT_WHEEL ||
	    s->scene3d->bot[0].actuator[1].def.kind != EVO_ACT_WHEEL) {
		fprintf(stderr, "bench_world3d: the bot has no two wheels\n");
		return 1;
	}
	replay rp = {.cmd = malloc((size_t)ticks * sizeof *rp.cmd),
		     .reset_after = malloc((size_t)ticks)};
	if (!rp.cmd || !rp.reset_after) {
		fprintf(stderr, "bench_world3d: out of memory\n");
		return 1;
	}
	uint64_t episode = 1;
	double best_floor = 0, best_full = 0;
	for (int round = 0; round < ROUNDS; round++) {
		double e = run_full(s, ticks, &episode, &rp);
		double f = run_floor(s, ticks, &rp);
		best_floor = f > best_floor ? f : best_floor;
		best_full = e > best_full ? e : best_full;
	}
	const evo_scene3d *sc = s->scene3d;
	int rays = 0;
	for (int k = 0; k < sc->bot[0].n_sensors; k++)
		if (sc->bot[0].sensor[k].def.kind == EVO_SENSE_PROXIMITY)
			rays += sc->bot[0].sensor[k].def.rays;
	double ratio = best_full / best_floor;
	printf("EXP3D_Avoid, one robot (%s), %d static obstacles, %d physics "
	       "steps a tick, best of %d runs of %ld ticks:\n",
	       evo_simbatch_get(task.sb, "BOTMODEL"), sc->n_obstacles,
	       sc->def.substeps, ROUNDS, ticks);
	printf("  physics floor (ODE alone, the mind's wheel rates) "
	       "%9.0f ticks/s  %6.2f us/tick\n",
	       best_floor, 1e6 / best_floor);
	printf("  evo full tick (%d rays, mind, rewards, resets)     "
	       "%9.0f ticks/s  %6.2f us/tick\n",
	       rays, best_full, 1e6 / best_full);
	printf("  ratio %.2f of the floor (bar: at least %.2f): %s\n", ratio,
	       BAR, ratio >= BAR ? "met" : "NOT MET");
	free(rp.cmd);
	free(rp.reset_after);
	evo_sim_destroy(s);
	evo_task_free(&task);
	return ratio >= BAR ? 0 : 1;
}
