/* The 2D scene's storage: creation, adding elements, bots, sensors,
 * actuators, rewards and controls, lookups by name, and placing bots and
 * elements (sim/world2d/scene.h). It calls nothing above it: the pieces that
 * run each tick (sensors.c, actuators.c, rewards.c) read the scene, and
 * step.c drives them. A sensor's checks and storage are the scene model's
 * (scene/sensor.c); its rays' directions and team masks are made here. */
#include "world2d/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/number.h"
#include "world2d/scene_internal.h"

evo_scene *evo_scene_create(void)
{
	evo_scene *sc = calloc(1, sizeof *sc);
	if (!sc)
		return NULL;
	const evo_backend *be = &evo_backend_box2d;
	evo_bworld_def wd = be->world_def();
	evo_bworld *bw = be->create(&wd);
	if (!bw) {
		free(sc);
		return NULL;
	}
	evo_core_init(&sc->core, be, bw, &evo_scene_dim_2d);
	sc->world = (evo_world *)bw;
	return sc;
}

void evo_scene_destroy(evo_scene *sc)
{
	if (!sc)
		return;
	evo_core_free(&sc->core);
	free(sc->object);
	free(sc->obstacle);
	free(sc->body_owner);
	free(sc->sense_mem);
	free(sc->sense_shapes);
	sc->be->destroy(sc->bw);
	free(sc);
}

/* Room for one more item in array arr of sc (scene/store.h). */
#define GROW(sc, arr, n, cap)                                                  \
	evo_store_grow((void **)&(sc)->arr, &(sc)->cap, (sc)->n + 1,           \
		       sizeof *(sc)->arr, &(sc)->err)

/* Remember who owns body index `index`: a bot (>= 0) or an object
 * (-(element + 2)). */
static int set_owner(evo_scene *sc, int index, int owner)
{
	if (index >= sc->cap_body_owner) {
		int ncap = sc->cap_body_owner ? sc->cap_body_owner : 16;
		while (ncap <= index)
			ncap *= 2;
		int *p = realloc(sc->body_owner, (size_t)ncap * sizeof *p);
		if (!p)
			return evo_fail(&sc->err, "out of memory");
		for (int i = sc->cap_body_owner; i < ncap; i++)
			p[i] = -1;
		sc->body_owner = p;
		sc->cap_body_owner = ncap;
	}
	sc->body_owner[index] = owner;
	return 0;
}

int evo_scene_add_obstacle(evo_scene *sc, const evo_obstacle *o)
{
	if (GROW(sc, obstacle, n_obstacles, cap_obstacles))
		return -1;
	evo_bshape s = {.type = o->shape,
			.pos = {o->x, o->y, 0},
			.end = {o->x2, o->y2, 0},
			.yaw = o->angle,
			.radius = o->radius,
			.half = {o->half_w, o->half_h, 0}};
	int idx = sc->be->add_static(sc->bw, &s);
	if (idx < 0)
		return evo_fail(&sc->err, "an obstacle needs a positive size");
	sc->obstacle[sc->n_obstacles] = *o;
	return sc->n_obstacles++;
}

static evo_body_id add_object_body(evo_scene *sc, const evo_element_def *d)
{
	evo_bbody_def bd = {.dynamic = 1,
			    .pos = {d->x, d->y, 0},
			    .yaw = d->angle,
			    .density = d->density,
			    .linear_damping = d->linear_damping,
			    .angular_damping = d->angular_damping,
			    .n_shapes = 1,
			    .category = EVO_CAT_OBJECT,
			    .mask = EVO_CAT_ALL,
			    .group = -1};
	bd.shape[0] = (evo_bshape){.type = EVO_SHAPE_CIRCLE,
				   .radius = d->size,
				   .friction = d->friction,
				   .restitution = d->restitution};
	return sc->be->add_body(sc->bw, &bd);
}

int evo_scene_add_episode_obstacle(evo_scene *sc, const evo_obstacle *o)
{
	if (!isfinite(o->x) || !isfinite(o->y) || !isfinite(o->angle) ||
	    !isfinite(o->radius) || !isfinite(o->half_w) ||
	    !isfinite(o->half_h))
		return evo_fail(&sc->err, "obstacle: a value is not a number");
	return evo_scene_add_obstacle(sc, o);
}

int evo_scene_add_wall(evo_scene *sc, double x1, double y1, double x2,
		       double y2)
{
	double v[] = {x1, y1, x2, y2};
	if (!evo_finite_all(v, 4))
		return evo_fail(&sc->err, "wall: a value is not a number");
	if (sc->n_obstacles > sc->n_fixed_obstacles)
		return evo_fail(&sc->err,
				"walls must be added before the first reset");
	evo_obstacle o;
	memset(&o, 0, sizeof o);
	o.shape = EVO_SHAPE_SEGMENT;
	o.x = x1;
	o.y = y1;
	o.x2 = x2;
	o.y2 = y2;
	o.angle = atan2(y2 - y1, x2 - x1);
	o.half_w = 0.5 * hypot(x2 - x1, y2 - y1);
	int idx = evo_scene_add_obstacle(sc, &o);
	if (idx < 0)
		return evo_fail(
		    &sc->err,
		    "wall (%g, %g) -> (%g, %g): its ends are closer than 5 mm",
		    x1, y1, x2, y2);
	sc->n_fixed_obstacles = sc->n_obstacles;
	sc->n_walls++;
	return idx;
}

int evo_scene_add_element(evo_scene *sc, const evo_element_def *d)
{
	if (sc->n_obstacles > sc->n_fixed_obstacles)
		return evo_fail(&sc->err,
				"elements must be added before the first reset");
	evo_element *e =
	    evo_element_store(&sc->element, &sc->cap_elements, sc->n_elements,
			      d, EVO_DIM_2D, NULL, &sc->err);
	if (!e)
		return -1;
	if (d->kind == EVO_PIECE_CYLINDER || d->kind == EVO_PIECE_BOX) {
		evo_obstacle o;
		memset(&o, 0, sizeof o);
		o.shape = d->kind == EVO_PIECE_CYLINDER ? EVO_SHAPE_CIRCLE
							: EVO_SHAPE_BOX;
		o.x = d->x;
		o.y = d->y;
		o.angle = d->angle;
		o.radius = d->size;
		o.half_w = d->half_w;
		o.half_h = d->half_h;
		e->obstacle = evo_scene_add_obstacle(sc, &o);
		if (e->obstacle < 0)
			return -1;
		sc->n_fixed_obstacles = sc->n_obstacles;
	} else if (d->kind == EVO_PIECE_OBJECT) {
		if (GROW(sc, object, n_objects, cap_objects))
			return -1;
		e->body = add_object_body(sc, d);
		if (e->body.index < 0)
			return evo_fail(&sc->err, "element: bad object");
		if (set_owner(sc, e->body.index, -(sc->n_elements + 2)))
			return -1;
		sc->object[sc->n_objects++] = sc->n_elements;
	}
	return sc->n_elements++;
}

/* The checks and the storing are the scene model's (scene/core.c); the
 * body, one Box2D body of def.body at the start pose, is 2D's. */
int evo_scene_add_bot(evo_scene *sc, const evo_bot_def *d)
{
	evo_bot *b = evo_core_add_bot(&sc->core, d, NULL);
	if (!b)
		return -1;
	b->def.body.dynamic = 1;
	b->def.body.pos[0] = d->x;
	b->def.body.pos[1] = d->y;
	b->def.body.pos[2] = 0;
	b->def.body.yaw = d->yaw;
	if (d->team >= 0)
		b->def.body.category |= EVO_CAT_TEAM(d->team);
	b->body = sc->be->add_body(sc->bw, &b->def.body);
	if (b->body.index < 0)
		return evo_fail(&sc->err, "bot: its body needs a positive size");
	if (set_owner(sc, b->body.index, sc->n_bots))
		return -1;
	const evo_bshape *shape = &d->body.shape[0];
	b->radius = shape->type == EVO_SHAPE_CIRCLE
		       ? shape->radius
		       : sqrt(shape->half[0] * shape->half[0] +
			      shape->half[1] * shape->half[1]);
	evo_bot_refresh_pose(sc, b);
	return sc->n_bots++;
}

static int check_bot(evo_scene *sc, int bot)
{
	if (bot < 0 || bot >= sc->n_bots)
		return evo_fail(&sc->err, "no bot %d (there are %d)", bot,
				sc->n_bots);
	return 0;
}

int evo_scene_check_target(evo_scene *sc, int target, const char *what)
{
	if (target == EVO_TARGET_NONE || target == EVO_TARGET_NEAREST_OBJECT ||
	    target == EVO_TARGET_NEAREST_OPPONENT ||
	    target == EVO_TARGET_NEAREST_TEAMMATE)
		return 0;
	if (target < 0 || target >= sc->n_elements)
		return evo_fail(&sc->err, "%s: no element %d", what, target);
	return 0;
}

int evo_scene_add_sensor(evo_scene *sc, int bot, const evo_sensor_def *d)
{
	if (check_bot(sc, bot))
		return -1;
	evo_bot *b = &sc->bot[bot];
	const char *name = d->name ? d->name : "";
	if (evo_scene_check_target(sc, d->target, name))
		return -1;
	if (d->kind == EVO_SENSE_ZONE && d->target != EVO_TARGET_NONE &&
	    (d->target < 0 || sc->element[d->target].kind != EVO_PIECE_ZONE))
		return evo_fail(
		    &sc->err, "sensor '%s': a zone sensor needs a zone", name);
	evo_sensor *s = evo_sensor_store(&b->sensor, b->n_sensors, d,
					 EVO_DIM_2D, b->name, NULL, &sc->err);
	if (!s)
		return -1;
	/* Teammates and opponents are the bots of the sensor's team and of
	 * the others; a bot of no team has no teammates. */
	if (d->sees_teammates && b->team >= 0)
		s->def.mask |= EVO_CAT_TEAM(b->team);
	if (d->sees_opponents)
		s->def.mask |=
		    (uint16_t)(EVO_CAT_TEAMS &
			       ~(b->team >= 0 ? EVO_CAT_TEAM(b->team) : 0u));
	if (d->kind == EVO_SENSE_PROXIMITY) {
		double arc = d->rays > 1 ? fabs(d->arc) : 0;
		double step = d->rays > 1 ? 2 * arc / (d->rays - 1) : 0;
		for (int i = 0; i < d->rays; i++) {
			s->ray_c[i] = cos(d->angle - arc + step * i);
			s->ray_s[i] = sin(d->angle - arc + step * i);
		}
	}
	return b->n_sensors++;
}

int evo_scene_add_actuator(evo_scene *sc, int bot, const evo_actuator_def *d)
{
	if (check_bot(sc, bot))
		return -1;
	evo_bot *b = &sc->bot[bot];
	if (!evo_actuator_store(&b->actuator, b->n_actuators, d, EVO_DIM_2D,
				b->name, NULL, &sc->err))
		return -1;
	return b->n_actuators++;
}

void evo_scene_set_grid(evo_scene *sc, const evo_grid_def *def)
{
	sc->grid = *def;
}

void evo_scene_place_bot(evo_scene *sc, int bot, double x, double y,
			 double angle)
{
	if (bot < 0 || bot >= sc->n_bots)
		return;
	evo_body_id id = sc->bot[bot].body;
	static const double zero[3] = {0, 0, 0};
	sc->be->set_pose(sc->bw, id, (const double[3]){x, y, 0}, angle);
	sc->be->set_velocity(sc->bw, id, zero, zero);
	evo_bot_refresh_pose(sc, &sc->bot[bot]);
}

void evo_scene_place_element(evo_scene *sc, int element, double x, double y)
{
	if (element < 0 || element >= sc->n_elements)
		return;
	evo_element *e = &sc->element[element];
	e->x = x;
	e->y = y;
	if (e->kind == EVO_PIECE_OBJECT) {
		static const double zero[3] = {0, 0, 0};
		sc->be->set_pose(sc->bw, e->body, (const double[3]){x, y, 0},
				 e->angle);
		sc->be->set_velocity(sc->bw, e->body, zero, zero);
	}
}
