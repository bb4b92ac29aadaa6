/* What both scenes keep beside their bots, and its functions, once
 * (sim/scene/core.h): making and freeing the core, adding rewards and
 * controls with the checks of both dimensions, storing a bot with the
 * checks both worlds make (scene/bot.h), the metrics, the figures of a
 * new episode, and paying the rewards. */
#include "scene/core.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/store.h"

void evo_core_init(evo_scene_core *c, const evo_backend *be, evo_bworld *bw,
		   const evo_scene_dim *dim)
{
	c->be = be;
	c->bw = bw;
	c->dim = dim;
	c->rng = evo_rng_seed(1);
	c->winner = -1;
}

void evo_core_free(evo_scene_core *c)
{
	for (int i = 0; i < c->n_bots; i++) {
		free(c->bot[i].sensor);
		free(c->bot[i].actuator);
	}
	free(c->bot);
	free(c->element);
	free(c->reward);
	free(c->control);
	evo_swarm_free(&c->swarm);
}

/* ---- adding ---------------------------------------------------------- */

static int check_bot(evo_scene_core *c, int bot)
{
	int n = c->n_bots;
	if (bot < 0 || bot >= n)
		return evo_fail(&c->err, "no bot %d (there are %d)", bot, n);
	return 0;
}

/* What a reward and a control both need: a kind of the scene's dimension
 * (by its row of kinds.c), a bot, a target the dimension allows. */
static int check_piece(evo_scene_core *c, const char *what, const char *name,
		       unsigned dims, int bot, int target)
{
	if (!(dims & c->dim->dims))
		return evo_fail(&c->err, "%s %s is %s only", what, name,
				c->dim->dims == EVO_DIM_2D ? "3D" : "2D");
	if (check_bot(c, bot))
		return -1;
	return c->dim->check_target(c, target, what);
}

/* Room for item n of an array of the core, zeroed; NULL with c->err set. */
static void *slot(evo_scene_core *c, void **items, int n, int *cap, size_t size)
{
	if (evo_store_grow(items, cap, n + 1, size, &c->err))
		return NULL;
	return memset((char *)*items + (size_t)n * size, 0, size);
}

/* The checks of a reward, whatever its dimension. */
static int check_reward(evo_scene_core *c, const evo_reward_def *d)
{
	const char *name = evo_reward_kind_name(d->kind);
	if (check_piece(c, "reward", name, evo_reward_kind_dims(d->kind),
			d->bot, d->target))
		return -1;
	if ((unsigned)d->scope > EVO_SCOPE_SCENE ||
	    (d->scope == EVO_SCOPE_TEAM &&
	     (d->team < 0 || d->team >= EVO_SCENE_MAX_TEAMS)))
		return evo_fail(&c->err, "reward %s: no team %d", name,
				d->team);
	if (!isfinite(d->k) || !isfinite(d->k2) || !isfinite(d->threshold))
		return evo_fail(&c->err, "reward %s: a value is not a number",
				name);
	if (d->n_sensors < 0 || d->n_sensors > EVO_REWARD_MAX_SENSORS)
		return evo_fail(&c->err, "reward %s: %d sensors (at most %d)",
				name, d->n_sensors, EVO_REWARD_MAX_SENSORS);
	int n = c->bot[d->bot].n_sensors;
	for (int i = 0; i < d->n_sensors; i++)
		if (d->sensor[i] < 0 || d->sensor[i] >= n)
			return evo_fail(&c->err, "reward %s: no sensor %d",
					name, d->sensor[i]);
	if ((d->kind == EVO_RW_CLOSING_ON_TARGET ||
	     d->kind == EVO_RW_DISTANCE || d->kind == EVO_RW_FINAL_DISTANCE) &&
	    d->target == EVO_TARGET_NONE)
		return evo_fail(&c->err, "reward %s needs a target", name);
	return c->dim->check_reward ? c->dim->check_reward(c, d) : 0;
}

int evo_core_add_reward(evo_scene_core *c, const evo_reward_def *d)
{
	if ((unsigned)d->kind >= EVO_RW_KIND_COUNT)
		return evo_fail(&c->err, "reward: unknown kind %d",
				(int)d->kind);
	if (check_reward(c, d) || !slot(c, (void **)&c->reward, c->n_rewards,
					&c->cap_rewards, sizeof(evo_reward)))
		return -1;
	c->reward[c->n_rewards].def = *d;
	evo_reward_reset(&c->reward[c->n_rewards]);
	return c->n_rewards++;
}

static int check_control(evo_scene_core *c, const evo_control_def *d)
{
	const char *name = evo_control_kind_name(d->kind);
	if (check_piece(c, "control", name, evo_control_kind_dims(d->kind),
			d->bot, d->target))
		return -1;
	if (d->ticks < c->dim->timeout_shift)
		return evo_fail(&c->err,
				"control %s: ticks must be %ld or more", name,
				c->dim->timeout_shift);
	if (d->kind == EVO_CF_NEXT_ON_SENSOR_BELOW &&
	    (d->sensor < 0 || d->sensor >= c->bot[d->bot].n_sensors))
		return evo_fail(&c->err, "control %s: no sensor %d", name,
				d->sensor);
	if (d->kind == EVO_CF_NEXT_ON_TARGET_REACHED &&
	    (d->target == EVO_TARGET_NONE || !(d->threshold >= 0)))
		return evo_fail(&c->err,
				"control %s needs a target and a threshold of "
				"0 or more",
				name);
	if (d->kind == EVO_CF_NEXT_ON_COLLISION_WITH_TARGET) {
		const evo_element *e =
		    d->target >= 0 && d->target < c->n_elements
			? &c->element[d->target]
			: NULL;
		if (!e || (e->kind != EVO_PIECE_OBJECT &&
			   !evo_element_is_solid(e->kind)))
			return evo_fail(&c->err,
					"control %s needs an element a bot can "
					"touch: a cylinder, box or object (or "
					"a 3D sphere)",
					name);
		c->keeps_touches = 1;
	}
	return 0;
}

int evo_core_add_control(evo_scene_core *c, const evo_control_def *d)
{
	if ((unsigned)d->kind >= EVO_CF_KIND_COUNT)
		return evo_fail(&c->err, "control: unknown kind %d",
				(int)d->kind);
	evo_control *k = check_control(c, d)
			     ? NULL
			     : slot(c, (void **)&c->control, c->n_controls,
				    &c->cap_controls, sizeof *k);
	if (!k)
		return -1;
	k->def = *d;
	/* 3D's episode ends at tick `ticks` (evo_scene_dim) */
	k->def.ticks = d->ticks - c->dim->timeout_shift;
	evo_control_reset(k);
	return c->n_controls++;
}

/* ---- metrics, teams ---------------------------------------------------- */

int evo_core_add_metric(evo_scene_core *c, const char *name)
{
	return evo_metric_add(c->metric, &c->n_metrics, name, &c->err);
}

int evo_core_set_metric(evo_scene_core *c, int metric, double value)
{
	return evo_metric_set(c->metric, c->n_metrics, metric, value, &c->err);
}

int evo_core_find_metric(const evo_scene_core *c, const char *name)
{
	return evo_metric_find(c->metric, c->n_metrics, name);
}

void evo_core_note_team(evo_scene_core *c, int team)
{
	if (team >= c->n_teams)
		c->n_teams = team + 1;
}

/* ---- bots ---------------------------------------------------------------- */

evo_bot *evo_core_add_bot(evo_scene_core *c, const evo_bot_def *d,
			  const char *dflt)
{
	if (!isfinite(d->pos[0]) || !isfinite(d->pos[1]) ||
	    !isfinite(d->pos[2]) || !isfinite(d->yaw)) {
		evo_fail(&c->err, "bot: its position or yaw is not a number");
		return NULL;
	}
	if (d->name && d->name[0] && EVO_FIND(c, bot, evo_bot, d->name) >= 0) {
		evo_fail(&c->err, "bot '%s' is defined twice", d->name);
		return NULL;
	}
	if (d->team < -1 || d->team >= EVO_SCENE_MAX_TEAMS) {
		evo_fail(&c->err, "bot: no team %d (at most %d teams)", d->team,
			 EVO_SCENE_MAX_TEAMS);
		return NULL;
	}
	evo_bot *b = evo_store_add((void **)&c->bot, &c->cap_bots, c->n_bots,
				   sizeof *b, &c->err);
	if (!b || evo_store_name(b->name, d->name, dflt, c->n_bots, &c->err))
		return NULL;
	b->def = *d;
	b->def.name = NULL;
	b->body = EVO_BODY_NONE;
	b->team = d->team;
	for (int k = 0; k < 3; k++)
		b->start[k] = d->pos[k];
	b->start_yaw = d->yaw;
	evo_core_note_team(c, d->team);
	return b;
}

/* ---- the episode --------------------------------------------------------- */

void evo_core_reset(evo_scene_core *c, uint64_t grid_seed,
		    uint64_t episode_seed)
{
	for (int i = 0; i < c->n_rewards; i++)
		evo_reward_reset(&c->reward[i]);
	for (int i = 0; i < c->n_controls; i++)
		evo_control_reset(&c->control[i]);
	for (int i = 0; i < c->n_metrics; i++)
		c->metric[i].value = 0;
	c->rng = evo_rng_seed(episode_seed);
	c->grid_seed = grid_seed;
	c->tick = 0;
	c->step_reward = c->episode_reward = 0;
	memset(c->team_reward, 0, sizeof c->team_reward);
	c->winner = -1;
	c->fault[0] = 0;
}

void evo_core_pay(void *core, const evo_reward *r, double v)
{
	evo_scene_core *c = core;
	if (r->def.scope == EVO_SCOPE_TEAM) {
		c->team_reward[r->def.team] += v;
	} else if (r->def.scope == EVO_SCOPE_BOT && r->def.bot >= 0 &&
		   r->def.bot < c->n_bots) {
		evo_bot *b = &c->bot[r->def.bot];
		b->reward += v;
		if (b->team >= 0)
			c->team_reward[b->team] += v;
	}
}

int evo_core_score(evo_scene_core *c)
{
	evo_scored s = {c->dim->score, c, &c->hooks, &c->err};
	return evo_score_step(&s, c->reward, c->n_rewards, c->control,
			      c->n_controls, &c->step_reward,
			      &c->episode_reward);
}
