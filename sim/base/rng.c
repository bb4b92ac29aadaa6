/* splitmix64 streams (sim/base/rng.h). */
#include "base/rng.h"

/* Each coordinate goes through a full mix, so nearby tuples such as
 * (seed, 3, 1, 0) and (seed, 3, 0, 1) give unrelated streams. */
evo_rng evo_rng_for(uint64_t seed, uint64_t a, uint64_t b, uint64_t c)
{
	evo_rng r = evo_rng_seed(seed);
	uint64_t parts[3] = {a, b, c};
	for (int i = 0; i < 3; i++) {
		r.s ^= parts[i] + 0x632BE59BD9B4E019ull;
		r.s = evo_rng_next(&r);
	}
	return r;
}
