/* evo — a robot's episodes (sim/remote/session.h, evo_robot_*): a robot
 * ticks at its own rate and sends the sensors of every tick; evo answers
 * each with that tick's commands and never makes it wait, and counts each
 * tick answered in time, late or missing. */
#define _POSIX_C_SOURCE 200809L
#include "remote/robot.h"
#include "remote/session_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int evo_robot_start(evo_remotes *s, evo_robot *rb, int64_t episode,
		    uint64_t layout_seed, uint64_t seed, evo_err *err)
{
	if (s->n < 1)
		return evo_fail(err, "evo: no robot to start");
	const evo_wire_hello *h = &s->r[0]->hello;
	if (h->kind != EVO_REMOTE_ROBOT)
		return evo_fail(err, "remote %s is a %s, not a robot", h->name,
				evo_session_kind_name(h->kind));
	if (h->tick_us <= 0)
		return evo_fail(err,
				"robot %s gives no tick period (tick_us %d); "
				"a robot says how often it ticks "
				"(docs/remote.md)",
				h->name, (int)h->tick_us);
	if (rb->set != s) {
		memset(rb, 0, sizeof *rb);
		rb->set = s;
	}
	rb->period = h->tick_us * 1e-6;
	rb->episode = episode;
	rb->tick = -1;
	rb->answered = 1;
	rb->done = 0;
	rb->reward = 0;
	if (evo_remotes_send_reset(s, 0, 0, episode, layout_seed, seed, err))
		return -1;
	s->r[0]->env[0].waiting = 0; /* evo_remotes_wait awaits nothing */
	rb->reset_at = s->r[0]->env[0].sent_at;
	return 0;
}

/* The first late and the first missing tick are said at once. */
static void tell_late(evo_robot *rb, const char *what)
{
	if (rb->late == 1)
		fprintf(stderr,
			"evo: robot %s: tick %lld %s; later late ticks are "
			"counted and reported at the end\n",
			rb->set->r[0]->hello.name, (long long)rb->tick, what);
}

/* A sensors_t of the robot: hold it when it is a newer tick of the
 * episode. 1 when held, 0 when dropped. */
static int take_robot_sensors(evo_robot *rb, const evo_link_msg *m)
{
	evo_remote *r = rb->set->r[0];
	evo_wire_sensors s;
	char why[256];
	if (!evo_session_admit_sensors(r, m, 1, &s))
		return 0;
	if (rb->tick >= 0 && s.episode == rb->episode && s.tick == rb->tick &&
	    !evo_session_same_sensors(&s, &r->env[0].sensors)) {
		rb->conflict = 1;
		return 0;
	}
	double t = evo_clock_now();
	r->heard_at = t;
	/* A tick the robot cannot have reached since the RESET went out is
	 * of an episode it ran before (a run that ended without a STOP used
	 * the same number), or not the robot's: at every tick of the
	 * episode, not only before its first (a tick far ahead, once held,
	 * would make every true tick after it stale). The robot's clock
	 * may run a little fast: 1% and a tick of slack. */
	int64_t reachable =
	    (int64_t)((t - rb->reset_at) / rb->period * 1.01) + 2;
	if (s.episode < rb->episode ||
	    (s.episode == rb->episode &&
	     (s.tick <= rb->tick || s.tick > reachable))) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; evo holds tick %lld of "
			 "episode %lld%s",
			 (long long)s.tick, (long long)s.episode,
			 (long long)rb->tick, (long long)rb->episode,
			 s.tick > reachable ? ", and the robot cannot have "
					      "reached it since evo's RESET"
					    : "");
		evo_session_dropped(r, EVO_WIRE_STALE, "sensors_t", why);
		return 0;
	}
	if (s.episode > rb->episode) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; evo runs episode %lld",
			 (long long)s.tick, (long long)s.episode,
			 (long long)rb->episode);
		evo_session_dropped(r, EVO_WIRE_AHEAD, "sensors_t", why);
		return 0;
	}
	/* A robot's bad value costs that tick only: the robot holds its
	 * commands, and the next tick comes anyway. */
	evo_wire_reason rc =
	    evo_wire_check_values(s.value, s.n, &s.reward, why, sizeof why);
	if (rc) {
		evo_session_name_bad_value(&r->hello, &s, why, sizeof why);
		char w2[300];
		snprintf(w2, sizeof w2, "tick %lld: %s", (long long)s.tick,
			 why);
		evo_session_dropped(r, rc, "sensors_t", w2);
		return 0;
	}
	double arrived =
	    m->recv_utime > 0 ? (double)m->recv_utime * 1e-6 : evo_clock_real();
	if (!rb->answered) {
		rb->late++;
		rb->unanswered++;
		tell_late(rb, "was not answered: a newer tick came first");
	} else if (rb->in_time_held && rb->answered_at > arrived) {
		/* answered after the robot's next tick had come: late, even
		 * when its own arrival looked recent (LCM stamps a message
		 * when its reader thread takes it where the kernel's stamp
		 * is missing) */
		rb->in_time--;
		rb->late++;
		tell_late(rb, "was answered after the next tick had come");
	}
	rb->in_time_held = 0;
	int64_t gap = s.tick - (rb->tick + 1);
	if (gap > 0) {
		if (rb->missing == 0)
			fprintf(stderr,
				"evo: robot %s: tick %lld came after tick "
				"%lld: %lld tick%s missing; later missing "
				"ticks are counted and reported at the end\n",
				r->hello.name, (long long)s.tick,
				(long long)rb->tick, (long long)gap,
				gap == 1 ? "" : "s");
		rb->missing += (unsigned long)gap;
	}
	r->env[0].sensors = s;
	r->env[0].tick = s.tick;
	rb->tick = s.tick;
	rb->reward = s.reward;
	rb->arrived = arrived;
	rb->answered = 0;
	if (s.done) {
		rb->done = 1;
		rb->answered = 1; /* nothing to answer */
	}
	return 1;
}

int evo_robot_next(evo_robot *rb, int timeout_ms, evo_err *err)
{
	evo_remotes *s = rb->set;
	evo_remote *r = s->r[0];
	if (rb->done)
		return 1;
	double until =
	    evo_clock_now() + (timeout_ms > 0 ? timeout_ms : 0) * 1e-3;
	int held = 0;
	for (;;) {
		if (evo_session_stopped(&s->opts, err))
			return -1;
		int ri;
		if (evo_session_restarted(s, &ri, err))
			return -1;
		if (rb->conflict)
			return evo_session_conflict(r, &r->env[0].sensors, err);
		double t = evo_clock_now();
		evo_remote_env *e = &r->env[0];
		if (rb->tick < 0 && evo_session_resend(r, e, t, err))
			return -1;
		if (t - r->heard_at >= s->opts.timeout &&
		    t - r->told_at >= s->opts.timeout) {
			fprintf(stderr,
				"evo: robot %s silent for %.1f s; waiting "
				"(Ctrl-C stops); a robot goes neutral on its "
				"own\n",
				r->hello.name, t - r->heard_at);
			r->told_at = t;
		}
		int wait_ms = evo_robot_wait_ms(held, until, t, SLICE_MS);
		if (wait_ms < 0)
			return 2;
		evo_link_msg m;
		int which;
		int got = evo_link_next_any(s->links, s->n_links, wait_ms,
					    &which, &m, err);
		if (got < 0)
			return -1;
		if (!got) {
			if (held)
				return rb->done ? 1 : 0;
			continue;
		}
		if (which == 0 && strcmp(m.channel, "EVO_HELLO") == 0) {
			evo_session_take_hello(s, &m);
		} else if (s->links[which] == r->link &&
			   strcmp(m.channel, r->ch_sensors) == 0 &&
			   take_robot_sensors(rb, &m)) {
			held = 1;
			if (rb->done)
				return 1;
		}
	}
}

int evo_robot_answer(evo_robot *rb, const double *commands, evo_err *err)
{
	evo_remote *r = rb->set->r[0];
	if (rb->tick < 0 || rb->answered)
		return 0;
	rb->answered = 1;
	rb->answered_at = evo_clock_real();
	char what[96];
	if (evo_robot_answered_late(rb->arrived, rb->answered_at, rb->period,
				    what, sizeof what)) {
		rb->late++;
		tell_late(rb, what);
	} else {
		rb->in_time++;
		rb->in_time_held = 1;
	}
	evo_wire_command c;
	evo_session_command(r, 0, rb->episode, rb->tick, commands, &c);
	unsigned char buf[EVO_WIRE_MAX_BYTES];
	int n = evo_wire_encode_command(&c, buf, sizeof buf);
	if (n < 0)
		return evo_fail(err, "evo: cannot encode a command_t");
	return evo_link_publish(r->link, r->ch_command, buf, (size_t)n, err);
}

double evo_robot_quiet(const evo_robot *rb)
{
	return evo_clock_now() - rb->set->r[0]->heard_at;
}

void evo_robot_report(const evo_robot *rb)
{
	printf("robot %s: %lu ticks: %lu answered in time, %lu late (%lu "
	       "unanswered), %lu missing\n",
	       rb->set->r[0]->hello.name, rb->in_time + rb->late + rb->missing,
	       rb->in_time, rb->late, rb->unanswered, rb->missing);
	fflush(stdout);
}
