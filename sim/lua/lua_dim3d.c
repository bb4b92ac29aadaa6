/* The 3D scene as the one binding reaches it (lua_internal.h's
 * evo_lua_dim): what scene:NAME, bot:NAME and the bot's and element's
 * methods do in an ODE scene (world3d/scene3d.h, docs/world3d.md), read
 * from the options each kind's row of sim/scene/kinds.c lets through.
 * The methods themselves are lua_scene.c's, lua_bot.c's and
 * lua_element.c's, the same in either world. */
#include <string.h>

#include "lua/lua_internal.h"

static evo_scene3d *scene3d(lua_State *L)
{
	return evo_lua_ctx(L)->sc3;
}

static void view(evo_lua *l, evo_lua_view *v)
{
	evo_scene3d *sc = l->sc3;
	*v = (evo_lua_view){&sc->tick,	     &sc->rng,	      &sc->n_bots,
			    &sc->n_elements, &sc->n_rewards,  &sc->n_metrics,
			    &sc->reward,     sc->metric,      &sc->swarm,
			    &sc->err,	     &sc->episode_reward, &sc->winner,
			    &sc->grid_seed};
}

static double num(lua_State *L, int idx, const char *key, double dflt,
		  const char *what)
{
	return evo_lua_opt_num(L, idx, key, dflt, what);
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

/* ---- scene pieces ------------------------------------------------------ */

static void read_element(lua_State *L, evo_element3d_def *d, const char *what)
{
	d->name = evo_lua_opt_str(L, 2, "name", NULL, what);
	evo_lua_opt_pos(L, 2, d->pos, what);
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

static int add_element(lua_State *L, evo_element3d_kind kind, const char *what)
{
	evo_element3d_def d = evo_default_element3d_def(kind);
	read_element(L, &d, what);
	if (kind == EVO3D_ELEM_OBJECT) {
		lua_getfield(L, 2, "radius");
		d.sphere = !lua_isnil(L, -1);
		lua_pop(L, 1);
	}
	return evo_lua_scene_result(L, evo_scene3d_add_element(scene3d(L), &d));
}

/* scene:obstacle{shape = "box" | "cylinder" | "sphere", ...}: a static
 * obstacle of this episode only, from an environment's reset. */
static int add_obstacle(lua_State *L, const char *what)
{
	if (!evo_lua_ctx(L)->in_reset)
		luaL_error(L,
			   "%s: an episode's obstacles are added in the "
			   "environment's reset (scene:box and the others "
			   "add those of every episode in init)",
			   what);
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
	evo_lua_scene_result(
	    L, evo_scene3d_add_episode_obstacle(scene3d(L), &o));
	return -1;
}

/* scene:physics{...}: the world's settings, before the first bot. */
static int set_physics(lua_State *L, const char *what)
{
	evo_scene3d *sc = scene3d(L);
	if (sc->n_bots > 0 || sc->n_elements > 0 || evo_lua_ctx(L)->ready)
		luaL_error(L,
			   "%s: set the physics first in init, before any "
			   "bot or element",
			   what);
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
	return -1;
}

static int add_piece(lua_State *L, int kind, const char *what)
{
	switch (kind) {
	case EVO_PIECE_CYLINDER:
		return add_element(L, EVO3D_ELEM_CYLINDER, what);
	case EVO_PIECE_BOX:
		return add_element(L, EVO3D_ELEM_BOX, what);
	case EVO_PIECE_ZONE:
		return add_element(L, EVO3D_ELEM_ZONE, what);
	case EVO_PIECE_OBJECT:
		return add_element(L, EVO3D_ELEM_OBJECT, what);
	case EVO_PIECE_SPHERE:
		return add_element(L, EVO3D_ELEM_SPHERE, what);
	case EVO_PIECE_TARGET:
		return add_element(L, EVO3D_ELEM_TARGET, what);
	case EVO_PIECE_OBSTACLE:
		return add_obstacle(L, what);
	default: /* EVO_PIECE_PHYSICS: kinds.c's rows let no other through */
		return set_physics(L, what);
	}
}

/* ---- bots ----------------------------------------------------------------- */

/* The model's hull table (at 1) into the evo_bot3d_def at 2. Called
 * through lua_pcall: scene:bot puts the model's file before its errors. */
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
	evo_lua_options(L, 1, what, keys);
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
		d->caster_pos[0] = num(L, c, "x", d->caster_pos[0], "hull.caster");
		d->caster_pos[1] = num(L, c, "y", d->caster_pos[1], "hull.caster");
		d->caster_pos[2] = num(L, c, "z", d->caster_pos[2], "hull.caster");
		d->caster_radius = num(L, c, "radius", 0.04, "hull.caster");
	}
	lua_pop(L, 1);
	return 0;
}

/* A bot of the model's hull; z defaults to the hull's. */
static int add_bot(lua_State *L, int team, const char *name, const char *what)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_bot3d_def d = evo_default_bot3d_def();
	d.team = team;
	d.name = name;
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
	evo_lua_opt_pos(L, 2, d.pos, what);
	d.yaw = num(L, 2, "yaw", 0, what) * EVO_LUA_DEG;
	return evo_lua_scene_result(L, evo_scene3d_add_bot(l->sc3, &d));
}

/* ---- sensors and actuators ---------------------------------------------- */

/* Each 3D sensor kind's row of sim/scene/kinds.c (azimuth: the bearing
 * sensor's). */
static const evo_sense_kind sense_of[EVO3D_SENSOR_KIND_COUNT] = {
    [EVO3D_SENSOR_PROXIMITY] = EVO_SENSE_PROXIMITY,
    [EVO3D_SENSOR_DISTANCE] = EVO_SENSE_DISTANCE,
    [EVO3D_SENSOR_AZIMUTH] = EVO_SENSE_BEARING,
    [EVO3D_SENSOR_ELEVATION] = EVO_SENSE_ELEVATION,
    [EVO3D_SENSOR_ZONE] = EVO_SENSE_ZONE,
    [EVO3D_SENSOR_RANDOM] = EVO_SENSE_RANDOM,
    [EVO3D_SENSOR_CONSTANT] = EVO_SENSE_CONSTANT,
    [EVO3D_SENSOR_LIGHT] = EVO_SENSE_LIGHT,
    [EVO3D_SENSOR_GROUND] = EVO_SENSE_GROUND,
    [EVO3D_SENSOR_RAB] = EVO_SENSE_RAB,
    [EVO3D_SENSOR_CAMERA] = EVO_SENSE_CAMERA,
};

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

static void read_proximity(lua_State *L, evo_sensor3d_def *d, const char *what)
{
	d->yaw = num(L, 2, "yaw", 0, what) * EVO_LUA_DEG;
	d->pitch = num(L, 2, "pitch", 0, what) * EVO_LUA_DEG;
	d->range = num(L, 2, "range", d->range, what);
	d->arc = num(L, 2, "arc", 0, what) * EVO_LUA_DEG;
	double rays = num(L, 2, "rays", d->rays, what);
	if (rays != floor(rays) || rays < 1 || rays > EVO3D_PROX_MAX_RAYS)
		luaL_error(L, "%s: rays must be a whole number, 1 to %d", what,
			   EVO3D_PROX_MAX_RAYS);
	d->rays = (int)rays;
	d->mask = parse_sees(L, 2, d->mask, what);
}

/* The tutorial's TargetSensor:1 and TargetSensor:2. */
static evo_sensor3d_kind target_sensor_axis(lua_State *L, const char *what)
{
	double axis = num(L, 2, "axis", 1, what);
	if (axis != 1 && axis != 2)
		luaL_error(L,
			   "%s: axis is 1 (azimuth) or 2 (elevation), as in "
			   "the tutorial's TargetSensor:1 and TargetSensor:2",
			   what);
	return axis == 1 ? EVO3D_SENSOR_AZIMUTH : EVO3D_SENSOR_ELEVATION;
}

static int add_sensor(lua_State *L, int bot, int kind, const char *what)
{
	int k = 0;
	while (k < EVO3D_SENSOR_KIND_COUNT - 1 &&
	       sense_of[k] != (evo_sense_kind)kind)
		k++;
	if (kind == EVO_SENSE_TARGET_SENSOR)
		k = target_sensor_axis(L, what);
	evo_sensor3d_def d = evo_default_sensor3d_def((evo_sensor3d_kind)k);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: a sensor needs a name", what);
	evo_lua_opt_pos(L, 2, d.pos, what);
	switch (d.kind) {
	case EVO3D_SENSOR_PROXIMITY:
		read_proximity(L, &d, what);
		break;
	case EVO3D_SENSOR_DISTANCE:
		d.scale = num(L, 2, "scale", d.scale, what);
		d.target = evo_lua_opt_target(L, 2, "target", what);
		break;
	case EVO3D_SENSOR_AZIMUTH:
	case EVO3D_SENSOR_ELEVATION:
	case EVO3D_SENSOR_ZONE:
		d.target = evo_lua_opt_target(L, 2, "target", what);
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
		evo_lua_swarm_sensor(L, 2, what, d.kind == EVO3D_SENSOR_CAMERA,
				     &d.swarm);
		break;
	default:
		break;
	}
	return evo_lua_scene_result(
	    L, evo_scene3d_add_sensor(scene3d(L), bot, &d));
}

static void read_wheel(lua_State *L, evo_actuator3d_def *d, const char *what)
{
	d->radius = num(L, 2, "radius", d->radius, what);
	d->half_width = num(L, 2, "width", 2 * d->half_width, what) / 2;
	d->mass = num(L, 2, "mass", d->mass, what);
	d->friction = num(L, 2, "friction", d->friction, what);
	const char *mode = evo_lua_opt_str(L, 2, "mode", "velocity", what);
	if (strcmp(mode, "velocity") == 0)
		d->torque_mode = 0;
	else if (strcmp(mode, "torque") == 0)
		d->torque_mode = 1;
	else
		luaL_error(L,
			   "%s: mode is \"velocity\" or \"torque\", found "
			   "\"%s\"",
			   what, mode);
	d->max_rate = num(L, 2, "max_rate", d->max_rate, what);
	d->max_torque = num(L, 2, "max_torque", d->max_torque, what);
}

static int add_actuator(lua_State *L, int bot, int kind, const char *what)
{
	evo_actuator3d_kind k = kind == EVO_ACT_WHEEL ? EVO3D_ACTUATOR_WHEEL
				: kind == EVO_ACT_PROPELLER
				    ? EVO3D_ACTUATOR_PROPELLER
				    : EVO3D_ACTUATOR_BROADCAST;
	evo_actuator3d_def d = evo_default_actuator3d_def(k);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	if (!d.name)
		luaL_error(L, "%s: an actuator needs a name", what);
	evo_lua_opt_pos(L, 2, d.pos, what);
	if (k == EVO3D_ACTUATOR_WHEEL)
		read_wheel(L, &d, what);
	if (k == EVO3D_ACTUATOR_PROPELLER) {
		opt_vec(L, 2, "axis", d.axis, what);
		d.max_thrust = num(L, 2, "max_thrust", d.max_thrust, what);
	}
	return evo_lua_scene_result(
	    L, evo_scene3d_add_actuator(scene3d(L), bot, &d));
}

static int add_reward(evo_lua *l, const evo_reward_def *d)
{
	return evo_scene3d_add_reward(l->sc3, d);
}

static int add_control(evo_lua *l, const evo_control_def *d)
{
	return evo_scene3d_add_control(l->sc3, d);
}

/* ---- names and lookups ----------------------------------------------------- */

static int find_bot(const evo_lua *l, const char *name)
{
	return evo_scene3d_find_bot(l->sc3, name);
}

static int find_element(const evo_lua *l, const char *name)
{
	return evo_scene3d_find_element(l->sc3, name);
}

static const char *bot_name(const evo_lua *l, int bot)
{
	return l->sc3->bot[bot].name;
}

static int bot_team(const evo_lua *l, int bot)
{
	return l->sc3->bot[bot].def.team;
}

static const char *element_name(const evo_lua *l, int e)
{
	return l->sc3->element[e].name;
}

static int n_sensors(const evo_lua *l, int bot)
{
	return l->sc3->bot[bot].n_sensors;
}

static const char *sensor_name(const evo_lua *l, int bot, int s)
{
	return l->sc3->bot[bot].sensor[s].name;
}

static int sensor_kind(const evo_lua *l, int bot, int s)
{
	return sense_of[l->sc3->bot[bot].sensor[s].def.kind];
}

static int sensor_target(const evo_lua *l, int bot, int s)
{
	return l->sc3->bot[bot].sensor[s].def.target;
}

static int find_actuator(const evo_lua *l, int bot, const char *name)
{
	return evo_bot3d_find_actuator(&l->sc3->bot[bot], name);
}

static double command(const evo_lua *l, int bot, int a)
{
	return l->sc3->bot[bot].actuator[a].command;
}

/* ---- reading and moving --------------------------------------------------- */

static void set_target(lua_State *L, int bot, int s, int t)
{
	scene3d(L)->bot[bot].sensor[s].def.target = t;
}

static double sample(evo_lua *l, int bot, int s)
{
	return evo_sensor3d_sample(l->sc3, bot, s);
}

static void pose(const evo_lua *l, int bot, double p[3], double *yaw)
{
	const evo_bot3d *b = &l->sc3->bot[bot];
	memcpy(p, b->pos, 3 * sizeof *p);
	*yaw = atan2(b->R[3], b->R[0]);
}

static void start(const evo_lua *l, int bot, double p[3], double *yaw)
{
	const evo_bot3d *b = &l->sc3->bot[bot];
	memcpy(p, b->start, 3 * sizeof *p);
	*yaw = b->start_yaw;
}

static int place_bot(evo_lua *l, int bot, const double p[3], double yaw)
{
	return evo_scene3d_place_bot(l->sc3, bot, p, yaw);
}

static void counts(const evo_lua *l, int bot, evo_lua_counts *c)
{
	const evo_bot3d *b = &l->sc3->bot[bot];
	*c = (evo_lua_counts){b->touching, b->collisions, 0, 0, 0, b->reward};
}

static void element_pos(const evo_lua *l, int e, double p[3])
{
	memcpy(p, l->sc3->element[e].pos, 3 * sizeof *p);
}

static const char *element_fixed(const evo_lua *l, int e)
{
	evo_element3d_kind k = l->sc3->element[e].def.kind;
	return k == EVO3D_ELEM_TARGET || k == EVO3D_ELEM_ZONE
		   ? NULL
		   : "only targets and zones move";
}

static void place_element(evo_lua *l, int e, const double p[3])
{
	evo_scene3d_place_element(l->sc3, e, p);
}

/* 3D elements are never switched off. */
static int element_active(const evo_lua *l, int e)
{
	(void)l;
	(void)e;
	return 1;
}

const evo_lua_dim evo_lua_dim3d = {
    .dim = EVO_DIM_3D,
    .words = "3D",
    .coords = 3,
    .named_targets = 0,
    .min_ticks = 1, /* the control keeps ticks - 1 (scene3d.h) */
    .view = view,
    .bot_keys = (const char *const[]){"name", "x", "y", "z", "yaw", "model",
				      "team", NULL},
    .add_bot = add_bot,
    .add_piece = add_piece,
    .add_sensor = add_sensor,
    .add_actuator = add_actuator,
    .add_reward = add_reward,
    .add_control = add_control,
    .find_bot = find_bot,
    .find_element = find_element,
    .bot_name = bot_name,
    .bot_team = bot_team,
    .element_name = element_name,
    .n_sensors = n_sensors,
    .sensor_name = sensor_name,
    .sensor_kind = sensor_kind,
    .sensor_target = sensor_target,
    .find_actuator = find_actuator,
    .command = command,
    .set_target = set_target,
    .sample = sample,
    .pose = pose,
    .start = start,
    .place_bot = place_bot,
    .counts = counts,
    .element_pos = element_pos,
    .element_fixed = element_fixed,
    .place_element = place_element,
    .element_active = element_active,
    .set_element_active = NULL,
};
