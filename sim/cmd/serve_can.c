/* `evo serve TASK --can URL` (cmd/serve_can.h, docs/can.md): the task's
 * world, 2D or 3D, stands in for a robot's body on a CAN bus, in the frames of
 * docs/wire.md. Its rules are those of `evo serve --robot` over LCM
 * (cmd/standin.h keeps them for both): real time, one tick a period whether
 * commands come or not; each period the sensor frames and a TICK go out at its
 * start, and the world steps as soon as that tick's command (actuator frames
 * and a TICKED) comes, or at the period's end with the commands before, or,
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

#include "base/counts.h"
#include "cmd/standin.h"
#include "remote/can.h"
#include "remote/can_robot.h"
#include "tasksim/tasksim.h"

typedef struct body {
	const evo_serve_can_def *def;
	evo_can *can;
	evo_sim *sim;
	evo_can_rx rx;
	evo_can_body_info info;
	unsigned ns, na;
	evo_standin s;	/* its schedule, episode and counts */
	int full_next;	/* the next tick sends every sensor frame */
	int told_hello; /* a HELLO that does not fit was said */
	evo_q16 sent[EVO_CAN_MAX_SENSORS]; /* the values evo was sent */
	unsigned long dropped[EVO_CAN_ROBOT_BAD_COUNT];
} body;

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

/* The episode's reward so far, a REWARD frame. */
static int put_reward(body *b, evo_err *err)
{
	evo_can_frame f = {EVO_WIRE_REWARD, 8, {0}};
	double reward = evo_sim_episode_reward(b->sim);
	uint64_t bits;
	memcpy(&bits, &reward, sizeof bits);
	evo_wire_put_u32(f.data, (uint32_t)bits);
	evo_wire_put_u32(f.data + 4, (uint32_t)(bits >> 32));
	return put_frame(b, &f, err);
}

static int send_body(void *ctx, evo_err *err)
{
	body *b = ctx;
	evo_can_frame f;
	evo_can_body_encode(&b->info, &f);
	return put_frame(b, &f, err);
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
		       b->s.name, b->rx.hello.sensors, b->rx.hello.actuators,
		       b->rx.hello.version, b->ns, b->na, EVO_WIRE_VERSION);
		b->told_hello = 1;
	}
	return send_body(b, err);
}

/* RESET: a new episode from evo's seeds (cmd/standin.h); every sensor
 * frame goes out on its first tick. STOP: of the episode running only. */
static int on_reset(body *b, evo_err *err)
{
	uint32_t e = b->rx.episode;
	if (e < 1 || e > (uint32_t)INT32_MAX) {
		evo_can_frame f = {EVO_WIRE_RESET, 8, {0}};
		drop(b, EVO_CAN_ROBOT_BAD_VALUE, &f, "episode 0 or past 2^31");
		return 0;
	}
	int rc =
	    evo_standin_reset(&b->s, e, b->rx.layout_seed, b->rx.seed, err);
	if (rc == 0)
		b->full_next = 1;
	return rc < 0 ? -1 : 0;
}

static void on_stop(body *b)
{
	if (b->s.active && b->rx.episode == b->s.episode)
		evo_standin_stop(&b->s);
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
	evo_standin *st = &b->s;
	if (st->active && tick < st->tick) {
		evo_standin_late(st, tick);
		return 0;
	}
	if (!st->active || tick != st->tick || st->stepped) {
		snprintf(what, sizeof what,
			 "the command of tick %lld; the robot is at tick %lld "
			 "of episode %lld%s",
			 (long long)tick, (long long)st->tick,
			 (long long)st->episode,
			 st->active ? "" : " (stopped)");
		drop(b, EVO_CAN_ROBOT_BAD_STALE, f, what);
		return 0;
	}
	/* INCOMPLETE: the mind did not step (a sensor frame was lost);
	 * the commands before hold until the period ends */
	if (b->rx.flags & EVO_WIRE_F_INCOMPLETE)
		return 0;
	double cmd[EVO_CAN_MAX_ACTUATORS];
	for (unsigned j = 0; j < b->na; j++)
		cmd[j] = evo_q16_to_double(b->rx.values[j]);
	b->full_next = 0;
	return evo_standin_command(st, cmd, err);
}

/* The next frame within ms, acted on: 0, or -1 with err set. */
static int next_frame(void *ctx, int ms, evo_err *err)
{
	body *b = ctx;
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
static int send_tick(void *ctx, evo_err *err)
{
	body *b = ctx;
	double v[EVO_CAN_MAX_SENSORS];
	evo_q16 q[EVO_CAN_MAX_SENSORS];
	evo_sim_sense(b->sim, v);
	for (unsigned i = 0; i < b->ns; i++)
		q[i] = evo_q16_from_sensor(v[i]);
	unsigned frames = evo_wire_frames(b->ns);
	int full = b->full_next || frames > 32;
	b->full_next = 1; /* until this tick's command comes in time */
	uint32_t mask = 0;
	if (put_reward(b, err))
		return -1;
	evo_can_frame f;
	memset(&f, 0, sizeof f);
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
	evo_wire_put_u32(f.data, (uint32_t)b->s.tick);
	evo_wire_put_u32(f.data + 4, mask);
	return put_frame(b, &f, err);
}

/* The episode ended (the world's end or TICKLIM): its reward, then DONE. */
static int send_end(void *ctx, evo_err *err)
{
	body *b = ctx;
	if (put_reward(b, err))
		return -1;
	evo_can_frame f;
	memset(&f, 0, sizeof f);
	f.id = EVO_WIRE_DONE;
	f.len = 4;
	evo_wire_put_u32(f.data, (uint32_t)b->s.tick);
	return put_frame(b, &f, err);
}

static const char *bad_frame_name(int i)
{
	return evo_can_robot_bad_name((evo_can_robot_bad)i);
}

static const char *bad_input_name(int i)
{
	return evo_can_bad_name((evo_can_bad)i);
}

static void report(const body *b)
{
	evo_standin_report(&b->s);
	evo_report_drops("evo serve", "frame", "", b->dropped, 0,
			 EVO_CAN_ROBOT_BAD_COUNT, bad_frame_name);
	evo_report_drops(
	    "evo serve", "piece", " of input that were no frames of evo's",
	    evo_can_dropped(b->can), 0, EVO_CAN_BAD_COUNT, bad_input_name);
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
	b.ns = bd->n_sensors;
	b.na = bd->n_actuators;
	long p = lround(def->tick_ms * 10);
	b.info.names_hash = evo_names_hash_of(bd, NULL);
	b.info.sensors = b.ns;
	b.info.actuators = b.na;
	b.info.period_100us = (unsigned)(p < 1 ? 1 : p);
	const char *tl = evo_simbatch_get(def->task->sb, "TICKLIM");
	b.s = (evo_standin){
	    .name = def->url,
	    .na = b.na,
	    .io = {&b, send_body, send_tick, send_end, next_frame},
	    .stop = def->stop,
	    .period = b.info.period_100us * 1e-4,
	    .timeout = def->timeout,
	    .limit = tl ? strtoll(tl, NULL, 10) : 0,
	};
	evo_standin_neutral(&b.s);
	evo_can_rx_init(&b.rx, 1, b.na);
	int rc = 1;
	b.sim = evo_sim_create(def->task->mind, def->task->sb, def->task_path,
			       &err);
	if (!b.sim)
		goto out;
	b.s.sim = b.sim;
	b.can = evo_can_open(def->url, &err);
	if (!b.can)
		goto out;
	printf("evo serve: serves %s as a robot's body on %s, a tick every "
	       "%.1f ms, neutral after %.3g s without a command\n",
	       def->task_path, def->url, b.s.period * 1e3, b.s.timeout);
	if (evo_can_pty_name(b.can))
		printf(
		    "evo serve: its slcan pseudo-terminal is %s%s%s: evo run "
		    "TASK --can slcan:%s\n",
		    evo_can_pty_name(b.can),
		    evo_can_pty_link(b.can) ? ", linked from " : "",
		    evo_can_pty_link(b.can) ? evo_can_pty_link(b.can) : "",
		    evo_can_pty_link(b.can) ? evo_can_pty_link(b.can)
					    : evo_can_pty_name(b.can));
	if (evo_standin_run(&b.s, &err) == 0)
		rc = 0;
	report(&b);
out:
	if (rc && err.msg[0])
		fprintf(stderr, "%s\n", err.msg);
	evo_can_close(b.can);
	evo_sim_destroy(b.sim);
	return rc;
}
