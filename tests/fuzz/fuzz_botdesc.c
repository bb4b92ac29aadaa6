/* libFuzzer target for evo_botdesc_parse (core/src/parse_botdesc.c). Besides
 * crashes and sanitizer reports it checks the parser's promises: an error
 * always comes with a "file:line: " message, and a success stays within limits.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/formats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The struct is large: static, not on the stack. */
static evo_botdesc out;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	evo_diag err;
	evo_status st;

	memset(err.msg, 'x', sizeof err.msg);
	st = evo_botdesc_parse((const char *)data, size, "f.botdesc", &out,
			       &err);
	if (st >= EVO_STATUS_COUNT)
		abort();
	if (st != EVO_OK) {
		if (!memchr(err.msg, 0, sizeof err.msg) ||
		    strncmp(err.msg, "f.botdesc:", sizeof "f.botdesc:" - 1) !=
			0)
			abort();
		return 0;
	}
	if (out.n_sensors > EVO_MAX_SENSORS ||
	    out.n_actuators > EVO_MAX_ACTUATORS)
		abort();
	for (uint32_t i = 0; i < out.n_sensors; i++)
		if (!out.sensor[i].name[0] || !out.sensor[i].type[0] ||
		    !memchr(out.sensor[i].params, 0, EVO_VALUE_MAX))
			abort();
	return 0;
}
