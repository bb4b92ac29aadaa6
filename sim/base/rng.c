/* splitmix64 streams (base/rng.h). */
#include "base/rng.h"

evo_rng evo_rng_seed(uint64_t seed)
{
	evo_rng r = {seed};
	return r;
}

uint64_t evo_rng_next(evo_rng *r)
{
	uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	return z ^ (z >> 31);
}

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

double evo_rng_unit(evo_rng *r)
{
	return (double)(evo_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

double evo_rng_range(evo_rng *r, double lo, double hi)
{
	return lo + (hi - lo) * evo_rng_unit(r);
}
