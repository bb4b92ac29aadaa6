/* evo — finding a task's remotes (sim/remote/session.h): the task's remote
 * keys (LCMURL, REMOTENAME, REMOTETIMEOUT, LCMKEYFILE), the connection to
 * the URL, asking who is there, and checking each remote that answers
 * against the mind's botdesc (protocol, kind, sensor and actuator names),
 * which gives its name maps and its channels. */
#define _POSIX_C_SOURCE 200809L
#include "remote/session_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define WHO_EVERY_S 0.5

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
	if (o->url &&
	    (!o->url[0] || !evo_wire_url_ok(o->url, &ttl, uwhy, sizeof uwhy)))
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
		return evo_fail(err, "remote %s: its episodes' URL: %s",
				h->name, why);
	if (ttl > s->url_ttl)
		return evo_fail(
		    err,
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

/* A hello on EVO_HELLO: a new remote taken, or -1 with err set. */
static int take_new(evo_remotes *s, const evo_wire_hello *h, int64_t stamp,
		    evo_err *err)
{
	const evo_remote_opts *o = &s->opts;
	if (!evo_remote_named(o, h->name))
		return 0;
	if (evo_session_by_name(s, h->name))
		return 0;
	if (h->kind != o->kind) {
		if (o->name)
			return evo_fail(err,
					"remote %s is a %s; this task needs a "
					"%s",
					h->name, evo_session_kind_name(h->kind),
					evo_session_kind_name(o->kind));
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
	r->heard_at = evo_clock_now();
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
	snprintf(s->passed_why, sizeof s->passed_why, "%.1000s", err->msg);
	err->msg[0] = 0;
	free(s->r[--s->n]);
	return 0;
}

int evo_remotes_find(evo_remotes *s, double window, evo_err *err)
{
	const evo_remote_opts *o = &s->opts;
	double start = evo_clock_now(), asked = 0, told = start, until = 0;
	for (;;) {
		if (evo_session_stopped(o, err))
			return -1;
		double t = evo_clock_now();
		if (s->n && t >= until)
			return 0;
		if (t - asked >= WHO_EVERY_S) {
			if (send_who(s, err))
				return -1;
			asked = t;
		}
		if (!s->n && t - told >= o->timeout && s->passed_over[0]) {
			/* one answered: say which, and why it would not do */
			fprintf(stderr,
				"evo: no %s%s%s that fits has answered on %s "
				"for %.0f s; %s answered and was passed over "
				"(%s); waiting (Ctrl-C stops)\n",
				evo_session_kind_name(o->kind),
				o->name ? " named " : "",
				o->name ? o->name : "", evo_link_url(s->link),
				t - start, s->passed_over,
				strncmp(s->passed_why, "evo: ", 5) == 0
				    ? s->passed_why + 5
				    : s->passed_why);
			told = t;
		} else if (!s->n && t - told >= o->timeout) {
			fprintf(stderr,
				"evo: no %s%s%s has answered on %s for %.0f s; "
				"waiting (Ctrl-C stops)\n",
				evo_session_kind_name(o->kind),
				o->name ? " named " : "",
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
				return evo_fail(
				    err,
				    "evo: refused the hello of remote "
				    "%s on %s: %s",
				    h.name, evo_link_url(s->link), why);
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
			until = window > 0 ? evo_clock_now() + window : 0;
	}
}
