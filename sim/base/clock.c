/* The host's clocks (base/clock.h). */
#define _POSIX_C_SOURCE 200809L
#include "base/clock.h"

#include <time.h>

static double seconds(clockid_t c)
{
	struct timespec ts;
	clock_gettime(c, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double evo_clock_now(void)
{
	return seconds(CLOCK_MONOTONIC);
}

double evo_clock_real(void)
{
	return seconds(CLOCK_REALTIME);
}
