#include "base/err.h"

#include <stdarg.h>
#include <stdio.h>

int evo_fail(evo_err *err, const char *fmt, ...)
{
	if (err) {
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(err->msg, sizeof err->msg, fmt, ap);
		va_end(ap);
	}
	return -1;
}

static unsigned n_warnings, n_quiet;
static int quiet;

void evo_warning(const char *fmt, ...)
{
	if (quiet) {
		n_quiet++;
		return;
	}
	va_list ap;
	va_start(ap, fmt);
	fputs("warning: ", stderr);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
	n_warnings++;
}

unsigned evo_warning_count(void)
{
	return n_warnings;
}

unsigned evo_warning_quiet(int on)
{
	unsigned n = n_quiet;
	quiet = on;
	n_quiet = 0;
	return n;
}
