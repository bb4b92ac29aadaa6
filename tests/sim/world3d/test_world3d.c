/* The 3D world (sim/world3d/): ODE's ray casts give the nearest hit, the
 * sensors read what hand-worked placements say, a wheeled robot at rest
 * stays put, wheels and propellers push the way their commands say, and a
 * body that explodes ends the episode with a message and a penalty. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "world3d/scene3d.h"
#include "world3d/world3d.h"

#define NEAR(a, b, eps) (fabs((a) - (b)) <= (eps))

static evo_shape3d box_at(double x, double y, double z, double h)
{
	evo_shape3d s;
	memset(&s, 0, sizeof s);
	s.type = EVO_SHAPE3D_BOX;
	s.pos[0] = x;
	s.pos[1] = y;
	s.pos[2] = z;
	s.half[0] = s.half[1] = s.half[2] = h;
	s.category = EVO_CAT3D_OBSTACLE;
	return s;
}

/* Two boxes on the ray's line, the far one added first: the ray reports
 * the near one's face, 2 - 0.5 = 1.5 from the start. */
TEST(ray_reports_the_nearest_hit)
{
	evo_world3d_def d = evo_default_world3d_def();
	evo_world3d *w = evo_world3d_create(&d);
	CHECK(w != NULL);
	evo_shape3d far = box_at(5, 0, 1, 0.5), nearby = box_at(2, 0, 1, 0.5);
	CHECK(evo_world3d_add_static(w, &far) >= 0);
	CHECK(evo_world3d_add_static(w, &nearby) >= 0);
	double from[3] = {0, 0, 1}, ahead[3] = {1, 0, 0}, left[3] = {0, 1, 0};
	double down[3] = {0, 0, -1};
	CHECK(NEAR(evo_world3d_raycast(w, from, ahead, 10, EVO_CAT3D_ALL, -1),
		   1.5, 1e-9));
	/* too short, another way, a mask that leaves obstacles out */
	CHECK(evo_world3d_raycast(w, from, ahead, 1.4, EVO_CAT3D_ALL, -1) < 0);
	CHECK(evo_world3d_raycast(w, from, left, 10, EVO_CAT3D_OBSTACLE, -1) <
	      0);
	CHECK(evo_world3d_raycast(w, from, ahead, 10, EVO_CAT3D_BOT, -1) < 0);
	/* the ground plane, 1 below */
	CHECK(NEAR(evo_world3d_raycast(w, from, down, 10, EVO_CAT3D_ALL, -1),
		   1.0, 1e-9));
	CHECK(evo_world3d_raycast(w, from, down, 10, EVO_CAT3D_OBSTACLE, -1) <
	      0);
	evo_world3d_destroy(w);
}

/* A floating bot (a sphere of neutral buoyancy, gravity balanced) at
 * (0, 0, 2) facing yaw, with a target and the tutorial's target sensor. */
static evo_scene3d *floating(double yaw, int *target)
{
	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&sd);
	evo_element_def t =
	    evo_default_element_def(EVO_PIECE_TARGET, EVO_DIM_3D);
	t.name = "goal";
	*target = evo_scene3d_add_element(sc, &t);
	evo_bot_def b = evo_default_bot_def3d();
	b.radius = 0.25;
	b.pos[2] = 2;
	b.yaw = yaw;
	b.buoyancy = 1;
	evo_scene3d_add_bot(sc, &b);
	evo_sensor_def az = evo_default_sensor3d_def(EVO_SENSE_BEARING);
	az.name = "TARG_AZIM";
	az.target = *target;
	evo_sensor_def el = evo_default_sensor3d_def(EVO_SENSE_ELEVATION);
	el.name = "TARG_ELEV";
	el.target = *target;
	evo_sensor_def di = evo_default_sensor3d_def(EVO_SENSE_DISTANCE);
	di.name = "DIST";
	di.target = *target;
	di.scale = 10;
	evo_scene3d_add_sensor(sc, 0, &az);
	evo_scene3d_add_sensor(sc, 0, &el);
	evo_scene3d_add_sensor(sc, 0, &di);
	evo_scene3d_reset(sc, 1, 1);
	return sc;
}

static void target_at(evo_scene3d *sc, int t, double x, double y, double z)
{
	double p[3] = {x, y, z};
	evo_scene3d_place_element(sc, t, p);
	evo_scene3d_sense(sc);
}

/* Azimuth 0.5 + atan2(left, ahead) / 2 pi; elevation 0.5 + atan2(up,
 * horizontal) / pi, worked by hand for each placement. */
TEST(target_sensor_azimuth_and_elevation)
{
	int t;
	evo_scene3d *sc = floating(0, &t);
	const evo_sensor *s = sc->bot[0].sensor;
	target_at(sc, t, 3, 3, 2); /* ahead-left, 45 degrees */
	CHECK(NEAR(s[0].value, 0.625, 1e-9));
	CHECK(NEAR(s[1].value, 0.5, 1e-9));
	target_at(sc, t, -1, -1, 2); /* behind-right, -135 degrees */
	CHECK(NEAR(s[0].value, 0.125, 1e-9));
	target_at(sc, t, 4, 0, 5); /* up 3 over 4: atan(3/4) */
	CHECK(NEAR(s[0].value, 0.5, 1e-9));
	CHECK(NEAR(s[1].value, 0.5 + atan2(3, 4) / M_PI, 1e-9));
	CHECK(NEAR(s[1].value, 0.704833, 1e-6));
	CHECK(NEAR(s[2].value, 0.5, 1e-9)); /* 5 m of a scale of 10 */
	target_at(sc, t, 0, 0, -10);	    /* straight below */
	CHECK(NEAR(s[1].value, 0.0, 1e-9));
	evo_scene3d_destroy(sc);
	/* the same target seen by a bot turned 90 degrees left: ahead */
	sc = floating(M_PI / 2, &t);
	s = sc->bot[0].sensor;
	target_at(sc, t, 0, 5, 2);
	CHECK(NEAR(s[0].value, 0.5, 1e-9));
	target_at(sc, t, 5, 0, 2); /* now on its right: -90 degrees */
	CHECK(NEAR(s[0].value, 0.25, 1e-9));
	evo_scene3d_destroy(sc);
}

/* The wheeled robot of lua/bots/Wheeled3D.lua, built in C: a box chassis
 * 0.4 x 0.3 x 0.08 whose centre is the wheels' axle height, two wheels of
 * radius 0.08 at its sides, a caster at its back. */
static evo_scene3d *wheeled(void)
{
	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&sd);
	evo_bot_def b = evo_default_bot_def3d();
	b.half[0] = 0.2;
	b.half[1] = 0.15;
	b.half[2] = 0.04;
	b.pos[2] = 0.08;
	b.caster_pos[0] = -0.15;
	b.caster_pos[2] = -0.04;
	b.caster_radius = 0.04;
	evo_scene3d_add_bot(sc, &b);
	evo_actuator_def w = evo_default_actuator_def(EVO_ACT_WHEEL);
	w.name = "MotL";
	w.pos[1] = 0.18;
	evo_scene3d_add_actuator(sc, 0, &w);
	w.name = "MotR";
	w.pos[1] = -0.18;
	evo_scene3d_add_actuator(sc, 0, &w);
	evo_sensor_def p = evo_default_sensor3d_def(EVO_SENSE_PROXIMITY);
	p.name = "S1";
	p.pos[0] = 0.2;
	evo_scene3d_add_sensor(sc, 0, &p);
	return sc;
}

/* 60 simulated seconds with neutral commands: the robot settles on its
 * wheels and caster and moves less than 1 mm all the while. */
TEST(wheeled_robot_at_rest_drifts_under_a_millimetre)
{
	evo_scene3d *sc = wheeled();
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	for (int t = 0; t < 30; t++) /* settle onto the ground */
		evo_scene3d_step(sc);
	double p0[3];
	memcpy(p0, sc->bot[0].pos, sizeof p0);
	double worst = 0;
	for (int t = 0; t < 60 * 30; t++) {
		CHECK(evo_scene3d_step(sc) == 0);
		const double *p = sc->bot[0].pos;
		double d = sqrt((p[0] - p0[0]) * (p[0] - p0[0]) +
				(p[1] - p0[1]) * (p[1] - p0[1]) +
				(p[2] - p0[2]) * (p[2] - p0[2]));
		if (d > worst)
			worst = d;
	}
	printf("  at rest: worst drift %.3g m over 60 s\n", worst);
	CHECK(worst < 1e-3);
	/* on its wheels: the chassis' centre at the axle's height */
	CHECK(NEAR(sc->bot[0].pos[2], 0.08, 0.01));
	evo_scene3d_destroy(sc);
}

/* Both wheels at 1: 15 rad/s on wheels of radius 0.08 is 1.2 m/s ahead;
 * after 2 s, about 2.4 m less the start-up. MotL alone turns it right
 * (clockwise from above: its yaw falls). */
TEST(wheels_drive_ahead_and_turn)
{
	evo_scene3d *sc = wheeled();
	evo_scene3d_reset(sc, 1, 1);
	for (int t = 0; t < 60; t++) {
		sc->bot[0].actuator[0].command = 1;
		sc->bot[0].actuator[1].command = 1;
		evo_scene3d_step(sc);
	}
	printf("  2 s ahead: x %.3f y %.3f\n", sc->bot[0].pos[0],
	       sc->bot[0].pos[1]);
	CHECK(sc->bot[0].pos[0] > 1.9 && sc->bot[0].pos[0] < 2.45);
	CHECK(fabs(sc->bot[0].pos[1]) < 0.05);
	evo_scene3d_reset(sc, 1, 1);
	for (int t = 0; t < 30; t++) {
		sc->bot[0].actuator[0].command = 1;
		evo_scene3d_step(sc);
	}
	double yaw = atan2(sc->bot[0].R[3], sc->bot[0].R[0]);
	CHECK(yaw < -0.3);
	/* in torque mode, 0.3 N m on each wheel: 7.5 N on 2.4 kg, about
	 * 3 m/s^2, so about 1.5 m/s after half a second (2 N m would lift
	 * its nose: more than its weight's moment about the caster) */
	for (int k = 0; k < 2; k++) {
		sc->bot[0].actuator[k].def.torque_mode = 1;
		sc->bot[0].actuator[k].def.max_torque = 0.3;
	}
	evo_scene3d_reset(sc, 1, 1);
	for (int t = 0; t < 15; t++) {
		sc->bot[0].actuator[0].command = 1;
		sc->bot[0].actuator[1].command = 1;
		evo_scene3d_step(sc);
	}
	printf("  torque mode, 0.5 s: %.3f m/s\n", sc->bot[0].v[0]);
	CHECK(sc->bot[0].v[0] > 1.0 && sc->bot[0].v[0] < 1.6);
	CHECK(fabs(sc->bot[0].pos[1]) < 0.05);
	CHECK(sc->fault[0] == 0);
	evo_scene3d_destroy(sc);
}

/* The proximity ray from the robot's nose (0.2 ahead of its centre) at
 * the axle's height: a cylinder of radius 0.5 at x = 2 (a box behind it,
 * added first) is 2 - 0.5 - 0.2 = 1.3 away, 1.3 / 3 of the range. */
TEST(proximity_reads_the_nearest_obstacle)
{
	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&sd);
	evo_element_def bx = evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_3D);
	bx.pos[0] = 2.8;
	bx.pos[2] = 0.5;
	evo_scene3d_add_element(sc, &bx);
	evo_element_def cy =
	    evo_default_element_def(EVO_PIECE_CYLINDER, EVO_DIM_3D);
	cy.pos[0] = 2;
	cy.pos[2] = 0.5;
	evo_scene3d_add_element(sc, &cy);
	evo_scene3d_destroy(sc);
	sc = wheeled();
	evo_scene3d_add_element(sc, &bx);
	evo_scene3d_add_element(sc, &cy);
	evo_scene3d_reset(sc, 1, 1);
	evo_scene3d_sense(sc);
	CHECK(NEAR(sc->bot[0].sensor[0].value, 1.3 / 3, 1e-6));
	CHECK(NEAR(sc->bot[0].sensor[0].ray[0] * 3.0, 1.3, 1e-6));
	/* turned away, nothing within 3 m */
	sc->bot[0].def.yaw = M_PI;
	evo_scene3d_reset(sc, 1, 1);
	evo_scene3d_sense(sc);
	CHECK(NEAR(sc->bot[0].sensor[0].value, 1.0, 1e-12));
	evo_scene3d_destroy(sc);
}

/* A bump of the ground (the cap of a buried sphere, 4 cm high, 1.4 m
 * across) 1 m ahead: the rays pass over it, the robot drives over it in
 * 2 s, and touching it is no collision; a box the same height is one. */
TEST(bumps_of_the_ground_are_driven_over)
{
	evo_scene3d *sc = wheeled();
	evo_element_def bump =
	    evo_default_element_def(EVO_PIECE_SPHERE, EVO_DIM_3D);
	bump.radius = 6;
	bump.pos[0] = 1;
	bump.pos[2] = 0.04 - 6;
	bump.ground = 1;
	CHECK(evo_scene3d_add_element(sc, &bump) >= 0);
	CHECK_EQ_INT((int)sc->obstacle[0].category, (int)EVO_CAT3D_GROUND);
	evo_scene3d_reset(sc, 1, 1);
	evo_scene3d_sense(sc);
	CHECK(sc->bot[0].sensor[0].value == 1.0);
	int touched = 0;
	double top = 0;
	for (int t = 0; t < 60; t++) {
		sc->bot[0].actuator[0].command = 1;
		sc->bot[0].actuator[1].command = 1;
		CHECK_EQ_INT(evo_scene3d_step(sc), 0);
		touched += sc->bot[0].touching;
		if (sc->bot[0].pos[2] > top)
			top = sc->bot[0].pos[2];
	}
	CHECK_EQ_INT(touched, 0);
	CHECK(sc->bot[0].pos[0] > 1.8); /* past it */
	CHECK(top > 0.08 + 0.02);	/* lifted by it on the way */
	evo_scene3d_destroy(sc);
	/* the same height as an obstacle: a box 4 cm high */
	sc = wheeled();
	evo_element_def box =
	    evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_3D);
	box.pos[0] = 1;
	box.half[2] = 0.02;
	box.pos[2] = 0.02;
	CHECK(evo_scene3d_add_element(sc, &box) >= 0);
	evo_scene3d_reset(sc, 1, 1);
	touched = 0;
	for (int t = 0; t < 60; t++) {
		sc->bot[0].actuator[0].command = 1;
		sc->bot[0].actuator[1].command = 1;
		evo_scene3d_step(sc);
		touched += sc->bot[0].touching;
	}
	CHECK(touched > 0);
	evo_scene3d_destroy(sc);
}

/* A propeller pushing 1e7 N on a 2 kg body runs past 100 m/s in a tick:
 * the episode ends there, with a message naming the bot and the penalty
 * added, and the sensors never read what is not a number. */
TEST(an_exploding_body_ends_the_episode_with_a_penalty)
{
	int t;
	evo_scene3d *sc = floating(0, &t);
	evo_actuator_def p =
	    evo_default_actuator_def(EVO_ACT_PROPELLER);
	p.name = "M1";
	p.max_thrust = 1e7;
	CHECK(evo_scene3d_add_actuator(sc, 0, &p) == 0);
	evo_scene3d_reset(sc, 1, 1);
	sc->bot[0].actuator[0].command = 1;
	int r = 0, ticks = 0;
	while (r == 0 && ticks < 100) {
		evo_scene3d_sense(sc);
		r = evo_scene3d_step(sc);
		ticks++;
	}
	CHECK_EQ_INT(r, 1);
	CHECK_EQ_INT(ticks, 1);
	CHECK_CONTAINS(sc->fault, "bot1 exploded at tick 1");
	CHECK(sc->episode_reward == -1000);
	CHECK(evo_scene3d_step(sc) == 1); /* it stays ended */
	/* a position that is not a number: caught before ODE steps it */
	evo_scene3d_reset(sc, 1, 1);
	CHECK(sc->fault[0] == 0);
	double nan3[3] = {NAN, 0, 0};
	evo_body3d_set_position(sc->world, sc->bot[0].body.index, nan3);
	CHECK(evo_scene3d_step(sc) == 1);
	CHECK_CONTAINS(sc->fault, "not a number");
	evo_scene3d_sense(sc);
	for (int k = 0; k < sc->bot[0].n_sensors; k++)
		CHECK(isfinite(sc->bot[0].sensor[k].value));
	evo_scene3d_destroy(sc);
}

/* A dynamic sphere dropped from 1 m comes to rest on the ground, its
 * centre at its radius; a zone (a trigger volume, no body) reads TRUE
 * only with the bot's centre inside it, whatever passes through it. */
TEST(objects_fall_and_zones_trigger)
{
	int t;
	evo_scene3d *sc = floating(0, &t);
	evo_element_def o =
	    evo_default_element_def(EVO_PIECE_OBJECT, EVO_DIM_3D);
	o.pos[0] = 3;
	o.pos[2] = 1;
	o.radius = 0.2;
	int obj = evo_scene3d_add_element(sc, &o);
	evo_element_def z = evo_default_element_def(EVO_PIECE_ZONE, EVO_DIM_3D);
	z.pos[2] = 2; /* around the bot at (0, 0, 2): half sides 0.5 */
	int zone = evo_scene3d_add_element(sc, &z);
	evo_sensor_def zs = evo_default_sensor3d_def(EVO_SENSE_ZONE);
	zs.name = "INZONE";
	zs.target = zone;
	int k = evo_scene3d_add_sensor(sc, 0, &zs);
	CHECK(obj >= 0 && zone >= 0 && k >= 0);
	evo_scene3d_reset(sc, 1, 1);
	for (int i = 0; i < 90; i++)
		evo_scene3d_step(sc);
	CHECK(NEAR(sc->element[obj].pos[2], 0.2, 0.01));
	CHECK(NEAR(sc->element[obj].pos[0], 3, 1e-6));
	evo_scene3d_sense(sc);
	CHECK(sc->bot[0].sensor[k].value == EVO3D_TRUE);
	double away[3] = {0, 0.7, 2};
	evo_scene3d_place_element(sc, zone, away);
	evo_scene3d_sense(sc);
	CHECK(sc->bot[0].sensor[k].value == EVO3D_FALSE);
	evo_scene3d_destroy(sc);
}

/* Bad definitions are refused with a message, never built. */
TEST(bad_definitions_are_refused)
{
	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&sd);
	evo_bot_def b = evo_default_bot_def3d();
	b.mass = -1;
	CHECK(evo_scene3d_add_bot(sc, &b) < 0);
	CHECK_CONTAINS(sc->err.msg, "mass");
	b = evo_default_bot_def3d();
	CHECK(evo_scene3d_add_bot(sc, &b) == 0);
	evo_actuator_def p =
	    evo_default_actuator_def(EVO_ACT_PROPELLER);
	p.axis[0] = 0;
	CHECK(evo_scene3d_add_actuator(sc, 0, &p) < 0);
	CHECK_CONTAINS(sc->err.msg, "axis");
	evo_sensor_def s = evo_default_sensor3d_def(EVO_SENSE_PROXIMITY);
	s.rays = 0;
	CHECK(evo_scene3d_add_sensor(sc, 0, &s) < 0);
	evo_element_def e =
	    evo_default_element_def(EVO_PIECE_CYLINDER, EVO_DIM_3D);
	e.radius = 0;
	CHECK(evo_scene3d_add_element(sc, &e) < 0);
	evo_scene3d_destroy(sc);
}

int main(void)
{
	RUN(ray_reports_the_nearest_hit);
	RUN(target_sensor_azimuth_and_elevation);
	RUN(wheeled_robot_at_rest_drifts_under_a_millimetre);
	RUN(wheels_drive_ahead_and_turn);
	RUN(proximity_reads_the_nearest_obstacle);
	RUN(bumps_of_the_ground_are_driven_over);
	RUN(an_exploding_body_ends_the_episode_with_a_penalty);
	RUN(objects_fall_and_zones_trigger);
	RUN(bad_definitions_are_refused);
	return test_summary();
}
