/* evo — ODE behind the physics backend interface (sim/scene/backend.h):
 * evo_backend_ode, whose functions pass their arguments to world3d.h's,
 * unchanged, so a scene gives the same simulation to the bit through
 * either. The world is evo_world3d, seen as an evo_bworld; a body id's
 * index is the body's, its generation always 0 (a 3D world is made
 * again, never patched). */
#include <math.h>
#include <string.h>

#include "world3d/world3d.h"

static evo_world3d *W(evo_bworld *w)
{
	return (evo_world3d *)w;
}

static const evo_world3d *CW(const evo_bworld *w)
{
	return (const evo_world3d *)w;
}

static int body_ok(const evo_bworld *w, evo_body_id id)
{
	return id.index >= 0 && id.index < evo_world3d_n_bodies(CW(w)) &&
	       id.generation == 0;
}

static evo_bworld_def b_world_def(void)
{
	evo_world3d_def d = evo_default_world3d_def();
	return (evo_bworld_def){.step = d.step,
				.gravity = d.gravity,
				.erp = d.erp,
				.cfm = d.cfm,
				.ground_friction = d.ground_friction,
				.max_speed = d.max_speed,
				.max_spin = d.max_spin};
}

static evo_bworld *b_create(const evo_bworld_def *b)
{
	evo_world3d_def d = {.step = b->step,
			     .gravity = b->gravity,
			     .erp = b->erp,
			     .cfm = b->cfm,
			     .ground_friction = b->ground_friction,
			     .max_speed = b->max_speed,
			     .max_spin = b->max_spin};
	return (evo_bworld *)evo_world3d_create(&d);
}

static void b_destroy(evo_bworld *w)
{
	evo_world3d_destroy(W(w));
}

/* A shape of the interface as ODE's; -1 for one ODE has not (a segment). */
static int shape3d_of(const evo_bshape *s, unsigned category, evo_shape3d *out)
{
	memset(out, 0, sizeof *out);
	switch (s->type) {
	case EVO_SHAPE_CIRCLE:
		out->type = EVO_SHAPE3D_SPHERE;
		break;
	case EVO_SHAPE_BOX:
		out->type = EVO_SHAPE3D_BOX;
		break;
	case EVO_SHAPE_CYLINDER:
		out->type = EVO_SHAPE3D_CYLINDER;
		break;
	case EVO_SHAPE_SEGMENT:
		return -1;
	}
	memcpy(out->pos, s->pos, sizeof out->pos);
	out->yaw = s->yaw;
	memcpy(out->half, s->half, sizeof out->half);
	out->radius = s->radius;
	out->half_length = s->half_length;
	out->axis = s->axis;
	out->friction = s->friction;
	out->category = category;
	return 0;
}

static evo_body_id b_add_body(evo_bworld *w, const evo_bbody_def *b)
{
	evo_body3d_def d;
	memset(&d, 0, sizeof d);
	if (!b->dynamic || b->n_shapes < 1 ||
	    b->n_shapes > EVO_BODY3D_MAX_SHAPES)
		return EVO_BODY_NONE;
	memcpy(d.pos, b->pos, sizeof d.pos);
	d.yaw = b->yaw;
	d.mass = b->mass;
	d.group = b->group;
	d.n_shapes = b->n_shapes;
	for (int i = 0; i < b->n_shapes; i++)
		if (shape3d_of(&b->shape[i], b->category, &d.shape[i]))
			return EVO_BODY_NONE;
	int i = evo_world3d_add_body(W(w), &d);
	return i < 0 ? EVO_BODY_NONE : (evo_body_id){i, 0};
}

static int b_valid(const evo_bworld *w, evo_body_id id)
{
	return body_ok(w, id);
}

static int b_add_static(evo_bworld *w, const evo_bshape *s)
{
	evo_shape3d d;
	if (shape3d_of(s, s->category, &d))
		return -1;
	return evo_world3d_add_static(W(w), &d);
}

static evo_bpose b_pose(const evo_bworld *w, evo_body_id id)
{
	evo_bpose p;
	evo_body3d_pose(CW(w), id.index, p.pos, p.R);
	p.yaw = atan2(p.R[3], p.R[0]);
	return p;
}

static void b_set_pose(evo_bworld *w, evo_body_id id, const double pos[3],
		       double yaw)
{
	evo_body3d_set_pose(W(w), id.index, pos, yaw);
}

static void b_velocity(const evo_bworld *w, evo_body_id id, double v[3],
		       double omega[3])
{
	evo_body3d_velocity(CW(w), id.index, v, omega);
}

static void b_set_velocity(evo_bworld *w, evo_body_id id, const double v[3],
			   const double omega[3])
{
	evo_body3d_set_velocity(W(w), id.index, v, omega);
}

static void b_set_enabled(evo_bworld *w, evo_body_id id, int enabled)
{
	evo_body3d_set_enabled(W(w), id.index, enabled);
}

static void b_apply_force_at(evo_bworld *w, evo_body_id id, const double f[3],
			     const double at[3], unsigned frames)
{
	switch (frames & (EVO_BFORCE_BODY | EVO_BPOINT_BODY)) {
	case 0:
		evo_body3d_add_force_at_pos(W(w), id.index, f, at);
		break;
	case EVO_BFORCE_BODY:
		evo_body3d_add_rel_force_at_pos(W(w), id.index, f, at);
		break;
	case EVO_BPOINT_BODY:
		evo_body3d_add_force_at(W(w), id.index, f, at);
		break;
	default:
		evo_body3d_add_rel_force_at(W(w), id.index, f, at);
	}
}

static void b_add_torque(evo_bworld *w, evo_body_id id, const double t[3])
{
	evo_body3d_add_torque(W(w), id.index, t);
}

static int b_hinge(evo_bworld *w, evo_body_id a, evo_body_id b,
		   const double anchor[3], const double axis[3])
{
	if (!body_ok(w, a) || !body_ok(w, b))
		return -1;
	return evo_world3d_add_hinge(W(w), a.index, b.index, anchor, axis);
}

static void b_hinge_torque(evo_bworld *w, int hinge, double torque)
{
	evo_world3d_hinge_torque(W(w), hinge, torque);
}

static void b_hinge_velocity(evo_bworld *w, int hinge, double rate, double fmax)
{
	evo_world3d_hinge_velocity(W(w), hinge, rate, fmax);
}

static double b_hinge_rate(const evo_bworld *w, int hinge)
{
	return evo_world3d_hinge_rate(CW(w), hinge);
}

static double b_raycast(evo_bworld *w, const double from[3],
			const double dir[3], double len, uint16_t mask,
			evo_body_id ignore, int ignore_group)
{
	(void)ignore;
	return evo_world3d_raycast(W(w), from, dir, len, mask, ignore_group);
}

/* Contacts in the last step of the body's group (see
 * evo_world3d_group_touching); 0 for a body of a group of its own. */
static int b_touching(const evo_bworld *w, evo_body_id id)
{
	if (!body_ok(w, id))
		return 0;
	return evo_world3d_group_touching(CW(w),
					  evo_body3d_group(CW(w), id.index));
}

/* What the body's group touched since b_forget_touches. */
static int b_touching_body(const evo_bworld *w, evo_body_id id,
			   evo_body_id other)
{
	if (!body_ok(w, id) || !body_ok(w, other))
		return 0;
	return evo_world3d_group_touched_body(
	    CW(w), evo_body3d_group(CW(w), id.index), other.index);
}

static int b_touching_obstacle(const evo_bworld *w, evo_body_id id,
			       int obstacle)
{
	if (!body_ok(w, id))
		return 0;
	return evo_world3d_group_touched(
	    CW(w), evo_body3d_group(CW(w), id.index), obstacle);
}

static void b_forget_touches(evo_bworld *w)
{
	evo_world3d_forget_touches(W(w));
}

static int b_step(evo_bworld *w, evo_bfault *fault)
{
	evo_bfault unwanted; /* fault may be NULL */
	return evo_world3d_step(W(w), fault ? fault : &unwanted);
}

/* NULL: what a 3D world does not do (reset: a 3D scene makes its world
 * again; bodies are never removed or asleep (set_enabled takes an object
 * set off out of the world); no welds, no broad-phase query, no
 * kinematic body). */
const evo_backend evo_backend_ode = {
    .name = "ODE",
    .dims = 3,
    .world_def = b_world_def,
    .create = b_create,
    .destroy = b_destroy,
    .add_body = b_add_body,
    .valid = b_valid,
    .add_static = b_add_static,
    .pose = b_pose,
    .set_pose = b_set_pose,
    .velocity = b_velocity,
    .set_velocity = b_set_velocity,
    .set_enabled = b_set_enabled,
    .apply_force_at = b_apply_force_at,
    .add_torque = b_add_torque,
    .hinge = b_hinge,
    .hinge_torque = b_hinge_torque,
    .hinge_velocity = b_hinge_velocity,
    .hinge_rate = b_hinge_rate,
    .raycast = b_raycast,
    .touching = b_touching,
    .touching_body = b_touching_body,
    .touching_obstacle = b_touching_obstacle,
    .forget_touches = b_forget_touches,
    .step = b_step,
};
