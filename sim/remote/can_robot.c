/* evo's side of a robot over CAN (sim/remote/can_robot.h, docs/can.md).
 * The rules are a robot's over LCM (session.c, evo_robot_*): the newest
 * tick answered at once, every tick number counted once (in time, late,
 * missing), a silent robot reported and waited for; only the messages are
 * frames. */
#define _POSIX_C_SOURCE 200809L
#include "remote/can_robot.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/clock.h"
#include "base/counts.h"
#include "remote/can.h"

#define SLICE_MS      50   /* the longest wait between two looks at stop */
#define RESEND_S      0.25 /* a RESET unanswered this long is sent again */
#define HELLO_EVERY_S 0.5
/* A BODY later than this after evo's last HELLO is no answer to it: the
 * body started again, and its episode is lost. */
#define BODY_ANSWER_S 1.0

struct evo_can_robot {
	evo_can *can;
	char url[256];
	char about[512];
	const evo_mindfolder *mind;
	double timeout;
	volatile sig_atomic_t *stop;
	evo_can_body_info body;
	double period; /* seconds */
	evo_can_rx rx;
	/* the episode */
	int started; /* an episode was started: STOP at the end */
	int64_t episode;
	int64_t tick; /* held; -1: none yet */
	int answered, done;
	double reward;
	evo_q16 values[EVO_CAN_MAX_SENSORS];	 /* the held tick's */
	evo_q16 commands[EVO_CAN_MAX_ACTUATORS]; /* the last sent */
	evo_can_frame reset[3];
	double reset_at, reset_sent_at; /* monotonic */
	double arrived, answered_at;
	unsigned long in_time, late, unanswered, missing;
	double heard_at, told_at, hello_at;
	unsigned long dropped[EVO_CAN_ROBOT_BAD_COUNT];
};

static int stopped(const evo_can_robot *r, evo_err *err)
{
	if (r->stop && *r->stop)
		return evo_fail(err, "stopped");
	return 0;
}

/* The first drop of each reason is said at once; the counts at the end. */
static void dropped(evo_can_robot *r, evo_can_robot_bad why,
		    const evo_can_frame *f, const char *what)
{
	if (r->dropped[why]++ == 0)
		fprintf(stderr,
			"evo: robot %s: dropped a frame (%s: id %#05x, %u "
			"bytes: %s); later drops are counted and reported at "
			"the end\n",
			r->url, evo_can_robot_bad_name(why), (unsigned)f->id,
			(unsigned)f->len, what);
}

/* What a refused frame was refused for, in words. */
static const char *why_refused(const evo_can_rx *rx)
{
	switch (rx->bad) {
	case EVO_CAN_ROBOT_BAD_ID:
		return "not a frame a robot's body sends, or past its counts";
	case EVO_CAN_ROBOT_BAD_LENGTH:
		return "a length its id does not take";
	case EVO_CAN_ROBOT_BAD_VALUE:
		return "a value outside [0, 1], a reward not finite, or a "
		       "BODY of no sensors, actuators or period";
	default:
		return evo_can_robot_bad_name(rx->bad);
	}
}

static int send_frame(evo_can_robot *r, const evo_can_frame *f, evo_err *err)
{
	return evo_can_send(r->can, f, err);
}

static int send_hello(evo_can_robot *r, evo_err *err)
{
	const evo_mind *m = &r->mind->mind;
	evo_can_frame f = {EVO_WIRE_HELLO, 8, {0}};
	evo_wire_put_u32(f.data, r->mind->names_hash);
	f.data[4] = (uint8_t)m->n_sensors;
	f.data[5] = (uint8_t)m->n_actuators;
	f.data[6] = (uint8_t)m->n_vars;
	f.data[7] = EVO_WIRE_VERSION;
	r->hello_at = evo_clock_now();
	return send_frame(r, &f, err);
}

/* The body against the botdesc: the counts, then, when it gives one, the
 * names hash. Over CAN a value is known by its place, so a body whose
 * names are the botdesc's in another order does not fit either. */
static int check_fit(evo_can_robot *r, evo_err *err)
{
	const evo_botdesc *bd = r->mind->botdesc;
	const evo_can_body_info *b = &r->body;
	const char *bot = r->mind->bot_name;
	if (b->sensors != bd->n_sensors || b->actuators != bd->n_actuators)
		return evo_fail(err,
				"robot %s does not fit %s.botdesc: it has %u "
				"sensor%s and %u actuator%s, %s.botdesc %u and "
				"%u (docs/can.md)",
				r->url, bot, b->sensors,
				b->sensors == 1 ? "" : "s", b->actuators,
				b->actuators == 1 ? "" : "s", bot,
				bd->n_sensors, bd->n_actuators);
	uint32_t mine = evo_names_hash_of(bd, NULL);
	if (b->names_hash && b->names_hash != mine)
		return evo_fail(err,
				"robot %s does not fit %s.botdesc: its sensor "
				"and actuator names are others, or in another "
				"order (its names hash %08x, %s.botdesc's "
				"%08x); over CAN a value is known by its place "
				"in the botdesc (docs/can.md)",
				r->url, bot, (unsigned)b->names_hash, bot,
				(unsigned)mine);
	r->period = b->period_100us * 1e-4;
	snprintf(r->about, sizeof r->about,
		 "robot %s: a tick every %.3f ms; %u sensors and %u "
		 "actuators, %s",
		 r->url, r->period * 1e3, b->sensors, b->actuators,
		 b->names_hash ? "names as in the botdesc"
			       : "no names hash given: their order is taken "
				 "on trust");
	return 0;
}

evo_can_robot *evo_can_robot_open(const evo_can_robot_def *def, evo_err *err)
{
	evo_can_robot *r = calloc(1, sizeof *r);
	if (!r) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	snprintf(r->url, sizeof r->url, "%s", def->url);
	r->mind = def->mind;
	r->timeout = def->timeout > 0 ? def->timeout : 2.0;
	r->stop = def->stop;
	r->tick = -1;
	for (unsigned j = 0; j < EVO_CAN_MAX_ACTUATORS; j++)
		r->commands[j] = EVO_Q16_HALF;
	evo_can_rx_init(&r->rx, 0, r->mind->botdesc->n_sensors);
	r->can = evo_can_open(def->url, err);
	if (!r->can) {
		free(r);
		return NULL;
	}
	double start = evo_clock_now(), told = start;
	for (;;) {
		if (stopped(r, err)) {
			err->msg[0] = 0;
			break;
		}
		double t = evo_clock_now();
		if (t - r->hello_at >= HELLO_EVERY_S && send_hello(r, err))
			break;
		if (t - told >= r->timeout) {
			fprintf(stderr,
				"evo: no robot has answered on %s for %.0f s; "
				"waiting (Ctrl-C stops)\n",
				r->url, t - start);
			told = t;
		}
		evo_can_frame f;
		int got = evo_can_recv(r->can, SLICE_MS, &f, err);
		if (got < 0)
			break;
		if (!got)
			continue;
		evo_can_event ev = evo_can_rx_frame(&r->rx, &f);
		if (ev == EVO_CAN_EV_BAD) {
			dropped(r, r->rx.bad, &f, why_refused(&r->rx));
			continue;
		}
		if (ev != EVO_CAN_EV_BODY)
			continue; /* ticks of an episode before this evo */
		r->body = r->rx.body;
		r->heard_at = evo_clock_now();
		if (check_fit(r, err))
			break;
		return r;
	}
	evo_can_robot_close(r);
	return NULL;
}

static const char *bad_frame_name(int i)
{
	return evo_can_robot_bad_name((evo_can_robot_bad)i);
}

static const char *bad_input_name(int i)
{
	return evo_can_bad_name((evo_can_bad)i);
}

static void report_drops(const evo_can_robot *r)
{
	char who[sizeof r->url + 16];
	snprintf(who, sizeof who, "evo: robot %s", r->url);
	evo_report_drops(who, "frame", "", r->dropped, 0,
			 EVO_CAN_ROBOT_BAD_COUNT, bad_frame_name);
	if (evo_can_unsent(r->can))
		fprintf(stderr,
			"evo: robot %s: %lu frame%s not sent: the line took no "
			"more (no one was reading it)\n",
			r->url, evo_can_unsent(r->can),
			evo_can_unsent(r->can) == 1 ? "" : "s");
	evo_report_drops(who, "piece", " of input that were no frames of evo's",
			 evo_can_dropped(r->can), 0, EVO_CAN_BAD_COUNT,
			 bad_input_name);
}

void evo_can_robot_close(evo_can_robot *r)
{
	if (!r)
		return;
	if (r->can) {
		if (r->started) {
			evo_can_frame f = {EVO_WIRE_STOP, 4, {0}};
			evo_wire_put_u32(f.data, (uint32_t)r->episode);
			evo_err ignored;
			send_frame(r, &f, &ignored);
		}
		report_drops(r);
		evo_can_close(r->can);
	}
	free(r);
}

const char *evo_can_robot_about(const evo_can_robot *r)
{
	return r->about;
}

const char *evo_can_robot_name(const evo_can_robot *r)
{
	return r->url;
}

double evo_can_robot_period(const evo_can_robot *r)
{
	return r->period;
}

static int send_reset(evo_can_robot *r, evo_err *err)
{
	r->reset_sent_at = evo_clock_now();
	for (int i = 0; i < 3; i++)
		if (send_frame(r, &r->reset[i], err))
			return -1;
	return 0;
}

int evo_can_robot_start(evo_can_robot *r, int64_t episode, uint64_t layout_seed,
			uint64_t seed, evo_err *err)
{
	if (episode < 1 || episode > (int64_t)UINT32_MAX)
		return evo_fail(err,
				"robot %s: episode %lld does not fit a "
				"RESET frame",
				r->url, (long long)episode);
	r->started = 1;
	r->episode = episode;
	r->tick = -1;
	r->answered = 1;
	r->done = 0;
	r->reward = 0;
	evo_can_rx_restart(&r->rx);
	evo_can_reset_encode((uint32_t)episode, layout_seed, seed, r->reset);
	if (send_reset(r, err))
		return -1;
	r->reset_at = r->reset_sent_at;
	/* silence counts from the RESET, not from the hello long before */
	r->heard_at = r->reset_at;
	return 0;
}

/* The first late and the first missing tick are said at once. */
static void tell_late(evo_can_robot *r, int64_t tick, const char *what)
{
	if (r->late == 1)
		fprintf(stderr,
			"evo: robot %s: tick %lld %s; later late ticks are "
			"counted and reported at the end\n",
			r->url, (long long)tick, what);
}

static void tell_missing(evo_can_robot *r, unsigned long before,
			 const char *what)
{
	if (before == 0)
		fprintf(stderr,
			"evo: robot %s: %s; later missing ticks are counted "
			"and reported at the end\n",
			r->url, what);
}

/* An incomplete tick is answered as the firmware answers one: the
 * commands before, flagged INCOMPLETE (the mind did not step). */
static int send_commands(evo_can_robot *r, uint32_t tick, uint8_t flags,
			 evo_err *err)
{
	unsigned n = r->mind->botdesc->n_actuators;
	evo_can_frame f;
	for (unsigned k = 0; k < evo_wire_frames(n); k++) {
		evo_wire_pack(EVO_WIRE_ACTUATOR, r->commands, n, k, &f);
		if (send_frame(r, &f, err))
			return -1;
	}
	memset(&f, 0, sizeof f);
	f.id = EVO_WIRE_TICKED;
	f.len = 5;
	evo_wire_put_u32(f.data, tick);
	f.data[4] = flags;
	return send_frame(r, &f, err);
}

/* A TICK: held when it is a newer tick of the episode and complete.
 * 1 when held, 0 when not, -1 with err set. */
static int take_tick(evo_can_robot *r, const evo_can_frame *f, evo_err *err)
{
	int64_t tick = r->rx.tick;
	double t = evo_clock_now();
	/* Before the episode's first tick, a tick the robot cannot have
	 * reached since the RESET went out is of an episode it ran before
	 * (an evo that ended without a STOP). TICK carries no episode. */
	int64_t reachable = r->tick < 0
				? (int64_t)((t - r->reset_at) / r->period) + 1
				: INT64_MAX;
	if (tick <= r->tick || tick > reachable) {
		char what[160];
		snprintf(what, sizeof what, "tick %lld; evo holds tick %lld%s",
			 (long long)tick, (long long)r->tick,
			 tick > reachable ? ", and the robot cannot have "
					    "reached it since evo's RESET"
					  : "");
		dropped(r, EVO_CAN_ROBOT_BAD_STALE, f, what);
		return 0;
	}
	if (!r->answered) {
		r->late++;
		r->unanswered++;
		tell_late(r, r->tick,
			  "was not answered: a newer tick came first");
	}
	int64_t gap = tick - (r->tick + 1);
	if (gap > 0) {
		char what[160];
		snprintf(what, sizeof what,
			 "tick %lld came after tick %lld: %lld tick%s missing",
			 (long long)tick, (long long)r->tick, (long long)gap,
			 gap == 1 ? "" : "s");
		tell_missing(r, r->missing, what);
		r->missing += (unsigned long)gap;
	}
	r->tick = tick;
	r->reward = r->rx.reward;
	if (!r->rx.complete) {
		char what[200];
		snprintf(what, sizeof what,
			 "tick %lld came incomplete (sensor frames lacking: "
			 "mask %#llx): answered INCOMPLETE with the commands "
			 "before",
			 (long long)tick,
			 (unsigned long long)r->rx.missing_frames);
		/* counted as a drop, and said as a missing tick */
		r->dropped[EVO_CAN_ROBOT_BAD_INCOMPLETE]++;
		tell_missing(r, r->missing, what);
		r->missing++;
		r->answered = 1;
		return send_commands(r, (uint32_t)tick, EVO_WIRE_F_INCOMPLETE,
				     err)
			   ? -1
			   : 0;
	}
	memcpy(r->values, r->rx.values, sizeof r->values);
	r->arrived = t;
	r->answered = 0;
	return 1;
}

int evo_can_robot_next(evo_can_robot *r, int timeout_ms, evo_err *err)
{
	if (r->done)
		return 1;
	double until =
	    evo_clock_now() + (timeout_ms > 0 ? timeout_ms : 0) * 1e-3;
	int held = 0;
	for (;;) {
		if (stopped(r, err))
			return -1;
		double t = evo_clock_now();
		if (r->tick < 0 && t - r->reset_sent_at >= RESEND_S &&
		    send_reset(r, err))
			return -1;
		if (t - r->heard_at >= r->timeout &&
		    t - r->told_at >= r->timeout) {
			fprintf(stderr,
				"evo: robot %s silent for %.1f s: no frames "
				"from it; waiting (Ctrl-C stops); a robot goes "
				"neutral on its own\n",
				r->url, t - r->heard_at);
			r->told_at = t;
		}
		int wait_ms = evo_robot_wait_ms(held, until, t, SLICE_MS);
		if (wait_ms < 0)
			return 2;
		evo_can_frame f;
		int got = evo_can_recv(r->can, wait_ms, &f, err);
		if (got < 0)
			return -1;
		if (!got) {
			if (held)
				return 0;
			continue;
		}
		evo_can_event ev = evo_can_rx_frame(&r->rx, &f);
		if (ev == EVO_CAN_EV_BAD) {
			dropped(r, r->rx.bad, &f, why_refused(&r->rx));
			continue;
		}
		r->heard_at = evo_clock_now();
		if (ev == EVO_CAN_EV_BODY && r->tick >= 0 &&
		    r->heard_at - r->hello_at > BODY_ANSWER_S)
			return evo_fail(err,
					"robot %s started again (a BODY frame "
					"in the middle of episode %lld): the "
					"episode is lost",
					r->url, (long long)r->episode);
		if (ev == EVO_CAN_EV_DONE) {
			/* the end of an episode before this RESET: its
			 * count is more than the robot has ticked since */
			int64_t n = r->rx.tick;
			if (n <= r->tick ||
			    (r->tick < 0 &&
			     n > (int64_t)((r->heard_at - r->reset_at) /
					   r->period) +
				     1)) {
				dropped(r, EVO_CAN_ROBOT_BAD_STALE, &f,
					"the end of an episode before evo's "
					"RESET");
				continue;
			}
			if (!r->answered) {
				r->late++;
				r->unanswered++;
				tell_late(r, r->tick,
					  "was not answered: the robot ended "
					  "the episode first");
			}
			r->done = 1;
			r->answered = 1;
			r->reward = r->rx.reward;
			r->tick = r->rx.tick;
			return 1;
		}
		if (ev == EVO_CAN_EV_TICK) {
			int rc = take_tick(r, &f, err);
			if (rc < 0)
				return -1;
			held |= rc;
		}
	}
}

int evo_can_robot_answer(evo_can_robot *r, const evo_q16 *commands,
			 evo_err *err)
{
	if (r->tick < 0 || r->answered)
		return 0;
	r->answered = 1;
	r->answered_at = evo_clock_now();
	char what[96];
	if (evo_robot_answered_late(r->arrived, r->answered_at, r->period,
				    what, sizeof what)) {
		r->late++;
		tell_late(r, r->tick, what);
	} else {
		r->in_time++;
	}
	unsigned n = r->mind->botdesc->n_actuators;
	memcpy(r->commands, commands, n * sizeof *commands);
	return send_commands(r, (uint32_t)r->tick, 0, err);
}

void evo_can_robot_sensors(const evo_can_robot *r, evo_q16 *values)
{
	memcpy(values, r->values, r->mind->botdesc->n_sensors * sizeof *values);
}

void evo_can_robot_status(const evo_can_robot *r, evo_robot_status *s)
{
	s->tick = r->tick;
	s->done = r->done;
	s->reward = r->reward;
	s->in_time = r->in_time;
	s->late = r->late;
	s->unanswered = r->unanswered;
	s->missing = r->missing;
	s->quiet = evo_clock_now() - r->heard_at;
}

void evo_can_robot_report(const evo_can_robot *r)
{
	printf("robot %s: %lu ticks: %lu answered in time, %lu late (%lu "
	       "unanswered), %lu missing\n",
	       r->url, r->in_time + r->late + r->missing, r->in_time, r->late,
	       r->unanswered, r->missing);
	fflush(stdout);
}
