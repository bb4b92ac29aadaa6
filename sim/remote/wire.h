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

#define EVO_WIRE_PROTOCOL 2
/* The most values a behaviour has (tasksim.h's EVO_SIM_MAX_BEHAVIOUR). */
#define EVO_WIRE_MAX_BEHAVIOUR 16
#define EVO_REMOTE_NAME_MAX 64 /* bytes in a remote's name, with its NUL */
#define EVO_REMOTE_URL_MAX 256 /* bytes in an LCM URL, with its NUL */
#define EVO_WIRE_MAX_ENVS 64	/* environments of one remote */
#define EVO_WIRE_MAX_TICK_US 60000000 /* a robot's longest tick: 60 s */

typedef enum evo_wire_reason {
	EVO_WIRE_OK = 0,
	EVO_WIRE_UNDECODABLE, /* not this type, cut short, a bad count */
	EVO_WIRE_FOREIGN,     /* another remote's or another session's */
	EVO_WIRE_COUNTS,      /* n is not the hello's count */
	EVO_WIRE_VALUE,	      /* NaN, infinite or out of [0, 1] */
	EVO_WIRE_STALE,	      /* an earlier episode or an answered tick */
	EVO_WIRE_AHEAD,	      /* a tick past the one awaited */
	EVO_WIRE_FORGED,      /* no seal, or one that fails the key */
	EVO_WIRE_REPLAYED,    /* sealed, but not newer than the last taken */
	EVO_WIRE_CONFLICT,    /* a second, different answer for one tick */
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
	/* a simulator's behaviour of the episode so far (docs/remote.md):
	 * n_behaviour values, 0 when it sends none */
	unsigned n_behaviour;
	double behaviour[EVO_WIRE_MAX_BEHAVIOUR];
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
 * with why (cap bytes) saying what was wrong. Every count and index is
 * checked here against evo's limits (environments 1..EVO_WIRE_MAX_ENVS,
 * env 0..EVO_WIRE_MAX_ENVS - 1, episode and tick from 0, tick_us, the
 * hello's url: evo_wire_url_ok), so nothing past the decoder indexes out
 * of bounds; a hello refused after its name was read names it ("hello_t
 * from sim1: environments is 100, outside 1..64"), and out->name holds it
 * (else ""). The values are not checked here (evo_wire_check_values). */
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

/* A simulator's behaviour values each in [0, 1]: EVO_WIRE_OK, or
 * EVO_WIRE_VALUE with why naming the first bad one. */
evo_wire_reason evo_wire_check_behaviour(const evo_wire_sensors *s, char *why,
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

/* An LCM URL a hello may name for its episodes (docs/remote.md): empty
 * (the hello's own), or udpm://A.B.C.D:PORT on an IPv4 multicast group
 * (224.0.0.0 to 239.255.255.255), port 1..65535, with no options but
 * ttl=0 or ttl=1 and recv_buf_size=N (at most 16 MiB). Never another
 * provider (file:// would have evo write a file, tcpq:// connect out).
 * 1, or 0 with why. *ttl: the URL's ttl (0 when it gives none). */
int evo_wire_url_ok(const char *url, int *ttl, char *why, size_t cap);

/* ---- the shared key (docs/remote.md, Keys) ------------------------------
 *
 * With a key, every message carries a seal after its LCM bytes: an 8-byte
 * big-endian stamp (microseconds of the sender's real-time clock, made
 * strictly increasing), then HMAC-SHA-256 (whole, 32 bytes) over the
 * channel's name, a NUL, the message's bytes and the stamp. The message's
 * bytes hold its name, session, environment, episode, tick and values;
 * the channel binds it to where it was sent. A receiver takes a sealed
 * message only when its MAC is right, its stamp within
 * EVO_WIRE_FRESH_US of its own clock (a message recorded earlier is
 * refused) and newer than the last it took from the same sender on that
 * channel (evo_wire_fresh). */
#define EVO_WIRE_KEY_MIN 16
#define EVO_WIRE_KEY_MAX 256
#define EVO_WIRE_TAG_BYTES 32
#define EVO_WIRE_SEAL_BYTES (8 + EVO_WIRE_TAG_BYTES)
#define EVO_WIRE_FRESH_US 30000000LL /* 30 s */

typedef struct evo_wire_key {
	size_t len; /* 0: no key */
	unsigned char bytes[EVO_WIRE_KEY_MAX];
} evo_wire_key;

/* Read a key file: its bytes, without a trailing newline, 16..256 of them.
 * The key is never printed: messages name the file only. 0, or -1 with
 * why. */
int evo_wire_key_read(const char *path, evo_wire_key *k, char *why,
		      size_t cap);

/* The next stamp of a sender: the real-time clock in microseconds, or
 * one more than *last when the clock has not moved on. */
int64_t evo_wire_stamp(int64_t *last);

/* Append the seal of buf[0 .. len) sent on channel, stamped `stamp`: the
 * new length, or -1 when it does not fit in cap. */
int evo_wire_seal(const evo_wire_key *k, const char *channel, void *buf,
		  size_t len, size_t cap, int64_t stamp);

/* Check the seal of a message received on channel at now_us: EVO_WIRE_OK
 * with *body its length without the seal and *stamp its stamp;
 * EVO_WIRE_FORGED (too short to hold a seal, or the MAC is wrong) or
 * EVO_WIRE_REPLAYED (the stamp more than EVO_WIRE_FRESH_US from now_us)
 * with why. */
evo_wire_reason evo_wire_unseal(const evo_wire_key *k, const char *channel,
				const void *buf, size_t len, int64_t now_us,
				size_t *body, int64_t *stamp, char *why,
				size_t cap);

/* The last stamp taken from one sender on one channel. */
typedef struct evo_wire_fresh {
	int64_t last;
} evo_wire_fresh;

/* Take stamp when it is newer than the last taken (EVO_WIRE_OK), else
 * EVO_WIRE_REPLAYED with why. A stamp of 0 (no key) is always taken. */
evo_wire_reason evo_wire_fresh_take(evo_wire_fresh *f, int64_t stamp,
				    char *why, size_t cap);

#endif
