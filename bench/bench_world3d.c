/* make bench: evo's full 3D tick on EXP3D_Avoid beside ODE alone stepping
 * the same world, measured in the same run.
 *
 * The floor is ODE by itself: the scene's own world (the walls, the
 * episode's 24 obstacles, the Wheeled3D robot's chassis, caster and two
 * hinged wheels) stepped as a tick steps it, `substeps` physics steps,
 * with the wheels held at constant rates, and no rays, mind, rewards or
 * Lua. The full tick is what `evo run --headless` does: the 8 proximity
 * rays, the mind, the wheels, the physics, the rewards and the controls,
 * and an episode's reset (its world made again, the environment's reset
 * in Lua) when one ends. Bar (issue 20): the full tick reaches at least
 * 0.5 of the floor.
 *
 * usage: bench_world3d [TASK.simbatch] [--ticks N] */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mind/task.h"
#include "tasksim/tasksim.h"
#include "world3d/scene3d.h"
#include "world3d/world3d.h"

#define ROUNDS 9
#define BAR    0.50

static double now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* ODE alone on the scene's world, fresh from a reset: the wheels at the
 * rates of commands 0.9 and 0.8 (wide circles that meet obstacles now and
 * then), `substeps` steps a tick. */
static double run_floor(evo_sim *s, long ticks, uint64_t seed)
{
	evo_err err;
	evo_sim_reset(s, 1, seed, seed, &err);
	evo_scene3d *sc = s->scene3d;
	const evo_bot3d *b = &sc->bot[0];
	double t0 = now();
	for (long t = 0; t < ticks; t++)
		for (int k = 0; k < sc->def.substeps; k++) {
			for (int a = 0; a < b->n_actuators; a++) {
				const evo_actuator3d *w = &b->actuator[a];
				double c = a == 0 ? 0.9 : 0.8;
				evo_world3d_hinge_velocity(sc->world, w->hinge,
							   (2 * c - 1) *
							       w->def.max_rate,
							   w->def.max_torque);
			}
			evo_world3d_fault f;
			if (evo_world3d_step(sc->world, &f)) {
				fprintf(stderr, "bench_world3d: the floor's "
						"world exploded\n");
				exit(1);
			}
		}
	return (double)ticks / (now() - t0);
}

static double run_full(evo_sim *s, long ticks, uint64_t *episode)
{
	evo_err err;
	if (evo_sim_reset(s, (int)*episode, *episode, *episode, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		exit(1);
	}
	double t0 = now();
	for (long t = 0; t < ticks; t++) {
		int r = evo_sim_tick(s, &err);
		if (r < 0) {
			fprintf(stderr, "%s\n", err.msg);
			exit(1);
		}
		if (r > 0) {
			++*episode;
			evo_sim_reset(s, (int)*episode, *episode, *episode,
				      &err);
		}
	}
	return (double)ticks / (now() - t0);
}

int main(int argc, char **argv)
{
	const char *task_path = "minds/Wheeled3D/Tasks/Avoid3D-DEMO.simbatch";
	long ticks = 6000;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--ticks") == 0 && i + 1 < argc)
			ticks = atol(argv[++i]);
		else
			task_path = argv[i];
	}
	if (ticks <= 0) {
		fprintf(stderr, "bench_world3d: --ticks must be positive\n");
		return 2;
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
	uint64_t episode = 1;
	double best_floor = 0, best_full = 0;
	for (int round = 0; round < ROUNDS; round++) {
		double f = run_floor(s, ticks, (uint64_t)round + 1);
		double e = run_full(s, ticks, &episode);
		best_floor = f > best_floor ? f : best_floor;
		best_full = e > best_full ? e : best_full;
	}
	const evo_scene3d *sc = s->scene3d;
	int rays = 0;
	for (int k = 0; k < sc->bot[0].n_sensors; k++)
		if (sc->bot[0].sensor[k].def.kind == EVO3D_SENSOR_PROXIMITY)
			rays += sc->bot[0].sensor[k].def.rays;
	double ratio = best_full / best_floor;
	printf("EXP3D_Avoid, one robot (%s), %d static obstacles, %d physics "
	       "steps a tick, best of %d runs of %ld ticks:\n",
	       evo_simbatch_get(task.sb, "BOTMODEL"), sc->n_obstacles,
	       sc->def.substeps, ROUNDS, ticks);
	printf("  physics floor (ODE alone, constant wheel rates)   "
	       "%9.0f ticks/s  %6.2f us/tick\n",
	       best_floor, 1e6 / best_floor);
	printf("  evo full tick (%d rays, mind, rewards, resets)     "
	       "%9.0f ticks/s  %6.2f us/tick\n",
	       rays, best_full, 1e6 / best_full);
	printf("  ratio %.2f of the floor (bar: at least %.2f): %s\n", ratio,
	       BAR, ratio >= BAR ? "met" : "NOT MET");
	evo_sim_destroy(s);
	evo_task_free(&task);
	return ratio >= BAR ? 0 : 1;
}
