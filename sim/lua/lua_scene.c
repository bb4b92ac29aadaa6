/* The scene's methods in the scene scripts' `evo` module (docs/lua.md,
 * docs/world3d.md), one set for a scene of either dimension: adding bots
 * and the pieces of sim/scene/kinds.c's rows (scene:cylinder, scene:wall,
 * scene:physics...), the teams, looking pieces up, the lights and floor
 * patches, the episode's randomness and figures. What a piece is in each
 * world is the dimension's table's (lua_dim2d.c, lua_dim3d.c); rewards,
 * controls and metrics are lua_scoring.c's. */
#include <string.h>

#include "lua/lua_internal.h"

/* ---- pieces and bots ----------------------------------------------------- */

/* scene:NAME{...} of a piece kind (upvalue 1) named "scene:NAME"
 * (upvalue 2): an element's handle, or nothing for the other pieces. */
static int scene_piece(lua_State *L)
{
	int kind = (int)lua_tointeger(L, lua_upvalueindex(1));
	const char *what = lua_tostring(L, lua_upvalueindex(2));
	const evo_kind_row *row = evo_piece_kind_row(kind);
	evo_lua_options(L, 2, what, evo_lua_kind_keys(L, row, what));
	const evo_lua_dim *dim = evo_lua_ctx(L)->dim;
	if (kind > EVO_PIECE_LAST_ELEMENT) {
		dim->add_part(L, kind, what);
		return 0;
	}
	evo_lua_in_init(L, what);
	int i = dim->add_element(L, kind, what);
	evo_lua_push_handle(L, EVO_LUA_ELEMENT_MT, i);
	return 1;
}

/* scene:bot{name, x, y[, z], angle or yaw, model, team}: a bot of the
 * task's BOTMODEL (or model, or its team's), built by the model's
 * build(bot). A team's bot is named after the team and its member number
 * (docs/teams.md). */
static int scene_bot(lua_State *L)
{
	const char *what = "scene:bot";
	evo_lua *l = evo_lua_ctx(L);
	evo_lua_options(L, 2, what, l->dim->bot_keys);
	evo_lua_in_init(L, what);
	char auto_name[64];
	const char *model;
	int team = evo_lua_bot_team(L, 2, what, *l->v.n_bots, &model, auto_name,
				    sizeof auto_name);
	lua_settop(L, 2);
	/* the model's table at 3 */
	evo_lua_load_model(L, l, model,
			   team >= 0 ? l->team[team].mind_dir : NULL);
	const char *name = evo_lua_opt_str(L, 2, "name", auto_name, what);
	int i = l->dim->add_bot(L, team, name, what);
	if (team >= 0)
		l->team[team].made++;
	lua_getfield(L, 3, "build");
	if (!lua_isfunction(L, -1))
		luaL_error(L, "bot model %s: has no build(bot) function",
			   model);
	evo_lua_push_handle(L, EVO_LUA_BOT_MT, i);
	lua_call(L, 1, 0);
	evo_lua_push_handle(L, EVO_LUA_BOT_MT, i);
	return 1;
}

/* scene:teams(): the task's teams, {name, size, model, index} each. */
static int scene_teams(lua_State *L)
{
	evo_lua_push_teams(L);
	return 1;
}

/* scene:bots([team]): the bots of a team in member order, or every bot. */
static int scene_bots(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int team =
	    lua_isnoneornil(L, 2)
		? -2
		: evo_lua_check_team(L, luaL_checkstring(L, 2), "scene:bots");
	lua_newtable(L);
	int n = 0;
	for (int i = 0, t; i < *l->v.n_bots; i++)
		if (l->dim->bot(l, i, &t) && (team == -2 || t == team)) {
			evo_lua_push_handle(L, EVO_LUA_BOT_MT, i);
			lua_rawseti(L, -2, ++n);
		}
	return 1;
}

/* scene:winner(team) sets the episode's winner (nil: none);
 * scene:winner() returns its name, or nil. */
static int scene_winner(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int w = evo_lua_winner(L, *l->v.winner);
	if (w == -2)
		return 1; /* the name pushed */
	*l->v.winner = w;
	return 0;
}

/* ---- looking up ---------------------------------------------------------- */

/* A handle of class mt to index i, or nil for i < 0. */
static int handle_or_nil(lua_State *L, const char *mt, int i)
{
	if (i < 0)
		lua_pushnil(L);
	else
		evo_lua_push_handle(L, mt, i);
	return 1;
}

static int scene_element(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	return handle_or_nil(L, EVO_LUA_ELEMENT_MT,
			     l->dim->find(l, luaL_checkstring(L, 2), 1));
}

/* scene:get_bot(name or number): the bot, or nil. */
static int scene_get_bot(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int n = *l->v.n_bots;
	int i;
	if (lua_type(L, 2) == LUA_TSTRING)
		i = l->dim->find(l, lua_tostring(L, 2), 0);
	else {
		/* 1-based; anything past the bots, however large, is nil */
		lua_Integer k = luaL_checkinteger(L, 2);
		i = k >= 1 && k <= n ? (int)k - 1 : -1;
	}
	return handle_or_nil(L, EVO_LUA_BOT_MT, i < n ? i : -1);
}

/* ---- lights, floor and colours (lua_swarm.c) ----------------------------- */

/* scene:light{x, y[, z], intensity, colour}, scene:patch{...}: the swarm
 * sensors' lights and floor. */
static int scene_light(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_lua_add_light(L, 2, l->dim->coords, l->v.swarm, l->v.err);
	return 0;
}

static int scene_patch(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_lua_add_patch(L, 2, l->dim->coords, l->v.swarm, l->v.err);
	return 0;
}

/* scene:colour(bot or element, colour): what cameras see it as. */
static int scene_colour(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	if (luaL_testudata(L, 2, EVO_LUA_BOT_MT))
		evo_lua_set_colour(L, EVO_BLOB_BOT, evo_lua_check_bot(L, 2),
				   l->v.swarm, l->v.err);
	else if (luaL_testudata(L, 2, EVO_LUA_ELEMENT_MT))
		evo_lua_set_colour(L, EVO_BLOB_ELEMENT,
				   evo_lua_check_element(L, 2), l->v.swarm,
				   l->v.err);
	else
		luaL_error(L, "scene:colour: a bot or an element, found %s",
			   luaL_typename(L, 2));
	return 0;
}

/* ---- the episode --------------------------------------------------------- */

/* scene:random([lo, hi]): the episode's stream (its seed differs for
 * every candidate), uniform in [lo, hi), [0, 1) by default. */
static int scene_random(lua_State *L)
{
	double lo = luaL_optnumber(L, 2, 0), hi = luaL_optnumber(L, 3, 1);
	lua_pushnumber(L, evo_rng_range(evo_lua_ctx(L)->v.rng, lo, hi));
	return 1;
}

/* scene:layout_random(lo, hi): the grid seed's stream, the same for every
 * candidate of a generation: for an episode's obstacles and starts. */
static int scene_layout_random(lua_State *L)
{
	double lo = luaL_optnumber(L, 2, 0), hi = luaL_optnumber(L, 3, 1);
	lua_pushnumber(L, evo_rng_range(&evo_lua_ctx(L)->layout_rng, lo, hi));
	return 1;
}

static int scene_tick(lua_State *L)
{
	lua_pushinteger(L, evo_lua_tick(evo_lua_ctx(L)));
	return 1;
}

static int scene_episode_reward(lua_State *L)
{
	lua_pushnumber(L, *evo_lua_ctx(L)->v.episode_reward);
	return 1;
}

/* scene:genome() -> the environment genome an OPENENDED run evaluates
 * this episode on, as text (docs/openended.md), or nil outside one. */
static int scene_genome(lua_State *L)
{
	const char *g = evo_lua_ctx(L)->genome;
	if (g)
		lua_pushstring(L, g);
	else
		lua_pushnil(L);
	return 1;
}

static const luaL_Reg scene_methods[] = {
    {"bot", scene_bot},
    {"get_bot", scene_get_bot},
    {"teams", scene_teams},
    {"bots", scene_bots},
    {"winner", scene_winner},
    {"light", scene_light},
    {"patch", scene_patch},
    {"colour", scene_colour},
    {"element", scene_element},
    {"random", scene_random},
    {"layout_random", scene_layout_random},
    {"tick", scene_tick},
    {"episode_reward", scene_episode_reward},
    {"genome", scene_genome},
    {"reward", evo_lua_scene_reward},
    {"control", evo_lua_scene_control},
    {"reset_rewards", evo_lua_scene_reset_rewards},
    {"metric", evo_lua_scene_metric},
    {NULL, NULL}};

void evo_lua_scene_methods(lua_State *L)
{
	luaL_setfuncs(L, scene_methods, 0);
	for (int k = 0; k < EVO_PIECE_KIND_COUNT; k++) {
		const char *name = evo_piece_kind_row(k)->name;
		lua_pushinteger(L, k);
		lua_pushfstring(L, "scene:%s", name);
		lua_pushcclosure(L, scene_piece, 2);
		lua_setfield(L, -2, name);
	}
}
