/* The mazes' pieces (docs/world.md, "The mazes"): walls of no thickness,
 * radars, bumpers, speed wheels and drives, the rewards Distance,
 * FinalDistance and Effort, the control NextOnTargetReached, each against
 * values worked out by hand; then the built-in maze environments, whose
 * sensors at the start read what the published geometry gives; and a NEAT
 * task on a maze that runs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "lua/lua_evo.h"
#include "support/cli.h"
#include "support/scenes.h"
#include "viewer/png.h"
#include "viewer/viewer.h"
#include "world2d/scene.h"
#include "world2d/sensors.h"

#define NEAR(a, b, tol) (fabs((a) - (b)) <= (tol))
#define DEG		(M_PI / 180.0)

static double value(evo_scene *sc, int sensor)
{
	return sc->bot[0].sensor[sensor].value;
}

/* A rangefinder: one ray from the bot's centre, range 10. */
static int add_finder(evo_scene *sc, double angle)
{
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_PROXIMITY);
	d.angle = angle;
	d.range = 10;
	d.arc = 0;
	d.rays = 1;
	d.deadzone = 0;
	return evo_scene_add_sensor(sc, 0, &d);
}

/* A bot of radius 1 at the origin facing +x with no damping, so that
 * speed wheels and drives move it by exactly what they set. */
static evo_scene *scene_with_free_bot(void)
{
	evo_scene *sc = evo_scene_create();
	evo_bot_def b = evo_default_bot_def();
	b.name = "bot";
	b.body.linear_damping = b.body.angular_damping = 0;
	evo_scene_add_bot(sc, &b);
	return sc;
}

static int add_speed_wheel(evo_scene *sc, const char *name, double y)
{
	evo_actuator_def d = evo_default_actuator_def(EVO_ACT_SPEED_WHEEL);
	d.name = name;
	d.y = y;
	d.max_speed = 3;
	return evo_scene_add_actuator(sc, 0, &d);
}

/* ---- walls ------------------------------------------------------------ */

TEST(a_ray_reads_a_wall_and_misses_past_its_end)
{
	/* The wall x = 5, y in [-3, 3]. Ahead: 5 of 10. At 30 degrees the ray
	 * meets x = 5 at y = 5 tan 30 = 2.887, on the wall, 5 / cos 30 =
	 * 5.7735 away. At 45 degrees it would meet it at y = 5, past its
	 * end. */
	evo_scene *sc = scene_with_bot(0, 0, 0);
	CHECK(evo_scene_add_wall(sc, 5, -3, 5, 3) >= 0);
	int ahead = add_finder(sc, 0);
	int at30 = add_finder(sc, 30 * DEG);
	int at45 = add_finder(sc, 45 * DEG);
	evo_scene_reset(sc, 1, 1);
	evo_scene_sense(sc);
	CHECK(NEAR(value(sc, ahead), 0.5, 1e-6));
	CHECK(NEAR(value(sc, at30), 0.57735, 1e-5));
	CHECK(value(sc, at45) == 1.0);
	CHECK_EQ_INT(sc->obstacle[0].shape, EVO_SHAPE_SEGMENT);
	evo_scene_destroy(sc);
}

TEST(a_wall_stops_a_bot)
{
	/* Driving at 3 m/s for 3 s towards the wall x = 5 from 0: a body of
	 * radius 1 stops with its centre about 4 from the origin (Box2D's
	 * contact skin: within a centimetre), never through. */
	evo_scene *sc = scene_with_free_bot();
	evo_scene_add_wall(sc, 5, -3, 5, 3);
	int l = add_speed_wheel(sc, "L", -1), r = add_speed_wheel(sc, "R", 1);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 90; t++) {
		sc->bot[0].actuator[l].command = 1;
		sc->bot[0].actuator[r].command = 1;
		evo_scene_step(sc);
	}
	CHECK(NEAR(sc->bot[0].x, 4.0, 0.02));
	CHECK(sc->bot[0].touching > 0);
	CHECK(evo_scene_add_wall(sc, 1, 1, 1, 1) < 0); /* too late, and empty */
	evo_scene_destroy(sc);
}

/* A bot whose collision is "undo" (MazeBot's), at (x, y) facing `angle`,
 * with a SPEED drive of 3 m/s at full command (0.1 m a step) and a TURN
 * drive of 0.3 rad/s at full command (0.01 rad a step). */
static evo_scene *scene_with_undo_bot(double x, double y, double angle,
				      int *speed, int *turn)
{
	evo_scene *sc = evo_scene_create();
	evo_bot_def b = evo_default_bot_def();
	b.name = "bot";
	b.x = x;
	b.y = y;
	b.yaw = angle;
	b.body.kinematic = 1;
	evo_scene_add_bot(sc, &b);
	evo_actuator_def d = evo_default_actuator_def(EVO_ACT_DRIVE);
	d.name = "SPEED";
	d.max_speed = 3;
	*speed = evo_scene_add_actuator(sc, 0, &d);
	d.name = "TURN";
	d.turn = 1;
	d.max_speed = 0.3;
	*turn = evo_scene_add_actuator(sc, 0, &d);
	return sc;
}

/* Full speed ahead for `steps` steps, turning (turn command 1) or not
 * (0.5, neutral). */
static void drive_undo_bot(evo_scene *sc, int speed, int turn, double c,
			   int steps)
{
	for (int t = 0; t < steps; t++) {
		sc->bot[0].actuator[speed].command = 1;
		sc->bot[0].actuator[turn].command = c;
		evo_scene_step(sc);
	}
}

TEST(an_undo_bot_driven_into_a_wall_stays_where_it_was_and_turns)
{
	/* From x = 0.05 towards the wall x = 5 at 0.1 a step: centres 0.05,
	 * 0.15, ..., 3.95; the next, 4.05, would be 0.95 from the wall, less
	 * than the radius 1, so the bot stays at 3.95 (Lehman's simulator
	 * drops the move). Then turning at 0.3 rad/s (0.01 a step) while it
	 * pushes: a step along heading h moves it to 3.95 + 0.1 cos h, closer
	 * than 1 to the wall while cos h > 0.5; headings 0, 0.01, ..., 1.04
	 * (cos 1.04 = 0.5062) are refused, so after 105 steps it is still at
	 * 3.95, turned to 1.05; the 106th step, along 1.05 (cos = 0.4976),
	 * is taken: (3.95 + 0.04976, 0.1 sin 1.05 = 0.08674). */
	int speed, turn;
	evo_scene *sc = scene_with_undo_bot(0.05, 0, 0, &speed, &turn);
	CHECK(evo_scene_add_wall(sc, 5, -3, 5, 3) >= 0);
	evo_scene_reset(sc, 1, 1);
	drive_undo_bot(sc, speed, turn, 0.5, 60);
	CHECK(NEAR(sc->bot[0].x, 3.95, 1e-4));
	CHECK(NEAR(sc->bot[0].y, 0.0, 1e-6));
	CHECK(sc->bot[0].touching > 0);
	CHECK_EQ_INT(sc->bot[0].collisions, 60 - 39);
	evo_scene_destroy(sc);

	sc = scene_with_undo_bot(3.95, 0, 0, &speed, &turn);
	CHECK(evo_scene_add_wall(sc, 5, -3, 5, 3) >= 0);
	evo_scene_reset(sc, 1, 1);
	drive_undo_bot(sc, speed, turn, 1, 105);
	CHECK(NEAR(sc->bot[0].x, 3.95, 1e-4));
	CHECK(NEAR(sc->bot[0].y, 0.0, 1e-6));
	CHECK(NEAR(sc->bot[0].angle, 1.05, 1e-4));
	drive_undo_bot(sc, speed, turn, 1, 1);
	CHECK(NEAR(sc->bot[0].x, 3.95 + 0.1 * cos(1.05), 1e-4));
	CHECK(NEAR(sc->bot[0].y, 0.1 * sin(1.05), 1e-4));
	CHECK_EQ_INT(sc->bot[0].touching, 0);
	evo_scene_destroy(sc);
}

TEST(an_undo_bot_does_not_slide_along_a_wall)
{
	/* From (0, 0.02) at 30 degrees towards the wall y = 2: each step
	 * moves (0.1 cos 30, 0.1 sin 30) = (0.0866, 0.05); after 19 steps
	 * the centre is at (1.6454, 0.97), and the next would be 0.98 from
	 * the wall. It stays there however long it pushes: no sliding along
	 * the wall, as a frictionless bot would, nor sticking short of it. */
	int speed, turn;
	evo_scene *sc = scene_with_undo_bot(0, 0.02, 30 * DEG, &speed, &turn);
	CHECK(evo_scene_add_wall(sc, -10, 2, 10, 2) >= 0);
	evo_scene_reset(sc, 1, 1);
	drive_undo_bot(sc, speed, turn, 0.5, 19);
	CHECK(NEAR(sc->bot[0].x, 19 * 0.1 * cos(30 * DEG), 1e-4));
	CHECK(NEAR(sc->bot[0].y, 0.97, 1e-4));
	CHECK_EQ_INT(sc->bot[0].touching, 0);
	drive_undo_bot(sc, speed, turn, 0.5, 60);
	CHECK(NEAR(sc->bot[0].x, 19 * 0.1 * cos(30 * DEG), 1e-4));
	CHECK(NEAR(sc->bot[0].y, 0.97, 1e-4));
	CHECK(sc->bot[0].touching > 0);
	evo_scene_destroy(sc);
}

TEST(a_wall_of_no_length_is_refused)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	CHECK(evo_scene_add_wall(sc, 1, 1, 1.001, 1) < 0);
	CHECK(strstr(sc->err.msg, "closer than 5 mm") != NULL);
	CHECK(evo_scene_add_wall(sc, NAN, 1, 2, 1) < 0);
	evo_scene_destroy(sc);
}

/* ---- radar ------------------------------------------------------------ */

static int add_radar(evo_scene *sc, double angle, int target)
{
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_RADAR);
	d.angle = angle;
	d.arc = 45 * DEG;
	d.target = target;
	return evo_scene_add_sensor(sc, 0, &d);
}

TEST(radars_cut_the_bearing_into_four_slices)
{
	/* Slices [-45, 45), [45, 135), [135, 225), [-135, -45) of the
	 * bearing, + to the bot's right (+y). */
	evo_scene *sc = scene_with_bot(0, 0, 0);
	int goal = scene_add_element(sc, EVO_PIECE_ZONE, 3, 0, 0.5);
	int s[4];
	for (int k = 0; k < 4; k++)
		s[k] = add_radar(sc, (k == 3 ? -90 : 90 * k) * DEG, goal);
	evo_scene_reset(sc, 1, 1);
	const struct {
		double x, y;
		int slice;
	} cases[] = {
	    {3, 0, 0},	/* ahead */
	    {0, 3, 1},	/* 90: right */
	    {3, 3, 1},	/* 45: the right slice's first edge, not the front's */
	    {-3, 0, 2}, /* behind */
	    {3, -3, 0}, /* -45: the front slice's first edge */
	    {0, -3, 3}, /* -90: left */
	};
	for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
		evo_scene_place_element(sc, goal, cases[c].x, cases[c].y);
		evo_scene_sense(sc);
		for (int k = 0; k < 4; k++)
			CHECK(value(sc, s[k]) ==
			      (k == cases[c].slice ? EVO_TRUE : EVO_FALSE));
	}
	evo_scene_destroy(sc);
}

/* ---- bumper ----------------------------------------------------------- */

static int add_bumper(evo_scene *sc, double angle)
{
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_BUMPER);
	d.angle = angle;
	d.arc = M_PI / 4;
	return evo_scene_add_sensor(sc, 0, &d);
}

TEST(bumpers_cover_the_front_quarters)
{
	/* Kheperax's bumpers: left over (-90, 0], right over [0, 90) degrees
	 * from the heading, within reach (1.05) of the centre. */
	const struct {
		double x1, y1, x2, y2;
		double left, right;
	} cases[] = {
	    /* straight ahead, 1.02 away: both */
	    {1.02, -2, 1.02, 2, EVO_TRUE, EVO_TRUE},
	    /* a wall at 45 degrees right, nearest point 1.03 away */
	    {1.03 * M_SQRT2, 0, 0, 1.03 * M_SQRT2, EVO_FALSE, EVO_TRUE},
	    /* at -45: left only */
	    {1.03 * M_SQRT2, 0, 0, -1.03 * M_SQRT2, EVO_TRUE, EVO_FALSE},
	    /* exactly at +90 (beside the bot): neither, as in Kheperax */
	    {-2, 1.02, 2, 1.02, EVO_FALSE, EVO_FALSE},
	    /* ahead but 1.2 away: out of reach */
	    {1.2, -2, 1.2, 2, EVO_FALSE, EVO_FALSE},
	};
	for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
		evo_scene *sc = scene_with_bot(0, 0, 0);
		evo_scene_add_wall(sc, cases[c].x1, cases[c].y1, cases[c].x2,
				   cases[c].y2);
		int left = add_bumper(sc, -M_PI / 4);
		int right = add_bumper(sc, M_PI / 4);
		evo_scene_reset(sc, 1, 1);
		evo_scene_sense(sc);
		CHECK(value(sc, left) == cases[c].left);
		CHECK(value(sc, right) == cases[c].right);
		/* one sensor on its own reads the same */
		CHECK(evo_sensor_sample(sc, 0, right) == cases[c].right);
		evo_scene_destroy(sc);
	}
}

/* ---- speed wheels and drives ------------------------------------------ */

TEST(speed_wheels_set_speed_and_turn)
{
	/* Both at full: 3 m/s ahead, 3 m in 30 steps of 1/30 s. Left full,
	 * right full back: no speed, turn (3 - -3) / 2 = 3 rad/s to the
	 * right, 1 rad in 10 steps. */
	evo_scene *sc = scene_with_free_bot();
	int l = add_speed_wheel(sc, "L", -1), r = add_speed_wheel(sc, "R", 1);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 30; t++) {
		sc->bot[0].actuator[l].command = 1;
		sc->bot[0].actuator[r].command = 1;
		evo_scene_step(sc);
	}
	CHECK(NEAR(sc->bot[0].x, 3.0, 1e-4));
	CHECK(NEAR(sc->bot[0].y, 0.0, 1e-6));
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 10; t++) {
		sc->bot[0].actuator[l].command = 1;
		sc->bot[0].actuator[r].command = 0;
		evo_scene_step(sc);
	}
	CHECK(NEAR(sc->bot[0].angle, 1.0, 1e-4));
	CHECK(NEAR(sc->bot[0].x, 0.0, 1e-5));
	evo_scene_destroy(sc);
}

TEST(an_accelerating_drive_adds_up_to_its_top_speed)
{
	/* accel 0.5 at full command: speeds 0.5, 1, ..., 3 (the top) over six
	 * steps, 10.5 / 30 = 0.35 m; then 3 m/s: 0.1 m a step. */
	evo_scene *sc = scene_with_free_bot();
	evo_actuator_def d = evo_default_actuator_def(EVO_ACT_DRIVE);
	d.name = "SPEED";
	d.max_speed = 3;
	d.accel = 0.5;
	int a = evo_scene_add_actuator(sc, 0, &d);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 6; t++) {
		sc->bot[0].actuator[a].command = 1;
		evo_scene_step(sc);
	}
	CHECK(NEAR(sc->bot[0].x, 0.35, 1e-4));
	sc->bot[0].actuator[a].command = 1;
	evo_scene_step(sc);
	CHECK(NEAR(sc->bot[0].x, 0.45, 1e-4));
	/* a reset stops it */
	evo_scene_reset(sc, 1, 1);
	CHECK(sc->bot[0].actuator[a].speed == 0);
	d.max_speed = -1;
	d.name = "BAD";
	CHECK(evo_scene_add_actuator(sc, 0, &d) < 0);
	CHECK(strstr(sc->err.msg, "max_speed must be positive") != NULL);
	evo_scene_destroy(sc);
}

/* ---- rewards and control ---------------------------------------------- */

static int add_reward(evo_scene *sc, evo_reward_kind kind, double k, double k2,
		      int target)
{
	evo_reward_def d = evo_default_reward_def(kind);
	d.k = k;
	d.k2 = k2;
	d.target = target;
	return evo_scene_add_reward(sc, &d);
}

TEST(maze_rewards_pay_what_the_papers_do)
{
	/* The goal at (10, 0); the bot drives at 3 m/s (0.1 a step) with
	 * commands 1 and 0.75, (2c - 1)^2 = 1 + 0.25. */
	evo_scene *sc = scene_with_free_bot();
	int goal = scene_add_element(sc, EVO_PIECE_ZONE, 10, 0, 0.5);
	int l = add_speed_wheel(sc, "L", -1), r = add_speed_wheel(sc, "R", 1);
	int dist = add_reward(sc, EVO_RW_DISTANCE, -1, 0, goal);
	int fin = add_reward(sc, EVO_RW_FINAL_DISTANCE, -1, 300, goal);
	int eff = add_reward(sc, EVO_RW_EFFORT, -0.025 * 0.025, 0, -1);
	evo_control_def c =
	    evo_default_control_def(EVO_CF_NEXT_ON_TARGET_REACHED);
	c.target = goal;
	c.threshold = 0.55;
	evo_scene_add_control(sc, &c);
	evo_scene_reset(sc, 1, 1);
	sc->bot[0].actuator[l].command = 1;
	sc->bot[0].actuator[r].command = 0.75;
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	double x = sc->bot[0].x;
	CHECK(NEAR(sc->reward[dist].total, -hypot(10 - x, sc->bot[0].y), 1e-9));
	CHECK(NEAR(sc->reward[eff].total, -0.000625 * 1.25, 1e-12));
	/* straight on: the episode ends when the centre is within 0.55 of
	 * the goal, at 9.5 after 95 steps */
	evo_scene_reset(sc, 1, 1);
	int steps = 0, next = 0;
	while (!next && steps < 200) {
		sc->bot[0].actuator[l].command = 1;
		sc->bot[0].actuator[r].command = 1;
		next = evo_scene_step(sc);
		steps++;
	}
	CHECK_EQ_INT(steps, 95);
	double d = hypot(10 - sc->bot[0].x, sc->bot[0].y);
	CHECK(NEAR(d, 0.5, 1e-4));
	/* FinalDistance summed to 300 - the distance at the end */
	CHECK(NEAR(sc->reward[fin].total, 300 - d, 1e-9));
	CHECK(NEAR(sc->reward[eff].total, -0.000625 * 2 * 95, 1e-12));
	evo_scene_destroy(sc);
}

/* ---- the built-in environments ------------------------------------------ */

/* Environment env of lua/envs with bot model `model`, reset and sensed. */
static evo_lua *load_env(const char *env, const char *model, evo_scene **sc)
{
	evo_err err = {{0}};
	*sc = evo_scene_create();
	evo_lua_def ld = {.scene = *sc, .lua_dir = "lua", .botmodel = model};
	evo_lua *l = evo_lua_create(&ld, &err);
	if (l && (evo_lua_init_env(l, env, &err) ||
		  (evo_scene_reset(*sc, 1, 1), evo_lua_reset(l, 1, &err)))) {
		evo_lua_destroy(l);
		l = NULL;
	}
	if (!l) {
		printf("  %s: %s\n", env, err.msg);
		evo_scene_destroy(*sc);
		*sc = NULL;
		return NULL;
	}
	evo_scene_sense(*sc);
	return l;
}

static double named(evo_scene *sc, const char *name)
{
	int k = evo_bot_find_sensor(&sc->bot[0], name);
	return k >= 0 ? sc->bot[0].sensor[k].value : -1;
}

TEST(kheperax_lasers_at_the_start_read_the_published_values)
{
	/* Kheperax's anchors: [0.14142, 0.2, 0.2] of range 0.2; evo reads
	 * distance / range. 13 walls; bumpers off. */
	evo_scene *sc;
	evo_lua *l = load_env("EXP_Kheperax", "KheperaxBot", &sc);
	CHECK(l != NULL);
	if (!l)
		return;
	CHECK_EQ_INT(sc->n_obstacles, 13);
	CHECK(NEAR(named(sc, "LASER_LEFT"), 0.14142 / 0.2, 1e-4));
	CHECK(named(sc, "LASER_FRONT") == 1.0);
	CHECK(named(sc, "LASER_RIGHT") == 1.0);
	CHECK(named(sc, "BUMP_LEFT") == EVO_FALSE);
	CHECK(named(sc, "BUMP_RIGHT") == EVO_FALSE);
	CHECK(NEAR(sc->bot[0].x, 10.0, 1e-5) && NEAR(sc->bot[0].y, 10.0, 1e-5));
	evo_lua_destroy(l);
	evo_scene_destroy(sc);
}

TEST(hard_maze_sensors_at_the_start_read_the_published_geometry)
{
	/* From (36, 184) facing +x: ahead, the wall (77, 201)-(108, 164) at
	 * y = 184 is at x = 77 + 31 * 17/37 = 91.243, 55.243 away; behind, the
	 * wall (4, 49)-(7, 202) at x = 4 + 3 * 135/153 = 6.647, 29.353 away
	 * (range 100). The goal (31, 20) lies at -91.7 degrees: the left
	 * radar. */
	evo_scene *sc;
	evo_lua *l = load_env("EXP_HardMaze", "MazeBot", &sc);
	CHECK(l != NULL);
	if (!l)
		return;
	CHECK_EQ_INT(sc->n_obstacles, 13);
	CHECK_EQ_INT(sc->bot[0].def.body.kinematic, 1); /* collision "undo" */
	CHECK(NEAR(named(sc, "RF_FRONT"), 0.55243, 1e-4));
	CHECK(NEAR(named(sc, "RF_BACK"), 0.29353, 1e-4));
	CHECK(named(sc, "RAD_LEFT") == EVO_TRUE);
	CHECK(named(sc, "RAD_FRONT") == EVO_FALSE);
	CHECK(named(sc, "RAD_RIGHT") == EVO_FALSE);
	CHECK(named(sc, "RAD_BACK") == EVO_FALSE);
	evo_lua_destroy(l);
	evo_scene_destroy(sc);
}

/* ---- a NEAT task on a maze ---------------------------------------------- */

TEST(a_neat_task_on_kheperax_runs)
{
	if (cli_setup("maze"))
		return;
	CHECK_EQ_INT(cli_sh("cp -r minds/Kheperax %s/ && sed -i "
			    "'s/NUMGEN:50/NUMGEN:2/' "
			    "%s/Kheperax/Tasks/Kheperax-NEAT.simbatch",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_sh("%s run %s/Kheperax/Tasks/Kheperax-NEAT.simbatch "
			    "--seed 1 --threads 2 --run %s/run > %s/out 2>&1",
			    cli_evo, cli_tmp, cli_tmp, cli_tmp),
		     0);
	char *log = cli_read("%s/run/log.csv", cli_tmp);
	CHECK(log != NULL);
	if (log) {
		/* a header and two generations of 150 */
		CHECK_EQ_INT(cli_count_lines(log, ""), 3);
		CHECK(strstr(log, ",150,") != NULL);
	}
	free(log);
	cli_cleanup();
}

/* The hard maze's NEAT run gives the same log with one worker thread and
 * with two: which worker ran which episode, and what that worker's world
 * ran before, changes nothing (the world is made again at each reset in
 * a scene with walls). */
TEST(a_maze_run_is_the_same_on_one_thread_and_two)
{
	if (cli_setup("maze-threads"))
		return;
	CHECK_EQ_INT(
	    cli_sh("cp -r minds/Maze %s/ && sed -i "
		   "'s/NUMGEN:100/NUMGEN:3/; s/POPSIZE:250/POPSIZE:60/' "
		   "%s/Maze/Tasks/HardMaze-NEAT.simbatch",
		   cli_tmp, cli_tmp),
	    0);
	char *log[2] = {NULL, NULL};
	for (int t = 1; t <= 2; t++) {
		CHECK_EQ_INT(
		    cli_sh("%s run %s/Maze/Tasks/HardMaze-NEAT.simbatch "
			   "--seed 3 --threads %d --run %s/run%d > "
			   "%s/out%d 2>&1",
			   cli_evo, cli_tmp, t, cli_tmp, t, cli_tmp, t),
		    0);
		char dir[256];
		snprintf(dir, sizeof dir, "%s/run%d", cli_tmp, t);
		log[t - 1] = cli_fitness_log(dir);
	}
	CHECK(log[0] && log[1] && strcmp(log[0], log[1]) == 0);
	CHECK(log[0] && cli_count_lines(log[0], "") == 4);
	free(log[0]);
	free(log[1]);
	cli_cleanup();
}

/* A champion read back from its .net scores in the viewer what it scored
 * in training, to the printed digit: the file holds the Q16 weights evo
 * ran (lua/learn/netfile.lua). On the medium maze, seed 1, 10
 * generations, six decimals gave 226.035969 where training had
 * 226.038522. The maze has no randomness, so one DEMOSIM episode is the
 * training episode. */
TEST(a_champion_read_back_scores_what_it_scored_in_training)
{
	if (cli_setup("maze-replay"))
		return;
	CHECK_EQ_INT(cli_sh("cp -r minds/Maze %s/ && %s run "
			    "%s/Maze/Tasks/MediumMaze-NEAT.simbatch --seed 1 "
			    "--generations 10 --no-save --run %s/run > "
			    "%s/train 2>&1",
			    cli_tmp, cli_evo, cli_tmp, cli_tmp, cli_tmp),
		     0);
	char *log = cli_read("%s/run/log.csv", cli_tmp);
	const char *last = log ? strstr(log, "\n9,") : NULL;
	double best = 0;
	/* generation,best,mean,best_ever,... */
	CHECK(last && sscanf(last + 1, "9,%*[^,],%*[^,],%lf", &best) == 1);
	char out[4096], want[64];
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/Maze/Tasks/MediumMaze-DEMO.simbatch "
				 "--headless --episodes 1 --net "
				 "Maze=%s/run/champion.net",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	snprintf(want, sizeof want, "episode 1: reward %.6f over", best);
	CHECK_CONTAINS(out, want);
	free(log);
	cli_cleanup();
}

/* Kheperax's target task started on the target: every episode ends
 * within 0.05 of it after one step (a step moves at most 0.025), so every
 * network solves it, log.csv counts them all, and the run stops at its
 * first generation. From the standard start, the untrained (neutral)
 * network stays 0.75 away: not solved. */
TEST(a_solved_episode_is_counted)
{
	if (cli_setup("maze-solved"))
		return;
	const char *env = "local maze = require \"lib.maze\"\n"
			  "local m = {}\n"
			  "for k, v in pairs(maze.kheperax) do m[k] = v end\n"
			  "m.start = { 0.15, 0.9 }\n"
			  "return maze.env(m, { ticks = 250, reach = 0.05, "
			  "stop_at_goal = true,\n"
			  "\trewards = function(scene, bot, goal)\n"
			  "\t\tscene:reward(\"Distance\", { bot = bot, target "
			  "= goal, k = -0.015 })\n"
			  "\tend })\n";
	CHECK_EQ_INT(cli_sh("cp -r minds/Kheperax %s/ && mkdir -p "
			    "%s/Kheperax/Envs",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_write(env, "%s/Kheperax/Envs/Near.lua", cli_tmp), 0);
	CHECK_EQ_INT(cli_write("TYPE:LEARNSIM\nBOTMODEL:KheperaxBot\n"
			       "MASTERSKILL:Kheperax\nLEARNINGSKILL:Kheperax\n"
			       "ENV:Near\nLEARNINGMETHOD:NEAT\nPOPSIZE:20\n"
			       "NUMGEN:5\nEVALREP:1\nTICKLIM:250\n",
			       "%s/Kheperax/Tasks/Near.simbatch", cli_tmp),
		     0);
	CHECK_EQ_INT(cli_sh("%s run %s/Kheperax/Tasks/Near.simbatch --seed 1 "
			    "--threads 1 --run %s/run > %s/out 2>&1",
			    cli_evo, cli_tmp, cli_tmp, cli_tmp),
		     0);
	char *log = cli_read("%s/run/log.csv", cli_tmp);
	CHECK(log != NULL);
	if (log) {
		/* the header and generation 0, whose 20 networks all solved */
		CHECK_EQ_INT(cli_count_lines(log, ""), 2);
		CHECK_EQ_INT(cli_count_lines(log, "0,"), 1);
		CHECK(strstr(log, ",20,20,") != NULL);
	}
	free(log);
	char out[4096];
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run minds/Kheperax/Tasks/"
				 "KheperaxTarget-DEMO.simbatch --headless "
				 "--net Kheperax=zero",
				 cli_evo),
		     0);
	CHECK(strstr(out, "reward -187.500000 over 250 ticks") != NULL);
	CHECK(strstr(out, "behaviour (0.150000, 0.150000), not solved") !=
	      NULL);
	cli_cleanup();
}

/* Pixels of colour rgb in a screenshot, or -1 when it cannot be read. */
static long count_colour(const char *path, uint32_t rgb)
{
	evo_png_image img;
	evo_err err;
	if (evo_png_read(path, &img, &err)) {
		printf("  %s\n", err.msg);
		return -1;
	}
	long n = 0;
	for (long i = 0; i < (long)img.w * img.h; i++) {
		const uint8_t *p = img.pixels + i * img.channels;
		n += ((uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2]) == rgb;
	}
	evo_png_image_free(&img);
	return n;
}

/* The shipped Maze skill in the medium maze, screenshot after 400 steps:
 * with --trail its path is drawn (a long line of the trail's colour, from
 * the start, 30 m off, to near the goal), without it none; the walls are
 * drawn either way. */
TEST(a_screenshot_shows_the_path_with_trail)
{
	if (cli_setup("maze-trail"))
		return;
	for (int trail = 0; trail <= 1; trail++) {
		CHECK_EQ_INT(cli_sh("%s run minds/Maze/Tasks/MediumMaze-DEMO."
				    "simbatch --ticks 400 %s --screenshot "
				    "%s/shot%d.png > /dev/null 2>&1",
				    cli_evo, trail ? "--trail" : "", cli_tmp,
				    trail),
			     0);
		char path[256];
		snprintf(path, sizeof path, "%s/shot%d.png", cli_tmp, trail);
		long n = count_colour(path, EVO_VIEW_TRAIL);
		if (trail)
			CHECK(n > 600);
		else
			CHECK(n == 0);
		CHECK(count_colour(path, EVO_VIEW_WALL) > 1000);
	}
	cli_cleanup();
}

int main(void)
{
	RUN(a_ray_reads_a_wall_and_misses_past_its_end);
	RUN(a_wall_stops_a_bot);
	RUN(an_undo_bot_driven_into_a_wall_stays_where_it_was_and_turns);
	RUN(an_undo_bot_does_not_slide_along_a_wall);
	RUN(a_wall_of_no_length_is_refused);
	RUN(radars_cut_the_bearing_into_four_slices);
	RUN(bumpers_cover_the_front_quarters);
	RUN(speed_wheels_set_speed_and_turn);
	RUN(an_accelerating_drive_adds_up_to_its_top_speed);
	RUN(maze_rewards_pay_what_the_papers_do);
	RUN(kheperax_lasers_at_the_start_read_the_published_values);
	RUN(hard_maze_sensors_at_the_start_read_the_published_geometry);
	RUN(a_neat_task_on_kheperax_runs);
	RUN(a_solved_episode_is_counted);
	RUN(a_maze_run_is_the_same_on_one_thread_and_two);
	RUN(a_screenshot_shows_the_path_with_trail);
	RUN(a_champion_read_back_scores_what_it_scored_in_training);
	return test_summary();
}
