/* `evo tick` (sim/cmd/evo_main.c) on the sensor values it is given: a
 * value outside [0, 1], NaN and the infinities included, is refused with a
 * message that names the sensor and a non-zero exit, before any tick runs
 * (docs/mind.md, "Sensor values"); a value in range runs. A tick count
 * with a sign, past its range (99999999999999999999 was LONG_MAX ticks)
 * or with something after it is refused. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"

static char out[1 << 14];

static void refused(const char *value)
{
	char want[128];
	int rc = cli_capture(out, sizeof out,
			     "%s tick minds/Avoid --ticks 2 --sensor S2=%s",
			     cli_evo, value);
	CHECK_EQ_INT(rc, 2);
	snprintf(want, sizeof want,
		 "evo: --sensor S2=%s: the value of sensor 'S2' must be a "
		 "number in [0, 1]",
		 value);
	CHECK_CONTAINS(out, want);
	CHECK(strstr(out, "tick ") == NULL); /* no tick ran */
}

TEST(nan_is_refused)
{
	refused("nan");
	refused("NAN");
	refused("-nan");
}

TEST(infinities_are_refused)
{
	refused("inf");
	refused("-inf");
	refused("infinity");
}

TEST(out_of_range_is_refused)
{
	refused("1.5");
	refused("-0.1");
	refused("1e300");
}

TEST(values_in_range_run)
{
	int rc = cli_capture(out, sizeof out,
			     "%s tick minds/Avoid --ticks 2 --sensor S2=0 "
			     "--sensor S3=1 --sensor S4=-0.0 --sensor S5=0.5",
			     cli_evo);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "tick ");
	CHECK_CONTAINS(out, "   1 ");
}

TEST(a_tick_count_with_a_sign_overflow_or_junk_is_refused)
{
	static const char *const bad[] = {"-5", "99999999999999999999",
					  "1e20", "5x", "+5", "1000000001"};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		char want[128];
		int rc = cli_capture(out, sizeof out,
				     "%s tick minds/Avoid --ticks %s", cli_evo,
				     bad[k]);
		CHECK_EQ_INT(rc, 2);
		snprintf(want, sizeof want,
			 "evo: --ticks expects a whole number 0..1000000000, "
			 "found '%s'",
			 bad[k]);
		CHECK_CONTAINS(out, want);
		CHECK(strstr(out, "tick ") == NULL);
	}
}

int main(void)
{
	if (cli_setup("evo-main") != 0)
		return 1;
	RUN(nan_is_refused);
	RUN(infinities_are_refused);
	RUN(out_of_range_is_refused);
	RUN(values_in_range_run);
	RUN(a_tick_count_with_a_sign_overflow_or_junk_is_refused);
	cli_cleanup();
	return test_summary();
}
