/* The 3D sensors (the one evo_sensor of sim/scene/sensor.h, sampled in a
 * 3D scene): proximity rays, distance, the tutorial's target sensor
 * (azimuth, the bearing sensor, and elevation), zones, random and
 * constant values, and the swarm sensors (scene/swarm.h). Each reads the
 * scene and asks the world's ray cast; none calls back up. */
#include <math.h>

#include "world3d/scene3d.h"
#include "world3d/scene3d_internal.h"

static double clamp01(double v)
{
	/* a value that is not a number never reaches a mind */
	if (!(v >= 0))
		return 0;
	return v > 1 ? 1 : v;
}

/* Where the sensor sits in the world, and the target in the bot's frame
 * seen from there. */
static void target_in_body(const evo_scene3d *sc, const evo_bot *b,
			   const evo_sensor *s, double out[3])
{
	double at[3], d[3];
	evo_bot3d_to_world(b, s->def.pos, at);
	const double *t = sc->element[s->def.target].pos;
	for (int k = 0; k < 3; k++)
		d[k] = t[k] - (b->pos[k] + at[k]);
	evo_bot3d_to_body(b, d, out);
}

/* The nearest hit over the sensor's rays, / range; 1 when clear. */
static double proximity(evo_scene3d *sc, int bot, evo_sensor *s)
{
	const evo_bot *b = &sc->bot[bot];
	double from[3], dir[3];
	evo_bot3d_to_world(b, s->def.pos, from);
	for (int k = 0; k < 3; k++)
		from[k] += b->pos[k];
	double best = s->def.range;
	for (int r = 0; r < s->def.rays; r++) {
		double ray[3] = {s->ray_c[r], s->ray_s[r], s->ray_z};
		evo_bot3d_to_world(b, ray, dir);
		double h = sc->be->raycast(sc->bw, from, dir, s->def.range,
					   s->def.mask, EVO_BODY_NONE, bot);
		double hit = h < 0 ? s->def.range : h;
		s->ray[r] = (float)(hit / s->def.range);
		if (hit < best)
			best = hit;
	}
	return best / s->def.range;
}

/* A zone's trigger volume holds point p: p in the zone's own frame
 * (turned by its yaw) lies within its half sides. */
static int zone_holds(const evo_element *z, const double p[3])
{
	double dx = p[0] - z->pos[0], dy = p[1] - z->pos[1],
	       dz = p[2] - z->pos[2];
	double c = cos(z->def.yaw), s = sin(z->def.yaw);
	double lx = c * dx + s * dy, ly = -s * dx + c * dy;
	return fabs(lx) <= z->def.half[0] && fabs(ly) <= z->def.half[1] &&
	       fabs(dz) <= z->def.half[2];
}

/* A bot as range-and-bearing sensors hear it: its broadcast actuators'
 * commands, in the order it has them. */
static int peer_3d(void *ctx, int i, evo_swarm_peer *out)
{
	const evo_bot *b = &((const evo_scene3d *)ctx)->bot[i];
	for (int k = 0; k < 3; k++)
		out->pos[k] = b->pos[k];
	return evo_actuator_broadcasts(b->actuator, b->n_actuators, out);
}

/* Where a coloured bot or element is now, for a camera; how far its body
 * reaches from there, for occlusion. */
static int where_3d(void *ctx, const evo_blob *bl, double pos[3],
		    double *reach)
{
	const evo_scene3d *sc = ctx;
	*reach = 0;
	if (bl->kind == EVO_BLOB_BOT) {
		if (bl->index < 0 || bl->index >= sc->n_bots)
			return 0;
		for (int k = 0; k < 3; k++)
			pos[k] = sc->bot[bl->index].pos[k];
		return 1;
	}
	if (bl->kind != EVO_BLOB_ELEMENT || bl->index < 0 ||
	    bl->index >= sc->n_elements)
		return 0;
	const evo_element *e = &sc->element[bl->index];
	const evo_element_def *d = &e->def;
	if (!e->active)
		return 0;
	for (int k = 0; k < 3; k++)
		pos[k] = e->pos[k];
	double box = sqrt(d->half[0] * d->half[0] + d->half[1] * d->half[1] +
			  d->half[2] * d->half[2]);
	if (d->kind == EVO_PIECE_BOX || (d->kind == EVO_PIECE_OBJECT &&
					  !d->sphere))
		*reach = box;
	else if (d->kind == EVO_PIECE_CYLINDER)
		*reach = hypot(d->radius, d->half_length);
	else if (d->kind == EVO_PIECE_SPHERE || d->kind == EVO_PIECE_OBJECT)
		*reach = d->radius;
	return 1;
}

/* A light, ground or range-and-bearing sensor or a camera
 * (sim/scene/swarm.h);
 * obstacles occlude, the ground does not. */
static double swarm(evo_scene3d *sc, int bot, const evo_sensor *s)
{
	const evo_bot *b = &sc->bot[bot];
	evo_swarm_frame f;
	for (int k = 0; k < 3; k++)
		f.pos[k] = b->pos[k];
	for (int k = 0; k < 9; k++)
		f.R[k] = b->R[k];
	evo_swarm_rays rays = {sc->be, sc->bw, EVO_CAT3D_OBSTACLE,
			       EVO_BODY_NONE, bot};
	if (s->def.kind == EVO_SENSE_LIGHT)
		return evo_swarm_light(&sc->swarm, &f, s->def.pos, s->def.yaw,
				       s->def.swarm.aperture, &rays);
	if (s->def.kind == EVO_SENSE_GROUND)
		return evo_swarm_ground(&sc->swarm, &f, s->def.pos);
	if (s->def.kind == EVO_SENSE_CAMERA)
		return evo_swarm_camera(&sc->swarm, &s->def.swarm, &f, bot,
					where_3d, sc, &rays);
	return evo_swarm_rab(&s->def.swarm, &f, bot, sc->n_bots, peer_3d, sc,
			     &rays);
}

double evo_sensor3d_sample(evo_scene3d *sc, int bot, int k)
{
	evo_bot *b = &sc->bot[bot];
	evo_sensor *s = &b->sensor[k];
	/* a target set off is seen by none (element:set_active) */
	int has = s->def.target >= 0 && s->def.target < sc->n_elements &&
		  sc->element[s->def.target].active;
	double t[3];
	switch (s->def.kind) {
	case EVO_SENSE_PROXIMITY:
		return clamp01(proximity(sc, bot, s));
	case EVO_SENSE_DISTANCE:
		if (!has)
			return 1;
		target_in_body(sc, b, s, t);
		return clamp01(sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) /
			       s->def.scale);
	case EVO_SENSE_BEARING:
		if (!has)
			return 0.5;
		target_in_body(sc, b, s, t);
		return clamp01(0.5 + atan2(t[1], t[0]) / (2 * M_PI));
	case EVO_SENSE_ELEVATION:
		if (!has)
			return 0.5;
		target_in_body(sc, b, s, t);
		return clamp01(0.5 + atan2(t[2], hypot(t[0], t[1])) / M_PI);
	case EVO_SENSE_ZONE:
		return has && zone_holds(&sc->element[s->def.target], b->pos)
			   ? EVO3D_TRUE
			   : EVO3D_FALSE;
	case EVO_SENSE_PRESENCE:
		return has ? EVO3D_TRUE : EVO3D_FALSE;
	case EVO_SENSE_RADAR: {
		/* the target's azimuth from the bot's heading (+ to its
		 * left) in [yaw - arc, yaw + arc) */
		if (!has)
			return EVO3D_FALSE;
		target_in_body(sc, b, s, t);
		double delta = evo_wrap_angle(atan2(t[1], t[0]) - s->def.yaw);
		return delta >= -s->def.arc && delta < s->def.arc
			   ? EVO3D_TRUE
			   : EVO3D_FALSE;
	}
	case EVO_SENSE_MOVEMENT:
		return clamp01(evo_bot_spread(b) / s->def.scale);
	case EVO_SENSE_RANDOM:
		return evo_rng_unit(&sc->rng);
	case EVO_SENSE_CONSTANT:
		return clamp01(s->def.value);
	case EVO_SENSE_LIGHT:
	case EVO_SENSE_GROUND:
	case EVO_SENSE_RAB:
	case EVO_SENSE_CAMERA:
		return swarm(sc, bot, s);
	case EVO_SENSE_OBJECT_DETECTOR: /* 2D only: refused when added */
	case EVO_SENSE_HOLDING:
	case EVO_SENSE_BUMPER:
	case EVO_SENSE_TARGET_SENSOR:
	case EVO_SENSE_KIND_COUNT:
		break;
	}
	return 0.5;
}

void evo_scene3d_sense(evo_scene3d *sc)
{
	for (int i = 0; i < sc->n_bots; i++)
		for (int k = 0; k < sc->bot[i].n_sensors; k++)
			sc->bot[i].sensor[k].value =
			    evo_sensor3d_sample(sc, i, k);
}
