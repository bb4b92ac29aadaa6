/* The one sensor of both worlds (sim/scene/sensor.h): a proximity fan of
 * 21 rays (more than 3D took before the worlds shared it) reads a flat
 * wall 1.5 m ahead the same in 2D and 3D, each ray at 1.5 / cos(its
 * angle) of the way, worked out by hand; a kind of the other world and a
 * name used twice are refused with the same words in both. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "support/scenes.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

#define DEG  (M_PI / 180)
#define RAYS 21
#define ARC  (30 * DEG)

/* Ray i of the fan: from -30 to +30 degrees, 3 degrees apart; the wall's
 * face is 1.5 m ahead of the sensor, the range 12 m. */
static double expected(int i)
{
	double a = -ARC + 2 * ARC * i / (RAYS - 1);
	return 1.5 / cos(a) / 12;
}

static void check_fan(const evo_sensor *se)
{
	for (int i = 0; i < RAYS; i++)
		CHECK(fabs(se->ray[i] - expected(i)) < 1e-5);
	for (int i = RAYS; i < EVO_PROX_MAX_RAYS; i++)
		CHECK(se->ray[i] == 1.0f);
	CHECK(fabs(se->value - 1.5 / 12) < 1e-5);
}

static evo_sensor_def fan(evo_sensor_def d)
{
	d.name = "P";
	d.x = 1;
	d.range = 12;
	d.arc = ARC;
	d.rays = RAYS;
	return d;
}

TEST(a_fan_of_21_rays_reads_a_wall_the_same_in_2d_and_3d)
{
	/* 2D: the bot at the origin facing +x, a box whose face is x = 2.5 */
	evo_scene *sc = scene_with_bot(0, 0, 0);
	scene_add_box(sc, 3.0, 0, 0.5, 10, 0);
	evo_sensor_def d = fan(evo_default_sensor_def(EVO_SENSE_PROXIMITY));
	CHECK(evo_scene_add_sensor(sc, 0, &d) == 0);
	evo_scene_reset(sc, 1, 1);
	evo_scene_sense(sc);
	check_fan(&sc->bot[0].sensor[0]);
	evo_scene_destroy(sc);

	/* 3D: the same, the bot resting on the ground, the box 2 m high */
	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *s3 = evo_scene3d_create(&sd);
	evo_element_def bx =
	    evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_3D);
	bx.pos[0] = 3.0;
	bx.pos[2] = 1.0;
	bx.half[0] = 0.5;
	bx.half[1] = 10;
	bx.half[2] = 1.0;
	CHECK(evo_scene3d_add_element(s3, &bx) == 0);
	evo_bot_def b = evo_default_bot_def3d();
	b.pos[2] = b.half[2];
	CHECK(evo_scene3d_add_bot(s3, &b) == 0);
	evo_sensor_def d3 = fan(evo_default_sensor3d_def(EVO_SENSE_PROXIMITY));
	CHECK_EQ_INT(evo_scene3d_add_sensor(s3, 0, &d3), 0);
	CHECK(evo_scene3d_reset(s3, 1, 1) == 0);
	evo_scene3d_sense(s3);
	check_fan(&s3->bot[0].sensor[0]);
	evo_scene3d_destroy(s3);
}

TEST(the_other_worlds_kinds_and_a_name_twice_are_refused_alike)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_ELEVATION);
	d.name = "E";
	CHECK(evo_scene_add_sensor(sc, 0, &d) == -1);
	CHECK_CONTAINS(sc->err.msg,
		       "sensor 'E': elevation is no sensor of the 2D world");
	d = evo_default_sensor_def(EVO_SENSE_CONSTANT);
	d.name = "c";
	CHECK(evo_scene_add_sensor(sc, 0, &d) == 0);
	CHECK(evo_scene_add_sensor(sc, 0, &d) == -1);
	CHECK_CONTAINS(sc->err.msg, "sensor 'c' is defined twice");
	CHECK_EQ_INT(sc->bot[0].n_sensors, 1);
	evo_scene_destroy(sc);

	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *s3 = evo_scene3d_create(&sd);
	evo_bot_def b = evo_default_bot_def3d();
	b.name = "r";
	CHECK(evo_scene3d_add_bot(s3, &b) == 0);
	d = evo_default_sensor3d_def(EVO_SENSE_BUMPER);
	d.name = "B";
	CHECK(evo_scene3d_add_sensor(s3, 0, &d) == -1);
	CHECK_CONTAINS(s3->err.msg,
		       "sensor 'B': bumper is no sensor of the 3D world");
	d = evo_default_sensor3d_def(EVO_SENSE_CONSTANT);
	d.name = "c";
	CHECK(evo_scene3d_add_sensor(s3, 0, &d) == 0);
	CHECK(evo_scene3d_add_sensor(s3, 0, &d) == -1);
	CHECK_CONTAINS(s3->err.msg, "bot r: sensor 'c' is defined twice");
	CHECK_EQ_INT(s3->bot[0].n_sensors, 1);
	evo_scene3d_destroy(s3);
}

int main(void)
{
	RUN(a_fan_of_21_rays_reads_a_wall_the_same_in_2d_and_3d);
	RUN(the_other_worlds_kinds_and_a_name_twice_are_refused_alike);
	return test_summary();
}
