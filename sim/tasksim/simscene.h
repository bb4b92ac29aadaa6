/* evo — a task's scene seen through one interface, whatever its dimension:
 * what sim/tasksim/tasksim.c asks of the world it runs (reset, sense, step,
 * the bots' names, sensors and actuators, the episode's figures), so that
 * it never asks which world it holds. Two sides fill it, in simscene.c:
 * the 2D scene (world2d/scene.h) and the 3D one (world3d/scene3d.h).
 *
 * This is step 1 of docs/architecture.md's "Where the layout is going":
 * the functions are the shape the one scene model's own API takes, and
 * the two sides fold into one when the scenes do. What one dimension has
 * and the other lacks is said here, as data (teams, metrics, idle
 * sensors), not asked of the dimension by the caller. */
#ifndef EVO_SIMSCENE_H
#define EVO_SIMSCENE_H

#include <stdint.h>

#include "base/err.h"

typedef struct evo_simscene {
	const char *name; /* "2D" or "3D", for messages */
	/* 1 when its bots can be of teams (team tasks, docs/teams.md) */
	int teams;

	/* Start an episode; 0, or -1 with err set. */
	int (*reset)(void *sc, uint64_t grid_seed, uint64_t episode_seed,
		     evo_err *err);
	/* Step 1 of the tick: every bot's sensors sample. */
	void (*sense)(void *sc);
	/* Steps 3 to 5: 1 when the episode ends, 0 when it goes on, -1 with
	 * err set (a hook failed). */
	int (*step)(void *sc, evo_err *err);

	/* The bots and their parts: lookups by name give -1 when absent. */
	int (*n_bots)(const void *sc);
	const char *(*bot_name)(const void *sc, int bot);
	int (*bot_team)(const void *sc, int bot); /* -1: none */
	int (*n_parts)(const void *sc, int bot, int sensors);
	const char *(*part_name)(const void *sc, int bot, int sensors, int i);
	int (*find_part)(const void *sc, int bot, int sensors,
			 const char *name);
	/* values[i] = sensor map[i]'s last sample; actuator map[i]'s command =
	 * commands[i]. */
	void (*read)(const void *sc, int bot, const int *map, unsigned n,
		     double *values);
	void (*write)(void *sc, int bot, const int *map, unsigned n,
		      const double *commands);
	/* Mark a sensor of bot idle (1: not sampled) or not; wake the
	 * sensors the rewards and controls read. Nothing, where every sensor
	 * is sampled every tick (3D). */
	void (*set_idle)(void *sc, int bot, int sensor, int idle);
	void (*wake_scored)(void *sc);

	/* The episode's figures. */
	long (*ticks)(const void *sc);
	double (*episode_reward)(const void *sc);
	int (*collisions)(const void *sc, int bot);
	/* Teams (docs/teams.md): what bot was paid, what team was paid (its
	 * bots' own and its team rewards), the winner (-1: none). */
	double (*bot_reward)(const void *sc, int bot);
	double (*team_reward)(const void *sc, int team);
	int (*winner)(const void *sc);
	int (*n_metrics)(const void *sc);
	const char *(*metric_name)(const void *sc, int k);
	double (*metric)(const void *sc, int k);
	const char *(*fault)(const void *sc); /* "" when nothing broke */

	/* Where bot is on the ground plane now, and where it started. */
	void (*ground_pos)(const void *sc, int bot, double now[2],
			   double start[2]);
	/* Widen box (x0, y0, x1, y1) over the static obstacles the
	 * environment built (evo_sim_behaviour's arena). */
	void (*arena)(const void *sc, double box[4]);
} evo_simscene;

extern const evo_simscene evo_simscene_2d;
extern const evo_simscene evo_simscene_3d;

#endif
