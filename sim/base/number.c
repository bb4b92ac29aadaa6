/* Numbers from outside: whole numbers as a user writes them, figures as
 * evo prints them, finite or not (sim/base/number.h). */
#include "base/number.h"

#include <math.h>
#include <stdio.h>

#include <stddef.h>

int evo_parse_whole(const char *s, const char **end, long long lo,
		    long long hi, long long *v)
{
	const char *p = s;
	int neg = *p == '-';
	if (neg) {
		if (lo >= 0)
			return -1;
		p++;
	}
	if (*p < '0' || *p > '9')
		return -1;
	/* The magnitude's bound, -lo or hi, in unsigned arithmetic, where
	 * -LLONG_MIN fits. */
	unsigned long long cap = neg ? 0ull - (unsigned long long)lo
				     : hi < 0 ? 0 : (unsigned long long)hi;
	unsigned long long m = 0;
	for (; *p >= '0' && *p <= '9'; p++) {
		unsigned d = (unsigned)(*p - '0');
		if (m > (cap - d) / 10 || d > cap)
			return -1;
		m = m * 10 + d;
	}
	if (end)
		*end = p;
	else if (*p)
		return -1;
	long long x = neg ? (long long)(0ull - m) : (long long)m;
	if (x < lo || x > hi)
		return -1;
	*v = x;
	return 0;
}

const char *evo_number_text(char *buf, size_t cap, double v,
			    int whole)
{
	if (isnan(v))
		snprintf(buf, cap, "nan");
	else if (isinf(v))
		snprintf(buf, cap, v > 0 ? "inf" : "-inf");
	else if (whole && v == floor(v) && fabs(v) < 1e15)
		snprintf(buf, cap, "%.0f", v == 0 ? 0.0 : v);
	else
		snprintf(buf, cap, "%.6f", v);
	return buf;
}

int evo_finite_all(const double *v, int n)
{
	for (int i = 0; i < n; i++)
		if (!isfinite(v[i]))
			return 0;
	return 1;
}
