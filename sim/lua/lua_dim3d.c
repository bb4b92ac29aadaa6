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

static void read_element(lua_State *L, evo_element_def *d, const char *what)
{
	d->name = evo_lua_opt_str(L, 2, "name", NULL, what);
	evo_lua_opt_pos(L, 2, d->pos, what);
	/* yaw starts at 0 (evo_default_element_def); height is twice
	 * half_length */
	EVO_LUA_NUMS(L, 2, what, {"yaw", &d->yaw, EVO_LUA_DEG},
		     {"hx", &d->half[0], 0}, {"hy", &d->half[1], 0},
		     {"hz", &d->half[2], 0}, {"radius", &d->radius, 0},
		     {"height", &d->half_length, 0.5}, {"mass", &d->mass, 0},
		     {"friction", &d->friction, 0});
	lua_getfield(L, 2, "ground");
	if (!lua_isnil(L, -1) && !lua_isboolean(L, -1))
		luaL_error(L, "%s: ground must be true or false, found %s",
			   what, luaL_typename(L, -1));
	d->ground = lua_toboolean(L, -1);
	lua_pop(L, 1);
}

static int add_element(lua_State *L, int kind, const char *what)
{
	evo_element_def d =
	    evo_default_element_def((evo_piece_kind)kind, EVO_DIM_3D);
	read_element(L, &d, what);
	if (kind == EVO_PIECE_OBJECT) {
		lua_getfield(L, 2, "radius");
		d.sphere = !lua_isnil(L, -1);
		lua_pop(L, 1);
	}
	return evo_lua_scene_result(L, evo_scene3d_add_element(scene3d(L), &d));
}

/* scene:obstacle{shape = "box" | "cylinder" | "sphere", ...}: a static
 * obstacle of this episode only, from an environment's reset. */
static void add_obstacle(lua_State *L, const char *what)
{
	if (!evo_lua_ctx(L)->in_reset)
		luaL_error(L,
			   "%s: an episode's obstacles are added in the "
			   "environment's reset (scene:box and the others "
			   "add those of every episode in init)",
			   what);
	static const char *const shapes[] = {"box", "cylinder", "sphere"};
	static const evo_piece_kind kinds[] = {
	    EVO_PIECE_BOX, EVO_PIECE_CYLINDER, EVO_PIECE_SPHERE};
	const char *shape = evo_lua_opt_str(L, 2, "shape", "box", what);
	int at = 0;
	while (at < 3 && strcmp(shape, shapes[at]) != 0)
		at++;
	if (at == 3)
		luaL_error(L,
			   "%s: shape is \"box\", \"cylinder\" or "
			   "\"sphere\", found \"%s\"",
			   what, shape);
	evo_piece_kind kind = kinds[at];
	evo_element_def d = evo_default_element_def(kind, EVO_DIM_3D);
	read_element(L, &d, what);
	evo_obstacle3d o;
	memset(&o, 0, sizeof o);
	o.type = kind == EVO_PIECE_BOX	       ? EVO_SHAPE3D_BOX
		 : kind == EVO_PIECE_CYLINDER ? EVO_SHAPE3D_CYLINDER
					       : EVO_SHAPE3D_SPHERE;
	memcpy(o.pos, d.pos, sizeof o.pos);
	o.yaw = d.yaw;
	memcpy(o.half, d.half, sizeof o.half);
	o.radius = d.radius;
	o.half_length = d.half_length;
	o.friction = d.friction;
	o.category = d.ground ? EVO_CAT3D_GROUND : EVO_CAT3D_OBSTACLE;
	evo_lua_scene_result(L,
			     evo_scene3d_add_episode_obstacle(scene3d(L), &o));
}

/* scene:physics{...}: the world's settings, before the first bot. */
static void set_physics(lua_State *L, const char *what)
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
	EVO_LUA_NUMS(L, 2, what, {"gravity", &d.world.gravity, 0},
		     {"erp", &d.world.erp, 0}, {"cfm", &d.world.cfm, 0},
		     {"max_speed", &d.world.max_speed, 0},
		     {"max_spin", &d.world.max_spin, 0},
		     {"ground_friction", &d.world.ground_friction, 0},
		     {"fault_penalty", &d.fault_penalty, 0});
	if (!(d.world.step > 0) || !(d.world.max_speed > 0) ||
	    !(d.world.max_spin > 0) || d.world.erp < 0 || d.world.erp > 1 ||
	    d.world.cfm < 0 || d.world.ground_friction < 0)
		luaL_error(L,
			   "%s: step, max_speed and max_spin must be > 0, "
			   "erp in [0, 1], cfm and ground_friction >= 0",
			   what);
	if (evo_scene3d_set_def(sc, &d))
		luaL_error(L, "%s: %s", what, sc->err.msg);
}

/* The pieces of kinds.c's rows that are no elements, in 3D. */
static void add_part(lua_State *L, int kind, const char *what)
{
	if (kind == EVO_PIECE_OBSTACLE)
		add_obstacle(L, what);
	else
		set_physics(L, what);
}

/* ---- bots ---------------------------------------------------------------- */

/* The model's hull table (at 1) into the evo_bot_def at 2. Called
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
	evo_bot_def *d = lua_touserdata(L, 2);
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
	/* buoyancy and drag start at 0 (evo_default_bot_def3d) */
	EVO_LUA_NUMS(L, 1, what, {"mass", &d->mass, 0},
		     {"friction", &d->friction, 0}, {"z", &d->pos[2], 0},
		     {"buoyancy", &d->buoyancy, 0},
		     {"drag_linear", &d->drag_linear, 0},
		     {"drag_quadratic", &d->drag_quadratic, 0},
		     {"drag_angular", &d->drag_angular, 0});
	opt_vec(L, 1, "cob", d->cob, what);
	if (lua_getfield(L, 1, "caster") != LUA_TNIL) {
		int c = lua_gettop(L);
		evo_lua_check_keys(L, c, "hull.caster", caster_keys);
		d->caster_radius = 0.04;
		EVO_LUA_NUMS(L, c, "hull.caster", {"x", &d->caster_pos[0], 0},
			     {"y", &d->caster_pos[1], 0},
			     {"z", &d->caster_pos[2], 0},
			     {"radius", &d->caster_radius, 0});
	}
	lua_pop(L, 1);
	return 0;
}

/* A bot of the model's hull; z defaults to the hull's. */
static int add_bot(lua_State *L, int team, const char *name, const char *what)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_bot_def d = evo_default_bot_def3d();
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
	d.team = team;
	d.name = name;
	return evo_lua_scene_result(L, evo_scene3d_add_bot(l->sc3, &d));
}

/* ---- sensors and actuators ---------------------------------------------- */

EVO_LUA_DIM_COMMON(sc3, evo_scene3d, evo_bot_find_actuator)

/* `sees`: a list of "ground", "obstacles", "bots", "objects". A 3D ray
 * tells no teammate from an opponent: "teammates" and "opponents" are 2D
 * only (docs/teams.md). */
static unsigned parse_sees(lua_State *L, int idx, unsigned dflt,
			   const char *what)
{
	/* EVO_CAT3D_* in this order */
	static const char *const words[] = {"ground", "bots", "obstacles",
					    "objects"};
	int given;
	unsigned mask =
	    evo_lua_opt_words(L, idx, "sees", words, 4, what, &given);
	return given ? mask : dflt;
}

static void read_proximity(lua_State *L, evo_sensor_def *d, const char *what)
{
	/* yaw, pitch and arc start at 0 (evo_default_sensor3d_def) */
	EVO_LUA_NUMS(L, 2, what, {"yaw", &d->yaw, EVO_LUA_DEG},
		     {"pitch", &d->pitch, EVO_LUA_DEG}, {"range", &d->range, 0},
		     {"arc", &d->arc, EVO_LUA_DEG});
	double rays = num(L, 2, "rays", d->rays, what);
	if (rays != floor(rays) || rays < 1 || rays > EVO_PROX_MAX_RAYS)
		luaL_error(L, "%s: rays must be a whole number, 1 to %d", what,
			   EVO_PROX_MAX_RAYS);
	d->rays = (int)rays;
	d->mask = parse_sees(L, 2, d->mask, what);
}

/* The tutorial's TargetSensor:1 and TargetSensor:2. */
static evo_sense_kind target_sensor_axis(lua_State *L, const char *what)
{
	double axis = num(L, 2, "axis", 1, what);
	if (axis != 1 && axis != 2)
		luaL_error(L,
			   "%s: axis is 1 (azimuth) or 2 (elevation), as in "
			   "the tutorial's TargetSensor:1 and TargetSensor:2",
			   what);
	return axis == 1 ? EVO_SENSE_BEARING : EVO_SENSE_ELEVATION;
}

static int add_sensor(lua_State *L, int bot, int kind, const char *what)
{
	evo_sense_kind k = kind == EVO_SENSE_TARGET_SENSOR
			       ? target_sensor_axis(L, what)
			       : (evo_sense_kind)kind;
	evo_sensor_def d = evo_default_sensor3d_def(k);
	d.name = evo_lua_opt_name(L, what, "sensor");
	evo_lua_opt_pos(L, 2, d.pos, what);
	switch (d.kind) {
	case EVO_SENSE_PROXIMITY:
		read_proximity(L, &d, what);
		break;
	case EVO_SENSE_DISTANCE:
		d.scale = num(L, 2, "scale", d.scale, what);
		d.target = evo_lua_opt_target(L, 2, "target", what);
		break;
	case EVO_SENSE_BEARING:
	case EVO_SENSE_ELEVATION:
	case EVO_SENSE_ZONE:
	case EVO_SENSE_PRESENCE:
		d.target = evo_lua_opt_target(L, 2, "target", what);
		break;
	case EVO_SENSE_MOVEMENT:
		d.scale = num(L, 2, "scale", d.scale, what);
		break;
	case EVO_SENSE_RADAR:
		d.target = evo_lua_opt_target(L, 2, "target", what);
		EVO_LUA_NUMS(L, 2, what, {"yaw", &d.yaw, EVO_LUA_DEG},
			     {"arc", &d.arc, EVO_LUA_DEG});
		break;
	case EVO_SENSE_CONSTANT:
		d.value = num(L, 2, "value", 0.5, what);
		break;
	case EVO_SENSE_LIGHT:
		d.yaw = num(L, 2, "yaw", 0, what) * EVO_LUA_DEG;
		evo_lua_swarm_sensor(L, 2, what, 0, &d.swarm);
		break;
	case EVO_SENSE_RAB:
	case EVO_SENSE_CAMERA:
		evo_lua_swarm_sensor(L, 2, what, d.kind == EVO_SENSE_CAMERA,
				     &d.swarm);
		break;
	default:
		break;
	}
	return evo_lua_scene_result(
	    L, evo_scene3d_add_sensor(scene3d(L), bot, &d));
}

static void read_wheel(lua_State *L, evo_actuator_def *d, const char *what)
{
	EVO_LUA_NUMS(L, 2, what, {"radius", &d->radius, 0},
		     {"width", &d->half_width, 0.5}, {"mass", &d->mass, 0},
		     {"friction", &d->friction, 0},
		     {"max_rate", &d->max_rate, 0},
		     {"max_torque", &d->max_torque, 0});
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
}

static int add_actuator(lua_State *L, int bot, int kind, const char *what)
{
	/* kinds.c's row let only a 3D kind through */
	evo_act_kind k = (evo_act_kind)kind;
	evo_actuator_def d = evo_default_actuator_def(k);
	d.name = evo_lua_opt_name(L, what, "actuator");
	evo_lua_opt_pos(L, 2, d.pos, what);
	if (k == EVO_ACT_WHEEL)
		read_wheel(L, &d, what);
	if (k == EVO_ACT_PROPELLER) {
		opt_vec(L, 2, "axis", d.axis, what);
		d.max_thrust = num(L, 2, "max_thrust", d.max_thrust, what);
	}
	return evo_lua_scene_result(
	    L, evo_scene3d_add_actuator(scene3d(L), bot, &d));
}

/* ---- reading and moving -------------------------------------------------- */

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
	const evo_bot *b = &l->sc3->bot[bot];
	memcpy(p, b->pos, 3 * sizeof *p);
	*yaw = atan2(b->R[3], b->R[0]);
}

static void start(const evo_lua *l, int bot, double p[3], double *yaw)
{
	const evo_bot *b = &l->sc3->bot[bot];
	memcpy(p, b->start, 3 * sizeof *p);
	*yaw = b->start_yaw;
}

static int place_bot(evo_lua *l, int bot, const double p[3], double yaw)
{
	return evo_scene3d_place_bot(l->sc3, bot, p, yaw);
}

static void counts(const evo_lua *l, int bot, evo_lua_counts *c)
{
	const evo_bot *b = &l->sc3->bot[bot];
	*c = (evo_lua_counts){b->touching, b->collisions, 0, 0, 0, b->reward};
}

static void element_pos(const evo_lua *l, int e, double p[3])
{
	memcpy(p, l->sc3->element[e].pos, 3 * sizeof *p);
}

static const char *element_fixed(const evo_lua *l, int e)
{
	evo_piece_kind k = l->sc3->element[e].def.kind;
	return k == EVO_PIECE_TARGET || k == EVO_PIECE_ZONE
		   ? NULL
		   : "only targets and zones move";
}

static void place_element(evo_lua *l, int e, const double p[3])
{
	evo_scene3d_place_element(l->sc3, e, p);
}

static int element_active(const evo_lua *l, int e)
{
	return l->sc3->element[e].active;
}

static void set_element_active(evo_lua *l, int e, int on)
{
	evo_scene3d_set_active(l->sc3, e, on);
}

const evo_lua_dim evo_lua_dim3d = {
    .dim = EVO_DIM_3D,
    .words = "3D",
    .coords = 3,
    .named_targets = 0,
    .min_ticks = 1, /* the control keeps ticks - 1 (scene3d.h) */
    .bot_keys = (const char *const[]){"name", "x", "y", "z", "yaw", "model",
				      "team", NULL},
    .place_keys = (const char *const[]){"x", "y", "z", "yaw", NULL},
    EVO_LUA_DIM_FUNCTIONS,
    .set_element_active = set_element_active,
};
