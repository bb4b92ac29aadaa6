/* The networks LEARNINGMETHOD:CMAES builds (lua/learn/cmaes.lua's to_net),
 * as evo reads and runs them: a CMAES_RECURRENT network written to .net
 * text, parsed and compiled (core/src/net_compile.c) computes exactly the
 * Elman recurrence h(t) = tanh(W x(t) + U h(t-1)), out = sigmoid(V h(t)),
 * h(0) = 0, which the test works out in doubles beside it; a bias-free
 * network is a valid .net whose biases are 0. */
#define _POSIX_C_SOURCE 200809L
#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "evo/net.h"
#include "harness.h"
#include "learn/lua_linalg.h"
#include "lua/lua_evo.h"

enum { N_IN = 3, N_H = 3, N_OUT = 1 };

/* Genome weights in cmaes.lua's order for layers:1, no bias, recurrent:
 * each hidden unit: 3 from the inputs, 3 from the hidden units; then the
 * output: 3 from the hidden units. */
static double genome_w(int k)
{
	return 0.9 * sin(1.7 * k + 0.3);
}

/* The .net text of that genome, from learn.cmaes; malloc'd, NULL on error. */
static char *net_text(int recurrent)
{
	lua_State *L = luaL_newstate();
	luaL_openlibs(L);
	evo_lua_set_path(L, evo_lua_dir());
	evo_lua_open_linalg(L);
	char code[2048];
	int n = N_H * (N_IN + (recurrent ? N_H : 0)) + N_OUT * N_H;
	snprintf(
	    code, sizeof code,
	    "local cmaes = require 'learn.cmaes'\n"
	    "local w = {}\n"
	    "for k = 1, %d do w[k] = 0.9 * math.sin(1.7 * (k - 1) + 0.3) end\n"
	    "local g = { inputs = %d, outputs = %d, layers = 1, width = %d, "
	    "bias = false, recurrent = %s, hidden_act = 'tanh', weights = w }\n"
	    "return cmaes.to_net_text(cmaes.to_net(g))\n",
	    n, N_IN, N_OUT, N_H, recurrent ? "true" : "false");
	char *text = NULL;
	if (luaL_dostring(L, code) == LUA_OK)
		text = strdup(lua_tostring(L, -1));
	else
		printf("  lua: %s\n", lua_tostring(L, -1));
	lua_close(L);
	return text;
}

static double sigmoid(double x)
{
	return 1 / (1 + exp(-x));
}

/* The largest difference over 50 steps between evo's compiled network
 * and the Elman recurrence in doubles. */
static double elman_gap(const char *text)
{
	static evo_netdesc d;
	static evo_net_compile_ws ws;
	static evo_net_node nodes[EVO_NET_MAX_NODES];
	static evo_net_link links[EVO_NET_MAX_LINKS];
	static uint16_t out_ids[EVO_MAX_SKILL_IO];
	static evo_q16 act[EVO_NET_MAX_NODES + EVO_MAX_SKILL_IO];
	evo_diag err;
	evo_net net;
	if (evo_netdesc_parse(text, strlen(text), "cmaes.net", &d, &err) !=
		EVO_OK ||
	    evo_net_compile(&d, &ws, nodes, links, out_ids, &net) != EVO_OK)
		return 1e9;
	memset(act, 0, sizeof act);
	double h[N_H] = {0}, gap = 0;
	for (int t = 0; t < 50; t++) {
		double x[N_IN];
		evo_q16 qin[N_IN], qout[N_OUT];
		for (int i = 0; i < N_IN; i++) {
			x[i] = evo_q16_to_double(
			    evo_q16_from_double(sin(0.37 * t + i)));
			qin[i] = evo_q16_from_double(x[i]);
		}
		double nh[N_H];
		int k = 0;
		for (int j = 0; j < N_H; j++) {
			double s = 0;
			for (int i = 0; i < N_IN; i++)
				s += genome_w(k++) * x[i];
			for (int i = 0; i < N_H; i++)
				s += genome_w(k++) * h[i];
			nh[j] = tanh(s);
		}
		double s = 0;
		for (int j = 0; j < N_H; j++)
			s += genome_w(k++) * nh[j];
		memcpy(h, nh, sizeof h);
		evo_net_eval(&net, act, qin, qout);
		double g = fabs(evo_q16_to_double(qout[0]) - sigmoid(s));
		if (g > gap)
			gap = g;
	}
	return gap;
}

TEST(a_recurrent_network_is_exactly_an_elman_network)
{
	char *text = net_text(1);
	CHECK(text != NULL);
	if (!text)
		return;
	/* context nodes, identity, after the hidden units */
	CHECK(strstr(text, "node:7:identity:0\n") != NULL);
	double gap = elman_gap(text);
	/* fixed-point rounding only (Q16, evo's tanh and sigmoid tables) */
	CHECK(gap < 2e-3);
	printf("  Elman recurrence: largest difference %g\n", gap);
	/* the same weights with the hidden units reading each other in
	 * place (no context nodes) are not Elman's: the check can tell */
	char *bad = strdup(text);
	free(text);
	for (char *p = bad; (p = strstr(p, "link:")) != NULL; p++) {
		unsigned from, to;
		if (sscanf(p, "link:%u:%u:", &from, &to) == 2 && from >= 7 &&
		    to >= 4 && to <= 6) {
			/* hidden j reads unit from-3 directly */
			p[5] = (char)('0' + from - 3);
		}
	}
	CHECK(elman_gap(bad) > 1e-2);
	free(bad);
}

TEST(a_bias_free_feed_forward_network_is_a_valid_net)
{
	char *text = net_text(0);
	CHECK(text != NULL);
	if (!text)
		return;
	CHECK(strstr(text, "node:4:tanh:0\n") &&
	      strstr(text, "node:3:sigmoid:0\n"));
	static evo_netdesc d;
	evo_diag err;
	CHECK_EQ_INT(evo_netdesc_parse(text, strlen(text), "n.net", &d, &err),
		     EVO_OK);
	CHECK_EQ_INT(d.n_links, 12);
	free(text);
}

int main(void)
{
	RUN(a_recurrent_network_is_exactly_an_elman_network);
	RUN(a_bias_free_feed_forward_network_is_a_valid_net);
	return test_summary();
}
