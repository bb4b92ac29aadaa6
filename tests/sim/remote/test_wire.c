/* The remote protocol's messages (sim/remote/wire.c): what evo encodes
 * decodes to the same message; a message cut short anywhere, with a count
 * or a string length past evo's limits or past its bytes, with another
 * type's fingerprint, or with bad names, is refused with a reason and a
 * sentence, never decoded into garbage (the fuzz target tries the rest). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "evo/mac.h"
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
	s.n_behaviour = 1;
	s.behaviour[0] = 0.75;
	int n = evo_wire_encode_sensors(&s, buf, sizeof buf);
	/* 8 + (4 + 3) + 8 + 4 + 8 + 8 + 4 + 8 + 8 + 1, then the behaviour:
	 * 4 + 8 */
	CHECK_EQ_INT(n, 76);
	static const unsigned char name[] = {0, 0, 0, 3, 'a', 'b', 0};
	CHECK(memcmp(buf + 8, name, sizeof name) == 0);
	CHECK_EQ_INT(buf[8 + 7 + 7], 1);	   /* session, low byte */
	CHECK_EQ_INT(buf[8 + 7 + 8 + 3], 2);	   /* env */
	CHECK_EQ_INT(buf[8 + 7 + 8 + 4 + 8 + 8 + 3], 1); /* n */
	/* 0.5 is 0x3FE0000000000000 */
	CHECK_EQ_INT(buf[8 + 7 + 8 + 4 + 8 + 8 + 4], 0x3F);
	CHECK_EQ_INT(buf[8 + 7 + 8 + 4 + 8 + 8 + 4 + 1], 0xE0);
	CHECK_EQ_INT(buf[63], 1); /* done */
	CHECK_EQ_INT(buf[67], 1); /* n_behaviour */
	/* 0.75 is 0x3FE8000000000000 */
	CHECK_EQ_INT(buf[68], 0x3F);
	CHECK_EQ_INT(buf[69], 0xE8);
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_OK);
	CHECK(d.value[0] == 0.5 && d.reward == -2.0 && d.done == 1);
	CHECK(d.n_behaviour == 1 && d.behaviour[0] == 0.75);
	/* 17 values: past evo's 16, refused naming the field */
	buf[67] = 17;
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "sensors_t.n_behaviour is 17, outside 0..16");
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
	evo_wire_sensors s;
	memset(&s, 0, sizeof s);
	s.n_behaviour = 2;
	s.behaviour[0] = 1;
	CHECK_EQ_INT(evo_wire_check_behaviour(&s, why, sizeof why),
		     EVO_WIRE_OK);
	s.behaviour[1] = -0.5;
	CHECK_EQ_INT(evo_wire_check_behaviour(&s, why, sizeof why),
		     EVO_WIRE_VALUE);
	CHECK_CONTAINS(why, "behaviour value 1 is -0.5, outside [0, 1]");
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

/* Item 8: every count and index a remote sends is checked against evo's
 * limits in the decoder, and a refused hello names the remote and the
 * field. evo keeps 64 environments per remote (EVO_REMOTE_MAX_ENVS). */
TEST(counts_and_indexes_past_evos_limits_are_refused_naming_the_field)
{
	evo_wire_hello h = sample_hello(), d;
	h.environments = 100;
	int n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_EQ_STR(why, "hello_t from sim-1: environments is 100, outside "
			  "1..64");
	CHECK_EQ_STR(d.name, "sim-1");
	h.environments = 64;
	n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_OK);
	h.environments = -3;
	n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "environments is -3");
	h = sample_hello();
	h.tick_us = 60000001; /* a tick over a minute */
	n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "hello_t from sim-1: tick_us is 60000001");

	evo_wire_sensors s, sd;
	memset(&s, 0, sizeof s);
	snprintf(s.name, sizeof s.name, "sim-1");
	s.env = 64;
	n = evo_wire_encode_sensors(&s, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &sd, why,
					     sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_EQ_STR(why, "sensors_t for sim-1: env is 64, outside 0..63");
	s.env = 0;
	s.tick = -1;
	n = evo_wire_encode_sensors(&s, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &sd, why,
					     sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "tick is -1");
	s.tick = 0;
	s.episode = -5;
	n = evo_wire_encode_sensors(&s, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_sensors(buf, (size_t)n, &sd, why,
					     sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "episode is -5");

	evo_wire_command c, cd;
	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "sim-1");
	c.env = -1;
	n = evo_wire_encode_command(&c, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_command(buf, (size_t)n, &cd, why,
					     sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "command_t for sim-1: env is -1");
	evo_wire_control k, kd;
	memset(&k, 0, sizeof k);
	snprintf(k.name, sizeof k.name, "sim-1");
	k.op = EVO_CONTROL_RESET;
	k.env = 100;
	n = evo_wire_encode_control(&k, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_control(buf, (size_t)n, &kd, why,
					     sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "control_t for sim-1: env is 100");
}

/* Item 9: a hello's url names a multicast group and nothing else. */
TEST(a_hellos_url_is_only_ever_a_multicast_group)
{
	int ttl = -1;
	CHECK(evo_wire_url_ok("", &ttl, why, sizeof why) && ttl == 0);
	CHECK(evo_wire_url_ok("udpm://239.255.76.67:7667", &ttl, why,
			      sizeof why));
	CHECK(evo_wire_url_ok("udpm://239.255.76.67:7667?ttl=1", &ttl, why,
			      sizeof why) &&
	      ttl == 1);
	CHECK(evo_wire_url_ok("udpm://224.0.0.1:1?ttl=0&recv_buf_size=65536",
			      &ttl, why, sizeof why));
	static const char *const refused[] = {
	    "file:///tmp/x?mode=w",
	    "tcpq://127.0.0.1:7700",
	    "memq://",
	    "udpm://10.0.0.1:7667",	      /* not multicast */
	    "udpm://240.0.0.1:7667",	      /* not multicast */
	    "udpm://239.255.76.67:0",	      /* no port */
	    "udpm://239.255.76.67:70000",
	    "udpm://239.255.76.67:7667?ttl=2", /* past the link */
	    "udpm://239.255.76.67:7667?ttl=0&ttl=0",
	    "udpm://239.255.76.67:7667?mode=w",
	    "udpm://239.255.76.67:7667/x",
	    "udpm://239.255.76:7667",
	    "udpm://239.255.76.67.1:7667",
	};
	for (size_t i = 0; i < sizeof refused / sizeof *refused; i++) {
		why[0] = 0;
		CHECK(!evo_wire_url_ok(refused[i], &ttl, why, sizeof why));
		CHECK(why[0] != 0);
	}
	CHECK(!evo_wire_url_ok("file:///tmp/x?mode=w", &ttl, why, sizeof why));
	CHECK_CONTAINS(why, "is not udpm://GROUP:PORT");
	/* in a hello: refused by the decoder, naming the remote */
	evo_wire_hello h = sample_hello(), d;
	snprintf(h.url, sizeof h.url, "file:///tmp/x?mode=w");
	int n = evo_wire_encode_hello(&h, buf, sizeof buf);
	CHECK_EQ_INT(evo_wire_decode_hello(buf, (size_t)n, &d, why, sizeof why),
		     EVO_WIRE_UNDECODABLE);
	CHECK_CONTAINS(why, "hello_t from sim-1: url: 'file:///tmp/x?mode=w'");
}

static const evo_wire_key key16 = {16, "0123456789abcdef"};

/* Item 10: the seal is HMAC-SHA-256 over the channel, a NUL, the bytes and
 * the stamp, worked out here from the parts; any change to the bytes, the
 * channel or the key is forged, an old stamp or one taken before is
 * replayed. */
TEST(a_seal_holds_only_for_its_key_channel_bytes_and_time)
{
	evo_wire_sensors s;
	memset(&s, 0, sizeof s);
	snprintf(s.name, sizeof s.name, "sim-1");
	s.tick = 3;
	int n = evo_wire_encode_sensors(&s, buf, sizeof buf);
	int64_t now = 1700000000000000LL;
	int m = evo_wire_seal(&key16, "EVO_sim-1_SENSORS", buf, (size_t)n,
			      sizeof buf, now);
	CHECK_EQ_INT(m, n + 40);
	/* the tag, from its parts */
	unsigned char msg[4096];
	size_t k = 0;
	memcpy(msg, "EVO_sim-1_SENSORS", 18); /* with its NUL */
	k = 18;
	memcpy(msg + k, buf, (size_t)n + 8);
	k += (size_t)n + 8;
	uint8_t want[32];
	evo_hmac_sha256("0123456789abcdef", 16, msg, k, want);
	CHECK(memcmp(buf + n + 8, want, 32) == 0);
	CHECK(buf[n] == 0x00 && buf[n + 1] == 0x06 && buf[n + 7] == 0x00);
	size_t body = 0;
	int64_t stamp = 0;
	CHECK_EQ_INT(evo_wire_unseal(&key16, "EVO_sim-1_SENSORS", buf,
				     (size_t)m, now + 1000, &body, &stamp, why,
				     sizeof why),
		     EVO_WIRE_OK);
	CHECK(body == (size_t)n && stamp == now);
	/* another channel, another key, a byte changed, no seal */
	CHECK_EQ_INT(evo_wire_unseal(&key16, "EVO_sim-2_SENSORS", buf,
				     (size_t)m, now, &body, &stamp, why,
				     sizeof why),
		     EVO_WIRE_FORGED);
	evo_wire_key other = key16;
	other.bytes[0] ^= 1;
	CHECK_EQ_INT(evo_wire_unseal(&other, "EVO_sim-1_SENSORS", buf,
				     (size_t)m, now, &body, &stamp, why,
				     sizeof why),
		     EVO_WIRE_FORGED);
	buf[n - 12] ^= 0x40; /* in the count n */
	CHECK_EQ_INT(evo_wire_unseal(&key16, "EVO_sim-1_SENSORS", buf,
				     (size_t)m, now, &body, &stamp, why,
				     sizeof why),
		     EVO_WIRE_FORGED);
	CHECK_CONTAINS(why, "MAC fails the key");
	buf[n - 12] ^= 0x40;
	CHECK_EQ_INT(evo_wire_unseal(&key16, "EVO_sim-1_SENSORS", buf,
				     (size_t)n, now, &body, &stamp, why,
				     sizeof why),
		     EVO_WIRE_FORGED);
	CHECK_EQ_INT(evo_wire_unseal(&key16, "EVO_sim-1_SENSORS", buf, 20, now,
				     &body, &stamp, why, sizeof why),
		     EVO_WIRE_FORGED);
	/* 31 s later: a recording played back */
	CHECK_EQ_INT(evo_wire_unseal(&key16, "EVO_sim-1_SENSORS", buf,
				     (size_t)m, now + 31000000, &body, &stamp,
				     why, sizeof why),
		     EVO_WIRE_REPLAYED);
	CHECK_CONTAINS(why, "stamped 31 s behind");
	/* a stamp taken once only, and in order */
	evo_wire_fresh f = {0};
	CHECK_EQ_INT(evo_wire_fresh_take(&f, now, why, sizeof why), EVO_WIRE_OK);
	CHECK_EQ_INT(evo_wire_fresh_take(&f, now, why, sizeof why),
		     EVO_WIRE_REPLAYED);
	CHECK_EQ_INT(evo_wire_fresh_take(&f, now - 1, why, sizeof why),
		     EVO_WIRE_REPLAYED);
	CHECK_EQ_INT(evo_wire_fresh_take(&f, now + 1, why, sizeof why),
		     EVO_WIRE_OK);
	/* stamps of one sender only go up, even within one microsecond */
	int64_t last = INT64_MAX - 10, a = evo_wire_stamp(&last),
		b = evo_wire_stamp(&last);
	CHECK(a == INT64_MAX - 9 && b == INT64_MAX - 8);
	CHECK_EQ_INT(evo_wire_seal(&key16, "X", buf, 10, 49, now), -1);
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
	RUN(counts_and_indexes_past_evos_limits_are_refused_naming_the_field);
	RUN(a_hellos_url_is_only_ever_a_multicast_group);
	RUN(a_seal_holds_only_for_its_key_channel_bytes_and_time);
	return test_summary();
}
