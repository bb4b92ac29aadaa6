/* What a robot's firmware calls of the MIND runtime, for `make core-check`:
 * linked with --gc-sections, this keeps exactly the runtime code a
 * firmware needs, so its size is the runtime's size. */
#include "evo/mind.h"

void evo_core_check_entry(void);

extern const uint8_t evo_core_check_image[];
const uint8_t evo_core_check_image[64] __attribute__((aligned(4))) = {0};

static _Alignas(8) uint8_t state_mem[512];
static evo_q16 sensors[EVO_MAX_SENSORS], actuators[EVO_MAX_ACTUATORS];
static const char *volatile reason;

void evo_core_check_entry(void)
{
	evo_mind m;
	evo_state *s;
	evo_status st = evo_mind_open(evo_core_check_image,
				      sizeof evo_core_check_image, 0, &m);
	if (st == EVO_OK)
		st = evo_state_init(&m, state_mem, sizeof state_mem, &s);
	if (st != EVO_OK) {
		reason = evo_status_str(st);
		return;
	}
	for (;;)
		evo_mind_step(&m, s, sensors, actuators);
}
