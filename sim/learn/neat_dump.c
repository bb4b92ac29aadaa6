/* evo.neat's dump (sim/learn/neat_internal.h): plain Lua data as text,
 * serialize.dump_lua's text byte for byte, for the checkpoints. */
#include <ctype.h>
#include <lauxlib.h>
#include <lua.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/g17.h"
#include "learn/neat_internal.h"

/* How deep dump follows tables into tables (a checkpoint is 6 deep). */
#define DUMP_MAX_DEPTH 100

/* ------------------------------------------------------------------ */
/* Plain data as text */

/* A table already written: where its text is in the buffer. */
typedef struct written {
	const void *table; /* NULL: a free slot */
	size_t at, len;
} written;

/* The text being made, and the tables written into it: a table met
 * again (genomes share their node tables) is the same text, copied. */
typedef struct buffer {
	char *b;
	size_t len, cap;
	written *seen; /* open addressing on the table's address */
	size_t n_seen, seen_cap;
} buffer;

static void free_buffer_of(buffer *b)
{
	free(b->b);
	b->b = NULL;
	free(b->seen);
	b->seen = NULL;
}

int neat_free_buffer(lua_State *L)
{
	free_buffer_of(luaL_checkudata(L, 1, BUF_TYPE));
	return 0;
}

/* The slot of `table` in b->seen: its entry, or the free slot it would
 * take. */
static written *seen_slot(const buffer *b, const void *table)
{
	size_t h = ((uintptr_t)table >> 4) * 0x9E3779B97F4A7C15u;
	for (size_t i = h & (b->seen_cap - 1);; i = (i + 1) & (b->seen_cap - 1))
		if (b->seen[i].table == table || !b->seen[i].table)
			return &b->seen[i];
}

/* Notes that `table`'s text is b->b[at .. b->len). */
static void note_written(lua_State *L, buffer *b, const void *table,
			 size_t at)
{
	if (2 * (b->n_seen + 1) > b->seen_cap) {
		size_t cap = b->seen_cap ? 2 * b->seen_cap : 256;
		written *old = b->seen;
		size_t old_cap = b->seen_cap;
		b->seen = calloc(cap, sizeof *b->seen);
		if (!b->seen) {
			b->seen = old;
			luaL_error(L, "serialize: out of memory");
		}
		b->seen_cap = cap;
		for (size_t i = 0; i < old_cap; i++)
			if (old[i].table)
				*seen_slot(b, old[i].table) = old[i];
		free(old);
	}
	written *w = seen_slot(b, table);
	if (!w->table)
		b->n_seen++;
	*w = (written){table, at, b->len - at};
}

/* Room for n more bytes in b. */
static void reserve(lua_State *L, buffer *b, size_t n)
{
	if (b->cap - b->len < n) {
		size_t cap = b->cap ? b->cap : 4096;
		while (cap - b->len < n)
			cap *= 2;
		char *nb = realloc(b->b, cap);
		if (!nb)
			luaL_error(L, "serialize: out of memory");
		b->b = nb;
		b->cap = cap;
	}
}

static void put(lua_State *L, buffer *b, const char *s, size_t n)
{
	reserve(L, b, n);
	memcpy(b->b + b->len, s, n);
	b->len += n;
}

static void puts_(lua_State *L, buffer *b, const char *s)
{
	put(L, b, s, strlen(s));
}

/* The decimal digits of x (not LUA_MININTEGER) into s; their count. */
static size_t int_text(char *s, lua_Integer x)
{
	char tmp[24];
	size_t n = 0, k = 0;
	uint64_t u = x < 0 ? (uint64_t)0 - (uint64_t)x : (uint64_t)x;
	do {
		tmp[n++] = (char)('0' + u % 10);
		u /= 10;
	} while (u);
	if (x < 0)
		s[k++] = '-';
	while (n)
		s[k++] = tmp[--n];
	return k;
}

/* As serialize.lua's number(): integers as they are (the smallest as an
 * expression), floats with 17 digits and a ".0" when they would read as
 * an integer, inf and nan as expressions. */
static void put_number(lua_State *L, buffer *b, int idx)
{
	char s[64];
	if (lua_isinteger(L, idx)) {
		lua_Integer x = lua_tointeger(L, idx);
		if (x == LUA_MININTEGER)
			puts_(L, b, "(-9223372036854775807-1)");
		else
			put(L, b, s, int_text(s, x));
		return;
	}
	double x = lua_tonumber(L, idx);
	if (x > -0x1p53 && x < 0x1p53 && x == (double)(int64_t)x &&
	    (x != 0 || !signbit(x))) {
		/* a whole float: "%.17g" gives its digits (it has fewer
		 * than 17), and ".0" follows */
		size_t n = int_text(s, (lua_Integer)x);
		memcpy(s + n, ".0", 2);
		put(L, b, s, n + 2);
	} else if (x != x) {
		puts_(L, b, "(0/0)");
	} else if (x > 1.7976931348623157e308) {
		puts_(L, b, "(1/0)");
	} else if (x < -1.7976931348623157e308) {
		puts_(L, b, "(-1/0)");
	} else {
		evo_g17(x, s, sizeof s); /* "%.17g" */
		if (!strpbrk(s, ".eEn"))
			strcat(s, ".0");
		puts_(L, b, s);
	}
}

/* As string.format("%q", s). */
static void put_string(lua_State *L, buffer *b, int idx)
{
	size_t len;
	const char *s = lua_tolstring(L, idx, &len);
	put(L, b, "\"", 1);
	for (size_t i = 0; i < len; i++) {
		unsigned char c = (unsigned char)s[i];
		size_t run = 0; /* characters written as they are, from i */
		while (i + run < len && s[i + run] != '"' &&
		       s[i + run] != '\\' && s[i + run] != '\n' &&
		       !iscntrl((unsigned char)s[i + run]))
			run++;
		if (run) {
			put(L, b, s + i, run);
			i += run - 1;
		} else if (c == '"' || c == '\\' || c == '\n') {
			char e[2] = {'\\', (char)c};
			put(L, b, e, 2);
		} else if (iscntrl(c)) {
			char e[8];
			/* s[len] is the string's terminating zero */
			unsigned char next = (unsigned char)s[i + 1];
			snprintf(e, sizeof e, isdigit(next) ? "\\%03d" : "\\%d",
				 (int)c);
			puts_(L, b, e);
		}
	}
	put(L, b, "\"", 1);
}

/* n when the table at idx has exactly the keys 1 .. n (n = #t), else -1. */
static lua_Integer list_length(lua_State *L, int idx)
{
	lua_Integer n = (lua_Integer)lua_rawlen(L, idx);
	for (lua_Integer i = 1; i <= n; i++) {
		int nil = lua_rawgeti(L, idx, i) == LUA_TNIL;
		lua_pop(L, 1);
		if (nil)
			return -1;
	}
	lua_Integer count = 0;
	lua_pushnil(L);
	while (lua_next(L, idx)) {
		lua_pop(L, 1);
		if (++count > n) {
			lua_pop(L, 1);
			return -1;
		}
	}
	return n;
}

/* A record's key as the sort compares it: its stack slot, its type, and
 * a string key's bytes (read once, not at every comparison). */
typedef struct rkey {
	int slot, type;
	const char *s;
	size_t len;
} rkey;

/* serialize.lua's key order: by type name, then by value (Lua's <).
 * Strings compare byte by byte, a prefix first: what Lua's < does in the
 * C locale, which evo never leaves. */
static int key_less(lua_State *L, const rkey *a, const rkey *b)
{
	if (a->type != b->type)
		return strcmp(lua_typename(L, a->type),
			      lua_typename(L, b->type)) < 0;
	if (a->type == LUA_TSTRING) {
		int c = memcmp(a->s, b->s, a->len < b->len ? a->len : b->len);
		return c < 0 || (c == 0 && a->len < b->len);
	}
	return lua_compare(L, a->slot, b->slot, LUA_OPLT);
}

/* Sorts the n keys k[0 .. n-1] (insertion of each into the sorted ones
 * before it: a record has a few; the keys are distinct, so any sort
 * gives one order). */
static void sort_keys(lua_State *L, rkey *k, int n)
{
	for (int i = 1; i < n; i++) {
		rkey x = k[i];
		int j = i;
		for (; j > 0 && key_less(L, &x, &k[j - 1]); j--)
			k[j] = k[j - 1];
		k[j] = x;
	}
}

/* Merge sort of the n keys k[0 .. n-1], tmp as room: for big maps. */
static void merge_keys(lua_State *L, rkey *k, rkey *tmp, int n)
{
	for (int w = 1; w < n; w *= 2) {
		for (int lo = 0; lo < n; lo += 2 * w) {
			int mid = lo + w < n ? lo + w : n;
			int hi = lo + 2 * w < n ? lo + 2 * w : n;
			int a = lo, c = mid, o = lo;
			while (a < mid && c < hi)
				tmp[o++] = key_less(L, &k[c], &k[a]) ? k[c++]
								      : k[a++];
			while (a < mid)
				tmp[o++] = k[a++];
			while (c < hi)
				tmp[o++] = k[c++];
		}
		memcpy(k, tmp, (size_t)n * sizeof *k);
	}
}

static void put_value(lua_State *L, buffer *b, int idx, int depth);

/* Genes as the list of gene tables they stand for (genes:plain()'s
 * text): each gene's fields in key order. */
static void put_genes(lua_State *L, buffer *b, const genes *gs)
{
	static const char *const name[] = {
	    NULL, "[\"innov\"]=", "[\"from\"]=", "[\"to\"]=",
	    "[\"weight\"]=", "[\"enabled\"]="};
	static const enum key order[] = {K_ENABLED, K_FROM, K_INNOV, K_TO,
					 K_WEIGHT};
	luaL_checkstack(L, 2, "serialize: genes");
	put(L, b, "{", 1);
	for (int i = 0; i < gs->n; i++) {
		put(L, b, "{", 1);
		for (int k = 0; k < 5; k++) {
			puts_(L, b, name[order[k]]);
			neat_push_gene_field(L, &gs->g[i], order[k]);
			if (order[k] == K_ENABLED)
				puts_(L, b, lua_toboolean(L, -1) ? "true"
								 : "false");
			else
				put_number(L, b, lua_gettop(L));
			lua_pop(L, 1);
			put(L, b, ",", 1);
		}
		put(L, b, "},", 2);
	}
	put(L, b, "}", 1);
}

static void put_record(lua_State *L, buffer *b, int idx, int depth)
{
	/* every key and its value onto the stack, in pairs from base */
	int base = lua_gettop(L) + 1, n = 0;
	lua_pushnil(L);
	while (lua_next(L, idx)) {
		luaL_checkstack(L, 3, "serialize: a table of too many keys");
		lua_pushvalue(L, -2); /* the pair stays, a copy iterates */
		n++;
	}
	/* a record's few keys are sorted in an array here, a big map's in
	 * a userdata */
	rkey small[16];
	rkey *k = n <= 16 ? small
			  : lua_newuserdatauv(L, 2 * (size_t)n * sizeof *k, 0);
	for (int i = 0; i < n; i++) {
		k[i].slot = base + 2 * i;
		k[i].type = lua_type(L, k[i].slot);
		k[i].s = k[i].type == LUA_TSTRING
			     ? lua_tolstring(L, k[i].slot, &k[i].len)
			     : NULL;
	}
	if (n <= 16)
		sort_keys(L, k, n);
	else
		merge_keys(L, k, k + n, n);
	for (int i = 0; i < n; i++) {
		put(L, b, "[", 1);
		put_value(L, b, k[i].slot, depth);
		put(L, b, "]=", 2);
		put_value(L, b, k[i].slot + 1, depth);
		put(L, b, ",", 1);
	}
	lua_settop(L, base - 1);
}

static void put_value(lua_State *L, buffer *b, int idx, int depth)
{
	switch (lua_type(L, idx)) {
	case LUA_TNUMBER:
		put_number(L, b, idx);
		return;
	case LUA_TSTRING:
		put_string(L, b, idx);
		return;
	case LUA_TBOOLEAN:
		puts_(L, b, lua_toboolean(L, idx) ? "true" : "false");
		return;
	case LUA_TTABLE:
		break;
	case LUA_TUSERDATA:
		if (neat_to_genes(L, idx)) {
			put_genes(L, b, neat_to_genes(L, idx));
			return;
		}
		/* fall through */
	default:
		luaL_error(L, "serialize: cannot save a %s",
			   luaL_typename(L, idx));
	}
	const void *table = lua_topointer(L, idx);
	const written *w = b->seen_cap ? seen_slot(b, table) : NULL;
	if (w && w->table) {
		size_t at = w->at, n = w->len;
		reserve(L, b, n); /* (w may move no more: no lookup follows) */
		memcpy(b->b + b->len, b->b + at, n);
		b->len += n;
		return;
	}
	if (depth >= DUMP_MAX_DEPTH)
		luaL_error(L, "serialize: tables nested more than %d deep",
			   DUMP_MAX_DEPTH);
	size_t at = b->len;
	luaL_checkstack(L, 8, "serialize: tables nested too deep");
	put(L, b, "{", 1);
	lua_Integer len = list_length(L, idx);
	if (len >= 0) {
		for (lua_Integer i = 1; i <= len; i++) {
			lua_rawgeti(L, idx, i);
			put_value(L, b, lua_gettop(L), depth + 1);
			lua_pop(L, 1);
			put(L, b, ",", 1);
		}
	} else {
		put_record(L, b, idx, depth + 1);
	}
	put(L, b, "}", 1);
	note_written(L, b, table, at);
}

/* dump(v) -> "return " .. v's text .. "\n", as serialize.dump_lua. */
int neat_l_dump(lua_State *L)
{
	luaL_checkany(L, 1);
	lua_settop(L, 1);
	buffer *b = lua_newuserdatauv(L, sizeof *b, 0);
	memset(b, 0, sizeof *b);
	luaL_setmetatable(L, BUF_TYPE);
	puts_(L, b, "return ");
	put_value(L, b, 1, 0);
	put(L, b, "\n", 1);
	lua_pushlstring(L, b->b, b->len);
	free_buffer_of(b);
	return 1;
}
