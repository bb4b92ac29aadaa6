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

evo_rng evo_rng_seed(uint64_t seed);
/* A stream for (seed, a, b, c): evaluations are seeded from (run seed,
 * generation, candidate, repetition). */
evo_rng evo_rng_for(uint64_t seed, uint64_t a, uint64_t b, uint64_t c);
uint64_t evo_rng_next(evo_rng *r);
/* Uniform in [0, 1). */
double evo_rng_unit(evo_rng *r);
/* Uniform in [lo, hi). */
double evo_rng_range(evo_rng *r, double lo, double hi);

#endif
