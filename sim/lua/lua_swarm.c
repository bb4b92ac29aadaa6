/* The swarm sensors' options and the lights and floor patches, as the 2D
 * and 3D scene scripts give them (docs/lua.md, docs/world3d.md): one
 * reading of each for both worlds, over sim/scene/swarm.h. */
#include <stdio.h>
#include <string.h>

#include "lua/lua_internal.h"

/* The words of `read`, in evo_rab_read's order: a range-and-bearing
 * sensor's first four, a camera's with "colour" for "value". */
static const char *const read_words[EVO_RAB_READ_COUNT] = {
    "range", "bearing", "value", "count", "colour"};

static evo_rab_read opt_read(lua_State *L, int idx, const char *what,
			     int camera)
{
	const char *s = evo_lua_opt_str(L, idx, "read", "range", what);
	const char *words[4] = {"range", "bearing", camera ? "colour" : "value",
				"count"};
	for (int i = 0; i < 4; i++)
		if (strcmp(s, words[i]) == 0)
			for (int k = 0; k < EVO_RAB_READ_COUNT; k++)
				if (strcmp(s, read_words[k]) == 0)
					return (evo_rab_read)k;
	const char *near = evo_lua_near(s, words, 4);
	luaL_error(L,
		   "%s: read is \"range\", \"bearing\", \"%s\" or "
		   "\"count\", found \"%s\"%s%s%s",
		   what, words[2], s, near ? " (did you mean " : "",
		   near ? near : "", near ? "?)" : "");
	return EVO_RAB_RANGE;
}

/* A colour's name at the top of the stack (from option `key`): its
 * number; an unknown one is an error listing the colours. */
static int check_colour(lua_State *L, const char *what, const char *key)
{
	const char *s = lua_tostring(L, -1);
	int c = lua_type(L, -1) == LUA_TSTRING ? evo_colour_by_name(s) : -1;
	if (c >= 0)
		return c;
	luaL_Buffer b;
	luaL_buffinit(L, &b);
	for (int k = 0; k < EVO_COLOUR_COUNT; k++) {
		luaL_addstring(&b, k ? ", " : "");
		luaL_addstring(&b, evo_colour_name(k));
	}
	luaL_pushresult(&b);
	const char *names[EVO_COLOUR_COUNT];
	for (int k = 0; k < EVO_COLOUR_COUNT; k++)
		names[k] = evo_colour_name(k);
	const char *near = s ? evo_lua_near(s, names, EVO_COLOUR_COUNT) : NULL;
	return luaL_error(L, "%s: %s: unknown colour '%s'%s%s%s (known: %s)",
			  what, key, s ? s : luaL_typename(L, -2),
			  near ? "; did you mean " : "", near ? near : "",
			  near ? "?" : "", lua_tostring(L, -1));
}

/* Option `colour` of the table at idx: its number, or dflt. */
static int opt_colour(lua_State *L, int idx, int dflt, const char *what)
{
	lua_getfield(L, idx, "colour");
	int c = lua_isnil(L, -1) ? dflt : check_colour(L, what, "colour");
	lua_pop(L, 1);
	return c;
}

/* A whole number option in [lo, hi]. */
static int opt_int(lua_State *L, int idx, const char *key, int dflt, int lo,
		   int hi, const char *what)
{
	double v = evo_lua_opt_num(L, idx, key, dflt, what);
	if (v != floor(v) || v < lo || v > hi) {
		char found[32]; /* Lua's own format has no %g */
		snprintf(found, sizeof found, "%g", v);
		luaL_error(L,
			   "%s: %s must be a whole number from %d to %d, "
			   "found %s",
			   what, key, lo, hi, found);
	}
	return (int)v;
}

void evo_lua_swarm_sensor(lua_State *L, int idx, const char *what, int camera,
			  evo_swarm_sensor *s)
{
	s->aperture = evo_lua_opt_num(L, idx, "aperture",
				      s->aperture / EVO_LUA_DEG, what) *
		      EVO_LUA_DEG;
	s->range = evo_lua_opt_num(L, idx, "range", s->range, what);
	s->slot =
	    opt_int(L, idx, "slot", s->slot, 1, EVO_SWARM_MAX_SLOTS, what);
	s->read = opt_read(L, idx, what, camera);
	if (camera)
		s->colour = opt_colour(L, idx, s->colour, what);
	s->index = opt_int(L, idx, "index", s->index + 1, 1,
			   EVO_SWARM_MAX_VALUES, what) -
		   1;
	lua_getfield(L, idx, "occluded");
	if (!lua_isnil(L, -1) && !lua_isboolean(L, -1))
		luaL_error(L, "%s: occluded must be true or false, found %s",
			   what, luaL_typename(L, -1));
	s->occluded = lua_toboolean(L, -1);
	lua_pop(L, 1);
	s->scale = evo_lua_opt_num(L, idx, "scale", s->scale, what);
	if (!(s->aperture >= 0) || !(s->range > 0) || !(s->scale > 0))
		luaL_error(L,
			   "%s: aperture must be 0 or more, range and scale "
			   "above 0",
			   what);
}

/* Lights and patches are made in init: made in reset, one more would
 * pile up every episode. */
static void in_init(lua_State *L, const char *what)
{
	if (evo_lua_ctx(L)->in_reset)
		luaL_error(L,
			   "%s: lights and patches are made in init (made in "
			   "reset, one more would pile up every episode)",
			   what);
}

void evo_lua_add_light(lua_State *L, int idx, int dims, evo_swarm *w,
		       evo_err *err)
{
	static const char *const keys2[] = {"x", "y", "intensity", "colour",
					    NULL};
	static const char *const keys3[] = {"x",	 "y",	   "z",
					    "intensity", "colour", NULL};
	const char *what = "scene:light";
	evo_lua_check_keys(L, idx, what, dims == 3 ? keys3 : keys2);
	in_init(L, what);
	evo_light l;
	memset(&l, 0, sizeof l);
	l.pos[0] = evo_lua_opt_num(L, idx, "x", 0, what);
	l.pos[1] = evo_lua_opt_num(L, idx, "y", 0, what);
	l.pos[2] = dims == 3 ? evo_lua_opt_num(L, idx, "z", 0, what) : 0;
	l.intensity = evo_lua_opt_num(L, idx, "intensity", 1, what);
	int colour = opt_colour(L, idx, -1, what);
	int i = evo_swarm_add_light(w, &l, err);
	if (i < 0 || (colour >= 0 && evo_swarm_set_colour(w, EVO_BLOB_LIGHT, i,
							  colour, err) < 0))
		luaL_error(L, "scene:%s", err->msg);
}

void evo_lua_add_patch(lua_State *L, int idx, int dims, evo_swarm *w,
		       evo_err *err)
{
	/* each world's own words for a box's half sides and turn */
	static const char *const keys2[] = {
	    "x",     "y",      "half_width", "half_height",
	    "angle", "radius", "grey",	     NULL};
	static const char *const keys3[] = {"x",   "y",	     "hx",   "hy",
					    "yaw", "radius", "grey", NULL};
	const char *what = "scene:patch";
	evo_lua_check_keys(L, idx, what, dims == 3 ? keys3 : keys2);
	in_init(L, what);
	evo_patch p;
	memset(&p, 0, sizeof p);
	p.x = evo_lua_opt_num(L, idx, "x", 0, what);
	p.y = evo_lua_opt_num(L, idx, "y", 0, what);
	const char *hx = dims == 3 ? "hx" : "half_width";
	const char *hy = dims == 3 ? "hy" : "half_height";
	lua_getfield(L, idx, "radius");
	p.circle = !lua_isnil(L, -1);
	lua_pop(L, 1);
	if (p.circle) {
		lua_getfield(L, idx, hx);
		lua_getfield(L, idx, hy);
		if (!lua_isnil(L, -1) || !lua_isnil(L, -2))
			luaL_error(L,
				   "%s: a patch is a circle (radius) or a "
				   "rectangle (%s, %s), not both",
				   what, hx, hy);
		lua_pop(L, 2);
	}
	p.radius = evo_lua_opt_num(L, idx, "radius", 0, what);
	p.hx = evo_lua_opt_num(L, idx, hx, 0.5, what);
	p.hy = evo_lua_opt_num(L, idx, hy, 0.5, what);
	p.yaw = evo_lua_opt_num(L, idx, dims == 3 ? "yaw" : "angle", 0, what) *
		EVO_LUA_DEG;
	p.grey = evo_lua_opt_num(L, idx, "grey", 0, what);
	if (evo_swarm_add_patch(w, &p, err) < 0)
		luaL_error(L, "scene:%s", err->msg);
}

void evo_lua_set_colour(lua_State *L, evo_blob_kind kind, int index,
			evo_swarm *w, evo_err *err)
{
	lua_settop(L, 3);
	int c = check_colour(L, "scene:colour", "its colour");
	if (evo_swarm_set_colour(w, kind, index, c, err) < 0)
		luaL_error(L, "scene:colour: %s", err->msg);
}
