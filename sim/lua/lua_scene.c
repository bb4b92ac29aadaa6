/* Scene, element and metric methods of the scene scripts' `evo` module
 * (docs/lua.md): adding bots, elements, the obstacle grid, rewards,
 * controls and metrics; reading and placing elements; reporting
 * metrics. */
#include <string.h>

#include "lua/lua_internal.h"
#include "world2d/actuators.h"
#include "world2d/rewards.h"

/* ---- elements ------------------------------------------------------------ */

static int element_pos(lua_State *L)
{
	const evo_element *e =
	    &evo_lua_ctx(L)->sc->element[evo_lua_check_element(L, 1)];
	lua_pushnumber(L, e->x);
	lua_pushnumber(L, e->y);
	return 2;
}

static int element_place(lua_State *L)
{
	int e = evo_lua_check_element(L, 1);
	double x = luaL_checknumber(L, 2), y = luaL_checknumber(L, 3);
	evo_scene *sc = evo_lua_ctx(L)->sc;
	if (!isfinite(x) || !isfinite(y))
		luaL_error(L, "element:place: a value is not a number");
	if (sc->element[e].kind == EVO_ELEM_CYLINDER ||
	    sc->element[e].kind == EVO_ELEM_BOX)
		luaL_error(L, "element:place: static elements do not move");
	evo_scene_place_element(sc, e, x, y);
	return 0;
}

static int element_active(lua_State *L)
{
	lua_pushboolean(
	    L, evo_lua_ctx(L)->sc->element[evo_lua_check_element(L, 1)].active);
	return 1;
}

static int element_set_active(lua_State *L)
{
	int i = evo_lua_check_element(L, 1);
	evo_scene *sc = evo_lua_ctx(L)->sc;
	evo_element *e = &sc->element[i];
	int on = lua_toboolean(L, 2);
	if (e->kind == EVO_ELEM_OBJECT) {
		if (!on && e->held_by >= 0)
			evo_bot_release(sc, e->held_by);
		evo_body_set_enabled(sc->world, e->body, on);
	}
	e->active = on;
	return 0;
}

static int element_name(lua_State *L)
{
	lua_pushstring(
	    L, evo_lua_ctx(L)->sc->element[evo_lua_check_element(L, 1)].name);
	return 1;
}

/* ---- scene ---------------------------------------------------------------- */

/* Each kind's options, as docs/lua.md lists them: a zone takes `size`, a
 * cylinder `radius`, and neither takes the other's. */
static const char *const cylinder_keys[] = {"x", "y", "radius", "name", NULL};
static const char *const box_keys[] = {"x",	      "y",     "half_width",
				       "half_height", "angle", "name",
				       NULL};
static const char *const zone_keys[] = {"x",	 "y",	 "size",
					"angle", "name", NULL};
static const char *const object_keys[] = {
    "x",	"y",	      "radius",		"name",		   "density",
    "friction", "restitution", "linear_damping", "angular_damping", NULL};

static int add_element(lua_State *L, evo_element_kind kind, const char *what)
{
	const char *const *keys = kind == EVO_ELEM_CYLINDER ? cylinder_keys
				  : kind == EVO_ELEM_BOX    ? box_keys
				  : kind == EVO_ELEM_ZONE   ? zone_keys
							    : object_keys;
	evo_lua_check_keys(L, 2, what, keys);
	if (evo_lua_ctx(L)->in_reset)
		luaL_error(L,
			   "%s: elements are made in init and placed in reset "
			   "(made in reset, one more would pile up every "
			   "episode); per-episode obstacles come from "
			   "env.obstacles (docs/lua.md)",
			   what);
	evo_element_def d = evo_default_element_def(kind);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	d.x = evo_lua_opt_num(L, 2, "x", 0, what);
	d.y = evo_lua_opt_num(L, 2, "y", 0, what);
	d.angle = evo_lua_opt_num(L, 2, "angle", 0, what) * EVO_LUA_DEG;
	d.size = evo_lua_opt_num(
	    L, 2, kind == EVO_ELEM_ZONE ? "size" : "radius", d.size, what);
	d.half_w = evo_lua_opt_num(L, 2, "half_width", d.half_w, what);
	d.half_h = evo_lua_opt_num(L, 2, "half_height", d.half_h, what);
	d.density = evo_lua_opt_num(L, 2, "density", d.density, what);
	d.friction = evo_lua_opt_num(L, 2, "friction", d.friction, what);
	d.restitution =
	    evo_lua_opt_num(L, 2, "restitution", d.restitution, what);
	d.linear_damping =
	    evo_lua_opt_num(L, 2, "linear_damping", d.linear_damping, what);
	d.angular_damping =
	    evo_lua_opt_num(L, 2, "angular_damping", d.angular_damping, what);
	int i = evo_lua_scene_result(
	    L, evo_scene_add_element(evo_lua_ctx(L)->sc, &d));
	evo_lua_push_handle(L, EVO_LUA_ELEMENT_MT, i);
	return 1;
}

static int scene_cylinder(lua_State *L)
{
	return add_element(L, EVO_ELEM_CYLINDER, "scene:cylinder");
}

static int scene_box(lua_State *L)
{
	return add_element(L, EVO_ELEM_BOX, "scene:box");
}

/* scene:wall{x1, y1, x2, y2}: a wall of no thickness (docs/lua.md). */
static int scene_wall(lua_State *L)
{
	static const char *const keys[] = {"x1", "y1", "x2", "y2", NULL};
	const char *what = "scene:wall";
	evo_lua_check_keys(L, 2, what, keys);
	double v[4];
	for (int i = 0; i < 4; i++) {
		lua_getfield(L, 2, keys[i]);
		if (!lua_isnumber(L, -1))
			luaL_error(L, "%s: %s must be a number", what, keys[i]);
		v[i] = lua_tonumber(L, -1);
		lua_pop(L, 1);
	}
	evo_lua_scene_result(L, evo_scene_add_wall(evo_lua_ctx(L)->sc, v[0],
						    v[1], v[2], v[3]));
	return 0;
}

static int scene_zone(lua_State *L)
{
	return add_element(L, EVO_ELEM_ZONE, "scene:zone");
}

static int scene_object(lua_State *L)
{
	return add_element(L, EVO_ELEM_OBJECT, "scene:object");
}

static int scene_grid(lua_State *L)
{
	static const char *const keys[] = {
		"x0",	     "y0",	 "x1",	     "y1", "spacing", "jitter",
		"min_size", "size_variability", "shapes", "clearance", NULL};
	const char *what = "scene:grid";
	evo_lua_check_keys(L, 2, what, keys);
	evo_grid_def g = evo_default_grid_def();
	g.enabled = 1;
	g.x0 = evo_lua_opt_num(L, 2, "x0", g.x0, what);
	g.y0 = evo_lua_opt_num(L, 2, "y0", g.y0, what);
	g.x1 = evo_lua_opt_num(L, 2, "x1", g.x1, what);
	g.y1 = evo_lua_opt_num(L, 2, "y1", g.y1, what);
	g.spacing = evo_lua_opt_num(L, 2, "spacing", g.spacing, what);
	g.jitter = evo_lua_opt_num(L, 2, "jitter", g.jitter, what);
	g.min_size = evo_lua_opt_num(L, 2, "min_size", g.min_size, what);
	g.size_variability =
	    evo_lua_opt_num(L, 2, "size_variability", g.size_variability, what);
	g.clearance = evo_lua_opt_num(L, 2, "clearance", g.clearance, what);
	const char *shapes = evo_lua_opt_str(L, 2, "shapes", "cylinders", what);
	if (strcmp(shapes, "cylinders") == 0)
		g.boxes = 0;
	else if (strcmp(shapes, "boxes") == 0)
		g.boxes = 1;
	else if (strcmp(shapes, "mixed") == 0)
		g.boxes = 2;
	else
		luaL_error(L,
			   "%s: shapes is \"cylinders\", \"boxes\" or "
			   "\"mixed\", found \"%s\"",
			   what, shapes);
	if (!(g.spacing > 0) || g.x1 < g.x0 || g.y1 < g.y0 || g.jitter < 0 ||
	    !(g.min_size > 0) || g.size_variability < 0)
		luaL_error(L,
			   "%s: needs spacing > 0, x0 <= x1, y0 <= y1, "
			   "jitter >= 0, min_size > 0, size_variability >= 0",
			   what);
	if ((g.x1 - g.x0) / g.spacing * (g.y1 - g.y0) / g.spacing > 1e6)
		luaL_error(L, "%s: more than a million cells", what);
	evo_scene_set_grid(evo_lua_ctx(L)->sc, &g);
	return 0;
}

/* The line of a bot model's file where its body table starts (the first
 * "body =" outside a comment), 0 when none is found: a table has no line
 * of its own, and a mistake in it is reported there. */
static unsigned body_line(const char *path)
{
	FILE *f = fopen(path, "r");
	char line[512];
	unsigned n = 0, at = 0;
	while (f && !at && fgets(line, sizeof line, f)) {
		n++;
		const char *p = line;
		while (*p == ' ' || *p == '\t')
			p++;
		if (strncmp(p, "body", 4) != 0)
			continue;
		p += 4;
		while (*p == ' ' || *p == '\t')
			p++;
		if (*p == '=' && p[1] != '=')
			at = n;
	}
	if (f)
		fclose(f);
	return at;
}

/* The body table of a bot model (at 1) into the evo_bbody_def at 2.
 * Called through lua_pcall, so that its errors carry no script line:
 * scene:bot puts the bot model's file before them. */
static int read_body(lua_State *L)
{
	evo_bbody_def *body = lua_touserdata(L, 2);
	evo_bshape *sh = &body->shape[0];
	static const char *const bkeys[] = {
	    "shape",	       "radius",   "half_width",  "half_height",
	    "density",	       "friction", "restitution", "linear_damping",
	    "angular_damping", "sleep",	   "collision",	  NULL};
	int b = 1;
	const char *bw = "body";
	evo_lua_check_keys(L, b, bw, bkeys);
	const char *shape = evo_lua_opt_str(L, b, "shape", "circle", bw);
	if (strcmp(shape, "circle") == 0)
		sh->type = EVO_SHAPE_CIRCLE;
	else if (strcmp(shape, "box") == 0)
		sh->type = EVO_SHAPE_BOX;
	else
		luaL_error(L, "%s: shape is \"circle\" or \"box\"", bw);
	sh->radius = evo_lua_opt_num(L, b, "radius", sh->radius, bw);
	sh->half[0] = evo_lua_opt_num(L, b, "half_width", sh->half[0], bw);
	sh->half[1] = evo_lua_opt_num(L, b, "half_height", sh->half[1], bw);
	body->density = evo_lua_opt_num(L, b, "density", body->density, bw);
	sh->friction = evo_lua_opt_num(L, b, "friction", sh->friction, bw);
	sh->restitution =
	    evo_lua_opt_num(L, b, "restitution", sh->restitution, bw);
	body->linear_damping =
	    evo_lua_opt_num(L, b, "linear_damping", body->linear_damping, bw);
	body->angular_damping =
	    evo_lua_opt_num(L, b, "angular_damping", body->angular_damping, bw);
	lua_getfield(L, b, "sleep");
	body->allow_sleep = lua_toboolean(L, -1);
	lua_pop(L, 1);
	/* "undo": a kinematic body whose steps into a wall are undone
	 * (Lehman's maze simulator; docs/world.md, "The mazes") */
	const char *collision = evo_lua_opt_str(L, b, "collision", "physics", bw);
	if (strcmp(collision, "physics") == 0)
		body->kinematic = 0;
	else if (strcmp(collision, "undo") == 0)
		body->kinematic = 1;
	else
		luaL_error(L, "%s: collision is \"physics\" or \"undo\", not \"%s\"",
			   bw, collision);
	return 0;
}

static int scene_bot(lua_State *L)
{
	static const char *const keys[] = {"name",  "x",    "y", "angle",
					   "model", "team", NULL};
	const char *what = "scene:bot";
	evo_lua *l = evo_lua_ctx(L);
	if (lua_isnoneornil(L, 2)) {
		lua_settop(L, 1);
		lua_newtable(L);
	}
	evo_lua_check_keys(L, 2, what, keys);
	/* A team's bot is of the team's model and named after the team and
	 * its member number (docs/teams.md). */
	int team = evo_lua_opt_team(L, 2, what);
	const char *model;
	char auto_name[64];
	if (team >= 0) {
		lua_getfield(L, 2, "model");
		if (!lua_isnil(L, -1))
			luaL_error(L,
				   "%s: a bot of team %s is of its model, %s; "
				   "leave model out",
				   what, l->team[team].name,
				   l->team[team].botmodel);
		lua_pop(L, 1);
		if (l->team[team].made == l->team[team].size)
			luaL_error(L,
				   "%s: team %s has its %d bots already (its "
				   "SIZE in the task)",
				   what, l->team[team].name,
				   l->team[team].size);
		model = l->team[team].botmodel;
		snprintf(auto_name, sizeof auto_name, "%s%d",
			 l->team[team].name, l->team[team].made + 1);
	} else {
		model = evo_lua_opt_str(L, 2, "model", l->botmodel, what);
		if (!model[0] && l->n_teams > 0)
			luaL_error(L,
				   "%s: in a team task, a bot belongs to a "
				   "team (scene:bot{team = NAME}) or names "
				   "its model",
				   what);
		if (!model[0])
			luaL_error(L, "%s: the task names no BOTMODEL", what);
		snprintf(auto_name, sizeof auto_name, "bot%d",
			 l->sc->n_bots + 1);
	}
	lua_settop(L, 2);
	/* pushes the model table at 3 */
	evo_lua_load_model(L, l, model,
			   team >= 0 ? l->team[team].mind_dir : NULL);
	evo_bot_def d = evo_default_bot_def();
	d.team = team;
	d.name = evo_lua_opt_str(L, 2, "name", auto_name, what);
	d.x = evo_lua_opt_num(L, 2, "x", 0, what);
	d.y = evo_lua_opt_num(L, 2, "y", 0, what);
	d.angle = evo_lua_opt_num(L, 2, "angle", 0, what) * EVO_LUA_DEG;
	lua_getfield(L, 3, "body");
	if (!lua_isnil(L, -1)) {
		/* a mistake in the body is the bot model's: its file first */
		lua_pushcfunction(L, read_body);
		lua_pushvalue(L, -2);
		lua_pushlightuserdata(L, &d.body);
		if (lua_pcall(L, 2, 0, 0) != LUA_OK) {
			unsigned at = body_line(l->bot_path);
			if (at)
				lua_pushfstring(L, "%s:%d: %s", l->bot_path,
						(int)at, evo_lua_errstr(L, -1));
			else
				lua_pushfstring(L, "%s: %s", l->bot_path,
						evo_lua_errstr(L, -1));
			return lua_error(L);
		}
	}
	lua_pop(L, 1);
	int i = evo_lua_scene_result(L, evo_scene_add_bot(l->sc, &d));
	if (team >= 0)
		l->team[team].made++;
	lua_getfield(L, 3, "build");
	if (!lua_isfunction(L, -1))
		luaL_error(L, "bot model %s: has no build(bot) function", model);
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
	for (int i = 0; i < l->sc->n_bots; i++)
		if (team == -2 || l->sc->bot[i].team == team) {
			evo_lua_push_handle(L, EVO_LUA_BOT_MT, i);
			lua_rawseti(L, -2, ++n);
		}
	return 1;
}

/* scene:winner(team) sets the episode's winner (nil: none);
 * scene:winner() returns its name, or nil. */
static int scene_winner(lua_State *L)
{
	evo_scene *sc = evo_lua_ctx(L)->sc;
	int w = evo_lua_winner(L, sc->winner);
	if (w == -2)
		return 1; /* the name pushed */
	sc->winner = w;
	return 0;
}

static const char *const reward_keys[] = {
    "bot", "team", "k", "k2", "threshold", "target", "sensors", NULL};

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

/* The first argument of scene:reward and scene:control: a Lua function
 * (returns lua_kind, with *ref set) or the name of a built-in one (its
 * kind); an empty options table is pushed at 3 when none was given. */
static int function_or_name(lua_State *L, const char *what, const char *noun,
			    int (*by_name)(const char *),
			    const char *(*name_of)(int), int lua_kind,
			    int *ref)
{
	if (lua_isfunction(L, 2)) {
		if (evo_lua_ctx(L)->sc->n_bots == 0)
			luaL_error(L, "%s: there is no bot yet", what);
		evo_lua_function_options(L, what,
				     lua_kind == EVO_RW_LUA
					 ? &evo_lua_reward_resets_key
					 : &evo_lua_control_resets_key,
				     lua_kind == EVO_RW_LUA);
		lua_pushvalue(L, 2);
		*ref = luaL_ref(L, LUA_REGISTRYINDEX);
		return lua_kind;
	}
	const char *name = luaL_checkstring(L, 2);
	int kind = by_name(name);
	if (kind < 0 || kind == lua_kind) {
		/* the closest of the built-in names */
		const char *names[64];
		size_t n = 0;
		for (int k = 0; n < 64 && name_of(k); k++)
			if (k != lua_kind)
				names[n++] = name_of(k);
		const char *near = evo_lua_near(name, names, n);
		if (near)
			luaL_error(L,
				   "%s: unknown %s function '%s'; did you mean "
				   "%s? (or pass a Lua function for your own)",
				   what, noun, name, near);
		luaL_error(L,
			   "%s: unknown %s function '%s' (pass a Lua function "
			   "for your own)",
			   what, noun, name);
	}
	if (lua_isnoneornil(L, 3)) {
		lua_settop(L, 2);
		lua_newtable(L);
	}
	return kind;
}

/* The bots a built-in reward or control is for: its `bot`, or with
 * `team`, each bot of the team (docs/teams.md). Fills bots (cap) and
 * returns how many. */
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
	for (int i = 0; i < l->sc->n_bots && n < cap; i++)
		if (l->sc->bot[i].team == team)
			bots[n++] = i;
	if (n == 0)
		luaL_error(L,
			   "%s: team %s has no bots yet: make them "
			   "(scene:bot{team = ...}) before its rewards and "
			   "controls",
			   what, l->team[team].name);
	return n;
}

/* The sensors option of a reward, names resolved on bot. */
static void reward_sensors(lua_State *L, evo_reward_def *d, const char *what)
{
	d->n_sensors = 0;
	lua_getfield(L, 3, "sensors");
	if (!lua_isnil(L, -1)) {
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

static int scene_reward(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	const char *what = "scene:reward";
	int ref = -1;
	int kind = function_or_name(L, what, "reward", evo_reward_kind_by_name,
				    evo_reward_kind_name, EVO_RW_LUA, &ref);
	evo_reward_def d = evo_default_reward_def((evo_reward_kind)kind);
	d.lua_ref = ref;
	if (kind == EVO_RW_LUA) {
		/* a Lua function pays its bot, its team as a whole, or the
		 * scene */
		d.scope = EVO_SCOPE_SCENE;
		if (lua_istable(L, 3)) {
			int team = evo_lua_opt_team(L, 3, what);
			lua_getfield(L, 3, "bot");
			int has_bot = !lua_isnil(L, -1);
			lua_pop(L, 1);
			if (has_bot && team >= 0)
				luaL_error(L, "%s: give bot or team, not both",
					   what);
			if (has_bot) {
				d.bot = evo_lua_opt_bot(L, 3, what);
				d.scope = EVO_SCOPE_BOT;
			} else if (team >= 0) {
				d.team = team;
				d.scope = EVO_SCOPE_TEAM;
			}
		}
		evo_lua_scene_result(L, evo_scene_add_reward(l->sc, &d));
		return 0;
	}
	evo_lua_check_keys(L, 3, what, reward_keys);
	d.k = evo_lua_opt_num(L, 3, "k", d.k, what);
	d.k2 = evo_lua_opt_num(L, 3, "k2", d.k2, what);
	d.threshold = evo_lua_opt_num(L, 3, "threshold", d.threshold, what);
	d.target = evo_lua_opt_target(L, 3, "target", what);
	int bots[EVO_TEAM_BOTS_MAX];
	int n = scope_bots(L, what, bots, EVO_TEAM_BOTS_MAX);
	for (int i = 0; i < n; i++) {
		d.bot = bots[i];
		reward_sensors(L, &d, what);
		evo_lua_scene_result(L, evo_scene_add_reward(l->sc, &d));
	}
	return 0;
}

static int scene_control(lua_State *L)
{
	static const char *const keys[] = {
	    "bot", "team", "ticks", "target", "sensor", "threshold", NULL};
	evo_lua *l = evo_lua_ctx(L);
	const char *what = "scene:control";
	int ref = -1;
	int kind = function_or_name(L, what, "control", evo_control_kind_by_name,
				    evo_control_kind_name, EVO_CF_LUA, &ref);
	evo_control_def d = evo_default_control_def((evo_control_kind)kind);
	d.lua_ref = ref;
	if (kind == EVO_CF_LUA) {
		evo_lua_scene_result(L, evo_scene_add_control(l->sc, &d));
		return 0;
	}
	evo_lua_check_keys(L, 3, what, keys);
	double ticks = evo_lua_opt_num(L, 3, "ticks", (double)d.ticks, what);
	if (ticks < 0 || ticks != floor(ticks) || ticks > 1e15)
		luaL_error(L, "%s: ticks must be a whole number >= 0", what);
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
		evo_lua_scene_result(L, evo_scene_add_control(l->sc, &d));
	}
	return 0;
}

static int scene_element(lua_State *L)
{
	int i =
	    evo_scene_find_element(evo_lua_ctx(L)->sc, luaL_checkstring(L, 2));
	if (i < 0)
		lua_pushnil(L);
	else
		evo_lua_push_handle(L, EVO_LUA_ELEMENT_MT, i);
	return 1;
}

static int scene_get_bot(lua_State *L)
{
	evo_scene *sc = evo_lua_ctx(L)->sc;
	int i;
	if (lua_type(L, 2) == LUA_TSTRING)
		i = evo_scene_find_bot(sc, lua_tostring(L, 2));
	else {
		/* 1-based; anything past the bots, however large, is nil */
		lua_Integer k = luaL_checkinteger(L, 2);
		i = k >= 1 && k <= sc->n_bots ? (int)k - 1 : -1;
	}
	if (i < 0 || i >= sc->n_bots)
		lua_pushnil(L);
	else
		evo_lua_push_handle(L, EVO_LUA_BOT_MT, i);
	return 1;
}

static int scene_random(lua_State *L)
{
	evo_scene *sc = evo_lua_ctx(L)->sc;
	double u = evo_rng_unit(&sc->rng);
	if (lua_gettop(L) >= 3) {
		double lo = luaL_checknumber(L, 2), hi = luaL_checknumber(L, 3);
		u = lo + (hi - lo) * u;
	}
	lua_pushnumber(L, u);
	return 1;
}

static int scene_tick(lua_State *L)
{
	lua_pushinteger(L, evo_lua_ctx(L)->sc->tick);
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

/* Forget what the reward functions remember (ClosingOnTarget's last
 * distance), e.g. after moving a target: EvoAgents' r.reset(). */
static int scene_reset_rewards(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_scene *sc = l->sc;
	for (int i = 0; i < sc->n_rewards; i++)
		evo_reward_reset(&sc->reward[i]);
	evo_err err = {{0}};
	if (evo_lua_call_resets(l, &evo_lua_reward_resets_key, &err))
		luaL_error(L, "%s", err.msg);
	return 0;
}

static int scene_episode_reward(lua_State *L)
{
	lua_pushnumber(L, evo_lua_ctx(L)->sc->episode_reward);
	return 1;
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

/* Metric i of the scene, 2D or 3D. */
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
		luaL_error(L, "metric '%s': %s(%f) at tick %I: not a finite "
			      "number",
			   m->name, how, arg, tick);
	if (!isfinite(v))
		luaL_error(L, "metric '%s': %s(%f) at tick %I makes it %f, not "
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

/* scene:light{x, y, intensity}, scene:patch{...}: the swarm sensors'
 * lights and floor (lua_swarm.c). */
static int scene_light(lua_State *L)
{
	evo_scene *sc = evo_lua_ctx(L)->sc;
	evo_lua_add_light(L, 2, 2, &sc->swarm, &sc->err);
	return 0;
}

static int scene_patch(lua_State *L)
{
	evo_scene *sc = evo_lua_ctx(L)->sc;
	evo_lua_add_patch(L, 2, 2, &sc->swarm, &sc->err);
	return 0;
}

/* scene:colour(bot or element, colour): what cameras see it as. */
static int scene_colour(lua_State *L)
{
	evo_scene *sc = evo_lua_ctx(L)->sc;
	if (luaL_testudata(L, 2, EVO_LUA_BOT_MT))
		evo_lua_set_colour(L, EVO_BLOB_BOT, evo_lua_check_bot(L, 2),
				   &sc->swarm, &sc->err);
	else if (luaL_testudata(L, 2, EVO_LUA_ELEMENT_MT))
		evo_lua_set_colour(L, EVO_BLOB_ELEMENT,
				   evo_lua_check_element(L, 2), &sc->swarm,
				   &sc->err);
	else
		luaL_error(L, "scene:colour: a bot or an element, found %s",
			   luaL_typename(L, 2));
	return 0;
}

const luaL_Reg evo_lua_metric_methods[] = {
	{"set", metric_set},
	{"add", metric_add},
	{"value", metric_value},
	{"name", metric_name},
	{NULL, NULL},
};

const luaL_Reg evo_lua_element_methods[] = {
	{"pos", element_pos},
	{"place", element_place},
	{"active", element_active},
	{"set_active", element_set_active},
	{"name", element_name},
	{NULL, NULL},
};

const luaL_Reg evo_lua_scene_methods[] = {
    {"bot", scene_bot},
    {"get_bot", scene_get_bot},
    {"teams", scene_teams},
    {"bots", scene_bots},
    {"winner", scene_winner},
    {"cylinder", scene_cylinder},
    {"box", scene_box},
    {"wall", scene_wall},
    {"zone", scene_zone},
    {"object", scene_object},
    {"grid", scene_grid},
    {"light", scene_light},
    {"patch", scene_patch},
    {"colour", scene_colour},
    {"reward", scene_reward},
    {"control", scene_control},
    {"element", scene_element},
    {"random", scene_random},
    {"tick", scene_tick},
    {"episode_reward", scene_episode_reward},
    {"reset_rewards", scene_reset_rewards},
    {"metric", evo_lua_scene_metric},
    {"genome", scene_genome},
    {NULL, NULL},
};
