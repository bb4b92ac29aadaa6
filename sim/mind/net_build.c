#include "mind/net_build.h"

#include <math.h>

evo_q16 evo_net_weight_q16(double w)
{
	/* Largest magnitude below the exclusive limit, one ulp inside it. */
	const evo_q16 lim = EVO_NET_WEIGHT_MAX * EVO_Q16_ONE - 1;
	evo_q16 q;

	if (isnan(w))
		return 0;
	q = evo_q16_from_double(w);
	return q > lim ? lim : q < -lim ? -lim : q;
}

unsigned evo_net_layered_width(unsigned n_in, unsigned n_out)
{
	unsigned w = n_in > n_out ? n_in : n_out;
	return w > 0 ? w : 1;
}

size_t evo_net_layered_weight_count(unsigned n_in, unsigned n_out,
				    unsigned layers, unsigned width)
{
	size_t prev = n_in, count = 0;
	unsigned l;

	for (l = 0; l < layers; l++) {
		count += (size_t)width * (prev + 1);
		prev = width;
	}
	return count + (size_t)n_out * (prev + 1);
}

evo_status evo_net_build_layered(unsigned n_in, unsigned n_out,
				 unsigned layers, unsigned width,
				 unsigned hidden_act, unsigned out_act,
				 const double *weights, evo_netdesc *out)
{
	size_t n_hidden = (size_t)layers * width;
	unsigned prev_first = 0, prev_count = n_in, l, k, s;
	const double *w = weights;

	if (hidden_act >= EVO_ACT_COUNT || out_act >= EVO_ACT_COUNT)
		return EVO_ERR_NAME;
	if (n_in > EVO_MAX_SKILL_IO || n_out > EVO_MAX_SKILL_IO ||
	    (layers > 0 && width == 0) || n_hidden + n_out > EVO_NET_MAX_NODES ||
	    (layers > 0 ? width : n_in) > EVO_NET_MAX_FANIN ||
	    n_in > EVO_NET_MAX_FANIN ||
	    evo_net_layered_weight_count(n_in, n_out, layers, width) -
			    (n_hidden + n_out) >
		    EVO_NET_MAX_LINKS)
		return EVO_ERR_LIMIT;

	out->n_in = (uint16_t)n_in;
	out->n_out = (uint16_t)n_out;
	out->n_nodes = 0;
	out->n_links = 0;
	/* Layer `layers` is the output layer; its ids come first. */
	for (l = 0; l <= layers; l++) {
		unsigned count = l < layers ? width : n_out;
		unsigned first = l < layers ? n_in + n_out + l * width : n_in;
		unsigned act = l < layers ? hidden_act : out_act;
		for (k = 0; k < count; k++) {
			evo_netdesc_node *n = &out->node[out->n_nodes++];
			n->id = (uint16_t)(first + k);
			n->act = (uint8_t)act;
			n->bias = evo_net_weight_q16(*w++);
			n->line = 0;
			for (s = 0; s < prev_count; s++) {
				evo_netdesc_link *lk = &out->link[out->n_links++];
				lk->from = (uint16_t)(prev_first + s);
				lk->to = n->id;
				lk->weight = evo_net_weight_q16(*w++);
				lk->line = 0;
			}
		}
		prev_first = first;
		prev_count = count;
	}
	for (k = 0; k < n_out; k++)
		out->out_id[k] = (uint16_t)(n_in + k);
	return EVO_OK;
}
