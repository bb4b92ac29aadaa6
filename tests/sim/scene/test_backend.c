/* The physics backend interface (sim/scene/backend.h), through each of its
 * two fillings: a ray stops at the nearest face of a static box, a body
 * moves as its speed and gravity say (by hand: no damping in 2D; ODE's
 * semi-implicit Euler in 3D), a set pose reads back with its turn, an
 * exploding body is reported by the step, and what one engine has not is
 * NULL in its struct. Both scenes are made on their engine's filling. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "world2d/scene.h"
#include "world2d/world.h"
#include "world3d/scene3d.h"
#include "world3d/world3d.h"

#define NEAR(a, b, eps) (fabs((a) - (b)) <= (eps))

static const double pi = 3.14159265358979323846;

static evo_bworld *make(const evo_backend *be)
{
	evo_bworld_def d = be->world_def();
	return be->create(&d);
}

/* A static cube of half side 1 centred at (5, 0, z). */
static int add_cube(const evo_backend *be, evo_bworld *w, double z)
{
	evo_bshape s;
	memset(&s, 0, sizeof s);
	s.type = EVO_SHAPE_BOX;
	s.pos[0] = 5;
	s.pos[2] = z;
	s.half[0] = s.half[1] = s.half[2] = 1;
	s.category = be->dims == 3 ? EVO_CAT3D_OBSTACLE : EVO_CAT_OBSTACLE;
	return be->add_static(w, &s);
}

/* A dynamic ball of radius 0.5 at (0, 0, z): 1 kg in 3D, density 1 in
 * 2D. */
static evo_body_id add_ball(const evo_backend *be, evo_bworld *w, double z)
{
	evo_bbody_def d;
	memset(&d, 0, sizeof d);
	d.dynamic = 1;
	d.pos[2] = z;
	d.mass = 1;
	d.density = 1;
	d.n_shapes = 1;
	d.shape[0].type = EVO_SHAPE_CIRCLE;
	d.shape[0].radius = 0.5;
	d.category = be->dims == 3 ? EVO_CAT3D_OBJECT : EVO_CAT_OBJECT;
	d.mask = EVO_CAT_ALL;
	d.group = -1;
	return be->add_body(w, &d);
}

/* From (0, 0, z) along x, the cube's near face is 5 - 1 = 4 away; a ray
 * of 3 reaches nothing. */
static void check_ray(const evo_backend *be)
{
	evo_bworld *w = make(be);
	CHECK(w != NULL);
	double z = be->dims == 3 ? 1 : 0; /* on ODE's ground */
	CHECK(add_cube(be, w, z) >= 0);
	double from[3] = {0, 0, z}, dir[3] = {1, 0, 0};
	double h =
	    be->raycast(w, from, dir, 10, EVO_CAT_ALL, EVO_BODY_NONE, -1);
	CHECK(NEAR(h, 4, 1e-5));
	CHECK(be->raycast(w, from, dir, 3, EVO_CAT_ALL, EVO_BODY_NONE, -1) < 0);
	be->destroy(w);
}

TEST(a_ray_stops_at_the_nearest_face_in_both)
{
	check_ray(&evo_backend_box2d);
	check_ray(&evo_backend_ode);
}

/* Box2D has no gravity (evo's 2D world is seen from above) and the ball
 * no damping: at (1, 0.5) m/s for 30 steps of 1/30 s it moves (1, 0.5). */
TEST(a_2d_body_moves_as_its_speed_says)
{
	const evo_backend *be = &evo_backend_box2d;
	evo_bworld *w = make(be);
	evo_body_id b = add_ball(be, w, 0);
	CHECK(be->valid(w, b));
	double v[3] = {1, 0.5, 0}, still[3] = {0, 0, 0};
	be->set_velocity(w, b, v, still);
	for (int i = 0; i < 30; i++)
		CHECK_EQ_INT(be->step(w, NULL), 0);
	evo_bpose p = be->pose(w, b);
	CHECK(NEAR(p.pos[0], 1, 1e-5));
	CHECK(NEAR(p.pos[1], 0.5, 1e-5));
	CHECK(p.pos[2] == 0);
	double got[3], spin[3];
	be->velocity(w, b, got, spin);
	CHECK(NEAR(got[0], 1, 1e-6) && NEAR(got[1], 0.5, 1e-6));
	CHECK(got[2] == 0 && spin[2] == 0);
	be->destroy(w);
}

/* ODE steps by semi-implicit Euler: v_n = -g n h, z_n = z_0 - g h^2
 * n (n + 1) / 2. At h = 1/60 s and g = 9.81, after 30 steps from 5 m:
 * z = 5 - 9.81 * 465 / 3600 = 3.732875 m, v = -4.905 m/s. */
TEST(a_3d_body_falls_as_odes_euler_step_says)
{
	const evo_backend *be = &evo_backend_ode;
	evo_bworld *w = make(be);
	evo_body_id b = add_ball(be, w, 5);
	CHECK(be->valid(w, b));
	for (int i = 0; i < 30; i++)
		CHECK_EQ_INT(be->step(w, NULL), 0);
	evo_bpose p = be->pose(w, b);
	CHECK(NEAR(p.pos[2], 5 - 9.81 * 465 / 3600, 1e-9));
	CHECK(NEAR(p.pos[0], 0, 1e-12) && NEAR(p.pos[1], 0, 1e-12));
	double v[3], spin[3];
	be->velocity(w, b, v, spin);
	CHECK(NEAR(v[2], -4.905, 1e-9));
	be->destroy(w);
}

/* A pose set a quarter turn about z reads back so: R turns the body's x
 * onto the world's y (R[0] = cos 90 = 0, R[3] = sin 90 = 1). */
static void check_turn(const evo_backend *be)
{
	evo_bworld *w = make(be);
	evo_body_id b = add_ball(be, w, be->dims == 3 ? 2 : 0);
	double at[3] = {1, 2, be->dims == 3 ? 2 : 0};
	be->set_pose(w, b, at, pi / 2);
	evo_bpose p = be->pose(w, b);
	CHECK(NEAR(p.pos[0], 1, 1e-6) && NEAR(p.pos[1], 2, 1e-6));
	CHECK(NEAR(p.yaw, pi / 2, 1e-6));
	CHECK(NEAR(p.R[0], 0, 1e-6) && NEAR(p.R[3], 1, 1e-6));
	CHECK(NEAR(p.R[1], -1, 1e-6) && NEAR(p.R[8], 1, 1e-6));
	be->destroy(w);
}

TEST(a_set_pose_reads_back_with_its_turn_in_both)
{
	check_turn(&evo_backend_box2d);
	check_turn(&evo_backend_ode);
}

/* ODE's default max_speed is 100 m/s: a body sent at 1000 m/s has
 * exploded, and the step says which body and how fast. */
TEST(the_3d_step_reports_the_body_that_exploded)
{
	const evo_backend *be = &evo_backend_ode;
	evo_bworld *w = make(be);
	add_ball(be, w, 5);
	evo_body_id b = add_ball(be, w, 8);
	double v[3] = {1000, 0, 0}, still[3] = {0, 0, 0};
	be->set_velocity(w, b, v, still);
	evo_bfault f;
	memset(&f, 0, sizeof f);
	CHECK_EQ_INT(be->step(w, &f), -1);
	CHECK_EQ_INT(f.body.index, b.index);
	CHECK_EQ_INT(f.kind, EVO_BFAULT_SPEED);
	CHECK(NEAR(f.value, 1000, 1e-9));
	be->destroy(w);
}

/* What only one engine does is NULL in the other's struct. */
TEST(what_one_engine_has_not_is_null)
{
	const evo_backend *b2 = &evo_backend_box2d, *ode = &evo_backend_ode;
	CHECK_EQ_INT(b2->dims, 2);
	CHECK_EQ_INT(ode->dims, 3);
	CHECK(b2->weld && b2->unweld && b2->query_box && b2->blocked);
	CHECK(!b2->hinge && !b2->hinge_torque && !b2->hinge_velocity);
	CHECK(ode->hinge && ode->hinge_torque && ode->hinge_velocity);
	CHECK(!ode->weld && !ode->unweld && !ode->query_box && !ode->blocked);
}

/* Each scene is made on its engine's filling. */
TEST(each_scene_runs_on_its_backend)
{
	evo_scene *sc = evo_scene_create();
	CHECK(sc && sc->be == &evo_backend_box2d && sc->bw);
	evo_scene_destroy(sc);
	evo_scene3d_def d = evo_default_scene3d_def();
	evo_scene3d *sc3 = evo_scene3d_create(&d);
	CHECK(sc3 && sc3->be == &evo_backend_ode && sc3->bw);
	evo_scene3d_destroy(sc3);
}

int main(void)
{
	RUN(a_ray_stops_at_the_nearest_face_in_both);
	RUN(a_2d_body_moves_as_its_speed_says);
	RUN(a_3d_body_falls_as_odes_euler_step_says);
	RUN(a_set_pose_reads_back_with_its_turn_in_both);
	RUN(the_3d_step_reports_the_body_that_exploded);
	RUN(what_one_engine_has_not_is_null);
	RUN(each_scene_runs_on_its_backend);
	return test_summary();
}
