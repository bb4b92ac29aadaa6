/* A world standing in for a robot (`evo serve --robot` over LCM, `evo
 * serve --can` over CAN): it runs in real time, one tick a period, whether
 * commands come or not. Each period this tick's sensors go out at its
 * start and its command is awaited until its end; the world steps as soon
 * as the command comes, or at the period's end with the commands before,
 * or, once none has come for the timeout, with every actuator neutral
 * (0.5). What carries the messages is the caller's (evo_standin_io); the
 * schedule, the episode and the counts are here, the same for both. */
#ifndef EVO_CMD_STANDIN_H
#define EVO_CMD_STANDIN_H

#include <signal.h>
#include <stdint.h>

#include "base/err.h"
#include "tasksim/tasksim.h"

/* The messages, each 0 or -1 with err set; ctx is the caller's. */
typedef struct evo_standin_io {
	void *ctx;
	int (*announce)(void *ctx, evo_err *err);  /* say it is here */
	int (*send_tick)(void *ctx, evo_err *err); /* this tick's sensors */
	int (*send_end)(void *ctx, evo_err *err);  /* the episode ended */
	/* the next message, waiting at most ms, acted on */
	int (*message)(void *ctx, int ms, evo_err *err);
} evo_standin_io;

typedef struct evo_standin {
	const char *name; /* in messages: "robot NAME" */
	evo_sim *sim;
	unsigned na; /* actuators */
	evo_standin_io io;
	volatile sig_atomic_t *stop; /* ends the run */
	double period, timeout;	     /* seconds */
	long long limit; /* TICKLIM: the episode's ticks at most, 0 none */
	int active;	 /* in an episode: ticking and sending */
	int64_t episode, tick; /* the tick whose sensors went out last */
	double started_at;     /* the episode's RESET (monotonic) */
	double commanded_at;   /* the last command taken, or started_at */
	int commanded;	       /* a command came in this episode */
	int neutral;	       /* every actuator at 0.5 for want of commands */
	int stepped, ended;    /* this tick: the world stepped; it ended */
	int restart;	       /* a RESET or STOP broke off the period */
	double cmd[EVO_MAX_ACTUATORS]; /* what the actuators do (botdesc) */
	unsigned long ticks, in_time, held, neutral_ticks, late, overruns;
} evo_standin;

/* Every actuator neutral. */
void evo_standin_neutral(evo_standin *s);

/* Announce, then tick until stopped: 0, or -1 with err set. */
int evo_standin_run(evo_standin *s, evo_err *err);

/* A RESET of episode e (1..INT_MAX: the caller checks): a new episode,
 * now, from evo's seeds; except a RESET of the episode running, before
 * any command of it and within a second of its start, which is evo
 * sending its RESET again and is ignored (1). 0, 1, or -1 with err
 * set. */
int evo_standin_reset(evo_standin *s, int64_t e, uint64_t layout_seed,
		      uint64_t seed, evo_err *err);

/* A STOP of the episode running: every actuator neutral, and nothing more
 * until a RESET. */
void evo_standin_stop(evo_standin *s);

/* The command of an earlier tick came during this one: counted, the first
 * said. */
void evo_standin_late(evo_standin *s, int64_t tick);

/* This tick's command, in time: in force from now, and the world steps. */
int evo_standin_command(evo_standin *s, const double *cmd, evo_err *err);

/* The counts, one line on stdout. */
void evo_standin_report(const evo_standin *s);

#endif
