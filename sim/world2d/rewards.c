/* evo — the reward and control functions of an episode (EvoAgents' RW_ and
 * CF_ classes, tutorial sections 6.3 and 6.4).
 *
 * evo_scene_step calls evo_reward_compute on every reward after the
 * physics step (and before the post-step hook) and sums the values, then
 * evo_control_check on every control; any control returning 1 ends the
 * episode. Each function reads the bot and the elements it names by index;
 * an index that names nothing gives 0 (a reward) or "go on" (a control)
 * rather than a crash, since environments move things between episodes. */
#include "world2d/rewards.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "world2d/actuators.h"
#include "world2d/query.h"
#include "world2d/scene_internal.h"

/* ---- helpers ------------------------------------------------------------ */

static evo_bot *bot_at(evo_scene *sc, int bot)
{
	return bot >= 0 && bot < sc->n_bots ? &sc->bot[bot] : NULL;
}

static evo_element *element_at(evo_scene *sc, int e)
{
	return e >= 0 && e < sc->n_elements ? &sc->element[e] : NULL;
}

static const evo_sensor *sensor_at(const evo_bot *b, int s)
{
	return s >= 0 && s < b->n_sensors ? &b->sensor[s] : NULL;
}

/* ---- rewards ------------------------------------------------------------ */

/* ClosingOnTarget: k * (previous - d), d the distance from the bot's centre
 * to the target; 0 on the first step after a reset and whenever the target
 * is gone (previous is then -1, so a reappearing target is no jump). */
static double closing_on_target(evo_scene *sc, evo_reward *r, evo_bot *b)
{
	double tx, ty;
	if (!evo_scene_target_pos(sc, r->def.bot, r->def.target, &tx, &ty)) {
		r->previous = -1;
		return 0;
	}
	double d = hypot(tx - b->x, ty - b->y);
	double v = r->previous >= 0 ? r->def.k * (r->previous - d) : 0;
	r->previous = d;
	return v;
}

/* Distance: k * the distance from the bot's centre to the target's, each
 * step (Kheperax's target task pays -distance). Nothing without a
 * target. */
static double distance(evo_scene *sc, const evo_reward *r, const evo_bot *b)
{
	double tx, ty;
	if (!evo_scene_target_pos(sc, r->def.bot, r->def.target, &tx, &ty))
		return 0;
	return r->def.k * hypot(tx - b->x, ty - b->y);
}

/* FinalDistance: the novelty-search maze's fitness, b - distance at the
 * end, paid as the episode goes so that it needs no end: k2 + k * d on
 * the first step, then k * (d - the previous d), which sum to k2 + k *
 * the distance after the last step, wherever the episode stops. */
static double final_distance(evo_scene *sc, evo_reward *r, const evo_bot *b)
{
	double tx, ty;
	if (!evo_scene_target_pos(sc, r->def.bot, r->def.target, &tx, &ty))
		return 0;
	double d = hypot(tx - b->x, ty - b->y);
	double v = r->previous >= 0 ? r->def.k * (d - r->previous)
				    : r->def.k2 + r->def.k * d;
	r->previous = d;
	return v;
}

/* Effort: k * sum of (2c - 1)^2 over the bot's wheels of either kind, the
 * commands of this step (Kheperax's fitness, with k = -0.025^2, sums the
 * squares of the commanded wheel moves). */
static double effort(const evo_bot *b, const evo_reward *r)
{
	double sum = 0;
	for (int i = 0; i < b->n_actuators; i++) {
		const evo_actuator *a = &b->actuator[i];
		if (a->def.kind != EVO_ACTUATOR_WHEEL &&
		    a->def.kind != EVO_ACTUATOR_SPEED_WHEEL)
			continue;
		double c = a->command;
		c = isnan(c) ? 0.5 : c < 0 ? 0 : c > 1 ? 1 : c;
		sum += (2 * c - 1) * (2 * c - 1);
	}
	return r->def.k * sum;
}

/* SensorOverThreshold: k * sum(v - threshold) over the listed sensors whose
 * value v > threshold. SensorUnderThreshold: k * sum(threshold - v) over
 * those with v <= threshold. */
static double sensor_threshold(const evo_reward *r, const evo_bot *b, int over)
{
	double sum = 0;
	int n = r->def.n_sensors;
	if (n > EVO_REWARD_MAX_SENSORS)
		n = EVO_REWARD_MAX_SENSORS;
	for (int i = 0; i < n; i++) {
		const evo_sensor *s = sensor_at(b, r->def.sensor[i]);
		if (!s)
			continue;
		double v = s->value;
		if (over && v > r->def.threshold)
			sum += v - r->def.threshold;
		else if (!over && v <= r->def.threshold)
			sum += r->def.threshold - v;
	}
	return r->def.k * sum;
}

/* ForwardMotion: k when the velocity along the heading is above 1e-3, k2
 * when it is below -1e-3, 0 in between (standing, or sliding sideways). */
static double forward_motion(evo_scene *sc, const evo_reward *r,
			     const evo_bot *b)
{
	double v[3], w[3];
	sc->be->velocity(sc->bw, b->body, v, w);
	double vx = v[0], vy = v[1];
	double vf = vx * b->c + vy * b->s;
	if (vf > 1e-3)
		return r->def.k;
	if (vf < -1e-3)
		return r->def.k2;
	return 0;
}

/* ForwardSpeed (evo's own): k times the velocity along the heading, in
 * units per second; negative when backing, 0 sliding sideways. */
static double forward_speed(evo_scene *sc, const evo_reward *r,
			    const evo_bot *b)
{
	double v[3], w[3];
	sc->be->velocity(sc->bw, b->body, v, w);
	double vx = v[0], vy = v[1];
	return r->def.k * (vx * b->c + vy * b->s);
}

/* Speed: k * |v|^2, v the bot's linear velocity. */
static double speed(evo_scene *sc, const evo_reward *r, const evo_bot *b)
{
	double v[3], w[3];
	sc->be->velocity(sc->bw, b->body, v, w);
	double vx = v[0], vy = v[1];
	return r->def.k * (vx * vx + vy * vy);
}

/* Collect: k for each active object the bot holds whose centre lies in the
 * target zone (an active EVO_ELEM_ZONE; anything else gives 0). A delivery
 * opens the bot's claws (all of them), takes the object off the world
 * until the next reset and counts it in bot->delivered.
 *
 * EvoAgents crashed here by destroying a body still welded to the claw.
 * The order below avoids that and handles several objects in one step:
 * first mark every delivered object inactive (the claws still say who
 * holds what), then open the claws (removing the welds), and only then
 * disable the bodies of inactive objects. Disabling is idempotent, and an
 * inactive object is off the world by definition, so the second pass
 * needs no list of its own. */
static double collect(evo_scene *sc, const evo_reward *r, evo_bot *b)
{
	const evo_element *z = element_at(sc, r->def.target);
	int n = 0;
	if (!z || z->kind != EVO_ELEM_ZONE || !z->active)
		return 0;
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element *e = &sc->element[i];
		if (e->kind != EVO_ELEM_OBJECT || !e->active ||
		    e->held_by != r->def.bot)
			continue;
		evo_bpose p = sc->be->pose(sc->bw, e->body);
		if (!evo_zone_contains(z, p.pos[0], p.pos[1]))
			continue;
		e->active = 0;
		n++;
	}
	if (n == 0)
		return 0;
	evo_bot_release(sc, r->def.bot);
	for (int i = 0; i < sc->n_elements; i++) {
		evo_element *e = &sc->element[i];
		if (e->kind == EVO_ELEM_OBJECT && !e->active)
			sc->be->set_enabled(sc->bw, e->body, 0);
	}
	b->delivered += n;
	return r->def.k * n;
}

/* Gather (evo's own, for foraging, docs/teams.md): k for each active
 * object no claw holds that the bot touches, its centre within the bot's
 * radius + its own + EVO_GATHER_GAP; the object leaves the world until
 * the next reset (or until the environment places and activates it
 * again) and counts in bot->gathered. The objects are found through the
 * broad phase, near the bot. */
#define EVO_GATHER_GAP 0.1
#define GATHER_CAP     32

static double gather(evo_scene *sc, const evo_reward *r, evo_bot *b)
{
	evo_shape_info local[GATHER_CAP], *found = local;
	/* an object of radius up to 2 m is found; a larger one needs a
	 * larger square */
	double reach = b->radius + 2 + EVO_GATHER_GAP;
	double x0 = b->x - reach, y0 = b->y - reach;
	double x1 = b->x + reach, y1 = b->y + reach;
	int n = evo_scene_query(sc, x0, y0, x1, y1, EVO_CAT_OBJECT, local,
				GATHER_CAP);
	if (n > GATHER_CAP) {
		/* a heap of objects: room for all of them */
		evo_shape_info *big = malloc((size_t)n * sizeof *big);
		if (big) {
			found = big;
			n = evo_scene_query(sc, x0, y0, x1, y1, EVO_CAT_OBJECT,
					    big, n);
		} else {
			n = GATHER_CAP;
		}
	}
	int got = 0;
	for (int i = 0; i < n; i++) {
		int k = evo_scene_object_of_body(sc, found[i].body.index);
		evo_element *e = element_at(sc, k);
		if (!e || !e->active || e->held_by >= 0)
			continue;
		double lim = b->radius + e->size + EVO_GATHER_GAP;
		double dx = found[i].x - b->x, dy = found[i].y - b->y;
		if (dx * dx + dy * dy > lim * lim)
			continue;
		e->active = 0;
		sc->be->set_enabled(sc->bw, e->body, 0);
		got++;
	}
	if (found != local)
		free(found);
	b->gathered += got;
	return r->def.k * got;
}

/* Lua: the scene's reward hook gives the value; no hook gives 0. */
static double lua_reward(evo_scene *sc, const evo_reward *r, int *failed)
{
	double out = 0;
	if (!sc->hooks.reward)
		return 0;
	if (sc->hooks.reward(sc->hooks.ctx, sc, r, &out) != 0) {
		*failed = 1;
		return 0;
	}
	return out;
}

/* The value of reward r for the step just taken; r->total adds it up.
 * A reward whose bot index names no bot gives 0. */
double evo_reward_compute(evo_scene *sc, evo_reward *r, int *failed)
{
	evo_bot *b = bot_at(sc, r->def.bot);
	double v = 0;
	int dummy = 0;
	if (!failed)
		failed = &dummy;
	if (!b && r->def.kind != EVO_RW_LUA && r->def.kind != EVO_RW_STEP)
		return 0;
	switch (r->def.kind) {
	case EVO_RW_CLOSING_ON_TARGET:
		v = closing_on_target(sc, r, b);
		break;
	case EVO_RW_SENSOR_OVER:
		v = sensor_threshold(r, b, 1);
		break;
	case EVO_RW_SENSOR_UNDER:
		v = sensor_threshold(r, b, 0);
		break;
	/* PunishOnCollision: k (negative) every step the bot touches
	 * anything. */
	case EVO_RW_PUNISH_ON_COLLISION:
		v = b->touching > 0 ? r->def.k : 0;
		break;
	case EVO_RW_FORWARD_MOTION:
		v = forward_motion(sc, r, b);
		break;
	case EVO_RW_FORWARD_SPEED:
		v = forward_speed(sc, r, b);
		break;
	case EVO_RW_SPEED:
		v = speed(sc, r, b);
		break;
	/* Step: k every step. */
	case EVO_RW_STEP:
		v = r->def.k;
		break;
	case EVO_RW_COLLECT:
		v = collect(sc, r, b);
		break;
	case EVO_RW_GATHER:
		v = gather(sc, r, b);
		break;
	case EVO_RW_LUA:
		v = lua_reward(sc, r, failed);
		break;
	case EVO_RW_DISTANCE:
		v = distance(sc, r, b);
		break;
	case EVO_RW_FINAL_DISTANCE:
		v = final_distance(sc, r, b);
		break;
	case EVO_RW_EFFORT:
		v = effort(b, r);
		break;
	default:
		v = 0;
		break;
	}
	r->total += v;
	return v;
}

/* Forget the previous distance (ClosingOnTarget: comparing with the last
 * episode would make no sense) and the episode's total. */
void evo_reward_reset(evo_reward *r)
{
	r->previous = -1;
	r->total = 0;
}

/* ---- controls ------------------------------------------------------------ */

/* NextOnTimeout: counts its checks and ends the episode when the count
 * exceeds ticks, i.e. at the (ticks + 1)th check (the tutorial's rule). */
static int timeout(evo_control *c)
{
	c->counter++;
	return c->counter > c->def.ticks;
}

/* NextOnCollisionWithTarget: the bot touches the target element: an object
 * body, or a cylinder's or box's obstacle. A zone has no body and an
 * inactive object no contacts, so neither ever ends the episode. */
static int touching_target(evo_scene *sc, const evo_control *c,
			   const evo_bot *b)
{
	const evo_element *e = element_at(sc, c->def.target);
	if (!e)
		return 0;
	switch (e->kind) {
	case EVO_ELEM_OBJECT:
		return e->active &&
		       sc->be->touching_body(sc->bw, b->body, e->body);
	case EVO_ELEM_CYLINDER:
	case EVO_ELEM_BOX:
		return sc->be->touching_obstacle(sc->bw, b->body, e->obstacle);
	default:
		return 0;
	}
}

/* 1 to end the episode, 0 to go on, -1 when the Lua hook failed (sc->err
 * set by the hook). A control whose bot index names no bot goes on, but
 * still counts its ticks. */
int evo_control_check(evo_scene *sc, evo_control *c)
{
	evo_bot *b = bot_at(sc, c->def.bot);
	switch (c->def.kind) {
	case EVO_CF_NEXT_ON_TIMEOUT:
		return timeout(c);
	/* NextOnCollision: the bot touches anything this step. */
	case EVO_CF_NEXT_ON_COLLISION:
		return b && b->touching > 0;
	/* NextOnCollisionAndTimeout: either rule; the counter counts every
	 * check, touching or not. */
	case EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT: {
		int t = timeout(c);
		return t || (b && b->touching > 0);
	}
	case EVO_CF_NEXT_ON_COLLISION_WITH_TARGET:
		return b && touching_target(sc, c, b);
	/* NextOnSensorBelow: the sensor's last value < threshold. */
	case EVO_CF_NEXT_ON_SENSOR_BELOW: {
		const evo_sensor *s = b ? sensor_at(b, c->def.sensor) : NULL;
		return s && s->value < c->def.threshold;
	}
	/* NextOnTargetReached: the bot's centre within threshold of the
	 * target's (the mazes' goal). */
	case EVO_CF_NEXT_ON_TARGET_REACHED: {
		double tx, ty;
		return b &&
		       evo_scene_target_pos(sc, c->def.bot, c->def.target, &tx,
					    &ty) &&
		       hypot(tx - b->x, ty - b->y) < c->def.threshold;
	}
	/* Lua: the scene's control hook decides; no hook goes on. */
	case EVO_CF_LUA: {
		int next = 0;
		if (!sc->hooks.control)
			return 0;
		if (sc->hooks.control(sc->hooks.ctx, sc, c, &next) != 0)
			return -1;
		return next != 0;
	}
	default:
		return 0;
	}
}

/* Start counting again. */
void evo_control_reset(evo_control *c)
{
	c->counter = 0;
}
