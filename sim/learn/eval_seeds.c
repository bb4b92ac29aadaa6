/* The seeds of an evaluation (sim/learn/eval_seeds.h). */
#include "learn/eval_seeds.h"

#include "base/rng.h"

/* Stream tags of evo_rng_for (eval_seeds.h); `evo run` uses 1 and 2. */
enum { TAG_GRID = 3, TAG_EPISODE = 4 };

uint64_t evo_eval_grid_seed(uint64_t seed, int gen, int rep)
{
	evo_rng r = evo_rng_for(seed, (uint64_t)TAG_GRID << 32 | (uint32_t)gen,
				(uint64_t)rep, 0);
	return evo_rng_next(&r);
}

uint64_t evo_eval_episode_seed(uint64_t seed, int gen, int cand, int rep)
{
	evo_rng r =
	    evo_rng_for(seed, (uint64_t)TAG_EPISODE << 32 | (uint32_t)gen,
			(uint64_t)cand, (uint64_t)rep);
	return evo_rng_next(&r);
}
