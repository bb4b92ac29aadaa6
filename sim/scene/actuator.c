/* A bot's actuators, one definition for both worlds (scene/actuator.h):
 * their defaults, adding one with the checks of both worlds, and what a
 * bot broadcasts. */
#include "scene/actuator.h"

#include <math.h>
#include <string.h>

#include "base/number.h"

evo_actuator_def evo_default_actuator_def(evo_act_kind kind)
{
	evo_actuator_def d;
	memset(&d, 0, sizeof d);
	d.kind = kind;
	/* 2D */
	d.max_force = 80.0;
	d.reach = 1.5;
	d.max_speed = 1.0;
	if (kind == EVO_ACT_CLAW)
		d.x = 1.0;
	/* 3D */
	d.axis[0] = 1;
	d.max_thrust = 10;
	d.radius = 0.08;
	d.half_width = 0.02;
	d.mass = 0.2;
	d.friction = 1;
	d.max_rate = 15;
	d.max_torque = 2;
	return d;
}

static int nonneg(double v)
{
	return v >= 0 && isfinite(v);
}

/* The checks of the kind's own values; 0, or -1 with err set. */
static int check_values(const evo_actuator_def *d, const char *name,
			evo_err *err)
{
	double v[] = {d->pos[0],    d->pos[1],	d->pos[2],    d->angle,
		      d->max_force, d->reach,	d->max_speed, d->accel,
		      d->axis[0],   d->axis[1], d->axis[2]};
	if (!evo_finite_all(v, (int)(sizeof v / sizeof *v)))
		return evo_fail(err, "actuator '%s': a value is not a number",
				name);
	switch (d->kind) {
	case EVO_ACT_SPEED_WHEEL:
	case EVO_ACT_DRIVE:
		if (!(d->max_speed > 0) || d->accel < 0)
			return evo_fail(err,
					"actuator '%s': max_speed must be "
					"positive and accel 0 or more",
					name);
		break;
	case EVO_ACT_PROPELLER:
		if (!(sqrt(d->axis[0] * d->axis[0] + d->axis[1] * d->axis[1] +
			   d->axis[2] * d->axis[2]) > 1e-9) ||
		    !nonneg(d->max_thrust))
			return evo_fail(err,
					"propeller '%s': its axis must not be "
					"0 and max_thrust finite and >= 0",
					name);
		break;
	default:
		break;
	}
	return 0;
}

/* The 3D wheel's body and drive; 0, or -1 with err set. */
static int check_wheel3d(const evo_actuator_def *d, const char *name,
			 evo_err *err)
{
	if (d->radius > 0 && isfinite(d->radius) && d->half_width > 0 &&
	    isfinite(d->half_width) && d->mass > 0 && isfinite(d->mass) &&
	    nonneg(d->friction) && nonneg(d->max_rate) && nonneg(d->max_torque))
		return 0;
	return evo_fail(err,
			"wheel '%s': radius, width and mass must be > 0, "
			"friction, max_rate and max_torque finite and >= 0",
			name);
}

static int check(const evo_actuator_def *d, unsigned dim, evo_err *err)
{
	const char *name = d->name ? d->name : "";
	const evo_kind_row *row = evo_act_kind_row((int)d->kind);
	if (!row)
		return evo_fail(err, "actuator '%s': unknown kind %d", name,
				(int)d->kind);
	if (!(row->dims & dim))
		return evo_fail(err,
				"actuator '%s': %s is no actuator of the %s "
				"world",
				name, row->name,
				dim == EVO_DIM_2D ? "2D" : "3D");
	if (check_values(d, name, err))
		return -1;
	if (dim == EVO_DIM_3D && d->kind == EVO_ACT_WHEEL)
		return check_wheel3d(d, name, err);
	return 0;
}

evo_actuator *evo_actuator_store(evo_actuator **arr, int n,
				 const evo_actuator_def *d, unsigned dim,
				 const char *bot, const char *dflt,
				 evo_err *err)
{
	if (check(d, dim, err))
		return NULL;
	if (d->name && d->name[0] &&
	    evo_store_find(*arr, n, sizeof **arr, offsetof(evo_actuator, name),
			   d->name) >= 0) {
		evo_fail(err, "bot %s: actuator '%s' is defined twice",
			 bot && bot[0] ? bot : "?", d->name);
		return NULL;
	}
	evo_actuator *a = evo_store_add((void **)arr, NULL, n, sizeof *a, err);
	if (!a || evo_store_name(a->name, d->name, dflt, n, err))
		return NULL;
	a->def = *d;
	a->def.name = NULL;
	if (d->kind == EVO_ACT_PROPELLER) {
		double len =
		    sqrt(d->axis[0] * d->axis[0] + d->axis[1] * d->axis[1] +
			 d->axis[2] * d->axis[2]);
		for (int k = 0; k < 3; k++)
			a->def.axis[k] = d->axis[k] / len;
	}
	a->command = a->previous = 0.5;
	a->held = a->joint = -1;
	a->body = a->hinge = -1;
	a->dir_c = cos(d->angle);
	a->dir_s = sin(d->angle);
	return a;
}

int evo_actuator_broadcasts(const evo_actuator *a, int n, evo_swarm_peer *out)
{
	out->n_values = 0;
	int any = 0;
	for (int k = 0; k < n; k++) {
		if (a[k].def.kind != EVO_ACT_BROADCAST)
			continue;
		any = 1;
		if (out->n_values < EVO_SWARM_MAX_VALUES)
			out->value[out->n_values++] = a[k].command;
	}
	return any;
}
