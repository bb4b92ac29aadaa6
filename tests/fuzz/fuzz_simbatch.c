/* libFuzzer target for evo_simbatch_parse (core/src/parse_simbatch.c). Besides
 * crashes and sanitizer reports it checks the parser's promises: an error
 * always comes with a "file:line: " message, and a success stays within limits,
 * every value of a known key within its range.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/formats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The struct is large: static, not on the stack. */
static evo_simbatch out;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	evo_diag err;
	evo_status st;

	memset(err.msg, 'x', sizeof err.msg);
	st = evo_simbatch_parse((const char *)data, size, "f.simbatch", &out,
				&err);
	if (st >= EVO_STATUS_COUNT)
		abort();
	if (st != EVO_OK) {
		if (!memchr(err.msg, 0, sizeof err.msg) ||
		    strncmp(err.msg, "f.simbatch:", sizeof "f.simbatch:" - 1) !=
			0)
			abort();
		return 0;
	}
	if (out.n_pairs > EVO_MAX_SIMBATCH)
		abort();
	for (uint32_t i = 0; i < out.n_pairs; i++) {
		if (evo_simbatch_get(&out, out.pair[i].key) == NULL)
			abort();
		/* every value read is within its key's range */
		const evo_simbatch_key_def *d =
		    evo_simbatch_key_find(out.pair[i].key);
		if (d && !evo_simbatch_key_ok(d, out.pair[i].value))
			abort();
	}
	for (uint32_t i = 0; i < out.n_warnings && i < EVO_MAX_WARNINGS; i++)
		if (strncmp(out.warning[i].msg, "f.simbatch:", 11) != 0)
			abort();
	return 0;
}
