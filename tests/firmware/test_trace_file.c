/* The trace reader (firmware/host/trace_file.c), which feeds a recorded
 * trace's sensor values to a firmware under QEMU (make firmware-test, make
 * bench): a trace as evo writes it loads; a sensor value that is not what
 * a tick can read (docs/mind.md, "Sensor values": Q16 in [0, 1]) is
 * refused with the trace's path, line and sensor, nan and inf included,
 * instead of reaching the robot wrapped round or as a stray number. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "host/trace_file.h"
#include "support/cli.h"

static const char HEAD[] = "evo-trace 2\n"
			   "mind M names 1a2b\n"
			   "sensors 2 S1 S2\n"
			   "actuators 1 A\n"
			   "skills 1 M\n";

/* Load HEAD followed by ticks; the status, the message in err. */
static int load(const char *ticks, trace_file *t, char *err, size_t cap)
{
	char text[1024];
	snprintf(text, sizeof text, "%s%s", HEAD, ticks);
	if (cli_write(text, "%s/t.trace", cli_tmp))
		return -2;
	char path[256];
	snprintf(path, sizeof path, "%s/t.trace", cli_tmp);
	return trace_load(path, t, err, cap);
}

TEST(a_trace_as_evo_writes_it_loads)
{
	trace_file t;
	char err[512] = "";
	CHECK_EQ_INT(load("0 0 65536 | 32768 | 65536\n"
			  "1 19661 45875 | -5 | 0\n",
			  &t, err, sizeof err),
		     0);
	CHECK_EQ_STR(err, "");
	CHECK_EQ_INT(t.n_ticks, 2);
	CHECK_EQ_INT(t.sensor[1], 65536);
	CHECK_EQ_INT(t.sensor[2], 19661);
	CHECK_EQ_INT(t.actuator[1], -5);
	trace_free(&t);
}

TEST(a_sensor_value_no_tick_reads_is_refused_where_it_is)
{
	static const char *const bad[] = {
	    "nan",	   "-nan",	 "inf",	      "-inf", "1e9",
	    "65537",	   "-1",	 "4294967296", "99999999999999999999",
	};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		char ticks[256], err[512] = "";
		snprintf(ticks, sizeof ticks,
			 "0 0 0 | 0 | 0\n"
			 "1 0 %s | 0 | 0\n",
			 bad[k]);
		trace_file t;
		CHECK_EQ_INT(load(ticks, &t, err, sizeof err), -1);
		CHECK_CONTAINS(err, "/t.trace:7: sensor 2: expected a Q16 "
				    "value in 0..65536 ([0, 1])");
		if (!strstr(err, "/t.trace:7: sensor 2"))
			printf("    for %s: %s\n", bad[k], err);
		trace_free(&t);
	}
}

TEST(an_actuator_value_past_an_int32_is_refused)
{
	trace_file t;
	char err[512] = "";
	CHECK_EQ_INT(load("0 0 0 | 2147483648 | 0\n", &t, err, sizeof err),
		     -1);
	CHECK_CONTAINS(err, "/t.trace:6: expected 'TICK sensors... | "
			    "actuators...");
	trace_free(&t);
}

int main(void)
{
	if (cli_setup("trace"))
		return 1;
	RUN(a_trace_as_evo_writes_it_loads);
	RUN(a_sensor_value_no_tick_reads_is_refused_where_it_is);
	RUN(an_actuator_value_past_an_int32_is_refused);
	cli_cleanup();
	return test_summary();
}
