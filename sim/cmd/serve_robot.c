/* `evo serve --robot` (cmd/serve_internal.h): the world stands in for a
 * robot over LCM (cmd/standin.h keeps its schedule): each tick's sensors
 * go out as a sensors_t, a RESET starts an episode from evo's seeds, a
 * STOP ends it, and a command_t of this tick, in time, steps the world. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/serve_internal.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

#include "cmd/standin.h"

typedef struct robot {
	server *sv;
	evo_standin s;
} robot;

static int robot_control(robot *rb, const evo_link_msg *m, evo_err *err)
{
	server *sv = rb->sv;
	evo_wire_control c;
	char why[256];
	if (!evo_serve_take_control(sv, m, &c))
		return 0;
	if (c.op == EVO_CONTROL_STOP) {
		if (rb->s.active)
			evo_standin_stop(&rb->s);
		return 0;
	}
	if (c.episode < 1 || c.episode > INT_MAX) {
		snprintf(why, sizeof why, "episode %lld", (long long)c.episode);
		evo_serve_drop(sv, EVO_WIRE_VALUE, "control_t", why);
		return 0;
	}
	return evo_standin_reset(&rb->s, c.episode, c.layout_seed, c.seed,
				 err) < 0
		   ? -1
		   : 0;
}

/* A command_t: taken and acted on when it is this tick's and comes
 * within its period; one for an earlier tick came late, and is dropped. */
static int robot_command(robot *rb, const evo_link_msg *m, evo_err *err)
{
	server *sv = rb->sv;
	evo_standin *s = &rb->s;
	evo_wire_command c;
	char why[256];
	if (!evo_serve_take_command(sv, m, &c))
		return 0;
	if (s->active && c.episode == s->episode && c.tick < s->tick) {
		evo_standin_late(s, c.tick);
		return 0;
	}
	if (!s->active || c.episode != s->episode || c.tick != s->tick ||
	    s->stepped) {
		evo_serve_drop_misplaced(sv, &c, "the robot", s->tick,
					 s->episode,
					 s->active ? "" : " (stopped)",
					 s->active && c.episode == s->episode &&
					     c.tick > s->tick);
		return 0;
	}
	evo_wire_reason r =
	    evo_wire_check_values(c.value, c.n, NULL, why, sizeof why);
	if (r) {
		evo_serve_drop(sv, r, "command_t", why);
		return 0;
	}
	return evo_standin_command(s, c.value, err);
}

/* The next message on the URL or the episodes' URL, within ms, acted on:
 * 0, or -1 with err set. */
static int robot_message(void *ctx, int ms, evo_err *err)
{
	robot *rb = ctx;
	evo_link_msg m;
	switch (evo_serve_next(rb->sv, ms, &m, err)) {
	case -1:
		return -1;
	case SERVE_COMMAND:
		return robot_command(rb, &m, err);
	case SERVE_CONTROL:
		return robot_control(rb, &m, err);
	default:
		return 0;
	}
}

static int robot_hello(void *ctx, evo_err *err)
{
	robot *rb = ctx;
	return evo_serve_publish_hello(rb->sv, err);
}

/* This tick's sensors_t, or (done) the last of the episode. */
static int robot_sensors(robot *rb, int done, evo_err *err)
{
	served_env *e = &rb->sv->env[0];
	e->episode = rb->s.episode;
	e->tick = rb->s.tick;
	return evo_serve_send_sensors(
	    rb->sv, e, 0, evo_sim_episode_reward(e->sim), done, err);
}

static int robot_tick(void *ctx, evo_err *err)
{
	return robot_sensors(ctx, 0, err);
}

static int robot_end(void *ctx, evo_err *err)
{
	return robot_sensors(ctx, 1, err);
}

int evo_serve_robot(server *sv, double period, double timeout, long long limit,
		    evo_err *err)
{
	robot rb = {.sv = sv};
	rb.s = (evo_standin){
	    .name = sv->hello.name,
	    .sim = sv->env[0].sim,
	    .na = sv->hello.n_actuators,
	    .io = {&rb, robot_hello, robot_tick, robot_end, robot_message},
	    .stop = &evo_cmd_stop_requested,
	    .period = period,
	    .timeout = timeout,
	    .limit = limit,
	};
	int rc = evo_standin_run(&rb.s, err);
	evo_standin_report(&rb.s);
	return rc;
}
