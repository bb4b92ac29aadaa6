#include "net_float.h"

#include <math.h>

#include "mind/net_build.h"

double net_float_act(unsigned act, double x)
{
	switch (act) {
	case EVO_ACT_IDENTITY:
		return x;
	case EVO_ACT_SIGMOID:
		return 1.0 / (1.0 + exp(-x));
	case EVO_ACT_NEAT_SIGMOID:
		return 1.0 / (1.0 + exp(-4.9 * x));
	case EVO_ACT_TANH:
		return tanh(x);
	case EVO_ACT_RELU:
		return x > 0 ? x : 0;
	case EVO_ACT_STEP:
		return x > 0 ? 1 : 0;
	case EVO_ACT_CLAMPED:
		return x < 0 ? 0 : x > 1 ? 1 : x;
	case EVO_ACT_GAUSS:
		return exp(-x * x);
	default:
		return 0;
	}
}

double net_float_lipschitz(unsigned act)
{
	switch (act) {
	case EVO_ACT_SIGMOID:
		return 0.25;
	case EVO_ACT_NEAT_SIGMOID:
		return 4.9 * 0.25;
	case EVO_ACT_GAUSS:
		return sqrt(2.0 / exp(1.0)); /* |f'| peaks at x = 1/sqrt(2) */
	case EVO_ACT_STEP:
		return -1;
	default:
		return 1;
	}
}

/* max f - min f, or HUGE_VAL for unbounded activations. */
static double span(unsigned act)
{
	switch (act) {
	case EVO_ACT_IDENTITY:
	case EVO_ACT_RELU:
		return HUGE_VAL;
	case EVO_ACT_TANH:
		return 2;
	default:
		return 1;
	}
}

static int listing_of(const net_float_desc *d, int id)
{
	int k;
	for (k = 0; k < d->n_nodes; k++)
		if (d->node_id[k] == id)
			return k;
	return -1; /* an input */
}

static int slot_of(const net_float_desc *d, int id)
{
	int k = listing_of(d, id);
	return k < 0 ? id : d->n_in + k;
}

static void visit(net_float *f, char *mark, int *n, int k)
{
	const net_float_desc *d = f->d;
	int j;

	mark[k] = 1;
	for (j = 0; j < d->n_links; j++) {
		int src;
		if (d->link_to[j] != d->node_id[k])
			continue;
		src = listing_of(d, d->link_from[j]);
		if (src >= 0 && !mark[src])
			visit(f, mark, n, src);
	}
	f->order[(*n)++] = k;
}

void net_float_init(net_float *f, const net_float_desc *d)
{
	char mark[EVO_NET_MAX_NODES] = {0};
	int k, n = 0;

	f->d = d;
	for (k = 0; k < d->n_out; k++) {
		int root = listing_of(d, d->out_id[k]);
		if (root >= 0 && !mark[root])
			visit(f, mark, &n, root);
	}
	for (k = 0; k < d->n_nodes; k++)
		if (!mark[k])
			f->order[n++] = k;
	for (k = 0; k < d->n_in + d->n_nodes; k++)
		f->act[k] = f->bound[k] = 0;
	for (k = 0; k < EVO_ACT_COUNT; k++)
		f->act_err[k] = 0;
	for (k = 0; k < d->n_links; k++)
		f->link_slot[k] = slot_of(d, d->link_from[k]);
	for (k = 0; k < d->n_out; k++)
		f->out_slot[k] = slot_of(d, d->out_id[k]);
}

void net_float_eval(net_float *f, const double *in, double *out,
		    double *bound_out)
{
	const double half_ulp = 1.0 / 131072;
	const net_float_desc *d = f->d;
	int p, j;

	for (j = 0; j < d->n_in; j++)
		f->act[j] = in[j];
	for (p = 0; p < d->n_nodes; p++) {
		int k = f->order[p];
		unsigned a = (unsigned)d->node_act[k];
		double sum = d->node_bias[k], dsum = 2 * half_ulp, e;
		for (j = 0; j < d->n_links; j++) {
			int src = f->link_slot[j];
			double w = d->link_weight[j];
			if (d->link_to[j] != d->node_id[k])
				continue;
			sum += w * f->act[src];
			dsum += (fabs(w) + half_ulp) * f->bound[src] +
				half_ulp * fabs(f->act[src]);
		}
		f->sum[k] = sum;
		f->act[d->n_in + k] = net_float_act(a, sum);
		e = f->act_err[a] + net_float_lipschitz(a) * dsum;
		f->bound[d->n_in + k] = e < span(a) ? e : span(a);
	}
	for (j = 0; j < d->n_out; j++) {
		out[j] = f->act[f->out_slot[j]];
		if (bound_out)
			bound_out[j] = f->bound[f->out_slot[j]];
	}
}

void net_float_quantise(const net_float_desc *d, evo_netdesc *out)
{
	int k;

	out->n_in = (uint16_t)d->n_in;
	out->n_out = (uint16_t)d->n_out;
	out->n_nodes = (uint16_t)d->n_nodes;
	out->n_links = (uint16_t)d->n_links;
	for (k = 0; k < d->n_out; k++)
		out->out_id[k] = (uint16_t)d->out_id[k];
	for (k = 0; k < d->n_nodes; k++) {
		out->node[k].id = (uint16_t)d->node_id[k];
		out->node[k].act = (uint8_t)d->node_act[k];
		out->node[k].bias = evo_net_weight_q16(d->node_bias[k]);
		out->node[k].line = 0;
	}
	for (k = 0; k < d->n_links; k++) {
		out->link[k].from = (uint16_t)d->link_from[k];
		out->link[k].to = (uint16_t)d->link_to[k];
		out->link[k].weight = evo_net_weight_q16(d->link_weight[k]);
		out->link[k].line = 0;
	}
}

void net_float_from_layered(const evo_netdesc *nd, const double *weights,
			    net_float_desc *d)
{
	int k, j = 0;

	d->n_in = nd->n_in;
	d->n_out = nd->n_out;
	d->n_nodes = nd->n_nodes;
	d->n_links = nd->n_links;
	for (k = 0; k < nd->n_out; k++)
		d->out_id[k] = nd->out_id[k];
	/* Per node: the bias, then its links, which the builder lists
	 * node by node. */
	for (k = 0; k < nd->n_nodes; k++) {
		d->node_id[k] = nd->node[k].id;
		d->node_act[k] = nd->node[k].act;
		d->node_bias[k] = *weights++;
		for (; j < nd->n_links && nd->link[j].to == nd->node[k].id; j++) {
			d->link_from[j] = nd->link[j].from;
			d->link_to[j] = nd->link[j].to;
			d->link_weight[j] = *weights++;
		}
	}
}
