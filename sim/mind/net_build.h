/* evo — building fixed-point network descriptions from floating-point
 * genomes (host side).
 *
 * Learning algorithms keep their genomes as doubles; these helpers turn a
 * genome into an evo_netdesc, which evo_net_compile then turns into the
 * network that is evaluated. docs/fixed-point.md describes the rounding
 * and the layered topology. */
#ifndef EVO_NET_BUILD_H
#define EVO_NET_BUILD_H

#include "evo/formats.h"
#include "evo/net.h"

/* A weight or bias as Q16: rounded to nearest (evo_q16_from_double) and
 * clamped into the open range (-EVO_NET_WEIGHT_MAX, EVO_NET_WEIGHT_MAX)
 * that evo_net_compile accepts. NaN gives 0. */
evo_q16 evo_net_weight_q16(double w);

/* The hidden-layer width evo uses for a skill's `layers:N`:
 * max(n_in, n_out), at least 1. */
unsigned evo_net_layered_width(unsigned n_in, unsigned n_out);

/* Number of doubles evo_net_build_layered reads. */
size_t evo_net_layered_weight_count(unsigned n_in, unsigned n_out,
				    unsigned layers, unsigned width);

/* A fully connected layered network: `layers` hidden layers of `width`
 * nodes (layers = 0 connects the inputs straight to the outputs), every
 * node fed by every node of the previous layer plus a bias.
 *
 * Ids: inputs 0 .. n_in-1, outputs n_in .. n_in+n_out-1, hidden nodes
 * from n_in+n_out on, layer by layer. Nodes are listed hidden layer 1,
 * ..., hidden layer `layers`, then the outputs; out_id[k] is output k.
 *
 * weights holds evo_net_layered_weight_count() doubles, node by node in
 * that listing order; for each node: its bias, then the weights of its
 * links from the previous layer's nodes in order (inputs 0 .. n_in-1 for
 * the first layer). Each is converted with evo_net_weight_q16.
 *
 * evo's default for a neural skill with `layers:N` is N hidden layers of
 * evo_net_layered_width(n_in, n_out), sigmoid in hidden and output nodes
 * (signals are in [0, 1]).
 *
 * Fails with EVO_ERR_LIMIT when the network would exceed the limits of
 * formats.h (nodes, links, fan-in, EVO_MAX_SKILL_IO inputs or outputs),
 * EVO_ERR_NAME for an unknown activation; out is then unspecified. */
evo_status evo_net_build_layered(unsigned n_in, unsigned n_out,
				 unsigned layers, unsigned width,
				 unsigned hidden_act, unsigned out_act,
				 const double *weights, evo_netdesc *out);

#endif
