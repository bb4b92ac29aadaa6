/* Bot methods of the scene scripts' `evo` module (docs/lua.md): adding
 * sensors and actuators, and reading or placing a bot. */
#include <string.h>

#include "lua/lua_internal.h"
#include "world2d/actuators.h"
#include "world2d/sensors.h"

/* ---- bot: sensors and actuators ---------------------------------------- */

/* Each kind's options, as docs/lua.md lists them: an unknown key's
 * message names what this kind of sensor takes. */
static const char *const proximity_keys[] = {
    "name", "x", "y", "angle", "range", "arc", "rays", "deadzone", "sees",
    NULL};
static const char *const distance_keys[] = {"name",   "x",     "y",
					    "target", "scale", NULL};
static const char *const tracker_keys[] = {"name", "target", NULL};
static const char *const detector_keys[] = {"name",  "x",     "y",
					    "angle", "reach", "arc", NULL};
static const char *const movement_keys[] = {"name", "scale", NULL};
static const char *const name_keys[] = {"name", NULL};
static const char *const constant_keys[] = {"name", "value", NULL};
static const char *const radar_keys[] = {"name", "target", "angle", "arc",
					 NULL};
static const char *const bumper_keys[] = {"name", "angle", "arc", "reach",
					  "sees", NULL};
static const char *const light_keys[] = {"name", "x", "y", "angle",
					 "aperture", NULL};
static const char *const ground_keys[] = {"name", "x", "y", NULL};
static const char *const rab_keys[] = {"name",	"range",    "slot",  "read",
				       "index", "occluded", "scale", NULL};
static const char *const camera_keys[] = {"name",   "range",	"slot",
					  "read",   "colour",	"occluded",
					  "scale", NULL};

static const char *const *const sensor_keys[EVO_SENSOR_KIND_COUNT] = {
    [EVO_SENSOR_PROXIMITY] = proximity_keys,
    [EVO_SENSOR_DISTANCE] = distance_keys,
    [EVO_SENSOR_ZONE] = tracker_keys,
    [EVO_SENSOR_BEARING] = tracker_keys,
    [EVO_SENSOR_PRESENCE] = tracker_keys,
    [EVO_SENSOR_OBJECT] = detector_keys,
    [EVO_SENSOR_MOVEMENT] = movement_keys,
    [EVO_SENSOR_RANDOM] = name_keys,
    [EVO_SENSOR_CONSTANT] = constant_keys,
    [EVO_SENSOR_HOLDING] = name_keys,
    [EVO_SENSOR_RADAR] = radar_keys,
    [EVO_SENSOR_BUMPER] = bumper_keys,
    [EVO_SENSOR_LIGHT] = light_keys,
    [EVO_SENSOR_GROUND] = ground_keys,
    [EVO_SENSOR_RAB] = rab_keys,
    [EVO_SENSOR_CAMERA] = camera_keys,
};

/* `sees`: what a proximity sensor's rays hit, into d's mask and its
 * teammates and opponents flags (docs/lua.md, docs/teams.md). */
static void parse_sees(lua_State *L, int idx, const char *what,
		       evo_sensor_def *d)
{
	static const char *const words[] = {"obstacles", "bots", "objects",
					    "teammates", "opponents"};
	lua_getfield(L, idx, "sees");
	if (!lua_isnil(L, -1)) {
		luaL_checktype(L, -1, LUA_TTABLE);
		d->mask = 0;
		lua_Integer n = luaL_len(L, -1);
		if (n > 5)
			luaL_error(L,
				   "%s: sees lists at most \"obstacles\", "
				   "\"bots\", \"objects\", \"teammates\" "
				   "and \"opponents\"",
				   what);
		for (lua_Integer i = 1; i <= n; i++) {
			lua_geti(L, -1, i);
			const char *s = lua_tostring(L, -1);
			int w = 0;
			while (w < 5 && !(s && strcmp(s, words[w]) == 0))
				w++;
			if (w == 0)
				d->mask |= EVO_CAT_OBSTACLE;
			else if (w == 1)
				d->mask |= EVO_CAT_BOT;
			else if (w == 2)
				d->mask |= EVO_CAT_OBJECT;
			else if (w == 3)
				d->sees_teammates = 1;
			else if (w == 4)
				d->sees_opponents = 1;
			else
				luaL_error(L,
					   "%s: sees lists \"obstacles\", "
					   "\"bots\", \"objects\", "
					   "\"teammates\" or \"opponents\", "
					   "found %s",
					   what, s ? s : luaL_typename(L, -1));
			lua_pop(L, 1);
		}
	}
	lua_pop(L, 1);
}

static int add_sensor(lua_State *L, evo_sensor_kind kind, const char *what)
{
	int bot = evo_lua_check_bot(L, 1);
	evo_lua_check_keys(L, 2, what, sensor_keys[kind]);
	evo_sensor_def d = evo_default_sensor_def(kind);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: a sensor needs a name", what);
	d.x = evo_lua_opt_num(L, 2, "x", d.x, what);
	d.y = evo_lua_opt_num(L, 2, "y", d.y, what);
	d.angle = evo_lua_opt_num(L, 2, "angle", d.angle / EVO_LUA_DEG, what) *
		  EVO_LUA_DEG;
	d.range = evo_lua_opt_num(L, 2, "range", d.range, what);
	d.arc = evo_lua_opt_num(L, 2, "arc", d.arc / EVO_LUA_DEG, what) *
		EVO_LUA_DEG;
	double rays = evo_lua_opt_num(L, 2, "rays", d.rays, what);
	if (rays != floor(rays) || rays < 1 || rays > EVO_PROX_MAX_RAYS)
		luaL_error(L, "%s: rays must be a whole number from 1 to %d",
			   what, EVO_PROX_MAX_RAYS);
	d.rays = (int)rays;
	d.deadzone = evo_lua_opt_num(L, 2, "deadzone", d.deadzone, what);
	parse_sees(L, 2, what, &d);
	d.target = evo_lua_opt_target(L, 2, "target", what);
	d.scale = evo_lua_opt_num(L, 2, "scale", d.scale, what);
	d.reach = evo_lua_opt_num(L, 2, "reach", d.reach, what);
	d.value = evo_lua_opt_num(L, 2, "value", d.value, what);
	if (kind == EVO_SENSOR_LIGHT || kind == EVO_SENSOR_RAB ||
	    kind == EVO_SENSOR_CAMERA)
		evo_lua_swarm_sensor(L, 2, what, kind == EVO_SENSOR_CAMERA,
				     &d.swarm);
	lua_pushinteger(
	    L, evo_lua_scene_result(
		   L, evo_scene_add_sensor(evo_lua_ctx(L)->sc, bot, &d)) +
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
SENSOR_FN(radar, EVO_SENSOR_RADAR)
SENSOR_FN(bumper, EVO_SENSOR_BUMPER)
SENSOR_FN(light, EVO_SENSOR_LIGHT)
SENSOR_FN(ground, EVO_SENSOR_GROUND)
SENSOR_FN(rab, EVO_SENSOR_RAB)
SENSOR_FN(camera, EVO_SENSOR_CAMERA)

/* Each kind's options: a wheel has no reach and a claw no force, so
 * either one given to the other is an error, as for the sensors. */
static const char *const wheel_keys[] = {"name", "x", "y", "angle",
					 "max_force", NULL};
static const char *const claw_keys[] = {"name", "x", "y", "angle", "reach",
					NULL};
static const char *const speed_wheel_keys[] = {"name", "x", "y", "max_speed",
					       NULL};
static const char *const drive_keys[] = {"name", "turn", "max_speed", "accel",
					 NULL};
static const char *const broadcast_keys[] = {"name", NULL};
static const char *const *const actuator_keys[EVO_ACTUATOR_KIND_COUNT] = {
    [EVO_ACTUATOR_WHEEL] = wheel_keys,
    [EVO_ACTUATOR_CLAW] = claw_keys,
    [EVO_ACTUATOR_SPEED_WHEEL] = speed_wheel_keys,
    [EVO_ACTUATOR_DRIVE] = drive_keys,
    [EVO_ACTUATOR_BROADCAST] = broadcast_keys,
};

static int add_actuator(lua_State *L, evo_actuator_kind kind,
			const char *what)
{
	int bot = evo_lua_check_bot(L, 1);
	evo_lua_check_keys(L, 2, what, actuator_keys[kind]);
	evo_actuator_def d = evo_default_actuator_def(kind);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: an actuator needs a name", what);
	d.x = evo_lua_opt_num(L, 2, "x", d.x, what);
	d.y = evo_lua_opt_num(L, 2, "y", d.y, what);
	d.angle = evo_lua_opt_num(L, 2, "angle", d.angle / EVO_LUA_DEG, what) *
		  EVO_LUA_DEG;
	d.max_force = evo_lua_opt_num(L, 2, "max_force", d.max_force, what);
	d.reach = evo_lua_opt_num(L, 2, "reach", d.reach, what);
	/* a drive's turn rate is given in degrees, as every angle in Lua */
	lua_getfield(L, 2, "turn");
	d.turn = lua_toboolean(L, -1);
	lua_pop(L, 1);
	double unit = d.turn ? EVO_LUA_DEG : 1;
	d.max_speed =
	    evo_lua_opt_num(L, 2, "max_speed", d.max_speed / unit, what) * unit;
	d.accel = evo_lua_opt_num(L, 2, "accel", d.accel / unit, what) * unit;
	lua_pushinteger(
	    L, evo_lua_scene_result(
		   L, evo_scene_add_actuator(evo_lua_ctx(L)->sc, bot, &d)) +
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

static int speed_wheel(lua_State *L)
{
	return add_actuator(L, EVO_ACTUATOR_SPEED_WHEEL, "bot:speed_wheel");
}

static int drive(lua_State *L)
{
	return add_actuator(L, EVO_ACTUATOR_DRIVE, "bot:drive");
}

static int broadcast(lua_State *L)
{
	return add_actuator(L, EVO_ACTUATOR_BROADCAST, "bot:broadcast");
}

/* bot:target(sensor name, element or "nearest_object"): what a tracker
 * looks at (EvoAgents' setTarget). */
static int bot_target(lua_State *L)
{
	int bot = evo_lua_check_bot(L, 1);
	const char *name = luaL_checkstring(L, 2);
	evo_scene *sc = evo_lua_ctx(L)->sc;
	int s = evo_lua_bot_sensor_index(L, bot, name, "bot:target");
	lua_settop(L, 3);
	lua_newtable(L);
	lua_pushvalue(L, 3);
	lua_setfield(L, -2, "target");
	int t = evo_lua_opt_target(L, 4, "target", "bot:target");
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
	int bot = evo_lua_check_bot(L, 1);
	evo_scene *sc = evo_lua_ctx(L)->sc;
	evo_pose p = evo_body_pose(sc->world, sc->bot[bot].body);
	lua_pushnumber(L, p.x);
	lua_pushnumber(L, p.y);
	lua_pushnumber(L, p.angle / EVO_LUA_DEG);
	return 3;
}

static int bot_place(lua_State *L)
{
	int bot = evo_lua_check_bot(L, 1);
	double x = luaL_checknumber(L, 2), y = luaL_checknumber(L, 3);
	double a = luaL_optnumber(L, 4, 0) * EVO_LUA_DEG;
	if (!isfinite(x) || !isfinite(y) || !isfinite(a))
		luaL_error(L, "bot:place: a value is not a number");
	evo_scene_place_bot(evo_lua_ctx(L)->sc, bot, x, y, a);
	return 0;
}

static int bot_value(lua_State *L)
{
	int bot = evo_lua_check_bot(L, 1);
	int s = evo_lua_bot_sensor_index(L, bot, luaL_checkstring(L, 2),
					 "bot:value");
	evo_scene *sc = evo_lua_ctx(L)->sc;
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
	int bot = evo_lua_check_bot(L, 1);
	const evo_bot *b = &evo_lua_ctx(L)->sc->bot[bot];
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
	int bot = evo_lua_check_bot(L, 1);
	const evo_bot *b = &evo_lua_ctx(L)->sc->bot[bot];
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
	lua_pushinteger(L, b->gathered);
	lua_setfield(L, -2, "gathered");
	lua_pushnumber(L, b->reward);
	lua_setfield(L, -2, "reward");
	lua_pushboolean(L, holding);
	lua_setfield(L, -2, "holding");
	return 1;
}

/* The kinds as bot:sensors names them, the names of the bot's methods
 * that add them. */
static const char *const sensor_kind_names[EVO_SENSOR_KIND_COUNT] = {
    [EVO_SENSOR_PROXIMITY] = "proximity",
    [EVO_SENSOR_DISTANCE] = "distance",
    [EVO_SENSOR_ZONE] = "zone",
    [EVO_SENSOR_BEARING] = "bearing",
    [EVO_SENSOR_PRESENCE] = "presence",
    [EVO_SENSOR_OBJECT] = "object_detector",
    [EVO_SENSOR_MOVEMENT] = "movement",
    [EVO_SENSOR_RANDOM] = "random",
    [EVO_SENSOR_CONSTANT] = "constant",
    [EVO_SENSOR_HOLDING] = "holding",
    [EVO_SENSOR_RADAR] = "radar",
    [EVO_SENSOR_BUMPER] = "bumper",
    [EVO_SENSOR_LIGHT] = "light",
    [EVO_SENSOR_GROUND] = "ground",
    [EVO_SENSOR_RAB] = "rab",
    [EVO_SENSOR_CAMERA] = "camera",
};

/* bot:sensors(kind[, "untargeted"]): the names of the bot's sensors of a
 * kind, in the order the bot model added them; with "untargeted", only
 * those that look at nothing yet (for bot:target). Environments use it to
 * work with any bot model instead of naming one model's sensors. */
static int bot_sensors(lua_State *L)
{
	int bot = evo_lua_check_bot(L, 1);
	const char *kind = luaL_checkstring(L, 2);
	const char *filter = luaL_optstring(L, 3, NULL);
	if (filter && strcmp(filter, "untargeted") != 0)
		luaL_error(L, "bot:sensors: the filter is \"untargeted\", found "
			      "\"%s\"",
			   filter);
	int k = -1;
	for (int i = 0; i < EVO_SENSOR_KIND_COUNT; i++)
		if (strcmp(kind, sensor_kind_names[i]) == 0)
			k = i;
	if (k < 0) {
		luaL_Buffer b;
		luaL_buffinit(L, &b);
		for (int i = 0; i < EVO_SENSOR_KIND_COUNT; i++) {
			luaL_addstring(&b, i ? ", " : "");
			luaL_addstring(&b, sensor_kind_names[i]);
		}
		luaL_pushresult(&b);
		luaL_error(L, "bot:sensors: unknown kind '%s' (known: %s)", kind,
			   lua_tostring(L, -1));
	}
	const evo_bot *b = &evo_lua_ctx(L)->sc->bot[bot];
	lua_newtable(L);
	lua_Integer n = 0;
	for (int i = 0; i < b->n_sensors; i++) {
		const evo_sensor *se = &b->sensor[i];
		if ((int)se->def.kind != k ||
		    (filter && se->def.target != EVO_TARGET_NONE))
			continue;
		lua_pushstring(L, se->name);
		lua_seti(L, -2, ++n);
	}
	return 1;
}

/* bot:team(): its team's name, or nil. */
static int bot_team(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int t = l->sc->bot[evo_lua_check_bot(L, 1)].team;
	if (t >= 0 && t < l->n_teams)
		lua_pushstring(L, l->team[t].name);
	else
		lua_pushnil(L);
	return 1;
}

static int bot_name(lua_State *L)
{
	lua_pushstring(L,
		       evo_lua_ctx(L)->sc->bot[evo_lua_check_bot(L, 1)].name);
	return 1;
}

const luaL_Reg evo_lua_bot_methods[] = {
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
    {"radar", sensor_radar},
    {"bumper", sensor_bumper},
    {"light", sensor_light},
    {"ground", sensor_ground},
    {"rab", sensor_rab},
    {"camera", sensor_camera},
    {"wheel", wheel},
    {"claw", claw},
    {"speed_wheel", speed_wheel},
    {"drive", drive},
    {"broadcast", broadcast},
    {"target", bot_target},
    {"pose", bot_pose},
    {"place", bot_place},
    {"value", bot_value},
    {"command", bot_command},
    {"counts", bot_counts},
    {"sensors", bot_sensors},
    {"name", bot_name},
    {"team", bot_team},
    {NULL, NULL},
};
