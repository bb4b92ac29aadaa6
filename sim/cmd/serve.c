/* `evo serve TASK.simbatch`: evo's own 2D world served as a remote
 * simulator over LCM (docs/remote.md). The task's environment and bot
 * model run here; the mind runs in the `evo run` that drives it. Each
 * environment is a world of its own, stepped in lockstep with the commands
 * that arrive for it.
 *
 * With --robot the world stands in for a robot instead: it runs in real
 * time, one tick a period, whether commands come or not; it holds the last
 * commands through a tick whose command comes late, and sets every
 * actuator to neutral when none has come for its timeout. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/serve.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/rng.h"
#include "cmd/serve_can.h"
#include "lua/lua_evo.h"
#include "mind/task.h"
#include "remote/link.h"
#include "remote/session.h"
#include "remote/wire.h"
#include "tasksim/tasksim.h"

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
	stop_requested = sig; /* a scene script stops too (lua_evo.h) */
}

void evo_serve_usage(FILE *f)
{
	fputs("usage: evo serve TASK.simbatch [options]\n"
	      "  --name NAME         the name evo run finds it by (default\n"
	      "                      evo-serve-PID)\n"
	      "  --environments N    episodes run at once (default 1)\n"
	      "  --url URL           the LCM URL (default: the task's LCMURL,\n"
	      "                      else LCM's default)\n"
	      "  --data-url URL      the LCM URL of its episodes (default: the\n"
	      "                      URL on a port of its own, from its name;\n"
	      "                      'same': the URL itself)\n"
	      "  --key-file FILE     the key shared with evo run (default: the\n"
	      "                      task's LCMKEYFILE; docs/remote.md, Keys)\n"
	      "  --robot             stand in for a robot: run in real time and\n"
	      "                      go neutral when evo's commands stop\n"
	      "  --tick-ms MS        the robot's period (default 33.333: 30\n"
	      "                      ticks a second)\n"
	      "  --timeout S         seconds without a command before every\n"
	      "                      actuator goes neutral (default 0.5)\n"
	      "  --can URL           stand in for a robot's body on a CAN bus\n"
	      "                      instead (--robot's rules; socketcan:IFACE,\n"
	      "                      slcan-pty:[?link=PATH], cannelloni:HOST:PORT\n"
	      "                      ...; docs/can.md)\n",
	      f);
}

static double mono_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Seconds after a RESET during which the same RESET again, once the
 * episode is past tick 0, is a late copy of it (docs/remote.md). */
#define LATE_RESET_S 2.0

typedef struct served_env {
	evo_sim *sim;
	int64_t episode; /* 0: none yet */
	int64_t tick;	 /* the tick of the last sensors_t sent */
	uint64_t layout_seed, seed; /* of the episode's RESET */
	double reset_at;	    /* when it came (monotonic seconds) */
	int active;
	unsigned char last[EVO_WIRE_MAX_BYTES]; /* that sensors_t */
	int last_len;
} served_env;

typedef struct server {
	evo_link *link;	 /* the URL: who_t, hello_t */
	evo_link *data;	 /* its episodes: control_t, command_t, sensors_t */
	evo_wire_hello hello;
	char ch_control[96], ch_command[96], ch_sensors[96];
	served_env *env;
	unsigned long dropped[EVO_WIRE_N_REASONS];
	/* with a key: the last stamp taken on each channel from evo */
	evo_wire_fresh fresh_control, fresh_command;
} server;

static void drop(server *sv, evo_wire_reason r, const char *type,
		 const char *why)
{
	if (sv->dropped[r]++ == 0)
		fprintf(stderr,
			"evo serve: dropped a %s (%s: %s); later drops are "
			"counted and reported at the end\n",
			type, evo_wire_reason_name(r), why);
}

static int publish_hello(server *sv, evo_err *err)
{
	unsigned char buf[EVO_WIRE_MAX_BYTES];
	int n = evo_wire_encode_hello(&sv->hello, buf, sizeof buf);
	if (n < 0)
		return evo_fail(err, "evo serve: cannot encode the hello");
	return evo_link_publish(sv->link, "EVO_HELLO", buf, (size_t)n, err);
}

/* Sense env's world and send the sensors_t of its current tick. */
static int send_sensors(server *sv, served_env *e, int env, double reward,
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

static int resend(server *sv, served_env *e, evo_err *err)
{
	return evo_link_publish(sv->data, sv->ch_sensors, e->last,
				(size_t)e->last_len, err);
}

/* A message for another remote or session, or an environment not run
 * here: not for us. */
static int ours(server *sv, const char *name, int64_t session, int32_t env,
		const char *type)
{
	if (strcmp(name, sv->hello.name) == 0 &&
	    session == sv->hello.session && env >= 0 &&
	    env < sv->hello.environments)
		return 1;
	char why[160];
	snprintf(why, sizeof why, "for %s, session %lld, environment %d",
		 name, (long long)session, (int)env);
	drop(sv, EVO_WIRE_FOREIGN, type, why);
	return 0;
}

/* A control_t or command_t decoded and for this server: 1, or 0 when it
 * was dropped (counted by reason). */
static int take_control(server *sv, const evo_link_msg *m, evo_wire_control *c)
{
	char why[256];
	evo_wire_reason r =
	    evo_wire_decode_control(m->data, m->len, c, why, sizeof why);
	if (r) {
		drop(sv, r, "control_t", why);
		return 0;
	}
	if (!ours(sv, c->name, c->session, c->env, "control_t"))
		return 0;
	r = evo_wire_fresh_take(&sv->fresh_control, m->stamp, why, sizeof why);
	if (r) {
		drop(sv, r, "control_t", why);
		return 0;
	}
	return 1;
}

static int take_command(server *sv, const evo_link_msg *m, evo_wire_command *c)
{
	char why[256];
	evo_wire_reason r =
	    evo_wire_decode_command(m->data, m->len, c, why, sizeof why);
	if (r) {
		drop(sv, r, "command_t", why);
		return 0;
	}
	if (!ours(sv, c->name, c->session, c->env, "command_t"))
		return 0;
	r = evo_wire_fresh_take(&sv->fresh_command, m->stamp, why, sizeof why);
	if (r) {
		drop(sv, r, "command_t", why);
		return 0;
	}
	return 1;
}

static int on_control(server *sv, const evo_link_msg *m, evo_err *err)
{
	evo_wire_control c;
	char why[256];
	if (!take_control(sv, m, &c))
		return 0;
	served_env *e = &sv->env[c.env];
	if (c.op == EVO_CONTROL_STOP) {
		e->active = 0;
		e->reset_at = -LATE_RESET_S; /* a RESET after it is new */
		return 0;
	}
	/* the same RESET again (same episode, same seeds), not yet answered
	 * by a command: its answer was lost, so it goes again
	 * (docs/remote.md) */
	double t = mono_now();
	int same = e->episode > 0 && c.episode == e->episode &&
		   c.layout_seed == e->layout_seed && c.seed == e->seed;
	if (same && e->active && e->tick == 0)
		return resend(sv, e, err);
	/* the same RESET past tick 0, soon after it: a copy evo sent again
	 * while the first answer was on its way, come late; starting over
	 * would leave evo's next command ahead of the world */
	if (same && e->tick > 0 && t - e->reset_at < LATE_RESET_S) {
		snprintf(why, sizeof why,
			 "a late copy of the RESET of episode %lld, now at "
			 "tick %lld",
			 (long long)c.episode, (long long)e->tick);
		drop(sv, EVO_WIRE_STALE, "control_t", why);
		return 0;
	}
	if (c.episode < 1 || c.episode > INT_MAX) {
		snprintf(why, sizeof why, "episode %lld", (long long)c.episode);
		drop(sv, EVO_WIRE_VALUE, "control_t", why);
		return 0;
	}
	if (evo_sim_reset(e->sim, (int)c.episode, c.layout_seed, c.seed, err))
		return -1;
	e->episode = c.episode;
	e->layout_seed = c.layout_seed;
	e->seed = c.seed;
	e->reset_at = t;
	e->tick = 0;
	e->active = 1;
	return send_sensors(sv, e, c.env, 0.0, 0, err);
}

static int on_command(server *sv, const evo_link_msg *m, evo_err *err)
{
	evo_wire_command c;
	char why[256];
	evo_wire_reason r;
	if (!take_command(sv, m, &c))
		return 0;
	served_env *e = &sv->env[c.env];
	if (c.n != sv->hello.n_actuators) {
		snprintf(why, sizeof why, "%u values; the hello says %u", c.n,
			 sv->hello.n_actuators);
		drop(sv, EVO_WIRE_COUNTS, "command_t", why);
		return 0;
	}
	/* the command answered last, again: its answer was lost (also the
	 * one that ended the episode, whose answer said done) */
	if (e->last_len > 0 && c.episode == e->episode && c.tick == e->tick - 1)
		return resend(sv, e, err);
	if (!e->active || c.episode != e->episode || c.tick != e->tick) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; this environment is at "
			 "tick %lld of episode %lld%s",
			 (long long)c.tick, (long long)c.episode,
			 (long long)e->tick, (long long)e->episode,
			 e->active ? "" : " (ended)");
		drop(sv,
		     c.episode > e->episode ||
			     (c.episode == e->episode && c.tick > e->tick)
			 ? EVO_WIRE_AHEAD
			 : EVO_WIRE_STALE,
		     "command_t", why);
		return 0;
	}
	r = evo_wire_check_values(c.value, c.n, NULL, why, sizeof why);
	if (r) {
		drop(sv, r, "command_t", why);
		return 0;
	}
	int done = evo_sim_act(e->sim, c.value, err);
	if (done < 0)
		return -1;
	e->tick++;
	if (done)
		e->active = 0;
	return send_sensors(sv, e, c.env, evo_sim_episode_reward(e->sim), done,
			    err);
}

static int serve(server *sv, evo_err *err)
{
	if (publish_hello(sv, err))
		return -1;
	evo_link *links[2] = {sv->link, sv->data};
	int n_links = sv->data == sv->link ? 1 : 2;
	while (!stop_requested) {
		evo_link_msg m;
		int which;
		int got = evo_link_next_any(links, n_links, 100, &which, &m, err);
		if (got < 0)
			return -1;
		if (!got)
			continue;
		int rc = 0;
		int data = links[which] == sv->data;
		if (data && strcmp(m.channel, sv->ch_command) == 0)
			rc = on_command(sv, &m, err);
		else if (data && strcmp(m.channel, sv->ch_control) == 0)
			rc = on_control(sv, &m, err);
		else if (which == 0 && strcmp(m.channel, "EVO_WHO") == 0)
			rc = publish_hello(sv, err);
		if (rc)
			return -1;
	}
	return 0;
}

/* ---- a robot: free running ---------------------------------------------- */

/* A stand-in robot's episode, and what it counts. */
typedef struct robot {
	double period, timeout; /* seconds */
	int active;		/* in an episode: ticking and sending */
	int64_t episode, tick;	/* the tick whose sensors went out last */
	double started_at;	/* the episode's RESET (monotonic) */
	double commanded_at;	/* the last command taken, or started_at */
	int commanded;		/* a command came in this episode */
	int neutral;		/* every actuator at 0.5 for want of commands */
	int stepped, ended;	/* this tick: the world stepped; it ended */
	int restart;		/* a RESET or STOP broke off the period */
	double cmd[EVO_MAX_ACTUATORS]; /* what the actuators do (botdesc) */
	unsigned long ticks, in_time, held, neutral_ticks, late, overruns;
	long long limit; /* TICKLIM: the episode's ticks at most, 0 none */
} robot;

static void robot_neutral(server *sv, robot *rb)
{
	for (unsigned j = 0; j < sv->hello.n_actuators; j++)
		rb->cmd[j] = 0.5;
}

/* The world steps once with the commands in force. */
static int robot_step(server *sv, robot *rb, evo_err *err)
{
	int done = evo_sim_act(sv->env[0].sim, rb->cmd, err);
	if (done < 0)
		return -1;
	rb->stepped = 1;
	rb->ended = done;
	return 0;
}

/* RESET: a new episode, now, from evo's seeds; except a RESET of the
 * episode running, before any command of it and within a second of its
 * start, which is evo sending its RESET again (docs/remote.md). STOP:
 * every actuator neutral, and nothing more until a RESET. */
static int robot_control(server *sv, robot *rb, const evo_link_msg *m,
			 evo_err *err)
{
	evo_wire_control c;
	char why[256];
	if (!take_control(sv, m, &c))
		return 0;
	double t = mono_now();
	if (c.op == EVO_CONTROL_STOP) {
		if (!rb->active)
			return 0;
		rb->active = 0;
		rb->restart = 1;
		robot_neutral(sv, rb);
		printf("evo serve: robot %s: evo stopped episode %lld at tick "
		       "%lld: every actuator neutral; waiting for a RESET\n",
		       sv->hello.name, (long long)rb->episode,
		       (long long)rb->tick);
		fflush(stdout);
		return 0;
	}
	if (c.episode < 1 || c.episode > INT_MAX) {
		snprintf(why, sizeof why, "episode %lld", (long long)c.episode);
		drop(sv, EVO_WIRE_VALUE, "control_t", why);
		return 0;
	}
	if (rb->active && c.episode == rb->episode && !rb->commanded &&
	    t - rb->started_at < 1.0)
		return 0;
	if (evo_sim_reset(sv->env[0].sim, (int)c.episode, c.layout_seed,
			  c.seed, err))
		return -1;
	rb->active = 1;
	rb->restart = 1;
	rb->episode = c.episode;
	rb->tick = 0;
	rb->started_at = rb->commanded_at = t;
	rb->commanded = 0;
	rb->neutral = 0;
	robot_neutral(sv, rb);
	printf("evo serve: robot %s: episode %lld starts\n", sv->hello.name,
	       (long long)c.episode);
	fflush(stdout);
	return 0;
}

/* A command_t: taken and acted on when it is this tick's and comes
 * within its period; one for an earlier tick came late, and is dropped. */
static int robot_command(server *sv, robot *rb, const evo_link_msg *m,
			 evo_err *err)
{
	evo_wire_command c;
	char why[256];
	evo_wire_reason r;
	if (!take_command(sv, m, &c))
		return 0;
	if (c.n != sv->hello.n_actuators) {
		snprintf(why, sizeof why, "%u values; the hello says %u", c.n,
			 sv->hello.n_actuators);
		drop(sv, EVO_WIRE_COUNTS, "command_t", why);
		return 0;
	}
	if (rb->active && c.episode == rb->episode && c.tick < rb->tick) {
		if (rb->late++ == 0)
			printf("evo serve: robot %s: the command of tick %lld "
			       "came during tick %lld, after its period; "
			       "later ones are counted\n",
			       sv->hello.name, (long long)c.tick,
			       (long long)rb->tick);
		return 0;
	}
	if (!rb->active || c.episode != rb->episode || c.tick != rb->tick ||
	    rb->stepped) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; the robot is at tick %lld "
			 "of episode %lld%s",
			 (long long)c.tick, (long long)c.episode,
			 (long long)rb->tick, (long long)rb->episode,
			 rb->active ? "" : " (stopped)");
		drop(sv,
		     rb->active && c.episode == rb->episode && c.tick > rb->tick
			 ? EVO_WIRE_AHEAD
			 : EVO_WIRE_STALE,
		     "command_t", why);
		return 0;
	}
	r = evo_wire_check_values(c.value, c.n, NULL, why, sizeof why);
	if (r) {
		drop(sv, r, "command_t", why);
		return 0;
	}
	double t = mono_now();
	if (rb->neutral)
		printf("evo serve: robot %s: commands again at tick %lld, "
		       "after %.2f s\n",
		       sv->hello.name, (long long)rb->tick,
		       t - rb->commanded_at);
	rb->neutral = 0;
	rb->commanded = 1;
	rb->commanded_at = t;
	rb->in_time++;
	memcpy(rb->cmd, c.value, c.n * sizeof c.value[0]);
	return robot_step(sv, rb, err);
}

/* The next message on the URL or the episodes' URL, within ms, acted on:
 * 0, or -1 with err set. */
static int robot_message(server *sv, robot *rb, int ms, evo_err *err)
{
	evo_link *links[2] = {sv->link, sv->data};
	int which;
	evo_link_msg m;
	int got = evo_link_next_any(links, sv->data == sv->link ? 1 : 2, ms,
				    &which, &m, err);
	if (got <= 0)
		return got;
	int data = links[which] == sv->data;
	if (data && strcmp(m.channel, sv->ch_command) == 0)
		return robot_command(sv, rb, &m, err);
	if (data && strcmp(m.channel, sv->ch_control) == 0)
		return robot_control(sv, rb, &m, err);
	if (which == 0 && strcmp(m.channel, "EVO_WHO") == 0)
		return publish_hello(sv, err);
	return 0;
}

/* No command of this tick within its period: the robot holds the last
 * commands, or goes neutral once none has come for its timeout. */
static int robot_no_command(server *sv, robot *rb, evo_err *err)
{
	double quiet = mono_now() - rb->commanded_at;
	if (quiet >= rb->timeout) {
		if (!rb->neutral) {
			printf("evo serve: robot %s: no command for %.2f s, "
			       "at tick %lld: every actuator neutral\n",
			       sv->hello.name, quiet, (long long)rb->tick);
			fflush(stdout);
			robot_neutral(sv, rb);
			rb->neutral = 1;
		}
		rb->neutral_ticks++;
	} else {
		if (rb->held++ == 0)
			printf("evo serve: robot %s: no command for tick "
			       "%lld within its period: the commands before "
			       "hold; later ones are counted\n",
			       sv->hello.name, (long long)rb->tick);
	}
	return robot_step(sv, rb, err);
}

/* One period: the sensors of this tick out at its start, then its command
 * awaited until its end (the world steps as soon as it comes), the world
 * stepped with the commands in force if it did not. */
static int robot_tick(server *sv, robot *rb, double start, evo_err *err)
{
	served_env *e = &sv->env[0];
	e->episode = rb->episode;
	e->tick = rb->tick;
	if (send_sensors(sv, e, 0, evo_sim_episode_reward(e->sim), 0, err))
		return -1;
	rb->stepped = rb->ended = rb->restart = 0;
	double deadline = start + rb->period;
	for (;;) {
		if (stop_requested || rb->restart)
			return 0;
		double left = deadline - mono_now();
		if (left <= 0)
			break;
		int ms = (int)(left * 1e3) + 1;
		if (robot_message(sv, rb, ms < 100 ? ms : 100, err))
			return -1;
	}
	if (!rb->stepped && robot_no_command(sv, rb, err))
		return -1;
	rb->ticks++;
	rb->tick++;
	/* a simulated episode lasts TICKLIM ticks, as DEMOSIM's: the
	 * scene's timeout control ends it one check later */
	if (rb->limit > 0 && rb->tick >= rb->limit)
		rb->ended = 1;
	if (rb->ended) {
		/* the world ended the episode: its last sensors say so */
		e->tick = rb->tick;
		if (send_sensors(sv, e, 0, evo_sim_episode_reward(e->sim), 1,
				 err))
			return -1;
		rb->active = 0;
		robot_neutral(sv, rb);
		printf("evo serve: robot %s: episode %lld ended at tick %lld: "
		       "every actuator neutral; waiting for a RESET\n",
		       sv->hello.name, (long long)rb->episode,
		       (long long)rb->tick);
		fflush(stdout);
	}
	return 0;
}

static int serve_robot(server *sv, robot *rb, evo_err *err)
{
	if (publish_hello(sv, err))
		return -1;
	double next = 0;
	while (!stop_requested) {
		if (!rb->active) {
			rb->restart = 0;
			if (robot_message(sv, rb, 100, err))
				return -1;
			next = mono_now();
			continue;
		}
		/* a period that starts late (the last one overran) starts
		 * now, and the schedule goes on from there */
		double t = mono_now();
		if (t > next + rb->period) {
			if (rb->tick > 0)
				rb->overruns++;
			next = t;
		}
		double start = next;
		if (robot_tick(sv, rb, start, err))
			return -1;
		next = rb->restart ? mono_now() : start + rb->period;
	}
	return 0;
}

static void robot_report(const server *sv, const robot *rb)
{
	printf("evo serve: robot %s: %lu ticks: %lu commanded in time, %lu "
	       "held the commands before, %lu neutral; %lu commands came "
	       "late; %lu periods overran\n",
	       sv->hello.name, rb->ticks, rb->in_time, rb->held,
	       rb->neutral_ticks, rb->late, rb->overruns);
}

/* The URL of a server's episodes: udpm://GROUP:PORT?OPTS on PORT + 1 +
 * (a hash of its name) % 2000, so that each server's traffic reaches
 * only evo and itself, not every other server on the URL (LCM over UDP
 * multicast hands every message on a port to every process listening on
 * it). Another kind of URL is used as it is. */
static void data_url_for(const char *url, const char *name, char *out,
			 size_t cap)
{
	const char *colon = strncmp(url, "udpm://", 7) == 0
				? strchr(url + 7, ':')
				: NULL;
	char *end;
	long port = colon ? strtol(colon + 1, &end, 10) : -1;
	if (!colon || end == colon + 1 || port < 1 || port > 65535) {
		snprintf(out, cap, "%s", url);
		return;
	}
	uint32_t h = 2166136261u;
	for (const char *p = name; *p; p++)
		h = (h ^ (unsigned char)*p) * 16777619u;
	long own = port + 1 + (long)(h % 2000);
	if (own > 65535)
		own -= 4000;
	snprintf(out, cap, "%.*s:%ld%s", (int)(colon - url), url, own, end);
}

/* A session number no earlier run of this name is likely to have had. */
static int64_t new_session(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	evo_rng r = evo_rng_for((uint64_t)ts.tv_sec, (uint64_t)ts.tv_nsec,
				(uint64_t)getpid(), 0);
	return (int64_t)(evo_rng_next(&r) >> 1);
}

int evo_serve_main(int argc, char **argv)
{
	const char *task_path = NULL, *name = NULL, *url = NULL,
		   *data_url = NULL, *key_file = NULL;
	long envs = 1;
	int as_robot = 0, envs_set = 0;
	double tick_ms = 1000.0 / 30, timeout = 0.5;
	const char *robot_opt = NULL, *can_url = NULL, *lcm_opt = NULL;
	for (int i = 2; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (strcmp(a, "--robot") == 0) {
			as_robot = 1;
		} else if (strcmp(a, "--can") == 0 && v) {
			can_url = v;
			as_robot = 1;
			i++;
		} else if ((strcmp(a, "--tick-ms") == 0 ||
			    strcmp(a, "--timeout") == 0) &&
			   v) {
			int is_tick = strcmp(a, "--tick-ms") == 0;
			double max = is_tick ? 60000 : 3600;
			char *end;
			double x = strtod(v, &end);
			if (*end || !(x > 0 && x <= max)) {
				fprintf(stderr,
					"evo serve: %s expects %s, more than 0 "
					"and at most %g, found '%s'\n",
					a, is_tick ? "milliseconds" : "seconds",
					max, v);
				return 2;
			}
			if (is_tick)
				tick_ms = x;
			else
				timeout = x;
			robot_opt = a;
			i++;
		} else if (strcmp(a, "--name") == 0 && v) {
			name = v;
			i++;
			lcm_opt = a;
		} else if (strcmp(a, "--url") == 0 && v) {
			url = v;
			i++;
			lcm_opt = a;
		} else if (strcmp(a, "--data-url") == 0 && v) {
			data_url = v;
			i++;
			lcm_opt = a;
		} else if (strcmp(a, "--key-file") == 0 && v) {
			key_file = v;
			i++;
			lcm_opt = a;
		} else if (strcmp(a, "--environments") == 0 && v) {
			char *end;
			errno = 0;
			envs = strtol(v, &end, 10);
			if (*end || errno || envs < 1 ||
			    envs > EVO_REMOTE_SERVE_MAX_ENVS) {
				fprintf(stderr,
					"evo serve: --environments expects a "
					"whole number 1..%d, found '%s'\n",
					EVO_REMOTE_SERVE_MAX_ENVS, v);
				return 2;
			}
			envs_set = 1;
			lcm_opt = a;
			i++;
		} else if (a[0] == '-' || task_path) {
			fprintf(stderr, "evo serve: unexpected argument '%s'\n",
				a);
			evo_serve_usage(stderr);
			return 2;
		} else {
			task_path = a;
		}
	}
	if (!task_path) {
		evo_serve_usage(stderr);
		return 2;
	}
	if (robot_opt && !as_robot) {
		fprintf(stderr, "evo serve: %s is for a robot (--robot)\n",
			robot_opt);
		return 2;
	}
	if (as_robot && envs_set && envs != 1) {
		fprintf(stderr,
			"evo serve: a robot runs one environment; --robot "
			"takes no --environments %ld\n",
			envs);
		return 2;
	}
	if (can_url && lcm_opt) {
		fprintf(stderr,
			"evo serve: %s is for LCM; over CAN (--can) a robot is "
			"its bus, with no name, URL or environments of its own\n",
			lcm_opt);
		return 2;
	}
	if (can_url && tick_ms > 6553.5) {
		fprintf(stderr,
			"evo serve: --tick-ms over CAN is at most 6553.5 (a "
			"BODY frame says the period in 0.1 ms, in 16 bits)\n");
		return 2;
	}
	long tick_us = lround(tick_ms * 1000);
	if (as_robot && tick_us < 1)
		tick_us = 1;
	char own[EVO_REMOTE_NAME_MAX];
	if (!name) {
		snprintf(own, sizeof own, "evo-serve-%ld", (long)getpid());
		name = own;
	}
	if (!evo_wire_name_ok(name)) {
		fprintf(stderr,
			"evo serve: --name '%s': a remote's name is 1..63 "
			"letters, digits, '_' or '-'\n",
			name);
		return 2;
	}
	/* a server's lines go to a log as they happen, not when it ends */
	setvbuf(stdout, NULL, _IOLBF, 0);
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	evo_lua_watch_stop(&stop_requested);

	evo_err err = {{0}};
	evo_task task;
	if (evo_task_load(task_path, &task, &err)) {
		fprintf(stderr, "%s\n", err.msg);
		return 1;
	}
	if (can_url) {
		evo_serve_can_def def = {
		    .task = &task,
		    .task_path = task_path,
		    .url = can_url,
		    .tick_ms = tick_ms,
		    .timeout = timeout,
		    .stop = &stop_requested,
		};
		int crc = evo_serve_can(&def);
		evo_task_free(&task);
		return crc;
	}
	if (!url)
		url = evo_simbatch_get(task.sb, "LCMURL");
	server sv;
	memset(&sv, 0, sizeof sv);
	int rc = 1;
	/* the task's remote keys, for its LCMKEYFILE (and their checks) */
	evo_remote_opts ro;
	if (evo_remote_opts_from_task(task.sb, task_path,
				      as_robot ? EVO_REMOTE_ROBOT
					       : EVO_REMOTE_SIMULATOR,
				      &ro, &err))
		goto out;
	if (key_file) {
		char why[600];
		if (evo_wire_key_read(key_file, &ro.key, why, sizeof why)) {
			evo_fail(&err, "evo serve: --key-file: %s", why);
			goto out;
		}
	}
	sv.env = calloc((size_t)envs, sizeof *sv.env);
	if (!sv.env) {
		fprintf(stderr, "evo serve: out of memory\n");
		goto out;
	}
	for (long i = 0; i < envs; i++) {
		sv.env[i].sim = evo_sim_create(task.mind, task.sb, task_path,
					       &err);
		if (!sv.env[i].sim)
			goto out;
	}
	const evo_botdesc *bd = task.mind->botdesc;
	evo_wire_hello *h = &sv.hello;
	h->protocol = EVO_WIRE_PROTOCOL;
	snprintf(h->name, sizeof h->name, "%s", name);
	h->session = new_session();
	h->kind = as_robot ? EVO_REMOTE_ROBOT : EVO_REMOTE_SIMULATOR;
	h->environments = (int32_t)envs;
	h->tick_us = as_robot ? (int32_t)tick_us : 0;
	h->n_sensors = bd->n_sensors;
	h->n_actuators = bd->n_actuators;
	for (unsigned i = 0; i < bd->n_sensors; i++)
		snprintf(h->sensor[i], EVO_NAME_MAX, "%s", bd->sensor[i].name);
	for (unsigned i = 0; i < bd->n_actuators; i++)
		snprintf(h->actuator[i], EVO_NAME_MAX, "%s",
			 bd->actuator[i].name);
	snprintf(sv.ch_control, sizeof sv.ch_control, "EVO_%s_CONTROL", name);
	snprintf(sv.ch_command, sizeof sv.ch_command, "EVO_%s_COMMAND", name);
	snprintf(sv.ch_sensors, sizeof sv.ch_sensors, "EVO_%s_SENSORS", name);
	sv.link = evo_link_open(url, &err);
	if (!sv.link || evo_link_subscribe(sv.link, "EVO_WHO", &err))
		goto out;
	if (ro.key.len)
		evo_link_set_key(sv.link, &ro.key, "evo serve");
	if (!data_url)
		data_url_for(evo_link_url(sv.link), name, h->url, sizeof h->url);
	else if (strcmp(data_url, "same") != 0)
		snprintf(h->url, sizeof h->url, "%s", data_url);
	if (h->url[0] && strcmp(h->url, evo_link_url(sv.link)) != 0) {
		sv.data = evo_link_open(h->url, &err);
		if (!sv.data)
			goto out;
		if (ro.key.len)
			evo_link_set_key(sv.data, &ro.key, "evo serve");
	} else {
		h->url[0] = 0;
		sv.data = sv.link;
	}
	if (evo_link_subscribe(sv.data, sv.ch_control, &err) ||
	    evo_link_subscribe(sv.data, sv.ch_command, &err))
		goto out;
	if (as_robot) {
		printf("evo serve: %s serves %s on %s as a robot (its episodes "
		       "on %s), a tick every %.3f ms, neutral after %.3g s "
		       "without a command\n",
		       name, task_path, evo_link_url(sv.link),
		       evo_link_url(sv.data), tick_us * 1e-3, timeout);
		robot rb;
		memset(&rb, 0, sizeof rb);
		rb.period = tick_us * 1e-6;
		rb.timeout = timeout;
		const char *tl = evo_simbatch_get(task.sb, "TICKLIM");
		rb.limit = tl ? strtoll(tl, NULL, 10) : 0;
		if (serve_robot(&sv, &rb, &err) == 0)
			rc = 0;
		robot_report(&sv, &rb);
	} else {
		printf("evo serve: %s serves %s on %s (%ld environment%s; its "
		       "episodes on %s)\n",
		       name, task_path, evo_link_url(sv.link), envs,
		       envs == 1 ? "" : "s", evo_link_url(sv.data));
		fflush(stdout);
		if (serve(&sv, &err) == 0)
			rc = 0;
	}
out:
	if (rc && err.msg[0])
		fprintf(stderr, "%s\n", err.msg);
	unsigned long total = 0;
	for (int i = 1; i < EVO_WIRE_N_REASONS; i++)
		total += sv.dropped[i];
	if (total) {
		fprintf(stderr, "evo serve: dropped %lu message%s (", total,
			total == 1 ? "" : "s");
		const char *sep = "";
		for (int i = 1; i < EVO_WIRE_N_REASONS; i++)
			if (sv.dropped[i]) {
				fprintf(stderr, "%s%lu %s", sep, sv.dropped[i],
					evo_wire_reason_name((evo_wire_reason)i));
				sep = ", ";
			}
		fprintf(stderr, ")\n");
	}
	if (sv.link)
		evo_link_report(sv.link);
	if (sv.data && sv.data != sv.link) {
		evo_link_report(sv.data);
		evo_link_close(sv.data);
	}
	evo_link_close(sv.link);
	memset(&ro.key, 0, sizeof ro.key);
	for (long i = 0; sv.env && i < envs; i++)
		evo_sim_destroy(sv.env[i].sim);
	free(sv.env);
	evo_task_free(&task);
	return rc;
}
