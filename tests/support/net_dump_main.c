/* net_dump: evaluates a few hundred deterministic random networks and
 * prints every output as hex Q16, one line per evaluation. The Makefile
 * builds it at -O0 and at -O2 from the same core sources, and
 * tests/core/test_net_opt.c checks that both print the same bytes: the
 * fixed-point networks must not depend on the optimiser.
 *
 * Self-contained on purpose: it links with core/src only, so it builds
 * its networks directly as evo_netdesc with integer weights, and covers
 * what the float comparison cannot: every activation (step, identity and
 * relu included), weights up to the limit, saturating sums, and inputs
 * over the whole Q16 range. */
#include <stdio.h>

#include "evo/net.h"
#include "support/rng.h"

#define N_NETS 300
#define N_STEPS 8

static evo_netdesc desc;
static evo_net_compile_ws ws;
static evo_net_node nodes[EVO_NET_MAX_NODES];
static evo_net_link links[EVO_NET_MAX_LINKS];
static uint16_t outs[EVO_MAX_SKILL_IO];
static evo_q16 act[EVO_MAX_SKILL_IO + EVO_NET_MAX_NODES];

/* A weight or bias: mostly moderate, sometimes near the limit. */
static evo_q16 random_weight(rng *r)
{
	const int64_t lim = EVO_NET_WEIGHT_MAX * (int64_t)EVO_Q16_ONE - 1;
	if (rng_int(r, 0, 7) == 0)
		return (evo_q16)rng_int(r, -lim, lim);
	return (evo_q16)rng_int(r, -8 * EVO_Q16_ONE, 8 * EVO_Q16_ONE);
}

/* A NEAT-like graph: random ids, listing order, fan-in and sources, so
 * cycles, self-loops and unreached nodes all occur. */
static void random_graph(rng *r)
{
	int n_in = (int)rng_int(r, 1, 12), n_out = (int)rng_int(r, 1, 6);
	int n = n_out + (int)rng_int(r, 0, 40), k, j;
	/* One net in three is feed-forward: sources listed before. */
	int feed_forward = rng_int(r, 0, 2) == 0;

	desc.n_in = (uint16_t)n_in;
	desc.n_out = (uint16_t)n_out;
	desc.n_nodes = (uint16_t)n;
	desc.n_links = 0;
	for (k = 0; k < n; k++) {
		int at = (int)rng_int(r, 0, k);
		desc.node[k].id = desc.node[at].id;
		desc.node[at].id = (uint16_t)(n_in + 5 * k + rng_int(r, 0, 4));
	}
	for (k = 0; k < n; k++) {
		desc.node[k].act = (uint8_t)rng_int(r, 0, EVO_ACT_COUNT - 1);
		desc.node[k].bias = random_weight(r);
		desc.node[k].line = 0;
	}
	for (k = 0; k < n_out; k++)
		desc.out_id[k] = desc.node[rng_int(r, 0, n - 1)].id;
	for (k = 0; k < n; k++) {
		int fan = (int)rng_int(r, 0, 24);
		for (j = 0; j < fan; j++) {
			evo_netdesc_link *l = &desc.link[desc.n_links++];
			int src = (int)rng_int(
				r, 0, feed_forward ? n_in + k - 1 : n_in + n - 1);
			l->from = (uint16_t)(src < n_in ? src
						       : desc.node[src - n_in].id);
			l->to = desc.node[k].id;
			l->weight = random_weight(r);
			l->line = 0;
		}
	}
}

/* Inputs: mostly signals in [0, 1], sometimes anywhere in Q16. */
static evo_q16 random_input(rng *r)
{
	if (rng_int(r, 0, 9) == 0)
		return (evo_q16)rng_int(r, INT32_MIN, INT32_MAX);
	return (evo_q16)rng_int(r, 0, EVO_Q16_ONE);
}

int main(void)
{
	rng r = rng_seed(0x6e65745f64756d70u);
	int n, t, i;

	for (n = 0; n < N_NETS; n++) {
		evo_net net;
		evo_status st;
		random_graph(&r);
		st = evo_net_compile(&desc, &ws, nodes, links, outs, &net);
		if (st != EVO_OK) {
			printf("net %d: compile failed: %s\n", n,
			       evo_status_str(st));
			return 1;
		}
		for (i = 0; i < net.n_nodes; i++)
			act[i] = 0;
		for (t = 0; t < N_STEPS; t++) {
			evo_q16 in[EVO_MAX_SKILL_IO], out[EVO_MAX_SKILL_IO];
			for (i = 0; i < net.n_in; i++)
				in[i] = random_input(&r);
			evo_net_eval(&net, act, in, out);
			printf("%d %d %d", n, t, evo_net_is_recurrent(&net));
			for (i = 0; i < net.n_out; i++)
				printf(" %08x", (unsigned)out[i]);
			printf("\n");
		}
	}
	/* The activation functions alone, over a sweep of arguments. */
	for (i = 0; i < EVO_ACT_COUNT; i++) {
		int64_t x;
		printf("act %s", evo_act_name((unsigned)i));
		for (x = -20 * EVO_Q16_ONE; x <= 20 * EVO_Q16_ONE; x += 4099)
			printf(" %x", (unsigned)evo_act_apply((unsigned)i,
							      (evo_q16)x));
		printf("\n");
	}
	return 0;
}
