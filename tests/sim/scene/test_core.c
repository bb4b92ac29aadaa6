/* The scene model's core (sim/scene/core.h), through both scenes: the core
 * is each scene's first member and its fields read by their own names; a
 * reward is paid to its bot and the bot's team and the tick counted by
 * the one tick of sim/scene/tick.c, with figures worked out by hand; a
 * NextOnTimeout of 3 ticks ends a 2D episode at the 4th step (the
 * tutorial's rule) and a 3D one at the 3rd; a kind of the other
 * dimension is refused by its name, and a team that does not exist or a
 * NextOnCollisionWithTarget with nothing to touch with the same words in
 * both; a 3D scene counts its teams; a bot's sensors and
 * actuators are read, written and found by name through the one evo_bot
 * (scene/bot.h) the same way in 2D and 3D; a bot is refused with the
 * same words in both (one add), and its name, team, start, pose and
 * reward are the core's bot's in both. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

#define NEAR(a, b) (fabs((a) - (b)) < 1e-12)

/* A 2D scene with one bot "r" of team `team`, a constant sensor "c" of
 * 0.25 and a wheel "w". */
static evo_scene *scene_2d(int team)
{
	evo_scene *sc = evo_scene_create();
	evo_bot_def b = evo_default_bot_def();
	b.name = "r";
	b.team = team;
	evo_actuator_def a = evo_default_actuator_def(EVO_ACT_WHEEL);
	a.name = "w";
	evo_sensor_def s = evo_default_sensor_def(EVO_SENSE_CONSTANT);
	s.name = "c";
	s.value = 0.25;
	CHECK(evo_scene_add_bot(sc, &b) == 0 &&
	      evo_scene_add_sensor(sc, 0, &s) == 0 &&
	      evo_scene_add_actuator(sc, 0, &a) == 0);
	return sc;
}

/* The same in 3D, with a propeller "p", resting on the ground. */
static evo_scene3d *scene_3d(int team)
{
	evo_scene3d_def d = evo_default_scene3d_def();
	evo_scene3d *sc = evo_scene3d_create(&d);
	evo_bot_def b = evo_default_bot_def3d();
	b.name = "r";
	b.team = team;
	b.pos[2] = b.half[2];
	evo_sensor_def s = evo_default_sensor3d_def(EVO_SENSE_CONSTANT);
	s.name = "c";
	s.value = 0.25;
	evo_actuator_def a = evo_default_actuator_def(EVO_ACT_PROPELLER);
	a.name = "p";
	CHECK(evo_scene3d_add_bot(sc, &b) == 0 &&
	      evo_scene3d_add_sensor(sc, 0, &s) == 0 &&
	      evo_scene3d_add_actuator(sc, 0, &a) == 0);
	return sc;
}

static void core_is_first(void)
{
	evo_scene *s2 = scene_2d(-1);
	evo_scene3d *s3 = scene_3d(-1);
	CHECK((void *)&s2->core == (void *)s2);
	CHECK((void *)&s3->core == (void *)s3);
	CHECK(&s2->tick == &s2->core.tick);
	CHECK(&s3->episode_reward == &s3->core.episode_reward);
	CHECK_EQ_INT(s2->core.n_bots, 1);
	CHECK_EQ_INT(s3->core.n_bots, 1);
	evo_scene_destroy(s2);
	evo_scene3d_destroy(s3);
}

/* StepReward k = 0.5 paid to bot 0, of team 1, and NextOnTimeout of 3
 * ticks; steps until the control ends the episode. Returns the number of
 * steps, with the figures checked after each: step t pays 0.5, so after
 * it the tick is t and the episode, the bot and team 1 have 0.5 t. */
static int run_to_timeout(evo_scene_core *c)
{
	evo_reward_def r = evo_default_reward_def(EVO_RW_STEP);
	r.k = 0.5;
	evo_control_def t = evo_default_control_def(EVO_CF_NEXT_ON_TIMEOUT);
	t.ticks = 3;
	CHECK_EQ_INT(evo_core_add_reward(c, &r), 0);
	CHECK_EQ_INT(evo_core_add_control(c, &t), 0);
	CHECK_EQ_INT(c->dim->reset(c, 1, 2), 0);
	int steps = 0, end = 0;
	while (!end && steps < 10) {
		end = evo_core_step(c);
		steps++;
		CHECK_EQ_INT((int)c->tick, steps);
		CHECK(NEAR(c->step_reward, 0.5));
		CHECK(NEAR(c->episode_reward, 0.5 * steps));
		CHECK(NEAR(c->bot[0].reward, 0.5 * steps));
		CHECK(NEAR(c->team_reward[1], 0.5 * steps));
		CHECK(NEAR(c->team_reward[0], 0));
	}
	return steps;
}

static void rewards_and_timeout(void)
{
	evo_scene *s2 = scene_2d(1);
	evo_scene3d *s3 = scene_3d(1);
	CHECK_EQ_INT(run_to_timeout(&s2->core), 4);
	CHECK_EQ_INT(run_to_timeout(&s3->core), 3);
	evo_scene_destroy(s2);
	evo_scene3d_destroy(s3);
}

static void refused_alike(void)
{
	evo_scene *s2 = scene_2d(-1);
	evo_scene3d *s3 = scene_3d(-1);
	evo_reward_def r = evo_default_reward_def(EVO_RW_COLLECT);
	CHECK_EQ_INT(evo_scene3d_add_reward(s3, &r), -1);
	CHECK_CONTAINS(s3->err.msg, "reward Collect is 2D only");
	evo_control_def c =
	    evo_default_control_def(EVO_CF_NEXT_ON_COLLISION_WITH_TARGET);
	CHECK_EQ_INT(evo_scene_add_control(s2, &c), -1);
	CHECK_EQ_INT(evo_scene3d_add_control(s3, &c), -1);
	CHECK_CONTAINS(s2->err.msg, "control NextOnCollisionWithTarget needs "
				    "an element a bot can touch");
	CHECK_CONTAINS(s3->err.msg, "control NextOnCollisionWithTarget needs "
				    "an element a bot can touch");
	r = evo_default_reward_def(EVO_RW_STEP);
	r.scope = EVO_SCOPE_TEAM;
	r.team = 12;
	CHECK_EQ_INT(evo_scene_add_reward(s2, &r), -1);
	CHECK_EQ_INT(evo_scene3d_add_reward(s3, &r), -1);
	CHECK_CONTAINS(s2->err.msg, "reward StepReward: no team 12");
	CHECK_CONTAINS(s3->err.msg, "reward StepReward: no team 12");
	c = evo_default_control_def(EVO_CF_NEXT_ON_SENSOR_BELOW);
	c.sensor = 1;
	CHECK_EQ_INT(evo_scene_add_control(s2, &c), -1);
	CHECK_EQ_INT(evo_scene3d_add_control(s3, &c), -1);
	CHECK_CONTAINS(s2->err.msg,
		       "control NextOnSensorBelowThreshold: no sensor 1");
	CHECK_CONTAINS(s3->err.msg,
		       "control NextOnSensorBelowThreshold: no sensor 1");
	CHECK_EQ_INT(s2->n_rewards + s2->n_controls, 0);
	CHECK_EQ_INT(s3->n_rewards + s3->n_controls, 0);
	evo_scene_destroy(s2);
	evo_scene3d_destroy(s3);
}

static void teams_3d(void)
{
	evo_scene3d *s3 = scene_3d(0);
	evo_bot_def b = evo_default_bot_def3d();
	b.team = 2;
	b.pos[0] = 2;
	b.pos[2] = b.half[2];
	CHECK_EQ_INT(evo_scene3d_add_bot(s3, &b), 1);
	CHECK_EQ_INT(s3->n_teams, 3);
	evo_scene3d_destroy(s3);
}

/* The constant sensor reads 0.25 after the sensing; a command written
 * through evo_bot_write_actuators is the actuator's. */
static void bot_view(evo_scene_core *c, const char *actuator)
{
	CHECK_EQ_INT(c->dim->reset(c, 1, 2), 0);
	evo_core_sense(c);
	evo_bot *b = &c->bot[0];
	CHECK(strcmp(b->name, "r") == 0);
	CHECK_EQ_INT(b->team, -1);
	int s = evo_bot_find_sensor(b, "c");
	int a = evo_bot_find_actuator(b, actuator);
	CHECK_EQ_INT(s, 0);
	CHECK_EQ_INT(a, 0);
	CHECK_EQ_INT(evo_bot_find_sensor(b, "nothing"), -1);
	double value = 0, command = 0.9;
	evo_bot_read_sensors(b, &s, 1, &value);
	evo_bot_write_actuators(b, &a, 1, &command);
	CHECK(NEAR(value, 0.25));
	CHECK(NEAR(b->actuator[0].command, 0.9));
}

static void bots_alike(void)
{
	evo_scene *s2 = scene_2d(-1);
	evo_scene3d *s3 = scene_3d(-1);
	bot_view(&s2->core, "w");
	bot_view(&s3->core, "p");
	CHECK(NEAR(s2->bot[0].actuator[0].command, 0.9));
	CHECK(NEAR(s3->bot[0].actuator[0].command, 0.9));
	evo_scene_destroy(s2);
	evo_scene3d_destroy(s3);
}

/* A second bot "r", a bot of team 12 and a bot at no number are refused
 * with the same words in both worlds (scene/bot.h's one add), and the
 * scene keeps its one bot; a bot of no name is "" in 2D and "bot2" in
 * 3D. */
static void bots_refused_alike(void)
{
	evo_scene *s2 = scene_2d(-1);
	evo_scene3d *s3 = scene_3d(-1);
	evo_bot_def b2 = evo_default_bot_def(), b3 = evo_default_bot_def3d();
	b2.name = b3.name = "r";
	CHECK_EQ_INT(evo_scene_add_bot(s2, &b2), -1);
	CHECK_EQ_INT(evo_scene3d_add_bot(s3, &b3), -1);
	CHECK_CONTAINS(s2->err.msg, "bot 'r' is defined twice");
	CHECK_CONTAINS(s3->err.msg, "bot 'r' is defined twice");
	b2.name = b3.name = "t";
	b2.team = b3.team = 12;
	CHECK_EQ_INT(evo_scene_add_bot(s2, &b2), -1);
	CHECK_EQ_INT(evo_scene3d_add_bot(s3, &b3), -1);
	CHECK_CONTAINS(s2->err.msg, "bot: no team 12 (at most 12 teams)");
	CHECK_CONTAINS(s3->err.msg, "bot: no team 12 (at most 12 teams)");
	b2.team = b3.team = -1;
	b2.yaw = b3.yaw = NAN;
	CHECK_EQ_INT(evo_scene_add_bot(s2, &b2), -1);
	CHECK_EQ_INT(evo_scene3d_add_bot(s3, &b3), -1);
	CHECK_CONTAINS(s2->err.msg, "bot: its position or yaw is not a number");
	CHECK_CONTAINS(s3->err.msg, "bot: its position or yaw is not a number");
	CHECK_EQ_INT(s2->n_bots, 1);
	CHECK_EQ_INT(s3->n_bots, 1);
	b2.name = b3.name = NULL;
	b2.yaw = b3.yaw = 0;
	b3.pos[0] = 2;
	b3.pos[2] = b3.half[2];
	CHECK_EQ_INT(evo_scene_add_bot(s2, &b2), 1);
	CHECK_EQ_INT(evo_scene3d_add_bot(s3, &b3), 1);
	CHECK(strcmp(s2->bot[1].name, "") == 0);
	CHECK(strcmp(s3->bot[1].name, "bot2") == 0);
	evo_scene_destroy(s2);
	evo_scene3d_destroy(s3);
}

/* The one bot keeps its start and pose in both worlds: a 2D bot of team 1 added
 * at (3, 4) and placed at (5, 6) started at (3, 4) and is at (5, 6); a 3D bot
 * of team 2 at (1, 2) resting on the ground starts there and, with nothing
 * pushing it, is still there (within 1 mm) after a reset. */
static void bot_keeps_start_and_pose(void)
{
	evo_scene *s2 = evo_scene_create();
	evo_bot_def b2 = evo_default_bot_def();
	b2.name = "a";
	b2.team = 1;
	b2.x = 3;
	b2.y = 4;
	CHECK_EQ_INT(evo_scene_add_bot(s2, &b2), 0);
	evo_scene_reset(s2, 1, 1);
	evo_scene_place_bot(s2, 0, 5, 6, 0);
	const evo_bot *v = &s2->core.bot[0];
	CHECK(strcmp(v->name, "a") == 0);
	CHECK_EQ_INT(v->team, 1);
	CHECK(NEAR(v->start[0], 3) && NEAR(v->start[1], 4));
	CHECK(fabs(v->pos[0] - 5) < 1e-6 && fabs(v->pos[1] - 6) < 1e-6);
	evo_scene_destroy(s2);

	evo_scene3d_def d = evo_default_scene3d_def();
	evo_scene3d *s3 = evo_scene3d_create(&d);
	evo_bot_def b3 = evo_default_bot_def3d();
	b3.name = "b";
	b3.team = 2;
	b3.pos[0] = 1;
	b3.pos[1] = 2;
	b3.pos[2] = b3.half[2];
	CHECK_EQ_INT(evo_scene3d_add_bot(s3, &b3), 0);
	CHECK_EQ_INT(evo_scene3d_reset(s3, 1, 1), 0);
	v = &s3->core.bot[0];
	CHECK(strcmp(v->name, "b") == 0);
	CHECK_EQ_INT(v->team, 2);
	CHECK(NEAR(v->start[0], 1) && NEAR(v->start[1], 2));
	CHECK(fabs(v->pos[0] - 1) < 1e-3 && fabs(v->pos[1] - 2) < 1e-3);
	evo_scene3d_destroy(s3);
}

int main(void)
{
	RUN(core_is_first);
	RUN(rewards_and_timeout);
	RUN(refused_alike);
	RUN(teams_3d);
	RUN(bots_alike);
	RUN(bots_refused_alike);
	RUN(bot_keeps_start_and_pose);
	return test_summary();
}
