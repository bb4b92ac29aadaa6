/* evo — a line of counts by reason, as evo reports what it dropped at the
 * end of a run: "evo serve: dropped 3 messages (2 stale, 1 ahead)". */
#ifndef EVO_COUNTS_H
#define EVO_COUNTS_H

/* On stderr: "WHO: dropped N THING[s]TAIL (n1 name1, n2 name2)" for
 * count[first..n-1], each nonzero count with its reason's name(i);
 * nothing when they are all 0. */
void evo_report_drops(const char *who, const char *thing, const char *tail,
		      const unsigned long *count, int first, int n,
		      const char *(*name)(int));

#endif
