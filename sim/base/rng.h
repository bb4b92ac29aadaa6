/* evo — seedable random streams for the host side: the 2D world's
 * episodes (RANDOM sensors, placements, the obstacle grid) and the
 * learning evaluator's seeds. Pure functions of their seed, so a run is
 * repeatable and does not depend on threads. */
#ifndef EVO_RNG_H
#define EVO_RNG_H

#include <stdint.h>

/* splitmix64: small, seedable, one per scene (never shared between
 * threads). */
typedef struct evo_rng {
	uint64_t s;
} evo_rng;

/* The per-draw functions are inline: the obstacle grid and the RANDOM
 * sensors draw in their inner loops, and a call per draw costs more than
 * the draw. */
static inline evo_rng evo_rng_seed(uint64_t seed)
{
	evo_rng r = {seed};
	return r;
}

static inline uint64_t evo_rng_next(evo_rng *r)
{
	uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	return z ^ (z >> 31);
}

/* Uniform in [0, 1): the top 53 bits. */
static inline double evo_rng_unit(evo_rng *r)
{
	return (double)(evo_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* Uniform in [lo, hi). */
static inline double evo_rng_range(evo_rng *r, double lo, double hi)
{
	return lo + (hi - lo) * evo_rng_unit(r);
}

/* A stream for (seed, a, b, c): evaluations are seeded from (run seed,
 * generation, candidate, repetition). */
evo_rng evo_rng_for(uint64_t seed, uint64_t a, uint64_t b, uint64_t c);

#endif
