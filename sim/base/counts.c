/* A line of counts by reason (base/counts.h). */
#include "base/counts.h"

#include <stdio.h>

void evo_report_drops(const char *who, const char *thing, const char *tail,
		      const unsigned long *count, int first, int n,
		      const char *(*name)(int))
{
	unsigned long total = 0;
	for (int i = first; i < n; i++)
		total += count[i];
	if (!total)
		return;
	fprintf(stderr, "%s: dropped %lu %s%s%s (", who, total, thing,
		total == 1 ? "" : "s", tail);
	const char *sep = "";
	for (int i = first; i < n; i++)
		if (count[i]) {
			fprintf(stderr, "%s%lu %s", sep, count[i], name(i));
			sep = ", ";
		}
	fprintf(stderr, ")\n");
}
