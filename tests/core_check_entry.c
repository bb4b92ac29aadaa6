/* What a robot's firmware calls of the MIND runtime, for `make core-check`:
 * linked with --gc-sections, this keeps exactly the runtime code a
 * firmware needs, so its size is the runtime's size. The image and the
 * state memory are the firmware's (its flash and its RAM), so they are
 * reached through pointers here rather than counted as runtime text. A
 * firmware reports a refused image by its status code: the messages
 * (evo_status_str, status.c) are host-side. */
#include "evo/mind.h"

void evo_core_check_entry(void);

/* Not linked (nothing uses it): `make core-check` reads its size from this
 * file's object for the M0+ and for the host, which is sizeof(evo_state)
 * on each, to turn the state size evo reports on the host into the M0+'s. */
extern const uint8_t evo_core_check_state_header[];
const uint8_t evo_core_check_state_header[sizeof(evo_state)] = {0};

static const uint8_t *volatile image;
static volatile size_t image_len;
static _Alignas(8) uint8_t state_mem[512];
static evo_q16 sensors[EVO_MAX_SENSORS], actuators[EVO_MAX_ACTUATORS];
static volatile evo_status refused;

void evo_core_check_entry(void)
{
	evo_mind m;
	evo_state *s;
	evo_status st = evo_mind_open(image, image_len, 0, &m);
	if (st == EVO_OK)
		st = evo_state_init(&m, state_mem, sizeof state_mem, &s);
	if (st != EVO_OK) {
		refused = st;
		return;
	}
	for (;;)
		evo_mind_step(&m, s, sensors, actuators);
}
