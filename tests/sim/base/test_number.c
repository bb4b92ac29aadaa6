/* Whole numbers as a user writes them (sim/base/number.c): digits, a '-'
 * only where the range has negatives; a sign where none belongs, a value
 * past the range (2^64 and more included), or anything after the digits
 * is refused, not wrapped round, saturated or cut off. */
#include <limits.h>
#include <stdio.h>

#include "base/number.h"
#include "harness.h"

/* The status of s read as a whole number in [lo, hi]; the value in *v. */
static int whole(const char *s, long long lo, long long hi, long long *v)
{
	*v = 12345;
	return evo_parse_whole(s, NULL, lo, hi, v);
}

TEST(whole_numbers_in_range_are_read)
{
	long long v;
	CHECK_EQ_INT(whole("0", 0, 10, &v), 0);
	CHECK_EQ_INT(v, 0);
	CHECK_EQ_INT(whole("4294967295", 0, 4294967295LL, &v), 0);
	CHECK_EQ_INT(v, 4294967295LL);
	CHECK_EQ_INT(whole("-5", -10, 10, &v), 0);
	CHECK_EQ_INT(v, -5);
	CHECK_EQ_INT(whole("007", 0, 10, &v), 0);
	CHECK_EQ_INT(v, 7);
	/* the ends of a long long */
	CHECK_EQ_INT(whole("9223372036854775807", LLONG_MIN, LLONG_MAX, &v), 0);
	CHECK_EQ_INT(v, LLONG_MAX);
	CHECK_EQ_INT(whole("-9223372036854775808", LLONG_MIN, LLONG_MAX, &v),
		     0);
	CHECK_EQ_INT(v, LLONG_MIN);
}

TEST(a_sign_overflow_or_junk_is_refused)
{
	static const char *const bad[] = {
	    "-5",	  /* strtoul: 4294967291 */
	    "+5",	  "",	       "-",	     " 5",	"5 ",
	    "5x",	  "1e20",     "0x10",	     "1.0",	"--5",
	    "4294967296", /* 2^32 */
	    "18446744073709551616",	 /* 2^64: strtoul wraps or saturates */
	    "99999999999999999999",	 /* strtoul: 4294967295 */
	    "9223372036854775808",	 /* LLONG_MAX + 1 */
	    "100000000000000000000000000000000000000",
	};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		long long v;
		int rc = whole(bad[k], 0, 4294967295LL, &v);
		if (rc != -1 || v != 12345)
			printf("  accepted '%s'\n", bad[k]);
		CHECK_EQ_INT(rc, -1);
		CHECK_EQ_INT(v, 12345);
	}
	long long v;
	CHECK_EQ_INT(whole("11", 0, 10, &v), -1);
	CHECK_EQ_INT(whole("-11", -10, 10, &v), -1);
	CHECK_EQ_INT(whole("-9223372036854775809", LLONG_MIN, LLONG_MAX, &v),
		     -1);
	CHECK_EQ_INT(whole("9223372036854775808", LLONG_MIN, LLONG_MAX, &v),
		     -1);
}

TEST(with_end_the_caller_sees_what_follows)
{
	long long v;
	const char *end = NULL;
	const char *s = "42 | 7";
	CHECK_EQ_INT(evo_parse_whole(s, &end, 0, 100, &v), 0);
	CHECK_EQ_INT(v, 42);
	CHECK(end == s + 2);
	CHECK_EQ_INT(evo_parse_whole("x", &end, 0, 100, &v), -1);
	CHECK_EQ_INT(evo_parse_whole("101,", &end, 0, 100, &v), -1);
}

int main(void)
{
	RUN(whole_numbers_in_range_are_read);
	RUN(a_sign_overflow_or_junk_is_refused);
	RUN(with_end_the_caller_sees_what_follows);
	return test_summary();
}
