/* evo — evo's side of a remote (docs/remote.md): find it on the LCM URL,
 * check its names against the mind's botdesc, and drive its episodes in
 * lockstep, one environment at a time or several at once; or, for a robot,
 * answer each tick it sends as it runs free (evo_robot_*, at the end).
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

#define EVO_REMOTE_MAX_ENVS EVO_WIRE_MAX_ENVS

/* Seconds of silence before evo says a remote is silent (REMOTETIMEOUT). */
#define EVO_REMOTE_DEFAULT_TIMEOUT 2.0

#define EVO_REMOTE_MAX_REMOTES 16

typedef struct evo_remote_opts {
	const char *task;  /* the task's path, for messages; NULL: none */
	const char *url;   /* NULL: LCM's default */
	/* the remotes to use, by name, separated by commas ("sim1,sim2");
	 * NULL: any of the kind (with a key: any that presents it) */
	const char *name;
	evo_wire_key key;  /* the task's LCMKEYFILE; len 0: none */
	evo_remote_kind kind;
	double timeout;	   /* seconds of silence before saying so */
	/* 1: a remote silent for `timeout` while evo waits for it is lost
	 * (evo_remotes_wait says which) instead of waited for */
	int lose_silent;
	const char *self;  /* evo's name in who_t */
	/* set by a signal handler: every wait ends soon after, with
	 * "stopped" in err */
	volatile sig_atomic_t *stop;
} evo_remote_opts;

/* One environment's episode, as evo sees it. */
typedef struct evo_remote_env {
	int64_t episode;
	int64_t tick;	/* the tick of `sensors` */
	int waiting;	/* a message was sent and its answer is awaited */
	int have;	/* sensors holds the answer */
	int taken;	/* sensors holds a tick taken (of `sensors.episode`) */
	evo_wire_sensors sensors;
	unsigned char sent[EVO_WIRE_MAX_BYTES]; /* the last message sent */
	int sent_len;
	char sent_channel[96];
	double sent_at;
} evo_remote_env;

typedef struct evo_remote {
	struct evo_remotes *set;
	evo_link *link; /* of its episodes: its hello's url, or the set's */
	evo_wire_hello hello;
	/* botdesc sensor i is hello sensor sensor_at[i]; hello actuator j is
	 * botdesc actuator actuator_of[j] */
	int sensor_at[EVO_MAX_SENSORS];
	int actuator_of[EVO_MAX_ACTUATORS];
	char ch_sensors[96], ch_command[96], ch_control[96];
	unsigned long dropped[EVO_WIRE_N_REASONS];
	evo_wire_fresh fresh_hello, fresh_sensors; /* with a key */
	/* a hello of its name with another session came at new_session_at
	 * (0: none): a restart, unless this session answers on (then the
	 * hello was not its: another process says hello under its name) */
	int64_t new_session;
	double new_session_at;
	int64_t new_session_recv; /* its arrival, real-time microseconds */
	unsigned long impostor_hellos;
	unsigned long resent; /* messages sent again, unanswered in time */
	double heard_at, told_at; /* the last message; the last "silent" */
	int lost;
	evo_remote_env env[EVO_REMOTE_MAX_ENVS];
} evo_remote;

/* A task's remote keys (docs/remote.md): LCMURL, REMOTENAME,
 * REMOTETIMEOUT and LCMKEYFILE (read here, relative to the task's folder;
 * the key is never printed), into o (which keeps pointers into sb). 0, or
 * -1 with err set ("TASK: REMOTETIMEOUT expects seconds, ..."). */
int evo_remote_opts_from_task(const evo_simbatch *sb, const char *path,
			      evo_remote_kind kind, evo_remote_opts *o,
			      evo_err *err);

/* 0 when o names its remotes or has a key; else -1 with err set: the
 * task's remotes would be whatever process answered first on its URL. */
int evo_remote_opts_chosen(const evo_remote_opts *o, evo_err *err);

/* 1 when name is one of o's REMOTENAME list (or the list is empty). */
int evo_remote_named(const evo_remote_opts *o, const char *name);

/* The remotes evo uses, all on one LCM connection. */
typedef struct evo_remotes {
	evo_link *link; /* the URL's: who_t and hello_t */
	/* every connection: link first, then each other URL a remote's
	 * episodes use (a remote on a port of its own keeps its traffic
	 * from every other process on the URL) */
	evo_link *links[EVO_REMOTE_MAX_REMOTES + 1];
	int n_links;
	evo_remote_opts opts;
	const evo_mindfolder *mind;
	int n;
	evo_remote *r[EVO_REMOTE_MAX_REMOTES];
	unsigned long undecodable_hellos;
	int url_ttl; /* the URL's ttl: a remote's episodes' URL reaches no
			further */
	char passed_over[EVO_REMOTE_NAME_MAX]; /* the last that did not fit */
	char passed_why[1024];		       /* and why */
} evo_remotes;

/* Connect to the URL. NULL with err set, also when o names no remote
 * and has no key (the task's remotes would be whoever answers). */
evo_remotes *evo_remotes_open(const evo_mindfolder *mind,
			      const evo_remote_opts *o, evo_err *err);

/* Send STOP to every environment that ran an episode, print each remote's
 * drop counts if any, close. */
void evo_remotes_close(evo_remotes *s);

/* Ask who is on the URL until a remote of the kind (and name) answers,
 * then go on listening `window` seconds for more (0: the first only), and
 * check each: protocol, kind, sensor and actuator names. 0, or -1 with
 * err set ("remote sim1 does not fit Avoid.botdesc; it lacks the sensors
 * S3; it has the extra sensors S11 ..."). */
int evo_remotes_find(evo_remotes *s, double window, evo_err *err);

/* Start episode `episode` in environment env of remote ri; its tick 0
 * is then awaited. */
int evo_remotes_send_reset(evo_remotes *s, int ri, int env, int64_t episode,
			   uint64_t layout_seed, uint64_t seed, evo_err *err);

/* Send the commands (botdesc order) of env's current tick; the next tick
 * is then awaited. */
int evo_remotes_send_command(evo_remotes *s, int ri, int env,
			     const double *commands, evo_err *err);

/* Wait until an awaited answer comes: 0 with (*ri, *env) the environment
 * whose sensors now hold it; 1 when remote *ri was lost (lose_silent; its
 * environments await nothing any more); -1 with err set. */
int evo_remotes_wait(evo_remotes *s, int *ri, int *env, evo_err *err);

/* The sensor values of an environment's current tick, in botdesc order. */
void evo_remote_sensors(const evo_remote *r, int env, double *values);

/* ---- one remote, one environment at a time (DEMOREMOTESIM) ------------ */

/* Open, find one remote, check it. NULL with err set. */
evo_remotes *evo_remote_connect(const evo_mindfolder *mind,
				const evo_remote_opts *o, evo_err *err);

/* Start episode `episode` in environment env of the first remote and wait
 * for its tick 0. */
int evo_remote_reset(evo_remotes *s, int env, int64_t episode,
		     uint64_t layout_seed, uint64_t seed, evo_err *err);

/* Send env's commands (botdesc order) for its current tick and wait for
 * the next tick. 0, 1 when the episode ended (done), -1 with err set. */
int evo_remote_step(evo_remotes *s, int env, const double *commands,
		    evo_err *err);

/* The episode's reward so far in env (the last sensors_t's). */
double evo_remote_reward(const evo_remote *r, int env);

/* ---- a robot: free running (DEMOREMOTE) --------------------------------- */

/* evo's side of a robot's episodes. A robot ticks at its own rate (its
 * hello's tick_us) and sends the sensors of every tick; evo answers each
 * with that tick's commands and never makes it wait. Every tick number
 * from 0 on is counted once: answered in time, late (answered more than a
 * period after its sensors came or after the next tick's came, or not at
 * all because a newer tick came first) or missing (never came, or came
 * unusable). The first late and the first missing tick are reported at
 * once, and the counts by evo_robot_report. Zero the struct before its
 * first episode. */
typedef struct evo_robot {
	evo_remotes *set; /* its first remote is the robot */
	double period;	  /* seconds, from the hello's tick_us */
	int64_t episode;
	int64_t tick;	  /* the tick whose sensors are held; -1: none yet */
	int answered;	  /* the held tick's commands were sent */
	int done;	  /* the robot ended the episode (sensors_t.done) */
	double reward;	  /* the last sensors_t's */
	double reset_at;  /* the RESET first sent (monotonic seconds) */
	double arrived;	  /* the held tick's arrival (real-time seconds) */
	double answered_at; /* its answer sent (real-time seconds) */
	int in_time_held;   /* it was counted in time, so far */
	unsigned long in_time, late, missing;
	unsigned long unanswered; /* of the late: a newer tick came first */
	int conflict; /* a second, different sensors_t of the held tick */
} evo_robot;

/* Start episode `episode` on the first remote of s, which must be a robot
 * (one environment, a tick period): a RESET carrying the seeds (a robot
 * with a world of its own may use them: `evo serve --robot` does), sent
 * again every quarter second until a tick of the episode comes. The
 * counts go on from the episodes before. 0, or -1 with err set. */
int evo_robot_start(evo_remotes *s, evo_robot *rb, int64_t episode,
		    uint64_t layout_seed, uint64_t seed, evo_err *err);

/* Wait at most timeout_ms for a tick newer than the one held, and hold the
 * newest of those that came (evo_remote_sensors(s->r[0], 0, ...) reads
 * it). 0: a tick to answer is held; 1: the robot ended the episode (its
 * reward in rb->reward); 2: nothing new came in time; -1 with err set
 * (stopped, the robot restarted, the link failed). A robot silent for the
 * timeout is reported, and waited for. */
int evo_robot_next(evo_robot *rb, int timeout_ms, evo_err *err);

/* Send the commands (botdesc order) of the held tick, once. */
int evo_robot_answer(evo_robot *rb, const double *commands, evo_err *err);

/* Seconds since the robot was last heard from. */
double evo_robot_quiet(const evo_robot *rb);

/* One line on stdout: "robot NAME: T ticks: A answered in time, L late
 * (U unanswered), M missing". */
void evo_robot_report(const evo_robot *rb);

#endif
