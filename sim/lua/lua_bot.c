/* A bot's methods in the scene scripts' `evo` module (docs/lua.md,
 * docs/world3d.md), one set for a bot of either world: adding the
 * sensors and actuators of sim/scene/kinds.c's rows (bot:proximity,
 * bot:wheel...), pointing trackers, reading its pose, sensors, commands
 * and counts, and placing it. What each does in a world is the
 * dimension's table's (lua_dim2d.c, lua_dim3d.c). */
#include <string.h>

#include "lua/lua_internal.h"

/* ---- sensors and actuators ---------------------------------------------- */

/* bot:NAME{...} of a sensor (upvalue 3: 1) or actuator (0) kind (upvalue
 * 1), named "bot:NAME" (upvalue 2): its number on the bot, from 1. */
static int bot_add(lua_State *L)
{
	int kind = (int)lua_tointeger(L, lua_upvalueindex(1));
	const char *what = lua_tostring(L, lua_upvalueindex(2));
	int sensor = lua_toboolean(L, lua_upvalueindex(3));
	int bot = evo_lua_check_bot(L, 1);
	const evo_kind_row *row =
	    sensor ? evo_sense_kind_row(kind) : evo_act_kind_row(kind);
	evo_lua_options(L, 2, what, evo_lua_kind_keys(L, row, what));
	const evo_lua_dim *dim = evo_lua_ctx(L)->dim;
	int i = sensor ? dim->add_sensor(L, bot, kind, what)
		       : dim->add_actuator(L, bot, kind, what);
	lua_pushinteger(L, i + 1);
	return 1;
}

/* Set bot_add as method name of kind into the table at the top. */
static void set_add(lua_State *L, const char *name, int kind, int sensor)
{
	lua_pushinteger(L, kind);
	lua_pushfstring(L, "bot:%s", name);
	lua_pushboolean(L, sensor);
	lua_pushcclosure(L, bot_add, 3);
	lua_setfield(L, -2, name);
}

/* bot:target(sensor name, element or "nearest_object"...): what a
 * tracker looks at (EvoAgents' setTarget). */
static int bot_target(lua_State *L)
{
	int bot = evo_lua_check_bot(L, 1);
	int s = evo_lua_bot_sensor_index(L, bot, luaL_checkstring(L, 2),
					 "bot:target");
	lua_settop(L, 3);
	lua_newtable(L);
	lua_pushvalue(L, 3);
	lua_setfield(L, -2, "target");
	int t = evo_lua_opt_target(L, 4, "target", "bot:target");
	evo_lua_ctx(L)->dim->set_target(L, bot, s, t);
	return 0;
}

/* ---- pose and place ------------------------------------------------------ */

/* bot:pose(): x, y[, z] and its heading in degrees; bot:pos(): x, y[, z]. */
static int push_pose(lua_State *L, int with_yaw)
{
	evo_lua *l = evo_lua_ctx(L);
	double p[3], yaw;
	l->dim->pose(l, evo_lua_check_bot(L, 1), p, &yaw);
	for (int k = 0; k < l->dim->coords; k++)
		lua_pushnumber(L, p[k]);
	if (with_yaw)
		lua_pushnumber(L, yaw / EVO_LUA_DEG);
	return l->dim->coords + with_yaw;
}

static int bot_pose(lua_State *L)
{
	return push_pose(L, 1);
}

static int bot_pos(lua_State *L)
{
	return push_pose(L, 0);
}

/* bot:place(x, y[, z][, angle]), or in 3D bot:place{x, y, z, yaw}: this
 * episode's start (in reset); what a table leaves out stays as it was. */
static int bot_place(lua_State *L)
{
	const char *what = "bot:place";
	evo_lua *l = evo_lua_ctx(L);
	int bot = evo_lua_check_bot(L, 1);
	int n = l->dim->coords;
	double p[3], yaw;
	l->dim->start(l, bot, p, &yaw);
	const char *const *keys = l->dim->place_keys;
	if (lua_istable(L, 2) && keys) {
		evo_lua_check_keys(L, 2, what, keys);
		evo_lua_opt_pos(L, 2, p, what);
		/* the turn is the last of the keys: angle, or yaw in 3D */
		while (keys[1])
			keys++;
		EVO_LUA_NUMS(L, 2, what, {keys[0], &yaw, EVO_LUA_DEG});
	} else {
		for (int k = 0; k < n; k++)
			p[k] = luaL_checknumber(L, 2 + k);
		yaw = luaL_optnumber(L, 2 + n, 0) * EVO_LUA_DEG;
	}
	for (int k = 0; k < n; k++)
		if (!isfinite(p[k]))
			luaL_error(L, "%s: a value is not a number", what);
	if (!isfinite(yaw))
		luaL_error(L, "%s: a value is not a number", what);
	evo_lua_scene_result(L, l->dim->place_bot(l, bot, p, yaw));
	return 0;
}

/* ---- reading -------------------------------------------------------------- */

static int bot_value(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int bot = evo_lua_check_bot(L, 1);
	int s = evo_lua_bot_sensor_index(L, bot, luaL_checkstring(L, 2),
					 "bot:value");
	lua_pushnumber(L, l->dim->sample(l, bot, s));
	return 1;
}

/* bot:command(name): what its mind last asked of actuator name. */
static int bot_command(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int bot = evo_lua_check_bot(L, 1);
	const char *name = luaL_checkstring(L, 2);
	double c;
	int team;
	if (l->dim->command(l, bot, name, &c) < 0)
		luaL_error(L, "bot:command: bot '%s' has no actuator '%s'",
			   l->dim->bot(l, bot, &team), name);
	lua_pushnumber(L, c);
	return 1;
}

/* bot:counts(): what the bot did since the reset (a 3D bot carries and
 * gathers nothing). */
static int bot_counts(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_lua_counts c;
	l->dim->counts(l, evo_lua_check_bot(L, 1), &c);
	const struct {
		const char *name;
		int n;
	} whole[] = {{"touching", c.touching},
		     {"collisions", c.collisions},
		     {"delivered", c.delivered},
		     {"gathered", c.gathered}};
	lua_newtable(L);
	for (int i = 0; i < 4; i++) {
		lua_pushinteger(L, whole[i].n);
		lua_setfield(L, -2, whole[i].name);
	}
	lua_pushnumber(L, c.reward);
	lua_setfield(L, -2, "reward");
	lua_pushboolean(L, c.holding);
	lua_setfield(L, -2, "holding");
	return 1;
}

/* The sensor kind named kind (its row's name or another of its names);
 * an unknown one is an error listing those of the scene's world. */
static int sensor_kind(lua_State *L, const char *kind)
{
	int k = evo_sense_kind_by_name(kind);
	if (k >= 0)
		return k;
	unsigned dim = evo_lua_ctx(L)->dim->dim;
	luaL_Buffer b;
	luaL_buffinit(L, &b);
	for (int i = 0, n = 0; i < EVO_SENSE_KIND_COUNT; i++)
		if (evo_sense_kind_row(i)->dims & dim) {
			luaL_addstring(&b, n++ ? ", " : "");
			luaL_addstring(&b, evo_sense_kind_row(i)->name);
		}
	luaL_pushresult(&b);
	return luaL_error(L, "bot:sensors: unknown kind '%s' (known: %s)", kind,
			  lua_tostring(L, -1));
}

/* bot:sensors([kind[, "untargeted"]]): the names of the bot's sensors (of
 * a kind), in the order the bot model added them; with "untargeted",
 * only those that look at nothing yet (for bot:target). Environments use
 * it to work with any bot model instead of naming one model's sensors. */
static int bot_sensors(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int bot = evo_lua_check_bot(L, 1);
	const char *kind = luaL_optstring(L, 2, NULL);
	const char *filter = luaL_optstring(L, 3, NULL);
	if (filter && strcmp(filter, "untargeted") != 0)
		luaL_error(L,
			   "bot:sensors: the filter is \"untargeted\", found "
			   "\"%s\"",
			   filter);
	int k = kind ? sensor_kind(L, kind) : -1;
	lua_newtable(L);
	lua_Integer n = 0;
	evo_lua_sensor se;
	for (int i = 0; i < l->dim->sensor(l, bot, i, &se); i++) {
		if ((kind && se.kind != k) ||
		    (filter && se.target != EVO_TARGET_NONE))
			continue;
		lua_pushstring(L, se.name);
		lua_seti(L, -2, ++n);
	}
	return 1;
}

/* bot:team(): its team's name, or nil. */
static int bot_team(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int t;
	l->dim->bot(l, evo_lua_check_bot(L, 1), &t);
	if (t >= 0 && t < l->n_teams)
		lua_pushstring(L, l->team[t].name);
	else
		lua_pushnil(L);
	return 1;
}

static int bot_name(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int team;
	lua_pushstring(L, l->dim->bot(l, evo_lua_check_bot(L, 1), &team));
	return 1;
}

static const luaL_Reg bot_methods[] = {{"target", bot_target},
				       {"pose", bot_pose},
				       {"pos", bot_pos},
				       {"place", bot_place},
				       {"value", bot_value},
				       {"command", bot_command},
				       {"counts", bot_counts},
				       {"sensors", bot_sensors},
				       {"name", bot_name},
				       {"team", bot_team},
				       {NULL, NULL}};

void evo_lua_bot_methods(lua_State *L)
{
	luaL_setfuncs(L, bot_methods, 0);
	for (int k = 0; k < EVO_SENSE_KIND_COUNT; k++)
		set_add(L, evo_sense_kind_row(k)->name, k, 1);
	int kind;
	for (int i = 0; evo_sense_kind_alias(i, &kind); i++)
		set_add(L, evo_sense_kind_alias(i, &kind), kind, 1);
	for (int k = 0; k < EVO_ACT_KIND_COUNT; k++)
		set_add(L, evo_act_kind_row(k)->name, k, 0);
}
