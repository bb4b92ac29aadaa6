/* strdup that fails on demand (tests/support/alloc_fail.h). */
#define _POSIX_C_SOURCE 200809L
#include "support/alloc_fail.h"

#include <errno.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

static atomic_int fail_at, calls;

void alloc_fail_strdup(int nth)
{
	atomic_store(&calls, 0);
	atomic_store(&fail_at, nth);
}

int alloc_fail_strdup_calls(void)
{
	return atomic_load(&calls);
}

/* The C library's strdup, but for the armed call. The test binary's
 * definition is the one the linker gives every caller in it, sim/'s
 * included (AddressSanitizer's and ThreadSanitizer's own are shared
 * libraries, which it comes before). */
char *strdup(const char *s)
{
	int n = atomic_fetch_add(&calls, 1) + 1;
	if (n == atomic_load(&fail_at)) {
		errno = ENOMEM;
		return NULL;
	}
	size_t len = strlen(s) + 1;
	char *p = malloc(len);
	return p ? memcpy(p, s, len) : NULL;
}
