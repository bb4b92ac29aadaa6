/* evo — private to sim/remote/: what the files of evo's side of its remotes
 * share (session_find.c finds and checks the remotes, session.c drives
 * their episodes in lockstep, session_robot.c answers a robot running
 * free): the clocks, the waits' constants, drop counting, and the checks
 * every message from a remote passes whoever waits for it.
 * No other folder may include it. */
#ifndef EVO_SESSION_INTERNAL_H
#define EVO_SESSION_INTERNAL_H

#include <stdint.h>

#include "base/clock.h"
#include "remote/session.h"

#define SLICE_MS 50   /* the longest wait between two looks at stop */
#define RESEND_S 0.25 /* a message unanswered this long is sent again */
/* a hello of a new session is a restart once the old session has been
 * silent this long after it (without a key anyone can send that hello) */
#define RESTART_GRACE_S 1.0

/* "stopped" in err, -1, when o's stop flag is set; else 0. */
int evo_session_stopped(const evo_remote_opts *o, evo_err *err);

/* "simulator" or "robot". */
const char *evo_session_kind_name(evo_remote_kind k);

/* The remote of s by that name, or NULL. */
evo_remote *evo_session_by_name(const evo_remotes *s, const char *name);

/* Count a message of r dropped for why_code; the first of each reason is
 * said at once. */
void evo_session_dropped(evo_remote *r, evo_wire_reason why_code,
			 const char *type, const char *why);

/* A sensors_t on r's channel, decoded and checked as r's own: its name,
 * session and an environment below n_envs, its count of values, its
 * freshness (with a key). 1 with *s filled, or 0 when dropped (counted). */
int evo_session_admit_sensors(evo_remote *r, const evo_link_msg *m, int n_envs,
			      evo_wire_sensors *s);

/* Two sensors_t of one tick: the same values, reward and end. */
int evo_session_same_sensors(const evo_wire_sensors *a,
			     const evo_wire_sensors *b);

/* -1 with err set: two different answers came for one tick of r. */
int evo_session_conflict(evo_remote *r, const evo_wire_sensors *s,
			 evo_err *err);

/* Name a value outside [0, 1] in why by the sensor r's hello gives it. */
void evo_session_name_bad_value(const evo_wire_hello *h,
				const evo_wire_sensors *s, char *why,
				size_t cap);

/* A hello on EVO_HELLO while running: a restart noted, or nothing. */
void evo_session_take_hello(evo_remotes *s, const evo_link_msg *m);

/* A remote whose restart is now certain: -1 with err set, or (lose_silent)
 * 1 with *ri the remote, taken as lost. 0: none. */
int evo_session_restarted(evo_remotes *s, int *ri, evo_err *err);

/* Send env's last message again when unanswered for RESEND_S at time t.
 * 0, or -1 with err set. */
int evo_session_resend(evo_remote *r, evo_remote_env *e, double t,
		       evo_err *err);

/* A command_t of r for (env, episode, tick): commands (botdesc order) in
 * the remote's actuator order. */
void evo_session_command(const evo_remote *r, int env, int64_t episode,
			 int64_t tick, const double *commands,
			 evo_wire_command *c);

#endif
