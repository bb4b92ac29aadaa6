/* The 3D scene's methods in the scene scripts' `evo` module (docs/world3d.md):
 * a 3D environment's scene, its bots and its elements, in the style of
 * the 2D ones (lua_scene.c, lua_bot.c). Every option table is checked by
 * key: an unknown key is an error naming the ones the function knows.
 * Angles are degrees in Lua, radians in C. */
#include <string.h>

#include "lua/lua_internal.h"
#include "scene/kinds.h"

/* ---- handles ------------------------------------------------------------ */

static evo_scene3d *scene3d(lua_State *L)
{
	return evo_lua_ctx(L)->sc3;
}

static int check_bot3d(lua_State *L, int idx)
{
	int i = *(int *)luaL_checkudata(L, idx, EVO_LUA_BOT3D_MT);
	if (i < 0 || i >= scene3d(L)->n_bots)
		luaL_error(L, "stale bot handle");
	return i;
}

static int check_element3d(lua_State *L, int idx)
{
	int i = *(int *)luaL_checkudata(L, idx, EVO_LUA_ELEMENT3D_MT);
	if (i < 0 || i >= scene3d(L)->n_elements)
		luaL_error(L, "stale element handle");
	return i;
}

static int result(lua_State *L, int r)
{
	if (r < 0)
		luaL_error(L, "%s", scene3d(L)->err.msg);
	return r;
}

/* An options table at idx (nil: an empty one), checked by key. */
static void options(lua_State *L, int idx, const char *what,
		    const char *const *keys)
{
	if (lua_isnoneornil(L, idx)) {
		lua_settop(L, idx - 1);
		lua_newtable(L);
	}
	evo_lua_check_keys(L, idx, what, keys);
}

static double num(lua_State *L, int idx, const char *key, double dflt,
		  const char *what)
{
	return evo_lua_opt_num(L, idx, key, dflt, what);
}

/* x, y, z of the table at idx into v (each defaulting to v's). */
static void opt_xyz(lua_State *L, int idx, double v[3], const char *what)
{
	v[0] = num(L, idx, "x", v[0], what);
	v[1] = num(L, idx, "y", v[1], what);
	v[2] = num(L, idx, "z", v[2], what);
}

/* A vector option {x, y, z} (a list of three numbers). */
static void opt_vec(lua_State *L, int idx, const char *key, double v[3],
		    const char *what)
{
	lua_getfield(L, idx, key);
	if (!lua_isnil(L, -1)) {
		if (!lua_istable(L, -1) || luaL_len(L, -1) != 3)
			luaL_error(L, "%s: %s must be a list of three numbers",
				   what, key);
		for (int k = 0; k < 3; k++) {
			lua_geti(L, -1, k + 1);
			int ok;
			v[k] = lua_tonumberx(L, -1, &ok);
			if (!ok || !isfinite(v[k]))
				luaL_error(L,
					   "%s: %s must be a list of three "
					   "numbers",
					   what, key);
			lua_pop(L, 1);
		}
	}
	lua_pop(L, 1);
}

/* A target option: an element handle or nil. The 2D trackers of teams,
 * "nearest_opponent" and "nearest_teammate" (docs/teams.md), are 2D only:
 * the 3D world has no broad-phase query of bots near a bot yet. */
static int opt_target(lua_State *L, int idx, const char *what)
{
	lua_getfield(L, idx, "target");
	int t = EVO3D_TARGET_NONE;
	if (!lua_isnil(L, -1)) {
		if (!luaL_testudata(L, -1, EVO_LUA_ELEMENT3D_MT))
			luaL_error(L, "%s: target must be an element, found %s",
				   what, luaL_typename(L, -1));
		t = check_element3d(L, lua_gettop(L));
	}
	lua_pop(L, 1);
	return t;
}

/* The `bot` option: a bot handle, else the first bot. */
static int opt_bot(lua_State *L, int idx, const char *what)
{
	lua_getfield(L, idx, "bot");
	int b = 0;
	if (!lua_isnil(L, -1)) {
		if (!luaL_testudata(L, -1, EVO_LUA_BOT3D_MT))
			luaL_error(L, "%s: bot must be a bot, found %s", what,
				   luaL_typename(L, -1));
		b = check_bot3d(L, lua_gettop(L));
	} else if (scene3d(L)->n_bots == 0) {
		luaL_error(L, "%s: there is no bot yet", what);
	}
	lua_pop(L, 1);
	return b;
}

static int sensor_index(lua_State *L, int bot, const char *name,
			const char *what)
{
	const evo_bot3d *b = &scene3d(L)->bot[bot];
	int s = evo_bot3d_find_sensor(b, name);
	if (s < 0)
		luaL_error(L, "%s: bot '%s' has no sensor '%s'", what, b->name,
			   name);
	return s;
}

static void no_new_pieces(lua_State *L, const char *what)
{
	if (evo_lua_ctx(L)->in_reset)
		luaL_error(L,
			   "%s: elements, bots, rewards and controls are "
			   "added in init, not in reset (an obstacle of "
			   "the episode is scene:obstacle{...})",
			   what);
}

/* ---- bot: sensors ---------------------------------------------------------
 */

static const char *const prox_keys[] = {"name", "x",	 "y",	  "z",
					"yaw",	"pitch", "range", "arc",
					"rays", "sees",	 NULL};
static const char *const target_keys[] = {"name", "x",	    "y",
					  "z",	  "target", NULL};
static const char *const distance_keys[] = {"name",   "x",     "y", "z",
					    "target", "scale", NULL};
static const char *const tsensor_keys[] = {"name",   "x",    "y", "z",
					   "target", "axis", NULL};
static const char *const zone_sensor_keys[] = {"name", "target", NULL};
static const char *const name_keys[] = {"name", NULL};
static const char *const constant_keys[] = {"name", "value", NULL};
static const char *const light_keys[] = {"name", "x",	     "y",
					 "z",	 "yaw", "aperture", NULL};
static const char *const ground_keys[] = {"name", "x", "y", "z", NULL};
static const char *const rab_keys[] = {"name",	"range",    "slot",  "read",
				       "index", "occluded", "scale", NULL};
static const char *const camera_keys[] = {"name",   "range",	"slot",
					  "read",   "colour",	"occluded",
					  "scale", NULL};

/* `sees`: a list of "ground", "obstacles", "bots", "objects". A 3D ray
 * tells no teammate from an opponent: "teammates" and "opponents" are 2D
 * only (docs/teams.md). */
static unsigned parse_sees(lua_State *L, int idx, unsigned dflt,
			   const char *what)
{
	static const char *const words[] = {"ground", "bots", "obstacles",
					    "objects"};
	lua_getfield(L, idx, "sees");
	unsigned mask = dflt;
	if (!lua_isnil(L, -1)) {
		luaL_checktype(L, -1, LUA_TTABLE);
		mask = 0;
		lua_Integer n = luaL_len(L, -1);
		for (lua_Integer i = 1; i <= n; i++) {
			lua_geti(L, -1, i);
			const char *s = lua_tostring(L, -1);
			int w = 0;
			while (w < 4 && !(s && strcmp(s, words[w]) == 0))
				w++;
			if (w == 4)
				luaL_error(L,
					   "%s: sees lists \"ground\", "
					   "\"bots\", \"obstacles\" or "
					   "\"objects\", found %s",
					   what, s ? s : luaL_typename(L, -1));
			mask |= 1u << w; /* EVO_CAT3D_* in this order */
			lua_pop(L, 1);
		}
	}
	lua_pop(L, 1);
	return mask;
}

static int add_sensor(lua_State *L, evo_sensor3d_kind kind, const char *what,
		      const char *const *keys)
{
	int bot = check_bot3d(L, 1);
	options(L, 2, what, keys);
	evo_sensor3d_def d = evo_default_sensor3d_def(kind);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: a sensor needs a name", what);
	opt_xyz(L, 2, d.pos, what);
	switch (kind) {
	case EVO3D_SENSOR_PROXIMITY: {
		d.yaw = num(L, 2, "yaw", 0, what) * EVO_LUA_DEG;
		d.pitch = num(L, 2, "pitch", 0, what) * EVO_LUA_DEG;
		d.range = num(L, 2, "range", d.range, what);
		d.arc = num(L, 2, "arc", 0, what) * EVO_LUA_DEG;
		double rays = num(L, 2, "rays", d.rays, what);
		if (rays != floor(rays) || rays < 1 ||
		    rays > EVO3D_PROX_MAX_RAYS)
			luaL_error(L,
				   "%s: rays must be a whole number, 1 to %d",
				   what, EVO3D_PROX_MAX_RAYS);
		d.rays = (int)rays;
		d.mask = parse_sees(L, 2, d.mask, what);
		break;
	}
	case EVO3D_SENSOR_DISTANCE:
		d.scale = num(L, 2, "scale", d.scale, what);
		d.target = opt_target(L, 2, what);
		break;
	case EVO3D_SENSOR_AZIMUTH:
	case EVO3D_SENSOR_ELEVATION:
		/* the tutorial's TargetSensor:1 and TargetSensor:2 */
		if (keys == tsensor_keys) {
			double axis = num(L, 2, "axis", 1, what);
			if (axis != 1 && axis != 2)
				luaL_error(L,
					   "%s: axis is 1 (azimuth) or 2 "
					   "(elevation), as in the "
					   "tutorial's TargetSensor:1 and "
					   "TargetSensor:2",
					   what);
			d.kind = axis == 1 ? EVO3D_SENSOR_AZIMUTH
					   : EVO3D_SENSOR_ELEVATION;
		}
		d.target = opt_target(L, 2, what);
		break;
	case EVO3D_SENSOR_ZONE:
		d.target = opt_target(L, 2, what);
		break;
	case EVO3D_SENSOR_CONSTANT:
		d.value = num(L, 2, "value", 0.5, what);
		break;
	case EVO3D_SENSOR_LIGHT:
		d.yaw = num(L, 2, "yaw", 0, what) * EVO_LUA_DEG;
		evo_lua_swarm_sensor(L, 2, what, 0, &d.swarm);
		break;
	case EVO3D_SENSOR_RAB:
	case EVO3D_SENSOR_CAMERA:
		evo_lua_swarm_sensor(L, 2, what, kind == EVO3D_SENSOR_CAMERA,
				     &d.swarm);
		break;
	default:
		break;
	}
	result(L, evo_scene3d_add_sensor(scene3d(L), bot, &d));
	return 0;
}

static int bot_proximity(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_PROXIMITY, "bot:proximity",
			  prox_keys);
}
static int bot_distance(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_DISTANCE, "bot:distance",
			  distance_keys);
}
static int bot_azimuth(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_AZIMUTH, "bot:azimuth", target_keys);
}
/* bot:bearing: the 2D name of the same reading */
static int bot_bearing(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_AZIMUTH, "bot:bearing", target_keys);
}
static int bot_elevation(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_ELEVATION, "bot:elevation",
			  target_keys);
}
static int bot_target_sensor(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_AZIMUTH, "bot:target_sensor",
			  tsensor_keys);
}
static int bot_zone(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_ZONE, "bot:zone", zone_sensor_keys);
}
static int bot_random(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_RANDOM, "bot:random", name_keys);
}
static int bot_constant(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_CONSTANT, "bot:constant",
			  constant_keys);
}

static int bot_light(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_LIGHT, "bot:light", light_keys);
}
static int bot_ground(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_GROUND, "bot:ground", ground_keys);
}
static int bot_rab(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_RAB, "bot:rab", rab_keys);
}
static int bot_camera(lua_State *L)
{
	return add_sensor(L, EVO3D_SENSOR_CAMERA, "bot:camera", camera_keys);
}

/* ---- bot: actuators --------------------------------------------------- */

static int bot_broadcast(lua_State *L)
{
	static const char *const keys[] = {"name", NULL};
	const char *what = "bot:broadcast";
	int bot = check_bot3d(L, 1);
	options(L, 2, what, keys);
	evo_actuator3d_def d =
	    evo_default_actuator3d_def(EVO3D_ACTUATOR_BROADCAST);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: an actuator needs a name", what);
	result(L, evo_scene3d_add_actuator(scene3d(L), bot, &d));
	return 0;
}

static int bot_wheel(lua_State *L)
{
	static const char *const keys[] = {
	    "name", "x",	"y",	"z",	    "radius",	  "width",
	    "mass", "friction", "mode", "max_rate", "max_torque", NULL};
	const char *what = "bot:wheel";
	int bot = check_bot3d(L, 1);
	options(L, 2, what, keys);
	evo_actuator3d_def d = evo_default_actuator3d_def(EVO3D_ACTUATOR_WHEEL);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: a wheel needs a name", what);
	opt_xyz(L, 2, d.pos, what);
	d.radius = num(L, 2, "radius", d.radius, what);
	d.half_width = num(L, 2, "width", 2 * d.half_width, what) / 2;
	d.mass = num(L, 2, "mass", d.mass, what);
	d.friction = num(L, 2, "friction", d.friction, what);
	const char *mode = evo_lua_opt_str(L, 2, "mode", "velocity", what);
	if (strcmp(mode, "velocity") == 0)
		d.torque_mode = 0;
	else if (strcmp(mode, "torque") == 0)
		d.torque_mode = 1;
	else
		luaL_error(L,
			   "%s: mode is \"velocity\" or \"torque\", found "
			   "\"%s\"",
			   what, mode);
	d.max_rate = num(L, 2, "max_rate", d.max_rate, what);
	d.max_torque = num(L, 2, "max_torque", d.max_torque, what);
	result(L, evo_scene3d_add_actuator(scene3d(L), bot, &d));
	return 0;
}

static int bot_propeller(lua_State *L)
{
	static const char *const keys[] = {"name", "x",		 "y", "z",
					   "axis", "max_thrust", NULL};
	const char *what = "bot:propeller";
	int bot = check_bot3d(L, 1);
	options(L, 2, what, keys);
	evo_actuator3d_def d =
	    evo_default_actuator3d_def(EVO3D_ACTUATOR_PROPELLER);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: a propeller needs a name", what);
	opt_xyz(L, 2, d.pos, what);
	opt_vec(L, 2, "axis", d.axis, what);
	d.max_thrust = num(L, 2, "max_thrust", d.max_thrust, what);
	result(L, evo_scene3d_add_actuator(scene3d(L), bot, &d));
	return 0;
}

/* ---- bot: the rest ------------------------------------------------------- */

/* bot:target(sensor_name, element): point a distance, azimuth, elevation
 * or zone sensor at an element. */
static int bot_target(lua_State *L)
{
	int bot = check_bot3d(L, 1);
	int s = sensor_index(L, bot, luaL_checkstring(L, 2), "bot:target");
	int e = check_element3d(L, 3);
	scene3d(L)->bot[bot].sensor[s].def.target = e;
	return 0;
}

/* bot:place{x, y, z, yaw}: this episode's start (in reset). */
static int bot_place(lua_State *L)
{
	static const char *const keys[] = {"x", "y", "z", "yaw", NULL};
	const char *what = "bot:place";
	int bot = check_bot3d(L, 1);
	options(L, 2, what, keys);
	evo_bot3d *b = &scene3d(L)->bot[bot];
	double p[3];
	memcpy(p, b->start, sizeof p);
	opt_xyz(L, 2, p, what);
	double yaw = num(L, 2, "yaw", b->start_yaw / EVO_LUA_DEG, what);
	result(L, evo_scene3d_place_bot(scene3d(L), bot, p, yaw * EVO_LUA_DEG));
	return 0;
}

static int bot_pos(lua_State *L)
{
	const evo_bot3d *b = &scene3d(L)->bot[check_bot3d(L, 1)];
	for (int k = 0; k < 3; k++)
		lua_pushnumber(L, b->pos[k]);
	return 3;
}

static int bot_name(lua_State *L)
{
	lua_pushstring(L, scene3d(L)->bot[check_bot3d(L, 1)].name);
	return 1;
}

/* bot:sensors([kind]): the names of its sensors (of one kind). */
static int bot_sensors(lua_State *L)
{
	static const char *const kinds[] = {"proximity", "light", "ground",
					    "rab", "camera"};
	static const evo_sensor3d_kind ids[] = {
	    EVO3D_SENSOR_PROXIMITY, EVO3D_SENSOR_LIGHT, EVO3D_SENSOR_GROUND,
	    EVO3D_SENSOR_RAB, EVO3D_SENSOR_CAMERA};
	const evo_bot3d *b = &scene3d(L)->bot[check_bot3d(L, 1)];
	const char *kind = luaL_optstring(L, 2, NULL);
	int k = -1;
	for (int i = 0; kind && i < 5; i++)
		if (strcmp(kind, kinds[i]) == 0)
			k = i;
	if (kind && k < 0)
		luaL_error(L, "bot:sensors: kind is \"proximity\", \"light\", "
			      "\"ground\", \"rab\", \"camera\" or nothing");
	lua_newtable(L);
	int n = 0;
	for (int i = 0; i < b->n_sensors; i++)
		if (!kind || b->sensor[i].def.kind == ids[k]) {
			lua_pushstring(L, b->sensor[i].name);
			lua_rawseti(L, -2, ++n);
		}
	return 1;
}

/* bot:value(name): the sensor's value now. */
/* bot:team(): its team's name, or nil. */
static int bot_team(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int t = scene3d(L)->bot[check_bot3d(L, 1)].def.team;
	if (t >= 0 && t < l->n_teams)
		lua_pushstring(L, l->team[t].name);
	else
		lua_pushnil(L);
	return 1;
}

static int bot_value(lua_State *L)
{
	int bot = check_bot3d(L, 1);
	int s = sensor_index(L, bot, luaL_checkstring(L, 2), "bot:value");
	lua_pushnumber(L, evo_sensor3d_sample(scene3d(L), bot, s));
	return 1;
}

const luaL_Reg evo_lua_bot3d_methods[] = {
    {"proximity", bot_proximity}, {"distance", bot_distance},
    {"azimuth", bot_azimuth},	  {"bearing", bot_bearing},
    {"elevation", bot_elevation}, {"target_sensor", bot_target_sensor},
    {"zone", bot_zone},		  {"random", bot_random},
    {"constant", bot_constant},	  {"wheel", bot_wheel},
    {"propeller", bot_propeller}, {"target", bot_target},
    {"place", bot_place},	  {"pos", bot_pos},
    {"name", bot_name},		  {"sensors", bot_sensors},
    {"value", bot_value},	  {"light", bot_light},
    {"ground", bot_ground},	  {"rab", bot_rab},
    {"broadcast", bot_broadcast}, {"camera", bot_camera},
    {"team", bot_team},
    {NULL, NULL},
};

/* ---- elements ------------------------------------------------------------ */

static int element_pos(lua_State *L)
{
	const evo_element3d *e = &scene3d(L)->element[check_element3d(L, 1)];
	for (int k = 0; k < 3; k++)
		lua_pushnumber(L, e->pos[k]);
	return 3;
}

/* element:place{x, y, z}: move a target or zone (this episode). */
static int element_place(lua_State *L)
{
	static const char *const keys[] = {"x", "y", "z", NULL};
	const char *what = "element:place";
	int i = check_element3d(L, 1);
	evo_element3d *e = &scene3d(L)->element[i];
	if (e->def.kind != EVO3D_ELEM_TARGET && e->def.kind != EVO3D_ELEM_ZONE)
		luaL_error(L, "%s: only targets and zones move; %s is fixed",
			   what, e->name);
	options(L, 2, what, keys);
	double p[3];
	memcpy(p, e->pos, sizeof p);
	opt_xyz(L, 2, p, what);
	evo_scene3d_place_element(scene3d(L), i, p);
	return 0;
}

static int element_name(lua_State *L)
{
	lua_pushstring(L, scene3d(L)->element[check_element3d(L, 1)].name);
	return 1;
}

const luaL_Reg evo_lua_element3d_methods[] = {
    {"pos", element_pos},
    {"place", element_place},
    {"name", element_name},
    {NULL, NULL},
};

/* ---- scene: elements --------------------------------------------------------
 */

static const char *const box_keys[] = {
    "name", "x", "y", "z", "yaw", "hx", "hy", "hz", "friction", "ground", NULL};
static const char *const cylinder_keys[] = {
    "name", "x", "y", "z", "radius", "height", "friction", "ground", NULL};
static const char *const sphere_keys[] = {"name",   "x",	"y",	  "z",
					  "radius", "friction", "ground", NULL};
static const char *const zone_keys[] = {"name", "x",  "y",  "z", "yaw",
					"hx",	"hy", "hz", NULL};
static const char *const target_el_keys[] = {"name", "x",      "y",
					     "z",    "radius", NULL};
static const char *const object_keys[] = {"name", "x",	    "y",	"z",
					  "yaw",  "radius", "hx",	"hy",
					  "hz",	  "mass",   "friction", NULL};

static void read_element(lua_State *L, evo_element3d_def *d, const char *what)
{
	d->name = evo_lua_opt_str(L, 2, "name", NULL, what);
	opt_xyz(L, 2, d->pos, what);
	d->yaw = num(L, 2, "yaw", 0, what) * EVO_LUA_DEG;
	d->half[0] = num(L, 2, "hx", d->half[0], what);
	d->half[1] = num(L, 2, "hy", d->half[1], what);
	d->half[2] = num(L, 2, "hz", d->half[2], what);
	d->radius = num(L, 2, "radius", d->radius, what);
	d->half_length = num(L, 2, "height", 2 * d->half_length, what) / 2;
	d->mass = num(L, 2, "mass", d->mass, what);
	d->friction = num(L, 2, "friction", d->friction, what);
	lua_getfield(L, 2, "ground");
	if (!lua_isnil(L, -1) && !lua_isboolean(L, -1))
		luaL_error(L, "%s: ground must be true or false, found %s",
			   what, luaL_typename(L, -1));
	d->ground = lua_toboolean(L, -1);
	lua_pop(L, 1);
}

static int add_element(lua_State *L, evo_element3d_kind kind, const char *what,
		       const char *const *keys)
{
	no_new_pieces(L, what);
	options(L, 2, what, keys);
	evo_element3d_def d = evo_default_element3d_def(kind);
	read_element(L, &d, what);
	if (kind == EVO3D_ELEM_OBJECT) {
		lua_getfield(L, 2, "radius");
		d.sphere = !lua_isnil(L, -1);
		lua_pop(L, 1);
	}
	int i = result(L, evo_scene3d_add_element(scene3d(L), &d));
	evo_lua_push_handle(L, EVO_LUA_ELEMENT3D_MT, i);
	return 1;
}

static int scene_box(lua_State *L)
{
	return add_element(L, EVO3D_ELEM_BOX, "scene:box", box_keys);
}
static int scene_cylinder(lua_State *L)
{
	return add_element(L, EVO3D_ELEM_CYLINDER, "scene:cylinder",
			   cylinder_keys);
}
static int scene_sphere(lua_State *L)
{
	return add_element(L, EVO3D_ELEM_SPHERE, "scene:sphere", sphere_keys);
}
static int scene_zone(lua_State *L)
{
	return add_element(L, EVO3D_ELEM_ZONE, "scene:zone", zone_keys);
}
static int scene_target(lua_State *L)
{
	return add_element(L, EVO3D_ELEM_TARGET, "scene:target",
			   target_el_keys);
}
static int scene_object(lua_State *L)
{
	return add_element(L, EVO3D_ELEM_OBJECT, "scene:object", object_keys);
}

/* scene:obstacle{shape = "box" | "cylinder" | "sphere", ...}: a static
 * obstacle of this episode only, from an environment's reset. */
static int scene_obstacle(lua_State *L)
{
	static const char *const keys[] = {
	    "shape", "x",      "y",	 "z",	     "yaw",    "hx", "hy",
	    "hz",    "radius", "height", "friction", "ground", NULL};
	const char *what = "scene:obstacle";
	if (!evo_lua_ctx(L)->in_reset)
		luaL_error(L,
			   "%s: an episode's obstacles are added in the "
			   "environment's reset (scene:box and the others "
			   "add those of every episode in init)",
			   what);
	options(L, 2, what, keys);
	const char *shape = evo_lua_opt_str(L, 2, "shape", "box", what);
	evo_element3d_kind kind;
	if (strcmp(shape, "box") == 0)
		kind = EVO3D_ELEM_BOX;
	else if (strcmp(shape, "cylinder") == 0)
		kind = EVO3D_ELEM_CYLINDER;
	else if (strcmp(shape, "sphere") == 0)
		kind = EVO3D_ELEM_SPHERE;
	else
		return luaL_error(L,
				  "%s: shape is \"box\", \"cylinder\" or "
				  "\"sphere\", found \"%s\"",
				  what, shape);
	evo_element3d_def d = evo_default_element3d_def(kind);
	read_element(L, &d, what);
	evo_obstacle3d o;
	memset(&o, 0, sizeof o);
	o.type = kind == EVO3D_ELEM_BOX	       ? EVO_SHAPE3D_BOX
		 : kind == EVO3D_ELEM_CYLINDER ? EVO_SHAPE3D_CYLINDER
					       : EVO_SHAPE3D_SPHERE;
	memcpy(o.pos, d.pos, sizeof o.pos);
	o.yaw = d.yaw;
	memcpy(o.half, d.half, sizeof o.half);
	o.radius = d.radius;
	o.half_length = d.half_length;
	o.friction = d.friction;
	o.category = d.ground ? EVO_CAT3D_GROUND : EVO_CAT3D_OBSTACLE;
	result(L, evo_scene3d_add_episode_obstacle(scene3d(L), &o));
	return 0;
}

/* ---- scene: bots
 * ------------------------------------------------------------- */

/* The model's hull table (at the top of the stack) into d. */
static int read_hull(lua_State *L)
{
	static const char *const keys[] = {
	    "shape",	      "hx",	      "hy",	  "hz",
	    "radius",	      "mass",	      "friction", "z",
	    "caster",	      "buoyancy",     "cob",	  "drag_linear",
	    "drag_quadratic", "drag_angular", NULL};
	static const char *const caster_keys[] = {"x", "y", "z", "radius",
						  NULL};
	const char *what = "hull";
	evo_bot3d_def *d = lua_touserdata(L, 2);
	options(L, 1, what, keys);
	const char *shape = evo_lua_opt_str(L, 1, "shape", "box", what);
	if (strcmp(shape, "box") == 0) {
		d->radius = 0;
		d->half[0] = num(L, 1, "hx", d->half[0], what);
		d->half[1] = num(L, 1, "hy", d->half[1], what);
		d->half[2] = num(L, 1, "hz", d->half[2], what);
	} else if (strcmp(shape, "sphere") == 0) {
		d->radius = num(L, 1, "radius", 0.25, what);
	} else {
		luaL_error(L,
			   "%s: shape is \"box\" or \"sphere\", found "
			   "\"%s\"",
			   what, shape);
	}
	d->mass = num(L, 1, "mass", d->mass, what);
	d->friction = num(L, 1, "friction", d->friction, what);
	d->pos[2] = num(L, 1, "z", d->pos[2], what);
	d->buoyancy = num(L, 1, "buoyancy", 0, what);
	opt_vec(L, 1, "cob", d->cob, what);
	d->drag_linear = num(L, 1, "drag_linear", 0, what);
	d->drag_quadratic = num(L, 1, "drag_quadratic", 0, what);
	d->drag_angular = num(L, 1, "drag_angular", 0, what);
	if (lua_getfield(L, 1, "caster") != LUA_TNIL) {
		int c = lua_gettop(L);
		evo_lua_check_keys(L, c, "hull.caster", caster_keys);
		opt_xyz(L, c, d->caster_pos, "hull.caster");
		d->caster_radius = num(L, c, "radius", 0.04, "hull.caster");
	}
	lua_pop(L, 1);
	return 0;
}

/* scene:bot{name, x, y, z, yaw, model}: a bot of the task's BOTMODEL (or
 * model), whose hull the model's `hull` table gives, built by its
 * build(bot). z defaults to the hull's. */
static int scene_bot(lua_State *L)
{
	static const char *const keys[] = {"name",  "x",    "y", "z", "yaw",
					   "model", "team", NULL};
	const char *what = "scene:bot";
	evo_lua *l = evo_lua_ctx(L);
	no_new_pieces(L, what);
	options(L, 2, what, keys);
	char auto_name[64];
	const char *model;
	int team = evo_lua_bot_team(L, 2, what, l->sc3->n_bots, &model,
				    auto_name, sizeof auto_name);
	lua_settop(L, 2);
	/* the model's table at 3 */
	evo_lua_load_model(L, l, model,
			   team >= 0 ? l->team[team].mind_dir : NULL);
	evo_bot3d_def d = evo_default_bot3d_def();
	d.team = team;
	d.name = evo_lua_opt_str(L, 2, "name", auto_name, what);
	if (lua_getfield(L, 3, "hull") != LUA_TTABLE)
		luaL_error(
		    L, "%s: a 3D bot model has a hull table (docs/world3d.md)",
		    l->bot_path);
	/* a mistake in the hull is the bot model's: its file first */
	lua_pushcfunction(L, read_hull);
	lua_insert(L, -2);
	lua_pushlightuserdata(L, &d);
	if (lua_pcall(L, 2, 0, 0) != LUA_OK) {
		lua_pushfstring(L, "%s: %s", l->bot_path,
				evo_lua_errstr(L, -1));
		return lua_error(L);
	}
	opt_xyz(L, 2, d.pos, what);
	d.yaw = num(L, 2, "yaw", 0, what) * EVO_LUA_DEG;
	int i = result(L, evo_scene3d_add_bot(l->sc3, &d));
	if (team >= 0)
		l->team[team].made++;
	lua_getfield(L, 3, "build");
	if (!lua_isfunction(L, -1))
		luaL_error(L, "bot model %s: has no build(bot) function",
			   model);
	evo_lua_push_handle(L, EVO_LUA_BOT3D_MT, i);
	lua_call(L, 1, 0);
	evo_lua_push_handle(L, EVO_LUA_BOT3D_MT, i);
	return 1;
}

/* ---- scene: rewards and controls --------------------------------------------
 */

/* The reward (reward 1) or control (0) named at idx, by the scene model's
 * names (scene/kinds.h: the tutorial's RW_ and CF_ prefixes allowed);
 * one that is not in 3D is an error that says so. */
static int kind_by_name(lua_State *L, int idx, int reward, const char *what)
{
	const char *s = luaL_checkstring(L, idx);
	const char *noun = reward ? "reward" : "control";
	int k =
	    reward ? evo_reward_kind_by_name(s) : evo_control_kind_by_name(s);
	unsigned dims =
	    reward ? evo_reward_kind_dims(k) : evo_control_kind_dims(k);
	if (k == (reward ? (int)EVO_RW_LUA : (int)EVO_CF_LUA))
		return luaL_error(L,
				  "%s: for a %s of your own, pass a Lua "
				  "function, not the name '%s'",
				  what, noun, s);
	if (k >= 0 && (dims & EVO_DIM_3D))
		return k;
	if (k >= 0)
		return luaL_error(L, "%s: %s '%s' is 2D only (docs/world3d.md)",
				  what, noun, s);
	const char *c = reward ? evo_reward_kind_closest(s, EVO_DIM_3D)
			       : evo_control_kind_closest(s, EVO_DIM_3D);
	return luaL_error(L, "%s: no %s '%s' in 3D (did you mean %s?)", what,
			  noun, s, c ? c : "?");
}

/* The bots a built-in reward or control is for: its `bot` (the first bot
 * when absent), or with `team`, each bot of the team (docs/teams.md).
 * Fills bots (EVO_TEAM_BOTS_MAX of room) and returns how many. */
static int scope_bots(lua_State *L, const char *what, int *bots)
{
	int team = evo_lua_opt_team(L, 3, what);
	if (team < 0) {
		bots[0] = opt_bot(L, 3, what);
		return 1;
	}
	lua_getfield(L, 3, "bot");
	if (!lua_isnil(L, -1))
		luaL_error(L, "%s: give bot or team, not both", what);
	lua_pop(L, 1);
	const evo_scene3d *sc = scene3d(L);
	int n = 0;
	for (int i = 0; i < sc->n_bots && n < EVO_TEAM_BOTS_MAX; i++)
		if (sc->bot[i].def.team == team)
			bots[n++] = i;
	if (n == 0)
		luaL_error(L,
			   "%s: team %s has no bots yet: make them "
			   "(scene:bot{team = ...}) before its rewards and "
			   "controls",
			   what, evo_lua_ctx(L)->team[team].name);
	return n;
}

/* scene:reward(fn, {bot = b | team = NAME, reset = f}) and
 * scene:control(fn, {reset = f}): a Lua function as a reward (paid to the
 * scene, to bot, or to a team as a whole) or a control, called each tick
 * with the scene (sim/lua/lua_hooks.c), as in 2D. */
static int lua_function(lua_State *L, int reward, const char *what)
{
	static const char *const rkeys[] = {"reset", "bot", "team", NULL};
	static const char *const ckeys[] = {"reset", NULL};
	evo_scene3d *sc = scene3d(L);
	if (sc->n_bots == 0)
		luaL_error(L, "%s: there is no bot yet", what);
	if (!lua_isnoneornil(L, 3))
		evo_lua_check_keys(L, 3, what, reward ? rkeys : ckeys);
	evo_lua_function_options(L, what,
				 reward ? &evo_lua_reward_resets_key
					: &evo_lua_control_resets_key,
				 reward);
	lua_pushvalue(L, 2);
	int ref = luaL_ref(L, LUA_REGISTRYINDEX);
	if (!reward) {
		evo_control_def d = evo_default_control_def(EVO_CF_LUA);
		d.lua_ref = ref;
		result(L, evo_scene3d_add_control(sc, &d));
		return 0;
	}
	evo_reward_def d = evo_default_reward_def(EVO_RW_LUA);
	d.lua_ref = ref;
	d.scope = EVO_SCOPE_SCENE;
	if (lua_istable(L, 3)) {
		lua_getfield(L, 3, "bot");
		int has_bot = !lua_isnil(L, -1);
		lua_pop(L, 1);
		int team = evo_lua_opt_team(L, 3, what);
		if (has_bot && team >= 0)
			luaL_error(L, "%s: give bot or team, not both", what);
		if (has_bot) {
			d.bot = opt_bot(L, 3, what);
			d.scope = EVO_SCOPE_BOT;
		} else if (team >= 0) {
			d.team = team;
			d.scope = EVO_SCOPE_TEAM;
		}
	}
	result(L, evo_scene3d_add_reward(sc, &d));
	return 0;
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
				luaL_error(L, "%s: sensors lists names", what);
			d->sensor[d->n_sensors++] =
			    sensor_index(L, d->bot, s, what);
			lua_pop(L, 1);
		}
	}
	lua_pop(L, 1);
}

/* scene:reward(kind, {bot = b | team = NAME, ...}): with team, one such
 * reward for each bot of the team, each paying its own bot. */
static int scene_reward(lua_State *L)
{
	static const char *const keys[] = {"bot",	"team",	  "k",
					   "k2",	"threshold", "target",
					   "sensors", NULL};
	const char *what = "scene:reward";
	no_new_pieces(L, what);
	if (lua_isfunction(L, 2))
		return lua_function(L, 1, what);
	int kind = kind_by_name(L, 2, 1, what);
	options(L, 3, what, keys);
	int bots[EVO_TEAM_BOTS_MAX];
	int n = scope_bots(L, what, bots);
	for (int i = 0; i < n; i++) {
		evo_reward_def d =
		    evo_default_reward_def((evo_reward_kind)kind);
		d.bot = bots[i];
		d.k = num(L, 3, "k", d.k, what);
		d.k2 = num(L, 3, "k2", d.k2, what);
		d.threshold = num(L, 3, "threshold", d.threshold, what);
		d.target = opt_target(L, 3, what);
		reward_sensors(L, &d, what);
		result(L, evo_scene3d_add_reward(scene3d(L), &d));
	}
	return 0;
}

/* scene:control(kind, {bot = b | team = NAME, ...}): with team, one for
 * each bot of the team, the episode ending when any of them meets it. */
static int scene_control(lua_State *L)
{
	static const char *const keys[] = {"bot",    "team",	  "ticks",
					   "sensor", "target", "threshold",
					   NULL};
	const char *what = "scene:control";
	no_new_pieces(L, what);
	if (lua_isfunction(L, 2))
		return lua_function(L, 0, what);
	int kind = kind_by_name(L, 2, 0, what);
	options(L, 3, what, keys);
	int bots[EVO_TEAM_BOTS_MAX];
	int n = scope_bots(L, what, bots);
	for (int i = 0; i < n; i++) {
		evo_control_def d =
		    evo_default_control_def((evo_control_kind)kind);
		d.bot = bots[i];
		double ticks = num(L, 3, "ticks", (double)d.ticks, what);
		if (ticks < 1 || ticks != floor(ticks) || ticks > 1e15)
			luaL_error(L, "%s: ticks must be a whole number >= 1",
				   what);
		d.ticks = (long)ticks;
		d.threshold = num(L, 3, "threshold", d.threshold, what);
		d.target = opt_target(L, 3, what);
		const char *s = evo_lua_opt_str(L, 3, "sensor", NULL, what);
		if (s)
			d.sensor = sensor_index(L, d.bot, s, what);
		result(L, evo_scene3d_add_control(scene3d(L), &d));
	}
	return 0;
}

/* scene:bots([team]): the bots of a team in member order, or every bot. */
static int scene_bots(lua_State *L)
{
	int team = lua_isnoneornil(L, 2) ? -2
					 : evo_lua_check_team(
					       L, luaL_checkstring(L, 2),
					       "scene:bots");
	const evo_scene3d *sc = scene3d(L);
	lua_newtable(L);
	int n = 0;
	for (int i = 0; i < sc->n_bots; i++)
		if (team == -2 || sc->bot[i].def.team == team) {
			evo_lua_push_handle(L, EVO_LUA_BOT3D_MT, i);
			lua_rawseti(L, -2, ++n);
		}
	return 1;
}

/* scene:winner(team) sets the episode's winner (nil: none);
 * scene:winner() returns its name, or nil. */
static int scene_winner(lua_State *L)
{
	evo_scene3d *sc = scene3d(L);
	int w = evo_lua_winner(L, sc->winner);
	if (w == -2)
		return 1; /* the name pushed */
	sc->winner = w;
	return 0;
}

static int scene_teams(lua_State *L)
{
	evo_lua_push_teams(L);
	return 1;
}

/* ---- scene: the rest
 * ---------------------------------------------------------- */

/* scene:physics{...}: the world's settings, before the first bot. */
static int scene_physics(lua_State *L)
{
	static const char *const keys[] = {
	    "substeps", "step",		 "gravity",
	    "erp",	"cfm",		 "max_speed",
	    "max_spin", "fault_penalty", "ground_friction",
	    NULL};
	const char *what = "scene:physics";
	evo_scene3d *sc = scene3d(L);
	if (sc->n_bots > 0 || sc->n_elements > 0 || evo_lua_ctx(L)->ready)
		luaL_error(L,
			   "%s: set the physics first in init, before any "
			   "bot or element",
			   what);
	options(L, 2, what, keys);
	evo_scene3d_def d = sc->def;
	double sub = num(L, 2, "substeps", d.substeps, what);
	if (sub != floor(sub) || sub < 1 || sub > 100)
		luaL_error(L, "%s: substeps must be a whole number, 1 to 100",
			   what);
	d.substeps = (int)sub;
	d.world.step = num(L, 2, "step", 1.0 / 30.0, what) / d.substeps;
	d.world.gravity = num(L, 2, "gravity", d.world.gravity, what);
	d.world.erp = num(L, 2, "erp", d.world.erp, what);
	d.world.cfm = num(L, 2, "cfm", d.world.cfm, what);
	d.world.max_speed = num(L, 2, "max_speed", d.world.max_speed, what);
	d.world.max_spin = num(L, 2, "max_spin", d.world.max_spin, what);
	d.world.ground_friction =
	    num(L, 2, "ground_friction", d.world.ground_friction, what);
	d.fault_penalty = num(L, 2, "fault_penalty", d.fault_penalty, what);
	if (!(d.world.step > 0) || !(d.world.max_speed > 0) ||
	    !(d.world.max_spin > 0) || d.world.erp < 0 || d.world.erp > 1 ||
	    d.world.cfm < 0 || d.world.ground_friction < 0)
		luaL_error(L,
			   "%s: step, max_speed and max_spin must be > 0, "
			   "erp in [0, 1], cfm and ground_friction >= 0",
			   what);
	if (evo_scene3d_set_def(sc, &d))
		luaL_error(L, "%s: %s", what, sc->err.msg);
	return 0;
}

static int scene_element(lua_State *L)
{
	int i = evo_scene3d_find_element(scene3d(L), luaL_checkstring(L, 2));
	if (i < 0)
		lua_pushnil(L);
	else
		evo_lua_push_handle(L, EVO_LUA_ELEMENT3D_MT, i);
	return 1;
}

static int scene_get_bot(lua_State *L)
{
	int i = evo_scene3d_find_bot(scene3d(L), luaL_checkstring(L, 2));
	if (i < 0)
		lua_pushnil(L);
	else
		evo_lua_push_handle(L, EVO_LUA_BOT3D_MT, i);
	return 1;
}

/* scene:random(lo, hi): the episode's stream (its seed differs for every
 * candidate). */
static int scene_random(lua_State *L)
{
	double lo = luaL_optnumber(L, 2, 0), hi = luaL_optnumber(L, 3, 1);
	lua_pushnumber(L, evo_rng_range(&scene3d(L)->rng, lo, hi));
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
	lua_pushinteger(L, scene3d(L)->tick);
	return 1;
}

/* Forget what the reward functions remember (ClosingOnTarget's last
 * distance), e.g. after moving a target, and call the Lua rewards' own
 * resets: as in 2D. */
static int scene_reset_rewards(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	for (int i = 0; i < l->sc3->n_rewards; i++)
		evo_reward_reset(&l->sc3->reward[i]);
	evo_err err = {{0}};
	if (evo_lua_call_resets(l, &evo_lua_reward_resets_key, &err))
		luaL_error(L, "%s", err.msg);
	return 0;
}

static int scene_episode_reward(lua_State *L)
{
	lua_pushnumber(L, scene3d(L)->episode_reward);
	return 1;
}

/* scene:light{x, y, z, intensity}, scene:patch{...} (lua_swarm.c) */
static int scene_light(lua_State *L)
{
	evo_scene3d *sc = scene3d(L);
	evo_lua_add_light(L, 2, 3, &sc->swarm, &sc->err);
	return 0;
}

static int scene_patch(lua_State *L)
{
	evo_scene3d *sc = scene3d(L);
	evo_lua_add_patch(L, 2, 3, &sc->swarm, &sc->err);
	return 0;
}

/* scene:colour(bot or element, colour): what cameras see it as. */
static int scene_colour(lua_State *L)
{
	evo_scene3d *sc = scene3d(L);
	if (luaL_testudata(L, 2, EVO_LUA_BOT3D_MT))
		evo_lua_set_colour(L, EVO_BLOB_BOT, check_bot3d(L, 2),
				   &sc->swarm, &sc->err);
	else if (luaL_testudata(L, 2, EVO_LUA_ELEMENT3D_MT))
		evo_lua_set_colour(L, EVO_BLOB_ELEMENT, check_element3d(L, 2),
				   &sc->swarm, &sc->err);
	else
		luaL_error(L, "scene:colour: a bot or an element, found %s",
			   luaL_typename(L, 2));
	return 0;
}

const luaL_Reg evo_lua_scene3d_methods[] = {
    {"physics", scene_physics},
    {"bot", scene_bot},
    {"get_bot", scene_get_bot},
    {"box", scene_box},
    {"cylinder", scene_cylinder},
    {"sphere", scene_sphere},
    {"zone", scene_zone},
    {"target", scene_target},
    {"object", scene_object},
    {"obstacle", scene_obstacle},
    {"light", scene_light},
    {"patch", scene_patch},
    {"colour", scene_colour},
    {"reward", scene_reward},
    {"control", scene_control},
    {"element", scene_element},
    {"random", scene_random},
    {"layout_random", scene_layout_random},
    {"tick", scene_tick},
    {"episode_reward", scene_episode_reward},
    {"teams", scene_teams},
    {"bots", scene_bots},
    {"winner", scene_winner},
    {"reset_rewards", scene_reset_rewards},
    {"metric", evo_lua_scene_metric},
    {NULL, NULL},
};
