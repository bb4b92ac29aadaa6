/* The entry of runtime-m0.elf and runtime-m3.elf (make firmware-size):
 * everything a firmware calls of the MIND runtime, linked with
 * --gc-sections, so the ELF's size is the runtime's alone. The image, the
 * state memory and the signal arrays are the firmware's, reached here
 * through pointers so that they do not count as the runtime's. */
#include "evo/mind.h"

void fw_size_entry(void);

static const void *volatile image;
static void *volatile state_mem;
static const evo_q16 *volatile sensors;
static evo_q16 *volatile actuators;
static volatile uint32_t result;

void fw_size_entry(void)
{
	evo_mind m;
	evo_state *s;
	size_t size;
	if (evo_mind_open(image, 8192, 0, &m) != EVO_OK)
		return;
	size = evo_state_size(&m);
	if (evo_state_init(&m, state_mem, size, &s) != EVO_OK)
		return;
	for (;;) {
		evo_mind_step(&m, s, sensors, actuators);
		result = s->tick;
	}
}
