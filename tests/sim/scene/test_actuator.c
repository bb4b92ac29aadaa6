/* The one actuator of both worlds (sim/scene/actuator.h): a propeller's
 * axis is made unit when it is added, and its thrust moves a weightless
 * bot by F / m per second, worked out by hand, a command below 0 as 0
 * (full reverse) and one not a number as 0.5 (none), as in 2D; a kind
 * of the other world and a name used twice are refused with the same
 * words in both; an unnamed actuator is named as its world names it. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "support/scenes.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

TEST(a_propellers_thrust_is_f_over_m_along_its_unit_axis)
{
	evo_scene3d_def sd = evo_default_scene3d_def();
	sd.world.gravity = 0;
	evo_scene3d *sc = evo_scene3d_create(&sd);
	evo_bot_def b = evo_default_bot_def3d();
	b.radius = 0.2; /* a sphere, floating 1 m up, nothing touching */
	b.pos[2] = 1;
	b.mass = 2;
	CHECK(evo_scene3d_add_bot(sc, &b) == 0);
	evo_actuator_def p = evo_default_actuator_def(EVO_ACT_PROPELLER);
	p.name = "P";
	p.axis[0] = 3; /* (3, 4, 0): unit (0.6, 0.8, 0) */
	p.axis[1] = 4;
	p.max_thrust = 10;
	CHECK_EQ_INT(evo_scene3d_add_actuator(sc, 0, &p), 0);
	const evo_actuator *a = &sc->bot[0].actuator[0];
	CHECK(fabs(a->def.axis[0] - 0.6) < 1e-15);
	CHECK(fabs(a->def.axis[1] - 0.8) < 1e-15);
	CHECK(a->def.axis[2] == 0);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	/* command 1: 10 N along (0.6, 0.8, 0) on 2 kg for one tick of two
	 * steps of 1/60 s: v = (6, 8, 0) / 2 / 30 = (0.1, 0.1333..., 0) */
	sc->bot[0].actuator[0].command = 1;
	evo_scene3d_sense(sc);
	CHECK(evo_scene3d_step(sc) == 0);
	CHECK(fabs(sc->bot[0].v[0] - 0.1) < 1e-9);
	CHECK(fabs(sc->bot[0].v[1] - 8.0 / 60) < 1e-9);
	CHECK(fabs(sc->bot[0].v[2]) < 1e-12);
	/* a command below 0 is full reverse, as in 2D (clamped into
	 * [0, 1]); one that is not a number is neutral */
	double commands[] = {-3, NAN}, want[] = {-1, 0};
	for (int k = 0; k < 2; k++) {
		CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
		sc->bot[0].actuator[0].command = commands[k];
		evo_scene3d_sense(sc);
		CHECK(evo_scene3d_step(sc) == 0);
		CHECK(fabs(sc->bot[0].v[0] - want[k] * 0.1) < 1e-9);
		CHECK(fabs(sc->bot[0].v[1] - want[k] * 8.0 / 60) < 1e-9);
	}
	evo_scene3d_destroy(sc);
}

TEST(the_other_worlds_kinds_and_a_name_twice_are_refused_alike)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	evo_actuator_def d = evo_default_actuator_def(EVO_ACT_PROPELLER);
	d.name = "P";
	CHECK(evo_scene_add_actuator(sc, 0, &d) == -1);
	CHECK_CONTAINS(
	    sc->err.msg,
	    "actuator 'P': propeller is no actuator of the 2D world");
	d = evo_default_actuator_def(EVO_ACT_WHEEL);
	CHECK(evo_scene_add_actuator(sc, 0, &d) == 0);
	CHECK_EQ_STR(sc->bot[0].actuator[0].name, ""); /* 2D: unnamed */
	d.name = "w";
	CHECK(evo_scene_add_actuator(sc, 0, &d) == 1);
	CHECK(evo_scene_add_actuator(sc, 0, &d) == -1);
	CHECK_CONTAINS(sc->err.msg, "actuator 'w' is defined twice");
	CHECK_EQ_INT(sc->bot[0].n_actuators, 2);
	evo_scene_destroy(sc);

	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *s3 = evo_scene3d_create(&sd);
	evo_bot_def b = evo_default_bot_def3d();
	b.name = "r";
	CHECK(evo_scene3d_add_bot(s3, &b) == 0);
	d = evo_default_actuator_def(EVO_ACT_CLAW);
	d.name = "C";
	CHECK(evo_scene3d_add_actuator(s3, 0, &d) == -1);
	CHECK_CONTAINS(s3->err.msg,
		       "actuator 'C': claw is no actuator of the 3D world");
	d = evo_default_actuator_def(EVO_ACT_BROADCAST);
	CHECK(evo_scene3d_add_actuator(s3, 0, &d) == 0);
	CHECK_EQ_STR(s3->bot[0].actuator[0].name, "actuator1"); /* 3D */
	d.name = "w";
	CHECK(evo_scene3d_add_actuator(s3, 0, &d) == 1);
	CHECK(evo_scene3d_add_actuator(s3, 0, &d) == -1);
	CHECK_CONTAINS(s3->err.msg, "bot r: actuator 'w' is defined twice");
	/* a propeller with no axis */
	d = evo_default_actuator_def(EVO_ACT_PROPELLER);
	d.axis[0] = 0;
	CHECK(evo_scene3d_add_actuator(s3, 0, &d) == -1);
	CHECK_CONTAINS(s3->err.msg, "its axis must not be 0");
	CHECK_EQ_INT(s3->bot[0].n_actuators, 2);
	evo_scene3d_destroy(s3);
}

int main(void)
{
	RUN(a_propellers_thrust_is_f_over_m_along_its_unit_axis);
	RUN(the_other_worlds_kinds_and_a_name_twice_are_refused_alike);
	return test_summary();
}
