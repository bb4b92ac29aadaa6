/* evo — compiling a network description into evaluation order.
 *
 * Runs on the host (learning workers compile every candidate), never on
 * the robot. The depth-first search is iterative with an explicit stack in
 * the caller's scratch, so a long chain of nodes cannot overflow a worker
 * thread's stack.
 *
 * The scratch needs no initialisation. index_of_id is a sparse map: an
 * entry is trusted only when it points back at a listed node with that id,
 * so stale or uninitialised entries are harmless and the 128 KB array is
 * never cleared as a whole. The entries a compile sets are reset to 0
 * before it returns, so a ws that starts zeroed stays zeroed. */
#include <stddef.h>
#include <stdint.h>

#include "evo/net.h"

#define NO_LINK 0xFFFFu

enum { UNSEEN = 0, ON_STACK = 1, DONE = 2 };

/* Listing index of the non-input node with this id, or -1. */
static int32_t listed(const evo_netdesc *d, const evo_net_compile_ws *ws,
		      uint32_t n_registered, uint16_t id)
{
	uint32_t v = ws->index_of_id[id];
	if (v == 0 || v > n_registered || d->node[v - 1].id != id)
		return -1;
	return (int32_t)v - 1;
}

static int weight_ok(evo_q16 w)
{
	const int32_t lim = EVO_NET_WEIGHT_MAX * EVO_Q16_ONE;
	return w > -lim && w < lim;
}

/* Checks everything the order and the evaluation rely on; registers the
 * node ids in index_of_id (listing index + 1) as it goes, counting them in
 * *n_registered so the caller can clear exactly those. */
static evo_status validate(const evo_netdesc *d, evo_net_compile_ws *ws,
			   uint32_t *n_registered, evo_net_node *nodes)
{
	uint32_t k, j;

	if (d->n_in > EVO_MAX_SKILL_IO || d->n_out > EVO_MAX_SKILL_IO ||
	    d->n_nodes > EVO_NET_MAX_NODES || d->n_links > EVO_NET_MAX_LINKS)
		return EVO_ERR_LIMIT;
	for (k = 0; k < d->n_nodes; k++) {
		const evo_netdesc_node *n = &d->node[k];
		/* An id below n_in is an input; a repeated id is ambiguous. */
		if (n->id < d->n_in || n->act >= EVO_ACT_COUNT ||
		    listed(d, ws, k, n->id) >= 0)
			return EVO_ERR_NAME;
		if (!weight_ok(n->bias))
			return EVO_ERR_LIMIT;
		ws->index_of_id[n->id] = (uint16_t)(k + 1);
		*n_registered = k + 1;
		nodes[k].link_count = 0;
	}
	for (k = 0; k < d->n_out; k++)
		if (d->out_id[k] >= d->n_in &&
		    listed(d, ws, d->n_nodes, d->out_id[k]) < 0)
			return EVO_ERR_NAME;
	for (j = 0; j < d->n_links; j++) {
		const evo_netdesc_link *l = &d->link[j];
		int32_t to = listed(d, ws, d->n_nodes, l->to);
		/* A link into an input has no node to feed: `to` is never an
		 * input id, since inputs are not listed. */
		if (to < 0 ||
		    (l->from >= d->n_in && listed(d, ws, d->n_nodes, l->from) < 0))
			return EVO_ERR_NAME;
		if (!weight_ok(l->weight))
			return EVO_ERR_LIMIT;
		if (++nodes[to].link_count > EVO_NET_MAX_FANIN)
			return EVO_ERR_LIMIT;
	}
	return EVO_OK;
}

/* Depth-first post-order from each output, then the nodes no output
 * reaches. Fills ws->order with listing indices. Until the final layout is
 * written, nodes[k].link_start holds the first link into listed node k and
 * links[j].pad the next link into the same node, both in listing order:
 * the caller's output arrays double as the adjacency lists. */
static void order_nodes(const evo_netdesc *d, evo_net_compile_ws *ws,
			evo_net_node *nodes, evo_net_link *links)
{
	uint32_t k, j, n_order = 0;

	for (k = 0; k < d->n_nodes; k++) {
		nodes[k].link_start = NO_LINK;
		ws->mark[k] = UNSEEN;
	}
	/* Prepending in reverse listing order leaves each list in order. */
	for (j = d->n_links; j-- > 0;) {
		int32_t to = listed(d, ws, d->n_nodes, d->link[j].to);
		links[j].pad = nodes[to].link_start;
		nodes[to].link_start = (uint16_t)j;
	}

	for (k = 0; k < d->n_out; k++) {
		int32_t root = listed(d, ws, d->n_nodes, d->out_id[k]);
		uint32_t sp = 0;
		if (root < 0 || ws->mark[root] != UNSEEN)
			continue; /* an input, or already placed */
		ws->mark[root] = ON_STACK;
		ws->stack[0] = (uint16_t)root;
		ws->edge_pos[0] = nodes[root].link_start;
		sp = 1;
		while (sp > 0) {
			uint32_t top = sp - 1;
			uint32_t link = ws->edge_pos[top];
			int32_t src;
			if (link == NO_LINK) {
				ws->order[n_order++] = ws->stack[top];
				ws->mark[ws->stack[top]] = DONE;
				sp--;
				continue;
			}
			ws->edge_pos[top] = links[link].pad;
			src = listed(d, ws, d->n_nodes, d->link[link].from);
			/* A source on the stack closes a cycle: that link
			 * will read the previous evaluation. */
			if (src < 0 || ws->mark[src] != UNSEEN)
				continue;
			ws->mark[src] = ON_STACK;
			ws->stack[sp] = (uint16_t)src;
			ws->edge_pos[sp] = nodes[src].link_start;
			sp++;
		}
	}
	for (k = 0; k < d->n_nodes; k++)
		if (ws->mark[k] == UNSEEN)
			ws->order[n_order++] = (uint16_t)k;
}

/* Node index (inputs first, then evaluation order) of an id, once
 * index_of_id has been rewritten to hold node index + 1. */
static uint16_t node_index(const evo_netdesc *d, const evo_net_compile_ws *ws,
			   uint16_t id)
{
	return id < d->n_in ? id : (uint16_t)(ws->index_of_id[id] - 1);
}

evo_status evo_net_compile(const evo_netdesc *d, evo_net_compile_ws *ws,
			   evo_net_node *nodes, evo_net_link *links,
			   uint16_t *out, evo_net *net)
{
	uint32_t n_registered = 0, p, j, start;
	evo_status st = validate(d, ws, &n_registered, nodes);

	if (st != EVO_OK)
		goto done;
	order_nodes(d, ws, nodes, links);

	/* From here on index_of_id maps an id to its node index + 1. */
	for (p = 0; p < d->n_nodes; p++) {
		const evo_netdesc_node *n = &d->node[ws->order[p]];
		ws->index_of_id[n->id] = (uint16_t)(d->n_in + p + 1);
		nodes[p].bias = n->bias;
		nodes[p].act = n->act;
		nodes[p].pad[0] = nodes[p].pad[1] = nodes[p].pad[2] = 0;
		nodes[p].link_count = 0;
	}
	for (j = 0; j < d->n_links; j++)
		nodes[node_index(d, ws, d->link[j].to) - d->n_in].link_count++;
	/* Group links by destination; a stable placement keeps the listing
	 * order within each destination. edge_pos is the placement cursor. */
	for (p = 0, start = 0; p < d->n_nodes; p++) {
		nodes[p].link_start = (uint16_t)start;
		ws->edge_pos[p] = (uint16_t)start;
		start += nodes[p].link_count;
	}
	for (j = 0; j < d->n_links; j++) {
		const evo_netdesc_link *l = &d->link[j];
		uint32_t q = ws->edge_pos[node_index(d, ws, l->to) - d->n_in]++;
		links[q].weight = l->weight;
		links[q].src = node_index(d, ws, l->from);
		links[q].pad = 0;
	}
	for (p = 0; p < d->n_out; p++)
		out[p] = node_index(d, ws, d->out_id[p]);

	net->n_in = d->n_in;
	net->n_out = d->n_out;
	net->n_nodes = (uint16_t)(d->n_in + d->n_nodes);
	net->n_links = d->n_links;
	net->nodes = nodes;
	net->links = links;
	net->out = out;
done:
	for (p = 0; p < n_registered; p++)
		ws->index_of_id[d->node[p].id] = 0;
	return st;
}
