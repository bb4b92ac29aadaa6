/* `evo serve TASK --can URL` (cmd/serve_can.h, docs/can.md): the task's
 * 2D world stands in for a robot's body on a CAN bus, in the frames of
 * docs/wire.md. Its rules are those of `evo serve --robot` over LCM
 * (serve.c): real time, one tick a period whether commands come or not;
 * each period the sensor frames and a TICK go out at its start, and the
 * world steps as soon as that tick's command (actuator frames and a
 * TICKED) comes, or at the period's end with the commands before, or,
 * once none has come for the timeout, with every actuator neutral. A RESET
 * starts an episode from its seeds, so that a DEMOREMOTE run against it
 * gives the trace DEMOSIM gives. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/serve_can.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "remote/can.h"
#include "remote/can_robot.h"
#include "tasksim/tasksim.h"

typedef struct body {
	const evo_serve_can_def *def;
	evo_can *can;
	const char *name; /* the URL, in messages */
	evo_sim *sim;
	evo_can_rx rx;
	evo_can_body_info info;
	unsigned ns, na;
	double period, timeout; /* seconds */
	int active;		/* in an episode: ticking and sending */
	uint32_t episode;
	int64_t tick;	     /* the tick whose sensors went out last */
	double started_at;   /* the episode's RESET (monotonic) */
	double commanded_at; /* the last command taken, or started_at */
	int commanded;	     /* a command came in this episode */
	int neutral;	     /* every actuator at 0.5 for want of commands */
	int stepped, ended;  /* this tick: the world stepped; it ended */
	int restart;	     /* a RESET or STOP broke off the period */
	int full_next;	     /* the next tick sends every sensor frame */
	int told_hello;	     /* a HELLO that does not fit was said */
	evo_q16 sent[EVO_CAN_MAX_SENSORS]; /* the values evo was sent */
	double cmd[EVO_CAN_MAX_ACTUATORS]; /* what the actuators do */
	unsigned long ticks, in_time, held, neutral_ticks, late, overruns;
	unsigned long dropped[EVO_CAN_ROBOT_BAD_COUNT];
	long long limit; /* TICKLIM: the episode's ticks at most, 0 none */
} body;

static double mono_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int stopping(const body *b)
{
	return b->def->stop && *b->def->stop;
}

static void drop(body *b, evo_can_robot_bad why, const evo_can_frame *f,
		 const char *what)
{
	if (b->dropped[why]++ == 0)
		fprintf(stderr,
			"evo serve: dropped a frame (%s: id %#05x, %u bytes: "
			"%s); later drops are counted and reported at the "
			"end\n",
			evo_can_robot_bad_name(why), (unsigned)f->id,
			(unsigned)f->len, what);
}

static int put_frame(body *b, const evo_can_frame *f, evo_err *err)
{
	return evo_can_send(b->can, f, err);
}

static int send_body(body *b, evo_err *err)
{
	evo_can_frame f;
	evo_can_body_encode(&b->info, &f);
	return put_frame(b, &f, err);
}

static void go_neutral(body *b)
{
	for (unsigned j = 0; j < b->na; j++)
		b->cmd[j] = 0.5;
}

/* The world steps once with the commands in force. */
static int step(body *b, evo_err *err)
{
	int done = evo_sim_act(b->sim, b->cmd, err);
	if (done < 0)
		return -1;
	b->stepped = 1;
	b->ended = done;
	return 0;
}

/* A HELLO: the BODY in answer. A mind of other counts is said once; evo
 * refuses this body then, and says why. */
static int on_hello(body *b, evo_err *err)
{
	if ((b->rx.hello.sensors != b->ns || b->rx.hello.actuators != b->na ||
	     b->rx.hello.version != EVO_WIRE_VERSION) &&
	    !b->told_hello) {
		printf("evo serve: robot %s: a mind of %u sensors and %u "
		       "actuators (wire version %u) says HELLO; this body has "
		       "%u and %u (version %u)\n",
		       b->name, b->rx.hello.sensors, b->rx.hello.actuators,
		       b->rx.hello.version, b->ns, b->na, EVO_WIRE_VERSION);
		b->told_hello = 1;
	}
	return send_body(b, err);
}

/* RESET: a new episode, now, from evo's seeds; except a RESET of the
 * episode running, before any command of it and within a second of its
 * start, which is evo sending its RESET again (as over LCM). */
static int on_reset(body *b, evo_err *err)
{
	double t = mono_now();
	uint32_t e = b->rx.episode;
	if (b->active && e == b->episode && !b->commanded &&
	    t - b->started_at < 1.0)
		return 0;
	if (e < 1 || e > (uint32_t)INT32_MAX) {
		evo_can_frame f = {EVO_WIRE_RESET, 8, {0}};
		drop(b, EVO_CAN_ROBOT_BAD_VALUE, &f, "episode 0 or past 2^31");
		return 0;
	}
	if (evo_sim_reset(b->sim, (int)e, b->rx.layout_seed, b->rx.seed, err))
		return -1;
	b->active = 1;
	b->restart = 1;
	b->episode = e;
	b->tick = 0;
	b->started_at = b->commanded_at = t;
	b->commanded = 0;
	b->neutral = 0;
	b->full_next = 1;
	go_neutral(b);
	printf("evo serve: robot %s: episode %u starts\n", b->name, e);
	return 0;
}

static void on_stop(body *b)
{
	if (!b->active || b->rx.episode != b->episode)
		return;
	b->active = 0;
	b->restart = 1;
	go_neutral(b);
	printf("evo serve: robot %s: evo stopped episode %u at tick %lld: "
	       "every actuator neutral; waiting for a RESET\n",
	       b->name, b->episode, (long long)b->tick);
}

/* A TICKED: this tick's command, taken and acted on when it is whole and
 * comes within the period; one for an earlier tick came late. */
static int on_ticked(body *b, const evo_can_frame *f, evo_err *err)
{
	char what[160];
	if (!b->rx.complete) {
		snprintf(what, sizeof what,
			 "the command of tick %lu lacks actuator frames (mask "
			 "%#llx)",
			 (unsigned long)b->rx.tick,
			 (unsigned long long)b->rx.missing_frames);
		drop(b, EVO_CAN_ROBOT_BAD_INCOMPLETE, f, what);
		return 0;
	}
	int64_t tick = b->rx.tick;
	if (b->active && tick < b->tick) {
		if (b->late++ == 0)
			printf("evo serve: robot %s: the command of tick %lld "
			       "came during tick %lld, after its period; "
			       "later ones are counted\n",
			       b->name, (long long)tick, (long long)b->tick);
		return 0;
	}
	if (!b->active || tick != b->tick || b->stepped) {
		snprintf(what, sizeof what,
			 "the command of tick %lld; the robot is at tick %lld "
			 "of episode %u%s",
			 (long long)tick, (long long)b->tick, b->episode,
			 b->active ? "" : " (stopped)");
		drop(b, EVO_CAN_ROBOT_BAD_STALE, f, what);
		return 0;
	}
	/* INCOMPLETE: the mind did not step (a sensor frame was lost);
	 * the commands before hold until the period ends */
	if (b->rx.flags & EVO_WIRE_F_INCOMPLETE)
		return 0;
	double t = mono_now();
	if (b->neutral)
		printf("evo serve: robot %s: commands again at tick %lld, "
		       "after %.2f s\n",
		       b->name, (long long)b->tick, t - b->commanded_at);
	b->neutral = 0;
	b->commanded = 1;
	b->commanded_at = t;
	b->in_time++;
	b->full_next = 0;
	for (unsigned j = 0; j < b->na; j++)
		b->cmd[j] = evo_q16_to_double(b->rx.values[j]);
	return step(b, err);
}

/* The next frame within ms, acted on: 0, or -1 with err set. */
static int next_frame(body *b, int ms, evo_err *err)
{
	evo_can_frame f;
	int got = evo_can_recv(b->can, ms, &f, err);
	if (got <= 0)
		return got;
	switch (evo_can_rx_frame(&b->rx, &f)) {
	case EVO_CAN_EV_BAD:
		drop(b, b->rx.bad, &f,
		     b->rx.bad == EVO_CAN_ROBOT_BAD_ID
			 ? "not a frame a mind sends a robot's body"
		     : b->rx.bad == EVO_CAN_ROBOT_BAD_INCOMPLETE
			 ? "a RESET without the seed frames sent before it"
			 : "malformed");
		return 0;
	case EVO_CAN_EV_HELLO:
		return on_hello(b, err);
	case EVO_CAN_EV_RESET:
		return on_reset(b, err);
	case EVO_CAN_EV_STOP:
		on_stop(b);
		return 0;
	case EVO_CAN_EV_TICKED:
		return on_ticked(b, &f, err);
	default:
		return 0;
	}
}

/* The sensor frames of this tick and its TICK: every frame on the first
 * tick of an episode and after any tick not commanded in time (a frame
 * evo lacks is sent again), else only those whose values changed, with
 * their mask (docs/wire.md). The reward so far goes first. */
static int send_tick(body *b, evo_err *err)
{
	double v[EVO_CAN_MAX_SENSORS];
	evo_q16 q[EVO_CAN_MAX_SENSORS];
	evo_sim_sense(b->sim, v);
	for (unsigned i = 0; i < b->ns; i++)
		q[i] = evo_q16_from_sensor(v[i]);
	unsigned frames = evo_wire_frames(b->ns);
	int full = b->full_next || frames > 32;
	b->full_next = 1; /* until this tick's command comes in time */
	uint32_t mask = 0;
	evo_can_frame f = {EVO_WIRE_REWARD, 8, {0}};
	double reward = b->sim->scene->episode_reward;
	uint64_t bits;
	memcpy(&bits, &reward, sizeof bits);
	evo_wire_put_u32(f.data, (uint32_t)bits);
	evo_wire_put_u32(f.data + 4, (uint32_t)(bits >> 32));
	if (put_frame(b, &f, err))
		return -1;
	for (unsigned k = 0; k < frames; k++) {
		unsigned i = 2 * k;
		int changed = q[i] != b->sent[i] ||
			      (i + 1 < b->ns && q[i + 1] != b->sent[i + 1]);
		if (!full && !changed)
			continue;
		evo_wire_pack(EVO_WIRE_SENSOR, q, b->ns, k, &f);
		if (put_frame(b, &f, err))
			return -1;
		if (k < 32)
			mask |= (uint32_t)1 << k;
	}
	memcpy(b->sent, q, b->ns * sizeof *q);
	memset(&f, 0, sizeof f);
	f.id = EVO_WIRE_TICK;
	f.len = full ? 4 : 8;
	evo_wire_put_u32(f.data, (uint32_t)b->tick);
	evo_wire_put_u32(f.data + 4, mask);
	return put_frame(b, &f, err);
}

/* No command of this tick within its period: the commands before hold,
 * or every actuator goes neutral once none has come for the timeout. */
static int no_command(body *b, evo_err *err)
{
	double quiet = mono_now() - b->commanded_at;
	if (quiet >= b->timeout) {
		if (!b->neutral) {
			printf("evo serve: robot %s: no command for %.2f s, "
			       "at tick %lld: every actuator neutral\n",
			       b->name, quiet, (long long)b->tick);
			go_neutral(b);
			b->neutral = 1;
		}
		b->neutral_ticks++;
	} else if (b->held++ == 0) {
		printf("evo serve: robot %s: no command for tick %lld within "
		       "its period: the commands before hold; later ones are "
		       "counted\n",
		       b->name, (long long)b->tick);
	}
	return step(b, err);
}

/* One period: the sensors out at its start, its command awaited until
 * its end (the world steps as soon as it comes), the world stepped with
 * the commands in force if it did not. */
static int one_tick(body *b, double start, evo_err *err)
{
	if (send_tick(b, err))
		return -1;
	b->stepped = b->ended = b->restart = 0;
	double deadline = start + b->period;
	for (;;) {
		if (stopping(b) || b->restart)
			return 0;
		double left = deadline - mono_now();
		if (left <= 0)
			break;
		int ms = (int)(left * 1e3) + 1;
		if (next_frame(b, ms < 100 ? ms : 100, err))
			return -1;
	}
	if (!b->stepped && no_command(b, err))
		return -1;
	b->ticks++;
	b->tick++;
	/* a simulated episode lasts TICKLIM ticks, as DEMOSIM's and over
	 * LCM: the scene's timeout control ends it one check later */
	if (b->limit > 0 && b->tick >= b->limit)
		b->ended = 1;
	if (b->ended) {
		/* the world ended the episode: its reward, then DONE */
		evo_can_frame f = {EVO_WIRE_REWARD, 8, {0}};
		double reward = b->sim->scene->episode_reward;
		uint64_t bits;
		memcpy(&bits, &reward, sizeof bits);
		evo_wire_put_u32(f.data, (uint32_t)bits);
		evo_wire_put_u32(f.data + 4, (uint32_t)(bits >> 32));
		if (put_frame(b, &f, err))
			return -1;
		memset(&f, 0, sizeof f);
		f.id = EVO_WIRE_DONE;
		f.len = 4;
		evo_wire_put_u32(f.data, (uint32_t)b->tick);
		if (put_frame(b, &f, err))
			return -1;
		b->active = 0;
		go_neutral(b);
		printf("evo serve: robot %s: episode %u ended at tick %lld: "
		       "every actuator neutral; waiting for a RESET\n",
		       b->name, b->episode, (long long)b->tick);
	}
	return 0;
}

static int serve_body(body *b, evo_err *err)
{
	if (send_body(b, err))
		return -1;
	double next = 0;
	while (!stopping(b)) {
		if (!b->active) {
			b->restart = 0;
			if (next_frame(b, 100, err))
				return -1;
			next = mono_now();
			continue;
		}
		/* a period that starts late (the last one overran) starts
		 * now, and the schedule goes on from there */
		double t = mono_now();
		if (t > next + b->period) {
			if (b->tick > 0)
				b->overruns++;
			next = t;
		}
		double start = next;
		if (one_tick(b, start, err))
			return -1;
		next = b->restart ? mono_now() : start + b->period;
	}
	return 0;
}

static void report(const body *b)
{
	printf("evo serve: robot %s: %lu ticks: %lu commanded in time, %lu "
	       "held the commands before, %lu neutral; %lu commands came "
	       "late; %lu periods overran\n",
	       b->name, b->ticks, b->in_time, b->held, b->neutral_ticks,
	       b->late, b->overruns);
	unsigned long total = 0;
	for (int i = 0; i < EVO_CAN_ROBOT_BAD_COUNT; i++)
		total += b->dropped[i];
	const char *sep = "";
	if (total) {
		fprintf(stderr, "evo serve: dropped %lu frame%s (", total,
			total == 1 ? "" : "s");
		for (int i = 0; i < EVO_CAN_ROBOT_BAD_COUNT; i++)
			if (b->dropped[i]) {
				fprintf(stderr, "%s%lu %s", sep, b->dropped[i],
					evo_can_robot_bad_name(
					    (evo_can_robot_bad)i));
				sep = ", ";
			}
		fprintf(stderr, ")\n");
	}
	const unsigned long *bus = evo_can_dropped(b->can);
	total = 0;
	for (int i = 0; i < EVO_CAN_BAD_COUNT; i++)
		total += bus[i];
	if (total) {
		fprintf(stderr,
			"evo serve: dropped %lu piece%s of input that "
			"were no frames of evo's (",
			total, total == 1 ? "" : "s");
		sep = "";
		for (int i = 0; i < EVO_CAN_BAD_COUNT; i++)
			if (bus[i]) {
				fprintf(stderr, "%s%lu %s", sep, bus[i],
					evo_can_bad_name((evo_can_bad)i));
				sep = ", ";
			}
		fprintf(stderr, ")\n");
	}
	if (evo_can_unsent(b->can))
		fprintf(stderr,
			"evo serve: %lu frame%s not sent: the line took no "
			"more (no one was reading it)\n",
			evo_can_unsent(b->can),
			evo_can_unsent(b->can) == 1 ? "" : "s");
}

int evo_serve_can(const evo_serve_can_def *def)
{
	evo_err err = {{0}};
	const evo_botdesc *bd = def->task->mind->botdesc;
	if (bd->n_sensors > EVO_CAN_MAX_SENSORS ||
	    bd->n_actuators > EVO_CAN_MAX_ACTUATORS) {
		fprintf(stderr,
			"%s: %u sensors and %u actuators: over CAN a robot has "
			"at most %d and %d (docs/wire.md)\n",
			def->task_path, bd->n_sensors, bd->n_actuators,
			EVO_CAN_MAX_SENSORS, EVO_CAN_MAX_ACTUATORS);
		return 1;
	}
	static body b;
	memset(&b, 0, sizeof b);
	b.def = def;
	b.name = def->url;
	b.ns = bd->n_sensors;
	b.na = bd->n_actuators;
	long p = lround(def->tick_ms * 10);
	b.info.names_hash = evo_names_hash_of(bd, NULL);
	b.info.sensors = b.ns;
	b.info.actuators = b.na;
	b.info.period_100us = (unsigned)(p < 1 ? 1 : p);
	b.period = b.info.period_100us * 1e-4;
	b.timeout = def->timeout;
	const char *tl = evo_simbatch_get(def->task->sb, "TICKLIM");
	b.limit = tl ? strtoll(tl, NULL, 10) : 0;
	go_neutral(&b);
	evo_can_rx_init(&b.rx, 1, b.na);
	int rc = 1;
	b.sim = evo_sim_create(def->task->mind, def->task->sb, def->task_path,
			       &err);
	if (!b.sim)
		goto out;
	b.can = evo_can_open(def->url, &err);
	if (!b.can)
		goto out;
	printf("evo serve: serves %s as a robot's body on %s, a tick every "
	       "%.1f ms, neutral after %.3g s without a command\n",
	       def->task_path, def->url, b.period * 1e3, b.timeout);
	if (evo_can_pty_name(b.can))
		printf(
		    "evo serve: its slcan pseudo-terminal is %s%s%s: evo run "
		    "TASK --can slcan:%s\n",
		    evo_can_pty_name(b.can),
		    evo_can_pty_link(b.can) ? ", linked from " : "",
		    evo_can_pty_link(b.can) ? evo_can_pty_link(b.can) : "",
		    evo_can_pty_link(b.can) ? evo_can_pty_link(b.can)
					    : evo_can_pty_name(b.can));
	if (serve_body(&b, &err) == 0)
		rc = 0;
	report(&b);
out:
	if (rc && err.msg[0])
		fprintf(stderr, "%s\n", err.msg);
	evo_can_close(b.can);
	evo_sim_destroy(b.sim);
	return rc;
}
