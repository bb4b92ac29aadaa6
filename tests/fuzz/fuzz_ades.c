/* libFuzzer target for evo_ades_parse (core/src/parse_ades.c). Besides crashes
 * and sanitizer reports it checks the parser's promises: an error always
 * comes with a "file:line: " message, and a success stays within limits. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/formats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The struct is large: static, not on the stack. */
static evo_ades out;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	evo_diag err;
	evo_status st;

	memset(err.msg, 'x', sizeof err.msg);
	st = evo_ades_parse((const char *)data, size, "f.ades", &out, &err);
	if (st >= EVO_STATUS_COUNT)
		abort();
	if (st != EVO_OK) {
		if (!memchr(err.msg, 0, sizeof err.msg) ||
		    strncmp(err.msg, "f.ades:", sizeof "f.ades:" - 1) != 0)
			abort();
		return 0;
	}
	if (out.n_in > EVO_MAX_SKILL_IO || out.n_out > EVO_MAX_SKILL_IO ||
	    !out.name[0] || out.layers > 16 ||
	    (out.kind == EVO_SKILL_HARDCODED && !out.hc_class[0]))
		abort();
	for (uint32_t i = 0; i < out.n_in; i++)
		if (!evo_input_type_name(out.in[i].type) || !out.in[i].name[0])
			abort();
	for (uint32_t i = 0; i < out.n_out; i++)
		if (!evo_output_type_name(out.out[i].type) ||
		    !out.out[i].name[0])
			abort();
	return 0;
}
