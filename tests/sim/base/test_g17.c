/* evo_g17 (sim/base/g17.c) writes what printf's "%.17g" writes: for
 * values worked out by hand, and for millions of doubles against glibc's
 * snprintf (every bit pattern's range, weights' range, halfway cases). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "base/g17.h"
#include "harness.h"

static int same_as_printf(double x)
{
	char want[64], got[64];
	snprintf(want, sizeof want, "%.17g", x);
	size_t n = evo_g17(x, got, sizeof got);
	if (strcmp(want, got) != 0 || n != strlen(want)) {
		printf("    %a: printf \"%s\", evo_g17 \"%s\" (%zu)\n", x, want,
		       got, n);
		return 0;
	}
	return 1;
}

static uint64_t state = 0x9E3779B97F4A7C15ull;

static uint64_t next(void)
{
	state ^= state << 13;
	state ^= state >> 7;
	state ^= state << 17;
	return state;
}

TEST(values_worked_out_by_hand)
{
	char s[64];
	/* 0.1 is 0.1000000000000000055511151231257827...: 17 digits */
	evo_g17(0.1, s, sizeof s);
	CHECK_EQ_STR(s, "0.10000000000000001");
	evo_g17(-2.5, s, sizeof s);
	CHECK_EQ_STR(s, "-2.5");
	evo_g17(1.0 / 3, s, sizeof s);
	CHECK_EQ_STR(s, "0.33333333333333331");
	evo_g17(1e16, s, sizeof s);
	CHECK_EQ_STR(s, "10000000000000000");
	/* 0.000123 is 0.000123000000000000008...: 17 digits */
	evo_g17(0.000123, s, sizeof s);
	CHECK_EQ_STR(s, "0.00012300000000000001");
	/* below 1e-4: exponent form; 1.5e-5's 18th digit is 0 */
	evo_g17(1.5e-5, s, sizeof s);
	CHECK_EQ_STR(s, "1.5e-05");
	/* 2^53, a whole number of 16 digits: no point */
	evo_g17(9007199254740992.0, s, sizeof s);
	CHECK_EQ_STR(s, "9007199254740992");
}

TEST(millions_of_doubles_as_printf_writes_them)
{
	int bad = 0;
	for (long i = 0; i < 1000000 && bad < 5; i++) {
		uint64_t bits = next();
		double x;
		memcpy(&x, &bits, sizeof x);
		if (!isfinite(x))
			continue;
		bad += !same_as_printf(x);
		/* the range the fast path takes, and weights' */
		double y = ldexp((double)(next() >> 11), -53) *
			   pow(10, (double)(next() % 25) - 7);
		bad += !same_as_printf(y);
		bad += !same_as_printf(-y);
		double w =
		    ((double)(next() >> 11) / 9007199254740992.0 - 0.5) * 20;
		bad += !same_as_printf(w);
	}
	/* halfway cases: integers and halves near 2^53, small dyadic
	 * fractions whose 18th digit is a 5 */
	for (long i = 0; i < 200000 && bad < 5; i++) {
		double h = ldexp((double)(next() >> 11), -(int)(next() % 70));
		bad += !same_as_printf(h);
		bad += !same_as_printf((double)(next() >> 10) + 0.5);
	}
	for (int k = -8; k <= 18; k++) {
		bad += !same_as_printf(pow(10, k));
		bad += !same_as_printf(nextafter(pow(10, k), 0));
		bad += !same_as_printf(nextafter(pow(10, k), INFINITY));
	}
	CHECK_EQ_INT(bad, 0);
}

int main(void)
{
	RUN(values_worked_out_by_hand);
	RUN(millions_of_doubles_as_printf_writes_them);
	return test_summary();
}
