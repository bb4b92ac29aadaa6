/* evo — fixed-point neural networks.
 *
 * A compiled network is a list of nodes in evaluation order: nodes
 * 0 .. n_in-1 are the inputs, the rest are computed in index order, each
 * as act(bias + sum of weight * activation[src]) over its incoming links.
 * Evaluation is in place over one activation array, so a link from a node
 * that comes later in the order (or from the node itself) reads the value
 * that node had at the previous evaluation: that is what makes a network
 * recurrent. A feed-forward network (every src < dst) has no memory.
 *
 * Products are exact (Q32) and summed in 64 bits; the sum is rounded to
 * Q16 once per node and saturated. Weights and biases are limited to
 * |w| < EVO_NET_WEIGHT_MAX and fan-in to EVO_NET_MAX_FANIN, which keeps
 * the 64-bit sum from overflowing. */
#ifndef EVO_NET_H
#define EVO_NET_H

#include <stddef.h>
#include <stdint.h>

#include "evo/fixed.h"
#include "evo/formats.h"

/* One non-input node; node i (i >= n_in) is nodes[i - n_in]. */
typedef struct evo_net_node {
	evo_q16 bias;
	uint16_t link_start; /* first incoming link in links[] */
	uint16_t link_count;
	uint8_t act; /* evo_act */
	uint8_t pad[3];
} evo_net_node;

typedef struct evo_net_link {
	evo_q16 weight;
	uint16_t src; /* node index, 0 .. n_nodes-1 */
	uint16_t pad;
} evo_net_link;

/* A compiled network: a view over memory the caller owns (a mind image,
 * or arrays filled by evo_net_compile). */
typedef struct evo_net {
	uint16_t n_in, n_out;
	uint16_t n_nodes; /* inputs included */
	uint16_t n_links;
	const evo_net_node *nodes; /* n_nodes - n_in */
	const evo_net_link *links; /* n_links, grouped by destination */
	const uint16_t *out;	   /* n_out node indices */
} evo_net;

/* Evaluate once. act holds n_nodes activations and is the network's
 * memory (zero it to reset); in gives n_in values; out receives n_out
 * values, each the activation of its output node. in and out may not
 * overlap act. */
void evo_net_eval(const evo_net *net, evo_q16 *act, const evo_q16 *in,
		  evo_q16 *out);

/* 1 when some link reads a node at or after its destination. */
int evo_net_is_recurrent(const evo_net *net);

/* Scratch for evo_net_compile; large, so the caller provides it. */
typedef struct evo_net_compile_ws {
	uint16_t order[EVO_NET_MAX_NODES];
	uint16_t index_of_id[65536]; /* id -> node index + 1, 0 = none */
	uint16_t stack[EVO_NET_MAX_NODES];
	uint16_t edge_pos[EVO_NET_MAX_NODES];
	uint8_t mark[EVO_NET_MAX_NODES];
} evo_net_compile_ws;

/* Compile a parsed network into evaluation order:
 *   - nodes are ordered depth-first from each output in turn, visiting the
 *     sources of a node's links in the order the links were listed, so a
 *     node comes after everything it reads except along a cycle;
 *   - nodes no output depends on come last, in listing order.
 * nodes must hold d->n_nodes entries, links d->n_links, out d->n_out.
 * On success fills *net to view those arrays; on failure those arrays hold
 * garbage. Fails with EVO_ERR_LIMIT for a fan-in above EVO_NET_MAX_FANIN,
 * more than EVO_MAX_SKILL_IO inputs, or a weight or bias of 128 or more;
 * EVO_ERR_NAME for an output or link naming an id that is not a node, a
 * link into an input, a node reusing an input's or another node's id, or
 * an unknown activation. ws needs no initialisation. */
evo_status evo_net_compile(const evo_netdesc *d, evo_net_compile_ws *ws,
			   evo_net_node *nodes, evo_net_link *links,
			   uint16_t *out, evo_net *net);

#endif
