/* libFuzzer target for evo_vardesc_parse (core/src/parse_vardesc.c). Besides
 * crashes and sanitizer reports it checks the parser's promises: an error
 * always comes with a "file:line: " message, and a success stays within limits.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/formats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The struct is large: static, not on the stack. */
static evo_vardesc out;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	evo_diag err;
	evo_status st;

	memset(err.msg, 'x', sizeof err.msg);
	st = evo_vardesc_parse((const char *)data, size, "f.vardesc", &out,
			       &err);
	if (st >= EVO_STATUS_COUNT)
		abort();
	if (st != EVO_OK) {
		if (!memchr(err.msg, 0, sizeof err.msg) ||
		    strncmp(err.msg, "f.vardesc:", sizeof "f.vardesc:" - 1) !=
			0)
			abort();
		return 0;
	}
	if (out.n_vars > EVO_MAX_VARIABLES)
		abort();
	for (uint32_t i = 0; i < out.n_vars; i++)
		if (!out.var[i].name[0] ||
		    out.var[i].type >= EVO_VAR_TYPE_COUNT)
			abort();
	return 0;
}
