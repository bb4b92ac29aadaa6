/* The benchmarks' --ticks argument: a whole number 1..1000000000 as
 * base/number.h reads it, or a usage message naming the benchmark. */
#ifndef EVO_BENCH_ARGS_H
#define EVO_BENCH_ARGS_H

#include <stdio.h>

#include "base/number.h"

/* 0 with *ticks set, or -1 after the message. */
static inline int bench_ticks_arg(const char *prog, const char *text,
				  long long *ticks)
{
	if (evo_parse_whole(text, NULL, 1, 1000000000, ticks) == 0)
		return 0;
	fprintf(stderr,
		"%s: --ticks expects a whole number 1..1000000000, found "
		"'%s'\n",
		prog, text);
	return -1;
}

#endif
