/* `evo serve --robot` (cmd/serve_internal.h): the world stands in for a
 * robot: it runs in real time, one tick a period, whether commands come or
 * not; it holds the last commands through a tick whose command comes
 * late, and sets every actuator to neutral when none has come for its
 * timeout. A RESET starts an episode from evo's seeds, a STOP ends it. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/serve_internal.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

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
	if (!evo_serve_take_control(sv, m, &c))
		return 0;
	double t = evo_serve_now();
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
		evo_serve_drop(sv, EVO_WIRE_VALUE, "control_t", why);
		return 0;
	}
	if (rb->active && c.episode == rb->episode && !rb->commanded &&
	    t - rb->started_at < 1.0)
		return 0;
	if (evo_sim_reset(sv->env[0].sim, (int)c.episode, c.layout_seed, c.seed,
			  err))
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
	if (!evo_serve_take_command(sv, m, &c))
		return 0;
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
		evo_serve_drop(sv,
			       rb->active && c.episode == rb->episode &&
				       c.tick > rb->tick
				   ? EVO_WIRE_AHEAD
				   : EVO_WIRE_STALE,
			       "command_t", why);
		return 0;
	}
	r = evo_wire_check_values(c.value, c.n, NULL, why, sizeof why);
	if (r) {
		evo_serve_drop(sv, r, "command_t", why);
		return 0;
	}
	double t = evo_serve_now();
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
	evo_link_msg m;
	switch (evo_serve_next(sv, ms, &m, err)) {
	case -1:
		return -1;
	case SERVE_COMMAND:
		return robot_command(sv, rb, &m, err);
	case SERVE_CONTROL:
		return robot_control(sv, rb, &m, err);
	default:
		return 0;
	}
}

/* No command of this tick within its period: the robot holds the last
 * commands, or goes neutral once none has come for its timeout. */
static int robot_no_command(server *sv, robot *rb, evo_err *err)
{
	double quiet = evo_serve_now() - rb->commanded_at;
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
	if (evo_serve_send_sensors(sv, e, 0, evo_sim_episode_reward(e->sim), 0,
				   err))
		return -1;
	rb->stepped = rb->ended = rb->restart = 0;
	double deadline = start + rb->period;
	for (;;) {
		if (evo_cmd_stop_requested || rb->restart)
			return 0;
		double left = deadline - evo_serve_now();
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
		if (evo_serve_send_sensors(
			sv, e, 0, evo_sim_episode_reward(e->sim), 1, err))
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
	if (evo_serve_publish_hello(sv, err))
		return -1;
	double next = 0;
	while (!evo_cmd_stop_requested) {
		if (!rb->active) {
			rb->restart = 0;
			if (robot_message(sv, rb, 100, err))
				return -1;
			next = evo_serve_now();
			continue;
		}
		/* a period that starts late (the last one overran) starts
		 * now, and the schedule goes on from there */
		double t = evo_serve_now();
		if (t > next + rb->period) {
			if (rb->tick > 0)
				rb->overruns++;
			next = t;
		}
		double start = next;
		if (robot_tick(sv, rb, start, err))
			return -1;
		next = rb->restart ? evo_serve_now() : start + rb->period;
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

int evo_serve_robot(server *sv, double period, double timeout, long long limit,
		    evo_err *err)
{
	robot rb;
	memset(&rb, 0, sizeof rb);
	rb.period = period;
	rb.timeout = timeout;
	rb.limit = limit;
	int rc = serve_robot(sv, &rb, err);
	robot_report(sv, &rb);
	return rc;
}
