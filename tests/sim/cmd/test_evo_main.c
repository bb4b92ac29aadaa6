/* `evo tick` (sim/cmd/evo_main.c) on the sensor values it is given: a
 * value outside [0, 1], NaN and the infinities included, is refused with a
 * message that names the sensor and a non-zero exit, before any tick runs
 * (docs/mind.md, "Sensor values"); a value in range runs. */
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

int main(void)
{
	if (cli_setup("evo-main") != 0)
		return 1;
	RUN(nan_is_refused);
	RUN(infinities_are_refused);
	RUN(out_of_range_is_refused);
	RUN(values_in_range_run);
	cli_cleanup();
	return test_summary();
}
