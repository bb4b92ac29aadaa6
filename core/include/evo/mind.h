/* evo — the mind model, its state, and the tick.
 *
 * A mind model is always a mind image (see image.h): read-only bytes that
 * on a robot live in flash and are used in place. evo_mind is a small view
 * over those bytes, filled by evo_mind_open after the image is validated.
 *
 * The mind state is everything that changes while the mind runs:
 * influences, variables, previous values for derivatives, recurrent
 * activations, the tick counter. Its size comes from the model
 * (evo_state_size) and its memory from the caller (evo_state_init).
 *
 * docs/mind.md defines the tick and influence; this header is the API. */
#ifndef EVO_MIND_H
#define EVO_MIND_H

#include <stddef.h>
#include <stdint.h>

#include "evo/fixed.h"
#include "evo/image.h"
#include "evo/net.h"
#include "evo/status.h"

/* A skill whose influence is below this (0.01) is not computed. */
#define EVO_INFLUENCE_MIN ((evo_q16)655)

/* Words of private memory each hard-coded skill gets in the state. */
#define EVO_HC_WORDS 4

typedef struct evo_mind {
	const uint8_t *base; /* the image */
	uint32_t length;
	uint16_t n_sensors, n_actuators, n_vars, n_skills, n_nets;
	uint16_t max_io;	 /* largest skill input or output count */
	uint16_t n_hardcoded;
	uint16_t max_ff_nodes;	 /* largest feed-forward net, nodes */
	uint32_t n_persist;	 /* recurrent activations kept, words */
	const uint8_t *var_type; /* n_vars, evo_var_type */
	const evo_image_skill *skill; /* n_skills, top-down; 0 = master */
	const evo_image_io *io;
	const evo_image_net *net;
	const char *names; /* NUL-separated; see image.h */
	uint32_t names_len;
} evo_mind;

/* Validate an image and view it as a mind. buf must be 4-byte aligned and
 * stay valid and unchanged while the mind is used. names_hash is the hash
 * of the names the caller runs with (evo_names_hash): an image built for
 * other sensors, actuators or variables is refused. Checks, in order:
 * alignment, magic, version, length, CRC-32, names hash, layout (every
 * offset, count and index in range; sub-skills come after their parents;
 * networks match their skills; every network weight and bias below
 * EVO_NET_WEIGHT_MAX in magnitude, else EVO_ERR_IMAGE_RANGE), and
 * hard-coded classes. */
evo_status evo_mind_open(const void *buf, size_t len, uint32_t names_hash,
			 evo_mind *m);

/* Per-variable state. */
typedef struct evo_var_state {
	evo_q16 value; /* what VA inputs read */
	evo_q16 prev;  /* value at the previous tick, for VD */
	int32_t a, b;  /* type-specific; see variables.c */
} evo_var_state;

typedef struct evo_state {
	uint32_t tick;	      /* ticks stepped since init or reset */
	evo_q16 *influence;   /* n_skills, this tick's */
	evo_q16 *actuator;    /* n_actuators, this tick's commands */
	evo_q16 *sensor_prev; /* n_sensors, last tick's sensor values */
	evo_var_state *var;   /* n_vars */
	evo_q16 *persist;     /* recurrent network activations */
	evo_q16 *ff;	      /* feed-forward network scratch */
	int32_t *hc;	      /* EVO_HC_WORDS per hard-coded skill */
	uint64_t *acc_num;    /* n_actuators + n_vars weighted sums, Q32 */
	uint32_t *acc_den;    /* n_actuators + n_vars summed influence, Q16 */
	evo_q16 *io_in, *io_out; /* max_io each */
	uint8_t *hc_class;	 /* per hard-coded skill: evo_hc_classes index */
} evo_state;

/* Bytes of caller memory a state for m needs (the evo_state included); a
 * multiple of 8. */
size_t evo_state_size(const evo_mind *m);

/* Lay out a state in mem (8-byte aligned, at least evo_state_size bytes)
 * and reset it. *out points into mem. */
evo_status evo_state_init(const evo_mind *m, void *mem, size_t size,
			  evo_state **out);

/* Back to tick 0: variables, derivatives, recurrent memory and hard-coded
 * skill memory as at init. */
void evo_state_reset(const evo_mind *m, evo_state *s);

/* One tick. sensors: n_sensors values, clamped to [0, 1] on read.
 * actuators: receives n_actuators commands in [0, 1] (also kept in
 * s->actuator). See docs/mind.md for the exact order of work. */
void evo_mind_step(const evo_mind *m, evo_state *s, const evo_q16 *sensors,
		   evo_q16 *actuators);

/* The n-th name of a kind in the image's name table, or "" if absent. */
const char *evo_mind_sensor_name(const evo_mind *m, unsigned i);
const char *evo_mind_actuator_name(const evo_mind *m, unsigned i);
const char *evo_mind_var_name(const evo_mind *m, unsigned i);
const char *evo_mind_skill_name(const evo_mind *m, unsigned i);

/* The compiled network of neural skill i (undefined for hard-coded). */
void evo_mind_net(const evo_mind *m, unsigned skill, evo_net *net);

/* ---- hard-coded skills -------------------------------------------- */

typedef struct evo_hc_ctx {
	const evo_q16 *in; /* the skill's inputs, as its .ades lists them */
	evo_q16 *out;	   /* its outputs; clamped to [0, 1] afterwards */
	uint16_t n_in, n_out;
	int32_t *mem; /* EVO_HC_WORDS, zero at reset */
	uint32_t tick;
} evo_hc_ctx;

typedef void (*evo_hc_fn)(evo_hc_ctx *c);

typedef struct evo_hc_class {
	const char *name; /* as written after class: in .ades */
	int16_t n_in, n_out; /* required counts, -1 for any */
	evo_hc_fn fn;
} evo_hc_class;

/* The built-in classes; see core/src/hardcoded.c to add one. */
extern const evo_hc_class evo_hc_classes[];
extern const unsigned evo_hc_class_count;

/* Look a class up by name, or by evo_name_hash(name); NULL if absent. */
const evo_hc_class *evo_hc_find(const char *name);
const evo_hc_class *evo_hc_find_hash(uint32_t hash);

#endif
