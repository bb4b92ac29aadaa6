/* libFuzzer target for the remote protocol's decoding
 * (sim/remote/wire.c): the first byte picks the message type, the rest
 * are the bytes a remote sent. Besides crashes, leaks and sanitizer
 * reports it checks the decoder's promises: a refusal comes with a
 * sentence, and a message taken stays within evo's limits and encodes
 * back to the very bytes it came from. Seeds: tests/data/wire/. */
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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const uint8_t *b = data + 1;
	size_t n = size - 1;
	char why[256];
	memset(why, 'x', sizeof why);
	evo_wire_reason r;
	int len = -1;
	switch (data[0] % 5) {
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
