/* `evo serve TASK.simbatch --can URL`: the task's 2D world as a robot's
 * body on a CAN bus (docs/can.md), for a DEMOREMOTE run over CAN. */
#ifndef EVO_SERVE_CAN_H
#define EVO_SERVE_CAN_H

#include <signal.h>

#include "mind/task.h"

typedef struct evo_serve_can_def {
	const evo_task *task;
	const char *task_path;
	const char *url; /* can.h's */
	double tick_ms;	 /* the period, rounded to 0.1 ms */
	double timeout;	 /* seconds without a command before neutral */
	volatile sig_atomic_t *stop; /* ends the run */
} evo_serve_can_def;

/* Serve until stopped: 0, or 1 with the reason printed. */
int evo_serve_can(const evo_serve_can_def *def);

#endif
