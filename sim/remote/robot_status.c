/* The wait of a robot over LCM or CAN for its next tick, and whether an
 * answer was late (sim/remote/robot_status.h). */
#include "remote/robot_status.h"

#include <stdio.h>

int evo_robot_wait_ms(int held, double until, double t, int slice_ms)
{
	if (held)
		return 0;
	double left = until - t;
	if (left <= 0)
		return -1;
	int ms = (int)(left * 1e3) + 1;
	return ms > slice_ms ? slice_ms : ms;
}

int evo_robot_answered_late(double arrived, double answered, double period,
			    char *what, size_t cap)
{
	double delay = answered - arrived;
	if (!(delay > period))
		return 0;
	snprintf(what, cap,
		 "was answered %.0f ms after it came, past its period (%.0f "
		 "ms)",
		 delay * 1e3, period * 1e3);
	return 1;
}
