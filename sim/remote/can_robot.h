/* evo — a robot over CAN (DEMOREMOTE over CAN; docs/can.md, docs/wire.md).
 *
 * evo runs the mind on the host and takes the firmware's place on the
 * bus: the robot's body (its sensor and motor nodes, or `evo serve
 * --can`) sends each tick's sensor frames and a TICK, and evo answers
 * with the actuator frames and a TICKED, in the layout of evo/wire.h. A
 * few frames of that layout carry what LCM's hello and control messages
 * carry for a robot over LCM: the body's BODY (its names hash, counts and
 * period) in answer to evo's HELLO, evo's RESET with the episode's seeds,
 * its STOP, and the body's REWARD and DONE.
 *
 * The first half is pure functions of the frames, one receiver for each
 * side: evo's (the mind's), which puts a tick together from its sensor
 * frames as the firmware does, and the body's (`evo serve --can`), which
 * puts a command together from the actuator frames. Anything malformed is
 * refused with a reason, never taken (tests/fuzz/fuzz_can_robot.c). The
 * second half is evo's side of a robot's episodes over a transport of
 * can.h, with the counts and reports of a robot over LCM (session.h,
 * evo_robot_*). */
#ifndef EVO_CAN_ROBOT_H
#define EVO_CAN_ROBOT_H

#include <signal.h>
#include <stdint.h>

#include "base/err.h"
#include "evo/fixed.h"
#include "evo/wire.h"
#include "mind/mindfolder.h"
#include "remote/robot_status.h"

#define EVO_CAN_MAX_SENSORS   (2 * EVO_WIRE_SENSOR_FRAMES)   /* 128 */
#define EVO_CAN_MAX_ACTUATORS (2 * EVO_WIRE_ACTUATOR_FRAMES) /* 64 */

/* Why a frame was refused. */
typedef enum evo_can_robot_bad {
	EVO_CAN_ROBOT_BAD_ID = 0,     /* not one of the frames this side
					 takes: another node's, one going
					 the other way, a value frame past
					 the counts */
	EVO_CAN_ROBOT_BAD_LENGTH,     /* a DLC its id does not take */
	EVO_CAN_ROBOT_BAD_VALUE,      /* a value outside [0, 1], a reward
					 that is NaN or infinite */
	EVO_CAN_ROBOT_BAD_INCOMPLETE, /* a TICK or TICKED whose value frames
					 did not all come; a RESET whose
					 seed frames did not */
	EVO_CAN_ROBOT_BAD_STALE,      /* a tick not newer than the one held,
					 or from before evo's RESET */
	EVO_CAN_ROBOT_BAD_COUNT
} evo_can_robot_bad;

/* "id", "length", "value", "incomplete", "stale". */
const char *evo_can_robot_bad_name(evo_can_robot_bad b);

/* ---- the frames (pure functions) --------------------------------------- */

/* What a body says of itself (EVO_WIRE_BODY). */
typedef struct evo_can_body_info {
	uint32_t names_hash; /* evo_names_hash_of(botdesc, NULL); 0: none */
	unsigned sensors, actuators;
	unsigned period_100us; /* 1 .. 65535 */
} evo_can_body_info;

void evo_can_body_encode(const evo_can_body_info *b, evo_can_frame *f);

/* The three frames that start episode `episode` (LAYOUT_SEED, SEED,
 * RESET, to be sent in this order). */
void evo_can_reset_encode(uint32_t episode, uint64_t layout_seed, uint64_t seed,
			  evo_can_frame f[3]);

/* What a receiver made of a frame. */
typedef enum evo_can_event {
	EVO_CAN_EV_NONE = 0, /* taken; nothing to do yet (a value frame, a
				REWARD, the seed frames) */
	EVO_CAN_EV_BAD,	     /* refused: the receiver's `bad` says why */
	/* evo's side */
	EVO_CAN_EV_TICK, /* a TICK: `tick`, and `complete` (then `values`
			    holds its sensors) or `bad` why not */
	EVO_CAN_EV_BODY, /* a BODY: `body` */
	EVO_CAN_EV_DONE, /* a DONE: `tick` the episode's ticks */
	/* the body's side */
	EVO_CAN_EV_TICKED, /* a TICKED: `tick`, `flags`, and `complete`
			      (then `values` holds its actuators) or `bad` */
	EVO_CAN_EV_HELLO,  /* a HELLO: `hello` */
	EVO_CAN_EV_RESET,  /* a RESET with its seeds: `episode`, `layout_seed`,
			      `seed` */
	EVO_CAN_EV_STOP,   /* a STOP: `episode` */
} evo_can_event;

/* A receiver, of either side. Values arrive into `pending` and are taken
 * into `values` only by a complete TICK (TICKED), so a tick is never made
 * of half-updated values. */
typedef struct evo_can_rx {
	int is_body; /* 1: the body's receiver; 0: evo's */
	unsigned n;  /* the values it takes: sensors (evo), actuators (body) */
	evo_q16 pending[EVO_CAN_MAX_SENSORS];
	evo_q16 values[EVO_CAN_MAX_SENSORS];
	uint64_t got;	/* value frames received since the last TICK(ED) */
	uint64_t known; /* received since restart (evo's side) */
	/* the result of the last frame */
	evo_can_robot_bad bad;
	uint32_t tick;
	uint8_t flags;
	int complete;
	uint64_t missing_frames; /* of an incomplete tick: frames lacking */
	evo_can_body_info body;
	struct {
		uint32_t names_hash;
		unsigned sensors, actuators, variables, version;
	} hello;
	uint32_t episode;
	uint64_t layout_seed, seed;
	double reward; /* the last REWARD (evo's side); 0 until one comes */
	/* the body's side: the seed frames since the last RESET */
	int have_layout, have_seed;
	uint8_t seed_bytes[16];
} evo_can_rx;

/* A receiver of n values (1 .. 128 sensors for evo's, 1 .. 64 actuators
 * for the body's). */
void evo_can_rx_init(evo_can_rx *rx, int body, unsigned n);

/* A new episode (evo's side): the next TICK must bring every sensor
 * frame, and the reward starts at 0. */
void evo_can_rx_restart(evo_can_rx *rx);

evo_can_event evo_can_rx_frame(evo_can_rx *rx, const evo_can_frame *f);

/* ---- evo's side of a robot's episodes --------------------------------- */

typedef struct evo_can_robot_def {
	const char *url; /* can.h's */
	const evo_mindfolder *mind;
	double timeout; /* seconds of silence before saying so; 0: 2 */
	/* set by a signal handler: every wait ends soon after, with
	 * "stopped" in err */
	volatile sig_atomic_t *stop;
} evo_can_robot_def;

typedef struct evo_can_robot evo_can_robot;

/* Open the URL, say HELLO until the body answers (saying so every
 * `timeout` while none does), and check that it fits the botdesc: the
 * same numbers of sensors and actuators and, when the body gives one, the
 * same names hash (the names in the botdesc's order: over CAN a value is
 * known by its place). NULL with err set ("robot cannelloni:...: does not
 * fit Avoid.botdesc: ..."), or with err empty when stopped. */
evo_can_robot *evo_can_robot_open(const evo_can_robot_def *def, evo_err *err);

/* Say STOP when an episode ran, report the drops (stderr), close. */
void evo_can_robot_close(evo_can_robot *r);

/* "robot URL: a tick every 33.300 ms; ..." */
const char *evo_can_robot_about(const evo_can_robot *r);
const char *evo_can_robot_name(const evo_can_robot *r); /* its URL */
double evo_can_robot_period(const evo_can_robot *r);	/* seconds */

/* As evo_robot_start, evo_robot_next and evo_robot_answer (session.h),
 * over CAN: the RESET (with its seed frames) sent again every quarter
 * second until a tick of the episode comes; ticks held and counted as a
 * robot's over LCM are. An incomplete tick is answered at once with the
 * INCOMPLETE flag and the commands before (as the firmware answers one),
 * and counted missing. */
int evo_can_robot_start(evo_can_robot *r, int64_t episode, uint64_t layout_seed,
			uint64_t seed, evo_err *err);
int evo_can_robot_next(evo_can_robot *r, int timeout_ms, evo_err *err);
int evo_can_robot_answer(evo_can_robot *r, const evo_q16 *commands,
			 evo_err *err);

/* The held tick's sensor values, botdesc order. */
void evo_can_robot_sensors(const evo_can_robot *r, evo_q16 *values);

/* Where the episode is, and the counts so far (robot_status.h). */
void evo_can_robot_status(const evo_can_robot *r, evo_robot_status *s);

/* "robot URL: T ticks: A answered in time, L late (U unanswered), M
 * missing" on stdout. */
void evo_can_robot_report(const evo_can_robot *r);

#endif
