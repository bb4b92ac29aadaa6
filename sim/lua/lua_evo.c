/* The evo Lua module (sim/lua_evo.h, docs/lua.md).
 *
 * Lua holds handles, not pointers: a bot or element handle is a small
 * userdata with its index in the scene, and every method finds the scene
 * through the state's registry. Options come in tables; an option the
 * function does not know is an error naming the ones it does, so a typo
 * in a script never goes unnoticed. Angles are in degrees in Lua and in
 * radians in C. */
#define _DEFAULT_SOURCE /* realpath */
#define _POSIX_C_SOURCE 200809L
#include "lua/lua_evo.h"
#include "world2d/rewards.h"
#include "world2d/actuators.h"
#include "world2d/sensors.h"
#include "base/fileio.h"

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

struct evo_lua {
	lua_State *L;
	evo_scene *sc;
	char mind_dir[1024];
	char lua_dir[1024];
	char botmodel[EVO_NAME_MAX];
	const evo_simbatch *task;
	int env_ref;	 /* the environment's table */
	int has_post_step;
	char env_path[1200];
	char bot_path[1200];
};

static const char CTX_KEY = 'k'; /* registry key: its address */

#define DEG (M_PI / 180.0)

static evo_lua *ctx(lua_State *L)
{
	lua_rawgetp(L, LUA_REGISTRYINDEX, &CTX_KEY);
	evo_lua *l = lua_touserdata(L, -1);
	lua_pop(L, 1);
	return l;
}

/* ---- the lua/ folder --------------------------------------------------- */

static int is_dir_with(const char *dir, const char *sub)
{
	char p[1200];
	snprintf(p, sizeof p, "%s/%s", dir, sub);
	return access(p, R_OK) == 0;
}

const char *evo_lua_dir(void)
{
	static char dir[1024];
	const char *env = getenv("EVO_LUA_DIR");
	if (env && env[0])
		return env;
	char exe[1024];
	ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
	if (n > 0) {
		exe[n] = 0;
		char *slash = strrchr(exe, '/');
		if (slash)
			*slash = 0;
		/* build/evo, build/asan/evo, PREFIX/bin/evo */
		const char *tries[] = {"%s/../lua", "%s/../../lua",
				       "%s/../share/evo/lua"};
		for (unsigned i = 0; i < 3; i++) {
			char raw[1100];
			snprintf(raw, sizeof raw, tries[i], exe);
			if (is_dir_with(raw, "envs") && realpath(raw, dir))
				return dir;
		}
	}
	return "lua";
}

/* ---- option tables ----------------------------------------------------- */

/* Raise an error for any key of the table at idx not in `known`. */
static void check_keys(lua_State *L, int idx, const char *what,
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
			luaL_error(L, "%s: unknown option '%s' (known: %s)",
				   what, k, lua_tostring(L, -1));
			return;
		}
	}
}

static double opt_num(lua_State *L, int idx, const char *key, double dflt,
		      const char *what)
{
	lua_getfield(L, idx, key);
	double v = dflt;
	if (!lua_isnil(L, -1)) {
		int isnum;
		v = lua_tonumberx(L, -1, &isnum);
		if (!isnum || !isfinite(v))
			luaL_error(L, "%s: option '%s' must be a number, found %s",
				   what, key, luaL_typename(L, -1));
	}
	lua_pop(L, 1);
	return v;
}

static const char *opt_str(lua_State *L, int idx, const char *key,
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

#define BOT_MT "evo.bot"
#define ELEMENT_MT "evo.element"
#define SCENE_MT "evo.scene"

static void push_handle(lua_State *L, const char *mt, int index)
{
	int *p = lua_newuserdatauv(L, sizeof *p, 0);
	*p = index;
	luaL_setmetatable(L, mt);
}

static int check_bot(lua_State *L, int idx)
{
	int i = *(int *)luaL_checkudata(L, idx, BOT_MT);
	if (i < 0 || i >= ctx(L)->sc->n_bots)
		luaL_error(L, "stale bot handle");
	return i;
}

static int check_element(lua_State *L, int idx)
{
	int i = *(int *)luaL_checkudata(L, idx, ELEMENT_MT);
	if (i < 0 || i >= ctx(L)->sc->n_elements)
		luaL_error(L, "stale element handle");
	return i;
}

/* A target option: an element handle, "nearest_object", or nil. */
static int opt_target(lua_State *L, int idx, const char *key,
		      const char *what)
{
	lua_getfield(L, idx, key);
	int t = EVO_TARGET_NONE;
	if (lua_type(L, -1) == LUA_TSTRING) {
		if (strcmp(lua_tostring(L, -1), "nearest_object") != 0)
			luaL_error(L,
				   "%s: %s must be an element or "
				   "\"nearest_object\", found \"%s\"",
				   what, key, lua_tostring(L, -1));
		t = EVO_TARGET_NEAREST_OBJECT;
	} else if (!lua_isnil(L, -1)) {
		if (!luaL_testudata(L, -1, ELEMENT_MT))
			luaL_error(L, "%s: %s must be an element, found %s",
				   what, key, luaL_typename(L, -1));
		t = check_element(L, lua_gettop(L));
	}
	lua_pop(L, 1);
	return t;
}

static int opt_bot(lua_State *L, int idx, const char *what)
{
	lua_getfield(L, idx, "bot");
	int b = 0;
	if (!lua_isnil(L, -1)) {
		if (!luaL_testudata(L, -1, BOT_MT))
			luaL_error(L, "%s: bot must be a bot, found %s", what,
				   luaL_typename(L, -1));
		b = check_bot(L, lua_gettop(L));
	} else if (ctx(L)->sc->n_bots == 0) {
		luaL_error(L, "%s: there is no bot yet", what);
	}
	lua_pop(L, 1);
	return b;
}

static int bot_sensor_index(lua_State *L, int bot, const char *name,
			    const char *what)
{
	const evo_bot *b = &ctx(L)->sc->bot[bot];
	int s = evo_bot_find_sensor(b, name);
	if (s < 0)
		luaL_error(L, "%s: bot '%s' has no sensor '%s'", what, b->name,
			   name);
	return s;
}

/* Turn a scene error into a Lua error at the caller's line. */
static int scene_result(lua_State *L, int r)
{
	if (r < 0)
		luaL_error(L, "%s", ctx(L)->sc->err.msg);
	return r;
}

/* ---- bot: sensors and actuators ---------------------------------------- */

static const char *const sensor_keys[] = {
	"name",	 "x",	   "y",	    "angle", "range", "arc",   "rays",
	"deadzone", "sees", "target", "scale", "reach", "value", NULL};

static uint16_t parse_sees(lua_State *L, int idx, const char *what)
{
	lua_getfield(L, idx, "sees");
	uint16_t mask = EVO_CAT_OBSTACLE | EVO_CAT_BOT;
	if (!lua_isnil(L, -1)) {
		luaL_checktype(L, -1, LUA_TTABLE);
		mask = 0;
		int n = (int)luaL_len(L, -1);
		for (int i = 1; i <= n; i++) {
			lua_geti(L, -1, i);
			const char *s = lua_tostring(L, -1);
			if (s && strcmp(s, "obstacles") == 0)
				mask |= EVO_CAT_OBSTACLE;
			else if (s && strcmp(s, "bots") == 0)
				mask |= EVO_CAT_BOT;
			else if (s && strcmp(s, "objects") == 0)
				mask |= EVO_CAT_OBJECT;
			else
				luaL_error(L,
					   "%s: sees lists \"obstacles\", "
					   "\"bots\" or \"objects\", found %s",
					   what, s ? s : luaL_typename(L, -1));
			lua_pop(L, 1);
		}
	}
	lua_pop(L, 1);
	return mask;
}

static int add_sensor(lua_State *L, evo_sensor_kind kind, const char *what)
{
	int bot = check_bot(L, 1);
	check_keys(L, 2, what, sensor_keys);
	evo_sensor_def d = evo_default_sensor_def(kind);
	d.name = opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: a sensor needs a name", what);
	d.x = opt_num(L, 2, "x", d.x, what);
	d.y = opt_num(L, 2, "y", d.y, what);
	d.angle = opt_num(L, 2, "angle", d.angle / DEG, what) * DEG;
	d.range = opt_num(L, 2, "range", d.range, what);
	d.arc = opt_num(L, 2, "arc", d.arc / DEG, what) * DEG;
	double rays = opt_num(L, 2, "rays", d.rays, what);
	if (rays != floor(rays) || rays < 1 || rays > EVO_PROX_MAX_RAYS)
		luaL_error(L, "%s: rays must be a whole number from 1 to %d",
			   what, EVO_PROX_MAX_RAYS);
	d.rays = (int)rays;
	d.deadzone = opt_num(L, 2, "deadzone", d.deadzone, what);
	d.mask = parse_sees(L, 2, what);
	d.target = opt_target(L, 2, "target", what);
	d.scale = opt_num(L, 2, "scale", d.scale, what);
	d.reach = opt_num(L, 2, "reach", d.reach, what);
	d.value = opt_num(L, 2, "value", d.value, what);
	lua_pushinteger(L, scene_result(L, evo_scene_add_sensor(ctx(L)->sc,
								bot, &d)) +
				   1);
	return 1;
}

#define SENSOR_FN(fn, kind)                                                  \
	static int sensor_##fn(lua_State *L)                                 \
	{                                                                    \
		return add_sensor(L, kind, "bot:" #fn);                      \
	}
SENSOR_FN(proximity, EVO_SENSOR_PROXIMITY)
SENSOR_FN(distance, EVO_SENSOR_DISTANCE)
SENSOR_FN(zone, EVO_SENSOR_ZONE)
SENSOR_FN(bearing, EVO_SENSOR_BEARING)
SENSOR_FN(presence, EVO_SENSOR_PRESENCE)
SENSOR_FN(object_detector, EVO_SENSOR_OBJECT)
SENSOR_FN(movement, EVO_SENSOR_MOVEMENT)
SENSOR_FN(random, EVO_SENSOR_RANDOM)
SENSOR_FN(constant, EVO_SENSOR_CONSTANT)
SENSOR_FN(holding, EVO_SENSOR_HOLDING)

static int add_actuator(lua_State *L, evo_actuator_kind kind,
			const char *what)
{
	static const char *const keys[] = {"name", "x", "y", "angle",
					   "max_force", "reach", NULL};
	int bot = check_bot(L, 1);
	check_keys(L, 2, what, keys);
	evo_actuator_def d = evo_default_actuator_def(kind);
	d.name = opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: an actuator needs a name", what);
	d.x = opt_num(L, 2, "x", d.x, what);
	d.y = opt_num(L, 2, "y", d.y, what);
	d.angle = opt_num(L, 2, "angle", d.angle / DEG, what) * DEG;
	d.max_force = opt_num(L, 2, "max_force", d.max_force, what);
	d.reach = opt_num(L, 2, "reach", d.reach, what);
	lua_pushinteger(L, scene_result(L, evo_scene_add_actuator(ctx(L)->sc,
								  bot, &d)) +
				   1);
	return 1;
}

static int wheel(lua_State *L)
{
	return add_actuator(L, EVO_ACTUATOR_WHEEL, "bot:wheel");
}

static int claw(lua_State *L)
{
	return add_actuator(L, EVO_ACTUATOR_CLAW, "bot:claw");
}

/* bot:target(sensor name, element or "nearest_object"): what a tracker
 * looks at (EvoAgents' setTarget). */
static int bot_target(lua_State *L)
{
	int bot = check_bot(L, 1);
	const char *name = luaL_checkstring(L, 2);
	evo_scene *sc = ctx(L)->sc;
	int s = bot_sensor_index(L, bot, name, "bot:target");
	lua_settop(L, 3);
	lua_newtable(L);
	lua_pushvalue(L, 3);
	lua_setfield(L, -2, "target");
	int t = opt_target(L, 4, "target", "bot:target");
	evo_sensor *sn = &sc->bot[bot].sensor[s];
	if (sn->def.kind == EVO_SENSOR_ZONE && t >= 0 &&
	    sc->element[t].kind != EVO_ELEM_ZONE)
		luaL_error(L, "bot:target: zone sensor '%s' needs a zone",
			   name);
	sn->def.target = t;
	return 0;
}

static int bot_pose(lua_State *L)
{
	int bot = check_bot(L, 1);
	evo_scene *sc = ctx(L)->sc;
	evo_pose p = evo_body_pose(sc->world, sc->bot[bot].body);
	lua_pushnumber(L, p.x);
	lua_pushnumber(L, p.y);
	lua_pushnumber(L, p.angle / DEG);
	return 3;
}

static int bot_place(lua_State *L)
{
	int bot = check_bot(L, 1);
	double x = luaL_checknumber(L, 2), y = luaL_checknumber(L, 3);
	double a = luaL_optnumber(L, 4, 0) * DEG;
	if (!isfinite(x) || !isfinite(y) || !isfinite(a))
		luaL_error(L, "bot:place: a value is not a number");
	evo_scene_place_bot(ctx(L)->sc, bot, x, y, a);
	return 0;
}

static int bot_value(lua_State *L)
{
	int bot = check_bot(L, 1);
	int s = bot_sensor_index(L, bot, luaL_checkstring(L, 2), "bot:value");
	evo_scene *sc = ctx(L)->sc;
	evo_sensor *se = &sc->bot[bot].sensor[s];
	if (se->idle) {
		/* Not sampled so far: from now on it is, every tick. */
		se->idle = 0;
		evo_sensor_sample(sc, bot, s);
	}
	lua_pushnumber(L, se->value);
	return 1;
}

static int bot_command(lua_State *L)
{
	int bot = check_bot(L, 1);
	const evo_bot *b = &ctx(L)->sc->bot[bot];
	const char *name = luaL_checkstring(L, 2);
	int a = evo_bot_find_actuator(b, name);
	if (a < 0)
		luaL_error(L, "bot:command: bot '%s' has no actuator '%s'",
			   b->name, name);
	lua_pushnumber(L, b->actuator[a].command);
	return 1;
}

static int bot_counts(lua_State *L)
{
	int bot = check_bot(L, 1);
	const evo_bot *b = &ctx(L)->sc->bot[bot];
	int holding = 0;
	for (int i = 0; i < b->n_actuators; i++)
		holding |= b->actuator[i].held >= 0;
	lua_newtable(L);
	lua_pushinteger(L, b->touching);
	lua_setfield(L, -2, "touching");
	lua_pushinteger(L, b->collisions);
	lua_setfield(L, -2, "collisions");
	lua_pushinteger(L, b->delivered);
	lua_setfield(L, -2, "delivered");
	lua_pushboolean(L, holding);
	lua_setfield(L, -2, "holding");
	return 1;
}

static int bot_name(lua_State *L)
{
	lua_pushstring(L, ctx(L)->sc->bot[check_bot(L, 1)].name);
	return 1;
}

/* ---- elements ------------------------------------------------------------ */

static int element_pos(lua_State *L)
{
	const evo_element *e = &ctx(L)->sc->element[check_element(L, 1)];
	lua_pushnumber(L, e->x);
	lua_pushnumber(L, e->y);
	return 2;
}

static int element_place(lua_State *L)
{
	int e = check_element(L, 1);
	double x = luaL_checknumber(L, 2), y = luaL_checknumber(L, 3);
	evo_scene *sc = ctx(L)->sc;
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
	lua_pushboolean(L, ctx(L)->sc->element[check_element(L, 1)].active);
	return 1;
}

static int element_set_active(lua_State *L)
{
	int i = check_element(L, 1);
	evo_scene *sc = ctx(L)->sc;
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
	lua_pushstring(L, ctx(L)->sc->element[check_element(L, 1)].name);
	return 1;
}

/* ---- scene ---------------------------------------------------------------- */

static int add_element(lua_State *L, evo_element_kind kind, const char *what)
{
	static const char *const keys[] = {
		"name",	    "x",	"y",	   "angle",
		"radius",   "size",	"half_width", "half_height",
		"density",  "friction", "restitution", "linear_damping",
		"angular_damping", NULL};
	check_keys(L, 2, what, keys);
	evo_element_def d = evo_default_element_def(kind);
	d.name = opt_str(L, 2, "name", NULL, what);
	d.x = opt_num(L, 2, "x", 0, what);
	d.y = opt_num(L, 2, "y", 0, what);
	d.angle = opt_num(L, 2, "angle", 0, what) * DEG;
	d.size = opt_num(L, 2, kind == EVO_ELEM_ZONE ? "size" : "radius",
			 d.size, what);
	d.half_w = opt_num(L, 2, "half_width", d.half_w, what);
	d.half_h = opt_num(L, 2, "half_height", d.half_h, what);
	d.density = opt_num(L, 2, "density", d.density, what);
	d.friction = opt_num(L, 2, "friction", d.friction, what);
	d.restitution = opt_num(L, 2, "restitution", d.restitution, what);
	d.linear_damping =
		opt_num(L, 2, "linear_damping", d.linear_damping, what);
	d.angular_damping =
		opt_num(L, 2, "angular_damping", d.angular_damping, what);
	int i = scene_result(L, evo_scene_add_element(ctx(L)->sc, &d));
	push_handle(L, ELEMENT_MT, i);
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
	check_keys(L, 2, what, keys);
	evo_grid_def g = evo_default_grid_def();
	g.enabled = 1;
	g.x0 = opt_num(L, 2, "x0", g.x0, what);
	g.y0 = opt_num(L, 2, "y0", g.y0, what);
	g.x1 = opt_num(L, 2, "x1", g.x1, what);
	g.y1 = opt_num(L, 2, "y1", g.y1, what);
	g.spacing = opt_num(L, 2, "spacing", g.spacing, what);
	g.jitter = opt_num(L, 2, "jitter", g.jitter, what);
	g.min_size = opt_num(L, 2, "min_size", g.min_size, what);
	g.size_variability =
		opt_num(L, 2, "size_variability", g.size_variability, what);
	g.clearance = opt_num(L, 2, "clearance", g.clearance, what);
	const char *shapes = opt_str(L, 2, "shapes", "cylinders", what);
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
	evo_scene_set_grid(ctx(L)->sc, &g);
	return 0;
}

/* Build a bot from the bot model file; see bot models in docs/lua.md. */
static int load_model(lua_State *L, evo_lua *l, const char *model);

static int scene_bot(lua_State *L)
{
	static const char *const keys[] = {"name", "x", "y", "angle", "model",
					   NULL};
	const char *what = "scene:bot";
	evo_lua *l = ctx(L);
	if (lua_isnoneornil(L, 2)) {
		lua_settop(L, 1);
		lua_newtable(L);
	}
	check_keys(L, 2, what, keys);
	const char *model = opt_str(L, 2, "model", l->botmodel, what);
	if (!model[0])
		luaL_error(L, "%s: the task names no BOTMODEL", what);
	lua_settop(L, 2);
	load_model(L, l, model); /* pushes the model table at 3 */
	evo_bot_def d = evo_default_bot_def();
	char auto_name[32];
	snprintf(auto_name, sizeof auto_name, "bot%d", l->sc->n_bots + 1);
	d.name = opt_str(L, 2, "name", auto_name, what);
	d.x = opt_num(L, 2, "x", 0, what);
	d.y = opt_num(L, 2, "y", 0, what);
	d.angle = opt_num(L, 2, "angle", 0, what) * DEG;
	lua_getfield(L, 3, "body");
	if (!lua_isnil(L, -1)) {
		static const char *const bkeys[] = {
			"shape",	  "radius",	    "half_width",
			"half_height", "density",	    "friction",
			"restitution", "linear_damping", "angular_damping",
			"sleep",	  NULL};
		int b = lua_gettop(L);
		const char *bw = "bot model body";
		check_keys(L, b, bw, bkeys);
		const char *shape = opt_str(L, b, "shape", "circle", bw);
		if (strcmp(shape, "circle") == 0)
			d.body.shape = EVO_SHAPE_CIRCLE;
		else if (strcmp(shape, "box") == 0)
			d.body.shape = EVO_SHAPE_BOX;
		else
			luaL_error(L, "%s: shape is \"circle\" or \"box\"", bw);
		d.body.radius = opt_num(L, b, "radius", d.body.radius, bw);
		d.body.half_w = opt_num(L, b, "half_width", d.body.half_w, bw);
		d.body.half_h =
			opt_num(L, b, "half_height", d.body.half_h, bw);
		d.body.density = opt_num(L, b, "density", d.body.density, bw);
		d.body.friction =
			opt_num(L, b, "friction", d.body.friction, bw);
		d.body.restitution =
			opt_num(L, b, "restitution", d.body.restitution, bw);
		d.body.linear_damping = opt_num(L, b, "linear_damping",
						d.body.linear_damping, bw);
		d.body.angular_damping = opt_num(L, b, "angular_damping",
						 d.body.angular_damping, bw);
		lua_getfield(L, b, "sleep");
		d.body.allow_sleep = lua_toboolean(L, -1);
		lua_pop(L, 1);
	}
	lua_pop(L, 1);
	int i = scene_result(L, evo_scene_add_bot(l->sc, &d));
	lua_getfield(L, 3, "build");
	if (!lua_isfunction(L, -1))
		luaL_error(L, "bot model %s: has no build(bot) function", model);
	push_handle(L, BOT_MT, i);
	lua_call(L, 1, 0);
	push_handle(L, BOT_MT, i);
	return 1;
}

static const char *const reward_keys[] = {"bot",       "k",	  "k2",
					  "threshold", "target", "sensors",
					  NULL};

/* The first argument of scene:reward and scene:control: a Lua function
 * (returns lua_kind, with *ref set) or the name of a built-in one (its
 * kind); an empty options table is pushed at 3 when none was given. */
static int function_or_name(lua_State *L, const char *what, const char *noun,
			    int (*by_name)(const char *), int lua_kind,
			    int *ref)
{
	if (lua_isfunction(L, 2)) {
		if (ctx(L)->sc->n_bots == 0)
			luaL_error(L, "%s: there is no bot yet", what);
		lua_pushvalue(L, 2);
		*ref = luaL_ref(L, LUA_REGISTRYINDEX);
		return lua_kind;
	}
	const char *name = luaL_checkstring(L, 2);
	int kind = by_name(name);
	if (kind < 0 || kind == lua_kind)
		luaL_error(L,
			   "%s: unknown %s function '%s' (pass a Lua function "
			   "for your own)",
			   what, noun, name);
	if (lua_isnoneornil(L, 3)) {
		lua_settop(L, 2);
		lua_newtable(L);
	}
	return kind;
}

static int scene_reward(lua_State *L)
{
	evo_lua *l = ctx(L);
	const char *what = "scene:reward";
	int ref = -1;
	int kind = function_or_name(L, what, "reward", evo_reward_kind_by_name,
				    EVO_RW_LUA, &ref);
	evo_reward_def d = evo_default_reward_def((evo_reward_kind)kind);
	d.lua_ref = ref;
	if (kind != EVO_RW_LUA) {
		check_keys(L, 3, what, reward_keys);
		d.bot = opt_bot(L, 3, what);
		d.k = opt_num(L, 3, "k", d.k, what);
		d.k2 = opt_num(L, 3, "k2", d.k2, what);
		d.threshold = opt_num(L, 3, "threshold", d.threshold, what);
		d.target = opt_target(L, 3, "target", what);
		lua_getfield(L, 3, "sensors");
		if (!lua_isnil(L, -1)) {
			luaL_checktype(L, -1, LUA_TTABLE);
			int n = (int)luaL_len(L, -1);
			if (n > EVO_REWARD_MAX_SENSORS)
				luaL_error(L, "%s: at most %d sensors", what,
					   EVO_REWARD_MAX_SENSORS);
			for (int i = 1; i <= n; i++) {
				lua_geti(L, -1, i);
				const char *s = lua_tostring(L, -1);
				if (!s)
					luaL_error(L, "%s: sensors are names",
						   what);
				d.sensor[d.n_sensors++] =
					bot_sensor_index(L, d.bot, s, what);
				lua_pop(L, 1);
			}
		}
		lua_pop(L, 1);
	}
	scene_result(L, evo_scene_add_reward(l->sc, &d));
	return 0;
}

static int scene_control(lua_State *L)
{
	static const char *const keys[] = {"bot",    "ticks",     "target",
					   "sensor", "threshold", NULL};
	evo_lua *l = ctx(L);
	const char *what = "scene:control";
	int ref = -1;
	int kind = function_or_name(L, what, "control", evo_control_kind_by_name,
				    EVO_CF_LUA, &ref);
	evo_control_def d = evo_default_control_def((evo_control_kind)kind);
	d.lua_ref = ref;
	if (kind != EVO_CF_LUA) {
		check_keys(L, 3, what, keys);
		d.bot = opt_bot(L, 3, what);
		double ticks = opt_num(L, 3, "ticks", (double)d.ticks, what);
		if (ticks < 0 || ticks != floor(ticks) || ticks > 1e15)
			luaL_error(L, "%s: ticks must be a whole number >= 0",
				   what);
		d.ticks = (long)ticks;
		d.target = opt_target(L, 3, "target", what);
		d.threshold = opt_num(L, 3, "threshold", d.threshold, what);
		const char *s = opt_str(L, 3, "sensor", NULL, what);
		if (s)
			d.sensor = bot_sensor_index(L, d.bot, s, what);
	}
	scene_result(L, evo_scene_add_control(l->sc, &d));
	return 0;
}

static int scene_element(lua_State *L)
{
	int i = evo_scene_find_element(ctx(L)->sc, luaL_checkstring(L, 2));
	if (i < 0)
		lua_pushnil(L);
	else
		push_handle(L, ELEMENT_MT, i);
	return 1;
}

static int scene_get_bot(lua_State *L)
{
	evo_scene *sc = ctx(L)->sc;
	int i;
	if (lua_type(L, 2) == LUA_TSTRING)
		i = evo_scene_find_bot(sc, lua_tostring(L, 2));
	else
		i = (int)luaL_checkinteger(L, 2) - 1;
	if (i < 0 || i >= sc->n_bots)
		lua_pushnil(L);
	else
		push_handle(L, BOT_MT, i);
	return 1;
}

static int scene_random(lua_State *L)
{
	evo_scene *sc = ctx(L)->sc;
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
	lua_pushinteger(L, ctx(L)->sc->tick);
	return 1;
}

/* Forget what the reward functions remember (ClosingOnTarget's last
 * distance), e.g. after moving a target: EvoAgents' r.reset(). */
static int scene_reset_rewards(lua_State *L)
{
	evo_scene *sc = ctx(L)->sc;
	for (int i = 0; i < sc->n_rewards; i++)
		evo_reward_reset(&sc->reward[i]);
	return 0;
}

static int scene_episode_reward(lua_State *L)
{
	lua_pushnumber(L, ctx(L)->sc->episode_reward);
	return 1;
}

/* ---- hooks: Lua reward and control functions ------------------------- */

/* Call the function behind ref with the scene; leaves one result. */
static int call_ref(evo_lua *l, int ref, const char *what)
{
	lua_State *L = l->L;
	lua_rawgeti(L, LUA_REGISTRYINDEX, ref);
	lua_rawgetp(L, LUA_REGISTRYINDEX, &SCENE_MT);
	if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
		evo_fail(&l->sc->err, "%s (in a %s)", lua_tostring(L, -1),
			 what);
		lua_pop(L, 1);
		return -1;
	}
	return 0;
}

static int hook_reward(void *c, evo_scene *sc, const evo_reward *r,
		       double *out)
{
	evo_lua *l = c;
	(void)sc;
	if (call_ref(l, r->def.lua_ref, "reward function"))
		return -1;
	int isnum;
	*out = lua_tonumberx(l->L, -1, &isnum);
	int ok = isnum && isfinite(*out);
	if (!ok)
		evo_fail(&l->sc->err,
			 "a reward function returned %s, not a finite number",
			 luaL_typename(l->L, -1));
	lua_pop(l->L, 1);
	return ok ? 0 : -1;
}

static int hook_control(void *c, evo_scene *sc, const evo_control *ctl,
			int *next)
{
	evo_lua *l = c;
	(void)sc;
	if (call_ref(l, ctl->def.lua_ref, "control function"))
		return -1;
	*next = lua_toboolean(l->L, -1);
	lua_pop(l->L, 1);
	return 0;
}

/* Call env[name](scene, arg) if the environment has it. */
static int call_env(evo_lua *l, const char *name, int with_arg, lua_Integer arg,
		    evo_err *err)
{
	lua_State *L = l->L;
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	lua_getfield(L, -1, name);
	lua_remove(L, -2);
	if (lua_isnil(L, -1)) {
		lua_pop(L, 1);
		return 0;
	}
	lua_rawgetp(L, LUA_REGISTRYINDEX, &SCENE_MT);
	int nargs = 1;
	if (with_arg == 1) {
		lua_pushinteger(L, arg);
		nargs = 2;
	} else if (with_arg == 2) {
		/* the task: every .simbatch key with its value */
		lua_newtable(L);
		for (unsigned i = 0; l->task && i < l->task->n_pairs; i++) {
			lua_pushstring(L, l->task->pair[i].value);
			lua_setfield(L, -2, l->task->pair[i].key);
		}
		nargs = 2;
	}
	if (lua_pcall(L, nargs, 0, 0) != LUA_OK) {
		evo_fail(err, "%s", lua_tostring(L, -1));
		lua_pop(L, 1);
		return -1;
	}
	return 0;
}

static int hook_post_step(void *c, evo_scene *sc)
{
	evo_lua *l = c;
	(void)sc;
	return call_env(l, "post_step", 0, 0, &l->sc->err);
}

/* ---- loading files ------------------------------------------------------- */

/* Find NAME.lua in mind_dir/<mind_sub> then lua_dir/<lua_sub>. */
static int find_script(const evo_lua *l, const char *mind_sub,
		       const char *lua_sub, const char *name, char *out,
		       size_t cap)
{
	if (!name[0] || strchr(name, '/') || strstr(name, ".."))
		return -1;
	if (l->mind_dir[0]) {
		snprintf(out, cap, "%s/%s/%s.lua", l->mind_dir, mind_sub, name);
		if (evo_file_exists(out))
			return 0;
	}
	snprintf(out, cap, "%s/%s/%s.lua", l->lua_dir, lua_sub, name);
	return evo_file_exists(out) ? 0 : -1;
}

/* Run a script file and leave its single result on the stack; raises. */
static void run_file(lua_State *L, const char *path, const char *what)
{
	if (luaL_loadfilex(L, path, "t") != LUA_OK)
		lua_error(L);
	lua_call(L, 0, 1);
	if (!lua_istable(L, -1))
		luaL_error(L, "%s: %s must return a table, returned %s", path,
			   what, luaL_typename(L, -1));
}

static int load_model(lua_State *L, evo_lua *l, const char *model)
{
	char path[1200];
	if (find_script(l, "Bots", "bots", model, path, sizeof path))
		luaL_error(L,
			   "bot model '%s' not found: looked for "
			   "%s/Bots/%s.lua and %s/bots/%s.lua",
			   model, l->mind_dir[0] ? l->mind_dir : ".", model,
			   l->lua_dir, model);
	snprintf(l->bot_path, sizeof l->bot_path, "%s", path);
	run_file(L, path, "a bot model");
	return 1;
}

/* ---- the module ---------------------------------------------------------- */

static const luaL_Reg bot_methods[] = {
	{"proximity", sensor_proximity},
	{"distance", sensor_distance},
	{"zone", sensor_zone},
	{"bearing", sensor_bearing},
	{"presence", sensor_presence},
	{"object_detector", sensor_object_detector},
	{"movement", sensor_movement},
	{"random", sensor_random},
	{"constant", sensor_constant},
	{"holding", sensor_holding},
	{"wheel", wheel},
	{"claw", claw},
	{"target", bot_target},
	{"pose", bot_pose},
	{"place", bot_place},
	{"value", bot_value},
	{"command", bot_command},
	{"counts", bot_counts},
	{"name", bot_name},
	{NULL, NULL},
};

static const luaL_Reg element_methods[] = {
	{"pos", element_pos},
	{"place", element_place},
	{"active", element_active},
	{"set_active", element_set_active},
	{"name", element_name},
	{NULL, NULL},
};

static const luaL_Reg scene_methods[] = {
	{"bot", scene_bot},
	{"get_bot", scene_get_bot},
	{"cylinder", scene_cylinder},
	{"box", scene_box},
	{"zone", scene_zone},
	{"object", scene_object},
	{"grid", scene_grid},
	{"reward", scene_reward},
	{"control", scene_control},
	{"element", scene_element},
	{"random", scene_random},
	{"tick", scene_tick},
	{"episode_reward", scene_episode_reward},
	{"reset_rewards", scene_reset_rewards},
	{NULL, NULL},
};

static void new_class(lua_State *L, const char *mt, const luaL_Reg *methods)
{
	luaL_newmetatable(L, mt);
	lua_newtable(L);
	luaL_setfuncs(L, methods, 0);
	lua_setfield(L, -2, "__index");
	lua_pushstring(L, mt);
	lua_setfield(L, -2, "__name");
	lua_pop(L, 1);
}

void evo_lua_set_path(lua_State *L, const char *mind_dir,
		      const char *lua_dir)
{
	lua_getglobal(L, "package");
	lua_pushfstring(L, "%s/?.lua;%s/?.lua", mind_dir[0] ? mind_dir : ".",
			lua_dir);
	lua_setfield(L, -2, "path");
	lua_pushstring(L, "");
	lua_setfield(L, -2, "cpath");
	lua_pop(L, 1);
}

static int open_evo(lua_State *L)
{
	lua_newtable(L);
	lua_pushnumber(L, EVO_TRUE);
	lua_setfield(L, -2, "TRUE");
	lua_pushnumber(L, EVO_FALSE);
	lua_setfield(L, -2, "FALSE");
	lua_pushstring(L, "nearest_object");
	lua_setfield(L, -2, "NEAREST_OBJECT");
	return 1;
}

static int setup(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	luaL_openlibs(L);
	lua_pushlightuserdata(L, l);
	lua_rawsetp(L, LUA_REGISTRYINDEX, &CTX_KEY);
	new_class(L, BOT_MT, bot_methods);
	new_class(L, ELEMENT_MT, element_methods);
	new_class(L, SCENE_MT, scene_methods);
	/* the one scene object */
	lua_newuserdatauv(L, 1, 0);
	luaL_setmetatable(L, SCENE_MT);
	lua_rawsetp(L, LUA_REGISTRYINDEX, &SCENE_MT);
	luaL_requiref(L, "evo", open_evo, 0);
	lua_pop(L, 1);
	/* require finds modules beside the scripts: the mind folder first */
	evo_lua_set_path(L, l->mind_dir, l->lua_dir);
	return 0;
}

evo_lua *evo_lua_create(const evo_lua_def *def, evo_err *err)
{
	evo_lua *l = calloc(1, sizeof *l);
	if (!l) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	l->sc = def->scene;
	l->task = def->task;
	l->env_ref = LUA_NOREF;
	snprintf(l->mind_dir, sizeof l->mind_dir, "%s",
		 def->mind_dir ? def->mind_dir : "");
	snprintf(l->lua_dir, sizeof l->lua_dir, "%s",
		 def->lua_dir ? def->lua_dir : evo_lua_dir());
	snprintf(l->botmodel, sizeof l->botmodel, "%s",
		 def->botmodel ? def->botmodel : "");
	l->L = luaL_newstate();
	if (!l->L) {
		free(l);
		evo_fail(err, "cannot create a Lua state");
		return NULL;
	}
	lua_pushcfunction(l->L, setup);
	lua_pushlightuserdata(l->L, l);
	if (lua_pcall(l->L, 1, 0, 0) != LUA_OK) {
		evo_fail(err, "Lua setup: %s", lua_tostring(l->L, -1));
		evo_lua_destroy(l);
		return NULL;
	}
	l->sc->hooks.ctx = l;
	l->sc->hooks.reward = hook_reward;
	l->sc->hooks.control = hook_control;
	return l;
}

void evo_lua_destroy(evo_lua *l)
{
	if (!l)
		return;
	if (l->sc && l->sc->hooks.ctx == l)
		memset(&l->sc->hooks, 0, sizeof l->sc->hooks);
	lua_close(l->L);
	free(l);
}

static int load_env(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	run_file(L, l->env_path, "an environment");
	if (lua_getfield(L, -1, "init") != LUA_TFUNCTION)
		luaL_error(L, "%s: the environment has no init(scene, task)",
			   l->env_path);
	lua_pop(L, 1);
	return 1;
}

int evo_lua_init_env(evo_lua *l, const char *env, evo_err *err)
{
	if (find_script(l, "Envs", "envs", env, l->env_path,
			sizeof l->env_path))
		return evo_fail(err,
				"environment '%s' not found: looked for "
				"%s/Envs/%s.lua and %s/envs/%s.lua",
				env, l->mind_dir[0] ? l->mind_dir : ".", env,
				l->lua_dir, env);
	lua_State *L = l->L;
	lua_pushcfunction(L, load_env);
	lua_pushlightuserdata(L, l);
	if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
		evo_fail(err, "%s", lua_tostring(L, -1));
		lua_pop(L, 1);
		return -1;
	}
	l->env_ref = luaL_ref(L, LUA_REGISTRYINDEX);
	if (call_env(l, "init", 2, 0, err))
		return -1;
	if (l->sc->n_bots == 0)
		return evo_fail(err, "%s: init added no bot (call scene:bot{...})",
				l->env_path);
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	l->has_post_step = lua_getfield(L, -1, "post_step") == LUA_TFUNCTION;
	lua_pop(L, 2);
	if (l->has_post_step)
		l->sc->hooks.post_step = hook_post_step;
	return 0;
}

int evo_lua_reset(evo_lua *l, int episode, evo_err *err)
{
	return call_env(l, "reset", 1, episode, err);
}

const char *evo_lua_env_path(const evo_lua *l)
{
	return l->env_path;
}

const char *evo_lua_bot_path(const evo_lua *l)
{
	return l->bot_path;
}
