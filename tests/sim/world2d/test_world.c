/* The 2D world over Box2D (sim/world2d/world_box2d.cpp): bodies move under forces
 * as Box2D moves them, obstacles block, rays and queries find what is
 * there, stale ids are refused. */
#include <math.h>

#include "harness.h"
#include "world2d/world.h"

#define NEAR(a, b, tol) (fabs((a) - (b)) <= (tol))

/* BotType8's body: a circle of radius 1.0, density 2, no friction, linear
 * damping 5, angular damping 20, never sleeping. */
static evo_body_id add_bot(evo_world *w, double x, double y)
{
	evo_body_def d = evo_default_body_def();
	d.dynamic = 1;
	d.x = x;
	d.y = y;
	d.radius = 1.0;
	d.density = 2.0;
	d.linear_damping = 5;
	d.angular_damping = 20;
	d.allow_sleep = 0;
	d.category = EVO_CAT_BOT;
	return evo_world_add_body(w, &d);
}

/* Two wheels at (0, -1) and (0, +1) in the body frame push along the
 * heading; `left` is the one at (0, -1), as BotType8 names them. */
static void push(evo_world *w, evo_body_id b, double left, double right)
{
	evo_pose p = evo_body_pose(w, b);
	double c = cos(p.angle), s = sin(p.angle);
	evo_body_apply_force(w, b, c * left, s * left, p.x + s, p.y - c);
	evo_body_apply_force(w, b, c * right, s * right, p.x - s, p.y + c);
}

TEST(equal_wheel_forces_drive_straight)
{
	evo_world *w = evo_world_create(NULL);
	evo_body_id b = add_bot(w, 0, 5);
	for (int t = 0; t < 60; t++) {
		push(w, b, 80, 80);
		evo_world_step(w);
	}
	evo_pose p = evo_body_pose(w, b);
	/* Terminal speed F / (m * damping) = 160 / (2 pi * 5) = 5.09 m/s;
	 * two seconds get most of the way to 10 m. */
	CHECK(p.x > 8 && p.x < 10.2);
	CHECK(NEAR(p.y, 5, 1e-4));
	CHECK(NEAR(p.angle, 0, 1e-4));
	evo_world_destroy(w);
}

TEST(one_wheel_turns_the_body)
{
	evo_world *w = evo_world_create(NULL);
	evo_body_id b = add_bot(w, 0, 0);
	for (int t = 0; t < 30; t++) {
		/* Only the wheel at (0, +1) pushes: facing +x that is the
		 * body's left side, so it turns clockwise. */
		push(w, b, 0, 80);
		evo_world_step(w);
	}
	CHECK(evo_body_pose(w, b).angle < -0.1);
	evo_world_destroy(w);
}

TEST(an_obstacle_blocks_and_is_touched)
{
	evo_world *w = evo_world_create(NULL);
	evo_world_add_static_circle(w, 6, 0, 2);
	evo_body_id b = add_bot(w, 0, 0);
	CHECK_EQ_INT(evo_body_touching(w, b), 0);
	for (int t = 0; t < 90; t++) {
		push(w, b, 80, 80);
		evo_world_step(w);
	}
	/* The bot's edge stops at the obstacle's: x <= 6 - 2 - 1. */
	CHECK(evo_body_pose(w, b).x < 3.05);
	CHECK_EQ_INT(evo_body_touching(w, b), 1);
	evo_world_destroy(w);
}

TEST(raycast_finds_the_nearest_shape)
{
	evo_world *w = evo_world_create(NULL);
	evo_world_add_static_circle(w, 5, 0, 1);
	evo_world_add_static_box(w, 9, 0, 1, 1, 0);
	evo_body_id b = add_bot(w, 0, 0);
	/* From the bot's rim (1, 0) over range 12: the circle's edge at 4. */
	double f = evo_world_raycast(w, 1, 0, 13, 0, EVO_CAT_ALL, b);
	CHECK(NEAR(f * 12, 3.0, 1e-3));
	/* Ignoring the bot, from its centre: it is not hit. */
	f = evo_world_raycast(w, 0, 0, 12, 0, EVO_CAT_ALL, b);
	CHECK(NEAR(f * 12, 4.0, 1e-3));
	/* Nothing along y = 10. */
	CHECK(evo_world_raycast(w, 0, 10, 12, 10, EVO_CAT_ALL, b) < 0);
	/* Obstacles masked out: nothing hit but the bot (ignored). */
	CHECK(evo_world_raycast(w, 1, 0, 13, 0, EVO_CAT_OBJECT, b) < 0);
	evo_world_destroy(w);
}

TEST(query_returns_the_shapes_near_a_box)
{
	evo_world *w = evo_world_create(NULL);
	evo_world_add_static_circle(w, 5, 0, 1);
	evo_world_add_static_box(w, 50, 50, 2, 1, 0);
	evo_world_add_static_circle(w, -30, 0, 1);
	evo_shape_info s[8];
	int n = evo_world_query(w, 0, -6, 12, 6, EVO_CAT_ALL, s, 8);
	CHECK_EQ_INT(n, 1);
	CHECK_EQ_INT(s[0].type, EVO_SHAPE_CIRCLE);
	CHECK(NEAR(s[0].x, 5, 1e-6) && NEAR(s[0].radius, 1, 1e-6));
	CHECK_EQ_INT(s[0].body.index, -1);
	n = evo_world_query(w, 45, 45, 55, 55, EVO_CAT_ALL, s, 8);
	CHECK_EQ_INT(n, 1);
	CHECK_EQ_INT(s[0].type, EVO_SHAPE_BOX);
	CHECK(NEAR(s[0].vx[0], 48, 1e-5) && NEAR(s[0].vy[0], 49, 1e-5));
	evo_world_destroy(w);
}

TEST(stale_ids_are_refused)
{
	evo_world *w = evo_world_create(NULL);
	evo_body_id a = add_bot(w, 0, 0);
	CHECK(evo_body_valid(w, a));
	CHECK_EQ_INT(evo_world_remove_body(w, a), 0);
	CHECK(!evo_body_valid(w, a));
	CHECK_EQ_INT(evo_world_remove_body(w, a), -1);
	evo_body_id b = add_bot(w, 3, 0); /* reuses the slot */
	CHECK_EQ_INT(b.index, a.index);
	CHECK(!evo_body_valid(w, a));
	CHECK(evo_body_valid(w, b));
	evo_body_def bad = evo_default_body_def();
	bad.radius = 0;
	CHECK_EQ_INT(evo_world_add_body(w, &bad).index, -1);
	CHECK_EQ_INT(evo_world_add_static_circle(w, 0, 0, -1), -1);
	evo_world_destroy(w);
}

/* Same inputs, same world: bit-identical poses. */
TEST(stepping_is_deterministic)
{
	double x[2], y[2], a[2];
	for (int run = 0; run < 2; run++) {
		evo_world *w = evo_world_create(NULL);
		for (int i = 0; i < 20; i++)
			evo_world_add_static_circle(w, 4 + i * 3, (i % 3) - 1,
						    0.8);
		evo_body_id b = add_bot(w, 0, 0);
		for (int t = 0; t < 300; t++) {
			push(w, b, 80 - (t % 7) * 10, 70);
			evo_world_step(w);
		}
		evo_pose p = evo_body_pose(w, b);
		x[run] = p.x;
		y[run] = p.y;
		a[run] = p.angle;
		evo_world_destroy(w);
	}
	CHECK(x[0] == x[1] && y[0] == y[1] && a[0] == a[1]);
}

/* Three bots pushed into one another and a pillar for 300 steps from
 * the same poses; their poses at the end, into out. */
static void crash(evo_world *w, const evo_body_id *b, double *out)
{
	evo_world_add_static_circle(w, 2, 1, 1);
	for (int i = 0; i < 3; i++) {
		evo_pose p = {3.0 * i, 0.5 * i, 0.3 * i};
		evo_body_set_pose(w, b[i], p);
		evo_body_set_velocity(w, b[i], 0, 0, 0);
	}
	for (int t = 0; t < 300; t++) {
		for (int i = 0; i < 3; i++)
			push(w, b[i], 40 + 10 * i, 60 - 10 * i);
		evo_world_step(w);
	}
	for (int i = 0; i < 3; i++) {
		evo_pose p = evo_body_pose(w, b[i]);
		out[3 * i] = p.x;
		out[3 * i + 1] = p.y;
		out[3 * i + 2] = p.angle;
	}
}

/* A world made again (evo_world_reset) is the same whatever it went
 * through: the same bodies and ids, no obstacles, and stepping it gives
 * the poses a fresh world of those bodies gives. */
TEST(a_reset_world_does_not_remember_its_past)
{
	evo_world *fresh = evo_world_create(NULL),
		  *old = evo_world_create(NULL);
	evo_body_id f[3], o[3];
	for (int i = 0; i < 3; i++)
		f[i] = add_bot(fresh, 3.0 * i, 0);
	/* old: the same three, but the first removed and added again (its
	 * slot reused), an obstacle, and a past full of contacts */
	for (int i = 0; i < 3; i++)
		o[i] = add_bot(old, 3.0 * i, 0);
	evo_world_remove_body(old, o[0]);
	o[0] = add_bot(old, 0, 0);
	CHECK_EQ_INT(o[0].index, f[0].index);
	double past[9];
	crash(old, o, past);
	evo_body_set_enabled(old, o[2], 0);
	evo_world_reset(fresh);
	evo_world_reset(old);
	/* ids still valid; the disabled body stays disabled, no obstacle */
	for (int i = 0; i < 3; i++)
		CHECK(evo_body_valid(old, o[i]));
	CHECK_EQ_INT(evo_world_raycast(old, 2, -5, 2, 5, EVO_CAT_OBSTACLE,
				       EVO_BODY_NONE) < 0,
		     1);
	evo_body_set_enabled(old, o[2], 1);
	double a[9], b[9];
	crash(fresh, f, a);
	crash(old, o, b);
	for (int i = 0; i < 9; i++)
		CHECK(a[i] == b[i]);
	evo_world_destroy(fresh);
	evo_world_destroy(old);
}

int main(void)
{
	RUN(equal_wheel_forces_drive_straight);
	RUN(one_wheel_turns_the_body);
	RUN(an_obstacle_blocks_and_is_touched);
	RUN(raycast_finds_the_nearest_shape);
	RUN(query_returns_the_shapes_near_a_box);
	RUN(stale_ids_are_refused);
	RUN(stepping_is_deterministic);
	RUN(a_reset_world_does_not_remember_its_past);
	return test_summary();
}
