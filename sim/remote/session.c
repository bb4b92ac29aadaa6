/* evo's side of its remotes (sim/remote/session.h, docs/remote.md). */
#define _POSIX_C_SOURCE 200809L
#include "remote/session.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SLICE_MS 50	 /* the longest wait between two looks at stop */
#define RESEND_S 0.25	 /* a message unanswered this long is sent again */
#define WHO_EVERY_S 0.5
/* a hello of a new session is a restart once the old session has been
 * silent this long after it (without a key anyone can send that hello) */
#define RESTART_GRACE_S 1.0

static double now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int64_t real_us(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static int stopped(const evo_remote_opts *o, evo_err *err)
{
	if (o->stop && *o->stop)
		return evo_fail(err, "stopped");
	return 0;
}

/* ---- drops ------------------------------------------------------------- */

static void dropped(evo_remote *r, evo_wire_reason why_code, const char *type,
		    const char *why)
{
	if (r->dropped[why_code]++ == 0)
		fprintf(stderr,
			"evo: remote %s: dropped a %s (%s: %s); later drops "
			"are counted and reported at the end\n",
			r->hello.name, type, evo_wire_reason_name(why_code),
			why);
}

static void report_drops(const evo_remote *r)
{
	if (r->resent)
		fprintf(stderr,
			"evo: remote %s: %lu message%s sent again, unanswered "
			"after %.2f s\n",
			r->hello.name, r->resent, r->resent == 1 ? "" : "s",
			RESEND_S);
	unsigned long total = 0;
	for (int i = 1; i < EVO_WIRE_N_REASONS; i++)
		total += r->dropped[i];
	if (!total)
		return;
	fprintf(stderr, "evo: remote %s: dropped %lu message%s (", r->hello.name,
		total, total == 1 ? "" : "s");
	const char *sep = "";
	for (int i = 1; i < EVO_WIRE_N_REASONS; i++)
		if (r->dropped[i]) {
			fprintf(stderr, "%s%lu %s", sep, r->dropped[i],
				evo_wire_reason_name((evo_wire_reason)i));
			sep = ", ";
		}
	fprintf(stderr, ")\n");
}

/* ---- the task's keys ----------------------------------------------------- */

int evo_remote_opts_from_task(const evo_simbatch *sb, const char *path,
			      evo_remote_kind kind, evo_remote_opts *o,
			      evo_err *err)
{
	memset(o, 0, sizeof *o);
	o->task = path;
	o->url = evo_simbatch_get(sb, "LCMURL");
	o->name = evo_simbatch_get(sb, "REMOTENAME");
	/* a task comes in a shared mind folder: its URL, as a hello's, names
	 * a multicast group and never another LCM provider (file:// would
	 * have evo write where the task says) */
	char uwhy[200];
	int ttl;
	if (o->url && (!o->url[0] || !evo_wire_url_ok(o->url, &ttl, uwhy,
						       sizeof uwhy)))
		return evo_fail(err, "%s: LCMURL: %s", path,
				o->url[0] ? uwhy : "empty");
	o->kind = kind;
	o->timeout = EVO_REMOTE_DEFAULT_TIMEOUT;
	/* REMOTENAME (names joined by ','), like REMOTETIMEOUT below, is
	 * within its range: the key table checked it at its line
	 * (evo_simbatch_parse) */
	const char *kf = evo_simbatch_get(sb, "LCMKEYFILE");
	if (kf) {
		/* relative to the task's folder, as the task's other files */
		char file[4096], why[600];
		const char *slash = strrchr(path, '/');
		if (kf[0] == '/' || !slash)
			snprintf(file, sizeof file, "%s", kf);
		else
			snprintf(file, sizeof file, "%.*s/%s",
				 (int)(slash - path), path, kf);
		if (evo_wire_key_read(file, &o->key, why, sizeof why))
			return evo_fail(err, "%s: LCMKEYFILE: %s", path, why);
	}
	const char *t = evo_simbatch_get(sb, "REMOTETIMEOUT");
	if (t)
		o->timeout = strtod(t, NULL);
	return 0;
}

int evo_remote_opts_chosen(const evo_remote_opts *o, evo_err *err)
{
	if (o->name || o->key.len)
		return 0;
	return evo_fail(err,
			"%s: a remote task names its remotes (REMOTENAME:sim1 "
			"or REMOTENAME:sim1,sim2) or shares a key with them "
			"(LCMKEYFILE); without either, any process on %s could "
			"pass for its remote (docs/remote.md)",
			o->task ? o->task : "the task",
			o->url ? o->url : EVO_LINK_DEFAULT_URL);
}

int evo_remote_named(const evo_remote_opts *o, const char *name)
{
	if (!o->name)
		return 1;
	size_t n = strlen(name);
	for (const char *p = o->name; p;) {
		const char *comma = strchr(p, ',');
		size_t k = comma ? (size_t)(comma - p) : strlen(p);
		if (k == n && strncmp(p, name, n) == 0)
			return 1;
		p = comma ? comma + 1 : NULL;
	}
	return 0;
}

/* The ttl of an LCM URL (LCM's default: 0). */
static int url_ttl(const char *url)
{
	const char *t = url ? strstr(url, "ttl=") : NULL;
	return t ? atoi(t + 4) : 0;
}

/* ---- finding the remote ---------------------------------------------- */

static const char *kind_name(evo_remote_kind k)
{
	return k == EVO_REMOTE_SIMULATOR ? "simulator" : "robot";
}

/* names the botdesc has and the hello lacks (missing), and the other way
 * round (extra), as one sentence; 0 when they are the same set. */
static int compare_names(char *out, size_t cap, const char *what,
			 const char (*mine)[EVO_NAME_MAX], unsigned n_mine,
			 const char (*theirs)[EVO_NAME_MAX], unsigned n_theirs)
{
	size_t k = 0;
	int bad = 0;
	out[0] = 0;
	for (int pass = 0; pass < 2; pass++) {
		const char(*a)[EVO_NAME_MAX] = pass ? theirs : mine;
		const char(*b)[EVO_NAME_MAX] = pass ? mine : theirs;
		unsigned na = pass ? n_theirs : n_mine,
			 nb = pass ? n_mine : n_theirs;
		int first = 1;
		for (unsigned i = 0; i < na; i++) {
			unsigned j = 0;
			while (j < nb && strcmp(a[i], b[j]) != 0)
				j++;
			if (j < nb)
				continue;
			bad = 1;
			if (k < cap)
				k += (size_t)snprintf(
				    out + k, cap - k, "%s%s%s",
				    first ? (pass ? "; it has the extra "
						  : "; it lacks the ")
					  : ", ",
				    first ? what : "", first ? " " : "");
			if (k < cap)
				k += (size_t)snprintf(out + k, cap - k, "%s",
						      a[i]);
			first = 0;
		}
	}
	return bad;
}

/* Check a hello against the mind and fill the maps. */
static int accept(evo_remotes *s, evo_remote *r, evo_err *err)
{
	const evo_botdesc *bd = s->mind->botdesc;
	const evo_wire_hello *h = &r->hello;
	if (h->protocol != EVO_WIRE_PROTOCOL)
		return evo_fail(err,
				"remote %s speaks protocol %d; this evo speaks "
				"%d (docs/remote.md)",
				h->name, (int)h->protocol, EVO_WIRE_PROTOCOL);
	char mine_s[EVO_MAX_SENSORS][EVO_NAME_MAX];
	char mine_a[EVO_MAX_ACTUATORS][EVO_NAME_MAX];
	for (unsigned i = 0; i < bd->n_sensors; i++)
		snprintf(mine_s[i], EVO_NAME_MAX, "%s", bd->sensor[i].name);
	for (unsigned i = 0; i < bd->n_actuators; i++)
		snprintf(mine_a[i], EVO_NAME_MAX, "%s", bd->actuator[i].name);
	char ms[700], ma[300];
	int bs = compare_names(ms, sizeof ms, "sensors",
			       (const char(*)[EVO_NAME_MAX])mine_s,
			       bd->n_sensors, h->sensor, h->n_sensors);
	int ba = compare_names(ma, sizeof ma, "actuators",
			       (const char(*)[EVO_NAME_MAX])mine_a,
			       bd->n_actuators, h->actuator, h->n_actuators);
	if (bs || ba)
		return evo_fail(err,
				"remote %s does not fit %s.botdesc%s%s (the "
				"names must be the same, in any order)",
				h->name, s->mind->bot_name, ms, ma);
	for (unsigned i = 0; i < bd->n_sensors; i++)
		for (unsigned j = 0; j < h->n_sensors; j++)
			if (strcmp(mine_s[i], h->sensor[j]) == 0)
				r->sensor_at[i] = (int)j;
	for (unsigned j = 0; j < h->n_actuators; j++)
		for (unsigned i = 0; i < bd->n_actuators; i++)
			if (strcmp(mine_a[i], h->actuator[j]) == 0)
				r->actuator_of[j] = (int)i;
	snprintf(r->ch_sensors, sizeof r->ch_sensors, "EVO_%s_SENSORS",
		 h->name);
	snprintf(r->ch_command, sizeof r->ch_command, "EVO_%s_COMMAND",
		 h->name);
	snprintf(r->ch_control, sizeof r->ch_control, "EVO_%s_CONTROL",
		 h->name);
	r->link = s->link;
	int ttl = 0;
	char why[256];
	if (!evo_wire_url_ok(h->url, &ttl, why, sizeof why))
		return evo_fail(err, "remote %s: its episodes' URL: %s", h->name,
				why);
	if (ttl > s->url_ttl)
		return evo_fail(err,
				"remote %s: its episodes' URL %s reaches further "
				"(ttl=%d) than the task's %s",
				h->name, h->url, ttl, evo_link_url(s->link));
	if (h->url[0] && strcmp(h->url, evo_link_url(s->link)) != 0) {
		r->link = NULL;
		for (int i = 1; i < s->n_links && !r->link; i++)
			if (strcmp(evo_link_url(s->links[i]), h->url) == 0)
				r->link = s->links[i];
		if (!r->link) {
			evo_err inner;
			r->link = evo_link_open(h->url, &inner);
			if (!r->link)
				return evo_fail(err,
						"remote %s: its episodes' URL: "
						"%s",
						h->name, inner.msg);
			if (s->opts.key.len)
				evo_link_set_key(r->link, &s->opts.key, "evo");
			s->links[s->n_links++] = r->link;
		}
	}
	return evo_link_subscribe(r->link, r->ch_sensors, err);
}

static int send_who(evo_remotes *s, evo_err *err)
{
	evo_wire_who w = {.protocol = EVO_WIRE_PROTOCOL};
	if (s->opts.self)
		snprintf(w.from, sizeof w.from, "%s", s->opts.self);
	else
		snprintf(w.from, sizeof w.from, "evo-%ld", (long)getpid());
	unsigned char buf[256];
	int n = evo_wire_encode_who(&w, buf, sizeof buf);
	if (n < 0)
		return evo_fail(err, "evo: cannot encode a who_t");
	return evo_link_publish(s->link, "EVO_WHO", buf, (size_t)n, err);
}

evo_remotes *evo_remotes_open(const evo_mindfolder *mind,
			      const evo_remote_opts *o, evo_err *err)
{
	/* the remotes of a task are the ones it names or that present its
	 * key: never whatever answers first on a URL the whole machine
	 * shares */
	if (evo_remote_opts_chosen(o, err))
		return NULL;
	evo_remotes *s = calloc(1, sizeof *s);
	if (!s) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	s->opts = *o;
	if (!(s->opts.timeout > 0))
		s->opts.timeout = EVO_REMOTE_DEFAULT_TIMEOUT;
	s->mind = mind;
	s->link = evo_link_open(o->url, err);
	s->links[0] = s->link;
	s->n_links = 1;
	s->url_ttl = s->link ? url_ttl(evo_link_url(s->link)) : 0;
	if (!s->link || evo_link_subscribe(s->link, "EVO_HELLO", err)) {
		evo_link_close(s->link);
		memset(&s->opts.key, 0, sizeof s->opts.key);
		free(s);
		return NULL;
	}
	if (o->key.len)
		evo_link_set_key(s->link, &o->key, "evo");
	return s;
}

static evo_remote *by_name(const evo_remotes *s, const char *name)
{
	for (int i = 0; i < s->n; i++)
		if (strcmp(s->r[i]->hello.name, name) == 0)
			return s->r[i];
	return NULL;
}

/* A hello on EVO_HELLO: a new remote taken, or -1 with err set. */
static int take_new(evo_remotes *s, const evo_wire_hello *h, int64_t stamp,
		    evo_err *err)
{
	const evo_remote_opts *o = &s->opts;
	if (!evo_remote_named(o, h->name))
		return 0;
	if (by_name(s, h->name))
		return 0;
	if (h->kind != o->kind) {
		if (o->name)
			return evo_fail(err,
					"remote %s is a %s; this task needs a "
					"%s",
					h->name, kind_name(h->kind),
					kind_name(o->kind));
		return 0;
	}
	if (s->n == EVO_REMOTE_MAX_REMOTES)
		return 0;
	evo_remote *r = calloc(1, sizeof *r);
	if (!r)
		return evo_fail(err, "out of memory");
	r->set = s;
	r->hello = *h;
	r->fresh_hello.last = stamp;
	r->heard_at = now();
	s->r[s->n++] = r;
	if (accept(s, r, err) == 0)
		return 0;
	if (o->name && !strchr(o->name, ','))
		return -1;
	/* any remote would do: one that does not fit is passed over, with
	 * why, and evo waits for another */
	if (strcmp(s->passed_over, h->name) != 0)
		fprintf(stderr, "evo: %s; passed over\n", err->msg);
	snprintf(s->passed_over, sizeof s->passed_over, "%s", h->name);
	err->msg[0] = 0;
	free(s->r[--s->n]);
	return 0;
}

int evo_remotes_find(evo_remotes *s, double window, evo_err *err)
{
	const evo_remote_opts *o = &s->opts;
	double start = now(), asked = 0, told = start, until = 0;
	for (;;) {
		if (stopped(o, err))
			return -1;
		double t = now();
		if (s->n && t >= until)
			return 0;
		if (t - asked >= WHO_EVERY_S) {
			if (send_who(s, err))
				return -1;
			asked = t;
		}
		if (!s->n && t - told >= o->timeout) {
			fprintf(stderr,
				"evo: no %s%s%s has answered on %s for %.0f s; "
				"waiting (Ctrl-C stops)\n",
				kind_name(o->kind), o->name ? " named " : "",
				o->name ? o->name : "", evo_link_url(s->link),
				t - start);
			told = t;
		}
		evo_link_msg m;
		int got = evo_link_next(s->link, SLICE_MS, &m, err);
		if (got < 0)
			return -1;
		if (!got || strcmp(m.channel, "EVO_HELLO") != 0)
			continue;
		evo_wire_hello h;
		char why[256];
		if (evo_wire_decode_hello(m.data, m.len, &h, why, sizeof why)) {
			/* the remote the task names, refused: no use waiting
			 * for another */
			if (o->name && h.name[0] && evo_remote_named(o, h.name))
				return evo_fail(err,
						"evo: refused the hello of remote "
						"%s on %s: %s",
						h.name, evo_link_url(s->link),
						why);
			if (s->undecodable_hellos++ == 0)
				fprintf(stderr,
					"evo: dropped a hello_t on EVO_HELLO "
					"(%s)\n",
					why);
			continue;
		}
		int had = s->n;
		if (take_new(s, &h, m.stamp, err))
			return -1;
		if (!had && s->n)
			until = window > 0 ? now() + window : 0;
	}
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
		r->heard_at = now();
	e->sent_len = len;
	snprintf(e->sent_channel, sizeof e->sent_channel, "%s", channel);
	e->sent_at = now();
	e->waiting = 1;
	e->have = 0;
	return evo_link_publish(r->link, channel, e->sent, (size_t)len, err);
}

/* Two sensors_t of one tick: the same values, reward and end. A simulator
 * repeats its answer byte for byte, and a robot sends each tick once. */
static int same_sensors(const evo_wire_sensors *a, const evo_wire_sensors *b)
{
	if (a->n != b->n || a->done != b->done ||
	    memcmp(&a->reward, &b->reward, sizeof a->reward) != 0)
		return 0;
	return memcmp(a->value, b->value, a->n * sizeof *a->value) == 0;
}

/* A second, different answer for a tick already taken: two processes
 * answer under r's name, and evo cannot tell which is the remote. The
 * run ends rather than go on with values that may be forged. */
static int conflict(evo_remote *r, const evo_wire_sensors *s, evo_err *err)
{
	r->dropped[EVO_WIRE_CONFLICT]++;
	return evo_fail(err,
			"remote %s: two different sensors_t for tick %lld of "
			"episode %lld (environment %d): another process answers "
			"as %s on %s, and evo cannot tell which is the remote; "
			"a key (LCMKEYFILE, docs/remote.md) keeps others out",
			r->hello.name, (long long)s->tick,
			(long long)s->episode, (int)s->env, r->hello.name,
			evo_link_url(r->link));
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
		fprintf(stderr,
			"evo: remote %s: a hello under its name with session "
			"%lld came while its session %lld answers on: not taken "
			"as a restart (another process says hello as %s; a key, "
			"LCMKEYFILE, keeps it out); later ones are counted\n",
			r->hello.name, (long long)r->new_session,
			(long long)r->hello.session, r->hello.name);
}

/* A sensors_t: keep it when it is the one its environment awaits. */
static int take_sensors(evo_remote *r, const evo_link_msg *m, evo_err *err)
{
	evo_wire_sensors s;
	char why[256];
	evo_wire_reason rc =
	    evo_wire_decode_sensors(m->data, m->len, &s, why, sizeof why);
	if (rc) {
		dropped(r, rc, "sensors_t", why);
		return 0;
	}
	if (strcmp(s.name, r->hello.name) != 0 ||
	    s.session != r->hello.session || s.env < 0 ||
	    s.env >= r->hello.environments || s.env >= EVO_REMOTE_MAX_ENVS) {
		snprintf(why, sizeof why,
			 "from %s, session %lld, environment %d",
			 s.name, (long long)s.session, (int)s.env);
		dropped(r, EVO_WIRE_FOREIGN, "sensors_t", why);
		return 0;
	}
	if (s.n != r->hello.n_sensors) {
		snprintf(why, sizeof why, "%u values; its hello says %u", s.n,
			 r->hello.n_sensors);
		dropped(r, EVO_WIRE_COUNTS, "sensors_t", why);
		return 0;
	}
	rc = evo_wire_fresh_take(&r->fresh_sensors, m->stamp, why, sizeof why);
	if (rc) {
		dropped(r, rc, "sensors_t", why);
		return 0;
	}
	answers_on(r, m);
	evo_remote_env *e = &r->env[s.env];
	if (e->taken && s.episode == e->sensors.episode &&
	    s.tick == e->sensors.tick && !same_sensors(&s, &e->sensors))
		return conflict(r, &s, err);
	if (!e->waiting || s.episode < e->episode ||
	    (s.episode == e->episode && (s.tick < e->tick || e->have))) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; evo is at tick %lld of "
			 "episode %lld",
			 (long long)s.tick, (long long)s.episode,
			 (long long)e->tick, (long long)e->episode);
		dropped(r, EVO_WIRE_STALE, "sensors_t", why);
		return 0;
	}
	if (s.episode > e->episode || s.tick > e->tick) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; evo waits for tick %lld "
			 "of episode %lld",
			 (long long)s.tick, (long long)s.episode,
			 (long long)e->tick, (long long)e->episode);
		dropped(r, EVO_WIRE_AHEAD, "sensors_t", why);
		return 0;
	}
	r->heard_at = now();
	rc = evo_wire_check_values(s.value, s.n, &s.reward, why, sizeof why);
	if (!rc)
		rc = evo_wire_check_behaviour(&s, why, sizeof why);
	if (rc) {
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
static void take_hello(evo_remotes *s, const evo_link_msg *m)
{
	evo_wire_hello h;
	char why[256];
	if (evo_wire_decode_hello(m->data, m->len, &h, why, sizeof why))
		return;
	evo_remote *r = by_name(s, h.name);
	if (!r || r->lost || h.session == r->hello.session)
		return;
	if (evo_wire_fresh_take(&r->fresh_hello, m->stamp, why, sizeof why)) {
		dropped(r, EVO_WIRE_REPLAYED, "hello_t", why);
		return;
	}
	if (r->new_session_at)
		return;
	r->new_session = h.session;
	r->new_session_at = s->opts.key.len ? now() - RESTART_GRACE_S : now();
	r->new_session_recv =
	    m->recv_utime > 0 ? m->recv_utime : real_us();
}

/* A remote whose restart is now certain: -1 with err set, or (lose_silent)
 * 1 with *ri the remote, taken as lost. 0: none. */
static int restarted(evo_remotes *s, int *ri, evo_err *err)
{
	double t = now();
	for (int i = 0; i < s->n; i++) {
		evo_remote *r = s->r[i];
		if (r->lost || !r->new_session_at ||
		    t - r->new_session_at < RESTART_GRACE_S)
			continue;
		if (!s->opts.lose_silent)
			return evo_fail(err,
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
		if (stopped(&s->opts, err))
			return -1;
		int rs = restarted(s, ri, err);
		if (rs)
			return rs < 0 ? -1 : 1;
		double t = now();
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
				if (t - v->sent_at >= RESEND_S) {
					v->sent_at = t;
					r->resent++;
					if (evo_link_publish(
						r->link, v->sent_channel,
						v->sent, (size_t)v->sent_len,
						err))
						return -1;
				}
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
			take_hello(s, &m);
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
	evo_wire_command c = {
	    .session = r->hello.session,
	    .env = env,
	    .episode = e->episode,
	    .tick = e->tick,
	    .n = r->hello.n_actuators,
	};
	snprintf(c.name, sizeof c.name, "%s", r->hello.name);
	for (unsigned j = 0; j < c.n; j++)
		c.value[j] = commands[r->actuator_of[j]];
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
		for (int i = 0;
		     !r->lost && i < r->hello.environments &&
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

/* ---- a robot: free running ---------------------------------------------- */

static double real_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int evo_robot_start(evo_remotes *s, evo_robot *rb, int64_t episode,
		    uint64_t layout_seed, uint64_t seed, evo_err *err)
{
	if (s->n < 1)
		return evo_fail(err, "evo: no robot to start");
	const evo_wire_hello *h = &s->r[0]->hello;
	if (h->kind != EVO_REMOTE_ROBOT)
		return evo_fail(err, "remote %s is a %s, not a robot", h->name,
				kind_name(h->kind));
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
	evo_wire_reason rc =
	    evo_wire_decode_sensors(m->data, m->len, &s, why, sizeof why);
	if (rc) {
		dropped(r, rc, "sensors_t", why);
		return 0;
	}
	if (strcmp(s.name, r->hello.name) != 0 ||
	    s.session != r->hello.session || s.env != 0) {
		snprintf(why, sizeof why,
			 "from %s, session %lld, environment %d", s.name,
			 (long long)s.session, (int)s.env);
		dropped(r, EVO_WIRE_FOREIGN, "sensors_t", why);
		return 0;
	}
	if (s.n != r->hello.n_sensors) {
		snprintf(why, sizeof why, "%u values; its hello says %u", s.n,
			 r->hello.n_sensors);
		dropped(r, EVO_WIRE_COUNTS, "sensors_t", why);
		return 0;
	}
	rc = evo_wire_fresh_take(&r->fresh_sensors, m->stamp, why, sizeof why);
	if (rc) {
		dropped(r, rc, "sensors_t", why);
		return 0;
	}
	answers_on(r, m);
	if (rb->tick >= 0 && s.episode == rb->episode && s.tick == rb->tick &&
	    !same_sensors(&s, &r->env[0].sensors)) {
		rb->conflict = 1;
		return 0;
	}
	double t = now();
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
		dropped(r, EVO_WIRE_STALE, "sensors_t", why);
		return 0;
	}
	if (s.episode > rb->episode) {
		snprintf(why, sizeof why,
			 "tick %lld of episode %lld; evo runs episode %lld",
			 (long long)s.tick, (long long)s.episode,
			 (long long)rb->episode);
		dropped(r, EVO_WIRE_AHEAD, "sensors_t", why);
		return 0;
	}
	/* A robot's bad value costs that tick only: the robot holds its
	 * commands, and the next tick comes anyway. */
	rc = evo_wire_check_values(s.value, s.n, &s.reward, why, sizeof why);
	if (rc) {
		char w2[300];
		snprintf(w2, sizeof w2, "tick %lld: %s", (long long)s.tick, why);
		dropped(r, rc, "sensors_t", w2);
		return 0;
	}
	double arrived = m->recv_utime > 0 ? (double)m->recv_utime * 1e-6
					   : real_now();
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
	double until = now() + (timeout_ms > 0 ? timeout_ms : 0) * 1e-3;
	int held = 0;
	for (;;) {
		if (stopped(&s->opts, err))
			return -1;
		int ri;
		if (restarted(s, &ri, err))
			return -1;
		if (rb->conflict)
			return conflict(r, &r->env[0].sensors, err);
		double t = now();
		evo_remote_env *e = &r->env[0];
		if (rb->tick < 0 && t - e->sent_at >= RESEND_S) {
			e->sent_at = t;
			r->resent++;
			if (evo_link_publish(r->link, e->sent_channel, e->sent,
					     (size_t)e->sent_len, err))
				return -1;
		}
		if (t - r->heard_at >= s->opts.timeout &&
		    t - r->told_at >= s->opts.timeout) {
			fprintf(stderr,
				"evo: robot %s silent for %.1f s; waiting "
				"(Ctrl-C stops); a robot goes neutral on its "
				"own\n",
				r->hello.name, t - r->heard_at);
			r->told_at = t;
		}
		/* once a tick is held, only what has already come: the
		 * newest of it */
		int wait_ms = 0;
		if (!held) {
			double left = until - t;
			if (left <= 0)
				return 2;
			wait_ms = (int)(left * 1e3) + 1;
			if (wait_ms > SLICE_MS)
				wait_ms = SLICE_MS;
		}
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
			take_hello(s, &m);
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
	rb->answered_at = real_now();
	double delay = rb->answered_at - rb->arrived;
	if (delay > rb->period) {
		rb->late++;
		char what[96];
		snprintf(what, sizeof what,
			 "was answered %.0f ms after it came, past its period "
			 "(%.0f ms)",
			 delay * 1e3, rb->period * 1e3);
		tell_late(rb, what);
	} else {
		rb->in_time++;
		rb->in_time_held = 1;
	}
	evo_wire_command c = {
	    .session = r->hello.session,
	    .env = 0,
	    .episode = rb->episode,
	    .tick = rb->tick,
	    .n = r->hello.n_actuators,
	};
	snprintf(c.name, sizeof c.name, "%s", r->hello.name);
	for (unsigned j = 0; j < c.n; j++)
		c.value[j] = commands[r->actuator_of[j]];
	unsigned char buf[EVO_WIRE_MAX_BYTES];
	int n = evo_wire_encode_command(&c, buf, sizeof buf);
	if (n < 0)
		return evo_fail(err, "evo: cannot encode a command_t");
	return evo_link_publish(r->link, r->ch_command, buf, (size_t)n, err);
}

double evo_robot_quiet(const evo_robot *rb)
{
	return now() - rb->set->r[0]->heard_at;
}

void evo_robot_report(const evo_robot *rb)
{
	printf("robot %s: %lu ticks: %lu answered in time, %lu late (%lu "
	       "unanswered), %lu missing\n",
	       rb->set->r[0]->hello.name,
	       rb->in_time + rb->late + rb->missing, rb->in_time, rb->late,
	       rb->unanswered, rb->missing);
	fflush(stdout);
}
