/* evo — what a robot over LCM (session_robot.c) and a robot over CAN
 * (can_robot.c) share beneath robot.h's one interface: where an episode
 * is and its counts (evo_robot_status), and how long a wait for the next
 * tick may block. Its own header, so that can_robot.c need not reach
 * robot.h, which reaches can_robot.h. */
#ifndef EVO_ROBOT_STATUS_H
#define EVO_ROBOT_STATUS_H

#include <stddef.h>
#include <stdint.h>

/* Where the episode is, and the counts so far. */
typedef struct evo_robot_status {
	int64_t tick; /* the tick held; -1: none yet */
	int done;     /* the robot ended the episode */
	double reward;
	unsigned long in_time, late, unanswered, missing;
	double quiet; /* seconds since the robot was last heard */
} evo_robot_status;

/* How long a wait for a robot's next tick may block at time t: once a
 * tick is held, 0 (only what has already come: the newest of it); else
 * what is left until `until`, in ms, at most slice_ms; -1 when nothing is
 * held and the time is up. */
int evo_robot_wait_ms(int held, double until, double t, int slice_ms);

/* Whether a tick that arrived at `arrived` and was answered at
 * `answered` (seconds) was answered late, past the robot's period: 1,
 * with what says so ("was answered 40 ms after it came, past its period
 * (33 ms)"), else 0. */
int evo_robot_answered_late(double arrived, double answered, double period,
			    char *what, size_t cap);

#endif
