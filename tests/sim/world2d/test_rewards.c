/* Reward and control functions (sim/world2d/rewards.c): each one with bodies in a
 * known situation and the value its documentation promises, computed
 * directly or through evo_scene_step. */
#include <math.h>
#include <stdio.h>

#include "harness.h"
#include "support/scenes.h"
#include "world2d/query.h"
#include "world2d/rewards.h"
#include "world2d/scene.h"

#define NEAR(a, b) (fabs((a) - (b)) <= 1e-9)

/* A scene with one BotType8 body at (x, y) facing `angle`. */
/* scene_with_bot, checking that the bot was added */
static evo_scene *scene_with_one_bot(double x, double y, double angle)
{
	evo_scene *sc = scene_with_bot(x, y, angle);
	CHECK_EQ_INT(sc->n_bots, 1);
	return sc;
}

static int add_element(evo_scene *sc, evo_piece_kind kind, double x, double y,
		       double size)
{
	int i = scene_add_element(sc, kind, x, y, size);
	CHECK(i >= 0);
	return i;
}

static int add_box(evo_scene *sc, double x, double y, double half_w,
		   double half_h)
{
	int i = scene_add_box(sc, x, y, half_w, half_h, 0);
	CHECK(i >= 0);
	return i;
}

static int add_constant_sensor(evo_scene *sc, double value)
{
	evo_sensor_def d = evo_default_sensor_def(EVO_SENSE_CONSTANT);
	d.value = value;
	int i = evo_scene_add_sensor(sc, 0, &d);
	CHECK(i >= 0);
	return i;
}

static int add_claw(evo_scene *sc, double x, double y)
{
	evo_actuator_def d = evo_default_actuator_def(EVO_ACT_CLAW);
	d.x = x;
	d.y = y;
	int i = evo_scene_add_actuator(sc, 0, &d);
	CHECK(i >= 0);
	return i;
}

static evo_reward_def reward_def(evo_reward_kind kind, double k)
{
	evo_reward_def d = evo_default_reward_def(kind);
	d.bot = 0;
	d.k = k;
	return d;
}

static int add_reward(evo_scene *sc, const evo_reward_def *d)
{
	int i = evo_scene_add_reward(sc, d);
	CHECK(i >= 0);
	return i;
}

static int add_control(evo_scene *sc, evo_control_kind kind, long ticks,
		       int target)
{
	evo_control_def d = evo_default_control_def(kind);
	d.bot = 0;
	d.ticks = ticks;
	d.target = target;
	int i = evo_scene_add_control(sc, &d);
	CHECK(i >= 0);
	return i;
}

static double compute(evo_scene *sc, int reward)
{
	int failed = 0;
	double v = evo_reward_compute(sc, &sc->reward[reward], &failed);
	CHECK_EQ_INT(failed, 0);
	return v;
}

static void set_velocity(evo_scene *sc, double vx, double vy)
{
	evo_body_set_velocity(sc->world, sc->bot[0].body, vx, vy, 0);
}

/* Objects of the world near (x, y): 0 once a delivered object left it. */
static int objects_near(evo_scene *sc, double x, double y)
{
	evo_shape_info info[4];
	return evo_world_query(sc->world, x - 0.1, y - 0.1, x + 0.1, y + 0.1,
			       EVO_CAT_OBJECT, info, 4);
}

/* ---- names ------------------------------------------------------------ */

TEST(names_resolve_with_and_without_their_prefix)
{
	char buf[80];
	for (int k = 0; k < EVO_RW_KIND_COUNT; k++) {
		const char *name = evo_reward_kind_name(k);
		CHECK(name != NULL);
		CHECK_EQ_INT(evo_reward_kind_by_name(name), k);
		snprintf(buf, sizeof buf, "RW_%s", name);
		CHECK_EQ_INT(evo_reward_kind_by_name(buf), k);
	}
	for (int k = 0; k < EVO_CF_KIND_COUNT; k++) {
		const char *name = evo_control_kind_name(k);
		CHECK(name != NULL);
		CHECK_EQ_INT(evo_control_kind_by_name(name), k);
		snprintf(buf, sizeof buf, "CF_%s", name);
		CHECK_EQ_INT(evo_control_kind_by_name(buf), k);
	}
	CHECK_EQ_INT(evo_reward_kind_by_name("RW_ClosingOnTarget"),
		     EVO_RW_CLOSING_ON_TARGET);
	CHECK_EQ_INT(evo_reward_kind_by_name("ClosingOnTarget"),
		     EVO_RW_CLOSING_ON_TARGET);
	CHECK_EQ_INT(evo_reward_kind_by_name("RW_SensorOverThreshold"),
		     EVO_RW_SENSOR_OVER);
	CHECK_EQ_INT(evo_reward_kind_by_name("SensorUnder"),
		     EVO_RW_SENSOR_UNDER);
	CHECK_EQ_INT(evo_control_kind_by_name("CF_NextOnTimeout"),
		     EVO_CF_NEXT_ON_TIMEOUT);
	CHECK_EQ_INT(evo_control_kind_by_name("NextOnTimeout"),
		     EVO_CF_NEXT_ON_TIMEOUT);
	CHECK_EQ_INT(evo_control_kind_by_name("CF_NextOnCollisionAndTimeout"),
		     EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT);
	CHECK_EQ_STR(evo_reward_kind_name(EVO_RW_COLLECT), "Collect");
	CHECK_EQ_STR(evo_control_kind_name(EVO_CF_NEXT_ON_COLLISION),
		     "NextOnCollision");

	CHECK_EQ_INT(evo_reward_kind_by_name("ClosingOnTargets"), -1);
	CHECK_EQ_INT(evo_reward_kind_by_name("closingontarget"), -1);
	CHECK_EQ_INT(evo_reward_kind_by_name("CF_ClosingOnTarget"), -1);
	CHECK_EQ_INT(evo_reward_kind_by_name("RW_"), -1);
	CHECK_EQ_INT(evo_reward_kind_by_name(""), -1);
	CHECK_EQ_INT(evo_reward_kind_by_name(NULL), -1);
	CHECK_EQ_INT(evo_control_kind_by_name("RW_NextOnTimeout"), -1);
	CHECK_EQ_INT(evo_control_kind_by_name("NextOnTimeOut"), -1);
	CHECK_EQ_INT(evo_control_kind_by_name(NULL), -1);
	CHECK(evo_reward_kind_name(-1) == NULL);
	CHECK(evo_reward_kind_name(EVO_RW_KIND_COUNT) == NULL);
	CHECK(evo_control_kind_name(EVO_CF_KIND_COUNT) == NULL);
}

/* ---- rewards ------------------------------------------------------------ */

TEST(closing_on_target_pays_k_per_unit_of_distance_gained)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int zone = add_element(sc, EVO_PIECE_ZONE, 10, 0, 1);
	evo_reward_def d = reward_def(EVO_RW_CLOSING_ON_TARGET, 0.5);
	d.target = zone;
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	evo_reward *rw = &sc->reward[r];

	/* The first step after a reset has nothing to compare with. */
	CHECK(NEAR(rw->previous, -1));
	CHECK(NEAR(compute(sc, r), 0));
	CHECK(NEAR(rw->previous, 10));
	/* 2.0 closer with k 0.5: +1.0; back again: -1.0. */
	evo_scene_place_bot(sc, 0, 2, 0, 0);
	CHECK(NEAR(compute(sc, r), 1.0));
	evo_scene_place_bot(sc, 0, 0, 0, 0);
	CHECK(NEAR(compute(sc, r), -1.0));
	CHECK(NEAR(rw->total, 0));

	/* Through the step: the bot stands still where it was placed. */
	evo_scene_place_bot(sc, 0, 2, 0, 0);
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK(NEAR(sc->step_reward, 1.0));
	CHECK(NEAR(sc->episode_reward, 1.0));
	CHECK(NEAR(rw->total, 1.0));

	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(rw->previous, -1));
	CHECK(NEAR(rw->total, 0));
	CHECK(NEAR(compute(sc, r), 0));
	evo_scene_destroy(sc);
}

TEST(closing_on_the_nearest_object_and_on_no_target)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int a = add_element(sc, EVO_PIECE_OBJECT, 5, 0, 0.5);
	int b = add_element(sc, EVO_PIECE_OBJECT, -8, 0, 0.5);
	evo_reward_def d = reward_def(EVO_RW_CLOSING_ON_TARGET, 1.0);
	d.target = EVO_TARGET_NEAREST_OBJECT;
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);

	CHECK(NEAR(compute(sc, r), 0));
	CHECK(NEAR(sc->reward[r].previous, 5));
	evo_scene_place_bot(sc, 0, 1, 0, 0);
	CHECK(NEAR(compute(sc, r), 1.0));
	/* Now the other one is nearer: 4 -> 3 from (-5, 0). */
	evo_scene_place_bot(sc, 0, -5, 0, 0);
	CHECK(NEAR(compute(sc, r), 1.0));

	/* No target at all: 0, and no jump when one comes back. */
	sc->element[a].active = 0;
	sc->element[b].active = 0;
	CHECK(NEAR(compute(sc, r), 0));
	CHECK(NEAR(sc->reward[r].previous, -1));
	sc->element[b].active = 1;
	CHECK(NEAR(compute(sc, r), 0));
	CHECK(NEAR(sc->reward[r].previous, 3));
	evo_scene_destroy(sc);
}

TEST(sensor_over_and_under_sum_the_distance_past_the_threshold)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	for (int i = 0; i < 3; i++)
		add_constant_sensor(sc, 0.5);
	evo_reward_def under = reward_def(EVO_RW_SENSOR_UNDER, -10);
	evo_reward_def over = reward_def(EVO_RW_SENSOR_OVER, 0.2);
	evo_reward_def last = reward_def(EVO_RW_SENSOR_OVER, 0.2);
	under.threshold = over.threshold = last.threshold = 0.5;
	under.n_sensors = over.n_sensors = 3;
	for (int i = 0; i < 3; i++)
		under.sensor[i] = over.sensor[i] = i;
	last.n_sensors = 1;
	last.sensor[0] = 0;
	int ru = add_reward(sc, &under);
	int ro = add_reward(sc, &over);
	int rl = add_reward(sc, &last);
	evo_scene_reset(sc, 1, 1);

	const double v[3] = {0.3, 0.5, 0.9};
	for (int i = 0; i < 3; i++)
		sc->bot[0].sensor[i].value = v[i];
	/* -10 * (0.2 + 0) and 0.2 * 0.4; only the listed sensors count. */
	CHECK(NEAR(compute(sc, ru), -2.0));
	CHECK(NEAR(compute(sc, ro), 0.08));
	CHECK(NEAR(compute(sc, rl), 0));
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK(NEAR(sc->step_reward, -1.92));

	/* Every value at the threshold: under and over both give 0. */
	for (int i = 0; i < 3; i++)
		sc->bot[0].sensor[i].value = 0.5;
	CHECK(NEAR(compute(sc, ru), 0));
	CHECK(NEAR(compute(sc, ro), 0));
	evo_scene_destroy(sc);
}

/* The bot driven at 6 m/s towards a wall whose face is 2.5 m ahead. */
static evo_scene *bot_before_a_wall(void)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	add_box(sc, 4, 0, 0.5, 3);
	return sc;
}

TEST(punish_on_collision_pays_k_every_touching_step)
{
	evo_scene *sc = bot_before_a_wall();
	evo_reward_def d = reward_def(EVO_RW_PUNISH_ON_COLLISION, -15);
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	int touching = 0, first = -1;
	for (int t = 0; t < 60; t++) {
		set_velocity(sc, 6, 0);
		CHECK_EQ_INT(evo_scene_step(sc), 0);
		if (sc->bot[0].touching > 0) {
			touching++;
			if (first < 0)
				first = t;
			CHECK(NEAR(sc->step_reward, -15));
		} else {
			CHECK(NEAR(sc->step_reward, 0));
		}
	}
	/* 2.5 m at 6 m/s, slowed by the damping: about half a second. */
	CHECK(first > 5);
	CHECK(touching > 30);
	CHECK_EQ_INT(sc->bot[0].collisions, touching);
	CHECK(NEAR(sc->reward[r].total, -15.0 * touching));
	CHECK(NEAR(sc->episode_reward, -15.0 * touching));
	evo_scene_destroy(sc);
}

/* ForwardSpeed pays k per unit/s along the heading: in proportion ahead,
 * negative backing, nothing sideways, and it turns with the bot. */
TEST(forward_speed_pays_k_per_unit_of_speed_ahead)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	evo_reward_def d = reward_def(EVO_RW_FORWARD_SPEED, 0.2);
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	CHECK(strcmp(evo_reward_kind_name(EVO_RW_FORWARD_SPEED), "ForwardSpeed") ==
	      0);
	set_velocity(sc, 3, 0);
	CHECK(NEAR(compute(sc, r), 0.6));
	set_velocity(sc, 1.5, 0);
	CHECK(NEAR(compute(sc, r), 0.3));
	set_velocity(sc, -3, 0);
	CHECK(NEAR(compute(sc, r), -0.6));
	set_velocity(sc, 0, 3); /* sideways */
	CHECK(NEAR(compute(sc, r), 0));
	evo_scene_place_bot(sc, 0, 0, 0, M_PI / 2); /* facing +y */
	set_velocity(sc, 0, 3);
	CHECK(NEAR(compute(sc, r), 0.6));
	set_velocity(sc, 3, 0);
	/* Box2D keeps the angle in single precision: cos(pi/2) is 4e-8. */
	CHECK(fabs(compute(sc, r)) < 1e-6);
	evo_scene_destroy(sc);
}

TEST(forward_motion_pays_k_ahead_and_k2_backward)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	evo_reward_def d = reward_def(EVO_RW_FORWARD_MOTION, 0.002);
	d.k2 = -0.02;
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);

	set_velocity(sc, 3, 0);
	CHECK(NEAR(compute(sc, r), 0.002));
	set_velocity(sc, -3, 0);
	CHECK(NEAR(compute(sc, r), -0.02));
	set_velocity(sc, 0, 3); /* sideways */
	CHECK(NEAR(compute(sc, r), 0));
	set_velocity(sc, 0, 0);
	CHECK(NEAR(compute(sc, r), 0));
	set_velocity(sc, 0.0005, 0); /* under 1e-3: standing */
	CHECK(NEAR(compute(sc, r), 0));
	set_velocity(sc, 0.002, 0); /* over it: moving */
	CHECK(NEAR(compute(sc, r), 0.002));
	set_velocity(sc, -0.002, 0);
	CHECK(NEAR(compute(sc, r), -0.02));

	/* Facing +y (down the screen), +y is ahead. */
	evo_scene_place_bot(sc, 0, 0, 0, M_PI / 2);
	set_velocity(sc, 0, 3);
	CHECK(NEAR(compute(sc, r), 0.002));
	set_velocity(sc, 3, 0);
	CHECK(NEAR(compute(sc, r), 0));
	set_velocity(sc, 0, -3);
	CHECK(NEAR(compute(sc, r), -0.02));

	/* Through the step: the damping slows it, the sign stays. */
	set_velocity(sc, 0, 3);
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK(NEAR(sc->step_reward, 0.002));
	evo_scene_destroy(sc);
}

TEST(speed_pays_k_times_speed_squared)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	evo_reward_def d = reward_def(EVO_RW_SPEED, 0.1);
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	set_velocity(sc, 3, 4);
	CHECK(NEAR(compute(sc, r), 2.5));
	set_velocity(sc, 0, 0);
	CHECK(NEAR(compute(sc, r), 0));
	set_velocity(sc, -3, 4);
	CHECK(NEAR(compute(sc, r), 2.5));
	CHECK(NEAR(sc->reward[r].total, 5.0));
	evo_scene_destroy(sc);
}

TEST(step_pays_k_every_step)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	evo_reward_def d = reward_def(EVO_RW_STEP, 0.25);
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 4; t++) {
		CHECK_EQ_INT(evo_scene_step(sc), 0);
		CHECK(NEAR(sc->step_reward, 0.25));
	}
	CHECK(NEAR(sc->episode_reward, 1.0));
	CHECK(NEAR(sc->reward[r].total, 1.0));
	evo_scene_reset(sc, 1, 1);
	CHECK(NEAR(sc->reward[r].total, 0));
	evo_scene_destroy(sc);
}

/* Close the claws after a step with them open: a clean rising edge. */
static void grab(evo_scene *sc)
{
	evo_bot *b = &sc->bot[0];
	for (int k = 0; k < b->n_actuators; k++)
		b->actuator[k].command = 0;
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	for (int k = 0; k < b->n_actuators; k++)
		b->actuator[k].command = 1;
}

TEST(collect_delivers_a_carried_object_once)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int obj = add_element(sc, EVO_PIECE_OBJECT, 1.6, 0, 0.5);
	int zone = add_element(sc, EVO_PIECE_ZONE, 6, 0, 1);
	int claw = add_claw(sc, 1, 0);
	evo_reward_def d = reward_def(EVO_RW_COLLECT, 10);
	d.target = zone;
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	evo_element *e = &sc->element[obj];
	evo_actuator *a = &sc->bot[0].actuator[claw];

	grab(sc);
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK_EQ_INT(e->held_by, 0);
	CHECK_EQ_INT(a->held, obj);
	CHECK(NEAR(sc->step_reward, 0));

	/* Carry it right until it is in the zone, then on past it. */
	int paid = 0, at = -1;
	for (int t = 0; t < 90; t++) {
		set_velocity(sc, 4, 0);
		CHECK_EQ_INT(evo_scene_step(sc), 0);
		if (NEAR(sc->step_reward, 10)) {
			paid++;
			at = t;
			/* It was in the zone where it was delivered. */
			CHECK(
			    evo_zone_contains(&sc->element[zone], e->x, e->y));
		} else {
			CHECK(NEAR(sc->step_reward, 0));
		}
	}
	CHECK_EQ_INT(paid, 1);
	CHECK(at > 0);
	CHECK_EQ_INT(sc->bot[0].delivered, 1);
	CHECK_EQ_INT(e->active, 0);
	CHECK_EQ_INT(e->held_by, -1);
	CHECK_EQ_INT(a->held, -1);
	CHECK_EQ_INT(a->joint, -1);
	CHECK(NEAR(sc->reward[r].total, 10));
	CHECK(NEAR(sc->episode_reward, 10));
	/* The object has left the world: nothing there, nothing touched. */
	CHECK_EQ_INT(objects_near(sc, e->x, e->y), 0);
	CHECK(sc->bot[0].collisions == 0);
	evo_scene_destroy(sc);
}

TEST(collect_ignores_a_free_object_in_the_zone)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int obj = add_element(sc, EVO_PIECE_OBJECT, 6, 0, 0.5);
	int zone = add_element(sc, EVO_PIECE_ZONE, 6, 0, 2);
	add_claw(sc, 1, 0);
	evo_reward_def d = reward_def(EVO_RW_COLLECT, 10);
	d.target = zone;
	add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	/* Closing the claw with nothing in reach holds nothing. */
	grab(sc);
	for (int t = 0; t < 5; t++) {
		CHECK_EQ_INT(evo_scene_step(sc), 0);
		CHECK(NEAR(sc->step_reward, 0));
	}
	CHECK_EQ_INT(sc->element[obj].active, 1);
	CHECK_EQ_INT(sc->bot[0].delivered, 0);
	evo_scene_destroy(sc);
}

/* Two claws grab two objects that already lie in the zone: both are
 * delivered in the same step, which is also the episode's last; the next
 * episode has them back and delivers them again. */
TEST(collect_two_objects_in_the_last_step)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int o1 = add_element(sc, EVO_PIECE_OBJECT, 1.6, -1, 0.4);
	int o2 = add_element(sc, EVO_PIECE_OBJECT, 1.6, 1, 0.4);
	int zone = add_element(sc, EVO_PIECE_ZONE, 1.6, 0, 1.5);
	int c1 = add_claw(sc, 1, -1);
	int c2 = add_claw(sc, 1, 1);
	evo_reward_def d = reward_def(EVO_RW_COLLECT, 10);
	d.target = zone;
	add_reward(sc, &d);
	add_control(sc, EVO_CF_NEXT_ON_TIMEOUT, 1, EVO_TARGET_NONE);

	for (int episode = 0; episode < 2; episode++) {
		evo_scene_reset(sc, 1, 1);
		CHECK_EQ_INT(sc->element[o1].active, 1);
		CHECK_EQ_INT(sc->element[o2].active, 1);
		CHECK_EQ_INT(objects_near(sc, 1.6, -1), 1);
		CHECK_EQ_INT(objects_near(sc, 1.6, 1), 1);
		CHECK_EQ_INT(sc->bot[0].delivered, 0);
		grab(sc); /* the first tick of 2 */
		CHECK_EQ_INT(evo_scene_step(sc), 1);
		CHECK(NEAR(sc->step_reward, 20));
		CHECK_EQ_INT(sc->bot[0].delivered, 2);
		CHECK_EQ_INT(sc->element[o1].active, 0);
		CHECK_EQ_INT(sc->element[o2].active, 0);
		CHECK_EQ_INT(sc->element[o1].held_by, -1);
		CHECK_EQ_INT(sc->element[o2].held_by, -1);
		CHECK_EQ_INT(sc->bot[0].actuator[c1].held, -1);
		CHECK_EQ_INT(sc->bot[0].actuator[c2].held, -1);
		CHECK_EQ_INT(objects_near(sc, 1.6, -1), 0);
		CHECK_EQ_INT(objects_near(sc, 1.6, 1), 0);
	}
	/* A step past the end is harmless and pays nothing more. */
	CHECK(evo_scene_step(sc) >= 0);
	CHECK(NEAR(sc->step_reward, 0));
	evo_scene_destroy(sc);
}

struct hook_log {
	int calls;
	const void *seen;
	double value;
	int next;
	int fail;
};

static int reward_hook(void *ctx, evo_err *err, const evo_reward *r,
		       double *out)
{
	struct hook_log *log = ctx;
	log->calls++;
	log->seen = r;
	if (log->fail)
		return evo_fail(err, "reward hook: boom");
	*out = log->value;
	return 0;
}

static int control_hook(void *ctx, evo_err *err, const evo_control *c,
			int *next)
{
	struct hook_log *log = ctx;
	log->calls++;
	log->seen = c;
	if (log->fail)
		return evo_fail(err, "control hook: boom");
	*next = log->next;
	return 0;
}

TEST(a_lua_reward_calls_the_hook_and_reports_its_failure)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	evo_reward_def d = reward_def(EVO_RW_LUA, 1);
	int r = add_reward(sc, &d);
	evo_scene_reset(sc, 1, 1);
	int failed = 0;

	/* No hook: 0. */
	CHECK(NEAR(evo_reward_compute(sc, &sc->reward[r], &failed), 0));
	CHECK_EQ_INT(failed, 0);

	struct hook_log log = {0};
	log.value = 1.25;
	sc->hooks.ctx = &log;
	sc->hooks.reward = reward_hook;
	CHECK(NEAR(compute(sc, r), 1.25));
	CHECK_EQ_INT(log.calls, 1);
	CHECK(log.seen == &sc->reward[r]);
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK(NEAR(sc->step_reward, 1.25));
	CHECK(NEAR(sc->reward[r].total, 2.5));

	log.fail = 1;
	CHECK(NEAR(evo_reward_compute(sc, &sc->reward[r], &failed), 0));
	CHECK_EQ_INT(failed, 1);
	CHECK_CONTAINS(sc->err.msg, "boom");
	CHECK_EQ_INT(evo_scene_step(sc), -1);
	evo_scene_destroy(sc);
}

/* ---- controls ------------------------------------------------------------ */

TEST(timeout_ends_after_ticks_plus_one_checks)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int c = add_control(sc, EVO_CF_NEXT_ON_TIMEOUT, 3, EVO_TARGET_NONE);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 3; t++)
		CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK_EQ_INT(evo_scene_step(sc), 1);
	CHECK_EQ_INT(sc->control[c].counter, 4);

	evo_scene_reset(sc, 1, 1);
	CHECK_EQ_INT(sc->control[c].counter, 0);
	for (int t = 0; t < 3; t++)
		CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 0);
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 1);
	evo_control_reset(&sc->control[c]);
	CHECK_EQ_INT(sc->control[c].counter, 0);

	/* ticks 0: the first check ends it. */
	sc->control[c].def.ticks = 0;
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 1);
	evo_scene_destroy(sc);
}

TEST(next_on_collision_ends_at_the_first_touch_not_before)
{
	evo_scene *sc = bot_before_a_wall();
	evo_reward_def d = reward_def(EVO_RW_PUNISH_ON_COLLISION, -15);
	add_reward(sc, &d);
	add_control(sc, EVO_CF_NEXT_ON_COLLISION, 0, EVO_TARGET_NONE);
	evo_scene_reset(sc, 1, 1);
	int end = -1;
	for (int t = 0; t < 60 && end < 0; t++) {
		set_velocity(sc, 6, 0);
		int ret = evo_scene_step(sc);
		if (sc->bot[0].touching > 0) {
			CHECK_EQ_INT(ret, 1);
			CHECK(NEAR(sc->step_reward, -15));
			end = t;
		} else {
			CHECK_EQ_INT(ret, 0);
			CHECK(NEAR(sc->step_reward, 0));
		}
	}
	CHECK(end > 5);
	CHECK_EQ_INT(sc->bot[0].collisions, 1);
	evo_scene_destroy(sc);
}

TEST(collision_and_timeout_ends_on_either_and_keeps_counting)
{
	/* Nothing to hit: the timeout. */
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int c = add_control(sc, EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT, 5,
			    EVO_TARGET_NONE);
	evo_scene_reset(sc, 1, 1);
	for (int t = 0; t < 5; t++)
		CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK_EQ_INT(evo_scene_step(sc), 1);
	evo_scene_destroy(sc);

	/* A wall long before the timeout: the collision, with every step
	 * counted. */
	sc = bot_before_a_wall();
	c = add_control(sc, EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT, 1000,
			EVO_TARGET_NONE);
	evo_scene_reset(sc, 1, 1);
	int steps = 0, ret = 0;
	while (ret == 0 && steps < 60) {
		set_velocity(sc, 6, 0);
		ret = evo_scene_step(sc);
		steps++;
	}
	CHECK_EQ_INT(ret, 1);
	CHECK(sc->bot[0].touching > 0);
	CHECK_EQ_INT(sc->control[c].counter, steps);
	CHECK(steps > 5 && steps < 60);
	evo_scene_destroy(sc);
}

/* Drive the bot from the origin at (vx, vy) until it touches something;
 * returns what the step said then. */
static int drive_until_touching(evo_scene *sc, double vx, double vy)
{
	int ret = -2;
	evo_scene_place_bot(sc, 0, 0, 0, 0);
	for (int t = 0; t < 60; t++) {
		set_velocity(sc, vx, vy);
		ret = evo_scene_step(sc);
		if (sc->bot[0].touching > 0)
			return ret;
		CHECK_EQ_INT(ret, 0);
	}
	CHECK(0 && "never touched");
	return ret;
}

TEST(collision_with_target_ends_only_on_that_element)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int cyl = add_element(sc, EVO_PIECE_CYLINDER, 0, -4, 1);
	int box = add_box(sc, 4, 0, 0.5, 1);
	int obj = add_element(sc, EVO_PIECE_OBJECT, -3.5, 0, 0.5);
	int zone = add_element(sc, EVO_PIECE_ZONE, 0, 0, 3);
	int c_cyl =
	    add_control(sc, EVO_CF_NEXT_ON_COLLISION_WITH_TARGET, 0, cyl);
	int c_box =
	    add_control(sc, EVO_CF_NEXT_ON_COLLISION_WITH_TARGET, 0, box);
	int c_obj =
	    add_control(sc, EVO_CF_NEXT_ON_COLLISION_WITH_TARGET, 0, obj);
	/* A zone has no body: the scene refuses it as a target, and a
	 * control made by hand never fires on it. */
	evo_control on_zone = {0};
	on_zone.def =
	    evo_default_control_def(EVO_CF_NEXT_ON_COLLISION_WITH_TARGET);
	on_zone.def.target = zone;
	CHECK(evo_scene_add_control(sc, &on_zone.def) < 0);
	evo_scene_reset(sc, 1, 1);
	evo_control *c = sc->control;

	CHECK_EQ_INT(drive_until_touching(sc, 0, -6), 1); /* up: cylinder */
	CHECK_EQ_INT(evo_control_check(sc, &c[c_cyl]), 1);
	CHECK_EQ_INT(evo_control_check(sc, &c[c_box]), 0);
	CHECK_EQ_INT(evo_control_check(sc, &c[c_obj]), 0);
	CHECK_EQ_INT(evo_control_check(sc, &on_zone), 0);

	CHECK_EQ_INT(drive_until_touching(sc, 6, 0), 1); /* right: box */
	CHECK_EQ_INT(evo_control_check(sc, &c[c_cyl]), 0);
	CHECK_EQ_INT(evo_control_check(sc, &c[c_box]), 1);
	CHECK_EQ_INT(evo_control_check(sc, &c[c_obj]), 0);

	CHECK_EQ_INT(drive_until_touching(sc, -6, 0), 1); /* left: object */
	CHECK_EQ_INT(evo_control_check(sc, &c[c_cyl]), 0);
	CHECK_EQ_INT(evo_control_check(sc, &c[c_box]), 0);
	CHECK_EQ_INT(evo_control_check(sc, &c[c_obj]), 1);
	CHECK_EQ_INT(evo_control_check(sc, &on_zone), 0);

	/* Down: nothing there, so nothing ends. */
	evo_scene_place_bot(sc, 0, 0, 0, 0);
	for (int t = 0; t < 20; t++) {
		set_velocity(sc, 0, 6);
		CHECK_EQ_INT(evo_scene_step(sc), 0);
	}
	evo_scene_destroy(sc);
}

TEST(sensor_below_ends_under_the_threshold)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int s = add_constant_sensor(sc, 0.5);
	evo_control_def d =
	    evo_default_control_def(EVO_CF_NEXT_ON_SENSOR_BELOW);
	d.sensor = s;
	d.threshold = 0.5;
	int c = evo_scene_add_control(sc, &d);
	CHECK(c >= 0);
	evo_scene_reset(sc, 1, 1);
	evo_sensor *sn = &sc->bot[0].sensor[s];

	sn->value = 0.6;
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 0);
	sn->value = 0.5; /* below, not at */
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 0);
	CHECK_EQ_INT(evo_scene_step(sc), 0);
	sn->value = 0.4;
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 1);
	CHECK_EQ_INT(evo_scene_step(sc), 1);
	evo_scene_destroy(sc);
}

TEST(a_lua_control_calls_the_hook_and_reports_its_failure)
{
	evo_scene *sc = scene_with_one_bot(0, 0, 0);
	int c = add_control(sc, EVO_CF_LUA, 0, EVO_TARGET_NONE);
	evo_scene_reset(sc, 1, 1);

	/* No hook: go on. */
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 0);

	struct hook_log log = {0};
	sc->hooks.ctx = &log;
	sc->hooks.control = control_hook;
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 0);
	CHECK_EQ_INT(log.calls, 1);
	CHECK(log.seen == &sc->control[c]);
	log.next = 1;
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), 1);
	CHECK_EQ_INT(evo_scene_step(sc), 1);

	log.fail = 1;
	CHECK_EQ_INT(evo_control_check(sc, &sc->control[c]), -1);
	CHECK_CONTAINS(sc->err.msg, "boom");
	CHECK_EQ_INT(evo_scene_step(sc), -1);
	evo_scene_destroy(sc);
}

int main(void)
{
	RUN(names_resolve_with_and_without_their_prefix);
	RUN(closing_on_target_pays_k_per_unit_of_distance_gained);
	RUN(closing_on_the_nearest_object_and_on_no_target);
	RUN(sensor_over_and_under_sum_the_distance_past_the_threshold);
	RUN(punish_on_collision_pays_k_every_touching_step);
	RUN(forward_motion_pays_k_ahead_and_k2_backward);
	RUN(forward_speed_pays_k_per_unit_of_speed_ahead);
	RUN(speed_pays_k_times_speed_squared);
	RUN(step_pays_k_every_step);
	RUN(collect_delivers_a_carried_object_once);
	RUN(collect_ignores_a_free_object_in_the_zone);
	RUN(collect_two_objects_in_the_last_step);
	RUN(a_lua_reward_calls_the_hook_and_reports_its_failure);
	RUN(timeout_ends_after_ticks_plus_one_checks);
	RUN(next_on_collision_ends_at_the_first_touch_not_before);
	RUN(collision_and_timeout_ends_on_either_and_keeps_counting);
	RUN(collision_with_target_ends_only_on_that_element);
	RUN(sensor_below_ends_under_the_threshold);
	RUN(a_lua_control_calls_the_hook_and_reports_its_failure);
	return test_summary();
}
