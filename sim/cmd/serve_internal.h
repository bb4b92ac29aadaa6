/* evo — private to sim/cmd/: what the files of `evo serve` over LCM share
 * (serve.c reads the options and sets the server up, serve_msg.c sends
 * and takes its messages, serve_sim.c serves a simulator in lockstep,
 * serve_robot.c stands in for a robot in real time).
 * No other folder may include it. */
#ifndef EVO_SERVE_INTERNAL_H
#define EVO_SERVE_INTERNAL_H

#include <signal.h>
#include <stdint.h>

#include "base/clock.h"
#include "base/err.h"
#include "cmd/stop.h"
#include "remote/link.h"
#include "remote/wire.h"
#include "tasksim/tasksim.h"

typedef struct served_env {
	evo_sim *sim;
	int64_t episode;	    /* 0: none yet */
	int64_t tick;		    /* the tick of the last sensors_t sent */
	uint64_t layout_seed, seed; /* of the episode's RESET */
	double reset_at;	    /* when it came (monotonic seconds) */
	int active;
	unsigned char last[EVO_WIRE_MAX_BYTES]; /* that sensors_t */
	int last_len;
} served_env;

typedef struct server {
	evo_link *link; /* the URL: who_t, hello_t */
	evo_link *data; /* its episodes: control_t, command_t, sensors_t */
	evo_wire_hello hello;
	char ch_control[96], ch_command[96], ch_sensors[96];
	served_env *env;
	unsigned long dropped[EVO_WIRE_N_REASONS];
	/* with a key: the last stamp taken on each channel from evo */
	evo_wire_fresh fresh_control, fresh_command;
} server;

/* Count a message dropped for r; the first of each reason is said. */
void evo_serve_drop(server *sv, evo_wire_reason r, const char *type,
		    const char *why);

/* A command_t for another tick than the one `who` ("this environment",
 * "the robot") is at (tick, episode), dropped as AHEAD (ahead: for a
 * tick to come) or STALE, the reason saying both places; state says why
 * none is awaited (" (ended)"), or is "". */
void evo_serve_drop_misplaced(server *sv, const evo_wire_command *c,
			      const char *who, long long tick,
			      long long episode, const char *state, int ahead);

int evo_serve_publish_hello(server *sv, evo_err *err);

/* Sense env's world and send the sensors_t of its current tick. */
int evo_serve_send_sensors(server *sv, served_env *e, int env, double reward,
			   int done, evo_err *err);

/* Send env's last sensors_t again. */
int evo_serve_resend(server *sv, served_env *e, evo_err *err);

/* A control_t decoded and for this server (its name, session and one of
 * its environments; fresh, with a key): 1, or 0 when it was dropped
 * (counted by reason). */
int evo_serve_take_control(server *sv, const evo_link_msg *m,
			   evo_wire_control *c);

/* The same for a command_t, which also carries one value an actuator. */
int evo_serve_take_command(server *sv, const evo_link_msg *m,
			   evo_wire_command *c);

/* What a message that came is (a who_t is answered where it comes). */
typedef enum serve_msg_kind {
	SERVE_OTHER,   /* none came, or not for the server */
	SERVE_CONTROL, /* on the episodes' control channel */
	SERVE_COMMAND, /* on their command channel */
} serve_msg_kind;

/* The next message on the URL or the episodes' URL, waiting at most ms:
 * its kind, with *m filled, or -1 with err set. A who_t is answered
 * here with the hello (SERVE_OTHER). */
int evo_serve_next(server *sv, int ms, evo_link_msg *m, evo_err *err);

/* Serve the environments in lockstep until stopped: 0, or -1. */
int evo_serve_lockstep(server *sv, evo_err *err);

/* Stand in for a robot until stopped, a tick every period seconds,
 * neutral after timeout seconds without a command, an episode lasting
 * limit ticks at most (0: no limit); its counts printed at the end. 0, or
 * -1 with err set. */
int evo_serve_robot(server *sv, double period, double timeout, long long limit,
		    evo_err *err);

#endif
