/* libFuzzer target for a robot's frames over CAN
 * (sim/remote/can_robot_frames.c): evo's receiver, which takes every frame
 * a robot's body sends, and the body's, which `evo serve --can` runs on
 * every frame a mind sends. The first byte chooses the side and the count
 * of values; then each 11 bytes are a frame (id, length up to 15, eight
 * data bytes). Besides crashes and sanitizer reports it checks the
 * receivers' promises: a value taken is in [0, 1], a complete tick has
 * every frame it needs, a refusal has a reason, and a BODY taken has
 * counts a robot can have. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "remote/can_robot.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	int body = data[0] & 1;
	unsigned max = body ? EVO_CAN_MAX_ACTUATORS : EVO_CAN_MAX_SENSORS;
	unsigned n = 1 + (unsigned)(data[0] >> 1) % max;
	evo_can_rx rx;
	evo_can_rx_init(&rx, body, n);
	for (size_t at = 1; at + 11 <= size; at += 11) {
		const uint8_t *p = data + at;
		if (p[2] == 0xFF) {
			evo_can_rx_restart(&rx);
			continue;
		}
		evo_can_frame f;
		f.id = (uint16_t)((p[0] | p[1] << 8) & 0x7FF);
		f.len = (uint8_t)(p[2] & 0x0F);
		memcpy(f.data, p + 3, 8);
		rx.bad = EVO_CAN_ROBOT_BAD_COUNT;
		evo_can_event ev = evo_can_rx_frame(&rx, &f);
		if (ev == EVO_CAN_EV_BAD && rx.bad >= EVO_CAN_ROBOT_BAD_COUNT)
			abort();
		if ((ev == EVO_CAN_EV_TICK || ev == EVO_CAN_EV_TICKED) &&
		    rx.complete && rx.missing_frames)
			abort();
		if (ev == EVO_CAN_EV_BODY &&
		    (rx.body.sensors < 1 ||
		     rx.body.sensors > EVO_CAN_MAX_SENSORS ||
		     rx.body.actuators < 1 ||
		     rx.body.actuators > EVO_CAN_MAX_ACTUATORS ||
		     rx.body.period_100us < 1))
			abort();
		if (body && (ev == EVO_CAN_EV_TICK || ev == EVO_CAN_EV_BODY ||
			     ev == EVO_CAN_EV_DONE))
			abort(); /* evo's events on the body's side */
		if (!body &&
		    (ev == EVO_CAN_EV_TICKED || ev == EVO_CAN_EV_HELLO ||
		     ev == EVO_CAN_EV_RESET || ev == EVO_CAN_EV_STOP))
			abort();
		for (unsigned i = 0; i < n; i++)
			if (rx.values[i] < 0 || rx.values[i] > EVO_Q16_ONE)
				abort();
	}
	return 0;
}
