/* Numbers from outside. Whole numbers as a user writes them, in a file, a
 * message or on a command line: decimal digits, with a '-' in front only
 * where the range has negatives; no '+', no space before. Unlike strtol, strtoul and
 * atoi, "-5" is no count (strtoul makes it 4294967291), 2^64 and more
 * are no wrap-round or saturation, and "12abc" is no 12. */
#ifndef EVO_NUMBER_H
#define EVO_NUMBER_H

#include <stddef.h>

/* Read a whole number in [lo, hi] at s into *v. end NULL: the number must
 * be all of s; else *end is set after its digits, for the caller to look
 * at what follows. Returns 0, or -1 (*v unchanged) when s does not start
 * with one, it is out of range, or (end NULL) something follows it. */
int evo_parse_whole(const char *s, const char **end, long long lo,
		    long long hi, long long *v);

/* v as evo prints a figure, into buf (returned): "%.6f", but "nan",
 * "inf" and "-inf" for those (printf may write "-nan"), and with whole
 * set, a whole number (a count a metric holds) without decimals: "486",
 * not "486.000000". */
const char *evo_number_text(char *buf, size_t cap, double v,
			    int whole);

/* 1 when each of the n numbers at v is finite (no NaN, no infinity): the
 * first check of a scene's piece as it is added. */
int evo_finite_all(const double *v, int n);

#endif
