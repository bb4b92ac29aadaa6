/* A tiny deterministic PRNG for tests (splitmix64): the same seed gives
 * the same sequence on every platform and at every optimisation level.
 * Header-only so that standalone programs (net_dump_main.c) can use it. */
#ifndef EVO_TEST_RNG_H
#define EVO_TEST_RNG_H

#include <stdint.h>

typedef struct rng {
	uint64_t state;
} rng;

static inline rng rng_seed(uint64_t seed)
{
	rng r = {seed};
	return r;
}

static inline uint64_t rng_next(rng *r)
{
	uint64_t z = (r->state += 0x9E3779B97F4A7C15u);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
	return z ^ (z >> 31);
}

/* Uniform integer in [lo, hi] (hi >= lo); the modulo bias is below
 * 2^-32 for the small ranges tests use. */
static inline int64_t rng_int(rng *r, int64_t lo, int64_t hi)
{
	return lo + (int64_t)(rng_next(r) % (uint64_t)(hi - lo + 1));
}

/* Uniform double in [0, 1), 53 random bits. */
static inline double rng_unit(rng *r)
{
	return (double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* Uniform double in [lo, hi). */
static inline double rng_uniform(rng *r, double lo, double hi)
{
	return lo + (hi - lo) * rng_unit(r);
}

#endif
