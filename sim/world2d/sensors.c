/* evo — the sensors of a 2D bot (sim/scene/sensor.h): each one samples the
 * scene and gives a value in [0, 1]; booleans read EVO_FALSE or EVO_TRUE.
 * Here each kind is sampled, and a bot's sensors all at once with one
 * area query among them; the proximity sensors' rays are proximity.c's,
 * sensing every bot at once sense_cells.c's. */
#include "world2d/sensors.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "world2d/query.h"
#include "world2d/scene_internal.h"
#include "world2d/sensors_internal.h"

static double boolean(int v)
{
	return v ? EVO_TRUE : EVO_FALSE;
}

/* ---- bumper and radar -------------------------------------------------- */

/* The nearest point of the segment a -> b to p, the parameter clamped to
 * [0, 1] (Kheperax's bumper rule, docs/world.md). */
static void nearest_on_segment(double ax, double ay, double bx, double by,
			       double px, double py, double *qx, double *qy)
{
	double ex = bx - ax, ey = by - ay;
	double ee = ex * ex + ey * ey;
	double t = ee > 0 ? ((px - ax) * ex + (py - ay) * ey) / ee : 0;
	t = t < 0 ? 0 : t > 1 ? 1 : t;
	*qx = ax + t * ex;
	*qy = ay + t * ey;
}

/* The point of shape s nearest to (px, py): on a circle's rim, on a
 * wall, or on a box's outline. */
static void nearest_point(const evo_shape_info *s, double px, double py,
			  double *qx, double *qy)
{
	if (s->type == EVO_SHAPE_CIRCLE) {
		double dx = px - s->x, dy = py - s->y;
		double d = sqrt(dx * dx + dy * dy);
		double k = d > 0 ? s->radius / d : 0;
		*qx = s->x + dx * k;
		*qy = s->y + dy * k;
		return;
	}
	int corners = s->type == EVO_SHAPE_SEGMENT ? 1 : 4;
	double best = INFINITY;
	*qx = s->vx[0];
	*qy = s->vy[0];
	for (int i = 0; i < corners; i++) {
		int j = s->type == EVO_SHAPE_SEGMENT ? 1 : (i + 1) & 3;
		double x, y;
		nearest_on_segment(s->vx[i], s->vy[i], s->vx[j], s->vy[j], px,
				   py, &x, &y);
		double d = (x - px) * (x - px) + (y - py) * (y - py);
		if (d < best) {
			best = d;
			*qx = x;
			*qy = y;
		}
	}
}

/* A bumper: true when the nearest point of some shape it sees lies
 * within reach of the bot's centre, in a direction within arc of the
 * bumper's angle; of the two ends of that arc, the one nearer straight
 * ahead counts and the other does not (Kheperax's rule: its bumpers cover
 * (-90, 0] and [0, 90) degrees). */
static double sample_bumper(const evo_sensor *se, const sense_frame *f,
			    const shape_set *set)
{
	const evo_sensor_def *d = &se->def;
	for (int k = 0; k < set->n; k++) {
		const evo_shape_info *s = &set->s[k];
		if (!(s->category & d->mask))
			continue;
		double qx, qy;
		nearest_point(s, f->x, f->y, &qx, &qy);
		double dx = qx - f->x, dy = qy - f->y;
		if (dx * dx + dy * dy >= d->reach * d->reach)
			continue;
		/* the direction in the bot's frame: + to its right */
		double delta =
		    atan2(-f->s * dx + f->c * dy, f->c * dx + f->s * dy);
		double off = fabs(evo_wrap_angle(delta - d->angle));
		if (off < d->arc ||
		    (off == d->arc && fabs(delta) < fabs(d->angle)))
			return EVO_TRUE;
	}
	return EVO_FALSE;
}

/* A radar: true when the target's bearing from the bot's centre, from
 * its heading, lies in [angle - arc, angle + arc) (one slice of the
 * novelty-search robot's pie). */
static double sample_radar(const evo_scene *sc, int bot,
			   const evo_sensor_def *d, const sense_frame *f)
{
	double tx, ty;
	if (!evo_scene_target_pos(sc, bot, d->target, &tx, &ty))
		return EVO_FALSE;
	double ox = tx - f->x, oy = ty - f->y;
	double a = atan2(-f->s * ox + f->c * oy, f->c * ox + f->s * oy);
	double delta = evo_wrap_angle(a - d->angle);
	return boolean(delta >= -d->arc && delta < d->arc);
}

/* ---- the others ------------------------------------------------------- */

static int holding(const evo_bot *b)
{
	for (int i = 0; i < b->n_actuators; i++)
		if (b->actuator[i].def.kind == EVO_ACT_CLAW &&
		    b->actuator[i].held >= 0)
			return 1;
	return 0;
}

/* ---- the swarm sensors (sim/scene/swarm.h) --------------------------- */

/* A bot as range-and-bearing sensors hear it: its broadcast actuators'
 * commands, in the order it has them. */
static int peer_2d(void *ctx, int i, evo_swarm_peer *out)
{
	const evo_bot *b = &((const evo_scene *)ctx)->bot[i];
	out->pos[0] = b->x;
	out->pos[1] = b->y;
	out->pos[2] = 0;
	return evo_actuator_broadcasts(b->actuator, b->n_actuators, out);
}

/* Where a coloured bot or element is now, for a camera; its reach from
 * there, for occlusion: a cylinder's or box's rim (objects and bots are
 * no obstacles). */
static int where_2d(void *ctx, const evo_blob *bl, double pos[3],
		    double *reach)
{
	const evo_scene *sc = ctx;
	pos[2] = 0;
	*reach = 0;
	if (bl->kind == EVO_BLOB_BOT) {
		if (bl->index < 0 || bl->index >= sc->n_bots)
			return 0;
		pos[0] = sc->bot[bl->index].x;
		pos[1] = sc->bot[bl->index].y;
		return 1;
	}
	if (bl->kind != EVO_BLOB_ELEMENT || bl->index < 0 ||
	    bl->index >= sc->n_elements)
		return 0;
	const evo_element *e = &sc->element[bl->index];
	pos[0] = e->x;
	pos[1] = e->y;
	switch (e->kind) {
	case EVO_PIECE_OBJECT:
		if (!e->active)
			return 0;
		evo_bpose p = sc->be->pose(sc->bw, e->body);
		pos[0] = p.pos[0];
		pos[1] = p.pos[1];
		return 1;
	case EVO_PIECE_ZONE:
		return e->active;
	case EVO_PIECE_CYLINDER:
		*reach = e->size;
		return 1;
	case EVO_PIECE_BOX:
		*reach = hypot(e->half_w, e->half_h);
		return 1;
	default: /* no other kind in 2D */
		return 0;
	}
}

/* A light, ground or range-and-bearing sensor or a camera; obstacles
 * occlude. */
static double sample_swarm(evo_scene *sc, int bot, const evo_sensor_def *d)
{
	const evo_bot *b = &sc->bot[bot];
	evo_swarm_frame f = evo_swarm_frame_2d(b->x, b->y, b->angle);
	evo_swarm_rays rays = {sc->be, sc->bw, EVO_CAT_OBSTACLE, b->body, -1};
	double at[3] = {d->x, d->y, 0};
	if (d->kind == EVO_SENSE_LIGHT)
		return evo_swarm_light(&sc->swarm, &f, at, d->angle,
				       d->swarm.aperture, &rays);
	if (d->kind == EVO_SENSE_GROUND)
		return evo_swarm_ground(&sc->swarm, &f, at);
	if (d->kind == EVO_SENSE_CAMERA)
		return evo_swarm_camera(&sc->swarm, &d->swarm, &f, bot,
					where_2d, sc, &rays);
	return evo_swarm_rab(&d->swarm, &f, bot, sc->n_bots, peer_2d, sc,
			     &rays);
}

/* One sensor's value; set holds the shapes around the bot for a
 * proximity sensor. */
static double sample(evo_scene *sc, int bot, evo_sensor *se, const sense_frame *f,
		     const shape_set *set)
{
	const evo_bot *b = &sc->bot[bot];
	const evo_sensor_def *d = &se->def;
	double px, py, tx, ty;
	switch (d->kind) {
	case EVO_SENSE_PROXIMITY:
		return evo_proximity_sample(se, f, set);
	case EVO_SENSE_DISTANCE:
		if (!evo_scene_target_pos(sc, bot, d->target, &tx, &ty))
			return 1;
		to_world(f, d->x, d->y, &px, &py);
		return clamp01(hypot(tx - px, ty - py) / d->scale);
	case EVO_SENSE_ZONE:
		return boolean(
		    d->target >= 0 && d->target < sc->n_elements &&
		    evo_zone_contains(&sc->element[d->target], f->x, f->y));
	case EVO_SENSE_BEARING: {
		if (!evo_scene_target_pos(sc, bot, d->target, &tx, &ty))
			return 0.5;
		/* The target in the bot's frame: +y is its right. */
		double ox = tx - f->x, oy = ty - f->y;
		double fwd = f->c * ox + f->s * oy;
		double right = -f->s * ox + f->c * oy;
		double a = atan2(right, fwd);
		if (a <= -M_PI)
			a = M_PI; /* straight behind reads 1, never 0 */
		return clamp01(0.5 + a / (2 * M_PI));
	}
	case EVO_SENSE_PRESENCE:
		if (d->target >= 0 && d->target < sc->n_elements)
			return boolean(sc->element[d->target].active);
		return boolean(
		    (d->target == EVO_TARGET_NEAREST_OBJECT ||
		     d->target == EVO_TARGET_NEAREST_OPPONENT ||
		     d->target == EVO_TARGET_NEAREST_TEAMMATE) &&
		    evo_scene_target_pos(sc, bot, d->target, &tx, &ty));
	case EVO_SENSE_OBJECT_DETECTOR: {
		to_world(f, d->x, d->y, &px, &py);
		double ux = f->c * cos(d->angle) - f->s * sin(d->angle);
		double uy = f->s * cos(d->angle) + f->c * sin(d->angle);
		return boolean(
		    evo_scene_object_in_reach(sc, px, py, ux, uy, d->reach, d->arc) >= 0);
	}
	case EVO_SENSE_MOVEMENT:
		return clamp01(evo_bot_spread(b) / d->scale);
	case EVO_SENSE_RANDOM:
		return evo_rng_unit(&sc->rng);
	case EVO_SENSE_CONSTANT:
		return clamp01(d->value);
	case EVO_SENSE_HOLDING:
		return boolean(holding(b));
	case EVO_SENSE_RADAR:
		return sample_radar(sc, bot, d, f);
	case EVO_SENSE_BUMPER:
		return sample_bumper(se, f, set);
	case EVO_SENSE_LIGHT:
	case EVO_SENSE_GROUND:
	case EVO_SENSE_RAB:
	case EVO_SENSE_CAMERA:
		return sample_swarm(sc, bot, d);
	case EVO_SENSE_ELEVATION: /* 3D only: refused when added */
	case EVO_SENSE_TARGET_SENSOR:
	case EVO_SENSE_KIND_COUNT:
		break;
	}
	return 0;
}

double evo_sensor_sample(evo_scene *sc, int bot, int sensor)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	assert(sensor >= 0 && sensor < b->n_sensors);
	evo_sensor *se = &b->sensor[sensor];
	sense_frame f = sense_frame_of(b);
	shape_set set;
	set.s = set.local;
	set.n = 0;
	if (se->def.kind == EVO_SENSE_PROXIMITY) {
		sense_box area = {INFINITY, INFINITY, -INFINITY, -INFINITY};
		evo_fan_box(se, &f, &area);
		evo_shapes_gather(sc, b, &area, se->def.mask, &set);
	} else if (se->def.kind == EVO_SENSE_BUMPER) {
		double r = se->def.reach;
		sense_box area = {f.x - r, f.y - r, f.x + r, f.y + r};
		evo_shapes_gather(sc, b, &area, se->def.mask, &set);
	}
	se->value = sample(sc, bot, se, &f, &set);
	evo_shapes_release(&set);
	return se->value;
}

void evo_bot_sense_with(evo_scene *sc, int bot, const sense_frame *f,
		       const shape_set *set)
{
	evo_bot *b = &sc->bot[bot];
	for (int i = 0; i < b->n_sensors; i++)
		if (!b->sensor[i].idle)
			b->sensor[i].value =
			    sample(sc, bot, &b->sensor[i], f, set);
}

/* One query serves every proximity sensor: the box that holds all of
 * their fans, for the union of what they see. */
void evo_bot_sense(evo_scene *sc, int bot)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	sense_frame f = sense_frame_of(b);
	sense_box area;
	uint16_t mask = evo_sense_area(b, &f, &area);
	shape_set set;
	set.s = set.local;
	set.n = 0;
	if (mask)
		evo_shapes_gather(sc, b, &area, mask, &set);
	evo_bot_sense_with(sc, bot, &f, &set);
	evo_shapes_release(&set);
}

