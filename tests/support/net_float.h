/* The floating-point reference for evo's fixed-point networks.
 *
 * Evaluates a network given with double weights and biases, using real
 * math (<math.h>) for the activations, in the same order and with the
 * same in-place semantics as evo_net_eval: nodes ordered depth-first from
 * each output, sources in link listing order, unreached nodes last; a
 * link from a node not yet computed reads its previous value. The order
 * is computed here independently (recursively; test networks are small),
 * so the comparison also checks evo_net_compile's order. Used to bound
 * the quantisation error of the fixed-point networks. */
#ifndef EVO_TEST_NET_FLOAT_H
#define EVO_TEST_NET_FLOAT_H

#include "evo/formats.h"
#include "evo/net.h"

/* Mirrors evo_netdesc, with doubles for weights and biases. */
typedef struct net_float_desc {
	int n_in, n_out, n_nodes, n_links;
	int out_id[EVO_MAX_SKILL_IO];
	int node_id[EVO_NET_MAX_NODES];
	int node_act[EVO_NET_MAX_NODES];
	double node_bias[EVO_NET_MAX_NODES];
	int link_from[EVO_NET_MAX_LINKS], link_to[EVO_NET_MAX_LINKS];
	double link_weight[EVO_NET_MAX_LINKS];
} net_float_desc;

/* A network ready to evaluate, with its memory. Values are kept per
 * slot: input i in slot i, listed node k in slot n_in + k. */
typedef struct net_float {
	const net_float_desc *d;
	int order[EVO_NET_MAX_NODES]; /* listing index, evaluation order */
	double act[EVO_MAX_SKILL_IO + EVO_NET_MAX_NODES];
	double sum[EVO_NET_MAX_NODES]; /* pre-activation, per listed node */
	/* Per slot, a bound on |fixed-point activation - act| (see
	 * net_float_eval); inputs are exact. */
	double bound[EVO_MAX_SKILL_IO + EVO_NET_MAX_NODES];
	double act_err[EVO_ACT_COUNT]; /* table error per activation */
	int link_slot[EVO_NET_MAX_LINKS];  /* slot of each link's source */
	int out_slot[EVO_MAX_SKILL_IO];
} net_float;

/* Activation act at x in double precision (the definitions in fixed.h). */
double net_float_act(unsigned act, double x);

/* Order d's nodes and zero the memory; d must stay alive. Ids are assumed
 * valid (the same description compiles with evo_net_compile). The
 * activation errors act_err start at 0; set them before evaluating. */
void net_float_init(net_float *f, const net_float_desc *d);

/* The Lipschitz constant of activation act (max |f'|), or a negative
 * value when it has none (step). */
double net_float_lipschitz(unsigned act);

/* One evaluation: in has n_in values, out receives n_out.
 *
 * Alongside, it propagates a bound on the error of a fixed-point network
 * built from the same description (weights and biases rounded to Q16) fed
 * the same inputs: for node i with activation f,
 *     |s' - s| <= 2^-17 (bias) + 2^-17 (rounding the sum)
 *                + sum_j (|w_j| + 2^-17) E_j + 2^-17 |a_j|
 *     E_i      <= min(span of f, act_err[f] + L_f |s' - s|)
 * where s, s' are the float and fixed sums, E_j the bounds of the
 * sources (current or previous evaluation, as the values themselves) and
 * act_err[f] the largest |table - f| at Q16 arguments. Valid while the
 * fixed sums stay inside the Q16 range; meaningless with step nodes.
 * bound_out, if not NULL, receives the output bounds. */
void net_float_eval(net_float *f, const double *in, double *out,
		    double *bound_out);

/* The fixed-point description of d: weights and biases through
 * evo_net_weight_q16. */
void net_float_quantise(const net_float_desc *d, evo_netdesc *out);

/* d for a layered network built by evo_net_build_layered from nd (its
 * topology) and the same weights (the documented weight order). */
void net_float_from_layered(const evo_netdesc *nd, const double *weights,
			    net_float_desc *d);

#endif
