/* evo.neat's pack_net (sim/learn/lua_neat.c): a genome becomes the network
 * evo.evaluate runs, checked field by field against a network worked out
 * by hand from neat.to_net's rules (inputs keep their ids, outputs then
 * hidden nodes take the next ones, links from the bias node become node
 * biases times the bias node's value, disabled links are left out). */
#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <stdlib.h>

#include "harness.h"
#include "learn/lua_neat.h"
#include "mind/net_build.h"

/* Two inputs (0, 1), bias 2 of value 0.5, output 3, hidden 7: 0->3 (1.0),
 * 1->3 off, bias->3 (2.0: bias 1.0), 0->7 (0.5), 7->3 (-1.0), bias->7
 * (4.0: bias 2.0, plus 1.0 more from a second bias gene: 3.0). */
static const char GENOME[] =
    "local neat = require 'evo.neat'\n"
    "local g = { nodes = {\n"
    "  { id = 0, kind = 'input' }, { id = 1, kind = 'input' },\n"
    "  { id = 2, kind = 'bias', value = 0.5 },\n"
    "  { id = 3, kind = 'output', act = 'neat_sigmoid' },\n"
    "  { id = 7, kind = 'hidden', act = 'tanh' } }, links = {\n"
    "  { innov = 1, from = 0, to = 3, weight = 1.0, enabled = true },\n"
    "  { innov = 2, from = 1, to = 3, weight = 9.0, enabled = false },\n"
    "  { innov = 3, from = 2, to = 3, weight = 2.0, enabled = true },\n"
    "  { innov = 4, from = 0, to = 7, weight = 0.5, enabled = true },\n"
    "  { innov = 5, from = 7, to = 3, weight = -1.0, enabled = true },\n"
    "  { innov = 6, from = 2, to = 7, weight = 4.0, enabled = true },\n"
    "  { innov = 8, from = 2, to = 7, weight = 2.0, enabled = true } } }\n"
    "return neat.pack_net(g), g\n";

static lua_State *state(void)
{
	lua_State *L = luaL_newstate();
	luaL_openlibs(L);
	evo_lua_open_neat(L);
	return L;
}

static unsigned act(const char *name)
{
	unsigned a = 0;
	while (evo_act_name(a) && strcmp(evo_act_name(a), name))
		a++;
	return a;
}

TEST(a_genome_packs_into_the_network_worked_out_by_hand)
{
	lua_State *L = state();
	CHECK_EQ_INT(luaL_dostring(L, GENOME), LUA_OK);
	static evo_netdesc d;
	CHECK_EQ_INT(evo_lua_net_unpack(L, -2, &d), 1);
	CHECK_EQ_INT(d.n_in, 2);
	CHECK_EQ_INT(d.n_out, 1);
	CHECK_EQ_INT(d.n_nodes, 2);
	CHECK_EQ_INT(d.out_id[0], 2);
	CHECK_EQ_INT(d.node[0].id, 2);
	CHECK_EQ_INT(d.node[0].act, act("neat_sigmoid"));
	CHECK_EQ_INT(d.node[0].bias, evo_net_weight_q16(1.0));
	CHECK_EQ_INT(d.node[1].id, 3);
	CHECK_EQ_INT(d.node[1].act, act("tanh"));
	CHECK_EQ_INT(d.node[1].bias, evo_net_weight_q16(3.0));
	CHECK_EQ_INT(d.n_links, 3);
	CHECK_EQ_INT(d.link[0].from, 0);
	CHECK_EQ_INT(d.link[0].to, 2);
	CHECK_EQ_INT(d.link[0].weight, evo_net_weight_q16(1.0));
	CHECK_EQ_INT(d.link[1].from, 0);
	CHECK_EQ_INT(d.link[1].to, 3);
	CHECK_EQ_INT(d.link[1].weight, evo_net_weight_q16(0.5));
	CHECK_EQ_INT(d.link[2].from, 3);
	CHECK_EQ_INT(d.link[2].to, 2);
	CHECK_EQ_INT(d.link[2].weight, evo_net_weight_q16(-1.0));
	/* the genome table itself is no packed network */
	CHECK_EQ_INT(evo_lua_net_unpack(L, -1, &d), 0);
	lua_close(L);
}

/* A genome pack_net cannot make a network of is refused with what is
 * wrong, not packed into a network that runs something else. */
TEST(a_broken_genome_is_refused_by_name)
{
	lua_State *L = state();
	CHECK(luaL_dostring(L, "return require('evo.neat').pack_net{ nodes = "
			       "{ { id = 0, kind = 'input' }, { id = 1, kind "
			       "= 'output', act = 'nosuch' } }, links = {} }") !=
	      LUA_OK);
	CHECK(strstr(lua_tostring(L, -1), "unknown activation 'nosuch'"));
	lua_settop(L, 0);
	CHECK(luaL_dostring(L, "return require('evo.neat').pack_net{ nodes = "
			       "{ { id = 0, kind = 'input' }, { id = 1, kind "
			       "= 'output', act = 'tanh' } }, links = { { "
			       "innov = 1, from = 5, to = 1, weight = 1, "
			       "enabled = true } } }") != LUA_OK);
	CHECK(strstr(lua_tostring(L, -1),
		     "link 1 starts at node 5, which the genome does not have"));
	lua_close(L);
}

int main(void)
{
	RUN(a_genome_packs_into_the_network_worked_out_by_hand);
	RUN(a_broken_genome_is_refused_by_name);
	return test_summary();
}
