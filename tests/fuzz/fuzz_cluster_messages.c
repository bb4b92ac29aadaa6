/* libFuzzer target for rank 0's checks of what a rank sends
 * (sim/cluster/cluster_messages.c): the first byte says HELLO or RESULT
 * (and the chunk a result answers), the rest is the message. Besides
 * crashes and sanitizer reports it checks their promises: a hello taken
 * gives 1..EVO_EVAL_MAX_THREADS threads and the task's settings, a result
 * taken is of the chunk asked for and holds only what an evaluation
 * gives, and every message, taken or not, is a NUL-ended string with no
 * control byte (it goes to the user's terminal). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cluster/cluster_messages.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void printable(const evo_err *err)
{
	const char *end = memchr(err->msg, 0, sizeof err->msg);
	if (!end)
		abort();
	for (const char *p = err->msg; p < end; p++)
		if ((unsigned char)*p < 0x20 || *p == 0x7f)
			abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const evo_cluster_task t = {
	    .seed = 11, .reps = 2, .ticks = 60, .n_in = 10, .n_out = 2};
	evo_err err;
	memset(&err, 'x', sizeof err);
	if (data[0] & 1) {
		evo_cluster_hello h;
		if (evo_cluster_check_hello(data + 1, size - 1, 3, &t, &h,
					    &err) == 0) {
			if (h.ok != 1 || h.threads < 1 ||
			    h.threads > EVO_EVAL_MAX_THREADS ||
			    h.seed != t.seed || h.reps != t.reps ||
			    h.ticks != t.ticks || h.n_in != t.n_in ||
			    h.n_out != t.n_out ||
			    !memchr(h.host, 0, sizeof h.host))
				abort();
			return 0;
		}
		printable(&err);
		return 0;
	}
	int count = 1 + (data[0] >> 1) % 4, first = 5;
	evo_eval_result res[4];
	if (evo_cluster_check_result(data + 1, size - 1, 1, "node", first,
				     count, res, &err) == 0) {
		if (size - 1 != 12 + (size_t)count * sizeof res[0])
			abort();
		for (int i = 0; i < count; i++)
			if ((res[i].solved != 0 && res[i].solved != 1) ||
			    res[i].collisions < 0 || res[i].group != 0 ||
			    res[i].wins != 0)
				abort();
		return 0;
	}
	printable(&err);
	return 0;
}
