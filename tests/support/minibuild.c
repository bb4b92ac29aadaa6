#include "minibuild.h"

#include <stdio.h>
#include <string.h>

static evo_net_compile_ws ws;

void mb_init(minibuild *b, unsigned sensors, unsigned actuators,
	     unsigned vars)
{
	static const char *const s[] = {"S0", "S1", "S2", "S3",
					"S4", "S5", "S6", "S7"};
	static const char *const m[] = {"M0", "M1", "M2", "M3",
					"M4", "M5", "M6", "M7"};
	static const char *const v[] = {"V0", "V1", "V2", "V3",
					"V4", "V5", "V6", "V7"};
	memset(b, 0, sizeof *b);
	b->n_sensors = (uint16_t)sensors;
	b->n_actuators = (uint16_t)actuators;
	b->n_vars = (uint16_t)vars;
	for (unsigned i = 0; i < 8; i++) {
		b->sensor[i] = s[i];
		b->actuator[i] = m[i];
		b->var[i] = v[i];
		b->var_type[i] = EVO_VAR_PLAIN;
	}
}

static unsigned add(minibuild *b, const char *name, unsigned n_in,
		    const uint8_t *in_type, const uint16_t *in_index,
		    unsigned n_out, const uint8_t *out_type,
		    const uint16_t *out_index)
{
	unsigned i = b->n_skills++;
	evo_build_skill *k = &b->skill[i];
	k->name = name;
	k->kind = EVO_SKILL_NEURAL;
	k->n_in = (uint16_t)n_in;
	k->n_out = (uint16_t)n_out;
	for (unsigned j = 0; j < n_in; j++)
		b->in[i][j] = (evo_image_io){.type = in_type[j],
					     .index = in_index[j]};
	for (unsigned j = 0; j < n_out; j++)
		b->out[i][j] = (evo_image_io){.type = out_type[j],
					      .index = out_index[j]};
	k->in = b->in[i];
	k->out = b->out[i];
	k->net = &b->net[i];
	evo_netdesc *d = &b->net[i];
	memset(d, 0, sizeof *d);
	d->n_in = (uint16_t)n_in;
	d->n_out = (uint16_t)n_out;
	return i;
}

static void node(evo_netdesc *d, uint16_t id, double bias)
{
	evo_netdesc_node *n = &d->node[d->n_nodes++];
	n->id = id;
	n->act = EVO_ACT_IDENTITY;
	n->bias = evo_q16_from_double(bias);
}

static void link(evo_netdesc *d, uint16_t from, uint16_t to, double w)
{
	evo_netdesc_link *l = &d->link[d->n_links++];
	l->from = from;
	l->to = to;
	l->weight = evo_q16_from_double(w);
}

unsigned mb_const(minibuild *b, const char *name, unsigned n_out,
		  const uint8_t *out_type, const uint16_t *out_index,
		  const double *value)
{
	unsigned i = add(b, name, 0, NULL, NULL, n_out, out_type, out_index);
	evo_netdesc *d = &b->net[i];
	for (unsigned k = 0; k < n_out; k++) {
		node(d, (uint16_t)(100 + k), value[k]);
		d->out_id[k] = (uint16_t)(100 + k);
	}
	return i;
}

unsigned mb_copy(minibuild *b, const char *name, unsigned n,
		 const uint8_t *in_type, const uint16_t *in_index,
		 const uint8_t *out_type, const uint16_t *out_index)
{
	unsigned i = add(b, name, n, in_type, in_index, n, out_type, out_index);
	evo_netdesc *d = &b->net[i];
	for (unsigned k = 0; k < n; k++) {
		node(d, (uint16_t)(100 + k), 0);
		link(d, (uint16_t)k, (uint16_t)(100 + k), 1.0);
		d->out_id[k] = (uint16_t)(100 + k);
	}
	return i;
}

unsigned mb_counter(minibuild *b, const char *name, double step,
		    uint8_t out_type, uint16_t out_index)
{
	unsigned i = add(b, name, 0, NULL, NULL, 1, &out_type, &out_index);
	evo_netdesc *d = &b->net[i];
	node(d, 100, step);
	link(d, 100, 100, 1.0);
	d->out_id[0] = 100;
	return i;
}

unsigned mb_hardcoded(minibuild *b, const char *name, const char *cls,
		      unsigned n_out, const uint8_t *out_type,
		      const uint16_t *out_index)
{
	unsigned i = add(b, name, 0, NULL, NULL, n_out, out_type, out_index);
	b->skill[i].kind = EVO_SKILL_HARDCODED;
	b->skill[i].net = NULL;
	b->skill[i].hc_class = cls;
	return i;
}

evo_status mb_finish(minibuild *b)
{
	evo_build build = {
		.n_sensors = b->n_sensors,
		.n_actuators = b->n_actuators,
		.n_vars = b->n_vars,
		.n_skills = b->n_skills,
		.sensor_name = b->sensor,
		.actuator_name = b->actuator,
		.var_name = b->var,
		.var_type = b->var_type,
		.skill = b->skill,
	};
	evo_status st = evo_image_write(&build, &ws, b->image,
					sizeof b->image, &b->image_len);
	if (st != EVO_OK)
		return st;
	uint32_t hash = evo_names_hash(b->sensor, b->n_sensors, b->actuator,
				       b->n_actuators, b->var, b->n_vars);
	st = evo_mind_open(b->image, b->image_len, hash, &b->mind);
	if (st != EVO_OK)
		return st;
	return evo_state_init(&b->mind, b->state_mem, sizeof b->state_mem,
			      &b->state);
}

void mb_step(minibuild *b, const double *sensors, evo_q16 *actuators)
{
	evo_q16 s[8] = {0};
	for (unsigned i = 0; i < b->n_sensors; i++)
		s[i] = evo_q16_from_double(sensors[i]);
	evo_mind_step(&b->mind, b->state, s, actuators);
}
