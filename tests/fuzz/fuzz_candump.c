/* libFuzzer target for evo's reading of candump log lines
 * (sim/remote/can_format.c). Besides crashes and sanitizer reports it
 * checks the parser's promises: a line taken gives a classic frame with
 * an 11-bit id, the interface is a NUL-ended string, a refusal names a
 * reason, and a frame taken formats back to a line that parses to it. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "remote/can.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	double t;
	char iface[EVO_CANDUMP_IFACE_MAX];
	evo_can_frame f, g;
	evo_can_bad why = EVO_CAN_BAD_COUNT;
	memset(iface, 'x', sizeof iface);
	if (!evo_candump_parse((const char *)data, size, &t, iface, &f, &why)) {
		if ((unsigned)why >= EVO_CAN_BAD_COUNT)
			abort();
		return 0;
	}
	if (f.id > 0x7FF || f.len > 8 || !memchr(iface, 0, sizeof iface))
		abort();
	char line[EVO_CANDUMP_LINE_MAX];
	size_t n = evo_candump_format(&f, 0.5, iface, line);
	char iface2[EVO_CANDUMP_IFACE_MAX];
	if (n < 2 || !evo_candump_parse(line, n - 1, &t, iface2, &g, &why) ||
	    g.id != f.id || g.len != f.len || memcmp(g.data, f.data, f.len))
		abort();
	return 0;
}
