/* A robot over CAN: its frames, and each side's receiver, as pure
 * functions (sim/remote/can_robot.h; fuzzed by fuzz_can_robot.c). */
#include <math.h>
#include <string.h>

#include "evo/image.h"
#include "remote/can_robot.h"

const char *evo_can_robot_bad_name(evo_can_robot_bad b)
{
	static const char *const names[EVO_CAN_ROBOT_BAD_COUNT] = {
	    "id", "length", "value", "incomplete", "stale"};
	return (unsigned)b < EVO_CAN_ROBOT_BAD_COUNT ? names[b] : "?";
}

static void put_u64(uint8_t *p, uint64_t v)
{
	evo_wire_put_u32(p, (uint32_t)v);
	evo_wire_put_u32(p + 4, (uint32_t)(v >> 32));
}

static uint64_t get_u64(const uint8_t *p)
{
	return (uint64_t)evo_wire_get_u32(p) | (uint64_t)evo_wire_get_u32(p + 4)
						   << 32;
}

void evo_can_body_encode(const evo_can_body_info *b, evo_can_frame *f)
{
	memset(f, 0, sizeof *f);
	f->id = EVO_WIRE_BODY;
	f->len = 8;
	evo_wire_put_u32(f->data, b->names_hash);
	f->data[4] = (uint8_t)b->sensors;
	f->data[5] = (uint8_t)b->actuators;
	evo_wire_put_u16(f->data + 6, (uint16_t)b->period_100us);
}

void evo_can_reset_encode(uint32_t episode, uint64_t layout_seed, uint64_t seed,
			  evo_can_frame f[3])
{
	memset(f, 0, 3 * sizeof *f);
	f[0].id = EVO_WIRE_LAYOUT_SEED;
	f[0].len = 8;
	put_u64(f[0].data, layout_seed);
	f[1].id = EVO_WIRE_SEED;
	f[1].len = 8;
	put_u64(f[1].data, seed);
	uint8_t both[16];
	memcpy(both, f[0].data, 8);
	memcpy(both + 8, f[1].data, 8);
	f[2].id = EVO_WIRE_RESET;
	f[2].len = 8;
	evo_wire_put_u32(f[2].data, episode);
	evo_wire_put_u32(f[2].data + 4, evo_crc32(0, both, sizeof both));
}

void evo_can_rx_init(evo_can_rx *rx, int body, unsigned n)
{
	memset(rx, 0, sizeof *rx);
	unsigned max = body ? EVO_CAN_MAX_ACTUATORS : EVO_CAN_MAX_SENSORS;
	rx->is_body = body;
	rx->n = n < 1 ? 1 : n > max ? max : n;
	for (unsigned i = 0; i < EVO_CAN_MAX_SENSORS; i++)
		rx->pending[i] = rx->values[i] = EVO_Q16_HALF;
}

void evo_can_rx_restart(evo_can_rx *rx)
{
	rx->got = 0;
	rx->known = 0;
	rx->reward = 0;
}

/* Every value frame of n values, bit k for frame k. */
static uint64_t all_frames(unsigned n)
{
	unsigned k = evo_wire_frames(n);
	return k >= 64 ? ~(uint64_t)0 : ((uint64_t)1 << k) - 1;
}

static evo_can_event refuse(evo_can_rx *rx, evo_can_robot_bad why)
{
	rx->bad = why;
	return EVO_CAN_EV_BAD;
}

/* A value frame of base: into pending, unless refused. Both values must
 * be in [0, 1]: a robot's sensor or a mind's command is nothing else. */
static evo_can_event value_frame(evo_can_rx *rx, uint16_t base,
				 const evo_can_frame *f)
{
	evo_q16 v[EVO_CAN_MAX_SENSORS];
	int k = evo_wire_unpack(base, f, v, rx->n);
	if (k < 0)
		return refuse(rx, k == -1 - (int)EVO_WIRE_BAD_LENGTH
				      ? EVO_CAN_ROBOT_BAD_LENGTH
				      : EVO_CAN_ROBOT_BAD_ID);
	unsigned first = 2u * (unsigned)k;
	unsigned count = rx->n - first >= 2u ? 2u : 1u;
	for (unsigned i = 0; i < count; i++)
		if (v[first + i] < 0 || v[first + i] > EVO_Q16_ONE)
			return refuse(rx, EVO_CAN_ROBOT_BAD_VALUE);
	for (unsigned i = 0; i < count; i++)
		rx->pending[first + i] = v[first + i];
	rx->got |= (uint64_t)1 << k;
	return EVO_CAN_EV_NONE;
}

/* The values of the frames in `frames` from pending into values. */
static void take_values(evo_can_rx *rx, uint64_t frames)
{
	for (unsigned i = 0; i < rx->n; i++)
		if (frames >> (i / 2u) & 1u)
			rx->values[i] = rx->pending[i];
}

/* evo's side: what a body sends. */
static evo_can_event mind_frame(evo_can_rx *rx, const evo_can_frame *f)
{
	if (f->id >= EVO_WIRE_SENSOR &&
	    f->id < EVO_WIRE_SENSOR + EVO_WIRE_SENSOR_FRAMES)
		return value_frame(rx, EVO_WIRE_SENSOR, f);
	switch (f->id) {
	case EVO_WIRE_TICK: {
		/* DLC 4: every frame was sent; DLC 8: those of the mask, the
		 * others keep their values (docs/wire.md), as the firmware
		 * takes them: what came is taken, and the mind steps only
		 * when nothing is lacking */
		unsigned frames = evo_wire_frames(rx->n);
		if (f->len != 4 && (f->len != 8 || frames > 32))
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		uint64_t all = all_frames(rx->n);
		uint64_t sent =
		    f->len == 4 ? all : evo_wire_get_u32(f->data + 4);
		rx->tick = evo_wire_get_u32(f->data);
		take_values(rx, rx->got);
		rx->known |= rx->got;
		rx->complete = rx->got == sent && rx->known == all;
		rx->missing_frames = (sent | (all & ~rx->known)) & ~rx->got;
		if (!rx->complete)
			rx->bad = EVO_CAN_ROBOT_BAD_INCOMPLETE;
		rx->got = 0;
		return EVO_CAN_EV_TICK;
	}
	case EVO_WIRE_BODY: {
		if (f->len != 8)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		evo_can_body_info b = {
		    .names_hash = evo_wire_get_u32(f->data),
		    .sensors = f->data[4],
		    .actuators = f->data[5],
		    .period_100us = evo_wire_get_u16(f->data + 6),
		};
		if (b.sensors < 1 || b.sensors > EVO_CAN_MAX_SENSORS ||
		    b.actuators < 1 || b.actuators > EVO_CAN_MAX_ACTUATORS ||
		    b.period_100us < 1)
			return refuse(rx, EVO_CAN_ROBOT_BAD_VALUE);
		rx->body = b;
		return EVO_CAN_EV_BODY;
	}
	case EVO_WIRE_REWARD: {
		if (f->len != 8)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		uint64_t bits = get_u64(f->data);
		double v;
		memcpy(&v, &bits, sizeof v);
		if (!isfinite(v))
			return refuse(rx, EVO_CAN_ROBOT_BAD_VALUE);
		rx->reward = v;
		return EVO_CAN_EV_NONE;
	}
	case EVO_WIRE_DONE:
		if (f->len != 4)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		rx->tick = evo_wire_get_u32(f->data);
		return EVO_CAN_EV_DONE;
	default:
		return refuse(rx, EVO_CAN_ROBOT_BAD_ID);
	}
}

/* The body's side: what evo sends. */
static evo_can_event body_frame(evo_can_rx *rx, const evo_can_frame *f)
{
	if (f->id >= EVO_WIRE_ACTUATOR &&
	    f->id < EVO_WIRE_ACTUATOR + EVO_WIRE_ACTUATOR_FRAMES)
		return value_frame(rx, EVO_WIRE_ACTUATOR, f);
	switch (f->id) {
	case EVO_WIRE_TICKED:
		/* the firmware sends every actuator frame before each TICKED:
		 * a command is whole or not taken */
		if (f->len != 5)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		rx->tick = evo_wire_get_u32(f->data);
		rx->flags = f->data[4];
		rx->complete = rx->got == all_frames(rx->n);
		rx->missing_frames = all_frames(rx->n) & ~rx->got;
		if (rx->complete)
			take_values(rx, rx->got);
		else
			rx->bad = EVO_CAN_ROBOT_BAD_INCOMPLETE;
		rx->got = 0;
		return EVO_CAN_EV_TICKED;
	case EVO_WIRE_HELLO:
		if (f->len != 8)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		rx->hello.names_hash = evo_wire_get_u32(f->data);
		rx->hello.sensors = f->data[4];
		rx->hello.actuators = f->data[5];
		rx->hello.variables = f->data[6];
		rx->hello.version = f->data[7];
		return EVO_CAN_EV_HELLO;
	case EVO_WIRE_LAYOUT_SEED:
	case EVO_WIRE_SEED:
		if (f->len != 8)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		if (f->id == EVO_WIRE_LAYOUT_SEED) {
			memcpy(rx->seed_bytes, f->data, 8);
			rx->have_layout = 1;
		} else {
			memcpy(rx->seed_bytes + 8, f->data, 8);
			rx->have_seed = 1;
		}
		return EVO_CAN_EV_NONE;
	case EVO_WIRE_RESET: {
		if (f->len != 8)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		/* the seeds are the ones this RESET was sent with, or the
		 * RESET is not taken: evo sends it again, seeds first */
		int whole = rx->have_layout && rx->have_seed &&
			    evo_crc32(0, rx->seed_bytes, 16) ==
				evo_wire_get_u32(f->data + 4);
		rx->have_layout = rx->have_seed = 0;
		if (!whole)
			return refuse(rx, EVO_CAN_ROBOT_BAD_INCOMPLETE);
		rx->episode = evo_wire_get_u32(f->data);
		rx->layout_seed = get_u64(rx->seed_bytes);
		rx->seed = get_u64(rx->seed_bytes + 8);
		return EVO_CAN_EV_RESET;
	}
	case EVO_WIRE_STOP:
		if (f->len != 4)
			return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
		rx->episode = evo_wire_get_u32(f->data);
		return EVO_CAN_EV_STOP;
	default:
		return refuse(rx, EVO_CAN_ROBOT_BAD_ID);
	}
}

evo_can_event evo_can_rx_frame(evo_can_rx *rx, const evo_can_frame *f)
{
	if (f->len > 8)
		return refuse(rx, EVO_CAN_ROBOT_BAD_LENGTH);
	return rx->is_body ? body_frame(rx, f) : mind_frame(rx, f);
}
