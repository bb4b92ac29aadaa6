/* A robot's frames over CAN (sim/remote/can_robot_frames.c): BODY and
 * RESET laid out by hand; evo's receiver puts a tick together from its
 * sensor frames as the firmware does (every frame, or a mask of the
 * changed ones) and refuses, by reason, what does not fit; the body's
 * receiver takes a command only when whole, and a RESET only with the
 * seed frames it was sent with. */
#include <math.h>
#include <string.h>

#include "evo/image.h"
#include "harness.h"
#include "remote/can_robot.h"

static evo_can_frame frame(unsigned id, unsigned len, const uint8_t *d)
{
	evo_can_frame f = {(uint16_t)id, (uint8_t)len, {0}};
	if (d)
		memcpy(f.data, d, len);
	return f;
}

/* Sensor frames of n values v, those of `frames`, into rx. */
static void feed_sensors(evo_can_rx *rx, const evo_q16 *v, unsigned n,
			 uint64_t frames)
{
	for (unsigned k = 0; k < evo_wire_frames(n); k++)
		if (frames >> k & 1) {
			evo_can_frame f;
			evo_wire_pack(EVO_WIRE_SENSOR, v, n, k, &f);
			evo_can_rx_frame(rx, &f);
		}
}

static evo_can_event tick(evo_can_rx *rx, uint32_t t, int masked, uint32_t mask)
{
	uint8_t d[8];
	evo_wire_put_u32(d, t);
	evo_wire_put_u32(d + 4, mask);
	evo_can_frame f = frame(EVO_WIRE_TICK, masked ? 8 : 4, d);
	return evo_can_rx_frame(rx, &f);
}

TEST(body_and_reset_frames_are_laid_out_as_docs_wire_md_says)
{
	evo_can_body_info b = {0xA1B2C3D4u, 11, 2, 333};
	evo_can_frame f;
	evo_can_body_encode(&b, &f);
	static const uint8_t want[8] = {0xD4, 0xC3, 0xB2, 0xA1,
					11,   2,    0x4D, 0x01};
	CHECK_EQ_INT(f.id, 0x1C6);
	CHECK_EQ_INT(f.len, 8);
	CHECK(memcmp(f.data, want, 8) == 0);
	evo_can_rx rx;
	evo_can_rx_init(&rx, 0, 11);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BODY);
	CHECK(rx.body.names_hash == 0xA1B2C3D4u && rx.body.sensors == 11 &&
	      rx.body.actuators == 2 && rx.body.period_100us == 333);

	evo_can_frame r[3];
	evo_can_reset_encode(7, 0x0102030405060708ull, 0x1112131415161718ull,
			     r);
	CHECK(r[0].id == 0x1C8 && r[0].len == 8 && r[0].data[0] == 0x08 &&
	      r[0].data[7] == 0x01);
	CHECK(r[1].id == 0x1C9 && r[1].len == 8 && r[1].data[0] == 0x18 &&
	      r[1].data[7] == 0x11);
	uint8_t seeds[16];
	memcpy(seeds, r[0].data, 8);
	memcpy(seeds + 8, r[1].data, 8);
	CHECK(r[2].id == 0x1C7 && r[2].len == 8);
	CHECK_EQ_INT(evo_wire_get_u32(r[2].data), 7);
	CHECK(evo_wire_get_u32(r[2].data + 4) == evo_crc32(0, seeds, 16));
}

TEST(a_tick_is_taken_only_whole)
{
	evo_can_rx rx;
	evo_can_rx_init(&rx, 0, 5); /* 3 frames, the last of 4 bytes */
	evo_q16 v[5] = {0, 1, EVO_Q16_HALF, EVO_Q16_ONE, 12345};
	feed_sensors(&rx, v, 5, 0x7);
	CHECK_EQ_INT(tick(&rx, 0, 0, 0), EVO_CAN_EV_TICK);
	CHECK(rx.complete && rx.tick == 0);
	CHECK(memcmp(rx.values, v, sizeof v) == 0);
	/* a frame lost: incomplete, and which */
	v[0] = 100;
	feed_sensors(&rx, v, 5, 0x6);
	CHECK_EQ_INT(tick(&rx, 1, 0, 0), EVO_CAN_EV_TICK);
	CHECK(!rx.complete);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_INCOMPLETE);
	CHECK_EQ_INT(rx.missing_frames, 0x1);
	/* only the changed frame, with its mask: the others keep theirs */
	v[4] = 777;
	feed_sensors(&rx, v, 5, 0x4);
	CHECK_EQ_INT(tick(&rx, 2, 1, 0x4), EVO_CAN_EV_TICK);
	CHECK(rx.complete);
	CHECK_EQ_INT(rx.values[4], 777);
	CHECK_EQ_INT(rx.values[0], 0);
	/* a mask that names a frame not sent */
	CHECK_EQ_INT(tick(&rx, 3, 1, 0x2), EVO_CAN_EV_TICK);
	CHECK(!rx.complete);
	CHECK_EQ_INT(rx.missing_frames, 0x2);
	/* a new episode: every frame again, however the mask reads */
	evo_can_rx_restart(&rx);
	feed_sensors(&rx, v, 5, 0x1);
	CHECK_EQ_INT(tick(&rx, 0, 1, 0x1), EVO_CAN_EV_TICK);
	CHECK(!rx.complete);
	CHECK_EQ_INT(rx.missing_frames, 0x6);
	feed_sensors(&rx, v, 5, 0x7);
	CHECK_EQ_INT(tick(&rx, 1, 0, 0), EVO_CAN_EV_TICK);
	CHECK(rx.complete);
	CHECK(memcmp(rx.values, v, sizeof v) == 0);
}

TEST(evos_receiver_refuses_by_reason)
{
	evo_can_rx rx;
	evo_can_rx_init(&rx, 0, 11);
	static const uint8_t z[8] = {0};
	static const struct {
		unsigned id, len;
		evo_can_robot_bad why;
	} cases[] = {
	    {0x050, 2, EVO_CAN_ROBOT_BAD_ID},	  /* another node's */
	    {0x106, 8, EVO_CAN_ROBOT_BAD_ID},	  /* past 11 sensors */
	    {0x180, 8, EVO_CAN_ROBOT_BAD_ID},	  /* an actuator frame */
	    {0x1C5, 8, EVO_CAN_ROBOT_BAD_ID},	  /* a mind's HELLO */
	    {0x1C7, 8, EVO_CAN_ROBOT_BAD_ID},	  /* a RESET */
	    {0x1D3, 8, EVO_CAN_ROBOT_BAD_ID},	  /* a flash reply */
	    {0x105, 8, EVO_CAN_ROBOT_BAD_LENGTH}, /* sensor 10 alone: 4 */
	    {0x100, 4, EVO_CAN_ROBOT_BAD_LENGTH},
	    {0x140, 3, EVO_CAN_ROBOT_BAD_LENGTH},
	    {0x1C6, 7, EVO_CAN_ROBOT_BAD_LENGTH},
	    {0x1CB, 4, EVO_CAN_ROBOT_BAD_LENGTH},
	    {0x1CC, 8, EVO_CAN_ROBOT_BAD_LENGTH},
	    {0x1C6, 8, EVO_CAN_ROBOT_BAD_VALUE}, /* a BODY of nothing */
	    {0x100, 9, EVO_CAN_ROBOT_BAD_LENGTH},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		evo_can_frame f = frame(cases[i].id, 8, z);
		f.len = (uint8_t)cases[i].len;
		rx.bad = EVO_CAN_ROBOT_BAD_COUNT;
		CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BAD);
		CHECK_EQ_INT(rx.bad, cases[i].why);
	}
	/* values outside [0, 1]; a reward not finite */
	uint8_t d[8];
	evo_wire_put_u32(d, (uint32_t)EVO_Q16_ONE + 1);
	evo_wire_put_u32(d + 4, 0);
	evo_can_frame f = frame(0x100, 8, d);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_VALUE);
	evo_wire_put_u32(d, 0);
	evo_wire_put_u32(d + 4, (uint32_t)-1);
	f = frame(0x100, 8, d);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.got, 0);
	double inf = INFINITY, ok = -3.5;
	f = frame(0x1CB, 8, (const uint8_t *)&inf);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_VALUE);
	f = frame(0x1CB, 8, (const uint8_t *)&ok);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_NONE);
	CHECK(rx.reward == -3.5);
	/* 12 sensor frames (24 sensors) take no mask... */
	evo_can_rx_init(&rx, 0, 24);
	CHECK_EQ_INT(tick(&rx, 0, 1, 0), EVO_CAN_EV_TICK);
	/* ...but 33 frames do not */
	evo_can_rx_init(&rx, 0, 66);
	CHECK_EQ_INT(tick(&rx, 0, 1, 0), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_LENGTH);
}

TEST(the_bodys_receiver_takes_whole_commands_and_resets)
{
	evo_can_rx rx;
	evo_can_rx_init(&rx, 1, 3); /* 3 actuators: 2 frames */
	evo_q16 a[3] = {1000, 2000, 3000};
	evo_can_frame f;
	uint8_t d[8];
	evo_wire_pack(EVO_WIRE_ACTUATOR, a, 3, 0, &f);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_NONE);
	evo_wire_put_u32(d, 41);
	d[4] = 0;
	f = frame(EVO_WIRE_TICKED, 5, d);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_TICKED);
	CHECK(!rx.complete && rx.tick == 41);
	CHECK_EQ_INT(rx.missing_frames, 0x2);
	for (unsigned k = 0; k < 2; k++) {
		evo_wire_pack(EVO_WIRE_ACTUATOR, a, 3, k, &f);
		evo_can_rx_frame(&rx, &f);
	}
	evo_wire_put_u32(d, 42);
	d[4] = EVO_WIRE_F_INCOMPLETE;
	f = frame(EVO_WIRE_TICKED, 5, d);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_TICKED);
	CHECK(rx.complete && rx.tick == 42 &&
	      rx.flags == EVO_WIRE_F_INCOMPLETE);
	CHECK(memcmp(rx.values, a, sizeof a) == 0);
	/* a RESET with its seeds; one whose seed frame was lost; one with
	 * the seeds of another */
	evo_can_frame r[3];
	evo_can_reset_encode(3, 11, 22, r);
	for (int i = 0; i < 2; i++)
		CHECK_EQ_INT(evo_can_rx_frame(&rx, &r[i]), EVO_CAN_EV_NONE);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &r[2]), EVO_CAN_EV_RESET);
	CHECK(rx.episode == 3 && rx.layout_seed == 11 && rx.seed == 22);
	evo_can_rx_frame(&rx, &r[1]);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &r[2]), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_INCOMPLETE);
	evo_can_frame other[3];
	evo_can_reset_encode(3, 11, 23, other);
	evo_can_rx_frame(&rx, &r[0]);
	evo_can_rx_frame(&rx, &other[1]);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &r[2]), EVO_CAN_EV_BAD);
	/* STOP, HELLO; and what a body does not take */
	evo_wire_put_u32(d, 3);
	f = frame(EVO_WIRE_STOP, 4, d);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_STOP);
	CHECK_EQ_INT(rx.episode, 3);
	uint8_t h[8] = {1, 2, 3, 4, 11, 2, 0, 1};
	f = frame(EVO_WIRE_HELLO, 8, h);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_HELLO);
	CHECK(rx.hello.names_hash == 0x04030201u && rx.hello.sensors == 11 &&
	      rx.hello.actuators == 2 && rx.hello.version == 1);
	f = frame(EVO_WIRE_TICK, 4, d);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_ID);
	f = frame(EVO_WIRE_ACTUATOR + 2, 4, d); /* past 3 actuators */
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_ID);
	f = frame(EVO_WIRE_TICKED, 4, d);
	CHECK_EQ_INT(evo_can_rx_frame(&rx, &f), EVO_CAN_EV_BAD);
	CHECK_EQ_INT(rx.bad, EVO_CAN_ROBOT_BAD_LENGTH);
}

int main(void)
{
	RUN(body_and_reset_frames_are_laid_out_as_docs_wire_md_says);
	RUN(a_tick_is_taken_only_whole);
	RUN(evos_receiver_refuses_by_reason);
	RUN(the_bodys_receiver_takes_whole_commands_and_resets);
	return test_summary();
}
