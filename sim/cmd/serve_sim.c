/* `evo serve` of a simulator (cmd/serve_internal.h): each environment a
 * world of its own, stepped in lockstep with the commands that arrive for
 * it; a RESET or command repeated because its answer was lost is answered
 * again (docs/remote.md). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/serve_internal.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

/* Seconds after a RESET during which the same RESET again, once the
 * episode is past tick 0, is a late copy of it (docs/remote.md). */
#define LATE_RESET_S 2.0

static int on_control(server *sv, const evo_link_msg *m, evo_err *err)
{
	evo_wire_control c;
	char why[256];
	if (!evo_serve_take_control(sv, m, &c))
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
	double t = evo_clock_now();
	int same = e->episode > 0 && c.episode == e->episode &&
		   c.layout_seed == e->layout_seed && c.seed == e->seed;
	if (same && e->active && e->tick == 0)
		return evo_serve_resend(sv, e, err);
	/* the same RESET past tick 0, soon after it: a copy evo sent again
	 * while the first answer was on its way, come late; starting over
	 * would leave evo's next command ahead of the world */
	if (same && e->tick > 0 && t - e->reset_at < LATE_RESET_S) {
		snprintf(why, sizeof why,
			 "a late copy of the RESET of episode %lld, now at "
			 "tick %lld",
			 (long long)c.episode, (long long)e->tick);
		evo_serve_drop(sv, EVO_WIRE_STALE, "control_t", why);
		return 0;
	}
	if (c.episode < 1 || c.episode > INT_MAX) {
		snprintf(why, sizeof why, "episode %lld", (long long)c.episode);
		evo_serve_drop(sv, EVO_WIRE_VALUE, "control_t", why);
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
	return evo_serve_send_sensors(sv, e, c.env, 0.0, 0, err);
}

static int on_command(server *sv, const evo_link_msg *m, evo_err *err)
{
	evo_wire_command c;
	char why[256];
	evo_wire_reason r;
	if (!evo_serve_take_command(sv, m, &c))
		return 0;
	served_env *e = &sv->env[c.env];
	/* the command answered last, again: its answer was lost (also the
	 * one that ended the episode, whose answer said done) */
	if (e->last_len > 0 && c.episode == e->episode && c.tick == e->tick - 1)
		return evo_serve_resend(sv, e, err);
	if (!e->active || c.episode != e->episode || c.tick != e->tick) {
		evo_serve_drop_misplaced(
		    sv, &c, "this environment", e->tick, e->episode,
		    e->active ? "" : " (ended)",
		    c.episode > e->episode ||
			(c.episode == e->episode && c.tick > e->tick));
		return 0;
	}
	r = evo_wire_check_values(c.value, c.n, NULL, why, sizeof why);
	if (r) {
		evo_serve_drop(sv, r, "command_t", why);
		return 0;
	}
	int done = evo_sim_act(e->sim, c.value, err);
	if (done < 0)
		return -1;
	e->tick++;
	if (done)
		e->active = 0;
	return evo_serve_send_sensors(
	    sv, e, c.env, evo_sim_episode_reward(e->sim), done, err);
}

int evo_serve_lockstep(server *sv, evo_err *err)
{
	if (evo_serve_publish_hello(sv, err))
		return -1;
	while (!evo_cmd_stop_requested) {
		evo_link_msg m;
		int rc = 0;
		switch (evo_serve_next(sv, 100, &m, err)) {
		case -1:
			return -1;
		case SERVE_COMMAND:
			rc = on_command(sv, &m, err);
			break;
		case SERVE_CONTROL:
			rc = on_control(sv, &m, err);
			break;
		default:
			break;
		}
		if (rc)
			return -1;
	}
	return 0;
}
