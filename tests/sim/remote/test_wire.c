/* The remote protocol's messages (sim/remote/wire.c): what evo encodes
 * decodes to the same message; a message cut short anywhere, with a count
 * or a string length past evo's limits or past its bytes, with another
 * type's fingerprint, or with bad names, is refused with a reason and a
 * sentence, never decoded into garbage (the fuzz target tries the rest). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "remote/wire.h"

static unsigned char buf[EVO_WIRE_MAX_BYTES];
static char why[256];

static evo_wire_hello sample_hello(void)
{
	evo_wire_hello h;
	memset(&h, 0, sizeof h);
	h.protocol = EVO_WIRE_PROTOCOL;
	snprintf(h.name, sizeof h.name, "sim-1");
	h.session = -1234567890123LL;
	h.kind = EVO_REMOTE_SIMULATOR;
	h.environments = 3;
	h.n_sensors = 2;
	snprintf(h.sensor[0], EVO_NAME_MAX, "S1");
	snprintf(h.sensor[1], EVO_NAME_MAX, "DOF");
	h.n_actuators = 1;
	snprintf(h.actuator[0], EVO_NAME_MAX, "MotL");
	return h;
}

TEST(hello_round_trips)
{
	evo_wire_hello h = sample_hello(), d;
	int n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK(n > 8);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_OK);
	CHECK_EQ_STR(d.name, "sim-1");
	CHECK(d.session == -1234567890123LL);
	CHECK_EQ_INT(d.kind, EVO_REMOTE_SIMULATOR);
	CHECK_EQ_INT(d.environments, 3);
	CHECK_EQ_INT(d.n_sensors, 2);
	CHECK_EQ_STR(d.sensor[1], "DOF");
	CHECK_EQ_INT(d.n_actuators, 1);
	CHECK_EQ_STR(d.actuator[0], "MotL");
}

/* The layout LCM gives a sensors_t, worked out by hand: the 8-byte
 * fingerprint, then each field big-endian. */
TEST(sensors_encode_as_lcm_lays_them_out)
{
	evo_wire_sensors s, d;
	memset(&s, 0, sizeof s);
	snprintf(s.name, sizeof s.name, "ab");
	s.session = 1;
	s.env = 2;
	s.episode = 3;
	s.tick = 4;
	s.n = 1;
	s.value[0] = 0.5;
	s.reward = -2.0;
	s.done = 1;
	int n = evo_wire_encode_sensors(&s, buf, sizeof buf);
	/* 8 + (4 + 3) + 8 + 4 + 8 + 8 + 4 + 8 + 8 + 1 */
	CHECK_EQ_INT(n, 64);
	static const unsigned char name[] = {0, 0, 0, 3, 'a', 'b', 0};
	CHECK(memcmp(buf + 8, name, sizeof name) == 0);
	CHECK_EQ_INT(buf[8 + 7 + 7], 1);	   /* session, low byte */
	CHECK_EQ_INT(buf[8 + 7 + 8 + 3], 2);	   /* env */
	CHECK_EQ_INT(buf[8 + 7 + 8 + 4 + 8 + 8 + 3], 1); /* n */
	/* 0.5 is 0x3FE0000000000000 */
	CHECK_EQ_INT(buf[8 + 7 + 8 + 4 + 8 + 8 + 4], 0x3F);
	CHECK_EQ_INT(buf[8 + 7 + 8 + 4 + 8 + 8 + 4 + 1], 0xE0);
	CHECK_EQ_INT(buf[63], 1); /* done */
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_OK);
	CHECK(d.value[0] == 0.5 && d.reward == -2.0 && d.done == 1);
	CHECK(d.tick == 4 && d.episode == 3 && d.env == 2);
}

TEST(every_cut_is_refused)
{
	evo_wire_hello h = sample_hello(), d;
	int n = evo_wire_encode_hello(&h, buf, sizeof buf);
	int refused = 0;
	for (int len = 0; len < n; len++)
		refused += evo_wire_decode_hello(buf, (size_t)len, &d, why,
						 sizeof why) ==
			   EVO_WIRE_UNDECODABLE;
	CHECK_EQ_INT(refused, n);
	/* ... and so is a byte past the end */
	buf[n] = 0;
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n + 1, &d, why,
					   sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "past its end");
}

TEST(another_types_bytes_are_refused)
{
	evo_wire_command c;
	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "x");
	int n = evo_wire_encode_command(&c, buf, sizeof buf);
	evo_wire_sensors s;
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &s, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "not an evo_lcm.sensors_t");
}

/* A count the remote claims is checked before anything is allocated. */
TEST(counts_and_lengths_past_the_limits_are_refused)
{
	evo_wire_sensors s, d;
	memset(&s, 0, sizeof s);
	snprintf(s.name, sizeof s.name, "ab");
	s.n = 1;
	int n = evo_wire_encode_sensors(&s, buf, sizeof buf);
	unsigned char *count = buf + 8 + 7 + 8 + 4 + 8 + 8;
	count[0] = 0x7f; /* 2^31 - 255 values */
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "sensors_t.n is");
	count[0] = 0xff; /* negative */
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	count[0] = 0;
	count[3] = 2; /* two values, one there */
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "sensors_t: cut short at");
	count[3] = 1;
	/* the name's length: huge, then without its NUL */
	buf[8] = 0x40;
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "sensors_t.name: a string of");
	buf[8] = 0;
	buf[8 + 4 + 2] = 'c';
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "not ended by its one NUL");
}

TEST(bad_hellos_are_refused)
{
	evo_wire_hello h = sample_hello(), d;
	snprintf(h.name, sizeof h.name, "a b");
	CHECK_EQ_INT(evo_wire_encode_hello(&h, buf, sizeof buf), -1);
	/* a robot with several environments, made by hand */
	h = sample_hello();
	h.kind = EVO_REMOTE_ROBOT;
	int n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "environments must be 1 for a robot");
	h = sample_hello();
	h.kind = (evo_remote_kind)7;
	n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "kind is neither");
}

TEST(values_outside_the_unit_interval_are_named)
{
	double v[3] = {0, 1, 0.25};
	double r = 5;
	CHECK_EQ_INT(evo_wire_check_values(v, 3, &r, why, sizeof why),
		     EVO_WIRE_OK);
	v[2] = NAN;
	CHECK_EQ_INT(evo_wire_check_values(v, 3, &r, why, sizeof why),
		     EVO_WIRE_VALUE);
	CHECK_CONTAINS(why, "value 2 is nan");
	v[2] = 1.0000001;
	CHECK_EQ_INT(evo_wire_check_values(v, 3, &r, why, sizeof why),
		     EVO_WIRE_VALUE);
	v[2] = 0;
	r = INFINITY;
	CHECK_EQ_INT(evo_wire_check_values(v, 3, &r, why, sizeof why),
		     EVO_WIRE_VALUE);
	CHECK_CONTAINS(why, "the reward is inf");
}

TEST(controls_round_trip_with_full_seeds)
{
	evo_wire_control c, d;
	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "sim");
	c.op = EVO_CONTROL_RESET;
	c.episode = 7;
	c.layout_seed = 0xFEDCBA9876543210ull;
	c.seed = 1;
	int n = evo_wire_encode_control(&c, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_control(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_OK);
	CHECK(d.layout_seed == 0xFEDCBA9876543210ull && d.seed == 1);
	CHECK_EQ_INT(d.op, EVO_CONTROL_RESET);
	buf[n - 8 - 8 - 8 - 1] = 9; /* op */
	CHECK_EQ_INT(evo_wire_decode_control(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
}

int main(void)
{
	RUN(hello_round_trips);
	RUN(sensors_encode_as_lcm_lays_them_out);
	RUN(every_cut_is_refused);
	RUN(another_types_bytes_are_refused);
	RUN(counts_and_lengths_past_the_limits_are_refused);
	RUN(bad_hellos_are_refused);
	RUN(values_outside_the_unit_interval_are_named);
	RUN(controls_round_trip_with_full_seeds);
	return test_summary();
}
