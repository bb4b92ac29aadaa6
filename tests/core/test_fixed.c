/* Fixed-point helpers (core/include/evo/fixed.h). evo_u64_div_u32_soft
 * replaces C's 64-bit division in the firmware's tick (the weighted means;
 * a 64-bit host divides with the operator), so it must give the same
 * quotient for every input with d > 0: checked here against the C
 * operator on every edge of its two paths, exhaustively on small values,
 * and on tens of millions of random ones. evo_q16_from_sensor is the one
 * rule for sensor values from any source (docs/mind.md, "Sensor values"),
 * NaN and infinities included. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>

#include "evo/fixed.h"
#include "harness.h"
#include "support/rng.h"

static unsigned long mismatches;

static void check_div(uint64_t n, uint32_t d)
{
	uint64_t got = evo_u64_div_u32_soft(n, d), want = n / d;
	if (got != want || evo_u64_div_u32(n, d) != want) {
		if (mismatches++ < 5)
			printf("    %" PRIu64 " / %" PRIu32 ": got %" PRIu64
			       ", want %" PRIu64 "\n",
			       n, d, got, want);
	}
}

/* Divisors and dividends where a shift-and-subtract division goes wrong if
 * it goes wrong anywhere: powers of two and their neighbours, the top of
 * each word, and quotients that land on a word boundary. */
static const uint32_t edge_d[] = {
	1u, 2u, 3u, 5u, 7u, 10u, 0xFFFFu, 0x10000u, 0x10001u, 65537u * 3,
	0x7FFFFFFFu, 0x80000000u, 0x80000001u, 0xC0000000u, 0xFFFFFFFEu,
	0xFFFFFFFFu, 0x12345678u, 0xDEADBEEFu,
};

TEST(division_edges)
{
	mismatches = 0;
	for (unsigned i = 0; i < sizeof edge_d / sizeof edge_d[0]; i++) {
		uint32_t d = edge_d[i];
		uint64_t n_list[] = {
			0,
			1,
			d - 1u,
			d,
			(uint64_t)d + 1,
			0xFFFFFFFFu,
			0x100000000u,
			0x100000001u,
			/* high word just below, at and above d: the two paths */
			(uint64_t)(d - 1u) << 32,
			((uint64_t)(d - 1u) << 32) | 0xFFFFFFFFu,
			(uint64_t)d << 32,
			((uint64_t)d << 32) - 1,
			((uint64_t)d << 32) + 1,
			(uint64_t)d * 0xFFFFFFFFu,
			(uint64_t)d * 0xFFFFFFFFu - 1,
			(uint64_t)d * 0xFFFFFFFFu + d - 1,
			0x7FFFFFFFFFFFFFFFu,
			0x8000000000000000u,
			0xFFFFFFFFFFFFFFFEu,
			0xFFFFFFFFFFFFFFFFu,
		};
		for (unsigned j = 0; j < sizeof n_list / sizeof n_list[0]; j++)
			check_div(n_list[j], d);
		/* multiples of d and their neighbours over the whole range */
		for (unsigned s = 0; s < 64; s++) {
			uint64_t q = (uint64_t)1 << s;
			if (q > UINT64_MAX / d)
				break;
			uint64_t n = q * d;
			check_div(n, d);
			check_div(n - 1, d);
			if (n + d - 1 > n)
				check_div(n + d - 1, d);
		}
	}
	CHECK_EQ_INT(mismatches, 0);
}

TEST(division_small_exhaustive)
{
	mismatches = 0;
	for (uint32_t d = 1; d <= 300; d++)
		for (uint64_t n = 0; n <= 3000; n++)
			check_div(n, d);
	CHECK_EQ_INT(mismatches, 0);
}

/* Random operands of random bit lengths, so short and long quotients and
 * both paths are all common; plus the shape the tick divides: a sum of
 * influence * value products over its writers, by the summed influence. */
TEST(division_random)
{
	rng r = rng_seed(20240605);
	mismatches = 0;
	for (unsigned long i = 0; i < 5000000ul; i++) {
		uint64_t n = rng_next(&r);
		uint32_t d = (uint32_t)rng_next(&r);
		unsigned nbits = (unsigned)(rng_next(&r) % 65);
		unsigned dbits = 1 + (unsigned)(rng_next(&r) % 32);
		n = nbits == 64 ? n : n & (((uint64_t)1 << nbits) - 1);
		d = dbits == 32 ? d : d & ((1u << dbits) - 1);
		if (d == 0)
			d = 1;
		check_div(n, d);
	}
	for (unsigned long i = 0; i < 2000000ul; i++) {
		unsigned writers = 1 + (unsigned)rng_int(&r, 0, 63);
		uint64_t num = 0;
		uint32_t den = 0;
		for (unsigned w = 0; w < writers; w++) {
			uint32_t inf = (uint32_t)rng_int(&r, 0, EVO_Q16_ONE);
			uint32_t val = (uint32_t)rng_int(&r, 0, EVO_Q16_ONE);
			num += (uint64_t)inf * val;
			den += inf;
		}
		if (den)
			check_div(num + den / 2, den);
	}
	CHECK_EQ_INT(mismatches, 0);
}

/* NaN reads 0.5; below 0 reads 0 and above 1 reads 1, infinities too;
 * values in [0, 1] are rounded as evo_q16_from_double rounds them. */
TEST(sensor_values)
{
	CHECK_EQ_INT(evo_q16_from_sensor(NAN), EVO_Q16_HALF);
	CHECK_EQ_INT(evo_q16_from_sensor(-NAN), EVO_Q16_HALF);
	CHECK_EQ_INT(evo_q16_from_sensor(INFINITY), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_q16_from_sensor(-INFINITY), 0);
	CHECK_EQ_INT(evo_q16_from_sensor(-0.0), 0);
	CHECK_EQ_INT(evo_q16_from_sensor(0.0), 0);
	CHECK_EQ_INT(evo_q16_from_sensor(1e300), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_q16_from_sensor(-1e300), 0);
	CHECK_EQ_INT(evo_q16_from_sensor(1.0), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_q16_from_sensor(0.5), EVO_Q16_HALF);
	CHECK_EQ_INT(evo_q16_from_sensor(0.2), EVO_Q16_FALSE);
	CHECK_EQ_INT(evo_q16_from_sensor(0.8), EVO_Q16_TRUE);
	CHECK_EQ_INT(evo_q16_from_sensor(1e-300), 0);
}

/* The general conversion saturates infinities and gives NaN 0, where a
 * plain cast would be undefined. The NaN goes through a volatile so that
 * the compiler cannot fold the conversion at build time. */
TEST(double_conversion_edges)
{
	volatile double nan = NAN;
	CHECK_EQ_INT(evo_q16_from_double(nan), 0);
	CHECK_EQ_INT(evo_q16_from_double(INFINITY), EVO_Q16_MAX);
	CHECK_EQ_INT(evo_q16_from_double(-INFINITY), EVO_Q16_MIN);
	CHECK_EQ_INT(evo_q16_from_double(1e300), EVO_Q16_MAX);
	CHECK_EQ_INT(evo_q16_from_double(-0.0), 0);
	CHECK_EQ_INT(evo_q16_from_double(-1.5), -98304);
}

int main(void)
{
	RUN(division_edges);
	RUN(division_small_exhaustive);
	RUN(division_random);
	RUN(sensor_values);
	RUN(double_conversion_edges);
	return test_summary();
}
