/* The wait of a robot over LCM or CAN for its next tick
 * (sim/remote/robot_status.h). */
#include "remote/robot_status.h"

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
