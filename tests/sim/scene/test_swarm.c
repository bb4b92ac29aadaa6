/* The swarm sensors (sim/scene/swarm.h) in both worlds: light sensors,
 * ground sensors, range-and-bearing sensors and cameras placed in known scenes
 * of the 2D (Box2D) and the 3D (ODE) world read the values worked out by hand
 * in each test's comment; a wall or box between hides a light, a message or a
 * blob; bad settings are refused with the sensor's name. */
#include <math.h>
#include <stdio.h>

#include "harness.h"
#include "support/scenes.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

#define NEAR(a, b, tol) (fabs((a) - (b)) <= (tol))
#define DEG		(M_PI / 180.0)

/* 0.5 + atan2(4, 3) / 2 pi: a neighbour 3 ahead and 4 aside. */
#define BEARING_34 (0.5 + 0.927295218001612 / (2 * M_PI))

/* ---- 2D --------------------------------------------------------------- */

static void light2d(evo_scene *sc, double x, double y, double intensity)
{
	evo_light l = {{x, y, 0}, intensity};
	CHECK(evo_swarm_add_light(&sc->swarm, &l, &sc->err) >= 0);
}

static int sensor2d(evo_scene *sc, int bot, evo_sense_kind kind,
		    const char *name, double x, double y, double angle)
{
	evo_sensor_def d = evo_default_sensor_def(kind);
	d.name = name;
	d.x = x;
	d.y = y;
	d.angle = angle;
	int s = evo_scene_add_sensor(sc, bot, &d);
	CHECK(s >= 0);
	return s;
}

static double read2d(evo_scene *sc, int bot, int s)
{
	evo_scene_sense(sc);
	return sc->bot[bot].sensor[s].value;
}

/* Intensity 10 at (4, 3), 5 away, 36.9 degrees off the heading: 10 / 25
 * = 0.4 through an aperture of 45 degrees, nothing through one of 30.
 * With every direction open, a light of 5 at (0, -5) adds 5 / 25. */
TEST(light_2d_falls_with_the_square_of_distance)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	light2d(sc, 4, 3, 10);
	int s = sensor2d(sc, 0, EVO_SENSE_LIGHT, "L", 0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(read2d(sc, 0, s), 0.4, 1e-12));
	sc->bot[0].sensor[s].def.swarm.aperture = 30 * DEG;
	CHECK(NEAR(read2d(sc, 0, s), 0.0, 1e-12));
	light2d(sc, 0, -5, 5);
	sc->bot[0].sensor[s].def.swarm.aperture = M_PI;
	CHECK(NEAR(read2d(sc, 0, s), 0.6, 1e-12));
	/* within sqrt(intensity) it reads 1, and so does a sum above 1 */
	light2d(sc, 1, 0, 10);
	CHECK(NEAR(read2d(sc, 0, s), 1.0, 1e-12));
	evo_scene_destroy(sc);
}

/* A bot at the origin turned 90 degrees (facing +y) with its sensor 1
 * ahead of its centre, (0, 1) in the world, facing ahead: a light of 4
 * at (0, 5) is 4 away straight ahead, 4 / 16. */
TEST(light_2d_turns_with_the_bot)
{
	evo_scene *sc = scene_with_bot(0, 0, 90 * DEG);
	light2d(sc, 0, 5, 4);
	int s = sensor2d(sc, 0, EVO_SENSE_LIGHT, "L", 1, 0, 0);
	int back = sensor2d(sc, 0, EVO_SENSE_LIGHT, "B", -1, 0, 180 * DEG);
	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(read2d(sc, 0, s), 0.25, 1e-12));
	CHECK(NEAR(read2d(sc, 0, back), 0.0, 1e-12));
	evo_scene_destroy(sc);
}

/* A light of 9 at (6, 0) reads 9 / 36; a box across x = 3 hides it. */
TEST(light_2d_is_hidden_by_an_obstacle)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	light2d(sc, 6, 0, 9);
	int s = sensor2d(sc, 0, EVO_SENSE_LIGHT, "L", 0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(read2d(sc, 0, s), 0.25, 1e-12));
	evo_scene_destroy(sc);
	sc = scene_with_bot(0, 0, 0);
	light2d(sc, 6, 0, 9);
	scene_add_box(sc, 3, 0, 0.5, 5, 0);
	s = sensor2d(sc, 0, EVO_SENSE_LIGHT, "L", 0, 0, 0);
	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(read2d(sc, 0, s), 0.0, 1e-12));
	evo_scene_destroy(sc);
}

/* A grey square of half side 1 at (5, 0), 0.3, under a circle of radius
 * 0.5 at (5, 0.5), 0.7, added last. The bot at (4.5, 0): its centre is
 * on the square only (0.71 from the circle's centre), (0.5, 0.5) ahead
 * and aside is the circle's centre, 5 behind is the bare floor, 1. */
TEST(ground_2d_reads_the_top_patch)
{
	evo_scene *sc = scene_with_bot(4.5, 0, 0);
	evo_patch sq = {0, 5, 0, 0, 1, 1, 0, 0.3};
	evo_patch ci = {1, 5, 0.5, 0, 0, 0, 0.5, 0.7};
	CHECK_EQ_INT(evo_swarm_add_patch(&sc->swarm, &sq, &sc->err), 0);
	CHECK_EQ_INT(evo_swarm_add_patch(&sc->swarm, &ci, &sc->err), 1);
	int c = sensor2d(sc, 0, EVO_SENSE_GROUND, "G0", 0, 0, 0);
	int a = sensor2d(sc, 0, EVO_SENSE_GROUND, "G1", 0.5, 0.5, 0);
	int b = sensor2d(sc, 0, EVO_SENSE_GROUND, "G2", -5, 0, 0);
	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(read2d(sc, 0, c), 0.3, 1e-12));
	CHECK(NEAR(read2d(sc, 0, a), 0.7, 1e-12));
	CHECK(NEAR(read2d(sc, 0, b), 1.0, 1e-12));
	evo_scene_destroy(sc);
}

/* A strip 4 long and 0.2 wide turned 45 degrees at the origin holds
 * (1, 1) (on its axis) and not (1, 0) (0.71 off it). */
TEST(ground_turned_patch)
{
	evo_swarm w = {0};
	evo_err err;
	evo_patch p = {0, 0, 0, 45 * DEG, 2, 0.1, 0, 0.25};
	CHECK(evo_swarm_add_patch(&w, &p, &err) == 0);
	evo_swarm_frame f = evo_swarm_frame_2d(0, 0, 0);
	double on[3] = {1, 1, 0}, off[3] = {1, 0, 0};
	CHECK(NEAR(evo_swarm_ground(&w, &f, on), 0.25, 1e-12));
	CHECK(NEAR(evo_swarm_ground(&w, &f, off), 1.0, 1e-12));
	evo_swarm_free(&w);
}

static void add_bot2d(evo_scene *sc, const char *name, double x, double y,
		      int broadcasts)
{
	evo_bot_def d = evo_default_bot_def();
	d.name = name;
	d.x = x;
	d.y = y;
	int b = evo_scene_add_bot(sc, &d);
	CHECK(b >= 0);
	if (broadcasts) {
		evo_actuator_def a =
		    evo_default_actuator_def(EVO_ACT_BROADCAST);
		a.name = "TX";
		CHECK(evo_scene_add_actuator(sc, b, &a) == 0);
	}
}

static int rab2d(evo_scene *sc, const char *name, int slot, evo_rab_read r,
		 double range, int occluded)
{
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_RAB);
	d.name = name;
	d.swarm.slot = slot;
	d.swarm.read = r;
	d.swarm.range = range;
	d.swarm.occluded = occluded;
	d.swarm.scale = 4;
	int s = evo_scene_add_sensor(sc, 0, &d);
	CHECK(s >= 0);
	return s;
}

/* Bot 0 at the origin heading +x; B at (3, 4), 5 away, broadcasting 0.3;
 * C at (-6, 0), 6 away straight behind, broadcasting its neutral 0.5; D
 * at (0, -3) broadcasts nothing and is not heard. Range 10: the nearest
 * is B (5 / 10, bearing 53.1 degrees), then C (6 / 10, behind: 1); a
 * third is none (1, 0.5, 0); 2 heard of a scale of 4; within 5.5, 1. */
static evo_scene *rab_scene2d(int box)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	evo_actuator_def a = evo_default_actuator_def(EVO_ACT_BROADCAST);
	a.name = "TX";
	CHECK(evo_scene_add_actuator(sc, 0, &a) == 0);
	add_bot2d(sc, "B", 3, 4, 1);
	add_bot2d(sc, "C", -6, 0, 1);
	add_bot2d(sc, "D", 0, -3, 0);
	if (box)
		scene_add_box(sc, -3, 0, 0.5, 0.5, 0);
	return sc;
}

TEST(rab_2d_ranks_neighbours_by_distance)
{
	evo_scene *sc = rab_scene2d(0);
	int r1 = rab2d(sc, "R1", 1, EVO_RAB_RANGE, 10, 0);
	int b1 = rab2d(sc, "B1", 1, EVO_RAB_BEARING, 10, 0);
	int v1 = rab2d(sc, "V1", 1, EVO_RAB_VALUE, 10, 0);
	int r2 = rab2d(sc, "R2", 2, EVO_RAB_RANGE, 10, 0);
	int b2 = rab2d(sc, "B2", 2, EVO_RAB_BEARING, 10, 0);
	int v2 = rab2d(sc, "V2", 2, EVO_RAB_VALUE, 10, 0);
	int r3 = rab2d(sc, "R3", 3, EVO_RAB_RANGE, 10, 0);
	int b3 = rab2d(sc, "B3", 3, EVO_RAB_BEARING, 10, 0);
	int v3 = rab2d(sc, "V3", 3, EVO_RAB_VALUE, 10, 0);
	int n = rab2d(sc, "N", 1, EVO_RAB_COUNT, 10, 0);
	int near = rab2d(sc, "NEAR", 1, EVO_RAB_COUNT, 5.5, 0);
	evo_scene_reset(sc, 1, 1);
	sc->bot[1].actuator[0].command = 0.3;
	evo_scene_sense(sc);
	const evo_sensor *s = sc->bot[0].sensor;
	CHECK(NEAR(s[r1].value, 0.5, 1e-12));
	CHECK(NEAR(s[b1].value, BEARING_34, 1e-12));
	CHECK(NEAR(s[v1].value, 0.3, 1e-12));
	CHECK(NEAR(s[r2].value, 0.6, 1e-12));
	CHECK(NEAR(s[b2].value, 1.0, 1e-12));
	CHECK(NEAR(s[v2].value, 0.5, 1e-12));
	CHECK(s[r3].value == 1.0 && s[b3].value == 0.5 && s[v3].value == 0);
	CHECK(NEAR(s[n].value, 0.5, 1e-12));
	CHECK(NEAR(s[near].value, 0.25, 1e-12));
	evo_scene_destroy(sc);
}

/* A box at (-3, 0) stands between bot 0 and C: occluded, C is not heard
 * (the second slot is empty, 1); not occluded, it is (0.6). */
TEST(rab_2d_occlusion_is_an_option)
{
	evo_scene *sc = rab_scene2d(1);
	int hid = rab2d(sc, "HID", 2, EVO_RAB_RANGE, 10, 1);
	int seen = rab2d(sc, "SEEN", 2, EVO_RAB_RANGE, 10, 0);
	evo_scene_reset(sc, 1, 1);
	evo_scene_sense(sc);
	CHECK(NEAR(sc->bot[0].sensor[hid].value, 1.0, 1e-12));
	CHECK(NEAR(sc->bot[0].sensor[seen].value, 0.6, 1e-12));
	evo_scene_destroy(sc);
}

TEST(bad_settings_are_refused)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_RAB);
	d.name = "RX";
	d.swarm.range = -1;
	CHECK(evo_scene_add_sensor(sc, 0, &d) < 0);
	CHECK(strstr(sc->err.msg, "'RX'") && strstr(sc->err.msg, "range"));
	d.swarm.range = 1;
	d.swarm.slot = 0;
	CHECK(evo_scene_add_sensor(sc, 0, &d) < 0);
	d = evo_default_sensor_def(EVO_SENSE_LIGHT);
	d.name = "L";
	d.swarm.aperture = -0.1;
	CHECK(evo_scene_add_sensor(sc, 0, &d) < 0);
	CHECK(strstr(sc->err.msg, "aperture") != NULL);
	evo_light l = {{0, 0, 0}, 0};
	CHECK(evo_swarm_add_light(&sc->swarm, &l, &sc->err) < 0);
	CHECK(strstr(sc->err.msg, "intensity") != NULL);
	evo_patch p = {0, 0, 0, 0, 1, 1, 0, 1.5};
	CHECK(evo_swarm_add_patch(&sc->swarm, &p, &sc->err) < 0);
	CHECK(strstr(sc->err.msg, "grey") != NULL);
	p.grey = 0.5;
	p.hx = 0;
	CHECK(evo_swarm_add_patch(&sc->swarm, &p, &sc->err) < 0);
	evo_scene_destroy(sc);
}

/* ---- 3D --------------------------------------------------------------- */

/* A floating bot (neutral buoyancy) at (x, y, 2) facing yaw. */
static int add_bot3d(evo_scene3d *sc, const char *name, double x, double y,
		     double z, double yaw, int broadcasts)
{
	evo_bot_def b = evo_default_bot_def3d();
	b.name = name;
	b.radius = 0.25;
	b.pos[0] = x;
	b.pos[1] = y;
	b.pos[2] = z;
	b.yaw = yaw;
	b.buoyancy = 1;
	int i = evo_scene3d_add_bot(sc, &b);
	CHECK(i >= 0);
	if (broadcasts) {
		evo_actuator_def a =
		    evo_default_actuator_def(EVO_ACT_BROADCAST);
		a.name = "TX";
		CHECK(evo_scene3d_add_actuator(sc, i, &a) == 0);
	}
	return i;
}

static evo_scene3d *scene3d(double yaw)
{
	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&sd);
	add_bot3d(sc, "A", 0, 0, 2, yaw, 0);
	return sc;
}

static int sensor3d(evo_scene3d *sc, int bot, evo_sense_kind kind,
		    const char *name, double x, double y, double yaw)
{
	evo_sensor_def d = evo_default_sensor3d_def(kind);
	d.name = name;
	d.pos[0] = x;
	d.pos[1] = y;
	d.yaw = yaw;
	int s = evo_scene3d_add_sensor(sc, bot, &d);
	CHECK(s >= 0);
	return s;
}

static void light3d(evo_scene3d *sc, double x, double y, double z, double i)
{
	evo_light l = {{x, y, z}, i};
	CHECK(evo_swarm_add_light(&sc->swarm, &l, &sc->err) >= 0);
}

static double read3d(evo_scene3d *sc, int bot, int s)
{
	evo_scene3d_sense(sc);
	return sc->bot[bot].sensor[s].value;
}

/* The bot at (0, 0, 2) heading +x. A light of 10 at (4, 3, 2): 5 away,
 * 36.9 degrees to the left, 10 / 25 = 0.4 through 45 degrees, 0 through
 * 30; moved up to (4, 3, 5): 34 m^2 away, 10 / 34, at the same bearing
 * about the bot's z (the aperture is about the vertical). */
TEST(light_3d_falls_with_the_square_of_distance)
{
	evo_scene3d *sc = scene3d(0);
	light3d(sc, 4, 3, 2, 10);
	int s = sensor3d(sc, 0, EVO_SENSE_LIGHT, "L", 0, 0, 0);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	CHECK(NEAR(read3d(sc, 0, s), 0.4, 1e-9));
	sc->bot[0].sensor[s].def.swarm.aperture = 30 * DEG;
	CHECK(NEAR(read3d(sc, 0, s), 0.0, 1e-12));
	sc->bot[0].sensor[s].def.swarm.aperture = 45 * DEG;
	sc->swarm.light[0].pos[2] = 5;
	CHECK(NEAR(read3d(sc, 0, s), 10.0 / 34, 1e-9));
	evo_scene3d_destroy(sc);
	/* turned 90 degrees left (facing +y), a light of 4 at (0, 5, 2)
	 * is 5 ahead: 4 / 25; a sensor facing back sees nothing */
	sc = scene3d(90 * DEG);
	light3d(sc, 0, 5, 2, 4);
	s = sensor3d(sc, 0, EVO_SENSE_LIGHT, "L", 0, 0, 0);
	int back = sensor3d(sc, 0, EVO_SENSE_LIGHT, "B", 0, 0, 180 * DEG);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	CHECK(NEAR(read3d(sc, 0, s), 0.16, 1e-9));
	CHECK(NEAR(read3d(sc, 0, back), 0.0, 1e-12));
	evo_scene3d_destroy(sc);
}

/* A light of 9 at (6, 0, 2): 9 / 36; a box of half side 0.5 at (3, 0, 2)
 * hides it. */
TEST(light_3d_is_hidden_by_an_obstacle)
{
	evo_scene3d *sc = scene3d(0);
	light3d(sc, 6, 0, 2, 9);
	int s = sensor3d(sc, 0, EVO_SENSE_LIGHT, "L", 0, 0, 0);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	CHECK(NEAR(read3d(sc, 0, s), 0.25, 1e-9));
	evo_element_def bx = evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_3D);
	bx.pos[0] = 3;
	bx.pos[2] = 2;
	CHECK(evo_scene3d_add_element(sc, &bx) >= 0);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	CHECK(NEAR(read3d(sc, 0, s), 0.0, 1e-12));
	evo_scene3d_destroy(sc);
}

/* The 2D patches again, under a bot floating at (4.5, 0, 2): a ground
 * sensor reads the floor under it whatever its height. In 3D +y is the
 * bot's left: (0.5, 0.5) is still the circle's centre (5, 0.5). */
TEST(ground_3d_reads_the_top_patch)
{
	evo_scene3d_def sd = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&sd);
	add_bot3d(sc, "A", 4.5, 0, 2, 0, 0);
	evo_patch sq = {0, 5, 0, 0, 1, 1, 0, 0.3};
	evo_patch ci = {1, 5, 0.5, 0, 0, 0, 0.5, 0.7};
	CHECK_EQ_INT(evo_swarm_add_patch(&sc->swarm, &sq, &sc->err), 0);
	CHECK_EQ_INT(evo_swarm_add_patch(&sc->swarm, &ci, &sc->err), 1);
	int c = sensor3d(sc, 0, EVO_SENSE_GROUND, "G0", 0, 0, 0);
	int a = sensor3d(sc, 0, EVO_SENSE_GROUND, "G1", 0.5, 0.5, 0);
	int b = sensor3d(sc, 0, EVO_SENSE_GROUND, "G2", -5, 0, 0);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	CHECK(NEAR(read3d(sc, 0, c), 0.3, 1e-9));
	CHECK(NEAR(read3d(sc, 0, a), 0.7, 1e-9));
	CHECK(NEAR(read3d(sc, 0, b), 1.0, 1e-9));
	evo_scene3d_destroy(sc);
}

static int rab3d(evo_scene3d *sc, const char *name, int slot, evo_rab_read r,
		 int occluded)
{
	evo_sensor_def d = evo_default_sensor3d_def(EVO_SENSE_RAB);
	d.name = name;
	d.swarm.slot = slot;
	d.swarm.read = r;
	d.swarm.range = 10;
	d.swarm.occluded = occluded;
	d.swarm.scale = 4;
	int s = evo_scene3d_add_sensor(sc, 0, &d);
	CHECK(s >= 0);
	return s;
}

/* Bot A at (0, 0, 2) heading +x; B at (3, 4, 2), 5 away and 53.1 degrees
 * to the left, broadcasting 0.3; C at (-3, 0, 6), 5 up and back: 5 away
 * too, ranked after B (its index is higher), behind (bearing 1); D at
 * (0, -2, 2) broadcasts nothing. With a box at (-1.5, 0, 4) on the line
 * to C and occlusion, only B is heard. */
TEST(rab_3d_ranks_neighbours_by_distance)
{
	evo_scene3d *sc = scene3d(0);
	evo_actuator_def a =
	    evo_default_actuator_def(EVO_ACT_BROADCAST);
	a.name = "TX";
	CHECK(evo_scene3d_add_actuator(sc, 0, &a) == 0);
	add_bot3d(sc, "B", 3, 4, 2, 0, 1);
	add_bot3d(sc, "C", -3, 0, 6, 0, 1);
	add_bot3d(sc, "D", 0, -2, 2, 0, 0);
	int r1 = rab3d(sc, "R1", 1, EVO_RAB_RANGE, 0);
	int b1 = rab3d(sc, "B1", 1, EVO_RAB_BEARING, 0);
	int v1 = rab3d(sc, "V1", 1, EVO_RAB_VALUE, 0);
	int r2 = rab3d(sc, "R2", 2, EVO_RAB_RANGE, 0);
	int b2 = rab3d(sc, "B2", 2, EVO_RAB_BEARING, 0);
	int n = rab3d(sc, "N", 1, EVO_RAB_COUNT, 0);
	int hid = rab3d(sc, "HID", 2, EVO_RAB_RANGE, 1);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	sc->bot[1].actuator[0].command = 0.3;
	evo_scene3d_sense(sc);
	const evo_sensor *s = sc->bot[0].sensor;
	CHECK(NEAR(s[r1].value, 0.5, 1e-9));
	CHECK(NEAR(s[b1].value, BEARING_34, 1e-9));
	CHECK(NEAR(s[v1].value, 0.3, 1e-12));
	CHECK(NEAR(s[r2].value, 0.5, 1e-9));
	CHECK(NEAR(s[b2].value, 1.0, 1e-9));
	CHECK(NEAR(s[n].value, 0.5, 1e-12));
	CHECK(NEAR(s[hid].value, 0.5, 1e-9)); /* nothing in the way yet */
	evo_element_def bx = evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_3D);
	bx.pos[0] = -1.5;
	bx.pos[2] = 4;
	bx.half[0] = bx.half[1] = bx.half[2] = 0.3;
	CHECK(evo_scene3d_add_element(sc, &bx) >= 0);
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	evo_scene3d_sense(sc);
	CHECK(NEAR(s[hid].value, 1.0, 1e-12));
	CHECK(NEAR(s[r2].value, 0.5, 1e-9));
	evo_scene3d_destroy(sc);
}

/* ---- cameras -------------------------------------------------------- */

static void camera_expect(double got[7], int occluded_light)
{
	/* slot 1: B, red, 4 ahead; slot 2: the green blob 5 aside (90
	 * degrees: right in 2D, left in 3D, 0.75 both); slot 3: the yellow
	 * light 6 the other side (0.25), unless a box hides it */
	CHECK(NEAR(got[0], 0.4, 1e-9));
	CHECK(NEAR(got[1], 0.5, 1e-9));
	CHECK(NEAR(got[2], 1.0 / 8, 1e-12));
	CHECK(NEAR(got[3], 0.75, 1e-9));
	CHECK(NEAR(got[4], 3.0 / 8, 1e-12));
	if (occluded_light) {
		CHECK(got[5] == 0.5); /* no third: a bearing of 0.5 */
		CHECK(NEAR(got[6], 0.5, 1e-12)); /* 2 seen of a scale of 4 */
	} else {
		CHECK(NEAR(got[5], 0.25, 1e-9));
		CHECK(NEAR(got[6], 0.75, 1e-12));
	}
}

static const struct {
	const char *name;
	int slot;
	evo_rab_read read;
} cam[7] = {{"R1", 1, EVO_RAB_RANGE},  {"B1", 1, EVO_RAB_BEARING},
	    {"C1", 1, EVO_RAB_COLOUR}, {"B2", 2, EVO_RAB_BEARING},
	    {"C2", 2, EVO_RAB_COLOUR}, {"B3", 3, EVO_RAB_BEARING},
	    {"N", 1, EVO_RAB_COUNT}};

/* Bot 0 at the origin heading +x; bot B at (4, 0) coloured red; a
 * cylinder of radius 1 at (0, 5) green; a light at (0, -6) yellow; an
 * uncoloured cylinder at (-5, 0) unseen. With a box at (0, -3) and
 * occlusion the light is hidden; the green cylinder's own rim does not
 * hide it; a camera for green alone sees it first, 5 away. */
static void camera_2d(int box)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	add_bot2d(sc, "B", 4, 0, 0);
	int green = scene_add_element(sc, EVO_PIECE_CYLINDER, 0, 5, 1);
	scene_add_element(sc, EVO_PIECE_CYLINDER, -5, 0, 1);
	if (box)
		scene_add_box(sc, 0, -3, 0.5, 0.5, 0);
	light2d(sc, 0, -6, 1);
	CHECK(evo_swarm_set_colour(&sc->swarm, EVO_BLOB_BOT, 1, EVO_COLOUR_RED,
				   &sc->err) >= 0);
	CHECK(evo_swarm_set_colour(&sc->swarm, EVO_BLOB_ELEMENT, green,
				   EVO_COLOUR_GREEN, &sc->err) >= 0);
	CHECK(evo_swarm_set_colour(&sc->swarm, EVO_BLOB_LIGHT, 0,
				   EVO_COLOUR_YELLOW, &sc->err) >= 0);
	int s[7];
	for (int i = 0; i < 7; i++) {
		evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_CAMERA);
		d.name = cam[i].name;
		d.swarm.slot = cam[i].slot;
		d.swarm.read = cam[i].read;
		d.swarm.range = 10;
		d.swarm.scale = 4;
		d.swarm.occluded = box;
		s[i] = evo_scene_add_sensor(sc, 0, &d);
		CHECK(s[i] >= 0);
	}
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_CAMERA);
	d.name = "G";
	d.swarm.range = 10;
	d.swarm.colour = EVO_COLOUR_GREEN;
	d.swarm.occluded = 1;
	int g = evo_scene_add_sensor(sc, 0, &d);
	evo_scene_reset(sc, 1, 1);
	evo_scene_sense(sc);
	double got[7];
	for (int i = 0; i < 7; i++)
		got[i] = sc->bot[0].sensor[s[i]].value;
	camera_expect(got, box);
	CHECK(NEAR(sc->bot[0].sensor[g].value, 0.5, 1e-9));
	evo_scene_destroy(sc);
}

TEST(camera_2d_sees_the_nearest_coloured_blobs)
{
	camera_2d(0);
	camera_2d(1);
}

/* The same in 3D, every centre at z = 2: a sphere of radius 1 for the
 * cylinder; +y is the bot's left. The sphere set off is seen no more. */
static void camera_3d(int box)
{
	evo_scene3d *sc = scene3d(0);
	add_bot3d(sc, "B", 4, 0, 2, 0, 0);
	evo_element_def sp =
	    evo_default_element_def(EVO_PIECE_SPHERE, EVO_DIM_3D);
	sp.pos[1] = 5;
	sp.pos[2] = 2;
	sp.radius = 1;
	int green = evo_scene3d_add_element(sc, &sp);
	CHECK(green >= 0);
	if (box) {
		evo_element_def bx =
		    evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_3D);
		bx.pos[1] = -3;
		bx.pos[2] = 2;
		CHECK(evo_scene3d_add_element(sc, &bx) >= 0);
	}
	light3d(sc, 0, -6, 2, 1);
	CHECK(evo_swarm_set_colour(&sc->swarm, EVO_BLOB_BOT, 1, EVO_COLOUR_RED,
				   &sc->err) >= 0);
	CHECK(evo_swarm_set_colour(&sc->swarm, EVO_BLOB_ELEMENT, green,
				   EVO_COLOUR_GREEN, &sc->err) >= 0);
	CHECK(evo_swarm_set_colour(&sc->swarm, EVO_BLOB_LIGHT, 0,
				   EVO_COLOUR_YELLOW, &sc->err) >= 0);
	int s[7];
	for (int i = 0; i < 7; i++) {
		evo_sensor_def d =
		    evo_default_sensor3d_def(EVO_SENSE_CAMERA);
		d.name = cam[i].name;
		d.swarm.slot = cam[i].slot;
		d.swarm.read = cam[i].read;
		d.swarm.range = 10;
		d.swarm.scale = 4;
		d.swarm.occluded = box;
		s[i] = evo_scene3d_add_sensor(sc, 0, &d);
		CHECK(s[i] >= 0);
	}
	CHECK(evo_scene3d_reset(sc, 1, 1) == 0);
	evo_scene3d_sense(sc);
	double got[7];
	for (int i = 0; i < 7; i++)
		got[i] = sc->bot[0].sensor[s[i]].value;
	camera_expect(got, box);
	if (!box) {
		/* the green sphere set off is no blob: the light is second
		 * (bearing 0.25), there is no third (0.5), 2 seen of 4 */
		evo_scene3d_set_active(sc, green, 0);
		evo_scene3d_sense(sc);
		CHECK(NEAR(sc->bot[0].sensor[s[3]].value, 0.25, 1e-9));
		CHECK(sc->bot[0].sensor[s[5]].value == 0.5);
		CHECK(NEAR(sc->bot[0].sensor[s[6]].value, 0.5, 1e-12));
	}
	evo_scene3d_destroy(sc);
}

TEST(camera_3d_sees_the_nearest_coloured_blobs)
{
	camera_3d(0);
	camera_3d(1);
}

int main(void)
{
	RUN(light_2d_falls_with_the_square_of_distance);
	RUN(light_2d_turns_with_the_bot);
	RUN(light_2d_is_hidden_by_an_obstacle);
	RUN(ground_2d_reads_the_top_patch);
	RUN(ground_turned_patch);
	RUN(rab_2d_ranks_neighbours_by_distance);
	RUN(rab_2d_occlusion_is_an_option);
	RUN(bad_settings_are_refused);
	RUN(light_3d_falls_with_the_square_of_distance);
	RUN(light_3d_is_hidden_by_an_obstacle);
	RUN(ground_3d_reads_the_top_patch);
	RUN(rab_3d_ranks_neighbours_by_distance);
	RUN(camera_2d_sees_the_nearest_coloured_blobs);
	RUN(camera_3d_sees_the_nearest_coloured_blobs);
	return test_summary();
}
