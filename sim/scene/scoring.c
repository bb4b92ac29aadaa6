/* How an episode is scored, in either dimension (sim/scene/scoring.h): the
 * reward and control functions, the step that pays the rewards, runs the
 * post-step hook and asks the controls, and an environment's metrics.
 *
 * Each function reads the scene only through its evo_score_ops, and the
 * bot and the element it names by index; an index that names nothing
 * gives 0 (a reward) or "go on" (a control) rather than a crash, since
 * environments move things between episodes. */
#include "scene/scoring.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- defaults ------------------------------------------------------------ */

evo_reward_def evo_default_reward_def(evo_reward_kind kind)
{
	evo_reward_def d;
	memset(&d, 0, sizeof d);
	d.kind = kind;
	d.k = 1.0;
	d.threshold = 0.5;
	d.target = EVO_TARGET_NONE;
	d.lua_ref = -1;
	return d;
}

evo_control_def evo_default_control_def(evo_control_kind kind)
{
	evo_control_def d;
	memset(&d, 0, sizeof d);
	d.kind = kind;
	d.ticks = 1000;
	d.target = EVO_TARGET_NONE;
	d.sensor = -1;
	d.threshold = 0.5;
	d.lua_ref = -1;
	return d;
}

/* ---- rewards ------------------------------------------------------------ */

/* ClosingOnTarget: k * (previous - d), d the distance from the bot's centre
 * to the target; 0 on the first step after a reset and whenever the target
 * is gone (previous is then -1, so a reappearing target is no jump). */
static double closing_on_target(const evo_scored *s, evo_reward *r)
{
	double d = s->ops->distance(s->sc, r->def.bot, r->def.target);
	if (d < 0) {
		r->previous = -1;
		return 0;
	}
	double v = r->previous >= 0 ? r->def.k * (r->previous - d) : 0;
	r->previous = d;
	return v;
}

/* Distance: k * the distance from the bot's centre to the target's, each
 * step (Kheperax's target task pays -distance). Nothing without a
 * target. */
static double distance(const evo_scored *s, const evo_reward *r)
{
	double d = s->ops->distance(s->sc, r->def.bot, r->def.target);
	return d < 0 ? 0 : r->def.k * d;
}

/* FinalDistance: the novelty-search maze's fitness, b - distance at the
 * end, paid as the episode goes so that it needs no end: k2 + k * d on
 * the first step, then k * (d - the previous d), which sum to k2 + k *
 * the distance after the last step, wherever the episode stops. */
static double final_distance(const evo_scored *s, evo_reward *r)
{
	double d = s->ops->distance(s->sc, r->def.bot, r->def.target);
	if (d < 0)
		return 0;
	double v = r->previous >= 0 ? r->def.k * (d - r->previous)
				    : r->def.k2 + r->def.k * d;
	r->previous = d;
	return v;
}

/* SensorOverThreshold: k * sum(v - threshold) over the listed sensors whose
 * value v > threshold. SensorUnderThreshold: k * sum(threshold - v) over
 * those with v <= threshold. */
static double sensor_threshold(const evo_scored *s, const evo_reward *r,
			       int over)
{
	double sum = 0;
	int n = r->def.n_sensors;
	if (n > EVO_REWARD_MAX_SENSORS)
		n = EVO_REWARD_MAX_SENSORS;
	for (int i = 0; i < n; i++) {
		/* NaN for a sensor that is not there: neither branch */
		double v = evo_core_sensor(s->sc, r->def.bot, r->def.sensor[i]);
		if (over && v > r->def.threshold)
			sum += v - r->def.threshold;
		else if (!over && v <= r->def.threshold)
			sum += r->def.threshold - v;
	}
	return r->def.k * sum;
}

/* The bot's velocity along its heading, and its speed squared. */
static void motion(const evo_scored *s, int bot, double *ahead_speed,
		   double *speed2)
{
	double v[3], a[3];
	s->ops->motion(s->sc, bot, v, a);
	*ahead_speed = v[0] * a[0] + v[1] * a[1] + v[2] * a[2];
	*speed2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
}

/* ForwardMotion: k when the velocity along the heading is above 1e-3, k2
 * when it is below -1e-3, 0 in between (standing, or sliding sideways).
 * ForwardSpeed (evo's own): k times the velocity along the heading, in
 * units per second; negative when backing. Speed: k * |v|^2. */
static double moving(const evo_scored *s, const evo_reward *r)
{
	double vf, v2;
	motion(s, r->def.bot, &vf, &v2);
	switch (r->def.kind) {
	case EVO_RW_FORWARD_MOTION:
		return vf > 1e-3 ? r->def.k : vf < -1e-3 ? r->def.k2 : 0;
	case EVO_RW_FORWARD_SPEED:
		return r->def.k * vf;
	default: /* EVO_RW_SPEED */
		return r->def.k * v2;
	}
}

double evo_effort_term(double c)
{
	c = isnan(c) ? 0.5 : c < 0 ? 0 : c > 1 ? 1 : c;
	return (2 * c - 1) * (2 * c - 1);
}

/* Lua: the scene's reward hook gives the value; no hook gives 0. */
static double lua_reward(const evo_scored *s, const evo_reward *r, int *failed)
{
	double out = 0;
	const evo_scene_hooks *h = s->hooks;
	if (!h || !h->reward)
		return 0;
	if (h->reward(h->ctx, s->err, r, &out) != 0) {
		*failed = 1;
		return 0;
	}
	return out;
}

static int has_bot(const evo_scored *s, int bot)
{
	return bot >= 0 && bot < evo_core_n_bots(s->sc);
}

double evo_reward_compute_in(const evo_scored *s, evo_reward *r, int *failed)
{
	const evo_score_ops *o = s->ops;
	int dummy = 0;
	if (!failed)
		failed = &dummy;
	if (!has_bot(s, r->def.bot) && r->def.kind != EVO_RW_LUA &&
	    r->def.kind != EVO_RW_STEP)
		return 0;
	double v = 0;
	switch (r->def.kind) {
	case EVO_RW_CLOSING_ON_TARGET:
		v = closing_on_target(s, r);
		break;
	case EVO_RW_SENSOR_OVER:
	case EVO_RW_SENSOR_UNDER:
		v = sensor_threshold(s, r, r->def.kind == EVO_RW_SENSOR_OVER);
		break;
	/* PunishOnCollision: k (negative) every step the bot touches
	 * anything. */
	case EVO_RW_PUNISH_ON_COLLISION:
		v = o->touching(s->sc, r->def.bot) > 0 ? r->def.k : 0;
		break;
	case EVO_RW_FORWARD_MOTION:
	case EVO_RW_FORWARD_SPEED:
	case EVO_RW_SPEED:
		v = moving(s, r);
		break;
	/* Step: k every step. */
	case EVO_RW_STEP:
		v = r->def.k;
		break;
	case EVO_RW_LUA:
		v = lua_reward(s, r, failed);
		break;
	case EVO_RW_DISTANCE:
		v = distance(s, r);
		break;
	case EVO_RW_FINAL_DISTANCE:
		v = final_distance(s, r);
		break;
	/* Effort: k * sum of (2c - 1)^2 over the bot's motors (Kheperax's
	 * fitness, with k = -0.025^2, sums the squares of the commanded
	 * wheel moves). */
	case EVO_RW_EFFORT:
		v = r->def.k * o->effort(s->sc, r->def.bot);
		break;
	default: /* a kind of one dimension only (kinds.c) */
		v = o->own_reward ? o->own_reward(s->sc, r) : 0;
		break;
	}
	if (!isfinite(v))
		v = 0;
	r->total += v;
	return v;
}

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

/* Lua: the scene's control hook decides; no hook goes on. */
static int lua_control(const evo_scored *s, const evo_control *c)
{
	int next = 0;
	const evo_scene_hooks *h = s->hooks;
	if (!h || !h->control)
		return 0;
	if (h->control(h->ctx, s->err, c, &next) != 0)
		return -1;
	return next != 0;
}

int evo_control_check_in(const evo_scored *s, evo_control *c)
{
	const evo_score_ops *o = s->ops;
	int b = has_bot(s, c->def.bot), bot = c->def.bot;
	switch (c->def.kind) {
	case EVO_CF_NEXT_ON_TIMEOUT:
		return timeout(c);
	/* NextOnCollision: the bot touches anything this step. */
	case EVO_CF_NEXT_ON_COLLISION:
		return b && o->touching(s->sc, bot) > 0;
	/* NextOnCollisionAndTimeout: either rule; the counter counts every
	 * check, touching or not. */
	case EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT: {
		int t = timeout(c);
		return t || (b && o->touching(s->sc, bot) > 0);
	}
	/* NextOnCollisionWithTarget: the bot touches the target element. */
	case EVO_CF_NEXT_ON_COLLISION_WITH_TARGET:
		return b && evo_core_touching(s->sc, bot, c->def.target);
	/* NextOnSensorBelow: the sensor's last value < threshold. */
	case EVO_CF_NEXT_ON_SENSOR_BELOW:
		return b && c->def.sensor >= 0 &&
		       evo_core_sensor(s->sc, bot, c->def.sensor) <
			   c->def.threshold;
	/* NextOnTargetReached: the bot's centre within threshold of the
	 * target's (the mazes' goal). */
	case EVO_CF_NEXT_ON_TARGET_REACHED: {
		double d = b ? o->distance(s->sc, bot, c->def.target) : -1;
		return d >= 0 && d < c->def.threshold;
	}
	case EVO_CF_LUA:
		return lua_control(s, c);
	default:
		return 0;
	}
}

void evo_control_reset(evo_control *c)
{
	c->counter = 0;
}

/* ---- the step ------------------------------------------------------------ */

int evo_score_step(const evo_scored *s, evo_reward *reward, int n_rewards,
		   evo_control *control, int n_controls, double *step_reward,
		   double *episode_reward)
{
	double total = 0;
	for (int i = 0; i < n_rewards; i++) {
		int failed = 0;
		double v = evo_reward_compute_in(s, &reward[i], &failed);
		if (failed)
			return -1;
		evo_core_pay(s->sc, &reward[i], v);
		total += v;
	}
	*step_reward = total;
	*episode_reward += total;
	/* EvoAgents' postStepOps, after the rewards: the bot has been paid
	 * for this step before the environment moves its target away. */
	const evo_scene_hooks *h = s->hooks;
	if (h && h->post_step && h->post_step(h->ctx, s->err))
		return -1;
	int next = 0;
	for (int i = 0; i < n_controls; i++) {
		int r = evo_control_check_in(s, &control[i]);
		if (r < 0)
			return -1;
		next |= r;
	}
	return next;
}

/* ---- metrics ------------------------------------------------------------- */

/* A metric's name goes into `evo run`'s episode lines and a log.csv
 * header: a C identifier needs no quoting in either. */
static int metric_name_ok(const char *name)
{
	if (!((name[0] >= 'A' && name[0] <= 'Z') ||
	      (name[0] >= 'a' && name[0] <= 'z') || name[0] == '_'))
		return 0;
	for (const char *p = name; *p; p++)
		if (!((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') ||
		      (*p >= '0' && *p <= '9') || *p == '_'))
			return 0;
	return 1;
}

int evo_metric_add(evo_metric *metric, int *n, const char *name, evo_err *err)
{
	int i = evo_metric_find(metric, *n, name);
	if (i >= 0)
		return i;
	if (!metric_name_ok(name))
		return evo_fail(err,
				"'%.40s' is not a metric name: use letters, "
				"digits and '_', not starting with a digit",
				name);
	if (strlen(name) >= EVO_METRIC_NAME_MAX)
		return evo_fail(err,
				"metric name '%.40s...' is longer than %d "
				"characters",
				name, EVO_METRIC_NAME_MAX - 1);
	if (*n == EVO_SCENE_MAX_METRICS)
		return evo_fail(err,
				"metric '%s' is one too many: an environment "
				"has at most %d",
				name, EVO_SCENE_MAX_METRICS);
	evo_metric *m = &metric[*n];
	snprintf(m->name, sizeof m->name, "%s", name);
	m->value = 0;
	return (*n)++;
}

int evo_metric_set(evo_metric *metric, int n, int k, double value, evo_err *err)
{
	if (k < 0 || k >= n)
		return evo_fail(err, "no metric %d", k);
	if (!isfinite(value))
		return evo_fail(err, "metric '%s': %g is not a finite number",
				metric[k].name, value);
	metric[k].value = value;
	return 0;
}

int evo_metric_find(const evo_metric *metric, int n, const char *name)
{
	for (int i = 0; i < n; i++)
		if (strcmp(metric[i].name, name) == 0)
			return i;
	return -1;
}
