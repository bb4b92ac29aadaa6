/* What one evaluation of a candidate gives, and the seeds it runs with:
 * shared by the evaluator of threads (sim/learn/evaluate.h) and of
 * remote simulators (sim/learn/evaluate_remote.h), which neither needs
 * the other for.
 *
 * Seeds: repetition r (0-based) of candidate i (its index in the batch)
 * in generation g runs
 *     episode number  r + 1
 *     grid seed       from evo_rng_for(seed, GRID << 32 | g, r, 0)
 *     episode seed    from evo_rng_for(seed, EPISODE << 32 | g, i, r)
 * (GRID = 3 and EPISODE = 4 are tags that keep the two streams apart and
 * apart from `evo run`'s). Every candidate of a generation thus meets the
 * same obstacle grids, while the rest of its randomness (placements,
 * RANDOM sensors) is its own; and nothing depends on which worker ran
 * which candidate, so results do not depend on the number of threads. */
#ifndef EVO_EVAL_SEEDS_H
#define EVO_EVAL_SEEDS_H

#include <stdint.h>

#include "tasksim/tasksim.h"
#include "world2d/scene.h"

typedef struct evo_eval_result evo_eval_result;

/* What an evaluation gives. */
struct evo_eval_result {
	double fitness;	 /* summed over the repetitions */
	long collisions; /* ticks the learning bot spent touching something,
			  * summed over the repetitions (0 for literature
			  * tasks) */
	int solved;	 /* literature tasks: the success criterion was met;
			  * other one-agent tasks: the environment's
			  * solved(scene, bot) held at the end of every
			  * repetition */
	/* what the episodes did (evo_sim_behaviour), each value the mean
	 * over the repetitions; n_behaviour of them, 0 for literature and
	 * team tasks */
	int n_behaviour;
	double behaviour[EVO_SIM_MAX_BEHAVIOUR];
	/* each metric's value at an episode's end, the mean over the
	 * repetitions (the settings' n_metrics of them) */
	double metric[EVO_SCENE_MAX_METRICS];
	/* team tasks: the team (group) it was scored in, the first when it
	 * is in several; that team's reward summed over the repetitions;
	 * the repetitions the learning team won (scene:winner) */
	int group;
	double team_fitness;
	int wins;
};

/* The seeds of repetition rep of candidate cand in generation gen (the
 * top of this file), for replaying one evaluation outside the pool. */
uint64_t evo_eval_grid_seed(uint64_t seed, int gen, int rep);
uint64_t evo_eval_episode_seed(uint64_t seed, int gen, int cand, int rep);

#endif
