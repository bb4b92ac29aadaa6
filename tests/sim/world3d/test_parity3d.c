/* What 3D now has as 2D had it, each against values worked out by hand:
 * NextOnCollisionWithTarget ends the episode at the tick the bot first
 * touches its target (a box or an object), and not for a box it never
 * touches; a target a bot cannot touch is refused; the presence sensor
 * reads 0.8 for a target that is on and 0.2 for one set off or none; the
 * movement sensor reads the spread of the last 30 places over its scale;
 * a radar reads TRUE for a target whose azimuth lies in its slice.
 *
 * The worked case: no gravity, a bot (half length 0.2) floating at
 * x = 0 with its front at 0.2, sent along +x at 1.5 m/s; a tick is two
 * steps of 1/60 s, 0.025 m each. A face at x = 0.91 is first overlapped
 * before step s when 0.2 + 0.025 (s - 1) > 0.91, s = 30: the second
 * step of tick 15. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "world3d/scene3d.h"

#define NEAR(a, b, eps) (fabs((a) - (b)) <= (eps))

/* A floating bot at the origin (z 0.5, no gravity), with a presence
 * sensor "p" and a movement sensor "m". */
static evo_scene3d *floating_bot(void)
{
	evo_scene3d_def d = evo_default_scene3d_def();
	d.world.gravity = 0;
	evo_scene3d *sc = evo_scene3d_create(&d);
	evo_bot_def b = evo_default_bot_def3d();
	b.name = "r";
	b.pos[2] = 0.5;
	evo_sensor_def p = evo_default_sensor3d_def(EVO_SENSE_PRESENCE);
	p.name = "p";
	evo_sensor_def m = evo_default_sensor3d_def(EVO_SENSE_MOVEMENT);
	m.name = "m";
	CHECK(evo_scene3d_add_bot(sc, &b) == 0 &&
	      evo_scene3d_add_sensor(sc, 0, &p) == 0 &&
	      evo_scene3d_add_sensor(sc, 0, &m) == 1);
	return sc;
}

/* An element of kind at (x, y, 0.5), of half side or radius 0.1: a box's
 * or a sphere's near side at x - 0.1. */
static int add_piece(evo_scene3d *sc, evo_piece_kind kind, const char *name,
		     double x, double y)
{
	evo_element_def e = evo_default_element_def(kind, EVO_DIM_3D);
	e.name = name;
	e.pos[0] = x;
	e.pos[1] = y;
	e.pos[2] = 0.5;
	e.half[0] = e.half[1] = e.half[2] = 0.1;
	e.radius = 0.1;
	return evo_scene3d_add_element(sc, &e);
}

static int add_box(evo_scene3d *sc, const char *name, double x, double y)
{
	return add_piece(sc, EVO_PIECE_BOX, name, x, y);
}

/* The bot sent along +x at vx m/s. */
static void send(evo_scene3d *sc, double vx)
{
	const double v[3] = {vx, 0, 0}, w[3] = {0, 0, 0};
	sc->be->set_velocity(sc->bw, sc->bot[0].body, v, w);
}

/* Reset, switch element `off` off (-1: none), send the bot along +x at
 * 1.5 m/s, and step until the episode ends or 40 ticks pass: the tick it
 * ended at, or 0. */
static int ticks_to_end(evo_scene3d *sc, int off)
{
	CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 1), 0);
	if (off >= 0)
		evo_scene3d_set_active(sc, off, 0);
	send(sc, 1.5);
	for (int t = 1; t <= 40; t++) {
		int r = evo_scene3d_step(sc);
		CHECK(r >= 0);
		if (r)
			return t;
	}
	return 0;
}

static int control_on(evo_scene3d *sc, int target)
{
	evo_control_def c =
	    evo_default_control_def(EVO_CF_NEXT_ON_COLLISION_WITH_TARGET);
	c.target = target;
	return evo_scene3d_add_control(sc, &c);
}

TEST(collision_with_a_target_box_ends_the_episode_at_first_touch)
{
	evo_scene3d *sc = floating_bot();
	int box = add_box(sc, "wall", 1.01, 0);
	CHECK_EQ_INT(control_on(sc, box), 0);
	CHECK_EQ_INT(ticks_to_end(sc, -1), 15);
	/* its front then: 0.2 + 30 steps of 0.025, into the face at 0.91
	 * by under a step and the push back */
	CHECK(NEAR(sc->bot[0].pos[0] + 0.2, 0.95, 0.03));
	evo_scene3d_destroy(sc);
}

TEST(a_box_never_touched_does_not_end_the_episode)
{
	evo_scene3d *sc = floating_bot();
	add_box(sc, "wall", 1.01, 0);
	int aside = add_box(sc, "aside", 1.01, 3);
	CHECK_EQ_INT(control_on(sc, aside), 0);
	CHECK_EQ_INT(ticks_to_end(sc, -1), 0);
	/* the bot did touch the other box */
	CHECK(sc->bot[0].collisions > 0);
	evo_scene3d_destroy(sc);
}

TEST(collision_with_a_target_object_ends_the_episode)
{
	evo_scene3d *sc = floating_bot();
	/* a sphere: its near point at 0.91 */
	int ball = add_piece(sc, EVO_PIECE_OBJECT, "ball", 1.01, 0);
	CHECK_EQ_INT(control_on(sc, ball), 0);
	CHECK_EQ_INT(ticks_to_end(sc, -1), 15);
	/* set off, the object leaves the world: nothing to touch */
	CHECK_EQ_INT(ticks_to_end(sc, ball), 0);
	evo_scene3d_destroy(sc);
}

TEST(a_target_that_cannot_be_touched_is_refused)
{
	evo_scene3d *sc = floating_bot();
	int zone = add_piece(sc, EVO_PIECE_ZONE, "home", 0, 0);
	CHECK_EQ_INT(control_on(sc, zone), -1);
	CHECK_CONTAINS(sc->err.msg,
		       "control NextOnCollisionWithTarget needs an element a "
		       "bot can touch: a cylinder, box or object (or a 3D "
		       "sphere)");
	CHECK_EQ_INT(control_on(sc, EVO_TARGET_NONE), -1);
	CHECK_CONTAINS(sc->err.msg, "needs an element a bot can touch");
	evo_scene3d_destroy(sc);
}

TEST(presence_reads_whether_the_target_is_on)
{
	evo_scene3d *sc = floating_bot();
	int box = add_box(sc, "wall", 3, 0);
	CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 1), 0);
	/* no target yet */
	CHECK(evo_sensor3d_sample(sc, 0, 0) == EVO3D_FALSE);
	sc->bot[0].sensor[0].def.target = box;
	CHECK(evo_sensor3d_sample(sc, 0, 0) == EVO3D_TRUE);
	evo_scene3d_set_active(sc, box, 0);
	CHECK(evo_sensor3d_sample(sc, 0, 0) == EVO3D_FALSE);
	evo_scene3d_destroy(sc);
}

/* At rest the spread is 0. Moving at 1.2 m/s, the last 30 places are
 * 0.04 m apart: their spread is 0.04 sqrt((30^2 - 1) / 12) = 0.346218,
 * over the default scale 0.35: 0.989193. */
TEST(movement_reads_the_spread_of_the_last_second)
{
	evo_scene3d *sc = floating_bot();
	CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 1), 0);
	for (int t = 0; t < 35; t++)
		CHECK_EQ_INT(evo_scene3d_step(sc), 0);
	CHECK(NEAR(evo_sensor3d_sample(sc, 0, 1), 0, 1e-9));
	send(sc, 1.2);
	for (int t = 0; t < 35; t++)
		CHECK_EQ_INT(evo_scene3d_step(sc), 0);
	double want = 0.04 * sqrt((30.0 * 30.0 - 1) / 12) / 0.35;
	CHECK(NEAR(want, 0.989193, 1e-6));
	CHECK(NEAR(evo_sensor3d_sample(sc, 0, 1), want, 1e-9));
	/* a reset forgets the places */
	CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 1), 0);
	CHECK(NEAR(evo_sensor3d_sample(sc, 0, 1), 0, 1e-12));
	evo_scene3d_destroy(sc);
}

/* A radar of slice [yaw - 45, yaw + 45) degrees, + to the bot's left: a
 * target at (1, 1) is at 45 degrees, the slice's edge: in the slice
 * about 90 (its lower end counts), not in the one about 0 (its upper end
 * does not); at (-1, 0), 180 degrees, in the slice about 180 only. */
TEST(radar_reads_whether_the_target_is_in_its_slice)
{
	evo_scene3d *sc = floating_bot();
	int goal = add_piece(sc, EVO_PIECE_TARGET, "goal", 1, 1);
	static const double yaw[3] = {0, 90, 180};
	int k[3];
	for (int i = 0; i < 3; i++) {
		evo_sensor_def r = evo_default_sensor3d_def(EVO_SENSE_RADAR);
		CHECK(NEAR(r.arc, M_PI / 4, 1e-15));
		r.name = i == 0 ? "ahead" : i == 1 ? "left" : "behind";
		r.yaw = yaw[i] * M_PI / 180;
		r.target = goal;
		k[i] = evo_scene3d_add_sensor(sc, 0, &r);
		CHECK(k[i] >= 0);
	}
	CHECK_EQ_INT(evo_scene3d_reset(sc, 1, 1), 0);
	CHECK(evo_sensor3d_sample(sc, 0, k[0]) == EVO3D_FALSE);
	CHECK(evo_sensor3d_sample(sc, 0, k[1]) == EVO3D_TRUE);
	CHECK(evo_sensor3d_sample(sc, 0, k[2]) == EVO3D_FALSE);
	const double behind[3] = {-1, 0, 0.5};
	evo_scene3d_place_element(sc, goal, behind);
	CHECK(evo_sensor3d_sample(sc, 0, k[0]) == EVO3D_FALSE);
	CHECK(evo_sensor3d_sample(sc, 0, k[1]) == EVO3D_FALSE);
	CHECK(evo_sensor3d_sample(sc, 0, k[2]) == EVO3D_TRUE);
	/* set off: no target, FALSE */
	evo_scene3d_set_active(sc, goal, 0);
	CHECK(evo_sensor3d_sample(sc, 0, k[2]) == EVO3D_FALSE);
	evo_scene3d_destroy(sc);
}

int main(void)
{
	RUN(collision_with_a_target_box_ends_the_episode_at_first_touch);
	RUN(a_box_never_touched_does_not_end_the_episode);
	RUN(collision_with_a_target_object_ends_the_episode);
	RUN(a_target_that_cannot_be_touched_is_refused);
	RUN(presence_reads_whether_the_target_is_on);
	RUN(movement_reads_the_spread_of_the_last_second);
	RUN(radar_reads_whether_the_target_is_in_its_slice);
	return test_summary();
}
