/* Teams in the 2D world (sim/world2d, docs/teams.md): bots of a team carry
 * its collision category; rewards pay a bot, a team or the scene; Gather
 * takes objects a bot touches; trackers find the nearest opponent or
 * teammate through the broad phase; proximity rays see teammates or
 * opponents as the bot model says. */
#include <math.h>
#include <stdio.h>

#include "base/rng.h"
#include "harness.h"
#include "world2d/query.h"
#include "world2d/rewards.h"
#include "world2d/scene.h"
#include "world2d/sensors.h"

#define NEAR(a, b) (fabs((a) - (b)) <= 1e-9)

static int add_bot(evo_scene *sc, int team, double x, double y, double angle)
{
	evo_bot_def d = evo_default_bot_def();
	d.team = team;
	d.x = x;
	d.y = y;
	d.yaw = angle;
	int i = evo_scene_add_bot(sc, &d);
	CHECK(i >= 0);
	return i;
}

static int add_reward(evo_scene *sc, evo_reward_kind kind, evo_scope scope,
		      int bot, int team, double k)
{
	evo_reward_def d = evo_default_reward_def(kind);
	d.scope = scope;
	d.bot = bot;
	d.team = team;
	d.k = k;
	int i = evo_scene_add_reward(sc, &d);
	CHECK(i >= 0);
	return i;
}

TEST(bots_of_a_team_are_numbered_and_named_by_body)
{
	evo_scene *sc = evo_scene_create();
	int a = add_bot(sc, -1, 0, 0, 0);
	int b = add_bot(sc, 2, 5, 0, 0);
	CHECK_EQ_INT(sc->bot[a].team, -1);
	CHECK_EQ_INT(sc->bot[b].team, 2);
	CHECK_EQ_INT(sc->n_teams, 3);
	CHECK_EQ_INT(evo_scene_bot_of_body(sc, sc->bot[b].body.index), b);
	CHECK_EQ_INT(evo_scene_object_of_body(sc, sc->bot[b].body.index), -1);
	evo_element_def o =
	    evo_default_element_def(EVO_PIECE_OBJECT, EVO_DIM_2D);
	o.x = 10;
	int e = evo_scene_add_element(sc, &o);
	CHECK_EQ_INT(evo_scene_object_of_body(sc, sc->element[e].body.index),
		     e);
	CHECK_EQ_INT(evo_scene_bot_of_body(sc, sc->element[e].body.index), -1);
	/* a team out of range */
	evo_bot_def d = evo_default_bot_def();
	d.team = EVO_SCENE_MAX_TEAMS;
	CHECK_EQ_INT(evo_scene_add_bot(sc, &d), -1);
	CHECK_CONTAINS(sc->err.msg, "no team 12");
	evo_scene_destroy(sc);
}

/* Each step: 1 to bot 0 (team 0), 2 to bot 1 (team 0), 4 to team 1 as a
 * whole, 8 to the scene. */
TEST(rewards_pay_a_bot_a_team_or_the_scene)
{
	evo_scene *sc = evo_scene_create();
	add_bot(sc, 0, 0, 0, 0);
	add_bot(sc, 0, 5, 0, 0);
	add_bot(sc, 1, 10, 0, 0);
	add_reward(sc, EVO_RW_STEP, EVO_SCOPE_BOT, 0, 0, 1);
	add_reward(sc, EVO_RW_STEP, EVO_SCOPE_BOT, 1, 0, 2);
	add_reward(sc, EVO_RW_STEP, EVO_SCOPE_TEAM, 0, 1, 4);
	add_reward(sc, EVO_RW_STEP, EVO_SCOPE_SCENE, 0, 0, 8);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 3; t++) {
		evo_scene_sense(sc);
		CHECK_EQ_INT(evo_scene_step(sc), 0);
	}
	CHECK(NEAR(sc->bot[0].reward, 3));
	CHECK(NEAR(sc->bot[1].reward, 6));
	CHECK(NEAR(sc->bot[2].reward, 0));
	CHECK(NEAR(sc->team_reward[0], 9));
	CHECK(NEAR(sc->team_reward[1], 12));
	CHECK(NEAR(sc->episode_reward, 45));
	/* a reset forgets them all, and the winner */
	sc->winner = 1;
	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(sc->bot[1].reward, 0));
	CHECK(NEAR(sc->team_reward[0], 0));
	CHECK_EQ_INT(sc->winner, -1);
	/* a team reward for a team out of range is refused */
	evo_reward_def d = evo_default_reward_def(EVO_RW_STEP);
	d.scope = EVO_SCOPE_TEAM;
	d.team = -1;
	CHECK_EQ_INT(evo_scene_add_reward(sc, &d), -1);
	evo_scene_destroy(sc);
}

TEST(gather_takes_the_objects_a_bot_touches)
{
	evo_scene *sc = evo_scene_create();
	int b = add_bot(sc, 0, 0, 0, 0);
	add_bot(sc, 0, 20, 0, 0);
	evo_element_def o =
	    evo_default_element_def(EVO_PIECE_OBJECT, EVO_DIM_2D);
	o.size = 0.5;
	o.x = 1.5; /* touching bot 0: 1 + 0.5 */
	int near = evo_scene_add_element(sc, &o);
	o.x = 3.0; /* a metre away */
	int far = evo_scene_add_element(sc, &o);
	o.x = 21.55; /* touching bot 1, within the gap */
	int other = evo_scene_add_element(sc, &o);
	add_reward(sc, EVO_RW_GATHER, EVO_SCOPE_BOT, 0, 0, 2);
	add_reward(sc, EVO_RW_GATHER, EVO_SCOPE_BOT, 1, 0, 2);
	evo_scene_reset(sc, 1, 1);
	evo_scene_sense(sc);
	evo_scene_step(sc);
	CHECK_EQ_INT(sc->element[near].active, 0);
	CHECK_EQ_INT(sc->element[far].active, 1);
	CHECK_EQ_INT(sc->element[other].active, 0);
	CHECK_EQ_INT(sc->bot[b].gathered, 1);
	CHECK_EQ_INT(sc->bot[1].gathered, 1);
	CHECK(NEAR(sc->bot[b].reward, 2));
	CHECK(NEAR(sc->team_reward[0], 4));
	/* a heap of 40 small objects around a bot: every one touching it
	 * is taken */
	evo_scene *heap = evo_scene_create();
	add_bot(heap, 0, 0, 0, 0);
	for (int i = 0; i < 40; i++) {
		evo_element_def h =
		    evo_default_element_def(EVO_PIECE_OBJECT, EVO_DIM_2D);
		h.size = 0.1;
		h.x = 1.1 * cos(i * 2 * M_PI / 40);
		h.y = 1.1 * sin(i * 2 * M_PI / 40);
		evo_scene_add_element(heap, &h);
	}
	add_reward(heap, EVO_RW_GATHER, EVO_SCOPE_BOT, 0, 0, 1);
	evo_scene_reset(heap, 1, 1);
	evo_scene_sense(heap);
	evo_scene_step(heap);
	CHECK_EQ_INT(heap->bot[0].gathered, 40);
	evo_scene_destroy(heap);
	/* gathered objects are gone until the next reset */
	evo_scene_sense(sc);
	evo_scene_step(sc);
	CHECK(NEAR(sc->team_reward[0], 4));
	evo_scene_reset(sc, 1, 1);
	CHECK_EQ_INT(sc->element[near].active, 1);
	CHECK_EQ_INT(sc->bot[b].gathered, 0);
	evo_scene_destroy(sc);
}

/* Bots: 0 (team 0) at the origin facing +x; 1 (team 0) at (0, 30); 2
 * (team 1) at (40, 0), 3 (team 1) at (100, 100). */
TEST(trackers_find_the_nearest_opponent_and_teammate)
{
	evo_scene *sc = evo_scene_create();
	add_bot(sc, 0, 0, 0, 0);
	add_bot(sc, 0, 0, 30, 0);
	add_bot(sc, 1, 40, 0, 0);
	add_bot(sc, 1, 100, 100, 0);
	double x = 0, y = 0;
	CHECK(evo_scene_target_pos(sc, 0, EVO_TARGET_NEAREST_OPPONENT, &x, &y));
	CHECK(NEAR(x, 40) && NEAR(y, 0));
	CHECK(evo_scene_target_pos(sc, 0, EVO_TARGET_NEAREST_TEAMMATE, &x, &y));
	CHECK(NEAR(x, 0) && NEAR(y, 30));
	CHECK(evo_scene_target_pos(sc, 3, EVO_TARGET_NEAREST_TEAMMATE, &x, &y));
	CHECK(NEAR(x, 40) && NEAR(y, 0));
	/* a bearing sensor on it: the opponent straight ahead reads 0.5 */
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_BEARING);
	d.name = "OPP";
	d.target = EVO_TARGET_NEAREST_OPPONENT;
	int s = evo_scene_add_sensor(sc, 0, &d);
	CHECK(s >= 0);
	CHECK(NEAR(evo_sensor_sample(sc, 0, s), 0.5));
	/* a presence sensor: TRUE while there is one within reach */
	evo_sensor_def p = evo_default_sensor_def(EVO_SENSE_PRESENCE);
	p.name = "HAS";
	p.target = EVO_TARGET_NEAREST_OPPONENT;
	s = evo_scene_add_sensor(sc, 0, &p);
	CHECK(NEAR(evo_sensor_sample(sc, 0, s), EVO_TRUE));
	evo_scene_destroy(sc);

	/* no opponent within EVO_TEAM_SEARCH, and a bot of no team has no
	 * teammate */
	sc = evo_scene_create();
	add_bot(sc, 0, 0, 0, 0);
	add_bot(sc, 1, 500, 0, 0);
	add_bot(sc, -1, 3, 0, 0);
	CHECK(
	    !evo_scene_target_pos(sc, 0, EVO_TARGET_NEAREST_OPPONENT, &x, &y));
	CHECK(
	    !evo_scene_target_pos(sc, 2, EVO_TARGET_NEAREST_TEAMMATE, &x, &y));
	/* every bot of a team is an opponent of a bot of none */
	CHECK(evo_scene_target_pos(sc, 2, EVO_TARGET_NEAREST_OPPONENT, &x, &y));
	CHECK(NEAR(x, 0));
	evo_scene_destroy(sc);
}

/* One ray straight ahead from bot 0 (team 0); a teammate 5 m ahead, an
 * opponent 8 m ahead. */
static double ray_reading(int teammates, int opponents, int bots)
{
	evo_scene *sc = evo_scene_create();
	add_bot(sc, 0, 0, 0, 0);
	add_bot(sc, 0, 5, 0, 0);
	add_bot(sc, 1, 8, 0, 0);
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_PROXIMITY);
	d.name = "P";
	d.rays = 1;
	d.x = 1;
	d.mask = EVO_CAT_OBSTACLE | (bots ? EVO_CAT_BOT : 0);
	d.sees_teammates = teammates;
	d.sees_opponents = opponents;
	int s = evo_scene_add_sensor(sc, 0, &d);
	double v = evo_sensor_sample(sc, 0, s);
	evo_scene_destroy(sc);
	return v;
}

TEST(rays_see_teammates_or_opponents_as_told)
{
	/* a ray from x = 1, 12 m long: the teammate's rim 3 m along it
	 * (0.25), the opponent's 6 m (0.5), nothing: 1 */
	CHECK(fabs(ray_reading(0, 0, 1) - 0.25) < 1e-4);
	CHECK(fabs(ray_reading(1, 0, 0) - 0.25) < 1e-4);
	CHECK(fabs(ray_reading(0, 1, 0) - 0.5) < 1e-4);
	CHECK(NEAR(ray_reading(0, 0, 0), 1));
}

/* A crowd of 300 bots of three teams among pillars and objects, with
 * proximity sensors of every kind of fan: sensing them all at once (one
 * query per cell) reads exactly what each bot's own query reads. */
TEST(a_crowd_senses_as_each_bot_alone)
{
	evo_scene *sc = evo_scene_create();
	evo_rng r = evo_rng_seed(42);
	for (int i = 0; i < 40; i++) {
		evo_element_def e = evo_default_element_def(
		    i % 2 ? EVO_PIECE_CYLINDER : EVO_PIECE_OBJECT, EVO_DIM_2D);
		e.x = evo_rng_range(&r, -40, 40);
		e.y = evo_rng_range(&r, -40, 40);
		e.size = evo_rng_range(&r, 0.3, 2);
		evo_scene_add_element(sc, &e);
	}
	evo_element_def bx = evo_default_element_def(EVO_PIECE_BOX, EVO_DIM_2D);
	bx.half_w = 3;
	bx.half_h = 0.5;
	bx.angle = 0.4;
	evo_scene_add_element(sc, &bx);
	for (int i = 0; i < 300; i++) {
		int b = add_bot(sc, i % 3, evo_rng_range(&r, -40, 40),
				evo_rng_range(&r, -40, 40),
				evo_rng_range(&r, -M_PI, M_PI));
		for (int k = 0; k < 3; k++) {
			evo_sensor_def d =
			    evo_default_sensor_def(EVO_SENSE_PROXIMITY);
			char name[16];
			snprintf(name, sizeof name, "P%d", k);
			d.name = name;
			d.angle = evo_rng_range(&r, -M_PI, M_PI);
			d.arc = evo_rng_range(&r, 0, 2 * M_PI / (1 + k));
			d.rays = 1 + (i + k) % 9;
			d.range = evo_rng_range(&r, 1, 15);
			d.x = evo_rng_range(&r, -1, 1);
			d.mask = k == 2 ? (EVO_CAT_OBJECT | EVO_CAT_OBSTACLE)
					: EVO_CAT_OBSTACLE;
			d.sees_teammates = k == 0;
			d.sees_opponents = k == 1;
			evo_scene_add_sensor(sc, b, &d);
		}
	}
	evo_scene_reset(sc, 1, 1);
	evo_scene_sense(sc);
	static double batched[300][3][EVO_PROX_MAX_RAYS + 1];
	int hits = 0;
	for (int b = 0; b < 300; b++)
		for (int k = 0; k < 3; k++) {
			const evo_sensor *se = &sc->bot[b].sensor[k];
			batched[b][k][0] = se->value;
			hits += se->value < 1;
			for (int i = 0; i < EVO_PROX_MAX_RAYS; i++)
				batched[b][k][i + 1] = se->ray[i];
		}
	CHECK(hits > 100);
	int same = 1;
	for (int b = 0; b < 300; b++) {
		evo_bot_sense(sc, b);
		for (int k = 0; k < 3; k++) {
			const evo_sensor *se = &sc->bot[b].sensor[k];
			same &= batched[b][k][0] == se->value;
			for (int i = 0; i < EVO_PROX_MAX_RAYS; i++)
				same &= batched[b][k][i + 1] == se->ray[i];
		}
	}
	CHECK(same);
	evo_scene_destroy(sc);
}

int main(void)
{
	RUN(bots_of_a_team_are_numbered_and_named_by_body);
	RUN(rewards_pay_a_bot_a_team_or_the_scene);
	RUN(gather_takes_the_objects_a_bot_touches);
	RUN(trackers_find_the_nearest_opponent_and_teammate);
	RUN(rays_see_teammates_or_opponents_as_told);
	RUN(a_crowd_senses_as_each_bot_alone);
	return test_summary();
}
