/* evo — a robot, whichever way it is reached: over LCM (session.h,
 * evo_robot_*: a remote that says hello with its names) or over CAN
 * (can_robot.h: a body on a bus, in the frames of docs/wire.md). A
 * DEMOREMOTE run (cmd/run.c) drives either through this one interface,
 * with the same panel, trace, counts and reports; what differs is said
 * in docs/remote.md and docs/can.md. */
#ifndef EVO_ROBOT_H
#define EVO_ROBOT_H

#include <signal.h>
#include <stdint.h>

#include "base/err.h"
#include "evo/fixed.h"
#include "mind/mindfolder.h"
#include "remote/robot_status.h"

typedef struct evo_robot_conn evo_robot_conn;

/* What `evo check` checks of a remote task's connection: a CANURL only
 * in a DEMOREMOTE task (a remote simulator is reached over LCM) and a URL
 * of can.h's; over LCM, the keys evo_remote_opts_from_task reads, and
 * for a remote simulator REMOTENAME or LCMKEYFILE given (a DEMOREMOTE
 * task may reach its robot by `evo run --can` instead). 0, or -1 with err set ("TASK: ..."). */
int evo_robot_task_check(const evo_simbatch *task, const char *type,
			 const char *task_path, evo_err *err);

typedef struct evo_robot_conn_def {
	const evo_mindfolder *mind;
	const evo_simbatch *task; /* its LCMURL, REMOTENAME, REMOTETIMEOUT,
				     CANURL */
	const char *task_path;	  /* for messages */
	/* the robot's CAN URL (can.h); NULL: the task's CANURL, and without
	 * one the robot is reached over LCM */
	const char *can_url;
	volatile sig_atomic_t *stop; /* as in evo_remote_opts */
} evo_robot_conn_def;

/* Find the robot and check that it fits the botdesc. NULL with err set,
 * or with err empty when stopped while waiting for it. */
evo_robot_conn *evo_robot_conn_open(const evo_robot_conn_def *def,
				    evo_err *err);

/* STOP to the robot when an episode ran, the drop counts (stderr),
 * close. NULL is fine. */
void evo_robot_conn_close(evo_robot_conn *c);

/* The line that says which robot was found ("remote avoid-bot: robot, a
 * tick every 33.333 ms"); its name (over CAN, its URL); its period in
 * seconds; REMOTETIMEOUT in seconds. */
const char *evo_robot_conn_about(const evo_robot_conn *c);
const char *evo_robot_conn_name(const evo_robot_conn *c);
double evo_robot_conn_period(const evo_robot_conn *c);
double evo_robot_conn_timeout(const evo_robot_conn *c);

/* As evo_robot_start, evo_robot_next, evo_robot_answer (session.h). */
int evo_robot_conn_start(evo_robot_conn *c, int64_t episode,
			 uint64_t layout_seed, uint64_t seed, evo_err *err);
int evo_robot_conn_next(evo_robot_conn *c, int timeout_ms, evo_err *err);
int evo_robot_conn_answer(evo_robot_conn *c, const evo_q16 *commands,
			  evo_err *err);

/* The held tick's sensor values, botdesc order, as the mind reads them. */
void evo_robot_conn_sensors(const evo_robot_conn *c, evo_q16 *values);

/* Where the episode is, and the counts so far (robot_status.h). */
void evo_robot_conn_status(const evo_robot_conn *c, evo_robot_status *s);

/* The closing line of counts on stdout ("robot NAME: T ticks: ..."). */
void evo_robot_conn_report(const evo_robot_conn *c);

#endif
