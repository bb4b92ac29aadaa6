/* The trace reader (firmware/host/trace_file.c), which feeds a recorded
 * trace's sensor values to a firmware under QEMU (make firmware-test, make
 * bench): a trace as evo writes it loads; a sensor value that is not what
 * a tick can read (docs/mind.md, "Sensor values": Q16 in [0, 1]) is
 * refused with the trace's path, line and sensor, nan and inf included,
 * instead of reaching the robot wrapped round or as a stray number. A tick
 * number or a header count with a sign, past its range or with something
 * after it is refused at its line, and a file too large, too long a line
 * or a FIFO before it costs memory or time. */
#define _POSIX_C_SOURCE 200809L
#include <fcntl.h>
#include <stdio.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
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

/* strtoul took "-5" for tick 4294967291 and 99999999999999999999 for
 * 4294967295; a tick is digits in 0..2^32 - 1 and nothing else. */
TEST(a_tick_number_with_a_sign_past_its_range_or_with_junk_is_refused)
{
	static const char *const bad[] = {
	    "-5",	  "+5",		      "-0",
	    "4294967296", "18446744073709551617", "99999999999999999999",
	    "1e20",	  "5x",		      "0x10",
	    "5.0",
	};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		char ticks[256], err[512] = "";
		snprintf(ticks, sizeof ticks,
			 "0 0 0 | 0 | 0\n"
			 "%s 0 0 | 0 | 0\n",
			 bad[k]);
		trace_file t;
		CHECK_EQ_INT(load(ticks, &t, err, sizeof err), -1);
		CHECK_CONTAINS(err, "/t.trace:7: expected a tick number in "
				    "0..4294967295 first");
		CHECK_CONTAINS(err, bad[k]);
		if (!strstr(err, "/t.trace:7: expected a tick"))
			printf("    for %s: %s\n", bad[k], err);
		trace_free(&t);
	}
	/* the largest tick is read as it is */
	trace_file t;
	char err[512] = "";
	CHECK_EQ_INT(load("4294967295 0 0 | 0 | 0\n", &t, err, sizeof err), 0);
	CHECK(t.n_ticks == 1 && t.tick[0] == 4294967295u);
	trace_free(&t);
	/* junk at the end of a tick line */
	CHECK_EQ_INT(load("1 0 0 | 0 | 0 x\n", &t, err, sizeof err), -1);
	CHECK_CONTAINS(err, "/t.trace:6: expected 'TICK sensors");
	trace_free(&t);
}

/* The header's counts were read with sscanf's %u, which took
 * "sensors -4294967295" for 1 sensor and "evo-trace 2junk" for 2. */
TEST(a_header_count_with_a_sign_or_junk_is_refused_at_its_line)
{
	static const struct {
		const char *text, *where;
	} bad[] = {
	    {"evo-trace 2junk\n", "t.trace:1: expected 'evo-trace 1'"},
	    {"evo-trace -2\n", "t.trace:1: expected 'evo-trace 1'"},
	    {"evo-trace 2\nmind M names -1\n", "t.trace:2: expected 'mind"},
	    {"evo-trace 2\nmind M names 1a2bzz\n", "t.trace:2: expected 'mind"},
	    {"evo-trace 2\nmind M names 123456789\n",
	     "t.trace:2: expected 'mind"},
	    {"evo-trace 2\nmind M names 1a2b\nsensors -4294967295 S\n",
	     "t.trace:3: expected 'sensors N"},
	    {"evo-trace 2\nmind M names 1a2b\nsensors 2x S1 S2\n",
	     "t.trace:3: expected 'sensors N"},
	    {"evo-trace 2\nmind M names 1a2b\nsensors 2 S1 S2\n"
	     "actuators 18446744073709551617 A\n",
	     "t.trace:4: expected 'actuators M"},
	    {"evo-trace 2\nmind M names 1a2b\nsensors 2 S1 S2\n"
	     "actuators 1 A\nskills +1 M\n",
	     "t.trace:5: expected 'skills K"},
	};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		char err[512] = "";
		CHECK_EQ_INT(cli_write(bad[k].text, "%s/h.trace", cli_tmp), 0);
		char path[256];
		snprintf(path, sizeof path, "%s/h.trace", cli_tmp);
		trace_file t;
		CHECK_EQ_INT(trace_load(path, &t, err, sizeof err), -1);
		CHECK_CONTAINS(err, bad[k].where + 2);
		if (!strstr(err, bad[k].where + 2))
			printf("    for %s", bad[k].text);
		trace_free(&t);
	}
}

static long max_rss_kb(void)
{
	struct rusage ru;
	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss;
}

/* A sparse 1.5 GB trace is refused by its size; a line of 100,000 bytes
 * (which getline read whole, however long) at its line; a FIFO at once:
 * none costs memory or waits. */
TEST(a_trace_too_large_a_line_too_long_or_a_fifo_is_refused)
{
	char path[256], err[512] = "";
	snprintf(path, sizeof path, "%s/huge.trace", cli_tmp);
	int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	CHECK(fd >= 0);
	CHECK_EQ_INT(ftruncate(fd, (off_t)1500000000), 0);
	close(fd);
	long before = max_rss_kb();
	trace_file t;
	CHECK_EQ_INT(trace_load(path, &t, err, sizeof err), -1);
	CHECK_CONTAINS(err, path);
	CHECK_CONTAINS(err, "1500000000 bytes");
	CHECK_CONTAINS(err, "at most 1024 MiB");
	CHECK(max_rss_kb() - before < 4096);
	unlink(path);
	static char text[120000];
	size_t n = (size_t)snprintf(text, sizeof text, "%s0", HEAD);
	memset(text + n, '0', 100000);
	memcpy(text + n + 100000, " 0 0 | 0 | 0\n", 14);
	CHECK_EQ_INT(cli_write(text, "%s", path), 0);
	CHECK_EQ_INT(trace_load(path, &t, err, sizeof err), -1);
	CHECK_CONTAINS(err, "/huge.trace:6: a line longer than 65535 bytes");
	unlink(path);
	CHECK_EQ_INT(mkfifo(path, 0644), 0);
	/* no writer: fopen would wait for one forever */
	CHECK_EQ_INT(trace_load(path, &t, err, sizeof err), -1);
	CHECK_CONTAINS(err, "/huge.trace: not a regular file");
	unlink(path);
}

int main(void)
{
	if (cli_setup("trace"))
		return 1;
	RUN(a_trace_as_evo_writes_it_loads);
	RUN(a_sensor_value_no_tick_reads_is_refused_where_it_is);
	RUN(an_actuator_value_past_an_int32_is_refused);
	RUN(a_tick_number_with_a_sign_past_its_range_or_with_junk_is_refused);
	RUN(a_header_count_with_a_sign_or_junk_is_refused_at_its_line);
	RUN(a_trace_too_large_a_line_too_long_or_a_fifo_is_refused);
	cli_cleanup();
	return test_summary();
}
