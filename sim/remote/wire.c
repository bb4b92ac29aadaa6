/* The remote protocol's messages: checked walks, then lcm-gen's code
 * (sim/remote/wire.h). */
#define _POSIX_C_SOURCE 200809L
#include "remote/wire.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* lcm-gen's C for lcmtypes/evo_remote.lcm, made at build time */
#include <evo_lcm_command_t.h>
#include <evo_lcm_control_t.h>
#include <evo_lcm_hello_t.h>
#include <evo_lcm_sensors_t.h>
#include <evo_lcm_who_t.h>

const char *evo_wire_reason_name(evo_wire_reason r)
{
	static const char *const names[EVO_WIRE_N_REASONS] = {
	    "ok", "undecodable", "foreign", "counts", "value", "stale",
	    "ahead"};
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

static const field sensors_fields[] = {
    {F_STR, EVO_REMOTE_NAME_MAX, "name"},
    {F_I64, 0, "session"},
    {F_I32, 0, "env"},
    {F_I64, 0, "episode"},
    {F_I64, 0, "tick"},
    {F_COUNT, EVO_MAX_SENSORS, "n"},
    {F_F64S, 0, "values"},
    {F_F64, 0, "reward"},
    {F_I8, 0, "done"},
};

static const field command_fields[] = {
    {F_STR, EVO_REMOTE_NAME_MAX, "name"},
    {F_I64, 0, "session"},
    {F_I32, 0, "env"},
    {F_I64, 0, "episode"},
    {F_I64, 0, "tick"},
    {F_COUNT, EVO_MAX_ACTUATORS, "n"},
    {F_F64S, 0, "values"},
};

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

evo_wire_reason evo_wire_decode_hello(const void *buf, size_t len,
				      evo_wire_hello *out, char *why, size_t cap)
{
	if (walk(buf, len, __evo_lcm_hello_t_get_hash(), hello_fields,
		 NF(hello_fields), "hello_t", why, cap))
		return EVO_WIRE_UNDECODABLE;
	evo_lcm_hello_t m;
	if (evo_lcm_hello_t_decode(buf, 0, (int)len, &m) < 0)
		return bad(why, cap, "%s: refused by its decoder", "hello_t");
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
	if (!evo_wire_name_ok(out->name))
		return bad(why, cap,
			   "%s: a remote's name is 1..63 letters, digits, '_' "
			   "or '-'",
			   "hello_t");
	if (kind != EVO_LCM_HELLO_T_ROBOT && kind != EVO_LCM_HELLO_T_SIMULATOR)
		return bad(why, cap, "%s: kind is neither ROBOT nor SIMULATOR",
			   "hello_t");
	if (out->environments < 1 ||
	    (out->kind == EVO_REMOTE_ROBOT && out->environments != 1))
		return bad(why, cap,
			   "%s: environments must be 1 for a robot, at least "
			   "1 for a simulator",
			   "hello_t");
	if (out->tick_us < 0)
		return bad(why, cap, "%s: tick_us is negative", "hello_t");
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_decode_who(const void *buf, size_t len, evo_wire_who *out,
				    char *why, size_t cap)
{
	if (walk(buf, len, __evo_lcm_who_t_get_hash(), who_fields,
		 NF(who_fields), "who_t", why, cap))
		return EVO_WIRE_UNDECODABLE;
	evo_lcm_who_t m;
	if (evo_lcm_who_t_decode(buf, 0, (int)len, &m) < 0)
		return bad(why, cap, "%s: refused by its decoder", "who_t");
	out->protocol = m.protocol;
	copy_name(out->from, sizeof out->from, m.sender);
	evo_lcm_who_t_decode_cleanup(&m);
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_decode_control(const void *buf, size_t len,
					evo_wire_control *out, char *why,
					size_t cap)
{
	if (walk(buf, len, __evo_lcm_control_t_get_hash(), control_fields,
		 NF(control_fields), "control_t", why, cap))
		return EVO_WIRE_UNDECODABLE;
	evo_lcm_control_t m;
	if (evo_lcm_control_t_decode(buf, 0, (int)len, &m) < 0)
		return bad(why, cap, "%s: refused by its decoder", "control_t");
	memset(out, 0, sizeof *out);
	copy_name(out->name, sizeof out->name, m.name);
	out->session = m.session;
	out->env = m.env;
	out->op = (evo_wire_control_op)m.op;
	out->episode = m.episode;
	out->layout_seed = (uint64_t)m.layout_seed;
	out->seed = (uint64_t)m.seed;
	int op = m.op;
	evo_lcm_control_t_decode_cleanup(&m);
	if (op != EVO_LCM_CONTROL_T_RESET && op != EVO_LCM_CONTROL_T_STOP)
		return bad(why, cap, "%s: op is neither RESET nor STOP",
			   "control_t");
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_decode_sensors(const void *buf, size_t len,
					evo_wire_sensors *out, char *why,
					size_t cap)
{
	if (walk(buf, len, __evo_lcm_sensors_t_get_hash(), sensors_fields,
		 NF(sensors_fields), "sensors_t", why, cap))
		return EVO_WIRE_UNDECODABLE;
	evo_lcm_sensors_t m;
	if (evo_lcm_sensors_t_decode(buf, 0, (int)len, &m) < 0)
		return bad(why, cap, "%s: refused by its decoder", "sensors_t");
	memset(out, 0, sizeof *out);
	copy_name(out->name, sizeof out->name, m.name);
	out->session = m.session;
	out->env = m.env;
	out->episode = m.episode;
	out->tick = m.tick;
	out->n = (unsigned)m.n;
	if (out->n)
		memcpy(out->value, m.values, out->n * sizeof *out->value);
	out->reward = m.reward;
	out->done = m.done != 0;
	evo_lcm_sensors_t_decode_cleanup(&m);
	return EVO_WIRE_OK;
}

evo_wire_reason evo_wire_decode_command(const void *buf, size_t len,
					evo_wire_command *out, char *why,
					size_t cap)
{
	if (walk(buf, len, __evo_lcm_command_t_get_hash(), command_fields,
		 NF(command_fields), "command_t", why, cap))
		return EVO_WIRE_UNDECODABLE;
	evo_lcm_command_t m;
	if (evo_lcm_command_t_decode(buf, 0, (int)len, &m) < 0)
		return bad(why, cap, "%s: refused by its decoder", "command_t");
	memset(out, 0, sizeof *out);
	copy_name(out->name, sizeof out->name, m.name);
	out->session = m.session;
	out->env = m.env;
	out->episode = m.episode;
	out->tick = m.tick;
	out->n = (unsigned)m.n;
	if (out->n)
		memcpy(out->value, m.values, out->n * sizeof *out->value);
	evo_lcm_command_t_decode_cleanup(&m);
	return EVO_WIRE_OK;
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

/* ---- encoding ------------------------------------------------------------- */

/* lcm-gen's structs hold char *, not const char *: the strings are only
 * read while encoding. */
static char *str(const char *s)
{
	return (char *)(uintptr_t)s;
}

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
	    .name = str(c->name),
	    .session = c->session,
	    .env = c->env,
	    .op = (int8_t)c->op,
	    .episode = c->episode,
	    .layout_seed = (int64_t)c->layout_seed,
	    .seed = (int64_t)c->seed,
	};
	ENCODE(evo_lcm_control_t, &m, buf, cap);
}

int evo_wire_encode_sensors(const evo_wire_sensors *s, void *buf, size_t cap)
{
	if (s->n > EVO_MAX_SENSORS)
		return -1;
	evo_lcm_sensors_t m = {
	    .name = str(s->name),
	    .session = s->session,
	    .env = s->env,
	    .episode = s->episode,
	    .tick = s->tick,
	    .n = (int32_t)s->n,
	    .values = (double *)(uintptr_t)s->value,
	    .reward = s->reward,
	    .done = (int8_t)(s->done != 0),
	};
	ENCODE(evo_lcm_sensors_t, &m, buf, cap);
}

int evo_wire_encode_command(const evo_wire_command *c, void *buf, size_t cap)
{
	if (c->n > EVO_MAX_ACTUATORS)
		return -1;
	evo_lcm_command_t m = {
	    .name = str(c->name),
	    .session = c->session,
	    .env = c->env,
	    .episode = c->episode,
	    .tick = c->tick,
	    .n = (int32_t)c->n,
	    .values = (double *)(uintptr_t)c->value,
	};
	ENCODE(evo_lcm_command_t, &m, buf, cap);
}
