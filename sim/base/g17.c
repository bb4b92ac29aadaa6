/* "%.17g" without printf: see g17.h.
 *
 * x = m 2^e exactly (m < 2^53). Its 17 significant digits are the
 * integer nearest x 10^k, k = 16 - (x's decimal exponent): m 10^k fits
 * in 128 bits for k <= 22 (2^53 10^22 < 2^127), and dividing by 2^-e is
 * a shift whose remainder says how to round, exactly. */
#include "base/g17.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

__extension__ typedef unsigned __int128 u128;

#define TEN16 10000000000000000ull
#define TEN17 100000000000000000ull

/* m 10^k / 2^s rounded half to even into *q, and its floor as the
 * result; s in [0, 127], k in [0, 22]. */
static uint64_t scaled(uint64_t m, int k, int s, uint64_t *q)
{
	u128 v = m;
	for (int i = 0; i < k; i++)
		v *= 10;
	if (s == 0) {
		*q = (uint64_t)v;
		return *q;
	}
	u128 fl = v >> s, r = v - (fl << s), half = (u128)1 << (s - 1);
	*q = (uint64_t)fl + (r > half || (r == half && (fl & 1)));
	return (uint64_t)fl;
}

size_t evo_g17(double x, char *out, size_t cap)
{
	double a = fabs(x);
	if (!(a >= 1e-5 && a < 1e17) || cap < 32)
		return (size_t)snprintf(out, cap, "%.17g", x);
	int e2;
	double f = frexp(a, &e2); /* a = f 2^e2, f in [0.5, 1) */
	uint64_t m = (uint64_t)ldexp(f, 53);
	int e = e2 - 53; /* a = m 2^e */
	int ex = (int)floor(log10(a)), s = e < 0 ? -e : 0;
	/* the exponent from the digits' floor (log10 may be off by one),
	 * then the rounded digits; 99..9.5 rounds up to 10^17 */
	uint64_t d = 0, fl = 0;
	for (int tries = 0; tries < 3; tries++) {
		int k = 16 - ex;
		if (k < 0 || k > 22 || s > 127)
			return (size_t)snprintf(out, cap, "%.17g", x);
		fl = scaled(e > 0 ? m << e : m, k, s, &d);
		if (fl >= TEN17)
			ex++;
		else if (fl < TEN16)
			ex--;
		else
			break;
	}
	if (fl < TEN16 || fl >= TEN17)
		return (size_t)snprintf(out, cap, "%.17g", x);
	if (d == TEN17) {
		d = TEN16;
		ex++;
	}
	char dig[17];
	for (int i = 16; i >= 0; i--, d /= 10)
		dig[i] = (char)('0' + d % 10);
	int nd = 17; /* significant digits after dropping trailing zeros */
	while (nd > 1 && dig[nd - 1] == '0')
		nd--;
	char *p = out;
	if (x < 0)
		*p++ = '-';
	if (ex < -4 || ex >= 17) {
		*p++ = dig[0];
		if (nd > 1) {
			*p++ = '.';
			memcpy(p, dig + 1, (size_t)nd - 1);
			p += nd - 1;
		}
		*p++ = 'e';
		*p++ = ex < 0 ? '-' : '+';
		int ae = ex < 0 ? -ex : ex;
		if (ae >= 100)
			*p++ = (char)('0' + ae / 100);
		*p++ = (char)('0' + ae / 10 % 10);
		*p++ = (char)('0' + ae % 10);
	} else if (ex >= 0) {
		memcpy(p, dig, (size_t)ex + 1);
		p += ex + 1;
		if (nd > ex + 1) {
			*p++ = '.';
			memcpy(p, dig + ex + 1, (size_t)(nd - ex - 1));
			p += nd - ex - 1;
		}
	} else {
		*p++ = '0';
		*p++ = '.';
		for (int i = 0; i < -ex - 1; i++)
			*p++ = '0';
		memcpy(p, dig, (size_t)nd);
		p += nd;
	}
	*p = 0;
	return (size_t)(p - out);
}
