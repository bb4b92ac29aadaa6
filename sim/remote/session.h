/* evo — evo's side of a remote (docs/remote.md): find it on the LCM URL,
 * check its names against the mind's botdesc, and drive its episodes in
 * lockstep, one environment at a time or several at once.
 *
 * Every message from the remote is checked before use; one that is not
 * for the tick awaited is dropped and counted by its reason, and the first
 * drop of each reason is reported at once. A message that gets no answer
 * is sent again after a quarter of a second (a simulator answers a repeat
 * of what it last answered by repeating its answer), and a remote that
 * stays silent for the timeout is reported while evo keeps waiting. */
#ifndef EVO_SESSION_H
#define EVO_SESSION_H

#include <signal.h>
#include <stdint.h>

#include "base/err.h"
#include "mind/mindfolder.h"
#include "remote/link.h"
#include "remote/wire.h"

#define EVO_REMOTE_MAX_ENVS 64

/* Seconds of silence before evo says a remote is silent (REMOTETIMEOUT). */
#define EVO_REMOTE_DEFAULT_TIMEOUT 2.0

typedef struct evo_remote_opts {
	const char *url;   /* NULL: LCM's default */
	const char *name;  /* the remote to use; NULL: the first to answer */
	evo_remote_kind kind;
	double timeout;	   /* seconds of silence before saying so */
	const char *self;  /* evo's name in who_t */
	/* set by a signal handler: every wait ends soon after, with
	 * "stopped" in err */
	volatile sig_atomic_t *stop;
} evo_remote_opts;

/* One environment's episode, as evo sees it. */
typedef struct evo_remote_env {
	int64_t episode;
	int64_t tick;	/* the tick of `sensors` */
	int have;	/* sensors holds tick's message */
	evo_wire_sensors sensors;
	unsigned char sent[EVO_WIRE_MAX_BYTES]; /* the last message sent */
	int sent_len;
	char sent_channel[96];
	double sent_at;
} evo_remote_env;

typedef struct evo_remote {
	evo_link *link;
	evo_wire_hello hello;
	evo_remote_opts opts;
	const evo_mindfolder *mind;
	/* botdesc sensor i is hello sensor sensor_at[i]; hello actuator j is
	 * botdesc actuator actuator_of[j] */
	int sensor_at[EVO_MAX_SENSORS];
	int actuator_of[EVO_MAX_ACTUATORS];
	char ch_sensors[96], ch_command[96], ch_control[96];
	unsigned long dropped[EVO_WIRE_N_REASONS];
	evo_remote_env env[EVO_REMOTE_MAX_ENVS];
	double heard_at; /* the last message from the remote */
} evo_remote;

/* Ask who is on the URL until a remote of the kind (and name) answers, then
 * check it: protocol, kind, sensor and actuator names. NULL with err set
 * ("remote sim1: its sensors lack S3; it has the extra sensor S11"). */
evo_remote *evo_remote_connect(const evo_mindfolder *mind,
			       const evo_remote_opts *o, evo_err *err);

/* Send STOP to every environment, print the drop counts if any, close. */
void evo_remote_close(evo_remote *r);

/* Start episode `episode` in environment env and wait for its tick 0. */
int evo_remote_reset(evo_remote *r, int env, int64_t episode,
		     uint64_t layout_seed, uint64_t seed, evo_err *err);

/* The sensor values of env's current tick, in botdesc order. */
void evo_remote_sensors(const evo_remote *r, int env, double *values);

/* Send env's commands (botdesc order) for its current tick and wait for
 * the next tick. 0, 1 when the episode ended (done), -1 with err set. */
int evo_remote_step(evo_remote *r, int env, const double *commands,
		    evo_err *err);

/* The episode's reward so far in env (the last sensors_t's). */
double evo_remote_reward(const evo_remote *r, int env);

#endif
