/* `evo serve` over LCM (cmd/serve_internal.h): the server's messages, the
 * same whether it serves a simulator or stands in for a robot: its hello,
 * its sensors_t, and the control_t and command_t it takes, each checked
 * as its own (name, session, environment, freshness with a key) or
 * dropped and counted by reason. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/serve_internal.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

#include "base/clock.h"

void evo_serve_drop(server *sv, evo_wire_reason r, const char *type,
		    const char *why)
{
	if (sv->dropped[r]++ == 0)
		fprintf(stderr,
			"evo serve: dropped a %s (%s: %s); later drops are "
			"counted and reported at the end\n",
			type, evo_wire_reason_name(r), why);
}

void evo_serve_drop_misplaced(server *sv, const evo_wire_command *c,
			      const char *who, long long tick,
			      long long episode, const char *state, int ahead)
{
	char why[256];
	snprintf(why, sizeof why,
		 "tick %lld of episode %lld; %s is at tick %lld of episode "
		 "%lld%s",
		 (long long)c->tick, (long long)c->episode, who, tick, episode,
		 state);
	evo_serve_drop(sv, ahead ? EVO_WIRE_AHEAD : EVO_WIRE_STALE,
		       "command_t", why);
}

int evo_serve_publish_hello(server *sv, evo_err *err)
{
	unsigned char buf[EVO_WIRE_MAX_BYTES];
	int n = evo_wire_encode_hello(&sv->hello, buf, sizeof buf);
	if (n < 0)
		return evo_fail(err, "evo serve: cannot encode the hello");
	return evo_link_publish(sv->link, "EVO_HELLO", buf, (size_t)n, err);
}

/* Sense env's world and send the sensors_t of its current tick. */
int evo_serve_send_sensors(server *sv, served_env *e, int env, double reward,
			   int done, evo_err *err)
{
	evo_wire_sensors s = {
	    .session = sv->hello.session,
	    .env = env,
	    .episode = e->episode,
	    .tick = e->tick,
	    .n = sv->hello.n_sensors,
	    .reward = reward,
	    .done = done,
	};
	snprintf(s.name, sizeof s.name, "%s", sv->hello.name);
	evo_sim_sense(e->sim, s.value);
	/* a simulator's episode so far, for novelty search and MAP-Elites
	 * (docs/remote.md): evo takes the episode's last */
	if (sv->hello.kind == EVO_REMOTE_SIMULATOR) {
		int nb = evo_sim_behaviour(e->sim, s.behaviour, err);
		if (nb < 0)
			return -1;
		s.n_behaviour = (unsigned)nb;
	}
	e->last_len = evo_wire_encode_sensors(&s, e->last, sizeof e->last);
	if (e->last_len < 0)
		return evo_fail(err, "evo serve: cannot encode a sensors_t");
	return evo_link_publish(sv->data, sv->ch_sensors, e->last,
				(size_t)e->last_len, err);
}

int evo_serve_resend(server *sv, served_env *e, evo_err *err)
{
	return evo_link_publish(sv->data, sv->ch_sensors, e->last,
				(size_t)e->last_len, err);
}

/* A control_t or command_t decoded (r, why: the decoder's verdict) and
 * for this server: 1, or 0 when it was dropped (counted by reason). */
static int admit(server *sv, const evo_link_msg *m, evo_wire_reason r,
		 char *why, size_t cap, const char *type, const char *name,
		 int64_t session, int32_t env, evo_wire_fresh *fresh)
{
	if (r) {
		evo_serve_drop(sv, r, type, why);
		return 0;
	}
	/* for another remote or session, or an environment not run here */
	if (strcmp(name, sv->hello.name) != 0 || session != sv->hello.session ||
	    env < 0 || env >= sv->hello.environments) {
		snprintf(why, cap, "for %s, session %lld, environment %d", name,
			 (long long)session, (int)env);
		evo_serve_drop(sv, EVO_WIRE_FOREIGN, type, why);
		return 0;
	}
	r = evo_wire_fresh_take(fresh, m->stamp, why, cap);
	if (r) {
		evo_serve_drop(sv, r, type, why);
		return 0;
	}
	return 1;
}

int evo_serve_take_control(server *sv, const evo_link_msg *m,
			   evo_wire_control *c)
{
	char why[256];
	evo_wire_reason r =
	    evo_wire_decode_control(m->data, m->len, c, why, sizeof why);
	return admit(sv, m, r, why, sizeof why, "control_t", c->name,
		     c->session, c->env, &sv->fresh_control);
}

int evo_serve_take_command(server *sv, const evo_link_msg *m,
			   evo_wire_command *c)
{
	char why[256];
	evo_wire_reason r =
	    evo_wire_decode_command(m->data, m->len, c, why, sizeof why);
	if (!admit(sv, m, r, why, sizeof why, "command_t", c->name, c->session,
		   c->env, &sv->fresh_command))
		return 0;
	if (c->n != sv->hello.n_actuators) {
		snprintf(why, sizeof why, "%u values; the hello says %u", c->n,
			 sv->hello.n_actuators);
		evo_serve_drop(sv, EVO_WIRE_COUNTS, "command_t", why);
		return 0;
	}
	return 1;
}

int evo_serve_next(server *sv, int ms, evo_link_msg *m, evo_err *err)
{
	evo_link *links[2] = {sv->link, sv->data};
	int which;
	int got = evo_link_next_any(links, sv->data == sv->link ? 1 : 2, ms,
				    &which, m, err);
	if (got <= 0)
		return got < 0 ? -1 : SERVE_OTHER;
	int data = links[which] == sv->data;
	if (data && strcmp(m->channel, sv->ch_command) == 0)
		return SERVE_COMMAND;
	if (data && strcmp(m->channel, sv->ch_control) == 0)
		return SERVE_CONTROL;
	if (which == 0 && strcmp(m->channel, "EVO_WHO") == 0 &&
	    evo_serve_publish_hello(sv, err))
		return -1;
	return SERVE_OTHER;
}
