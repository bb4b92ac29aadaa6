/* Tests for core/src/net.c and core/src/net_compile.c: activation
 * functions against <math.h>, hand-computed networks, the compile order
 * and its errors, the layered builder (sim/mind/net_build.c), and the bound on
 * the fixed-point error against the float reference (tests/support). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "evo/image.h"
#include "evo/net.h"
#include "harness.h"
#include "mind/net_build.h"
#include "support/net_float.h"
#include "support/rng.h"

/* Stated in docs/fixed-point.md; measured values are printed by the tests
 * and sit below these with margin. */
#define ACT_MAX_ERR_SIGMOID 3.5e-4
#define ACT_MAX_ERR_NEAT_SIGMOID 3.5e-4
#define ACT_MAX_ERR_TANH 7.0e-4
#define ACT_MAX_ERR_GAUSS 2.6e-4
#define NET_MAX_ERR_SIGMOID_LAYERED 1.0e-2 /* see run_family */

static evo_netdesc desc;
static evo_net_compile_ws ws;
static evo_net_node nodes[EVO_NET_MAX_NODES];
static evo_net_link links[EVO_NET_MAX_LINKS];
static uint16_t outs[EVO_MAX_SKILL_IO];
static evo_net net;
static evo_q16 act[EVO_MAX_SKILL_IO + EVO_NET_MAX_NODES];

static evo_q16 q(double d)
{
	return evo_q16_from_double(d);
}

static void desc_begin(unsigned n_in, unsigned n_out)
{
	desc.n_in = (uint16_t)n_in;
	desc.n_out = (uint16_t)n_out;
	desc.n_nodes = 0;
	desc.n_links = 0;
}

static void add_node(unsigned id, unsigned act_kind, double bias)
{
	evo_netdesc_node *n = &desc.node[desc.n_nodes++];
	n->id = (uint16_t)id;
	n->act = (uint8_t)act_kind;
	n->bias = q(bias);
	n->line = desc.n_nodes;
}

static void add_link(unsigned from, unsigned to, double w)
{
	evo_netdesc_link *l = &desc.link[desc.n_links++];
	l->from = (uint16_t)from;
	l->to = (uint16_t)to;
	l->weight = q(w);
	l->line = desc.n_links;
}

static evo_status compile(void)
{
	evo_status st = evo_net_compile(&desc, &ws, nodes, links, outs, &net);
	unsigned i;
	if (st == EVO_OK)
		for (i = 0; i < net.n_nodes; i++)
			act[i] = 0;
	return st;
}

static evo_q16 eval1(const evo_q16 *in)
{
	evo_q16 out[EVO_MAX_SKILL_IO];
	evo_net_eval(&net, act, in, out);
	return out[0];
}

static int ws_is_clean(void)
{
	size_t i;
	for (i = 0; i < sizeof ws.index_of_id / sizeof ws.index_of_id[0]; i++)
		if (ws.index_of_id[i] != 0)
			return 0;
	return 1;
}

/* ---- activation functions ------------------------------------------ */

TEST(act_names_follow_the_list)
{
	CHECK_EQ_STR(evo_act_name(EVO_ACT_IDENTITY), "identity");
	CHECK_EQ_STR(evo_act_name(EVO_ACT_NEAT_SIGMOID), "neat_sigmoid");
	CHECK_EQ_STR(evo_act_name(EVO_ACT_GAUSS), "gauss");
	CHECK(evo_act_name(EVO_ACT_COUNT) == NULL);
	CHECK(evo_act_name(1000) == NULL);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_COUNT, q(1)), 0);
}

TEST(exact_activations)
{
	static const evo_q16 xs[] = {EVO_Q16_MIN, -163840, -1,	   0, 1,
				     32768,	  65536,   98304, EVO_Q16_MAX};
	size_t i;
	for (i = 0; i < sizeof xs / sizeof xs[0]; i++) {
		evo_q16 x = xs[i];
		CHECK_EQ_INT(evo_act_apply(EVO_ACT_IDENTITY, x), x);
		CHECK_EQ_INT(evo_act_apply(EVO_ACT_RELU, x), x > 0 ? x : 0);
		CHECK_EQ_INT(evo_act_apply(EVO_ACT_STEP, x),
			     x > 0 ? EVO_Q16_ONE : 0);
		CHECK_EQ_INT(evo_act_apply(EVO_ACT_CLAMPED, x),
			     x < 0 ? 0 : x > EVO_Q16_ONE ? EVO_Q16_ONE : x);
	}
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_SIGMOID, 0), EVO_Q16_HALF);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_NEAT_SIGMOID, 0), EVO_Q16_HALF);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_TANH, 0), 0);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_GAUSS, 0), EVO_Q16_ONE);
	/* Saturation at the asymptotes, including the extremes of Q16. */
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_SIGMOID, q(8)), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_SIGMOID, EVO_Q16_MAX), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_SIGMOID, EVO_Q16_MIN), 0);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_NEAT_SIGMOID, EVO_Q16_MIN), 0);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_NEAT_SIGMOID, EVO_Q16_MAX),
		     EVO_Q16_ONE);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_TANH, q(4)), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_TANH, EVO_Q16_MIN), -EVO_Q16_ONE);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_TANH, EVO_Q16_MAX), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_GAUSS, q(3.5)), 0);
	CHECK_EQ_INT(evo_act_apply(EVO_ACT_GAUSS, EVO_Q16_MIN), 0);
}

static double act_error(unsigned a, double lo, double hi, int *symmetric,
			int *monotone)
{
	double max_err = 0;
	int32_t raw;
	evo_q16 prev = evo_act_apply(a, q(lo));

	*symmetric = *monotone = 1;
	for (raw = q(lo); raw <= q(hi); raw++) {
		evo_q16 y = evo_act_apply(a, raw);
		evo_q16 ym = evo_act_apply(a, -raw);
		double err = fabs(evo_q16_to_double(y) -
				  net_float_act(a, evo_q16_to_double(raw)));
		if (err > max_err)
			max_err = err;
		if (a == EVO_ACT_TANH ? ym != -y
		    : a == EVO_ACT_GAUSS ? ym != y
					 : ym != EVO_Q16_ONE - y)
			*symmetric = 0;
		if (a != EVO_ACT_GAUSS && y < prev)
			*monotone = 0;
		prev = y;
	}
	return max_err;
}

TEST(table_activations_match_math_h)
{
	static const struct {
		unsigned act;
		double bound;
	} cases[] = {
		{EVO_ACT_SIGMOID, ACT_MAX_ERR_SIGMOID},
		{EVO_ACT_NEAT_SIGMOID, ACT_MAX_ERR_NEAT_SIGMOID},
		{EVO_ACT_TANH, ACT_MAX_ERR_TANH},
		{EVO_ACT_GAUSS, ACT_MAX_ERR_GAUSS},
	};
	size_t i;
	for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		int sym, mono;
		/* Every Q16 argument in [-16, 16]; beyond it every table
		 * function sits at its asymptote, where the error shrinks. */
		double err = act_error(cases[i].act, -16, 16, &sym, &mono);
		printf("  %-12s max |fixed - math.h| at every Q16 x in "
		       "[-16, 16]: %.3g (bound %.3g)\n",
		       evo_act_name(cases[i].act), err, cases[i].bound);
		CHECK(err <= cases[i].bound);
		CHECK(sym);
		CHECK(mono);
	}
}

/* The table entries themselves: at its sample points a table function
 * gives its entry, and each entry is the true value rounded to nearest
 * (net.c stores the tables compressed; this pins what they hold). */
TEST(table_entries_are_rounded_math_h)
{
	for (int i = 0; i <= 136; i++) {
		double x = i / 16.0;
		int32_t want = i >= 128 ? EVO_Q16_ONE
					: EVO_Q16_HALF +
						  (int32_t)floor((1 / (1 + exp(-x)) - 0.5) *
								 65536 +
							 0.5);
		CHECK_EQ_INT(evo_act_apply(EVO_ACT_SIGMOID, i << 12), want);
	}
	for (int i = 0; i <= 120; i++) {
		double x = i / 32.0;
		int32_t want = i >= 109 ? 0
					: EVO_Q16_ONE -
						  (int32_t)floor((1 - exp(-x * x)) *
								 65536 +
							 0.5);
		CHECK_EQ_INT(evo_act_apply(EVO_ACT_GAUSS, i << 11), want);
	}
}

/* Every activation at every Q16 argument in [-16, 16], folded into a
 * CRC-32: the values of the full-table code this replaced (checked equal
 * to it at all 2^32 arguments when the tables were compressed). Any change
 * to an activation's output, however small, changes trained skills'
 * behaviour: this must not move. */
TEST(activations_are_pinned)
{
	static const uint32_t want[EVO_ACT_COUNT] = {
		0xCAD2CCA0u, 0x1281744Eu, 0xC89AEBF7u, 0x2EB58232u,
		0xF2CE448Eu, 0xA73919EBu, 0x3C9C7086u, 0x1C1CE926u,
	};
	for (unsigned f = 0; f < EVO_ACT_COUNT; f++) {
		uint32_t crc = 0;
		for (int32_t x = -16 * 65536; x <= 16 * 65536; x++) {
			evo_q16 y = evo_act_apply(f, x);
			crc = evo_crc32(crc, &y, sizeof y);
		}
		CHECK_EQ_INT(crc, want[f]);
	}
}

/* ---- hand-computed networks ---------------------------------------- */

TEST(single_neuron)
{
	evo_q16 in[2] = {q(0.5), q(0.25)};
	desc_begin(2, 1);
	add_node(2, EVO_ACT_IDENTITY, 0.5);
	desc.out_id[0] = 2;
	add_link(0, 2, 1.0);
	add_link(1, 2, -3.0);
	CHECK_EQ_INT(compile(), EVO_OK);
	/* 0.5 + 0.5 - 0.75 */
	CHECK_EQ_INT(eval1(in), q(0.25));
	CHECK_EQ_INT(evo_net_is_recurrent(&net), 0);

	desc.node[0].act = EVO_ACT_SIGMOID;
	CHECK_EQ_INT(compile(), EVO_OK);
	/* sigmoid(0.25) between table points 4/16 and 5/16 (exactly 4/16) */
	CHECK_EQ_INT(eval1(in), 32768 + 4075);

	/* The sum is rounded once: two products of half an ulp add up to
	 * one ulp, where rounding each (ties up) would give two. */
	desc_begin(1, 1);
	add_node(1, EVO_ACT_IDENTITY, 0);
	desc.out_id[0] = 1;
	add_link(0, 1, 0.5);
	add_link(0, 1, 0.5);
	CHECK_EQ_INT(compile(), EVO_OK);
	in[0] = 1; /* 2^-16 */
	CHECK_EQ_INT(eval1(in), 1);
}

/* x1 XOR x2 with step units: h1 = x1 OR x2, h2 = x1 AND x2,
 * out = h1 AND NOT h2. */
TEST(xor_2_2_1)
{
	int a, b;
	desc_begin(2, 1);
	add_node(10, EVO_ACT_STEP, -0.5);
	add_node(11, EVO_ACT_STEP, -1.5);
	add_node(12, EVO_ACT_STEP, -0.5);
	desc.out_id[0] = 12;
	add_link(0, 10, 1);
	add_link(1, 10, 1);
	add_link(0, 11, 1);
	add_link(1, 11, 1);
	add_link(10, 12, 1);
	add_link(11, 12, -1);
	CHECK_EQ_INT(compile(), EVO_OK);
	for (a = 0; a < 2; a++)
		for (b = 0; b < 2; b++) {
			evo_q16 in[2] = {a * EVO_Q16_ONE, b * EVO_Q16_ONE};
			CHECK_EQ_INT(eval1(in), (a ^ b) * EVO_Q16_ONE);
		}

	/* The same with sigmoid units and steep weights: the output is the
	 * table's value at the hand-computed sum. For (1, 0):
	 * h1 = sigmoid(10 - 5) = sigmoid(5), h2 = sigmoid(10 - 15) =
	 * 1 - sigmoid(5); out = sigmoid(10 h1 - 10 h2 - 5). */
	desc.node[0].act = desc.node[1].act = desc.node[2].act =
		EVO_ACT_SIGMOID;
	desc.node[0].bias = q(-5);
	desc.node[1].bias = q(-15);
	desc.node[2].bias = q(-5);
	for (a = 0; a < 6; a++)
		desc.link[a].weight = q(10);
	desc.link[5].weight = q(-10);
	CHECK_EQ_INT(compile(), EVO_OK);
	{
		evo_q16 in[2] = {EVO_Q16_ONE, 0};
		evo_q16 h1 = 32768 + 32329; /* table entry 80 = sigmoid(5) */
		evo_q16 h2 = 32768 - 32329;
		int64_t sum = (int64_t)q(10) * h1 - (int64_t)q(10) * h2 +
			      (int64_t)q(-5) * 65536;
		evo_q16 want = evo_act_apply(EVO_ACT_SIGMOID,
					     evo_q32_to_q16(sum));
		CHECK_EQ_INT(eval1(in), want);
		CHECK(want > q(0.99));
	}
}

/* A node feeding itself reads its own previous value: memory. */
TEST(self_loop_remembers)
{
	evo_q16 one = EVO_Q16_ONE;
	desc_begin(1, 1);
	add_node(1, EVO_ACT_IDENTITY, 0);
	desc.out_id[0] = 1;
	add_link(0, 1, 1);
	add_link(1, 1, 0.5);
	CHECK_EQ_INT(compile(), EVO_OK);
	CHECK_EQ_INT(evo_net_is_recurrent(&net), 1);
	CHECK_EQ_INT(eval1(&one), q(1));
	CHECK_EQ_INT(eval1(&one), q(1.5));
	CHECK_EQ_INT(eval1(&one), q(1.75));
	CHECK_EQ_INT(eval1(&one), q(1.875));
	/* Zeroing the activations resets the memory. */
	act[1] = 0;
	CHECK_EQ_INT(eval1(&one), q(1));
}

/* A (id 5) reads the input and B; B (id 6) reads A; output B. Depth-first
 * from B puts A first, so A reads B's previous value. */
TEST(two_node_cycle)
{
	evo_q16 one = EVO_Q16_ONE;
	desc_begin(1, 1);
	add_node(6, EVO_ACT_IDENTITY, 0.25);
	add_node(5, EVO_ACT_IDENTITY, 0);
	desc.out_id[0] = 6;
	add_link(0, 5, 1);
	add_link(6, 5, 1);
	add_link(5, 6, 1);
	CHECK_EQ_INT(compile(), EVO_OK);
	CHECK_EQ_INT(net.n_nodes, 3);
	CHECK_EQ_INT(nodes[0].bias, 0); /* A is node 1 */
	CHECK_EQ_INT(nodes[1].bias, q(0.25));
	CHECK_EQ_INT(outs[0], 2);
	CHECK_EQ_INT(evo_net_is_recurrent(&net), 1);
	/* A = 1 + B_prev, B = A + 0.25 */
	CHECK_EQ_INT(eval1(&one), q(1.25));
	CHECK_EQ_INT(eval1(&one), q(2.5));
	CHECK_EQ_INT(eval1(&one), q(3.75));
}

/* ---- compile ------------------------------------------------------- */

TEST(compile_orders_depth_first)
{
	/* inputs 0, 1; outputs 20, 21. 20 <- 30, 31 (in that order);
	 * 30 <- 31, 0; 31 <- 1; 21 <- 32 <- 20; 40 and 41 are unreached.
	 * Listed: 41, 21, 32, 20, 40, 31, 30. */
	desc_begin(2, 2);
	add_node(41, EVO_ACT_SIGMOID, 0.41);
	add_node(21, EVO_ACT_SIGMOID, 0.21);
	add_node(32, EVO_ACT_SIGMOID, 0.32);
	add_node(20, EVO_ACT_SIGMOID, 0.20);
	add_node(40, EVO_ACT_SIGMOID, 0.40);
	add_node(31, EVO_ACT_SIGMOID, 0.31);
	add_node(30, EVO_ACT_SIGMOID, 0.30);
	desc.out_id[0] = 20;
	desc.out_id[1] = 21;
	add_link(30, 20, 1);
	add_link(31, 20, 2);
	add_link(32, 21, 3);
	add_link(31, 30, 4);
	add_link(0, 30, 5);
	add_link(1, 31, 6);
	add_link(20, 32, 7);
	add_link(41, 40, 8);
	add_link(30, 20, 9); /* second link 30 -> 20, listed later */
	CHECK_EQ_INT(compile(), EVO_OK);
	{
		/* From 20: 30 first (its first source is 31), then 20;
		 * from 21: 32, 21; then 41, 40 in listing order. */
		static const double want_bias[] = {0.31, 0.30, 0.20, 0.32,
						   0.21, 0.41, 0.40};
		static const struct {
			uint16_t src;
			double w;
		} want_links[] = {{1, 6}, {2, 4}, {0, 5}, {3, 1}, {2, 2},
				  {3, 9}, {4, 7}, {5, 3}, {7, 8}};
		unsigned i;
		CHECK_EQ_INT(net.n_in, 2);
		CHECK_EQ_INT(net.n_nodes, 9);
		CHECK_EQ_INT(net.n_links, 9);
		for (i = 0; i < 7; i++)
			CHECK_EQ_INT(nodes[i].bias, q(want_bias[i]));
		for (i = 0; i < 9; i++) {
			CHECK_EQ_INT(links[i].src, want_links[i].src);
			CHECK_EQ_INT(links[i].weight, q(want_links[i].w));
		}
		CHECK_EQ_INT(nodes[2].link_start, 3);
		CHECK_EQ_INT(nodes[2].link_count, 3);
		CHECK_EQ_INT(nodes[5].link_count, 0);
		CHECK_EQ_INT(outs[0], 4);
		CHECK_EQ_INT(outs[1], 6);
		CHECK_EQ_INT(evo_net_is_recurrent(&net), 0);
	}
	CHECK(ws_is_clean());
}

TEST(compile_output_may_be_an_input)
{
	evo_q16 in[2] = {q(0.3), q(0.7)}, out[2];
	desc_begin(2, 2);
	add_node(2, EVO_ACT_IDENTITY, 0);
	add_link(0, 2, 1);
	desc.out_id[0] = 1;
	desc.out_id[1] = 2;
	CHECK_EQ_INT(compile(), EVO_OK);
	evo_net_eval(&net, act, in, out);
	CHECK_EQ_INT(out[0], q(0.7));
	CHECK_EQ_INT(out[1], q(0.3));
}

/* The scratch needs no initialisation: stale entries are ignored. */
TEST(compile_ignores_stale_scratch)
{
	size_t i;
	evo_q16 in[2] = {q(0.5), q(0.25)};
	for (i = 0; i < sizeof ws.index_of_id / sizeof ws.index_of_id[0]; i++)
		ws.index_of_id[i] = (uint16_t)(i * 7919u);
	desc_begin(2, 1);
	add_node(3, EVO_ACT_IDENTITY, 0);
	add_node(2, EVO_ACT_IDENTITY, 0);
	desc.out_id[0] = 3;
	add_link(2, 3, 2);
	add_link(0, 2, 1);
	add_link(1, 2, 1);
	CHECK_EQ_INT(compile(), EVO_OK);
	CHECK_EQ_INT(eval1(in), q(1.5));
	for (i = 0; i < sizeof ws.index_of_id / sizeof ws.index_of_id[0]; i++)
		ws.index_of_id[i] = 0;
}

TEST(compile_errors)
{
	desc_begin(2, 1);
	add_node(5, EVO_ACT_SIGMOID, 0);
	desc.out_id[0] = 5;
	add_link(0, 5, 1);
	CHECK_EQ_INT(compile(), EVO_OK);

	desc.link[0].from = 7; /* no such node */
	CHECK_EQ_INT(compile(), EVO_ERR_NAME);
	CHECK(ws_is_clean());
	desc.link[0].from = 0;
	desc.link[0].to = 1; /* into an input */
	CHECK_EQ_INT(compile(), EVO_ERR_NAME);
	desc.link[0].to = 6;
	CHECK_EQ_INT(compile(), EVO_ERR_NAME);
	desc.link[0].to = 5;
	desc.out_id[0] = 9;
	CHECK_EQ_INT(compile(), EVO_ERR_NAME);
	desc.out_id[0] = 5;
	desc.node[0].id = 1; /* a listed node with an input's id */
	CHECK_EQ_INT(compile(), EVO_ERR_NAME);
	desc.node[0].id = 5;
	desc.node[0].act = EVO_ACT_COUNT;
	CHECK_EQ_INT(compile(), EVO_ERR_NAME);
	desc.node[0].act = EVO_ACT_SIGMOID;
	add_node(5, EVO_ACT_SIGMOID, 0); /* the same id twice */
	CHECK_EQ_INT(compile(), EVO_ERR_NAME);
	CHECK(ws_is_clean());
	desc.n_nodes = 1;

	desc.link[0].weight = EVO_NET_WEIGHT_MAX * EVO_Q16_ONE;
	CHECK_EQ_INT(compile(), EVO_ERR_LIMIT);
	desc.link[0].weight = -EVO_NET_WEIGHT_MAX * EVO_Q16_ONE + 1;
	CHECK_EQ_INT(compile(), EVO_OK);
	desc.node[0].bias = -EVO_NET_WEIGHT_MAX * EVO_Q16_ONE;
	CHECK_EQ_INT(compile(), EVO_ERR_LIMIT);
	desc.node[0].bias = 0;
	CHECK(ws_is_clean());
}

TEST(compile_fanin_limit)
{
	unsigned i;
	desc_begin(1, 1);
	add_node(1, EVO_ACT_IDENTITY, 0);
	desc.out_id[0] = 1;
	for (i = 0; i < EVO_NET_MAX_FANIN; i++)
		add_link(0, 1, 0.5);
	CHECK_EQ_INT(compile(), EVO_OK);
	{
		evo_q16 in = q(0.25);
		CHECK_EQ_INT(eval1(&in), q(0.125 * EVO_NET_MAX_FANIN));
	}
	add_link(0, 1, 0.5);
	CHECK_EQ_INT(compile(), EVO_ERR_LIMIT);
	CHECK(ws_is_clean());
}

/* The extremes cannot overflow the sum: 256 links at the largest weight
 * from nodes at the largest activation saturate cleanly. */
TEST(extreme_sums_saturate)
{
	unsigned i;
	evo_q16 in[2] = {EVO_Q16_MAX, EVO_Q16_MIN};
	desc_begin(2, 2);
	add_node(2, EVO_ACT_IDENTITY, 0);
	add_node(3, EVO_ACT_IDENTITY, 0);
	desc.out_id[0] = 2;
	desc.out_id[1] = 3;
	for (i = 0; i < EVO_NET_MAX_FANIN; i++) {
		add_link(i % 2, 2, 0);
		desc.link[desc.n_links - 1].weight =
			i % 2 ? -(128 * 65536 - 1) : 128 * 65536 - 1;
	}
	desc.node[0].bias = 128 * 65536 - 1;
	for (i = 0; i < EVO_NET_MAX_FANIN; i++) {
		add_link(i % 2, 3, 0);
		desc.link[desc.n_links - 1].weight =
			i % 2 ? 128 * 65536 - 1 : -(128 * 65536 - 1);
	}
	desc.node[1].bias = -(128 * 65536 - 1);
	CHECK_EQ_INT(compile(), EVO_OK);
	{
		evo_q16 out[2];
		evo_net_eval(&net, act, in, out);
		CHECK_EQ_INT(out[0], EVO_Q16_MAX);
		CHECK_EQ_INT(out[1], EVO_Q16_MIN);
	}
}

/* A chain as long as the limits allow compiles without recursion. */
TEST(compile_long_chain)
{
	unsigned i;
	evo_q16 in = q(0.5);
	desc_begin(1, 1);
	for (i = 0; i < EVO_NET_MAX_NODES; i++) {
		add_node(1000 + i, EVO_ACT_IDENTITY, 0);
		add_link(i == 0 ? 0 : 1000 + i - 1, 1000 + i, 1);
	}
	desc.out_id[0] = (uint16_t)(1000 + EVO_NET_MAX_NODES - 1);
	CHECK_EQ_INT(compile(), EVO_OK);
	CHECK_EQ_INT(evo_net_is_recurrent(&net), 0);
	CHECK_EQ_INT(eval1(&in), q(0.5));
	desc.link[0].from = (uint16_t)(1000 + EVO_NET_MAX_NODES - 1);
	CHECK_EQ_INT(compile(), EVO_OK);
	CHECK_EQ_INT(evo_net_is_recurrent(&net), 1);
}

/* ---- the layered builder ------------------------------------------- */

TEST(layered_builder)
{
	/* 2 inputs, 1 hidden layer of 2, 1 output: weights per node are
	 * bias, then one per previous-layer node. */
	static const double w[] = {0.5,	 1,   -1,  /* hidden 1 */
				   -0.5, 2,   0.5, /* hidden 2 */
				   0.25, 1.5, -2}; /* output */
	evo_q16 in[2] = {q(1), q(0.5)};
	CHECK_EQ_INT(evo_net_layered_weight_count(2, 1, 1, 2), 9);
	CHECK_EQ_INT(evo_net_layered_weight_count(3, 2, 0, 7), 8);
	CHECK_EQ_INT(evo_net_layered_weight_count(4, 2, 2, 4),
		     4 * 5 + 4 * 5 + 2 * 5);
	CHECK_EQ_INT(evo_net_layered_width(3, 5), 5);
	CHECK_EQ_INT(evo_net_layered_width(0, 0), 1);
	CHECK_EQ_INT(evo_net_build_layered(2, 1, 1, 2, EVO_ACT_IDENTITY,
					   EVO_ACT_IDENTITY, w, &desc),
		     EVO_OK);
	CHECK_EQ_INT(desc.n_nodes, 3);
	CHECK_EQ_INT(desc.n_links, 6);
	CHECK_EQ_INT(desc.out_id[0], 2);
	CHECK_EQ_INT(desc.node[0].id, 3);
	CHECK_EQ_INT(desc.node[2].id, 2);
	CHECK_EQ_INT(compile(), EVO_OK);
	/* h1 = 0.5 + 1 - 0.5 = 1; h2 = -0.5 + 2 + 0.25 = 1.75;
	 * out = 0.25 + 1.5 - 3.5 = -1.75 */
	CHECK_EQ_INT(eval1(in), q(-1.75));

	CHECK_EQ_INT(evo_net_weight_q16(1000), 128 * 65536 - 1);
	CHECK_EQ_INT(evo_net_weight_q16(-1000), -(128 * 65536 - 1));
	CHECK_EQ_INT(evo_net_weight_q16(NAN), 0);
	CHECK_EQ_INT(evo_net_weight_q16(-0.75), q(-0.75));

	CHECK_EQ_INT(evo_net_build_layered(2, 1, 1, 2, EVO_ACT_COUNT,
					   EVO_ACT_SIGMOID, w, &desc),
		     EVO_ERR_NAME);
	CHECK_EQ_INT(evo_net_build_layered(2, 1, 3, 200, EVO_ACT_SIGMOID,
					   EVO_ACT_SIGMOID, w, &desc),
		     EVO_ERR_LIMIT);
	CHECK_EQ_INT(evo_net_build_layered(65, 1, 1, 2, EVO_ACT_SIGMOID,
					   EVO_ACT_SIGMOID, w, &desc),
		     EVO_ERR_LIMIT);
}

/* ---- fixed point against the float reference ----------------------- */

static net_float_desc fdesc;
static net_float fnet;
static double weights[EVO_NET_MAX_LINKS + EVO_NET_MAX_NODES];

/* Which activations a random net draws from: sigmoid only (evo's
 * default for layers:N), or every bounded Lipschitz activation. */
typedef enum net_acts { ACTS_SIGMOID, ACTS_SMOOTH } net_acts;

static unsigned random_act(rng *r, net_acts acts)
{
	static const unsigned smooth[] = {EVO_ACT_SIGMOID, EVO_ACT_NEAT_SIGMOID,
					  EVO_ACT_TANH, EVO_ACT_GAUSS,
					  EVO_ACT_CLAMPED};
	if (acts == ACTS_SIGMOID)
		return EVO_ACT_SIGMOID;
	return smooth[rng_int(r, 0, sizeof smooth / sizeof smooth[0] - 1)];
}

/* Layered nets as evo builds them for layers:N: 0 .. 3 hidden layers of
 * 1 .. 16 nodes, 1 .. 16 inputs, 1 .. 8 outputs (fan-in <= 16). */
static void random_layered(rng *r, net_acts acts)
{
	unsigned n_in = (unsigned)rng_int(r, 1, 16);
	unsigned n_out = (unsigned)rng_int(r, 1, 8);
	unsigned layers = (unsigned)rng_int(r, 0, 3);
	unsigned width = (unsigned)rng_int(r, 1, 16);
	unsigned prev = n_in, l, k, s;
	size_t i = 0;

	for (l = 0; l <= layers; l++) {
		unsigned count = l < layers ? width : n_out;
		for (k = 0; k < count; k++) {
			weights[i++] = rng_uniform(r, -4, 4);
			for (s = 0; s < prev; s++)
				weights[i++] = rng_uniform(r, -8, 8);
		}
		prev = count;
	}
	CHECK_EQ_INT(i, evo_net_layered_weight_count(n_in, n_out, layers,
						     width));
	CHECK_EQ_INT(evo_net_build_layered(n_in, n_out, layers, width,
					   random_act(r, acts),
					   random_act(r, acts), weights,
					   &desc),
		     EVO_OK);
	net_float_from_layered(&desc, weights, &fdesc);
}

/* A NEAT-like graph: random ids, listing order and fan-in (1 .. 16),
 * sources anywhere (inputs, earlier or later nodes, the node itself), so
 * cycles and self-loops are common. */
static void random_graph(rng *r, net_acts acts)
{
	int n_in = (int)rng_int(r, 1, 8), n_out = (int)rng_int(r, 1, 4);
	int n_hidden = (int)rng_int(r, 0, 24), n = n_out + n_hidden;
	int k, j;

	fdesc.n_in = n_in;
	fdesc.n_out = n_out;
	fdesc.n_nodes = n;
	fdesc.n_links = 0;
	for (k = 0; k < n; k++) {
		/* Distinct ids above the inputs, in shuffled order. */
		int at = (int)rng_int(r, 0, k);
		fdesc.node_id[k] = fdesc.node_id[at];
		fdesc.node_id[at] = n_in + 3 * k + (int)rng_int(r, 0, 2);
	}
	for (k = 0; k < n; k++) {
		fdesc.node_act[k] = (int)random_act(r, acts);
		fdesc.node_bias[k] = rng_uniform(r, -4, 4);
	}
	for (k = 0; k < n_out; k++)
		fdesc.out_id[k] = fdesc.node_id[rng_int(r, 0, n - 1)];
	for (k = 0; k < n; k++) {
		int fan = (int)rng_int(r, 1, 16);
		for (j = 0; j < fan; j++) {
			int src = (int)rng_int(r, 0, n_in + n - 1);
			int l = fdesc.n_links++;
			fdesc.link_from[l] =
				src < n_in ? src : fdesc.node_id[src - n_in];
			fdesc.link_to[l] = fdesc.node_id[k];
			fdesc.link_weight[l] = rng_uniform(r, -8, 8);
		}
	}
	/* Shuffle the link listing, as NEAT's innovation order would. */
	for (j = fdesc.n_links - 1; j > 0; j--) {
		int o = (int)rng_int(r, 0, j);
		int from = fdesc.link_from[j], to = fdesc.link_to[j];
		double w = fdesc.link_weight[j];
		fdesc.link_from[j] = fdesc.link_from[o];
		fdesc.link_to[j] = fdesc.link_to[o];
		fdesc.link_weight[j] = fdesc.link_weight[o];
		fdesc.link_from[o] = from;
		fdesc.link_to[o] = to;
		fdesc.link_weight[o] = w;
	}
	net_float_quantise(&fdesc, &desc);
}

#define N_RANDOM_NETS 500
#define N_STEPS 8

/* Per-run results: the largest |fixed - float| over all outputs and
 * evaluations, and whether it ever exceeded the propagated bound. */
typedef struct run_result {
	double max_err, max_bound;
	int over_bound;
} run_result;

/* Runs the compiled net and the float reference side by side on the same
 * random inputs in [0, 1]. */
static run_result compare_run(rng *r)
{
	double fin[EVO_MAX_SKILL_IO], fout[EVO_MAX_SKILL_IO];
	double fbound[EVO_MAX_SKILL_IO];
	evo_q16 in[EVO_MAX_SKILL_IO], out[EVO_MAX_SKILL_IO];
	run_result res = {0, 0, 0};
	int t, i;

	CHECK_EQ_INT(compile(), EVO_OK);
	net_float_init(&fnet, &fdesc);
	fnet.act_err[EVO_ACT_SIGMOID] = ACT_MAX_ERR_SIGMOID;
	fnet.act_err[EVO_ACT_NEAT_SIGMOID] = ACT_MAX_ERR_NEAT_SIGMOID;
	fnet.act_err[EVO_ACT_TANH] = ACT_MAX_ERR_TANH;
	fnet.act_err[EVO_ACT_GAUSS] = ACT_MAX_ERR_GAUSS;
	for (t = 0; t < N_STEPS; t++) {
		for (i = 0; i < fdesc.n_in; i++) {
			in[i] = evo_q16_from_double(rng_unit(r));
			fin[i] = evo_q16_to_double(in[i]);
		}
		evo_net_eval(&net, act, in, out);
		net_float_eval(&fnet, fin, fout, fbound);
		for (i = 0; i < fdesc.n_out; i++) {
			double e = fabs(evo_q16_to_double(out[i]) - fout[i]);
			/* 1e-9 absorbs the float reference's own rounding. */
			if (e > fbound[i] + 1e-9)
				res.over_bound = 1;
			if (e > res.max_err)
				res.max_err = e;
			if (fbound[i] > res.max_bound)
				res.max_bound = fbound[i];
		}
	}
	return res;
}

typedef struct family_result {
	double worst;	 /* max |fixed - float| over every output and step */
	int recurrent;	 /* nets with a cycle */
	int over_bound;	 /* nets that left their propagated bound */
} family_result;

static family_result run_family(const char *name, uint64_t seed, int graphs,
				net_acts acts, int count)
{
	family_result f = {0, 0, 0};
	rng r = rng_seed(seed);
	int n;
	for (n = 0; n < count; n++) {
		run_result res;
		if (graphs)
			random_graph(&r, acts);
		else
			random_layered(&r, acts);
		res = compare_run(&r);
		f.recurrent += evo_net_is_recurrent(&net);
		f.over_bound += res.over_bound;
		if (res.max_err > f.worst)
			f.worst = res.max_err;
		if (getenv("NET_DEBUG"))
			printf("net %s %d rec %d err %.4g bound %.4g\n", name, n,
			       evo_net_is_recurrent(&net), res.max_err,
			       res.max_bound);
	}
	printf("  %-22s %4d nets x %d evaluations (%3d recurrent): max |fixed -"
	       " float| = %.3g\n",
	       name, count, N_STEPS, f.recurrent, f.worst);
	return f;
}

/* The stated bound: evo's default topology for layers:N, all sigmoid. */
TEST(sigmoid_layered_nets_within_stated_bound)
{
	family_result f = run_family("sigmoid layered", 1, 0, ACTS_SIGMOID,
				     N_RANDOM_NETS);
	printf("  stated bound for sigmoid layered nets: %.3g\n",
	       NET_MAX_ERR_SIGMOID_LAYERED);
	CHECK(f.worst <= NET_MAX_ERR_SIGMOID_LAYERED);
	CHECK_EQ_INT(f.over_bound, 0);
}

/* Every other family: each net stays within the error bound propagated
 * through it (net_float_eval); no absolute bound holds, since a deep or
 * recurrent net with large weights amplifies any difference. */
TEST(smooth_nets_within_propagated_bound)
{
	family_result f;
	f = run_family("mixed layered", 2, 0, ACTS_SMOOTH, N_RANDOM_NETS);
	CHECK_EQ_INT(f.over_bound, 0);
	f = run_family("sigmoid graphs", 3, 1, ACTS_SIGMOID, N_RANDOM_NETS);
	CHECK_EQ_INT(f.over_bound, 0);
	CHECK(f.recurrent > N_RANDOM_NETS / 2);
	f = run_family("mixed graphs", 4, 1, ACTS_SMOOTH, N_RANDOM_NETS);
	CHECK_EQ_INT(f.over_bound, 0);
	CHECK(f.recurrent > N_RANDOM_NETS / 2);
}

int main(void)
{
	RUN(act_names_follow_the_list);
	RUN(exact_activations);
	RUN(table_activations_match_math_h);
	RUN(table_entries_are_rounded_math_h);
	RUN(activations_are_pinned);
	RUN(single_neuron);
	RUN(xor_2_2_1);
	RUN(self_loop_remembers);
	RUN(two_node_cycle);
	RUN(compile_orders_depth_first);
	RUN(compile_output_may_be_an_input);
	RUN(compile_ignores_stale_scratch);
	RUN(compile_errors);
	RUN(compile_fanin_limit);
	RUN(extreme_sums_saturate);
	RUN(compile_long_chain);
	RUN(layered_builder);
	RUN(sigmoid_layered_nets_within_stated_bound);
	RUN(smooth_nets_within_propagated_bound);
	return test_summary();
}
