/* evo — the remote protocol's messages (lcmtypes/evo_remote.lcm,
 * docs/remote.md) as evo holds them: fixed-size structs, checked before
 * use.
 *
 * Decoding is in two steps. The bytes are first walked field by field,
 * every count and string length checked against evo's limits and against
 * the bytes left, so that lcm-gen's decoder, which trusts them, only ever
 * sees a well-formed message; that decoder then fills the struct. A
 * message that fails gets a reason (evo_wire_reason) and a sentence. */
#ifndef EVO_REMOTE_WIRE_H
#define EVO_REMOTE_WIRE_H

#include <stddef.h>
#include <stdint.h>

#include "evo/formats.h"

#define EVO_WIRE_PROTOCOL 1
#define EVO_REMOTE_NAME_MAX 64 /* bytes in a remote's name, with its NUL */
#define EVO_REMOTE_URL_MAX 256 /* bytes in an LCM URL, with its NUL */

typedef enum evo_wire_reason {
	EVO_WIRE_OK = 0,
	EVO_WIRE_UNDECODABLE, /* not this type, cut short, a bad count */
	EVO_WIRE_FOREIGN,     /* another remote's or another session's */
	EVO_WIRE_COUNTS,      /* n is not the hello's count */
	EVO_WIRE_VALUE,	      /* NaN, infinite or out of [0, 1] */
	EVO_WIRE_STALE,	      /* an earlier episode or an answered tick */
	EVO_WIRE_AHEAD,	      /* a tick past the one awaited */
	EVO_WIRE_N_REASONS
} evo_wire_reason;

/* "undecodable", "foreign", ... as docs/remote.md names them. */
const char *evo_wire_reason_name(evo_wire_reason r);

typedef enum evo_remote_kind {
	EVO_REMOTE_ROBOT = 0,
	EVO_REMOTE_SIMULATOR = 1
} evo_remote_kind;

typedef struct evo_wire_hello {
	int32_t protocol;
	char name[EVO_REMOTE_NAME_MAX];
	int64_t session;
	char url[EVO_REMOTE_URL_MAX]; /* its episodes' URL; "": the hello's */
	evo_remote_kind kind;
	int32_t environments;
	int32_t tick_us;
	unsigned n_sensors, n_actuators;
	char sensor[EVO_MAX_SENSORS][EVO_NAME_MAX];
	char actuator[EVO_MAX_ACTUATORS][EVO_NAME_MAX];
} evo_wire_hello;

typedef struct evo_wire_who {
	int32_t protocol;
	char from[EVO_REMOTE_NAME_MAX]; /* the message's `sender` */
} evo_wire_who;

typedef enum evo_wire_control_op {
	EVO_CONTROL_RESET = 1,
	EVO_CONTROL_STOP = 2
} evo_wire_control_op;

typedef struct evo_wire_control {
	char name[EVO_REMOTE_NAME_MAX];
	int64_t session;
	int32_t env;
	evo_wire_control_op op;
	int64_t episode;
	uint64_t layout_seed, seed;
} evo_wire_control;

typedef struct evo_wire_sensors {
	char name[EVO_REMOTE_NAME_MAX];
	int64_t session;
	int32_t env;
	int64_t episode, tick;
	unsigned n;
	double value[EVO_MAX_SENSORS];
	double reward;
	int done;
} evo_wire_sensors;

typedef struct evo_wire_command {
	char name[EVO_REMOTE_NAME_MAX];
	int64_t session;
	int32_t env;
	int64_t episode, tick;
	unsigned n;
	double value[EVO_MAX_ACTUATORS];
} evo_wire_command;

/* A name a remote may have: 1..63 of [A-Za-z0-9_-]. */
int evo_wire_name_ok(const char *name);

/* Decode len bytes as one message. EVO_WIRE_OK, or EVO_WIRE_UNDECODABLE
 * with why (cap bytes) saying what was wrong. The values are not checked
 * here (evo_wire_check_values). */
evo_wire_reason evo_wire_decode_hello(const void *buf, size_t len,
				      evo_wire_hello *out, char *why, size_t cap);
evo_wire_reason evo_wire_decode_who(const void *buf, size_t len, evo_wire_who *out,
				    char *why, size_t cap);
evo_wire_reason evo_wire_decode_control(const void *buf, size_t len,
					evo_wire_control *out, char *why,
					size_t cap);
evo_wire_reason evo_wire_decode_sensors(const void *buf, size_t len,
					evo_wire_sensors *out, char *why,
					size_t cap);
evo_wire_reason evo_wire_decode_command(const void *buf, size_t len,
					evo_wire_command *out, char *why,
					size_t cap);

/* Every value in [0, 1] and the reward finite: EVO_WIRE_OK, or
 * EVO_WIRE_VALUE with why naming the first bad one. */
evo_wire_reason evo_wire_check_values(const double *v, unsigned n,
				      const double *reward, char *why,
				      size_t cap);

/* Encode into buf (cap bytes): the length, or -1 when it does not fit or
 * a field is out of the protocol's bounds. */
int evo_wire_encode_hello(const evo_wire_hello *m, void *buf, size_t cap);
int evo_wire_encode_who(const evo_wire_who *m, void *buf, size_t cap);
int evo_wire_encode_control(const evo_wire_control *m, void *buf, size_t cap);
int evo_wire_encode_sensors(const evo_wire_sensors *m, void *buf, size_t cap);
int evo_wire_encode_command(const evo_wire_command *m, void *buf, size_t cap);

/* The largest encoded message evo sends or takes. */
#define EVO_WIRE_MAX_BYTES 16384

#endif
