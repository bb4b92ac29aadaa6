/* libFuzzer target for whole numbers as users write them
 * (sim/base/number.c), against a reference built on strtoll: a number is
 * taken exactly when the input is digits (with one '-' in front only
 * where the range has negatives), nothing else, and strtoll reads it in
 * range without overflow; the value is strtoll's. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/number.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1 || size > 64)
		return 0;
	/* the first byte picks a range */
	static const long long lo[] = {0, -10, INT32_MIN, 0, -9223372036854775807LL - 1};
	static const long long hi[] = {4294967295LL, 10, INT32_MAX, 0,
				       9223372036854775807LL};
	unsigned k = data[0] % 5;
	char s[80];
	memcpy(s, data + 1, size - 1);
	s[size - 1] = 0;
	if (strlen(s) != size - 1)
		return 0; /* a NUL inside: a C string ends there */
	long long v = 12345;
	int rc = evo_parse_whole(s, NULL, lo[k], hi[k], &v);
	/* the reference */
	const char *p = s + (s[0] == '-' && lo[k] < 0);
	int digits = *p != 0;
	for (const char *q = p; *q; q++)
		digits &= *q >= '0' && *q <= '9';
	char *end;
	errno = 0;
	long long r = digits ? strtoll(s, &end, 10) : 0;
	int want = digits && errno == 0 && r >= lo[k] && r <= hi[k];
	if ((rc == 0) != want || (rc == 0 && v != r) || (rc != 0 && v != 12345))
		abort();
	return 0;
}
