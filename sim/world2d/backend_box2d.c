/* evo — Box2D behind the physics backend interface (sim/scene/backend.h):
 * evo_backend_box2d, whose functions pass their arguments to world.h's,
 * unchanged, so a scene gives the same simulation to the bit through
 * either. The world is evo_world, seen as an evo_bworld. */
#include <math.h>
#include <stddef.h>

#include "world2d/world.h"

static evo_world *W(evo_bworld *w)
{
	return (evo_world *)w;
}

static const evo_world *CW(const evo_bworld *w)
{
	return (const evo_world *)w;
}

static evo_bworld_def b_world_def(void)
{
	evo_world_def d = evo_default_world_def();
	evo_bworld_def b = {0};
	b.step = d.step;
	b.velocity_iterations = d.velocity_iterations;
	b.position_iterations = d.position_iterations;
	return b;
}

static evo_bworld *b_create(const evo_bworld_def *b)
{
	evo_world_def d;
	d.step = b->step;
	d.velocity_iterations = b->velocity_iterations;
	d.position_iterations = b->position_iterations;
	return (evo_bworld *)evo_world_create(&d);
}

static void b_destroy(evo_bworld *w)
{
	evo_world_destroy(W(w));
}

static void b_reset(evo_bworld *w)
{
	evo_world_reset(W(w));
}

static evo_body_id b_add_body(evo_bworld *w, const evo_bbody_def *b)
{
	if (b->n_shapes != 1 || (b->shape[0].type != EVO_SHAPE_CIRCLE &&
				 b->shape[0].type != EVO_SHAPE_BOX))
		return EVO_BODY_NONE;
	evo_body_def d = {0};
	d.dynamic = b->dynamic;
	d.kinematic = b->kinematic;
	d.x = b->pos[0];
	d.y = b->pos[1];
	d.angle = b->yaw;
	d.shape = b->shape[0].type;
	d.radius = b->shape[0].radius;
	d.half_w = b->shape[0].half[0];
	d.half_h = b->shape[0].half[1];
	d.density = b->density;
	d.friction = b->shape[0].friction;
	d.restitution = b->shape[0].restitution;
	d.linear_damping = b->linear_damping;
	d.angular_damping = b->angular_damping;
	d.allow_sleep = b->allow_sleep;
	d.category = b->category;
	d.mask = b->mask;
	return evo_world_add_body(W(w), &d);
}

static int b_remove_body(evo_bworld *w, evo_body_id id)
{
	return evo_world_remove_body(W(w), id);
}

static int b_valid(const evo_bworld *w, evo_body_id id)
{
	return evo_body_valid(CW(w), id);
}

static void b_set_enabled(evo_bworld *w, evo_body_id id, int enabled)
{
	evo_body_set_enabled(W(w), id, enabled);
}

static void b_wake(evo_bworld *w, evo_body_id id)
{
	evo_body_wake(W(w), id);
}

static int b_add_static(evo_bworld *w, const evo_bshape *s)
{
	switch (s->type) {
	case EVO_SHAPE_CIRCLE:
		return evo_world_add_static_circle(W(w), s->pos[0], s->pos[1],
						   s->radius);
	case EVO_SHAPE_BOX:
		return evo_world_add_static_box(W(w), s->pos[0], s->pos[1],
						s->half[0], s->half[1], s->yaw);
	case EVO_SHAPE_SEGMENT:
		return evo_world_add_static_segment(W(w), s->pos[0], s->pos[1],
						    s->end[0], s->end[1]);
	case EVO_SHAPE_CYLINDER:
		break;
	}
	return -1;
}

static void b_clear_statics(evo_bworld *w)
{
	evo_world_clear_obstacles(W(w));
}

static evo_bpose b_pose(const evo_bworld *w, evo_body_id id)
{
	evo_pose p = evo_body_pose(CW(w), id);
	double c = cos(p.angle), s = sin(p.angle);
	return (evo_bpose){
	    {p.x, p.y, 0}, p.angle, {c, -s, 0, s, c, 0, 0, 0, 1}};
}

static void b_set_pose(evo_bworld *w, evo_body_id id, const double pos[3],
		       double yaw)
{
	evo_body_set_pose(W(w), id, (evo_pose){pos[0], pos[1], yaw});
}

static void b_velocity(const evo_bworld *w, evo_body_id id, double v[3],
		       double omega[3])
{
	evo_body_velocity(CW(w), id, &v[0], &v[1], &omega[2]);
	v[2] = omega[0] = omega[1] = 0;
}

static void b_set_velocity(evo_bworld *w, evo_body_id id, const double v[3],
			   const double omega[3])
{
	evo_body_set_velocity(W(w), id, v[0], v[1], omega[2]);
}

static void b_apply_force_at(evo_bworld *w, evo_body_id id, const double f[3],
			     const double at[3], unsigned frames)
{
	if (frames == 0)
		evo_body_apply_force(W(w), id, f[0], f[1], at[0], at[1]);
}

static void b_add_torque(evo_bworld *w, evo_body_id id, const double t[3])
{
	evo_body_apply_torque(W(w), id, t[2]);
}

static int b_weld(evo_bworld *w, evo_body_id a, evo_body_id b)
{
	return evo_world_weld(W(w), a, b);
}

static void b_unweld(evo_bworld *w, int joint)
{
	evo_world_unweld(W(w), joint);
}

static double b_raycast(evo_bworld *w, const double from[3],
			const double dir[3], double len, uint16_t mask,
			evo_body_id ignore, int ignore_group)
{
	(void)ignore_group;
	double f =
	    evo_world_raycast(CW(w), from[0], from[1], from[0] + dir[0] * len,
			      from[1] + dir[1] * len, mask, ignore);
	return f < 0 ? -1 : f * len;
}

static int b_query_box(const evo_bworld *w, const double lo[3],
		       const double hi[3], uint16_t mask, evo_shape_info *out,
		       int cap)
{
	return evo_world_query(CW(w), lo[0], lo[1], hi[0], hi[1], mask, out,
			       cap);
}

static int b_touching(const evo_bworld *w, evo_body_id id)
{
	return evo_body_touching(CW(w), id);
}

static int b_touching_body(const evo_bworld *w, evo_body_id id,
			   evo_body_id other)
{
	return evo_body_touching_body(CW(w), id, other);
}

static int b_touching_obstacle(const evo_bworld *w, evo_body_id id,
			       int obstacle)
{
	return evo_body_touching_obstacle(CW(w), id, obstacle);
}

static int b_blocked(const evo_bworld *w, evo_body_id id)
{
	return evo_world_body_blocked(CW(w), id);
}

static int b_step(evo_bworld *w, evo_bfault *fault)
{
	(void)fault;
	evo_world_step(W(w));
	return 0;
}

/* NULL: ODE's hinges, and forget_touches (a 2D tick is one step, and
 * Box2D's contacts are those of the last). */
const evo_backend evo_backend_box2d = {
    .name = "Box2D",
    .dims = 2,
    .world_def = b_world_def,
    .create = b_create,
    .destroy = b_destroy,
    .reset = b_reset,
    .add_body = b_add_body,
    .remove_body = b_remove_body,
    .valid = b_valid,
    .set_enabled = b_set_enabled,
    .wake = b_wake,
    .add_static = b_add_static,
    .clear_statics = b_clear_statics,
    .pose = b_pose,
    .set_pose = b_set_pose,
    .velocity = b_velocity,
    .set_velocity = b_set_velocity,
    .apply_force_at = b_apply_force_at,
    .add_torque = b_add_torque,
    .weld = b_weld,
    .unweld = b_unweld,
    .raycast = b_raycast,
    .query_box = b_query_box,
    .touching = b_touching,
    .touching_body = b_touching_body,
    .touching_obstacle = b_touching_obstacle,
    .blocked = b_blocked,
    .step = b_step,
};
