/* Option tables and handles for the scene scripts' `evo` module
 * (sim/lua/lua_internal.h). Lua holds handles, not pointers: a bot,
 * element or metric handle is a small userdata with its index in the
 * scene, and every method finds the scene through the state's registry.
 * Options come in tables; an option the function does not know is an
 * error naming the ones it does (for a piece, sensor or actuator, the
 * ones its row of sim/scene/kinds.c gives the scene's world), so a typo
 * in a script never goes unnoticed. */
#include <stdio.h>
#include <string.h>

#include "lua/lua_internal.h"

const char evo_lua_ctx_key = 'k';
const char evo_lua_scene_key = 's';

evo_lua *evo_lua_ctx(lua_State *L)
{
	lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_ctx_key);
	evo_lua *l = lua_touserdata(L, -1);
	lua_pop(L, 1);
	return l;
}

/* ---- option tables ----------------------------------------------------- */

const char *evo_lua_near(const char *word, const char *const *list,
			 size_t n)
{
	unsigned best;
	const char *pick = evo_closest_name(word, list, n, &best);
	size_t wl = strlen(word);
	/* near enough, and not a name that shares nothing with the word (a
	 * one-letter word is one edit from every one-letter name) */
	return pick && best <= (wl < 4 ? 1u : wl / 3 + 1) && best < wl ? pick
								       : NULL;
}

/* Raise an error for any key of the table at idx not in `known`. */
void evo_lua_check_keys(lua_State *L, int idx, const char *what,
			const char *const *known)
{
	luaL_checktype(L, idx, LUA_TTABLE);
	lua_pushnil(L);
	while (lua_next(L, idx)) {
		lua_pop(L, 1);
		if (lua_type(L, -1) != LUA_TSTRING) {
			luaL_error(L, "%s: option keys are names", what);
			return;
		}
		const char *k = lua_tostring(L, -1);
		int ok = 0;
		for (unsigned i = 0; known[i]; i++)
			ok |= strcmp(k, known[i]) == 0;
		if (!ok) {
			luaL_Buffer b;
			luaL_buffinit(L, &b);
			for (unsigned i = 0; known[i]; i++) {
				luaL_addstring(&b, i ? ", " : "");
				luaL_addstring(&b, known[i]);
			}
			luaL_pushresult(&b);
			size_t n = 0;
			while (known[n])
				n++;
			const char *near = evo_lua_near(k, known, n);
			if (near)
				luaL_error(L,
					   "%s: unknown option '%s'; did you "
					   "mean %s? (known: %s)",
					   what, k, near, lua_tostring(L, -1));
			luaL_error(L, "%s: unknown option '%s' (known: %s)",
				   what, k, lua_tostring(L, -1));
			return;
		}
	}
}

double evo_lua_opt_num(lua_State *L, int idx, const char *key, double dflt,
		       const char *what)
{
	lua_getfield(L, idx, key);
	double v = dflt;
	if (!lua_isnil(L, -1)) {
		int isnum;
		v = lua_tonumberx(L, -1, &isnum);
		if (!isnum)
			luaL_error(L, "%s: option '%s' must be a number, found %s",
				   what, key, luaL_typename(L, -1));
		if (!isfinite(v))
			luaL_error(L, "%s: option '%s' must be a finite number, "
				   "found %f", what, key, (lua_Number)v);
	}
	lua_pop(L, 1);
	return v;
}

void evo_lua_opt_nums(lua_State *L, int idx, const char *what,
		      const evo_lua_num *nums)
{
	for (const evo_lua_num *n = nums; n->key; n++) {
		double unit = n->unit ? n->unit : 1;
		*n->v = evo_lua_opt_num(L, idx, n->key, *n->v / unit, what) *
			unit;
	}
}

const char *evo_lua_opt_str(lua_State *L, int idx, const char *key,
			    const char *dflt, const char *what)
{
	lua_getfield(L, idx, key);
	const char *v = dflt;
	if (!lua_isnil(L, -1)) {
		if (lua_type(L, -1) != LUA_TSTRING)
			luaL_error(L, "%s: option '%s' must be a string, found %s",
				   what, key, luaL_typename(L, -1));
		v = lua_tostring(L, -1); /* kept alive by the table */
	}
	lua_pop(L, 1);
	return v;
}

/* ---- handles ------------------------------------------------------------ */

void evo_lua_push_handle(lua_State *L, const char *mt, int index)
{
	int *p = lua_newuserdatauv(L, sizeof *p, 0);
	*p = index;
	luaL_setmetatable(L, mt);
}

int evo_lua_check_bot(lua_State *L, int idx)
{
	int i = *(int *)luaL_checkudata(L, idx, EVO_LUA_BOT_MT);
	if (i < 0 || i >= *evo_lua_ctx(L)->v.n_bots)
		luaL_error(L, "stale bot handle");
	return i;
}

int evo_lua_check_element(lua_State *L, int idx)
{
	int i = *(int *)luaL_checkudata(L, idx, EVO_LUA_ELEMENT_MT);
	if (i < 0 || i >= *evo_lua_ctx(L)->v.n_elements)
		luaL_error(L, "stale element handle");
	return i;
}

int evo_lua_check_metric(lua_State *L, int idx)
{
	int i = *(int *)luaL_checkudata(L, idx, EVO_LUA_METRIC_MT);
	int *n;
	evo_err *err;
	evo_lua_metrics(evo_lua_ctx(L), &n, &err);
	if (i < 0 || i >= *n)
		luaL_error(L, "stale metric handle");
	return i;
}

/* A target option: an element handle, "nearest_object",
 * "nearest_opponent", "nearest_teammate", or nil. */
int evo_lua_opt_target(lua_State *L, int idx, const char *key, const char *what)
{
	lua_getfield(L, idx, key);
	int t = EVO_TARGET_NONE;
	if (lua_type(L, -1) == LUA_TSTRING) {
		const char *v = lua_tostring(L, -1);
		const evo_lua_dim *dim = evo_lua_ctx(L)->dim;
		if (!dim->named_targets)
			luaL_error(L,
				   "%s: %s must be an element; \"%s\" and the "
				   "other nearest targets are 2D only, and "
				   "this is a %s scene",
				   what, key, v, dim->words);
		if (strcmp(v, "nearest_object") == 0)
			t = EVO_TARGET_NEAREST_OBJECT;
		else if (strcmp(v, "nearest_opponent") == 0)
			t = EVO_TARGET_NEAREST_OPPONENT;
		else if (strcmp(v, "nearest_teammate") == 0)
			t = EVO_TARGET_NEAREST_TEAMMATE;
		else
			luaL_error(L,
				   "%s: %s must be an element, "
				   "\"nearest_object\", \"nearest_opponent\" "
				   "or \"nearest_teammate\", found \"%s\"",
				   what, key, v);
	} else if (!lua_isnil(L, -1)) {
		if (!luaL_testudata(L, -1, EVO_LUA_ELEMENT_MT))
			luaL_error(L, "%s: %s must be an element, found %s",
				   what, key, luaL_typename(L, -1));
		t = evo_lua_check_element(L, lua_gettop(L));
	}
	lua_pop(L, 1);
	return t;
}

int evo_lua_check_team(lua_State *L, const char *name, const char *what)
{
	evo_lua *l = evo_lua_ctx(L);
	const char *names[EVO_SCENE_MAX_TEAMS];
	for (int i = 0; i < l->n_teams; i++) {
		if (strcmp(l->team[i].name, name) == 0)
			return i;
		names[i] = l->team[i].name;
	}
	if (l->n_teams == 0)
		return luaL_error(L,
				  "%s: no team %s: the task has no teams "
				  "(TEAM lines, docs/teams.md)",
				  what, name);
	const char *c = evo_closest_name(name, names, (size_t)l->n_teams, NULL);
	return luaL_error(L, "%s: no team %s in the task (did you mean %s?)",
			  what, name, c ? c : "?");
}

int evo_lua_opt_team(lua_State *L, int idx, const char *what)
{
	lua_getfield(L, idx, "team");
	int t = -1;
	if (!lua_isnil(L, -1)) {
		if (lua_type(L, -1) != LUA_TSTRING)
			luaL_error(L,
				   "%s: team must be a team's name, found %s",
				   what, luaL_typename(L, -1));
		t = evo_lua_check_team(L, lua_tostring(L, -1), what);
	}
	lua_pop(L, 1);
	return t;
}

int evo_lua_bot_team(lua_State *L, int idx, const char *what, int n_bots,
		     const char **model, char *name, size_t cap)
{
	evo_lua *l = evo_lua_ctx(L);
	int team = evo_lua_opt_team(L, idx, what);
	if (team < 0) {
		*model = evo_lua_opt_str(L, idx, "model", l->botmodel, what);
		if (!(*model)[0] && l->n_teams > 0)
			luaL_error(L,
				   "%s: in a team task, a bot belongs to a "
				   "team (scene:bot{team = NAME}) or names "
				   "its model",
				   what);
		if (!(*model)[0])
			luaL_error(L, "%s: the task names no BOTMODEL", what);
		snprintf(name, cap, "bot%d", n_bots + 1);
		return -1;
	}
	lua_getfield(L, idx, "model");
	if (!lua_isnil(L, -1))
		luaL_error(L, "%s: a bot of team %s is of its model, %s; leave "
			      "model out",
			   what, l->team[team].name, l->team[team].botmodel);
	lua_pop(L, 1);
	if (l->team[team].made == l->team[team].size)
		luaL_error(L,
			   "%s: team %s has its %d bots already (its SIZE in "
			   "the task)",
			   what, l->team[team].name, l->team[team].size);
	*model = l->team[team].botmodel;
	snprintf(name, cap, "%s%d", l->team[team].name,
		 l->team[team].made + 1);
	return team;
}

void evo_lua_push_teams(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	lua_createtable(L, l->n_teams, 0);
	for (int i = 0; i < l->n_teams; i++) {
		lua_createtable(L, 0, 4);
		lua_pushstring(L, l->team[i].name);
		lua_setfield(L, -2, "name");
		lua_pushinteger(L, l->team[i].size);
		lua_setfield(L, -2, "size");
		lua_pushstring(L, l->team[i].botmodel);
		lua_setfield(L, -2, "model");
		lua_pushinteger(L, i + 1);
		lua_setfield(L, -2, "index");
		lua_rawseti(L, -2, i + 1);
	}
}

int evo_lua_winner(lua_State *L, int winner)
{
	evo_lua *l = evo_lua_ctx(L);
	if (lua_gettop(L) < 2) {
		if (winner >= 0 && winner < l->n_teams)
			lua_pushstring(L, l->team[winner].name);
		else
			lua_pushnil(L);
		return -2;
	}
	return lua_isnil(L, 2) ? -1
			       : evo_lua_check_team(L, luaL_checkstring(L, 2),
						    "scene:winner");
}

int evo_lua_opt_bot(lua_State *L, int idx, const char *what)
{
	lua_getfield(L, idx, "bot");
	int b = 0;
	if (!lua_isnil(L, -1)) {
		if (!luaL_testudata(L, -1, EVO_LUA_BOT_MT))
			luaL_error(L, "%s: bot must be a bot, found %s", what,
				   luaL_typename(L, -1));
		b = evo_lua_check_bot(L, lua_gettop(L));
	} else if (*evo_lua_ctx(L)->v.n_bots == 0) {
		luaL_error(L, "%s: there is no bot yet", what);
	}
	lua_pop(L, 1);
	return b;
}

/* Names looked at for "did you mean". */
#define NAMES_MAX 256

int evo_lua_bot_sensor_index(lua_State *L, int bot, const char *name,
			     const char *what)
{
	const evo_lua *l = evo_lua_ctx(L);
	const evo_lua_dim *dim = l->dim;
	evo_lua_sensor se;
	const char *names[NAMES_MAX];
	int m = 0, team;
	for (int i = 0; i < dim->sensor(l, bot, i, &se); i++) {
		if (strcmp(se.name, name) == 0)
			return i;
		if (m < NAMES_MAX)
			names[m++] = se.name;
	}
	/* the closest of its sensors' names */
	const char *near = evo_lua_near(name, names, (size_t)m);
	if (near)
		luaL_error(L, "%s: bot '%s' has no sensor '%s'; did you mean %s?",
			   what, dim->bot(l, bot, &team), name, near);
	return luaL_error(L, "%s: bot '%s' has no sensor '%s'", what,
			  dim->bot(l, bot, &team), name);
}

/* Turn a scene error into a Lua error at the caller's line. */
int evo_lua_scene_result(lua_State *L, int r)
{
	if (r < 0)
		luaL_error(L, "%s", evo_lua_ctx(L)->v.err->msg);
	return r;
}

void evo_lua_options(lua_State *L, int idx, const char *what,
		     const char *const *keys)
{
	if (lua_isnoneornil(L, idx)) {
		lua_settop(L, idx - 1);
		lua_newtable(L);
	}
	evo_lua_check_keys(L, idx, what, keys);
}

void evo_lua_opt_pos(lua_State *L, int idx, double p[3], const char *what)
{
	static const char *const xyz[] = {"x", "y", "z"};
	int n = evo_lua_ctx(L)->dim->coords;
	for (int k = 0; k < n; k++)
		p[k] = evo_lua_opt_num(L, idx, xyz[k], p[k], what);
}

void evo_lua_in_init(lua_State *L, const char *what)
{
	if (evo_lua_ctx(L)->in_reset)
		luaL_error(L,
			   "%s: elements are made in init and placed in reset "
			   "(made in reset, one more would pile up every "
			   "episode), as are bots, rewards and controls; "
			   "per-episode obstacles come from %s (docs/lua.md)",
			   what,
			   evo_lua_ctx(L)->dim->dim == EVO_DIM_3D
			       ? "scene:obstacle{...}"
			       : "env.obstacles");
}

const char *const *evo_lua_kind_keys(lua_State *L, const evo_kind_row *row,
				     const char *what)
{
	const evo_lua_dim *dim = evo_lua_ctx(L)->dim;
	const char *const *keys = evo_kind_keys(row, dim->dim);
	if (!keys)
		luaL_error(L,
			   "%s: %s is %s only, and this is a %s scene "
			   "(docs/lua.md, \"Which world has what\")",
			   what, row->name,
			   dim->dim == EVO_DIM_3D ? "2D" : "3D", dim->words);
	return keys;
}

int evo_lua_kind_of(const int *rows, int n, int kind)
{
	int k = 0;
	while (k < n - 1 && rows[k] != kind)
		k++;
	return k;
}

const char *evo_lua_opt_name(lua_State *L, const char *what, const char *noun)
{
	const char *name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!name)
		luaL_error(L, "%s: %s %s needs a name", what,
			   strchr("aeiou", noun[0]) ? "an" : "a", noun);
	return name;
}

unsigned evo_lua_opt_words(lua_State *L, int idx, const char *key,
			   const char *const *words, int n, const char *what,
			   int *given)
{
	unsigned mask = 0;
	*given = lua_getfield(L, idx, key) != LUA_TNIL;
	if (*given) {
		luaL_checktype(L, -1, LUA_TTABLE);
		lua_Integer len = luaL_len(L, -1);
		for (lua_Integer i = 1; i <= len; i++) {
			lua_geti(L, -1, i);
			const char *s = lua_tostring(L, -1);
			int w = 0;
			while (w < n && !(s && strcmp(s, words[w]) == 0))
				w++;
			if (w == n) {
				luaL_Buffer b;
				luaL_buffinit(L, &b);
				for (int k = 0; k < n; k++) {
					luaL_addstring(&b, k == 0 ? "\""
						       : k < n - 1 ? ", \""
								   : " or \"");
					luaL_addstring(&b, words[k]);
					luaL_addstring(&b, "\"");
				}
				luaL_pushresult(&b);
				luaL_error(L, "%s: %s lists %s, found %s", what,
					   key, lua_tostring(L, -1),
					   s ? s : luaL_typename(L, -2));
			}
			mask |= 1u << w;
			lua_pop(L, 1);
		}
	}
	lua_pop(L, 1);
	return mask;
}
