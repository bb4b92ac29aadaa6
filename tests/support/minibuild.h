/* Build small minds in a test, without files.
 *
 * Skills are neural with hand-made networks of identity nodes, so their
 * outputs are exact and easy to reason about:
 *   mb_const    every output is a constant (the node's bias);
 *   mb_copy     output k copies input k;
 *   mb_counter  one output that adds `step` to itself each time the skill
 *               is computed (a recurrent self-loop), for showing that a
 *               skipped skill's memory holds. */
#ifndef EVO_TEST_MINIBUILD_H
#define EVO_TEST_MINIBUILD_H

#include "evo/evo.h"

#define MB_MAX_SKILLS 16

typedef struct minibuild {
	const char *sensor[8], *actuator[8], *var[8];
	uint8_t var_type[8];
	uint16_t n_sensors, n_actuators, n_vars, n_skills;
	evo_build_skill skill[MB_MAX_SKILLS];
	evo_image_io in[MB_MAX_SKILLS][8], out[MB_MAX_SKILLS][8];
	evo_netdesc net[MB_MAX_SKILLS];
	_Alignas(8) uint8_t image[16384];
	size_t image_len;
	evo_mind mind;
	_Alignas(8) uint8_t state_mem[16384];
	evo_state *state;
} minibuild;

/* n sensors S0.., actuators M0.., plain variables V0.. (set var_type
 * afterwards for other kinds). */
void mb_init(minibuild *b, unsigned sensors, unsigned actuators,
	     unsigned vars);

/* Add a skill (in tick order; the first is the master). Inputs and
 * outputs are given as types and indices; returns the skill index. */
unsigned mb_const(minibuild *b, const char *name, unsigned n_out,
		  const uint8_t *out_type, const uint16_t *out_index,
		  const double *value);
unsigned mb_copy(minibuild *b, const char *name, unsigned n,
		 const uint8_t *in_type, const uint16_t *in_index,
		 const uint8_t *out_type, const uint16_t *out_index);
unsigned mb_counter(minibuild *b, const char *name, double step,
		    uint8_t out_type, uint16_t out_index);
unsigned mb_hardcoded(minibuild *b, const char *name, const char *cls,
		      unsigned n_out, const uint8_t *out_type,
		      const uint16_t *out_index);

/* Write the image, open it, init a state; returns the first failure. */
evo_status mb_finish(minibuild *b);

/* Step with sensor values given as doubles. */
void mb_step(minibuild *b, const double *sensors, evo_q16 *actuators);

#endif
