/* The actuators (sim/world2d/actuators.c): wheels push the bot the way the frame
 * says (y down on screen, angles clockwise), and the claw grabs on a
 * rising edge what lies in reach, carries it, and lets go on a falling
 * edge. */
#include <math.h>

#include "harness.h"
#include "support/scenes.h"
#include "world2d/actuators.h"
#include "world2d/scene.h"

#define NEAR(a, b, tol) (fabs((a) - (b)) <= (tol))
#define DEG		(M_PI / 180.0)

enum { MOT_L = 0, MOT_R = 1, CLAW = 2 };

/* BotType8: MotL at (0, -1) (its left), MotR at (0, +1), both pushing
 * along the heading with 80 N; a claw on the rim ahead. Objects are added
 * by the caller, which then resets. */
static evo_scene *bot_with_wheels_and_claw(double x, double y, double angle)
{
	evo_scene *sc = scene_with_bot(x, y, angle);
	evo_actuator_def w = evo_default_actuator_def(EVO_ACT_WHEEL);
	w.name = "MotL";
	w.y = -1;
	evo_scene_add_actuator(sc, 0, &w);
	w.name = "MotR";
	w.y = 1;
	evo_scene_add_actuator(sc, 0, &w);
	evo_actuator_def c = evo_default_actuator_def(EVO_ACT_CLAW);
	c.name = "Claw";
	evo_scene_add_actuator(sc, 0, &c);
	return sc;
}

static void drive(evo_scene *sc, double left, double right, int ticks)
{
	for (int t = 0; t < ticks; t++) {
		sc->bot[0].actuator[MOT_L].command = left;
		sc->bot[0].actuator[MOT_R].command = right;
		evo_scene_step(sc);
	}
}

static evo_pose pose(const evo_scene *sc)
{
	return evo_body_pose(sc->world, sc->bot[0].body);
}

static evo_pose object_pose(const evo_scene *sc, int obj)
{
	return evo_body_pose(sc->world, sc->element[obj].body);
}

/* ---- wheels ----------------------------------------------------------- */

TEST(full_forward_drives_straight_ahead)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 5, 0);
	evo_scene_reset(sc, 1, 1);
	drive(sc, 1, 1, 60);
	evo_pose p = pose(sc);
	/* Terminal speed 160 / (2 pi * 5) = 5.09 m/s: most of 10 m in 2 s. */
	CHECK(p.x > 8 && p.x < 10.2);
	CHECK(NEAR(p.y, 5, 1e-4));
	CHECK(NEAR(p.angle, 0, 1e-4));
	evo_scene_destroy(sc);
}

TEST(full_reverse_drives_straight_back)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	drive(sc, 0, 0, 60);
	CHECK(pose(sc).x < -8);
	CHECK(NEAR(pose(sc).y, 0, 1e-4));
	evo_scene_destroy(sc);
}

TEST(forward_follows_the_heading)
{
	/* Facing 90° (clockwise on screen: downward, +y). */
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 90 * DEG);
	evo_scene_reset(sc, 1, 1);
	drive(sc, 1, 1, 30);
	evo_pose p = pose(sc);
	CHECK(p.y > 3);
	CHECK(NEAR(p.x, 0, 1e-3));
	CHECK(NEAR(p.angle, 90 * DEG, 1e-3));
	evo_scene_destroy(sc);
}

TEST(neutral_commands_leave_the_bot_still)
{
	evo_scene *sc = bot_with_wheels_and_claw(2, 3, 0.4);
	evo_scene_reset(sc, 1, 1);
	drive(sc, 0.5, 0.5, 60);
	evo_pose p = pose(sc);
	CHECK(p.x == 2 && p.y == 3);
	CHECK(NEAR(p.angle, 0.4, 1e-6));
	evo_scene_destroy(sc);
}

TEST(turn_left_decreases_the_heading)
{
	/* MotR pushing forward at (0, +1) and MotL backward at (0, -1): a
	 * negative torque in Box2D's frame, which y down shows as a turn
	 * counter-clockwise on screen, to the bot's left. */
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	drive(sc, 0, 1, 15);
	evo_pose p = pose(sc);
	CHECK(p.angle < -0.2);
	/* Turning in place: the centre stays. */
	CHECK(NEAR(p.x, 0, 1e-3) && NEAR(p.y, 0, 1e-3));
	evo_scene_destroy(sc);
}

TEST(turn_right_increases_the_heading)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	drive(sc, 1, 0, 15);
	CHECK(pose(sc).angle > 0.2);
	evo_scene_destroy(sc);
}

TEST(one_wheel_curves_toward_the_other_side)
{
	/* Only MotL pushes: the bot moves forward and turns right. */
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	drive(sc, 1, 0.5, 20);
	evo_pose p = pose(sc);
	CHECK(p.angle > 0.1);
	CHECK(p.x > 0.5);
	CHECK(p.y > 0); /* to the right: +y */
	evo_scene_destroy(sc);
}

TEST(commands_are_clamped)
{
	/* 3 pushes as 1 does; a command that is not a number, not at all. */
	double x[2];
	for (int k = 0; k < 2; k++) {
		evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
		evo_scene_reset(sc, 1, 1);
		drive(sc, k ? 3 : 1, k ? 3 : 1, 20);
		x[k] = pose(sc).x;
		evo_scene_destroy(sc);
	}
	CHECK(x[0] == x[1]);
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	drive(sc, NAN, NAN, 20);
	CHECK(pose(sc).x == 0);
	evo_scene_destroy(sc);
}

TEST(a_wheel_pushes_along_its_own_angle)
{
	/* A thruster at the centre pointing 90°: the bot slides to its
	 * right (+y) without turning. */
	evo_scene *sc = evo_scene_create();
	evo_bot_def b = evo_default_bot_def();
	evo_scene_add_bot(sc, &b);
	evo_actuator_def w = evo_default_actuator_def(EVO_ACT_WHEEL);
	w.angle = 90 * DEG;
	int a = evo_scene_add_actuator(sc, 0, &w);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 20; t++) {
		sc->bot[0].actuator[a].command = 1;
		evo_scene_step(sc);
	}
	evo_pose p = pose(sc);
	CHECK(p.y > 1);
	CHECK(NEAR(p.x, 0, 1e-4));
	CHECK(NEAR(p.angle, 0, 1e-4));
	evo_scene_destroy(sc);
}

/* ---- the claw ----------------------------------------------------------- */

static void claw(evo_scene *sc, double command)
{
	sc->bot[0].actuator[CLAW].command = command;
	evo_scene_step(sc);
}

TEST(claw_grabs_on_a_rising_edge_and_carries)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	int obj = scene_add_element(sc, EVO_PIECE_OBJECT, 2.2, 0, 0.5); /* surface 0.7 from the claw */
	evo_scene_reset(sc, 1, 1);
	const evo_actuator *a = &sc->bot[0].actuator[CLAW];
	claw(sc, 0.5);
	CHECK_EQ_INT(a->held, -1);
	claw(sc, 0.9);
	CHECK_EQ_INT(a->held, obj);
	CHECK(a->joint >= 0);
	CHECK_EQ_INT(sc->element[obj].held_by, 0);
	CHECK(a->previous == 0.9);
	/* Carried: it keeps its place ahead of the bot while the bot
	 * drives and turns. */
	sc->bot[0].actuator[CLAW].command = 1;
	drive(sc, 1, 1, 45);
	drive(sc, 1, 0.5, 20);
	evo_pose p = pose(sc), o = object_pose(sc, obj);
	CHECK(p.x > 4);
	double ahead = (o.x - p.x) * cos(p.angle) + (o.y - p.y) * sin(p.angle);
	double side = -(o.x - p.x) * sin(p.angle) + (o.y - p.y) * cos(p.angle);
	CHECK(NEAR(ahead, 2.2, 0.05));
	CHECK(NEAR(side, 0, 0.05));
	CHECK_EQ_INT(a->held, obj);
	evo_scene_destroy(sc);
}

TEST(claw_releases_on_a_falling_edge)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	int obj = scene_add_element(sc, EVO_PIECE_OBJECT, 2.2, 0, 0.5);
	evo_scene_reset(sc, 1, 1);
	const evo_actuator *a = &sc->bot[0].actuator[CLAW];
	claw(sc, 1);
	CHECK_EQ_INT(a->held, obj);
	claw(sc, 0.6); /* still above 0.5: no edge */
	CHECK_EQ_INT(a->held, obj);
	claw(sc, 0.1);
	CHECK_EQ_INT(a->held, -1);
	CHECK_EQ_INT(a->joint, -1);
	CHECK_EQ_INT(sc->element[obj].held_by, -1);
	/* Backing away leaves it behind. */
	double ox = object_pose(sc, obj).x;
	drive(sc, 0, 0, 30);
	CHECK(pose(sc).x < -2);
	CHECK(NEAR(object_pose(sc, obj).x, ox, 1e-3));
	evo_scene_destroy(sc);
}

TEST(claw_grabs_on_the_edge_not_the_level)
{
	/* Shut while nothing was in reach: an object arriving later is not
	 * taken until the claw opens and closes again. */
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	int obj = scene_add_element(sc, EVO_PIECE_OBJECT, 10, 0, 0.5);
	evo_scene_reset(sc, 1, 1);
	const evo_actuator *a = &sc->bot[0].actuator[CLAW];
	claw(sc, 1);
	CHECK_EQ_INT(a->held, -1);
	evo_scene_place_element(sc, obj, 2.2, 0);
	claw(sc, 1);
	claw(sc, 1);
	CHECK_EQ_INT(a->held, -1);
	claw(sc, 0);
	claw(sc, 1);
	CHECK_EQ_INT(a->held, obj);
	evo_scene_destroy(sc);
}

TEST(claw_does_not_grab_out_of_reach_or_behind)
{
	/* Claw on the rim (1, 0), reach 1.5, ±45°; objects of radius 0.5. */
	double where[][2] = {
	    {3.1, 0},	/* surface 1.6 away */
	    {-2.2, 0},	/* behind */
	    {1.2, 1.6}, /* beside: 83° off */
	    {20, 20},
	};
	for (unsigned k = 0; k < sizeof where / sizeof where[0]; k++) {
		evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
		int obj = scene_add_element(sc, EVO_PIECE_OBJECT, where[k][0], where[k][1], 0.5);
		evo_scene_reset(sc, 1, 1);
		claw(sc, 1);
		CHECK_EQ_INT(sc->bot[0].actuator[CLAW].held, -1);
		CHECK_EQ_INT(sc->element[obj].held_by, -1);
		evo_scene_destroy(sc);
	}
}

TEST(claw_takes_the_nearest_free_object)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	int far = scene_add_element(sc, EVO_PIECE_OBJECT, 2.8, 0.9, 0.5);
	int near = scene_add_element(sc, EVO_PIECE_OBJECT, 2.3, -0.4, 0.5);
	evo_scene_reset(sc, 1, 1);
	claw(sc, 1);
	CHECK_EQ_INT(sc->bot[0].actuator[CLAW].held, near);
	CHECK_EQ_INT(sc->element[far].held_by, -1);
	evo_scene_destroy(sc);
}

TEST(a_held_object_is_not_taken_by_another_bot)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	int obj = scene_add_element(sc, EVO_PIECE_OBJECT, 2.2, 0, 0.5);
	/* A second bot facing the first, its claw reaching the object. */
	evo_bot_def b = evo_default_bot_def();
	b.name = "other";
	b.x = 4.4;
	b.yaw = M_PI;
	int other = evo_scene_add_bot(sc, &b);
	evo_actuator_def c = evo_default_actuator_def(EVO_ACT_CLAW);
	int oc = evo_scene_add_actuator(sc, other, &c);
	evo_scene_reset(sc, 1, 1);
	sc->bot[0].actuator[CLAW].command = 1;
	sc->bot[other].actuator[oc].command = 1;
	evo_scene_step(sc);
	CHECK_EQ_INT(sc->bot[0].actuator[CLAW].held, obj);
	CHECK_EQ_INT(sc->bot[other].actuator[oc].held, -1);
	CHECK_EQ_INT(sc->element[obj].held_by, 0);
	evo_scene_destroy(sc);
}

TEST(release_opens_every_claw)
{
	evo_scene *sc = bot_with_wheels_and_claw(0, 0, 0);
	int obj = scene_add_element(sc, EVO_PIECE_OBJECT, 2.2, 0, 0.5);
	evo_scene_reset(sc, 1, 1);
	claw(sc, 1);
	CHECK_EQ_INT(sc->element[obj].held_by, 0);
	evo_bot_release(sc, 0);
	CHECK_EQ_INT(sc->bot[0].actuator[CLAW].held, -1);
	CHECK_EQ_INT(sc->bot[0].actuator[CLAW].joint, -1);
	CHECK_EQ_INT(sc->element[obj].held_by, -1);
	/* Released while shut: the next closing takes it again. */
	claw(sc, 1);
	CHECK_EQ_INT(sc->bot[0].actuator[CLAW].held, -1);
	claw(sc, 0);
	claw(sc, 1);
	CHECK_EQ_INT(sc->bot[0].actuator[CLAW].held, obj);
	/* A reset opens it too. */
	evo_scene_reset(sc, 1, 1);
	CHECK_EQ_INT(sc->bot[0].actuator[CLAW].held, -1);
	CHECK_EQ_INT(sc->element[obj].held_by, -1);
	evo_scene_destroy(sc);
}

int main(void)
{
	RUN(full_forward_drives_straight_ahead);
	RUN(full_reverse_drives_straight_back);
	RUN(forward_follows_the_heading);
	RUN(neutral_commands_leave_the_bot_still);
	RUN(turn_left_decreases_the_heading);
	RUN(turn_right_increases_the_heading);
	RUN(one_wheel_curves_toward_the_other_side);
	RUN(commands_are_clamped);
	RUN(a_wheel_pushes_along_its_own_angle);
	RUN(claw_grabs_on_a_rising_edge_and_carries);
	RUN(claw_releases_on_a_falling_edge);
	RUN(claw_grabs_on_the_edge_not_the_level);
	RUN(claw_does_not_grab_out_of_reach_or_behind);
	RUN(claw_takes_the_nearest_free_object);
	RUN(a_held_object_is_not_taken_by_another_bot);
	RUN(release_opens_every_claw);
	return test_summary();
}
