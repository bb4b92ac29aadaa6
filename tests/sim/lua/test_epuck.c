/* The e-puck models (lua/bots/EPuck.lua, lua/bots/EPuck3D.lua,
 * lua/lib/epuck.lua): built by the scene scripts in each world, they have
 * the published e-puck's IR ring (eight sensors on a rim of radius 35 mm
 * at +-17, +-46, +-90 and +-150 degrees), its wheels 53 mm apart and its
 * top speed of 0.128 m/s, worked out by hand below; and its light, ground
 * and range-and-bearing sensors read a light, a patch and a neighbour;
 * the shipped swarm of them (minds/Phototaxis) gathers at its light. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "lua/lua_evo.h"
#include "support/cli.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

#define NEAR(a, b, eps) (fabs((a) - (b)) <= (eps))
#define DEG		(M_PI / 180.0)

static const double ir_angles[8] = {17, 46, 90, 150, -150, -90, -46, -17};

/* Two e-pucks, the second 0.3 m to the side of the first; a light of
 * 0.04 at 0.2 m ahead of the first (0.04 / 0.2^2 = 1 at its centre; its
 * front sensors L0 and L7, 35 mm ahead, read 1 too); a black patch
 * under the first's ground sensors. */
static const char *const env2d =
    "local e = {}\n"
    "function e.init(scene)\n"
    "  scene:light{ x = 1.2, y = 0, intensity = 0.04 }\n"
    "  scene:patch{ x = 1.03, y = 0, radius = 0.02, grey = 0 }\n"
    "  scene:bot{ x = 1, y = 0 }\n"
    "  scene:bot{ x = 1, y = 0.3 }\n"
    "end\n"
    "return e\n";

static evo_lua *build2d(evo_scene **sc, evo_err *err)
{
	cli_write(env2d, "%s/Envs/E2.lua", cli_tmp);
	*sc = evo_scene_create();
	evo_lua_def ld = {
	    .scene = *sc, .mind_dir = cli_tmp, .botmodel = "EPuck"};
	evo_lua *l = evo_lua_create(&ld, err);
	if (l && evo_lua_init_env(l, "E2", err)) {
		evo_lua_destroy(l);
		l = NULL;
	}
	if (l) {
		evo_scene_reset(*sc, 1, 1);
		if (evo_lua_reset(l, 1, err)) {
			evo_lua_destroy(l);
			l = NULL;
		}
	}
	return l;
}

static double value2d(const evo_scene *sc, int bot, const char *name)
{
	int k = evo_bot_find_sensor(&sc->bot[bot], name);
	CHECK(k >= 0);
	return k >= 0 ? sc->bot[bot].sensor[k].value : -1;
}

static void command2d(evo_scene *sc, const char *name, double c)
{
	int a = evo_bot_find_actuator(&sc->bot[0], name);
	CHECK(a >= 0);
	if (a >= 0)
		sc->bot[0].actuator[a].command = c;
}

TEST(epuck_2d_has_the_published_ring_wheels_and_speed)
{
	evo_scene *sc;
	evo_err err = {{0}};
	evo_lua *l = build2d(&sc, &err);
	CHECK(l != NULL);
	if (!l) {
		printf("  %s\n", err.msg);
		evo_scene_destroy(sc);
		return;
	}
	const evo_bot *b = &sc->bot[0];
	CHECK(NEAR(b->radius, 0.035, 1e-12));
	for (int i = 0; i < 8; i++) {
		char name[16];
		snprintf(name, sizeof name, "IR%d", i);
		int k = evo_bot_find_sensor(b, name);
		CHECK(k >= 0);
		if (k < 0)
			continue;
		const evo_sensor_def *d = &b->sensor[k].def;
		CHECK(NEAR(d->angle, ir_angles[i] * DEG, 1e-12));
		CHECK(NEAR(hypot(d->x, d->y), 0.035, 1e-12));
		CHECK(NEAR(d->range, 0.04, 1e-12));
	}
	int ml = evo_bot_find_actuator(b, "MotL"),
	    mr = evo_bot_find_actuator(b, "MotR");
	CHECK(ml >= 0 && mr >= 0);
	if (ml >= 0 && mr >= 0)
		CHECK(NEAR(b->actuator[mr].def.y - b->actuator[ml].def.y, 0.053,
			   1e-12));
	/* the light 0.2 ahead of the centre: the front sensors, 0.2 -
	 * 0.035 cos 17 = 0.1665 away, read 1; L2, facing right, and the
	 * back ones see nothing; the ground under G2 (30 mm ahead) is the
	 * black patch, under G1 and G3 (10 mm aside) too; the neighbour 0.3
	 * to the right (+y): R1 0.3 / 0.8, B1 0.75 */
	evo_scene_sense(sc);
	CHECK(NEAR(value2d(sc, 0, "L0"), 1, 1e-12));
	CHECK(NEAR(value2d(sc, 0, "L7"), 1, 1e-12));
	CHECK(NEAR(value2d(sc, 0, "L3"), 0, 1e-12));
	CHECK(NEAR(value2d(sc, 0, "G2"), 0, 1e-12));
	CHECK(NEAR(value2d(sc, 1, "G2"), 1, 1e-12));
	/* (Box2D keeps positions in floats) */
	CHECK(NEAR(value2d(sc, 0, "R1"), 0.3 / 0.8, 1e-6));
	CHECK(NEAR(value2d(sc, 0, "B1"), 0.75, 1e-6));
	CHECK(NEAR(value2d(sc, 0, "NB"), 0.1, 1e-12));
	/* the second hears the first broadcast its TX1 command, last tick's */
	command2d(sc, "TX1", 0.9);
	evo_scene_sense(sc);
	CHECK(NEAR(value2d(sc, 1, "V1"), 0.9, 1e-12));
	/* both wheels full ahead for 60 ticks (2 s): 0.256 m ahead */
	command2d(sc, "MotL", 1);
	command2d(sc, "MotR", 1);
	for (int t = 0; t < 60; t++) {
		evo_scene_sense(sc);
		evo_scene_step(sc);
	}
	CHECK(NEAR(sc->bot[0].x - 1, 0.256, 2e-3));
	CHECK(NEAR(sc->bot[0].y, 0, 1e-6));
	/* MotL ahead, MotR back: a turn of 2 x 0.128 / 0.053 = 4.83 rad/s
	 * clockwise on screen; in 0.3 s (9 ticks) 1.449 rad */
	double a0 = sc->bot[0].angle;
	command2d(sc, "MotR", 0);
	for (int t = 0; t < 9; t++) {
		evo_scene_sense(sc);
		evo_scene_step(sc);
	}
	CHECK(NEAR(sc->bot[0].angle - a0, 2 * 0.128 / 0.053 * 0.3, 0.02));
	evo_lua_destroy(l);
	evo_scene_destroy(sc);
}

/* The 3D model on the ground: the same ring (angles counter-clockwise,
 * so IR0 at -17 degrees), wheels 53 mm apart of radius 20.5 mm, turned at
 * up to 0.128 / 0.0205 rad/s: after 3 s at full speed it goes at
 * 0.128 m/s (its last second's travel within 10 %). */
TEST(epuck_3d_has_the_published_ring_wheels_and_speed)
{
	cli_write("local e = {}\nfunction e.init(scene) scene:bot{} end\n"
		  "return e\n",
		  "%s/Envs/E3.lua", cli_tmp);
	evo_scene3d_def d = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&d);
	evo_lua_def ld = {
	    .scene3d = sc, .mind_dir = cli_tmp, .botmodel = "EPuck3D"};
	evo_err err = {{0}};
	evo_lua *l = evo_lua_create(&ld, &err);
	CHECK(l != NULL);
	if (!l || evo_lua_init_env(l, "E3", &err) ||
	    evo_scene3d_reset(sc, 1, 1)) {
		printf("  %s\n", err.msg);
		evo_lua_destroy(l);
		evo_scene3d_destroy(sc);
		return;
	}
	evo_bot *b = &sc->bot[0];
	for (int i = 0; i < 8; i++) {
		char name[16];
		snprintf(name, sizeof name, "IR%d", i);
		int k = evo_bot_find_sensor(b, name);
		CHECK(k >= 0);
		if (k < 0)
			continue;
		const evo_sensor_def *sd = &b->sensor[k].def;
		CHECK(NEAR(sd->yaw, -ir_angles[i] * DEG, 1e-12));
		CHECK(NEAR(hypot(sd->pos[0], sd->pos[1]), 0.035, 1e-12));
	}
	int ml = evo_bot_find_actuator(b, "MotL"),
	    mr = evo_bot_find_actuator(b, "MotR");
	CHECK(ml >= 0 && mr >= 0);
	if (ml < 0 || mr < 0) {
		evo_lua_destroy(l);
		evo_scene3d_destroy(sc);
		return;
	}
	CHECK(NEAR(b->actuator[ml].def.pos[1] - b->actuator[mr].def.pos[1],
		   0.053, 1e-12));
	CHECK(NEAR(b->actuator[ml].def.radius, 0.0205, 1e-12));
	CHECK_EQ_INT(b->n_actuators, 4); /* two wheels, two broadcasts */
	CHECK(NEAR(b->actuator[ml].def.max_rate, 0.128 / 0.0205, 1e-9));
	b->actuator[ml].command = b->actuator[mr].command = 1;
	double x2 = 0;
	for (int t = 0; t < 90; t++) { /* 3 s */
		if (t == 60)
			x2 = sc->bot[0].pos[0];
		evo_scene3d_sense(sc);
		evo_scene3d_step(sc);
	}
	double v = sc->bot[0].pos[0] - x2;
	CHECK(v > 0.128 * 0.9 && v < 0.128 * 1.1);
	if (!(v > 0.128 * 0.9 && v < 0.128 * 1.1))
		printf("  last second: %g m\n", v);
	evo_lua_destroy(l);
	evo_scene3d_destroy(sc);
}

/* The shipped swarm (minds/Phototaxis/README.md): the trained network
 * brings at least three of the five e-pucks onto the light's patch in each
 * of the DEMO task's first two episodes (5 and 3 when it was trained). */
TEST(phototaxis_swarm_gathers_at_the_light)
{
	static char out[1 << 14];
	int rc = cli_capture(out, sizeof out,
			     "%s run minds/Phototaxis/Tasks/"
			     "Phototaxis-DEMO.simbatch --headless --episodes 2",
			     cli_evo);
	CHECK_EQ_INT(rc, 0);
	int episodes = 0;
	for (const char *p = out; (p = strstr(p, "at_light ")) != NULL; p++) {
		int n = -1;
		sscanf(p, "at_light %d", &n);
		CHECK(n >= 3);
		episodes++;
	}
	CHECK_EQ_INT(episodes, 2);
	if (rc != 0 || episodes != 2)
		printf("  said: %s\n", out);
}

int main(void)
{
	if (cli_setup("epuck") || cli_sh("mkdir -p %s/Envs", cli_tmp))
		return 1;
	RUN(epuck_2d_has_the_published_ring_wheels_and_speed);
	RUN(epuck_3d_has_the_published_ring_wheels_and_speed);
	RUN(phototaxis_swarm_gathers_at_the_light);
	cli_cleanup();
	return test_summary();
}
