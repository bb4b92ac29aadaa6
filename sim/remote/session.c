/* evo — evo's side of its remotes (sim/remote/session.h, docs/remote.md):
 * the episodes in lockstep, any number at once (evo_remotes_*), and in the
 * one-remote, one-environment form DEMOREMOTESIM uses (evo_remote_*); and
 * what every wait for a remote shares (session_internal.h): the clocks,
 * drop counting, the checks of a sensors_t, restarts and resends.
 * session_find.c finds the remotes, session_robot.c answers a robot. */
#define _POSIX_C_SOURCE 200809L
#include "remote/session_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/clock.h"
#include "base/counts.h"

static int64_t real_us(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

int evo_session_stopped(const evo_remote_opts *o, evo_err *err)
{
	if (o->stop && *o->stop)
		return evo_fail(err, "stopped");
	return 0;
}

/* ---- drops ------------------------------------------------------------- */

void evo_session_dropped(evo_remote *r, evo_wire_reason why_code,
			 const char *type, const char *why)
{
	if (r->dropped[why_code]++ == 0)
		fprintf(stderr,
			"evo: remote %s: dropped a %s (%s: %s); later drops "
			"are counted and reported at the end\n",
			r->hello.name, type, evo_wire_reason_name(why_code),
			why);
}

static const char *reason_name(int i)
{
	return evo_wire_reason_name((evo_wire_reason)i);
}

static void report_drops(const evo_remote *r)
{
	if (r->resent)
		fprintf(stderr,
			"evo: remote %s: %lu message%s sent again, unanswered "
			"after %.2f s\n",
			r->hello.name, r->resent, r->resent == 1 ? "" : "s",
			RESEND_S);
	char who[EVO_REMOTE_NAME_MAX + 32];
	snprintf(who, sizeof who, "evo: remote %s", r->hello.name);
	evo_report_drops(who, "message", "", r->dropped, 1, EVO_WIRE_N_REASONS,
			 reason_name);
}

const char *evo_session_kind_name(evo_remote_kind k)
{
	return k == EVO_REMOTE_SIMULATOR ? "simulator" : "robot";
}

evo_remote *evo_session_by_name(const evo_remotes *s, const char *name)
{
	for (int i = 0; i < s->n; i++)
		if (strcmp(s->r[i]->hello.name, name) == 0)
			return s->r[i];
	return NULL;
}

/* ---- episodes ---------------------------------------------------------- */

/* 1 when evo awaits an answer from r. */
static int awaiting(const evo_remote *r)
{
	for (int e = 0; e < r->hello.environments && e < EVO_REMOTE_MAX_ENVS;
	     e++)
		if (r->env[e].waiting)
			return 1;
	return 0;
}

static int send_env(evo_remote *r, evo_remote_env *e, const char *channel,
		    int len, evo_err *err)
{
	if (len < 0)
		return evo_fail(err, "evo: cannot encode a message for %s",
				channel);
	/* silence counts from when evo starts waiting, not from the last
	 * answer of a wait long over */
	if (!awaiting(r))
		r->heard_at = evo_clock_now();
	e->sent_len = len;
	snprintf(e->sent_channel, sizeof e->sent_channel, "%s", channel);
	e->sent_at = evo_clock_now();
	e->waiting = 1;
	e->have = 0;
	return evo_link_publish(r->link, channel, e->sent, (size_t)len, err);
}

/* Two sensors_t of one tick: the same values, reward and end. A simulator
 * repeats its answer byte for byte, and a robot sends each tick once. */
int evo_session_same_sensors(const evo_wire_sensors *a,
			     const evo_wire_sensors *b)
{
	if (a->n != b->n || a->done != b->done ||
	    memcmp(&a->reward, &b->reward, sizeof a->reward) != 0)
		return 0;
	return memcmp(a->value, b->value, a->n * sizeof *a->value) == 0;
}

/* A second, different answer for a tick already taken: two processes
 * answer under r's name, and evo cannot tell which is the remote. The
 * run ends rather than go on with values that may be forged. */
int evo_session_conflict(evo_remote *r, const evo_wire_sensors *s, evo_err *err)
{
	r->dropped[EVO_WIRE_CONFLICT]++;
	return evo_fail(
	    err,
	    "remote %s: two different sensors_t for tick %lld of "
	    "episode %lld (environment %d): another process answers "
	    "as %s on %s, and evo cannot tell which is the remote; "
	    "a key (LCMKEYFILE, docs/remote.md) keeps others out",
	    r->hello.name, (long long)s->tick, (long long)s->episode,
	    (int)s->env, r->hello.name, evo_link_url(r->link));
}

/* A message of r's current session, received after a hello of another
 * session under its name: that hello was not r's restart. */
static void answers_on(evo_remote *r, const evo_link_msg *m)
{
	if (!r->new_session_at || m->recv_utime <= r->new_session_recv)
		return;
	r->new_session_at = 0;
	r->dropped[EVO_WIRE_FORGED]++;
	if (r->impostor_hellos++ == 0)
		fprintf(
		    stderr,
		    "evo: remote %s: a hello under its name with session "
		    "%lld came while its session %lld answers on: not taken "
		    "as a restart (another process says hello as %s; a key, "
		    "LCMKEYFILE, keeps it out); later ones are counted\n",
		    r->hello.name, (long long)r->new_session,
		    (long long)r->hello.session, r->hello.name);
}

/* A value outside [0, 1] named by the sensor the remote's hello gives
 * it ("sensor S4 (value 3) is nan"), where evo_wire_check_values could
 * only number it. */
void evo_session_name_bad_value(const evo_wire_hello *h,
				const evo_wire_sensors *s, char *why,
				size_t cap)
{
	for (unsigned i = 0; i < s->n && i < h->n_sensors; i++)
		if (!(s->value[i] >= 0.0 && s->value[i] <= 1.0)) {
			snprintf(why, cap,
				 "sensor %s (value %u) is %g, outside [0, 1]",
				 h->sensor[i], i, s->value[i]);
			return;
		}
}

int evo_session_admit_sensors(evo_remote *r, const evo_link_msg *m, int n_envs,
			      evo_wire_sensors *s)
{
	char why[256];
	evo_wire_reason rc =
	    evo_wire_decode_sensors(m->data, m->len, s, why, sizeof why);
	if (rc) {
		evo_session_dropped(r, rc, "sensors_t", why);
		return 0;
	}
	if (strcmp(s->name, r->hello.name) != 0 ||
	    s->session != r->hello.session || s->env < 0 || s->env >= n_envs) {
		snprintf(why, sizeof why,
			 "from %s, session %lld, environment %d", s->name,
			 (long long)s->session, (int)s->env);
		evo_session_dropped(r, EVO_WIRE_FOREIGN, "sensors_t", why);
		return 0;
	}
	if (s->n != r->hello.n_sensors) {
		snprintf(why, sizeof why, "%u values; its hello says %u", s->n,
			 r->hello.n_sensors);
		evo_session_dropped(r, EVO_WIRE_COUNTS, "sensors_t", why);
		return 0;
	}
	rc = evo_wire_fresh_take(&r->fresh_sensors, m->stamp, why, sizeof why);
	if (rc) {
		evo_session_dropped(r, rc, "sensors_t", why);
		return 0;
	}
	answers_on(r, m);
	return 1;
}

/* A sensors_t: keep it when it is the one its environment awaits. */
static int take_sensors(evo_remote *r, const evo_link_msg *m, evo_err *err)
{
	evo_wire_sensors s;
	char why[256];
	int n_envs = r->hello.environments < EVO_REMOTE_MAX_ENVS
			 ? r->hello.environments
			 : EVO_REMOTE_MAX_ENVS;
	if (!evo_session_admit_sensors(r, m, n_envs, &s))
		return 0;
	evo_remote_env *e = &r->env[s.env];
	if (e->taken && s.episode == e->sensors.episode &&
	    s.tick == e->sensors.tick &&
	    !evo_session_same_sensors(&s, &e->sensors))
		return evo_session_conflict(r, &s, err);
	int stale = !e->waiting || s.episode < e->episode ||
		    (s.episode == e->episode && (s.tick < e->tick || e->have));
	if (stale || s.episode > e->episode || s.tick > e->tick) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; evo %s tick %lld of "
			 "episode %lld",
			 (long long)s.tick, (long long)s.episode,
			 stale ? "is at" : "waits for", (long long)e->tick,
			 (long long)e->episode);
		evo_session_dropped(r, stale ? EVO_WIRE_STALE : EVO_WIRE_AHEAD,
				    "sensors_t", why);
		return 0;
	}
	r->heard_at = evo_clock_now();
	evo_wire_reason rc =
	    evo_wire_check_values(s.value, s.n, &s.reward, why, sizeof why);
	if (!rc)
		rc = evo_wire_check_behaviour(&s, why, sizeof why);
	if (rc) {
		evo_session_name_bad_value(&r->hello, &s, why, sizeof why);
		/* a simulator that sends a bad value for the awaited tick
		 * cannot go on: lockstep waits for this very message */
		r->dropped[rc]++;
		return evo_fail(err,
				"remote %s: the sensors_t of tick %lld of "
				"episode %lld (environment %d): %s",
				r->hello.name, (long long)s.tick,
				(long long)s.episode, (int)s.env, why);
	}
	e->sensors = s;
	e->have = 1;
	e->taken = 1;
	return 0;
}

/* A hello while running: the same session answering a who is fine; a new
 * session is a remote that restarted and lost its episodes. With a key
 * the hello is the remote's own: a restart at once. Without one anyone
 * can send it, so it is a restart only once the old session has been
 * silent for RESTART_GRACE_S after it (evo_restarted); a message of the
 * old session after it shows it was not (answers_on). */
void evo_session_take_hello(evo_remotes *s, const evo_link_msg *m)
{
	evo_wire_hello h;
	char why[256];
	if (evo_wire_decode_hello(m->data, m->len, &h, why, sizeof why))
		return;
	evo_remote *r = evo_session_by_name(s, h.name);
	if (!r || r->lost || h.session == r->hello.session)
		return;
	if (evo_wire_fresh_take(&r->fresh_hello, m->stamp, why, sizeof why)) {
		evo_session_dropped(r, EVO_WIRE_REPLAYED, "hello_t", why);
		return;
	}
	if (r->new_session_at)
		return;
	r->new_session = h.session;
	r->new_session_at = s->opts.key.len ? evo_clock_now() - RESTART_GRACE_S
					    : evo_clock_now();
	r->new_session_recv = m->recv_utime > 0 ? m->recv_utime : real_us();
}

/* A remote whose restart is now certain: -1 with err set, or (lose_silent)
 * 1 with *ri the remote, taken as lost. 0: none. */
int evo_session_restarted(evo_remotes *s, int *ri, evo_err *err)
{
	double t = evo_clock_now();
	for (int i = 0; i < s->n; i++) {
		evo_remote *r = s->r[i];
		if (r->lost || !r->new_session_at ||
		    t - r->new_session_at < RESTART_GRACE_S)
			continue;
		if (!s->opts.lose_silent)
			return evo_fail(
			    err,
			    "remote %s restarted (a new session): the "
			    "episodes it was running are lost",
			    r->hello.name);
		fprintf(stderr,
			"evo: remote %s restarted (a new session); its "
			"evaluations go to the others\n",
			r->hello.name);
		r->lost = 1;
		for (int e = 0; e < EVO_REMOTE_MAX_ENVS; e++)
			r->env[e].waiting = 0;
		*ri = i;
		return 1;
	}
	return 0;
}

/* Remote r is gone: nothing of it is awaited any more. */
static void lose(evo_remote *r)
{
	r->lost = 1;
	for (int e = 0; e < EVO_REMOTE_MAX_ENVS; e++)
		r->env[e].waiting = 0;
}

int evo_session_resend(evo_remote *r, evo_remote_env *e, double t, evo_err *err)
{
	if (t - e->sent_at < RESEND_S)
		return 0;
	e->sent_at = t;
	r->resent++;
	return evo_link_publish(r->link, e->sent_channel, e->sent,
				(size_t)e->sent_len, err);
}

void evo_session_command(const evo_remote *r, int env, int64_t episode,
			 int64_t tick, const double *commands,
			 evo_wire_command *c)
{
	memset(c, 0, sizeof *c);
	c->session = r->hello.session;
	c->env = env;
	c->episode = episode;
	c->tick = tick;
	c->n = r->hello.n_actuators;
	snprintf(c->name, sizeof c->name, "%s", r->hello.name);
	for (unsigned j = 0; j < c->n; j++)
		c->value[j] = commands[r->actuator_of[j]];
}

int evo_remotes_wait(evo_remotes *s, int *ri, int *env, evo_err *err)
{
	for (;;) {
		/* an answer already in */
		for (int i = 0; i < s->n; i++) {
			evo_remote *r = s->r[i];
			for (int e = 0; !r->lost && e < r->hello.environments;
			     e++)
				if (r->env[e].waiting && r->env[e].have) {
					r->env[e].waiting = 0;
					*ri = i;
					*env = e;
					return 0;
				}
		}
		if (evo_session_stopped(&s->opts, err))
			return -1;
		int rs = evo_session_restarted(s, ri, err);
		if (rs)
			return rs < 0 ? -1 : 1;
		double t = evo_clock_now();
		int awaited = 0;
		for (int i = 0; i < s->n; i++) {
			evo_remote *r = s->r[i];
			int waits = 0;
			for (int e = 0; !r->lost && e < r->hello.environments;
			     e++) {
				evo_remote_env *v = &r->env[e];
				if (!v->waiting)
					continue;
				waits = 1;
				if (evo_session_resend(r, v, t, err))
					return -1;
			}
			awaited |= waits;
			if (!waits || t - r->heard_at < s->opts.timeout)
				continue;
			if (s->opts.lose_silent) {
				fprintf(stderr,
					"evo: remote %s silent for %.1f s: "
					"taken as lost; its evaluations go to "
					"the others\n",
					r->hello.name, t - r->heard_at);
				lose(r);
				*ri = i;
				return 1;
			}
			if (t - r->told_at >= s->opts.timeout) {
				fprintf(stderr,
					"evo: remote %s silent for %.1f s; "
					"waiting (Ctrl-C stops)\n",
					r->hello.name, t - r->heard_at);
				r->told_at = t;
			}
		}
		if (!awaited)
			return evo_fail(err, "evo: waiting for no remote");
		evo_link_msg m;
		int which;
		int got = evo_link_next_any(s->links, s->n_links, SLICE_MS,
					    &which, &m, err);
		if (got < 0)
			return -1;
		if (!got)
			continue;
		if (which == 0 && strcmp(m.channel, "EVO_HELLO") == 0) {
			evo_session_take_hello(s, &m);
			continue;
		}
		for (int i = 0; i < s->n; i++)
			if (s->links[which] == s->r[i]->link &&
			    strcmp(m.channel, s->r[i]->ch_sensors) == 0) {
				if (!s->r[i]->lost &&
				    take_sensors(s->r[i], &m, err))
					return -1;
				break;
			}
	}
}

int evo_remotes_send_reset(evo_remotes *s, int ri, int env, int64_t episode,
			   uint64_t layout_seed, uint64_t seed, evo_err *err)
{
	evo_remote *r = s->r[ri];
	if (env < 0 || env >= r->hello.environments)
		return evo_fail(err, "remote %s runs %d environments, not %d",
				r->hello.name, (int)r->hello.environments,
				env + 1);
	evo_remote_env *e = &r->env[env];
	e->episode = episode;
	e->tick = 0;
	evo_wire_control c = {
	    .session = r->hello.session,
	    .env = env,
	    .op = EVO_CONTROL_RESET,
	    .episode = episode,
	    .layout_seed = layout_seed,
	    .seed = seed,
	};
	snprintf(c.name, sizeof c.name, "%s", r->hello.name);
	return send_env(r, e, r->ch_control,
			evo_wire_encode_control(&c, e->sent, sizeof e->sent),
			err);
}

int evo_remotes_send_command(evo_remotes *s, int ri, int env,
			     const double *commands, evo_err *err)
{
	evo_remote *r = s->r[ri];
	evo_remote_env *e = &r->env[env];
	evo_wire_command c;
	evo_session_command(r, env, e->episode, e->tick, commands, &c);
	e->tick++;
	return send_env(r, e, r->ch_command,
			evo_wire_encode_command(&c, e->sent, sizeof e->sent),
			err);
}

void evo_remote_sensors(const evo_remote *r, int env, double *values)
{
	const evo_remote_env *e = &r->env[env];
	for (unsigned i = 0; i < r->set->mind->botdesc->n_sensors; i++)
		values[i] = e->sensors.value[r->sensor_at[i]];
}

double evo_remote_reward(const evo_remote *r, int env)
{
	return r->env[env].sensors.reward;
}

void evo_remotes_close(evo_remotes *s)
{
	if (!s)
		return;
	evo_err ignored;
	for (int k = 0; k < s->n; k++) {
		evo_remote *r = s->r[k];
		for (int i = 0; !r->lost && i < r->hello.environments &&
				i < EVO_REMOTE_MAX_ENVS;
		     i++) {
			if (!r->env[i].episode)
				continue;
			evo_wire_control c = {.session = r->hello.session,
					      .env = i,
					      .op = EVO_CONTROL_STOP,
					      .episode = r->env[i].episode};
			snprintf(c.name, sizeof c.name, "%s", r->hello.name);
			unsigned char buf[512];
			int n = evo_wire_encode_control(&c, buf, sizeof buf);
			if (n > 0)
				evo_link_publish(r->link, r->ch_control, buf,
						 (size_t)n, &ignored);
		}
		report_drops(r);
		free(r);
	}
	for (int i = 0; i < s->n_links; i++) {
		evo_link_report(s->links[i]);
		evo_link_close(s->links[i]);
	}
	memset(&s->opts.key, 0, sizeof s->opts.key);
	free(s);
}

/* ---- one remote, one environment at a time ------------------------------ */

evo_remotes *evo_remote_connect(const evo_mindfolder *mind,
				const evo_remote_opts *o, evo_err *err)
{
	evo_remotes *s = evo_remotes_open(mind, o, err);
	if (s && evo_remotes_find(s, 0, err)) {
		evo_remotes_close(s);
		return NULL;
	}
	return s;
}

/* Wait for env of the first remote. */
static int await_first(evo_remotes *s, int env, evo_err *err)
{
	int ri, e;
	for (;;) {
		int rc = evo_remotes_wait(s, &ri, &e, err);
		if (rc != 0)
			return -1;
		if (ri == 0 && e == env)
			return 0;
	}
}

int evo_remote_reset(evo_remotes *s, int env, int64_t episode,
		     uint64_t layout_seed, uint64_t seed, evo_err *err)
{
	if (evo_remotes_send_reset(s, 0, env, episode, layout_seed, seed, err))
		return -1;
	return await_first(s, env, err);
}

int evo_remote_step(evo_remotes *s, int env, const double *commands,
		    evo_err *err)
{
	if (evo_remotes_send_command(s, 0, env, commands, err) ||
	    await_first(s, env, err))
		return -1;
	return s->r[0]->env[env].sensors.done ? 1 : 0;
}
