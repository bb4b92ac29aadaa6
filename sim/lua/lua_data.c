/* evo.data.read: the plain data lua/learn/serialize.lua writes, read as
 * data. A checkpoint is never run: running it as Lua let a file of a few
 * bytes reach the string library (a pattern that backtracks for seconds)
 * or loop. This reader takes exactly what serialize.dump writes, in time
 * linear in the text, with nesting bounded:
 *
 *   file   = "return" value
 *   value  = number | string | "true" | "false" | table
 *   table  = "{" { (value | "[" value "]=" value) "," } "}"
 *   number = Lua's numeral (integer or float, as tostring and %.17g
 *            write them), "(0/0)", "(1/0)", "(-1/0)" or
 *            "(-9223372036854775807-1)"
 *   string = "..." with the escapes string.format's %q writes
 *
 * with spaces, tabs and newlines between tokens. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <lauxlib.h>
#include <lua.h>

#include "lua/lua_evo.h"

/* Deeper than anything dump writes (a checkpoint nests about 6 deep),
 * shallow enough for the C stack. */
#define DATA_MAX_DEPTH 64

typedef struct reader {
	lua_State *L;
	const char *p, *end;
	const char *name;
	int line;
} reader;

static int fail(reader *r, const char *what)
{
	char found[24];
	size_t n = 0;
	if (r->p >= r->end)
		snprintf(found, sizeof found, "the end of the text");
	else {
		found[n++] = '\'';
		for (const char *q = r->p; q < r->end && n < 12 && *q != '\n';
		     q++)
			found[n++] = (*q >= 32 && *q < 127) ? *q : '?';
		found[n++] = '\'';
		found[n] = 0;
	}
	return luaL_error(r->L,
			  "%s:%d: not plain data as evo writes it: expected "
			  "%s, found %s",
			  r->name, r->line, what, found);
}

static void skip_space(reader *r)
{
	while (r->p < r->end && (*r->p == ' ' || *r->p == '\t' ||
				 *r->p == '\n' || *r->p == '\r')) {
		if (*r->p == '\n')
			r->line++;
		r->p++;
	}
}

static int take(reader *r, const char *tok)
{
	size_t n = strlen(tok);
	if ((size_t)(r->end - r->p) >= n && memcmp(r->p, tok, n) == 0) {
		r->p += n;
		return 1;
	}
	return 0;
}

static void read_string(reader *r)
{
	luaL_Buffer b;
	luaL_buffinit(r->L, &b);
	r->p++; /* the opening quote */
	for (;;) {
		if (r->p >= r->end)
			fail(r, "the string's closing '\"'");
		char c = *r->p++;
		if (c == '"')
			break;
		if (c == '\n') {
			r->p--;
			fail(r, "'\\' before a newline in a string");
		}
		if (c != '\\') {
			luaL_addchar(&b, c);
			continue;
		}
		if (r->p >= r->end)
			fail(r, "an escape");
		c = *r->p++;
		if (c == '\\' || c == '"') {
			luaL_addchar(&b, c);
		} else if (c == '\n') {
			r->line++;
			luaL_addchar(&b, '\n');
		} else if (c >= '0' && c <= '9') {
			int v = c - '0', k = 1;
			while (k < 3 && r->p < r->end && *r->p >= '0' &&
			       *r->p <= '9') {
				v = v * 10 + (*r->p++ - '0');
				k++;
			}
			if (v > 255) {
				r->p -= k;
				fail(r, "a byte escape \\0 .. \\255");
			}
			luaL_addchar(&b, (char)v);
		} else {
			r->p -= 2;
			fail(r, "one of the escapes %q writes");
		}
	}
	luaL_pushresult(&b);
}

static void read_number(reader *r)
{
	static const struct {
		const char *text;
		int kind; /* 0 nan, 1 inf, 2 -inf, 3 the least integer */
	} special[] = {{"(0/0)", 0},
		       {"(1/0)", 1},
		       {"(-1/0)", 2},
		       {"(-9223372036854775807-1)", 3}};
	for (unsigned i = 0; i < 4; i++)
		if (take(r, special[i].text)) {
			/* 0/0 as Lua computes it at run time, sign included */
			volatile double zero = 0;
			switch (special[i].kind) {
			case 0:
				lua_pushnumber(r->L, zero / zero);
				break;
			case 1:
				lua_pushnumber(r->L, HUGE_VAL);
				break;
			case 2:
				lua_pushnumber(r->L, -HUGE_VAL);
				break;
			default:
				lua_pushinteger(r->L, LUA_MININTEGER);
			}
			return;
		}
	char num[64];
	size_t n = 0;
	while (r->p + n < r->end && n < sizeof num - 1 &&
	       strchr("0123456789+-.eE", r->p[n]) && r->p[n])
		n++;
	memcpy(num, r->p, n);
	num[n] = 0;
	/* Lua's own reading of a numeral: the same value, bit for bit, as
	 * running the text gave */
	if (n == 0 || n == sizeof num - 1 ||
	    lua_stringtonumber(r->L, num) != n + 1)
		fail(r, "a value (a number, a string, true, false or a table)");
	r->p += n;
}

static void read_value(reader *r, int depth);

static void read_table(reader *r, int depth)
{
	if (depth >= DATA_MAX_DEPTH)
		fail(r, "tables nested at most 64 deep");
	luaL_checkstack(r->L, 4, "reading data");
	r->p++; /* { */
	lua_newtable(r->L);
	lua_Integer next = 1;
	for (;;) {
		skip_space(r);
		if (take(r, "}"))
			return;
		if (take(r, "[")) {
			skip_space(r);
			read_value(r, depth + 1);
			if (lua_type(r->L, -1) == LUA_TTABLE ||
			    (lua_type(r->L, -1) == LUA_TNUMBER &&
			     isnan(lua_tonumber(r->L, -1))))
				fail(r, "a key that is a number, a string or "
					"a boolean");
			skip_space(r);
			if (!take(r, "]"))
				fail(r, "']'");
			skip_space(r);
			if (!take(r, "="))
				fail(r, "'='");
			skip_space(r);
			read_value(r, depth + 1);
			lua_rawset(r->L, -3);
		} else {
			read_value(r, depth + 1);
			lua_rawseti(r->L, -2, next++);
		}
		skip_space(r);
		if (!take(r, ","))
			fail(r, "',' after a table's item");
	}
}

static void read_value(reader *r, int depth)
{
	skip_space(r);
	if (r->p >= r->end)
		fail(r, "a value");
	if (*r->p == '{')
		read_table(r, depth);
	else if (*r->p == '"')
		read_string(r);
	else if (take(r, "true"))
		lua_pushboolean(r->L, 1);
	else if (take(r, "false"))
		lua_pushboolean(r->L, 0);
	else
		read_number(r);
}

static int parse(lua_State *L)
{
	size_t len;
	const char *text = luaL_checklstring(L, 1, &len);
	reader r = {L, text, text + len, luaL_optstring(L, 2, "data"), 1};
	lua_settop(L, 2);
	skip_space(&r);
	if (!take(&r, "return") || r.p >= r.end ||
	    (*r.p != ' ' && *r.p != '\n' && *r.p != '\t' && *r.p != '{' &&
	     *r.p != '"' && *r.p != '('))
		fail(&r, "'return' and a value");
	read_value(&r, 0);
	skip_space(&r);
	if (r.p != r.end)
		fail(&r, "the end of the text after the value");
	return 1;
}

/* evo.data.read(text, name) -> the value. Reaching the state's memory
 * limit (docs/lua.md, "Limits") is an error that names the text. */
static int data_read(lua_State *L)
{
	luaL_checkstring(L, 1);
	const char *name = luaL_optstring(L, 2, "data");
	lua_settop(L, 2);
	lua_pushcfunction(L, parse);
	lua_pushvalue(L, 1);
	lua_pushvalue(L, 2);
	int r = lua_pcall(L, 2, 1, 0);
	if (r == LUA_OK)
		return 1;
	if (r != LUA_ERRMEM)
		return lua_error(L);
	lua_settop(L, 2);
	lua_gc(L, LUA_GCCOLLECT);
	return luaL_error(L,
			  "%s: reading it reached the Lua state's memory "
			  "limit (LUAMEMORY raises it, docs/lua.md)",
			  name);
}

static int open_data(lua_State *L)
{
	lua_newtable(L);
	lua_pushcfunction(L, data_read);
	lua_setfield(L, -2, "read");
	return 1;
}

void evo_lua_open_data(lua_State *L)
{
	luaL_requiref(L, "evo.data", open_data, 0);
	lua_pop(L, 1);
}
