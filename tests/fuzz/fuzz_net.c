/* libFuzzer target for evo_netdesc_parse (core/src/parse_net.c). Besides
 * crashes and sanitizer reports it checks the parser's promises: an error
 * always comes with a "file:line: " message, and a success stays within limits.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/formats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The struct is large: static, not on the stack. */
static evo_netdesc out;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	evo_diag err;
	evo_status st;

	memset(err.msg, 'x', sizeof err.msg);
	st = evo_netdesc_parse((const char *)data, size, "f.net", &out, &err);
	if (st >= EVO_STATUS_COUNT)
		abort();
	if (st != EVO_OK) {
		if (!memchr(err.msg, 0, sizeof err.msg) ||
		    strncmp(err.msg, "f.net:", sizeof "f.net:" - 1) != 0)
			abort();
		return 0;
	}
	if (out.n_nodes > EVO_NET_MAX_NODES ||
	    out.n_links > EVO_NET_MAX_LINKS || out.n_out > EVO_MAX_SKILL_IO)
		abort();
	for (uint32_t i = 0; i < out.n_links; i++) {
		evo_q16 w = out.link[i].weight;
		if (out.link[i].to < out.n_in ||
		    w >= EVO_NET_WEIGHT_MAX * 65536 ||
		    w <= -EVO_NET_WEIGHT_MAX * 65536)
			abort();
	}
	return 0;
}
