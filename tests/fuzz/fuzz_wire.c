/* libFuzzer target for the remote protocol's decoding
 * (sim/remote/wire.c): the first byte picks the message type, the rest
 * are the bytes a remote sent. Besides crashes, leaks and sanitizer
 * reports it checks the decoder's promises: a refusal comes with a
 * sentence, and a message taken stays within evo's limits and encodes
 * back to the very bytes it came from. It also fuzzes the seal of a
 * shared key (evo_wire_unseal, evo_wire_fresh_take): bytes as they came
 * (never taken: no one here knows the key), and bytes sealed here with
 * the stamp the input gives (taken within the freshness window, with
 * their own body and stamp, once only), and the URLs a hello may name.
 * Seeds: tests/data/wire/. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "remote/wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Large: static, not on the stack. */
static union {
	evo_wire_hello hello;
	evo_wire_who who;
	evo_wire_control control;
	evo_wire_sensors sensors;
	evo_wire_command command;
} m;
static unsigned char again[EVO_WIRE_MAX_BYTES];

static const evo_wire_key key = {20, "fuzzing-the-seal-key"};
#define NOW 1700000000000000LL
static unsigned char sealed[EVO_WIRE_MAX_BYTES + EVO_WIRE_SEAL_BYTES];

/* 0: the seal's promises held; the decoders then get the body. */
static int seal_case(int own, const uint8_t *b, size_t n)
{
	char why[256];
	size_t body = 0;
	int64_t stamp = 0;
	evo_wire_reason r;
	if (!own) {
		/* as they came: forged, or too far from now, never taken */
		r = evo_wire_unseal(&key, "EVO_f_SENSORS", b, n, NOW, &body,
				    &stamp, why, sizeof why);
		if (r != EVO_WIRE_FORGED && r != EVO_WIRE_REPLAYED &&
		    r != EVO_WIRE_OK)
			abort();
		if (r != EVO_WIRE_OK && why[0] == 0)
			abort();
		return 0;
	}
	/* sealed here: the first 8 bytes are the stamp, the rest the body */
	/* a body of 8 bytes at least: an LCM fingerprint */
	if (n < 16 || n - 8 > EVO_WIRE_MAX_BYTES)
		return 0;
	int64_t t = 0;
	for (int i = 0; i < 8; i++)
		t = (int64_t)((uint64_t)t << 8 | b[i]);
	memcpy(sealed, b + 8, n - 8);
	int len = evo_wire_seal(&key, "EVO_f_SENSORS", sealed, n - 8,
				sizeof sealed, t);
	if (len != (int)(n - 8 + EVO_WIRE_SEAL_BYTES))
		abort();
	r = evo_wire_unseal(&key, "EVO_f_SENSORS", sealed, (size_t)len, NOW,
			    &body, &stamp, why, sizeof why);
	uint64_t d = t > NOW ? (uint64_t)t - (uint64_t)NOW
			     : (uint64_t)NOW - (uint64_t)t;
	if ((r == EVO_WIRE_OK) != (d <= (uint64_t)EVO_WIRE_FRESH_US))
		abort();
	if (r != EVO_WIRE_OK) {
		if (r != EVO_WIRE_REPLAYED)
			abort();
		return 0;
	}
	if (body != n - 8 || stamp != t)
		abort();
	/* one byte changed anywhere: forged */
	sealed[(size_t)t % (size_t)len] ^= 1;
	if (evo_wire_unseal(&key, "EVO_f_SENSORS", sealed, (size_t)len, NOW,
			    &body, &stamp, why, sizeof why) != EVO_WIRE_FORGED)
		abort();
	sealed[(size_t)t % (size_t)len] ^= 1;
	evo_wire_fresh f = {0};
	if (evo_wire_fresh_take(&f, t, why, sizeof why) != EVO_WIRE_OK ||
	    (t != 0 &&
	     evo_wire_fresh_take(&f, t, why, sizeof why) != EVO_WIRE_REPLAYED))
		abort();
	evo_wire_sensors s;
	evo_wire_decode_sensors(sealed, body, &s, why, sizeof why);
	return 0;
}

static void url_case(const uint8_t *b, size_t n)
{
	char url[EVO_REMOTE_URL_MAX], why[256];
	size_t k = n < sizeof url - 1 ? n : sizeof url - 1;
	memcpy(url, b, k);
	url[k] = 0;
	int ttl = -1;
	why[0] = 0;
	int ok = evo_wire_url_ok(url, &ttl, why, sizeof why);
	if (ok ? (ttl < 0 || ttl > 1 ||
		  (url[0] && strncmp(url, "udpm://", 7) != 0))
	       : why[0] == 0)
		abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	if (data[0] % 8 >= 5) {
		if (data[0] % 8 == 7)
			url_case(data + 1, size - 1);
		else
			seal_case(data[0] % 8 == 6, data + 1, size - 1);
		return 0;
	}
	const uint8_t *b = data + 1;
	size_t n = size - 1;
	char why[256];
	memset(why, 'x', sizeof why);
	evo_wire_reason r;
	int len = -1;
	switch (data[0] % 8) {
	case 0:
		r = evo_wire_decode_hello(b, n, &m.hello, why, sizeof why);
		if (r == EVO_WIRE_OK) {
			if (m.hello.n_sensors > EVO_MAX_SENSORS ||
			    m.hello.n_actuators > EVO_MAX_ACTUATORS ||
			    !evo_wire_name_ok(m.hello.name))
				abort();
			len = evo_wire_encode_hello(&m.hello, again,
						    sizeof again);
		}
		break;
	case 1:
		r = evo_wire_decode_who(b, n, &m.who, why, sizeof why);
		if (r == EVO_WIRE_OK)
			len = evo_wire_encode_who(&m.who, again, sizeof again);
		break;
	case 2:
		r = evo_wire_decode_control(b, n, &m.control, why, sizeof why);
		if (r == EVO_WIRE_OK)
			len = evo_wire_encode_control(&m.control, again,
						      sizeof again);
		break;
	case 3:
		r = evo_wire_decode_sensors(b, n, &m.sensors, why, sizeof why);
		if (r == EVO_WIRE_OK) {
			if (m.sensors.n > EVO_MAX_SENSORS)
				abort();
			/* done is a boolean: any byte but 0 reads as 1, so
			 * only a 0 or 1 byte comes back as it was */
			if (n && b[n - 1] > 1)
				return 0;
			len = evo_wire_encode_sensors(&m.sensors, again,
						      sizeof again);
		}
		break;
	case 4:
	default:
		r = evo_wire_decode_command(b, n, &m.command, why, sizeof why);
		if (r == EVO_WIRE_OK) {
			if (m.command.n > EVO_MAX_ACTUATORS)
				abort();
			len = evo_wire_encode_command(&m.command, again,
						      sizeof again);
		}
		break;
	}
	if (r != EVO_WIRE_OK) {
		if (r != EVO_WIRE_UNDECODABLE || !memchr(why, 0, sizeof why) ||
		    why[0] == 0)
			abort();
		return 0;
	}
	/* taken: it encodes back to the same bytes */
	if (len < 0 || (size_t)len != n || memcmp(again, b, n) != 0)
		abort();
	return 0;
}
