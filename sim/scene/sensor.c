/* The sensors of either world (sim/scene/sensor.h): the checks and storage
 * of an add that the 2D and 3D scenes share. */
#include "scene/sensor.h"

#include <math.h>
#include <stddef.h>

#include "base/number.h"

/* 0 when the numbers d's kind reads are ones it can use, or -1 with err
 * set naming the sensor. */
static int check_numbers(const evo_sensor_def *d, const char *name,
			 evo_err *err)
{
	double v[] = {d->pos[0], d->pos[1], d->pos[2], d->angle,
		      d->pitch,	 d->range,  d->arc,    d->deadzone,
		      d->scale,	 d->reach,  d->value};
	if (!evo_finite_all(v, (int)(sizeof v / sizeof v[0])))
		return evo_fail(err, "sensor '%s': a value is not a number",
				name);
	if (d->kind == EVO_SENSE_PROXIMITY &&
	    (!(d->range > 0) || d->rays < 1 || d->rays > EVO_PROX_MAX_RAYS ||
	     d->arc < 0))
		return evo_fail(err,
				"sensor '%s': proximity needs range > 0, "
				"arc >= 0 and 1 to %d rays",
				name, EVO_PROX_MAX_RAYS);
	if ((d->kind == EVO_SENSE_DISTANCE || d->kind == EVO_SENSE_MOVEMENT) &&
	    !(d->scale > 0))
		return evo_fail(err, "sensor '%s': scale must be positive",
				name);
	if (d->kind == EVO_SENSE_BUMPER && !(d->reach > 0))
		return evo_fail(err, "sensor '%s': reach must be positive",
				name);
	if ((d->kind == EVO_SENSE_BUMPER || d->kind == EVO_SENSE_RADAR) &&
	    !(d->arc >= 0))
		return evo_fail(err, "sensor '%s': arc must be 0 or more",
				name);
	if ((d->kind == EVO_SENSE_LIGHT || d->kind == EVO_SENSE_RAB ||
	     d->kind == EVO_SENSE_CAMERA) &&
	    evo_swarm_check_sensor(&d->swarm, name, err))
		return -1;
	return 0;
}

/* 0 when d's kind is one world dim samples, or -1 with err set. */
static int check_kind(const evo_sensor_def *d, unsigned dim, const char *name,
		      evo_err *err)
{
	if ((unsigned)d->kind >= EVO_SENSE_KIND_COUNT)
		return evo_fail(err, "sensor '%s': unknown kind %d", name,
				(int)d->kind);
	const evo_kind_row *row = evo_sense_kind_row(d->kind);
	if (!(row->dims & dim))
		return evo_fail(err,
				"sensor '%s': %s is no sensor of the %s "
				"world",
				name, row->name,
				dim == EVO_DIM_2D ? "2D" : "3D");
	/* bot:target_sensor makes a bearing or an elevation sensor of its
	 * axis: nothing samples the name itself */
	if (d->kind == EVO_SENSE_TARGET_SENSOR)
		return evo_fail(err,
				"sensor '%s': a target sensor is added as a "
				"bearing (axis 1) or elevation (axis 2) sensor",
				name);
	return 0;
}

evo_sensor *evo_sensor_store(evo_sensor **arr, int n, const evo_sensor_def *d,
			     unsigned dim, const char *bot, const char *dflt,
			     evo_err *err)
{
	const char *name = d->name ? d->name : "";
	if (check_kind(d, dim, name, err) || check_numbers(d, name, err))
		return NULL;
	if (name[0] && evo_store_find(*arr, n, sizeof **arr,
				      offsetof(evo_sensor, name), name) >= 0) {
		evo_fail(err, "bot %s: sensor '%s' is defined twice",
			 bot && bot[0] ? bot : "?", name);
		return NULL;
	}
	evo_sensor *s = evo_store_add((void **)arr, NULL, n, sizeof *s, err);
	if (!s || evo_store_name(s->name, d->name, dflt, n, err))
		return NULL;
	s->def = *d;
	s->def.name = NULL;
	for (int i = 0; i < EVO_PROX_MAX_RAYS; i++)
		s->ray[i] = 1.0f;
	return s;
}
