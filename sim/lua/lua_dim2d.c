/* The 2D scene as the one binding reaches it (lua_internal.h's
 * evo_lua_dim): what scene:NAME, bot:NAME and the bot's and element's
 * methods do in a Box2D scene (world2d/scene.h), read from the options
 * each kind's row of sim/scene/kinds.c lets through. The methods
 * themselves are lua_scene.c's, lua_bot.c's and lua_element.c's, the
 * same in either world. */
#include <string.h>

#include "lua/lua_internal.h"
#include "world2d/actuators.h"
#include "world2d/sensors.h"

static evo_scene *scene(lua_State *L)
{
	return evo_lua_ctx(L)->sc;
}

static void view(evo_lua *l, evo_lua_view *v)
{
	evo_scene *sc = l->sc;
	*v = (evo_lua_view){&sc->tick,	     &sc->rng,	      &sc->n_bots,
			    &sc->n_elements, &sc->n_rewards,  &sc->n_metrics,
			    &sc->reward,     sc->metric,      &sc->swarm,
			    &sc->err,	     &sc->episode_reward, &sc->winner,
			    &sc->grid_seed};
}

/* ---- scene pieces ------------------------------------------------------ */

static int add_element(lua_State *L, evo_element_kind kind, const char *what)
{
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
	return evo_lua_scene_result(L, evo_scene_add_element(scene(L), &d));
}

/* scene:wall{x1, y1, x2, y2}: a wall of no thickness (docs/lua.md). */
static int add_wall(lua_State *L, const char *what)
{
	static const char *const keys[] = {"x1", "y1", "x2", "y2"};
	double v[4];
	for (int i = 0; i < 4; i++) {
		lua_getfield(L, 2, keys[i]);
		if (!lua_isnumber(L, -1))
			luaL_error(L, "%s: %s must be a number", what, keys[i]);
		v[i] = lua_tonumber(L, -1);
		lua_pop(L, 1);
	}
	evo_lua_scene_result(
	    L, evo_scene_add_wall(scene(L), v[0], v[1], v[2], v[3]));
	return -1;
}

static int add_grid(lua_State *L, const char *what)
{
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
	evo_scene_set_grid(scene(L), &g);
	return -1;
}

static int add_piece(lua_State *L, int kind, const char *what)
{
	switch (kind) {
	case EVO_PIECE_CYLINDER:
		return add_element(L, EVO_ELEM_CYLINDER, what);
	case EVO_PIECE_BOX:
		return add_element(L, EVO_ELEM_BOX, what);
	case EVO_PIECE_ZONE:
		return add_element(L, EVO_ELEM_ZONE, what);
	case EVO_PIECE_OBJECT:
		return add_element(L, EVO_ELEM_OBJECT, what);
	case EVO_PIECE_WALL:
		return add_wall(L, what);
	default: /* EVO_PIECE_GRID: kinds.c's rows let no other through */
		return add_grid(L, what);
	}
}

/* ---- bots ----------------------------------------------------------------- */

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

static int add_bot(lua_State *L, int team, const char *name, const char *what)
{
	evo_lua *l = evo_lua_ctx(L);
	evo_bot_def d = evo_default_bot_def();
	d.team = team;
	d.name = name;
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
	return evo_lua_scene_result(L, evo_scene_add_bot(l->sc, &d));
}

/* ---- sensors and actuators ---------------------------------------------- */

/* Each 2D sensor kind's row of sim/scene/kinds.c. */
static const evo_sense_kind sense_of[EVO_SENSOR_KIND_COUNT] = {
    [EVO_SENSOR_PROXIMITY] = EVO_SENSE_PROXIMITY,
    [EVO_SENSOR_DISTANCE] = EVO_SENSE_DISTANCE,
    [EVO_SENSOR_ZONE] = EVO_SENSE_ZONE,
    [EVO_SENSOR_BEARING] = EVO_SENSE_BEARING,
    [EVO_SENSOR_PRESENCE] = EVO_SENSE_PRESENCE,
    [EVO_SENSOR_OBJECT] = EVO_SENSE_OBJECT_DETECTOR,
    [EVO_SENSOR_MOVEMENT] = EVO_SENSE_MOVEMENT,
    [EVO_SENSOR_RANDOM] = EVO_SENSE_RANDOM,
    [EVO_SENSOR_CONSTANT] = EVO_SENSE_CONSTANT,
    [EVO_SENSOR_HOLDING] = EVO_SENSE_HOLDING,
    [EVO_SENSOR_RADAR] = EVO_SENSE_RADAR,
    [EVO_SENSOR_BUMPER] = EVO_SENSE_BUMPER,
    [EVO_SENSOR_LIGHT] = EVO_SENSE_LIGHT,
    [EVO_SENSOR_GROUND] = EVO_SENSE_GROUND,
    [EVO_SENSOR_RAB] = EVO_SENSE_RAB,
    [EVO_SENSOR_CAMERA] = EVO_SENSE_CAMERA,
};

static const evo_act_kind act_of[EVO_ACTUATOR_KIND_COUNT] = {
    [EVO_ACTUATOR_WHEEL] = EVO_ACT_WHEEL,
    [EVO_ACTUATOR_CLAW] = EVO_ACT_CLAW,
    [EVO_ACTUATOR_SPEED_WHEEL] = EVO_ACT_SPEED_WHEEL,
    [EVO_ACTUATOR_DRIVE] = EVO_ACT_DRIVE,
    [EVO_ACTUATOR_BROADCAST] = EVO_ACT_BROADCAST,
};

/* `sees`: what a proximity sensor's rays hit, into d's mask and its
 * teammates and opponents flags (docs/lua.md, docs/teams.md). */
static void parse_sees(lua_State *L, int idx, const char *what,
		       evo_sensor_def *d)
{
	static const char *const words[] = {"obstacles", "bots", "objects",
					    "teammates", "opponents"};
	static const uint16_t bits[] = {EVO_CAT_OBSTACLE, EVO_CAT_BOT,
					EVO_CAT_OBJECT};
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
			if (w < 3)
				d->mask |= bits[w];
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

static int add_sensor(lua_State *L, int bot, int kind, const char *what)
{
	int k = 0;
	while (k < EVO_SENSOR_KIND_COUNT - 1 &&
	       sense_of[k] != (evo_sense_kind)kind)
		k++;
	evo_sensor_def d = evo_default_sensor_def((evo_sensor_kind)k);
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
	if (kind == EVO_SENSE_LIGHT || kind == EVO_SENSE_RAB ||
	    kind == EVO_SENSE_CAMERA)
		evo_lua_swarm_sensor(L, 2, what, kind == EVO_SENSE_CAMERA,
				     &d.swarm);
	return evo_lua_scene_result(L, evo_scene_add_sensor(scene(L), bot, &d));
}

static int add_actuator(lua_State *L, int bot, int kind, const char *what)
{
	int k = 0;
	while (k < EVO_ACTUATOR_KIND_COUNT - 1 &&
	       act_of[k] != (evo_act_kind)kind)
		k++;
	evo_actuator_def d = evo_default_actuator_def((evo_actuator_kind)k);
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
	return evo_lua_scene_result(L,
				    evo_scene_add_actuator(scene(L), bot, &d));
}

static int add_reward(evo_lua *l, const evo_reward_def *d)
{
	return evo_scene_add_reward(l->sc, d);
}

static int add_control(evo_lua *l, const evo_control_def *d)
{
	return evo_scene_add_control(l->sc, d);
}

/* ---- names and lookups ----------------------------------------------------- */

static int find_bot(const evo_lua *l, const char *name)
{
	return evo_scene_find_bot(l->sc, name);
}

static int find_element(const evo_lua *l, const char *name)
{
	return evo_scene_find_element(l->sc, name);
}

static const char *bot_name(const evo_lua *l, int bot)
{
	return l->sc->bot[bot].name;
}

static int bot_team(const evo_lua *l, int bot)
{
	return l->sc->bot[bot].team;
}

static const char *element_name(const evo_lua *l, int e)
{
	return l->sc->element[e].name;
}

static int n_sensors(const evo_lua *l, int bot)
{
	return l->sc->bot[bot].n_sensors;
}

static const char *sensor_name(const evo_lua *l, int bot, int s)
{
	return l->sc->bot[bot].sensor[s].name;
}

static int sensor_kind(const evo_lua *l, int bot, int s)
{
	return sense_of[l->sc->bot[bot].sensor[s].def.kind];
}

static int sensor_target(const evo_lua *l, int bot, int s)
{
	return l->sc->bot[bot].sensor[s].def.target;
}

static int find_actuator(const evo_lua *l, int bot, const char *name)
{
	return evo_bot_find_actuator(&l->sc->bot[bot], name);
}

static double command(const evo_lua *l, int bot, int a)
{
	return l->sc->bot[bot].actuator[a].command;
}

/* ---- reading and moving --------------------------------------------------- */

/* A zone sensor looks at a zone (EvoAgents' setTarget). */
static void set_target(lua_State *L, int bot, int s, int t)
{
	evo_scene *sc = scene(L);
	evo_sensor *sn = &sc->bot[bot].sensor[s];
	if (sn->def.kind == EVO_SENSOR_ZONE && t >= 0 &&
	    sc->element[t].kind != EVO_ELEM_ZONE)
		luaL_error(L, "bot:target: zone sensor '%s' needs a zone",
			   sn->name);
	sn->def.target = t;
}

static double sample(evo_lua *l, int bot, int s)
{
	evo_sensor *se = &l->sc->bot[bot].sensor[s];
	if (se->idle) {
		/* Not sampled so far: from now on it is, every tick. */
		se->idle = 0;
		evo_sensor_sample(l->sc, bot, s);
	}
	return se->value;
}

static void pose(const evo_lua *l, int bot, double p[3], double *yaw)
{
	evo_pose q = evo_body_pose(l->sc->world, l->sc->bot[bot].body);
	p[0] = q.x;
	p[1] = q.y;
	p[2] = 0;
	*yaw = q.angle;
}

static int place_bot(evo_lua *l, int bot, const double p[3], double yaw)
{
	evo_scene_place_bot(l->sc, bot, p[0], p[1], yaw);
	return 0;
}

static void counts(const evo_lua *l, int bot, evo_lua_counts *c)
{
	const evo_bot *b = &l->sc->bot[bot];
	int holding = 0;
	for (int i = 0; i < b->n_actuators; i++)
		holding |= b->actuator[i].held >= 0;
	*c = (evo_lua_counts){b->touching, b->collisions, b->delivered,
			      b->gathered, holding,	  b->reward};
}

static void element_pos(const evo_lua *l, int e, double p[3])
{
	p[0] = l->sc->element[e].x;
	p[1] = l->sc->element[e].y;
	p[2] = 0;
}

static const char *element_fixed(const evo_lua *l, int e)
{
	evo_element_kind k = l->sc->element[e].kind;
	return k == EVO_ELEM_CYLINDER || k == EVO_ELEM_BOX
		   ? "static elements do not move"
		   : NULL;
}

static void place_element(evo_lua *l, int e, const double p[3])
{
	evo_scene_place_element(l->sc, e, p[0], p[1]);
}

static int element_active(const evo_lua *l, int e)
{
	return l->sc->element[e].active;
}

static void set_element_active(evo_lua *l, int i, int on)
{
	evo_scene *sc = l->sc;
	evo_element *e = &sc->element[i];
	if (e->kind == EVO_ELEM_OBJECT) {
		if (!on && e->held_by >= 0)
			evo_bot_release(sc, e->held_by);
		evo_body_set_enabled(sc->world, e->body, on);
	}
	e->active = on;
}

const evo_lua_dim evo_lua_dim2d = {
    .dim = EVO_DIM_2D,
    .words = "2D",
    .coords = 2,
    .named_targets = 1,
    .min_ticks = 0,
    .view = view,
    .bot_keys = (const char *const[]){"name", "x", "y", "angle", "model",
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
    .start = pose,
    .place_bot = place_bot,
    .counts = counts,
    .element_pos = element_pos,
    .element_fixed = element_fixed,
    .place_element = place_element,
    .element_active = element_active,
    .set_element_active = set_element_active,
};
