/* An element's methods in the scene scripts' `evo` module (docs/lua.md,
 * docs/world3d.md), one set for an element of either world: its name,
 * where it is, moving it, and switching it off where the world has
 * elements that switch off (the dimension's table, lua_dim2d.c and
 * lua_dim3d.c, says). */
#include "lua/lua_internal.h"

static int element_name(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	lua_pushstring(L, l->dim->element_name(l, evo_lua_check_element(L, 1)));
	return 1;
}

/* element:pos(): x, y[, z]. */
static int element_pos(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	double p[3];
	l->dim->element_pos(l, evo_lua_check_element(L, 1), p);
	for (int k = 0; k < l->dim->coords; k++)
		lua_pushnumber(L, p[k]);
	return l->dim->coords;
}

/* element:place(x, y[, z]) or element:place{x, y[, z]}: move it (this
 * episode); what a table leaves out stays where it is. */
static int element_place(lua_State *L)
{
	static const char *const keys[] = {"x", "y", "z", NULL};
	const char *what = "element:place";
	evo_lua *l = evo_lua_ctx(L);
	int e = evo_lua_check_element(L, 1);
	int n = l->dim->coords;
	double p[3];
	l->dim->element_pos(l, e, p);
	if (lua_istable(L, 2)) {
		evo_lua_check_keys(L, 2, what, keys);
		evo_lua_opt_pos(L, 2, p, what);
	} else {
		for (int k = 0; k < n; k++)
			p[k] = luaL_checknumber(L, 2 + k);
	}
	for (int k = 0; k < n; k++)
		if (!isfinite(p[k]))
			luaL_error(L, "%s: a value is not a number", what);
	const char *fixed = l->dim->element_fixed(l, e);
	if (fixed)
		luaL_error(L, "%s: %s", what, fixed);
	l->dim->place_element(l, e, p);
	return 0;
}

static int element_active(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	lua_pushboolean(L,
			l->dim->element_active(l, evo_lua_check_element(L, 1)));
	return 1;
}

/* element:set_active(on), in either world until the next reset: an object
 * off the world, a zone or target no sensor or reward sees. */
static int element_set_active(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	int e = evo_lua_check_element(L, 1);
	l->dim->set_element_active(l, e, lua_toboolean(L, 2));
	return 0;
}

static const luaL_Reg element_methods[] = {
    {"pos", element_pos},	{"place", element_place},
    {"active", element_active}, {"set_active", element_set_active},
    {"name", element_name},	{NULL, NULL}};

void evo_lua_element_methods(lua_State *L)
{
	luaL_setfuncs(L, element_methods, 0);
}
