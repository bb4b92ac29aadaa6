/* The remote protocol's messages: checked walks, then lcm-gen's code
 * (sim/remote/wire.h). */
#define _POSIX_C_SOURCE 200809L
#include "remote/wire.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "evo/mac.h"

/* lcm-gen's C for lcmtypes/evo_remote.lcm, made at build time */
#include <evo_lcm_command_t.h>
#include <evo_lcm_control_t.h>
#include <evo_lcm_hello_t.h>
#include <evo_lcm_sensors_t.h>
#include <evo_lcm_who_t.h>

const char *evo_wire_reason_name(evo_wire_reason r)
{
	static const char *const names[EVO_WIRE_N_REASONS] = {
	    "ok",    "undecodable", "foreign",	"counts",  "value",
	    "stale", "ahead",	    "forged",	"replayed", "conflict"};
	return (unsigned)r < EVO_WIRE_N_REASONS ? names[r] : "?";
}

int evo_wire_name_ok(const char *name)
{
	size_t n = strlen(name);
	if (n < 1 || n >= EVO_REMOTE_NAME_MAX)
		return 0;
	for (size_t i = 0; i < n; i++) {
		char c = name[i];
		if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
		      (c >= '0' && c <= '9') || c == '_' || c == '-'))
			return 0;
	}
	return 1;
}

/* ---- the walk ---------------------------------------------------------- */

/* One field of a message, as LCM lays it out (big-endian). */
typedef enum field_kind {
	F_I8,	/* int8_t or boolean: 1 byte */
	F_I32,	/* 4 bytes */
	F_I64,	/* 8 bytes */
	F_F64,	/* 8 bytes */
	F_STR,	/* int32 length with the NUL, the bytes, the NUL */
	F_COUNT, /* an int32 count 0..max, for the next array */
	F_STRS, /* `count` strings */
	F_F64S	/* `count` doubles */
} field_kind;

typedef struct field {
	field_kind kind;
	unsigned max; /* F_STR, F_STRS: bytes with the NUL; F_COUNT: count */
	const char *name;
} field;

static int32_t be32(const unsigned char *p)
{
	return (int32_t)((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 |
			 (uint32_t)p[2] << 8 | (uint32_t)p[3]);
}

static uint64_t be64(const unsigned char *p)
{
	return (uint64_t)(uint32_t)be32(p) << 32 | (uint32_t)be32(p + 4);
}

/* Walk buf: the type's fingerprint, then each field within the bytes and
 * the limits. 0, or -1 with why. */
static int walk(const unsigned char *buf, size_t len, int64_t hash,
		const field *f, unsigned nf, const char *type, char *why,
		size_t cap)
{
	if (len > EVO_WIRE_MAX_BYTES) {
		snprintf(why, cap, "%s: %zu bytes, more than evo takes (%d)",
			 type, len, EVO_WIRE_MAX_BYTES);
		return -1;
	}
	if (len < 8 || be64(buf) != (uint64_t)hash) {
		snprintf(why, cap, "not an evo_lcm.%s (its fingerprint differs)",
			 type);
		return -1;
	}
	size_t pos = 8;
	int32_t count = 0;
	const char *at = "";
	for (unsigned i = 0; i < nf; i++) {
		size_t left = len - pos;
		at = f[i].name;
		unsigned n = 1;
		switch (f[i].kind) {
		case F_I8:
			if (left < 1)
				goto short_;
			pos += 1;
			break;
		case F_I32:
			if (left < 4)
				goto short_;
			pos += 4;
			break;
		case F_I64:
		case F_F64:
			if (left < 8)
				goto short_;
			pos += 8;
			break;
		case F_COUNT:
			if (left < 4)
				goto short_;
			count = be32(buf + pos);
			if (count < 0 || (unsigned)count > f[i].max) {
				snprintf(why, cap,
					 "%s.%s is %ld, outside 0..%u", type,
					 f[i].name, (long)count, f[i].max);
				return -1;
			}
			pos += 4;
			break;
		case F_F64S:
			if (left / 8 < (size_t)count)
				goto short_;
			pos += 8 * (size_t)count;
			break;
		case F_STRS:
			n = (unsigned)count;
			/* fall through */
		case F_STR:
			for (unsigned k = 0; k < n; k++) {
				left = len - pos;
				if (left < 4)
					goto short_;
				int32_t sl = be32(buf + pos);
				if (sl < 1 || (unsigned)sl > f[i].max) {
					snprintf(why, cap,
						 "%s.%s: a string of %ld bytes "
						 "(1..%u with its NUL)",
						 type, f[i].name, (long)sl,
						 f[i].max);
					return -1;
				}
				if (left - 4 < (size_t)sl)
					goto short_;
				const unsigned char *s = buf + pos + 4;
				if (s[sl - 1] != 0 || memchr(s, 0, (size_t)sl - 1)) {
					snprintf(why, cap,
						 "%s.%s: a string not ended by "
						 "its one NUL",
						 type, f[i].name);
					return -1;
				}
				pos += 4 + (size_t)sl;
			}
			break;
		}
	}
	if (pos != len) {
		snprintf(why, cap, "%s: %zu bytes past its end", type,
			 len - pos);
		return -1;
	}
	return 0;
short_:
	snprintf(why, cap, "%s: cut short at %s (%zu bytes)", type, at, len);
	return -1;
}

/* ---- the types ------------------------------------------------------------ */

static const field hello_fields[] = {
    {F_I32, 0, "protocol"},
    {F_STR, EVO_REMOTE_NAME_MAX, "name"},
    {F_I64, 0, "session"},
    {F_STR, EVO_REMOTE_URL_MAX, "url"},
    {F_I8, 0, "kind"},
    {F_I32, 0, "environments"},
    {F_I32, 0, "tick_us"},
    {F_COUNT, EVO_MAX_SENSORS, "n_sensors"},
    {F_STRS, EVO_NAME_MAX, "sensors"},
    {F_COUNT, EVO_MAX_ACTUATORS, "n_actuators"},
    {F_STRS, EVO_NAME_MAX, "actuators"},
};

static const field who_fields[] = {
    {F_I32, 0, "protocol"},
    {F_STR, EVO_REMOTE_NAME_MAX, "sender"},
};

static const field control_fields[] = {
    {F_STR, EVO_REMOTE_NAME_MAX, "name"},
    {F_I64, 0, "session"},
    {F_I32, 0, "env"},
    {F_I8, 0, "op"},
    {F_I64, 0, "episode"},
    {F_I64, 0, "layout_seed"},
    {F_I64, 0, "seed"},
};

/* sensors_t and command_t begin alike: the episode's place, the tick and
 * at most `most` values. */
#define TICK_FIELDS(most)                                                    \
	{F_STR, EVO_REMOTE_NAME_MAX, "name"}, {F_I64, 0, "session"},         \
	    {F_I32, 0, "env"}, {F_I64, 0, "episode"}, {F_I64, 0, "tick"},    \
	    {F_COUNT, most, "n"}, {F_F64S, 0, "values"}

static const field sensors_fields[] = {
    TICK_FIELDS(EVO_MAX_SENSORS),
    {F_F64, 0, "reward"},
    {F_I8, 0, "done"},
    {F_COUNT, EVO_WIRE_MAX_BEHAVIOUR, "n_behaviour"},
    {F_F64S, 0, "behaviour"},
};

static const field command_fields[] = {TICK_FIELDS(EVO_MAX_ACTUATORS)};

#define NF(a) (unsigned)(sizeof(a) / sizeof(a)[0])

static void copy_name(char *dst, size_t cap, const char *src)
{
	snprintf(dst, cap, "%s", src);
}

static evo_wire_reason bad(char *why, size_t cap, const char *fmt,
			   const char *type)
{
	snprintf(why, cap, fmt, type);
	return EVO_WIRE_UNDECODABLE;
}

/* Walk the bytes of a message of lcm type evo_lcm_<t>, by its `fields`,
 * then let lcm-gen's decoder fill m; return from the caller with the
 * reason when either refuses it. */
#define DECODE(t, fields, m, buf, len, why, cap)                             \
	do {                                                                 \
		if (walk(buf, len, __evo_lcm_##t##_get_hash(), fields,       \
			 NF(fields), #t, why, cap))                          \
			return EVO_WIRE_UNDECODABLE;                         \
		if (evo_lcm_##t##_decode(buf, 0, (int)len, &(m)) < 0)        \
			return bad(why, cap, "%s: refused by its decoder",   \
				   #t);                                      \
	} while (0)

/* What every message of an episode starts with: out cleared, then its
 * remote's name, session, env and episode from the decoded m. */
#define TAKE_PLACE(out, m)                                                   \
	do {                                                                 \
		memset(out, 0, sizeof *(out));                               \
		copy_name((out)->name, sizeof (out)->name, (m).name);        \
		(out)->session = (m).session;                                \
		(out)->env = (m).env;                                        \
		(out)->episode = (m).episode;                                \
	} while (0)

/* A tick's values (sensors or commands) from the decoded m. */
#define TAKE_VALUES(out, m)                                                  \
	do {                                                                 \
		(out)->tick = (m).tick;                                      \
		(out)->n = (unsigned)(m).n;                                  \
		if ((out)->n)                                                \
			memcpy((out)->value, (m).values,                     \
			       (out)->n * sizeof *(out)->value);             \
	} while (0)

evo_wire_reason evo_wire_decode_hello(const void *buf, size_t len,
				      evo_wire_hello *out, char *why, size_t cap)
{
	out->name[0] = 0;
	evo_lcm_hello_t m;
	DECODE(hello_t, hello_fields, m, buf, len, why, cap);
	memset(out, 0, sizeof *out);
	out->protocol = m.protocol;
	copy_name(out->name, sizeof out->name, m.name);
	out->session = m.session;
	copy_name(out->url, sizeof out->url, m.url);
	out->kind = m.kind == EVO_LCM_HELLO_T_SIMULATOR ? EVO_REMOTE_SIMULATOR
							 : EVO_REMOTE_ROBOT;
	out->environments = m.environments;
	out->tick_us = m.tick_us;
	out->n_sensors = (unsigned)m.n_sensors;
	out->n_actuators = (unsigned)m.n_actuators;
	for (unsigned i = 0; i < out->n_sensors; i++)
		copy_name(out->sensor[i], EVO_NAME_MAX, m.sensors[i]);
	for (unsigned i = 0; i < out->n_actuators; i++)
		copy_name(out->actuator[i], EVO_NAME_MAX, m.actuators[i]);
	int kind = m.kind;
	evo_lcm_hello_t_decode_cleanup(&m);
	if (!evo_wire_name_ok(out->name)) {
		out->name[0] = 0;
		return bad(why, cap,
			   "%s: a remote's name is 1..63 letters, digits, '_' "
			   "or '-'",
			   "hello_t");
	}
	char from[EVO_REMOTE_NAME_MAX + 16];
	snprintf(from, sizeof from, "hello_t from %s", out->name);
	if (kind != EVO_LCM_HELLO_T_ROBOT && kind != EVO_LCM_HELLO_T_SIMULATOR)
		return bad(why, cap, "%s: kind is neither ROBOT nor SIMULATOR",
			   from);
	if (out->environments < 1 || out->environments > EVO_WIRE_MAX_ENVS) {
		snprintf(why, cap, "%s: environments is %ld, outside 1..%d",
			 from, (long)out->environments, EVO_WIRE_MAX_ENVS);
		return EVO_WIRE_UNDECODABLE;
	}
	if (out->kind == EVO_REMOTE_ROBOT && out->environments != 1)
		return bad(why, cap,
			   "%s: environments must be 1 for a robot, at least "
			   "1 for a simulator",
			   from);
	if (out->tick_us < 0 || out->tick_us > EVO_WIRE_MAX_TICK_US) {
		snprintf(why, cap, "%s: tick_us is %ld, outside 0..%d", from,
			 (long)out->tick_us, EVO_WIRE_MAX_TICK_US);
		return EVO_WIRE_UNDECODABLE;
	}
	char uw[200];
	int ttl;
	if (!evo_wire_url_ok(out->url, &ttl, uw, sizeof uw)) {
		snprintf(why, cap, "%s: url: %s", from, uw);
		return EVO_WIRE_UNDECODABLE;
	}
	return EVO_WIRE_OK;
}

/* env, episode and tick of a message of an episode: within evo's limits,
 * so that no reader indexes past its environments. */
static evo_wire_reason check_place(const char *type, const char *name,
				   int32_t env, int64_t episode,
				   const int64_t *tick, char *why, size_t cap)
{
	if (env < 0 || env >= EVO_WIRE_MAX_ENVS) {
		snprintf(why, cap, "%s for %s: env is %ld, outside 0..%d", type,
			 name, (long)env, EVO_WIRE_MAX_ENVS - 1);
		return EVO_WIRE_UNDECODABLE;
	}
	if (episode < 0) {
		snprintf(why, cap, "%s for %s: episode is %lld, negative",
			 type, name, (long long)episode);
		return EVO_WIRE_UNDECODABLE;
	}
	if (tick && *tick < 0) {
		snprintf(why, cap, "%s for %s: tick is %lld, negative", type,
			 name, (long long)*tick);
		return EVO_WIRE_UNDECODABLE;
	}
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_decode_who(const void *buf, size_t len, evo_wire_who *out,
				    char *why, size_t cap)
{
	evo_lcm_who_t m;
	DECODE(who_t, who_fields, m, buf, len, why, cap);
	out->protocol = m.protocol;
	copy_name(out->from, sizeof out->from, m.sender);
	evo_lcm_who_t_decode_cleanup(&m);
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_decode_control(const void *buf, size_t len,
					evo_wire_control *out, char *why,
					size_t cap)
{
	evo_lcm_control_t m;
	DECODE(control_t, control_fields, m, buf, len, why, cap);
	TAKE_PLACE(out, m);
	out->op = (evo_wire_control_op)m.op;
	out->layout_seed = (uint64_t)m.layout_seed;
	out->seed = (uint64_t)m.seed;
	int op = m.op;
	evo_lcm_control_t_decode_cleanup(&m);
	if (op != EVO_LCM_CONTROL_T_RESET && op != EVO_LCM_CONTROL_T_STOP)
		return bad(why, cap, "%s: op is neither RESET nor STOP",
			   "control_t");
	return check_place("control_t", out->name, out->env, out->episode,
			   NULL, why, cap);
}

evo_wire_reason evo_wire_decode_sensors(const void *buf, size_t len,
					evo_wire_sensors *out, char *why,
					size_t cap)
{
	evo_lcm_sensors_t m;
	DECODE(sensors_t, sensors_fields, m, buf, len, why, cap);
	TAKE_PLACE(out, m);
	TAKE_VALUES(out, m);
	out->reward = m.reward;
	out->done = m.done != 0;
	out->n_behaviour = (unsigned)m.n_behaviour;
	if (out->n_behaviour)
		memcpy(out->behaviour, m.behaviour,
		       out->n_behaviour * sizeof *out->behaviour);
	evo_lcm_sensors_t_decode_cleanup(&m);
	return check_place("sensors_t", out->name, out->env, out->episode,
			   &out->tick, why, cap);
}

evo_wire_reason evo_wire_decode_command(const void *buf, size_t len,
					evo_wire_command *out, char *why,
					size_t cap)
{
	evo_lcm_command_t m;
	DECODE(command_t, command_fields, m, buf, len, why, cap);
	TAKE_PLACE(out, m);
	TAKE_VALUES(out, m);
	evo_lcm_command_t_decode_cleanup(&m);
	return check_place("command_t", out->name, out->env, out->episode,
			   &out->tick, why, cap);
}

evo_wire_reason evo_wire_check_values(const double *v, unsigned n,
				      const double *reward, char *why,
				      size_t cap)
{
	for (unsigned i = 0; i < n; i++)
		if (!(v[i] >= 0.0 && v[i] <= 1.0)) {
			snprintf(why, cap, "value %u is %g, outside [0, 1]", i,
				 v[i]);
			return EVO_WIRE_VALUE;
		}
	if (reward && !isfinite(*reward)) {
		snprintf(why, cap, "the reward is %g", *reward);
		return EVO_WIRE_VALUE;
	}
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_check_behaviour(const evo_wire_sensors *s, char *why,
					 size_t cap)
{
	for (unsigned i = 0; i < s->n_behaviour; i++)
		if (!(s->behaviour[i] >= 0.0 && s->behaviour[i] <= 1.0)) {
			snprintf(why, cap,
				 "behaviour value %u is %g, outside [0, 1]", i,
				 s->behaviour[i]);
			return EVO_WIRE_VALUE;
		}
	return EVO_WIRE_OK;
}

/* ---- encoding ------------------------------------------------------------- */

/* lcm-gen's structs hold char *, not const char *: the strings are only
 * read while encoding. */
static char *str(const char *s)
{
	return (char *)(uintptr_t)s;
}

/* The designated initialisers of a message of an episode's place (c:
 * its evo_wire_* struct) and of a tick's values. */
#define PLACE_OF(c)                                                          \
	.name = str((c)->name), .session = (c)->session, .env = (c)->env,    \
	.episode = (c)->episode
#define VALUES_OF(c)                                                         \
	.tick = (c)->tick, .n = (int32_t)(c)->n,                             \
	.values = (double *)(uintptr_t)(c)->value

#define ENCODE(type, m, buf, cap)                                            \
	do {                                                                 \
		int size_ = type##_encoded_size(m);                          \
		if (size_ < 0 || (size_t)size_ > (cap) ||                     \
		    (size_t)size_ > EVO_WIRE_MAX_BYTES)                      \
			return -1;                                           \
		return type##_encode(buf, 0, size_, m) < 0 ? -1 : size_;     \
	} while (0)

int evo_wire_encode_hello(const evo_wire_hello *h, void *buf, size_t cap)
{
	if (h->n_sensors > EVO_MAX_SENSORS ||
	    h->n_actuators > EVO_MAX_ACTUATORS || !evo_wire_name_ok(h->name))
		return -1;
	char *s[EVO_MAX_SENSORS], *a[EVO_MAX_ACTUATORS];
	for (unsigned i = 0; i < h->n_sensors; i++)
		s[i] = str(h->sensor[i]);
	for (unsigned i = 0; i < h->n_actuators; i++)
		a[i] = str(h->actuator[i]);
	evo_lcm_hello_t m = {
	    .protocol = h->protocol,
	    .name = str(h->name),
	    .session = h->session,
	    .url = str(h->url),
	    .kind = (int8_t)h->kind,
	    .environments = h->environments,
	    .tick_us = h->tick_us,
	    .n_sensors = (int32_t)h->n_sensors,
	    .sensors = s,
	    .n_actuators = (int32_t)h->n_actuators,
	    .actuators = a,
	};
	ENCODE(evo_lcm_hello_t, &m, buf, cap);
}

int evo_wire_encode_who(const evo_wire_who *w, void *buf, size_t cap)
{
	evo_lcm_who_t m = {.protocol = w->protocol, .sender = str(w->from)};
	ENCODE(evo_lcm_who_t, &m, buf, cap);
}

int evo_wire_encode_control(const evo_wire_control *c, void *buf, size_t cap)
{
	evo_lcm_control_t m = {
	    PLACE_OF(c),
	    .op = (int8_t)c->op,
	    .layout_seed = (int64_t)c->layout_seed,
	    .seed = (int64_t)c->seed,
	};
	ENCODE(evo_lcm_control_t, &m, buf, cap);
}

int evo_wire_encode_sensors(const evo_wire_sensors *s, void *buf, size_t cap)
{
	if (s->n > EVO_MAX_SENSORS || s->n_behaviour > EVO_WIRE_MAX_BEHAVIOUR)
		return -1;
	evo_lcm_sensors_t m = {
	    PLACE_OF(s),
	    VALUES_OF(s),
	    .reward = s->reward,
	    .done = (int8_t)(s->done != 0),
	    .n_behaviour = (int32_t)s->n_behaviour,
	    .behaviour = (double *)(uintptr_t)s->behaviour,
	};
	ENCODE(evo_lcm_sensors_t, &m, buf, cap);
}

int evo_wire_encode_command(const evo_wire_command *c, void *buf, size_t cap)
{
	if (c->n > EVO_MAX_ACTUATORS)
		return -1;
	evo_lcm_command_t m = {PLACE_OF(c), VALUES_OF(c)};
	ENCODE(evo_lcm_command_t, &m, buf, cap);
}

/* ---- URLs ------------------------------------------------------------------ */

/* A decimal number lo..hi at *p, which is moved past it. */
static int number(const char **p, long lo, long hi, long *v)
{
	const char *s = *p;
	long n = 0;
	if (*s < '0' || *s > '9')
		return 0;
	while (*s >= '0' && *s <= '9') {
		n = n * 10 + (*s++ - '0');
		if (n > hi)
			return 0;
	}
	if (n < lo)
		return 0;
	*v = n;
	*p = s;
	return 1;
}

int evo_wire_url_ok(const char *url, int *ttl, char *why, size_t cap)
{
	*ttl = 0;
	if (!url[0])
		return 1;
	if (strncmp(url, "udpm://", 7) != 0) {
		snprintf(why, cap,
			 "'%.80s' is not udpm://GROUP:PORT (evo opens no other "
			 "LCM provider for a remote)",
			 url);
		return 0;
	}
	const char *p = url + 7;
	long octet[4], port, v;
	for (int i = 0; i < 4; i++)
		if (!number(&p, 0, 255, &octet[i]) || *p++ != (i < 3 ? '.' : ':'))
			goto form;
	if (octet[0] < 224 || octet[0] > 239) {
		snprintf(why, cap,
			 "'%.80s': %ld.%ld.%ld.%ld is not a multicast group "
			 "(224.0.0.0 to 239.255.255.255)",
			 url, octet[0], octet[1], octet[2], octet[3]);
		return 0;
	}
	if (!number(&p, 1, 65535, &port))
		goto form;
	int seen_ttl = 0, seen_buf = 0;
	char sep = '?';
	while (*p) {
		if (*p++ != sep)
			goto form;
		sep = '&';
		if (strncmp(p, "ttl=", 4) == 0 && !seen_ttl) {
			p += 4;
			if (!number(&p, 0, 1, &v)) {
				snprintf(why, cap,
					 "'%.80s': ttl must be 0 (this machine) "
					 "or 1 (the local network)",
					 url);
				return 0;
			}
			*ttl = (int)v;
			seen_ttl = 1;
		} else if (strncmp(p, "recv_buf_size=", 14) == 0 && !seen_buf) {
			p += 14;
			if (!number(&p, 1, 16L << 20, &v))
				goto form;
			seen_buf = 1;
		} else {
			snprintf(why, cap,
				 "'%.80s': an option other than ttl=0|1 and "
				 "recv_buf_size=N, or one given twice",
				 url);
			return 0;
		}
	}
	return 1;
form:
	snprintf(why, cap,
		 "'%.80s' is not udpm://A.B.C.D:PORT[?ttl=0|1][&recv_buf_size=N]",
		 url);
	return 0;
}

/* ---- the shared key ------------------------------------------------------ */

int evo_wire_key_read(const char *path, evo_wire_key *k, char *why, size_t cap)
{
	memset(k, 0, sizeof *k);
	int fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0) {
		snprintf(why, cap, "key file %s: %s", path, strerror(errno));
		return -1;
	}
	unsigned char buf[EVO_WIRE_KEY_MAX + 2];
	size_t n = 0;
	for (;;) {
		ssize_t r = read(fd, buf + n, sizeof buf - n);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			snprintf(why, cap, "key file %s: %s", path,
				 strerror(errno));
			close(fd);
			return -1;
		}
		if (r == 0 || (n += (size_t)r) == sizeof buf)
			break;
	}
	close(fd);
	if (n && buf[n - 1] == '\n')
		n--;
	if (n && buf[n - 1] == '\r')
		n--;
	if (n < EVO_WIRE_KEY_MIN || n > EVO_WIRE_KEY_MAX) {
		memset(buf, 0, sizeof buf);
		snprintf(why, cap,
			 "key file %s: a key is %d to %d bytes (one line, "
			 "e.g. of `head -c 32 /dev/urandom | base64`); this "
			 "file holds %s",
			 path, EVO_WIRE_KEY_MIN, EVO_WIRE_KEY_MAX,
			 n < EVO_WIRE_KEY_MIN ? "fewer" : "more");
		return -1;
	}
	memcpy(k->bytes, buf, n);
	k->len = n;
	memset(buf, 0, sizeof buf);
	return 0;
}

int64_t evo_wire_stamp(int64_t *last)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	int64_t t = (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
	if (t <= *last)
		t = *last + 1;
	*last = t;
	return t;
}

static void put64(unsigned char *p, int64_t v)
{
	for (int i = 0; i < 8; i++)
		p[i] = (unsigned char)((uint64_t)v >> (56 - 8 * i));
}

static void tag(const evo_wire_key *k, const char *channel,
		const unsigned char *body, size_t len,
		const unsigned char stamp[8], uint8_t out[EVO_WIRE_TAG_BYTES])
{
	evo_hmac h;
	evo_hmac_init(&h, k->bytes, k->len);
	evo_hmac_update(&h, channel, strlen(channel) + 1);
	evo_hmac_update(&h, body, len);
	evo_hmac_update(&h, stamp, 8);
	evo_hmac_final(&h, out);
}

int evo_wire_seal(const evo_wire_key *k, const char *channel, void *buf,
		  size_t len, size_t cap, int64_t stamp)
{
	if (len > cap || cap - len < EVO_WIRE_SEAL_BYTES)
		return -1;
	unsigned char *p = buf;
	put64(p + len, stamp);
	tag(k, channel, p, len, p + len, p + len + 8);
	return (int)(len + EVO_WIRE_SEAL_BYTES);
}

evo_wire_reason evo_wire_unseal(const evo_wire_key *k, const char *channel,
				const void *buf, size_t len, int64_t now_us,
				size_t *body, int64_t *stamp, char *why,
				size_t cap)
{
	const unsigned char *p = buf;
	if (len < 8 + EVO_WIRE_SEAL_BYTES) {
		snprintf(why, cap, "%zu bytes on %s, too few to hold a seal",
			 len, channel);
		return EVO_WIRE_FORGED;
	}
	size_t n = len - EVO_WIRE_SEAL_BYTES;
	uint8_t want[EVO_WIRE_TAG_BYTES];
	tag(k, channel, p, n, p + n, want);
	if (!evo_mac_equal(want, p + n + 8, EVO_WIRE_TAG_BYTES)) {
		snprintf(why, cap,
			 "a message on %s whose MAC fails the key (or that "
			 "has no seal)",
			 channel);
		return EVO_WIRE_FORGED;
	}
	int64_t t = (int64_t)be64(p + n);
	/* in unsigned arithmetic: a forged stamp far from now must not
	 * overflow the difference */
	uint64_t d = t > now_us ? (uint64_t)t - (uint64_t)now_us
				: (uint64_t)now_us - (uint64_t)t;
	if (d > (uint64_t)EVO_WIRE_FRESH_US) {
		snprintf(why, cap,
			 "a message on %s stamped %.0f s %s this machine's "
			 "clock (more than %lld s: recorded earlier, or the "
			 "clocks differ)",
			 channel, (double)d * 1e-6,
			 t > now_us ? "ahead of" : "behind",
			 EVO_WIRE_FRESH_US / 1000000);
		return EVO_WIRE_REPLAYED;
	}
	*body = n;
	*stamp = t;
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_fresh_take(evo_wire_fresh *f, int64_t stamp,
				    char *why, size_t cap)
{
	if (stamp == 0)
		return EVO_WIRE_OK;
	if (stamp <= f->last) {
		snprintf(why, cap,
			 "stamped %lld us, not after the last taken (%lld us)",
			 (long long)stamp, (long long)f->last);
		return EVO_WIRE_REPLAYED;
	}
	f->last = stamp;
	return EVO_WIRE_OK;
}
