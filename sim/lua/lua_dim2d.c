/* The 2D scene as the one binding reaches it (lua_internal.h's
 * evo_lua_dim): what scene:NAME, bot:NAME and the bot's and element's
 * methods do in a Box2D scene (world2d/scene.h), read from the options
 * each kind's row of sim/scene/kinds.c lets through. The methods
 * themselves are lua_scene.c's, lua_bot.c's and lua_element.c's, the
 * same in either world. */
#include <string.h>

#include "lua/lua_internal.h"
#include "world2d/sensors.h"

static evo_scene *scene(lua_State *L)
{
	return evo_lua_ctx(L)->sc;
}

/* ---- scene pieces ------------------------------------------------------ */

static int add_element(lua_State *L, int kind, const char *what)
{
	evo_element_def d =
	    evo_default_element_def((evo_piece_kind)kind, EVO_DIM_2D);
	d.name = evo_lua_opt_str(L, 2, "name", NULL, what);
	/* x, y and angle start at 0 (evo_default_element_def) */
	EVO_LUA_NUMS(L, 2, what, {"x", &d.x, 0}, {"y", &d.y, 0},
		     {"angle", &d.angle, EVO_LUA_DEG},
		     {kind == EVO_PIECE_ZONE ? "size" : "radius", &d.size, 0},
		     {"half_width", &d.half_w, 0},
		     {"half_height", &d.half_h, 0}, {"density", &d.density, 0},
		     {"friction", &d.friction, 0},
		     {"restitution", &d.restitution, 0},
		     {"linear_damping", &d.linear_damping, 0},
		     {"angular_damping", &d.angular_damping, 0});
	return evo_lua_scene_result(L, evo_scene_add_element(scene(L), &d));
}

/* scene:wall{x1, y1, x2, y2}: a wall of no thickness (docs/lua.md). */
static void add_wall(lua_State *L, const char *what)
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
}

static void add_grid(lua_State *L, const char *what)
{
	evo_grid_def g = evo_default_grid_def();
	g.enabled = 1;
	EVO_LUA_NUMS(L, 2, what, {"x0", &g.x0, 0}, {"y0", &g.y0, 0},
		     {"x1", &g.x1, 0}, {"y1", &g.y1, 0},
		     {"spacing", &g.spacing, 0}, {"jitter", &g.jitter, 0},
		     {"min_size", &g.min_size, 0},
		     {"size_variability", &g.size_variability, 0},
		     {"clearance", &g.clearance, 0});
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
}

/* The pieces of kinds.c's rows that are no elements, in 2D. */
static void add_part(lua_State *L, int kind, const char *what)
{
	if (kind == EVO_PIECE_WALL)
		add_wall(L, what);
	else
		add_grid(L, what);
}

/* ---- bots ---------------------------------------------------------------- */

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
	EVO_LUA_NUMS(
	    L, b, bw, {"radius", &sh->radius, 0},
	    {"half_width", &sh->half[0], 0}, {"half_height", &sh->half[1], 0},
	    {"density", &body->density, 0}, {"friction", &sh->friction, 0},
	    {"restitution", &sh->restitution, 0},
	    {"linear_damping", &body->linear_damping, 0},
	    {"angular_damping", &body->angular_damping, 0});
	lua_getfield(L, b, "sleep");
	body->allow_sleep = lua_toboolean(L, -1);
	lua_pop(L, 1);
	/* "undo": a kinematic body whose steps into a wall are undone
	 * (Lehman's maze simulator; docs/world.md, "The mazes") */
	const char *collision =
	    evo_lua_opt_str(L, b, "collision", "physics", bw);
	if (strcmp(collision, "physics") == 0)
		body->kinematic = 0;
	else if (strcmp(collision, "undo") == 0)
		body->kinematic = 1;
	else
		luaL_error(
		    L, "%s: collision is \"physics\" or \"undo\", not \"%s\"",
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
	d.yaw = evo_lua_opt_num(L, 2, "angle", 0, what) * EVO_LUA_DEG;
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

EVO_LUA_DIM_COMMON(sc, evo_scene, evo_bot_find_actuator)

/* `sees`: what a proximity sensor's rays hit, into d's mask and its
 * teammates and opponents flags (docs/lua.md, docs/teams.md). */
static void parse_sees(lua_State *L, int idx, const char *what,
		       evo_sensor_def *d)
{
	static const char *const words[] = {"obstacles", "bots", "objects",
					    "teammates", "opponents"};
	static const uint16_t bits[] = {EVO_CAT_OBSTACLE, EVO_CAT_BOT,
					EVO_CAT_OBJECT};
	int given;
	unsigned w = evo_lua_opt_words(L, idx, "sees", words, 5, what, &given);
	if (!given)
		return;
	d->mask = 0;
	for (int k = 0; k < 3; k++)
		if (w & 1u << k)
			d->mask |= bits[k];
	d->sees_teammates = (w & 8u) != 0;
	d->sees_opponents = (w & 16u) != 0;
}

/* A sensor's or actuator's x, y and angle on its bot (each defaulting to
 * what it holds). */
static void read_place(lua_State *L, double *x, double *y, double *angle,
		       const char *what)
{
	*x = evo_lua_opt_num(L, 2, "x", *x, what);
	*y = evo_lua_opt_num(L, 2, "y", *y, what);
	*angle = evo_lua_opt_num(L, 2, "angle", *angle / EVO_LUA_DEG, what) *
		 EVO_LUA_DEG;
}

static int add_sensor(lua_State *L, int bot, int kind, const char *what)
{
	evo_sensor_def d = evo_default_sensor_def((evo_sense_kind)kind);
	d.name = evo_lua_opt_name(L, what, "sensor");
	read_place(L, &d.x, &d.y, &d.angle, what);
	EVO_LUA_NUMS(L, 2, what, {"range", &d.range, 0},
		     {"arc", &d.arc, EVO_LUA_DEG}, {"deadzone", &d.deadzone, 0},
		     {"scale", &d.scale, 0}, {"reach", &d.reach, 0},
		     {"value", &d.value, 0});
	double rays = evo_lua_opt_num(L, 2, "rays", d.rays, what);
	if (rays != floor(rays) || rays < 1 || rays > EVO_PROX_MAX_RAYS)
		luaL_error(L, "%s: rays must be a whole number from 1 to %d",
			   what, EVO_PROX_MAX_RAYS);
	d.rays = (int)rays;
	parse_sees(L, 2, what, &d);
	d.target = evo_lua_opt_target(L, 2, "target", what);
	if (kind == EVO_SENSE_LIGHT || kind == EVO_SENSE_RAB ||
	    kind == EVO_SENSE_CAMERA)
		evo_lua_swarm_sensor(L, 2, what, kind == EVO_SENSE_CAMERA,
				     &d.swarm);
	return evo_lua_scene_result(L, evo_scene_add_sensor(scene(L), bot, &d));
}

static int add_actuator(lua_State *L, int bot, int kind, const char *what)
{
	/* kinds.c's row let only a 2D kind through */
	evo_actuator_def d = evo_default_actuator_def((evo_act_kind)kind);
	/* a drive's turn rate is given in degrees, as every angle in Lua */
	lua_getfield(L, 2, "turn");
	d.turn = lua_toboolean(L, -1);
	lua_pop(L, 1);
	double unit = d.turn ? EVO_LUA_DEG : 1;
	d.name = evo_lua_opt_name(L, what, "actuator");
	read_place(L, &d.x, &d.y, &d.angle, what);
	EVO_LUA_NUMS(L, 2, what, {"max_force", &d.max_force, 0},
		     {"reach", &d.reach, 0}, {"max_speed", &d.max_speed, unit},
		     {"accel", &d.accel, unit});
	return evo_lua_scene_result(L,
				    evo_scene_add_actuator(scene(L), bot, &d));
}

/* ---- reading and moving -------------------------------------------------- */

/* A zone sensor looks at a zone (EvoAgents' setTarget). */
static void set_target(lua_State *L, int bot, int s, int t)
{
	evo_scene *sc = scene(L);
	evo_sensor *sn = &sc->bot[bot].sensor[s];
	if (sn->def.kind == EVO_SENSE_ZONE && t >= 0 &&
	    sc->element[t].kind != EVO_PIECE_ZONE)
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

/* What bot:place{...} leaves out: where the bot is. */
static void start(const evo_lua *l, int bot, double p[3], double *yaw)
{
	pose(l, bot, p, yaw);
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
	evo_piece_kind k = l->sc->element[e].kind;
	return k == EVO_PIECE_CYLINDER || k == EVO_PIECE_BOX
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
	evo_scene_set_active(l->sc, i, on);
}

const evo_lua_dim evo_lua_dim2d = {
    .dim = EVO_DIM_2D,
    .words = "2D",
    .coords = 2,
    .named_targets = 1,
    .min_ticks = 0,
    .bot_keys =
	(const char *const[]){"name", "x", "y", "angle", "model", "team", NULL},
    .place_keys = NULL,
    EVO_LUA_DIM_FUNCTIONS,
    .set_element_active = set_element_active,
};
