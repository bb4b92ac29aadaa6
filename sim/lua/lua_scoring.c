/* How a scene script scores an episode, in either world (docs/lua.md,
 * docs/world3d.md): scene:reward and scene:control, by a built-in
 * function's name (sim/scene/kinds.c's rows, which say the worlds each
 * exists in) or as a Lua function (sim/lua/lua_hooks.c calls it each
 * tick), scene:reset_rewards, and the environment's metrics
 * (scene:metric and a metric's methods). */
#include <string.h>

#include "lua/lua_internal.h"

/* A Lua function's options, {reset = f, bot = b, team = NAME} (bot and
 * team for a reward only): f goes on the list under resets_key, called
 * with the scene at every episode's reset (and, for a reward, by
 * scene:reset_rewards). */
void evo_lua_function_options(lua_State *L, const char *what,
			      const void *resets_key, int reward)
{
	static const char *const keys[] = {"reset", NULL};
	static const char *const rkeys[] = {"reset", "bot", "team", NULL};
	if (lua_isnoneornil(L, 3))
		return;
	evo_lua_check_keys(L, 3, what, reward ? rkeys : keys);
	if (lua_getfield(L, 3, "reset") == LUA_TNIL) {
		lua_pop(L, 1);
		return;
	}
	if (!lua_isfunction(L, -1))
		luaL_error(L, "%s: option 'reset' must be a function, found %s",
			   what, luaL_typename(L, -1));
	if (lua_rawgetp(L, LUA_REGISTRYINDEX, resets_key) != LUA_TTABLE) {
		lua_pop(L, 1);
		lua_newtable(L);
		lua_pushvalue(L, -1);
		lua_rawsetp(L, LUA_REGISTRYINDEX, resets_key);
	}
	lua_pushvalue(L, -2);
	lua_seti(L, -2, luaL_len(L, -2) + 1);
	lua_pop(L, 2);
}

/* The functions of one family, rewards or controls. */
typedef struct family {
	const char *what; /* "scene:reward", "scene:control" */
	const char *noun; /* "reward", "control" */
	int lua_kind;	  /* EVO_RW_LUA, EVO_CF_LUA */
	int (*by_name)(const char *);
	const char *(*name_of)(int);
	unsigned (*dims)(int);
	const void *resets_key;
} family;

static const family rewards = {"scene:reward",
			       "reward",
			       EVO_RW_LUA,
			       evo_reward_kind_by_name,
			       evo_reward_kind_name,
			       evo_reward_kind_dims,
			       &evo_lua_reward_resets_key};
static const family controls = {"scene:control",
				"control",
				EVO_CF_LUA,
				evo_control_kind_by_name,
				evo_control_kind_name,
				evo_control_kind_dims,
				&evo_lua_control_resets_key};

/* The built-in function named at 2, of the scene's dimension; an empty
 * options table is pushed at 3 when none was given. */
static int kind_by_name(lua_State *L, const family *f, const char *what)
{
	const evo_lua_dim *dim = evo_lua_ctx(L)->dim;
	const char *name = luaL_checkstring(L, 2);
	int kind = f->by_name(name);
	if (kind == f->lua_kind)
		luaL_error(L,
			   "%s: for a %s of your own, pass a Lua function, "
			   "not the name '%s'",
			   what, f->noun, name);
	if (kind >= 0 && !(f->dims(kind) & dim->dim))
		luaL_error(L, "%s: %s '%s' is %s only (docs/world3d.md)", what,
			   f->noun, name, dim->dim == EVO_DIM_3D ? "2D" : "3D");
	if (kind < 0) {
		/* the closest of the built-in names of this world */
		const char *names[64];
		size_t n = 0;
		for (int k = 0; n < 64 && f->name_of(k); k++)
			if (k != f->lua_kind && (f->dims(k) & dim->dim))
				names[n++] = f->name_of(k);
		const char *near = evo_lua_near(name, names, n);
		if (near)
			luaL_error(L,
				   "%s: unknown %s function '%s'; did you mean "
				   "%s? (or pass a Lua function for your own)",
				   what, f->noun, name, near);
		luaL_error(L,
			   "%s: unknown %s function '%s' (pass a Lua function "
			   "for your own)",
			   what, f->noun, name);
	}
	if (lua_isnoneornil(L, 3)) {
		lua_settop(L, 2);
		lua_newtable(L);
	}
	return kind;
}

/* The bots a built-in reward or control is for: its `bot` (the first bot
 * when absent), or with `team`, each bot of the team (docs/teams.md).
 * Fills bots (cap) and returns how many. */
static int scope_bots(lua_State *L, const char *what, int *bots, int cap)
{
	evo_lua *l = evo_lua_ctx(L);
	int team = evo_lua_opt_team(L, 3, what);
	if (team < 0) {
		bots[0] = evo_lua_opt_bot(L, 3, what);
		return 1;
	}
	lua_getfield(L, 3, "bot");
	if (!lua_isnil(L, -1))
		luaL_error(L, "%s: give bot or team, not both", what);
	lua_pop(L, 1);
	int n = 0;
	for (int i = 0, t; i < *l->v.n_bots && n < cap; i++)
		if (l->dim->bot(l, i, &t) && t == team)
			bots[n++] = i;
	if (n == 0)
		luaL_error(L,
			   "%s: team %s has no bots yet: make them "
			   "(scene:bot{team = ...}) before its rewards and "
			   "controls",
			   what, l->team[team].name);
	return n;
}

/* The sensors option of a reward, names resolved on d's bot. */
static void reward_sensors(lua_State *L, evo_reward_def *d, const char *what)
{
	d->n_sensors = 0;
	if (lua_getfield(L, 3, "sensors") != LUA_TNIL) {
		luaL_checktype(L, -1, LUA_TTABLE);
		lua_Integer n = luaL_len(L, -1);
		if (n > EVO_REWARD_MAX_SENSORS)
			luaL_error(L, "%s: at most %d sensors", what,
				   EVO_REWARD_MAX_SENSORS);
		for (lua_Integer i = 1; i <= n; i++) {
			lua_geti(L, -1, i);
			const char *s = lua_tostring(L, -1);
			if (!s)
				luaL_error(L, "%s: sensors are names", what);
			d->sensor[d->n_sensors++] =
			    evo_lua_bot_sensor_index(L, d->bot, s, what);
			lua_pop(L, 1);
		}
	}
	lua_pop(L, 1);
}

/* scene:reward(fn, {bot = b | team = NAME, reset = f}) and
 * scene:control(fn, {reset = f}): a Lua function as a reward (paid to the
 * scene, to bot, or to a team as a whole) or a control, called each tick
 * with the scene (sim/lua/lua_hooks.c). */
static int lua_function(lua_State *L, const family *f, const char *what)
{
	evo_lua *l = evo_lua_ctx(L);
	int reward = f == &rewards;
	if (*l->v.n_bots == 0)
		luaL_error(L, "%s: there is no bot yet", what);
	evo_lua_function_options(L, what, f->resets_key, reward);
	lua_pushvalue(L, 2);
	int ref = luaL_ref(L, LUA_REGISTRYINDEX);
	if (!reward) {
		evo_control_def d = evo_default_control_def(EVO_CF_LUA);
		d.lua_ref = ref;
		return evo_lua_scene_result(L, l->dim->add_control(l, &d));
	}
	evo_reward_def d = evo_default_reward_def(EVO_RW_LUA);
	d.lua_ref = ref;
	d.scope = EVO_SCOPE_SCENE;
	if (lua_istable(L, 3)) {
		int team = evo_lua_opt_team(L, 3, what);
		lua_getfield(L, 3, "bot");
		int has_bot = !lua_isnil(L, -1);
		lua_pop(L, 1);
		if (has_bot && team >= 0)
			luaL_error(L, "%s: give bot or team, not both", what);
		if (has_bot) {
			d.bot = evo_lua_opt_bot(L, 3, what);
			d.scope = EVO_SCOPE_BOT;
		} else if (team >= 0) {
			d.team = team;
			d.scope = EVO_SCOPE_TEAM;
		}
	}
	return evo_lua_scene_result(L, l->dim->add_reward(l, &d));
}

/* The start of scene:reward and scene:control: a Lua function added
 * (-1), or the kind of the built-in one named, its options (at 3)
 * checked against keys. */
static int function_or_kind(lua_State *L, const family *f,
			    const char *const *keys)
{
	const char *what = f->what;
	evo_lua_in_init(L, what);
	if (lua_isfunction(L, 2)) {
		lua_function(L, f, what);
		return -1;
	}
	int kind = kind_by_name(L, f, what);
	evo_lua_check_keys(L, 3, what, keys);
	return kind;
}

/* scene:reward(kind, {bot = b | team = NAME, ...}): with team, one such
 * reward for each bot of the team, each paying its own bot. */
int evo_lua_scene_reward(lua_State *L)
{
	static const char *const keys[] = {
	    "bot", "team", "k", "k2", "threshold", "target", "sensors", NULL};
	int kind = function_or_kind(L, &rewards, keys);
	if (kind < 0)
		return 0;
	const char *what = rewards.what;
	evo_lua *l = evo_lua_ctx(L);
	evo_reward_def d = evo_default_reward_def((evo_reward_kind)kind);
	EVO_LUA_NUMS(L, 3, what, {"k", &d.k, 0}, {"k2", &d.k2, 0},
		     {"threshold", &d.threshold, 0});
	d.target = evo_lua_opt_target(L, 3, "target", what);
	int bots[EVO_TEAM_BOTS_MAX];
	int n = scope_bots(L, what, bots, EVO_TEAM_BOTS_MAX);
	for (int i = 0; i < n; i++) {
		d.bot = bots[i];
		reward_sensors(L, &d, what);
		evo_lua_scene_result(L, l->dim->add_reward(l, &d));
	}
	return 0;
}

/* scene:control(kind, {bot = b | team = NAME, ...}): with team, one for
 * each bot of the team, the episode ending when any of them meets it. */
int evo_lua_scene_control(lua_State *L)
{
	static const char *const keys[] = {
	    "bot", "team", "ticks", "target", "sensor", "threshold", NULL};
	int kind = function_or_kind(L, &controls, keys);
	if (kind < 0)
		return 0;
	evo_control_def d = evo_default_control_def((evo_control_kind)kind);
	const char *what = controls.what;
	evo_lua *l = evo_lua_ctx(L);
	double ticks = evo_lua_opt_num(L, 3, "ticks", (double)d.ticks, what);
	if (ticks < l->dim->min_ticks || ticks != floor(ticks) || ticks > 1e15)
		luaL_error(L, "%s: ticks must be a whole number >= %d", what,
			   (int)l->dim->min_ticks);
	d.ticks = (long)ticks;
	d.target = evo_lua_opt_target(L, 3, "target", what);
	d.threshold = evo_lua_opt_num(L, 3, "threshold", d.threshold, what);
	const char *s = evo_lua_opt_str(L, 3, "sensor", NULL, what);
	int bots[EVO_TEAM_BOTS_MAX];
	int n = scope_bots(L, what, bots, EVO_TEAM_BOTS_MAX);
	for (int i = 0; i < n; i++) {
		d.bot = bots[i];
		if (s)
			d.sensor = evo_lua_bot_sensor_index(L, d.bot, s, what);
		evo_lua_scene_result(L, l->dim->add_control(l, &d));
	}
	return 0;
}

/* Forget what the reward functions remember (ClosingOnTarget's last
 * distance), e.g. after moving a target, and call the Lua rewards' own
 * resets: EvoAgents' r.reset(). */
int evo_lua_scene_reset_rewards(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	for (int i = 0; i < *l->v.n_rewards; i++)
		evo_reward_reset(&(*l->v.reward)[i]);
	evo_err err = {{0}};
	if (evo_lua_call_resets(l, &evo_lua_reward_resets_key, &err))
		luaL_error(L, "%s", err.msg);
	return 0;
}

/* ---- metrics (docs/lua.md, "Metrics of your own") ---------------------- */

/* scene:metric(name): declares the metric in env.init and returns its
 * handle; later, the handle of a declared one. The set is fixed once init
 * returns, so that every episode, every worker and a log.csv header agree
 * on it. */
int evo_lua_scene_metric(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int *n;
	evo_err *err;
	evo_metric *metric = evo_lua_metrics(l, &n, &err);
	const char *name = luaL_checkstring(L, 2);
	if (lua_gettop(L) > 2)
		luaL_error(L,
			   "scene:metric takes a metric's name only; change "
			   "its value through the handle it returns: "
			   "scene:metric(\"%s\"):set(x) or :add(x)",
			   name);
	int i = evo_metric_find(metric, *n, name);
	if (i < 0 && l->ready) {
		const char *names[EVO_SCENE_MAX_METRICS];
		for (int k = 0; k < *n; k++)
			names[k] = metric[k].name;
		const char *c = evo_closest_name(name, names, (size_t)*n, NULL);
		luaL_error(L,
			   "scene:metric: no metric '%s' was declared; "
			   "metrics are declared in env.init%s%s%s",
			   name, c ? " (closest: " : "", c ? c : "",
			   c ? ")" : "");
	}
	if (i < 0 && (i = evo_metric_add(metric, n, name, err)) < 0)
		luaL_error(L, "scene:metric: %s", err->msg);
	evo_lua_push_handle(L, EVO_LUA_METRIC_MT, i);
	return 1;
}

static evo_metric *metric_at(lua_State *L, int i)
{
	int *n;
	evo_err *err;
	return &evo_lua_metrics(evo_lua_ctx(L), &n, &err)[i];
}

/* Set metric i to v for `how` (set or add): a value that is not finite
 * is an error at the script's line, with the tick. */
static void metric_store(lua_State *L, int i, double v, const char *how,
			 double arg)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_metric *m = metric_at(L, i);
	lua_Integer tick = (lua_Integer)evo_lua_tick(l);
	if (!l->ready)
		luaL_error(L,
			   "metric '%s': %s in env.init, before any episode: "
			   "every episode starts at 0 (report it in reset, "
			   "post_step or a reward or control function)",
			   m->name, how);
	if (!isfinite(arg))
		luaL_error(L,
			   "metric '%s': %s(%f) at tick %I: not a finite "
			   "number",
			   m->name, how, arg, tick);
	if (!isfinite(v))
		luaL_error(L,
			   "metric '%s': %s(%f) at tick %I makes it %f, not "
			   "a finite number",
			   m->name, how, arg, tick, v);
	m->value = v;
}

static int metric_set(lua_State *L)
{
	int i = evo_lua_check_metric(L, 1);
	double v = luaL_checknumber(L, 2);
	metric_store(L, i, v, "set", v);
	return 0;
}

/* m:add(x): x defaults to 1, for counting. */
static int metric_add(lua_State *L)
{
	int i = evo_lua_check_metric(L, 1);
	double x = luaL_optnumber(L, 2, 1);
	metric_store(L, i, metric_at(L, i)->value + x, "add", x);
	return 0;
}

static int metric_value(lua_State *L)
{
	lua_pushnumber(L, metric_at(L, evo_lua_check_metric(L, 1))->value);
	return 1;
}

static int metric_name(lua_State *L)
{
	lua_pushstring(L, metric_at(L, evo_lua_check_metric(L, 1))->name);
	return 1;
}

static const luaL_Reg metric_methods[] = {{"set", metric_set},
					  {"add", metric_add},
					  {"value", metric_value},
					  {"name", metric_name},
					  {NULL, NULL}};

void evo_lua_metric_methods(lua_State *L)
{
	luaL_setfuncs(L, metric_methods, 0);
}
