/* A 3D scene's storage (sim/world3d/scene3d.h): definitions with their
 * defaults (an element's are the scene model's, scene/element.c), the
 * adds (an element's checks and copy are scene/element.c's too; its ODE
 * shape is made here), and making the ODE world from them. A sensor's
 * checks and storage are the scene model's (scene/sensor.c); its rays'
 * directions are made here. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "world3d/scene3d.h"
#include "world3d/scene3d_internal.h"

/* ---- defaults ------------------------------------------------------- */

evo_sensor_def evo_default_sensor3d_def(evo_sense_kind kind)
{
	evo_sensor_def d;
	memset(&d, 0, sizeof d);
	d.kind = kind;
	d.range = 3;
	d.rays = 1;
	d.mask = EVO_CAT3D_BOT | EVO_CAT3D_OBSTACLE | EVO_CAT3D_OBJECT;
	d.target = EVO3D_TARGET_NONE;
	/* a distance's 20 m; movement's spread about 1 at 1.2 m/s, the
	 * wheeled bot's top speed (30 places 4 cm apart spread 0.35 m) */
	d.scale = kind == EVO_SENSE_MOVEMENT ? 0.35 : 20;
	/* a radar's slice: a quarter of the pie, as in 2D */
	d.arc = kind == EVO_SENSE_RADAR ? 45.0 * M_PI / 180.0 : 0;
	d.swarm = evo_default_swarm_sensor(3);
	return d;
}

evo_bot_def evo_default_bot_def3d(void)
{
	evo_bot_def d;
	memset(&d, 0, sizeof d);
	d.half[0] = 0.2;
	d.half[1] = 0.15;
	d.half[2] = 0.05;
	d.mass = 2;
	d.friction = 0.3;
	d.team = -1;
	return d;
}

evo_scene3d_def evo_default_scene3d_def(void)
{
	evo_scene3d_def d;
	d.world = evo_backend_ode.world_def();
	d.substeps = 2;
	d.fault_penalty = -1000;
	return d;
}

/* ---- create, destroy ---------------------------------------------------- */

/* A new world from sc->def (the old one is gone); 0, or -1. */
static int new_world(evo_scene3d *sc)
{
	sc->bw = sc->be->create(&sc->def.world);
	sc->world = (evo_world3d *)sc->bw;
	return sc->bw ? 0 : -1;
}

/* An obstacle into the world, as the backend's shape; its index or -1. */
static int add_static(evo_scene3d *sc, const evo_obstacle3d *o)
{
	evo_bshape s;
	memset(&s, 0, sizeof s);
	s.type = o->type == EVO_SHAPE3D_BOX	   ? EVO_SHAPE_BOX
		 : o->type == EVO_SHAPE3D_CYLINDER ? EVO_SHAPE_CYLINDER
						   : EVO_SHAPE_CIRCLE;
	memcpy(s.pos, o->pos, sizeof s.pos);
	s.yaw = o->yaw;
	memcpy(s.half, o->half, sizeof s.half);
	s.radius = o->radius;
	s.half_length = o->half_length;
	s.axis = o->axis;
	s.friction = o->friction;
	s.category = (uint16_t)o->category;
	return sc->be->add_static(sc->bw, &s);
}

evo_scene3d *evo_scene3d_create(const evo_scene3d_def *def)
{
	if (def->substeps < 1 || def->substeps > 100 ||
	    !isfinite(def->fault_penalty))
		return NULL;
	evo_scene3d *sc = calloc(1, sizeof *sc);
	if (!sc)
		return NULL;
	evo_core_init(&sc->core, &evo_backend_ode, NULL, &evo_scene_dim_3d);
	sc->def = *def;
	if (new_world(sc)) {
		free(sc);
		return NULL;
	}
	return sc;
}

int evo_scene3d_set_def(evo_scene3d *sc, const evo_scene3d_def *def)
{
	if (sc->n_bots > 0 || sc->n_elements > 0)
		return evo_fail(&sc->err, "the physics is set before any bot "
					  "or element");
	if (def->substeps < 1 || def->substeps > 100 ||
	    !isfinite(def->fault_penalty))
		return evo_fail(&sc->err, "substeps 1 to 100, a finite fault "
					  "penalty");
	evo_scene3d_def old = sc->def;
	sc->def = *def;
	if (evo_scene3d_build_world(sc)) {
		/* back to the world it had, with the message kept */
		evo_err e = sc->err;
		sc->def = old;
		evo_scene3d_build_world(sc);
		sc->err = e;
		return -1;
	}
	return 0;
}

void evo_scene3d_destroy(evo_scene3d *sc)
{
	if (!sc)
		return;
	if (sc->bw)
		sc->be->destroy(sc->bw);
	evo_core_free(&sc->core);
	free(sc->obstacle);
	free(sc);
}

/* ---- adding ------------------------------------------------------------- */

static int grow(evo_scene3d *sc, void **p, int *cap, int need, size_t size)
{
	return evo_store_grow(p, cap, need, size, &sc->err);
}

static int finite3(const double v[3])
{
	return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static int positive(double v)
{
	return isfinite(v) && v > 0;
}

/* The static shape of a box, cylinder or sphere element. */
static evo_shape3d element_shape(const evo_element_def *d)
{
	evo_shape3d s;
	memset(&s, 0, sizeof s);
	memcpy(s.pos, d->pos, sizeof s.pos);
	s.yaw = d->yaw;
	memcpy(s.half, d->half, sizeof s.half);
	s.radius = d->radius;
	s.half_length = d->half_length;
	s.axis = 2;
	s.friction = d->friction;
	s.category = d->ground ? EVO_CAT3D_GROUND : EVO_CAT3D_OBSTACLE;
	s.type = d->kind == EVO_PIECE_BOX	  ? EVO_SHAPE3D_BOX
		 : d->kind == EVO_PIECE_CYLINDER ? EVO_SHAPE3D_CYLINDER
						  : EVO_SHAPE3D_SPHERE;
	return s;
}

static int add_obstacle(evo_scene3d *sc, const evo_obstacle3d *o)
{
	if (grow(sc, (void **)&sc->obstacle, &sc->cap_obstacles,
		 sc->n_obstacles + 1, sizeof *sc->obstacle))
		return -1;
	sc->obstacle[sc->n_obstacles] = *o;
	if (add_static(sc, o) < 0)
		return evo_fail(&sc->err,
				"an obstacle whose size is not positive");
	return sc->n_obstacles++;
}

int evo_scene3d_add_element(evo_scene3d *sc, const evo_element_def *d)
{
	evo_element *e =
	    evo_element_store(&sc->element, &sc->cap_elements, sc->n_elements,
			      d, EVO_DIM_3D, "element", &sc->err);
	if (!e)
		return -1;
	if (evo_element_is_solid(d->kind)) {
		evo_shape3d s = element_shape(d);
		/* kept out of the episode's obstacles: before them */
		if (sc->n_obstacles != sc->n_fixed_obstacles)
			return evo_fail(&sc->err, "elements are added before "
						  "the first episode");
		e->obstacle = add_obstacle(sc, &s);
		if (e->obstacle < 0)
			return -1;
		sc->n_fixed_obstacles = sc->n_obstacles;
	}
	return sc->n_elements++;
}

/* The hull's checks are 3D's; the pose's, name's and team's and the
 * storing are the scene model's (scene/core.c); the bodies are made by
 * making the world again. */
int evo_scene3d_add_bot(evo_scene3d *sc, const evo_bot_def *d)
{
	int sphere = d->radius > 0;
	if (!sphere && !(positive(d->half[0]) && positive(d->half[1]) &&
			 positive(d->half[2])))
		return evo_fail(&sc->err, "a bot's half sides must be > 0");
	if (!positive(d->mass))
		return evo_fail(&sc->err, "a bot's mass must be > 0");
	if (!(d->friction >= 0) || !(d->buoyancy >= 0) ||
	    !(d->drag_linear >= 0) || !(d->drag_quadratic >= 0) ||
	    !(d->drag_angular >= 0) || !(d->caster_radius >= 0) ||
	    !finite3(d->cob) || !finite3(d->caster_pos) ||
	    !isfinite(d->buoyancy + d->drag_linear + d->drag_quadratic +
		      d->drag_angular + d->friction + d->caster_radius))
		return evo_fail(&sc->err, "a bot's friction, buoyancy, drag "
					  "and caster must be finite and >= 0");
	if (!evo_core_add_bot(&sc->core, d, "bot"))
		return -1;
	sc->n_bots++;
	if (evo_scene3d_build_world(sc)) {
		sc->n_bots--;
		return -1;
	}
	return sc->n_bots - 1;
}

static evo_bot *check_bot(evo_scene3d *sc, int bot)
{
	if (bot < 0 || bot >= sc->n_bots) {
		evo_fail(&sc->err, "no bot %d", bot);
		return NULL;
	}
	return &sc->bot[bot];
}

int evo_scene3d_add_sensor(evo_scene3d *sc, int bot, const evo_sensor_def *d)
{
	evo_bot *b = check_bot(sc, bot);
	if (!b)
		return -1;
	if (d->target != EVO3D_TARGET_NONE &&
	    (d->target < 0 || d->target >= sc->n_elements))
		return evo_fail(&sc->err, "sensor '%s': no element %d",
				d->name ? d->name : "?", d->target);
	evo_sensor *s =
	    evo_sensor_store(&b->sensor, b->n_sensors, d, EVO_DIM_3D, b->name,
			     "sensor", &sc->err);
	if (!s)
		return -1;
	s->value = 0.5;
	/* the rays fan out over yaw +- arc, all at one pitch */
	s->ray_z = sin(d->pitch);
	for (int r = 0; d->kind == EVO_SENSE_PROXIMITY && r < d->rays; r++) {
		double yaw = d->rays == 1 ? d->yaw
					  : d->yaw - d->arc +
						2 * d->arc * r / (d->rays - 1);
		s->ray_c[r] = cos(d->pitch) * cos(yaw);
		s->ray_s[r] = cos(d->pitch) * sin(yaw);
	}
	return b->n_sensors++;
}

int evo_scene3d_add_actuator(evo_scene3d *sc, int bot,
			     const evo_actuator_def *d)
{
	evo_bot *b = check_bot(sc, bot);
	if (!b || !evo_actuator_store(&b->actuator, b->n_actuators, d,
				      EVO_DIM_3D, b->name, "actuator", &sc->err))
		return -1;
	b->n_actuators++;
	/* a wheel is a body of its own, on a hinge */
	if (d->kind == EVO_ACT_WHEEL && evo_scene3d_build_world(sc)) {
		b->n_actuators--;
		return -1;
	}
	return b->n_actuators - 1;
}

int evo_scene3d_add_episode_obstacle(evo_scene3d *sc, const evo_obstacle3d *o)
{
	evo_obstacle3d s = *o;
	if (s.category != EVO_CAT3D_GROUND)
		s.category = EVO_CAT3D_OBSTACLE;
	if (!finite3(s.pos) || !isfinite(s.yaw))
		return evo_fail(&sc->err, "an obstacle's position is not a "
					  "number");
	if (s.type == EVO_SHAPE3D_CYLINDER)
		s.axis = 2;
	return add_obstacle(sc, &s);
}

/* ---- frames ----------------------------------------------------------------
 */

void evo_bot3d_to_world(const evo_bot *b, const double v[3], double out[3])
{
	for (int i = 0; i < 3; i++)
		out[i] = b->R[3 * i] * v[0] + b->R[3 * i + 1] * v[1] +
			 b->R[3 * i + 2] * v[2];
}

void evo_bot3d_to_body(const evo_bot *b, const double v[3], double out[3])
{
	for (int i = 0; i < 3; i++)
		out[i] =
		    b->R[i] * v[0] + b->R[3 + i] * v[1] + b->R[6 + i] * v[2];
}

/* ---- the world -------------------------------------------------------------
 */

/* A dynamic body at pos turned by yaw, of mass, group and category; its
 * shapes to come. */
static evo_bbody_def body_def(const double pos[3], double yaw, double mass,
			      int group, unsigned category)
{
	evo_bbody_def d;
	memset(&d, 0, sizeof d);
	d.dynamic = 1;
	memcpy(d.pos, pos, sizeof d.pos);
	d.yaw = yaw;
	d.mass = mass;
	d.group = group;
	d.category = (uint16_t)category;
	return d;
}

/* Bot i's bodies: its hull (with its caster), then a body and a hinge for
 * each wheel, turning about the bot's y axis. */
static int build_bot(evo_scene3d *sc, int i)
{
	evo_bot *b = &sc->bot[i];
	const evo_bot_def *d = &b->def;
	evo_bbody_def bd =
	    body_def(b->start, b->start_yaw, d->mass, i, EVO_CAT3D_BOT);
	evo_bshape *hull = &bd.shape[bd.n_shapes++];
	hull->type = d->radius > 0 ? EVO_SHAPE_CIRCLE : EVO_SHAPE_BOX;
	memcpy(hull->half, d->half, sizeof hull->half);
	hull->radius = d->radius;
	hull->friction = d->friction;
	if (d->caster_radius > 0) {
		evo_bshape *c = &bd.shape[bd.n_shapes++];
		c->type = EVO_SHAPE_CIRCLE;
		memcpy(c->pos, d->caster_pos, sizeof c->pos);
		c->radius = d->caster_radius;
		c->friction = 0;
	}
	b->body = sc->be->add_body(sc->bw, &bd);
	if (b->body.index < 0)
		return evo_fail(&sc->err, "bot %s: cannot make its body",
				b->name);
	evo_scene3d_pose(sc, b->body.index, b->pos, b->R);
	for (int k = 0; k < b->n_actuators; k++) {
		evo_actuator *a = &b->actuator[k];
		if (a->def.kind != EVO_ACT_WHEEL)
			continue;
		double hub[3];
		evo_bot3d_to_world(b, a->def.pos, hub);
		for (int j = 0; j < 3; j++)
			hub[j] += b->pos[j];
		evo_bbody_def wd =
		    body_def(hub, b->start_yaw, a->def.mass, i, EVO_CAT3D_BOT);
		wd.n_shapes = 1;
		wd.shape[0].type = EVO_SHAPE_CYLINDER;
		wd.shape[0].radius = a->def.radius;
		wd.shape[0].half_length = a->def.half_width;
		wd.shape[0].axis = 1;
		wd.shape[0].friction = a->def.friction;
		a->body = sc->be->add_body(sc->bw, &wd).index;
		static const double y[3] = {0, 1, 0};
		double axis[3];
		evo_bot3d_to_world(b, y, axis);
		a->hinge = a->body < 0
			       ? -1
			       : sc->be->hinge(
				     sc->bw, evo_scene3d_body(a->body),
				     b->body, wd.pos, axis);
		if (a->hinge < 0)
			return evo_fail(&sc->err,
					"bot %s: cannot make wheel %s", b->name,
					a->name);
	}
	return 0;
}

int evo_scene3d_build_world(evo_scene3d *sc)
{
	if (sc->bw)
		sc->be->destroy(sc->bw);
	if (new_world(sc))
		return evo_fail(&sc->err, "cannot create an ODE world");
	for (int i = 0; i < sc->n_obstacles; i++) {
		int k = add_static(sc, &sc->obstacle[i]);
		if (k < 0)
			return evo_fail(&sc->err, "obstacle %d: bad size", i);
		if (i == 0) /* the core's: for NextOnCollisionWithTarget */
			sc->first_static = k;
		else if (k != sc->first_static + i)
			return evo_fail(&sc->err, "obstacle %d: out of order",
					i);
	}
	for (int i = 0; i < sc->n_bots; i++)
		sc->bot[i].body = EVO_BODY_NONE;
	for (int i = 0; i < sc->n_bots; i++)
		if (build_bot(sc, i))
			return -1;
	evo_scene3d_refresh_bots(sc);
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element *e = &sc->element[i];
		if (e->def.kind != EVO_PIECE_OBJECT)
			continue;
		evo_bbody_def od = body_def(e->pos, e->def.yaw, e->def.mass, -1,
					    EVO_CAT3D_OBJECT);
		od.n_shapes = 1;
		od.shape[0].type =
		    e->def.sphere ? EVO_SHAPE_CIRCLE : EVO_SHAPE_BOX;
		od.shape[0].radius = e->def.radius;
		memcpy(od.shape[0].half, e->def.half, sizeof od.shape[0].half);
		od.shape[0].friction = e->def.friction;
		e->body = sc->be->add_body(sc->bw, &od);
		if (e->body.index < 0)
			return evo_fail(&sc->err, "object %s: cannot make it",
					e->name);
		double v[3];
		evo_scene3d_pose(sc, e->body.index, v, e->R);
		if (!e->active) /* set off this episode: out of the world */
			sc->be->set_enabled(sc->bw, e->body, 0);
	}
	return 0;
}

void evo_scene3d_refresh_bots(evo_scene3d *sc)
{
	for (int i = 0; i < sc->n_bots; i++) {
		evo_bot *b = &sc->bot[i];
		if (b->body.index < 0)
			continue;
		evo_scene3d_pose(sc, b->body.index, b->pos, b->R);
		sc->be->velocity(sc->bw, b->body, b->v,
				 b->omega);
	}
}

double evo_scene3d_distance(const evo_scene3d *sc, int bot, int element)
{
	const double *p = sc->bot[bot].pos, *q = sc->element[element].pos;
	double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
	return sqrt(dx * dx + dy * dy + dz * dz);
}
