/* evo — fixed-point network evaluation and activation functions.
 *
 * This file is part of the MIND runtime that a Cortex-M0+ carries, so it
 * stays small: two compact tables, one interpolation routine, integer
 * arithmetic only. docs/fixed-point.md documents the format, the tables
 * and their measured error. */
#include <stddef.h>
#include <stdint.h>

#include "evo/net.h"
#include "table.h"

/* Rounding (fixed.h) and the sign handling below rely on >> of a negative
 * value being arithmetic, which GCC and Clang guarantee but C11 does not. */
_Static_assert((-1 >> 1) == -1, "arithmetic right shift required");
_Static_assert(((int64_t)-1 >> 1) == -1, "arithmetic right shift required");

/* The sum cannot overflow: |weight| < 2^23 (Q16 of 128), |act| <= 2^31,
 * so a product is below 2^54; 256 of them stay below 2^62, and the bias
 * (below 2^39 in Q32) plus the rounding half-ulp keep it under 2^63. */
_Static_assert(EVO_NET_MAX_FANIN <= 256 && EVO_NET_WEIGHT_MAX <= 128,
	       "the 64-bit node sum is sized for these limits");

/* Two increasing tables, sampled at equal steps and interpolated linearly:
 *
 *   sigmoid  sigmoid(i / 16) - 1/2 in Q16 for i = 0 .. 128, rounded to
 *            nearest. The last entry is the asymptote 1/2 instead of
 *            sigmoid(8) - 1/2, so the function meets its saturation value
 *            continuously at x = 8. Negative arguments use sigmoid(-x) =
 *            1 - sigmoid(x), and tanh is built from the same table, which is
 *            why it holds an offset from 1/2.
 *   gauss    1 - e^(-(i / 32)^2) in Q16 for i = 0 .. 109, rounded to
 *            nearest; the complement, so that gauss(0) = 1 (65536) needs no
 *            17th bit. Beyond 109/32 the function is below one ulp and gauss
 *            gives 0.
 *
 * Both are stored as table.h describes: 160 + 136 bytes instead of 258 +
 * 220, for the runtime must fit 4 KB of a Cortex-M0+'s flash. The entries,
 * and so every result, are exactly those of the full tables (test_net
 * pins them). */
static const uint16_t sigmoid_cp[16] = {
	0, 1024, 15143, 793, 24956, 420, 29660, 180, 31589, 70, 32329, 27,
	32606, 10, 32708, 4,
};
static const int8_t sigmoid_dd[127] = {
	-4, -4, -7, -9, -11, -12, -15, -15, -17, -19, -19, -22, -22, -22, -24,
	-25, -24, -25, -26, -25, -26, -26, -24, -27, -24, -24, -25, -24, -23,
	-22, -23, -21, -21, -20, -20, -18, -19, -17, -17, -17, -15, -15, -14,
	-14, -13, -12, -13, -11, -11, -11, -9, -10, -9, -9, -8, -8, -7, -8,
	-6, -7, -6, -5, -7, -5, -4, -6, -5, -4, -4, -4, -4, -4, -3, -4, -3,
	-3, -4, -2, -3, -2, -3, -3, -2, -2, -3, -2, -2, -2, -2, -1, -3, -1,
	-3, 0, -3, -1, -2, -1, -2, -2, 0, -3, 0, -2, -2, -1, -1, -1, -2, -1,
	-1, -1, -2, -1, -1, -1, -1, -2, 0, -2, -1, -1, -1, -2, 0, -1, 20,
};
static const uint16_t gauss_cp[14] = {
	0, 64, 14497, 1618, 41427, 1482, 58629, 624, 64336, 142, 65409, 19,
	65528, 1,
};
static const int8_t gauss_dd[108] = {
	127, 124, 125, 121, 117, 114, 110, 103, 99, 93, 85, 80, 71, 64, 57,
	48, 42, 33, 25, 19, 10, 3, -3, -11, -15, -23, -27, -33, -37, -41, -45,
	-49, -49, -54, -55, -56, -58, -57, -58, -58, -58, -57, -55, -56, -52,
	-53, -49, -49, -46, -44, -43, -39, -39, -35, -34, -32, -29, -28, -26,
	-24, -22, -21, -18, -18, -16, -15, -13, -12, -11, -11, -9, -8, -8, -7,
	-6, -5, -6, -5, -4, -3, -4, -3, -4, -2, -2, -2, -3, -2, -1, -2, -2,
	-1, -2, -1, -1, -2, -1, -1, -1, -1, -2, 0, -2, 0, -2, -1, -1, -1,
};

#define SIGMOID_SHIFT 12 /* table step 1/16 in Q16 */
#define SIGMOID_END (8u << 16)
#define GAUSS_SHIFT 11 /* table step 1/32 */
#define GAUSS_END (109u << GAUSS_SHIFT)

/* 4.9 in Q16 (321126.4, rounded): the slope NEAT uses for its sigmoid. */
#define NEAT_SLOPE_Q16 321126

static const char *const act_names[] = {
#define EVO_ACT_NAME(code, name) name,
	EVO_ACT_LIST(EVO_ACT_NAME)
#undef EVO_ACT_NAME
};

const char *evo_act_name(unsigned act)
{
	return act < EVO_ACT_COUNT ? act_names[act] : NULL;
}

/* |x| without overflow at INT32_MIN. */
static uint32_t magnitude(evo_q16 x)
{
	return x < 0 ? 0u - (uint32_t)x : (uint32_t)x;
}

/* sigmoid(u) - 1/2 for u >= 0, in Q16, in [0, 32768]. */
static int32_t sigmoid_offset(uint32_t u)
{
	if (u >= SIGMOID_END)
		return EVO_Q16_HALF;
	return (int32_t)evo_table_lerp(sigmoid_cp, sigmoid_dd, u,
				       SIGMOID_SHIFT);
}

/* sigmoid(x), given u = |x| or a scaled |x|: built from |x| so that
 * sigmoid(-x) = 1 - sigmoid(x) holds exactly. */
static evo_q16 sigmoid_signed(evo_q16 x, uint32_t u)
{
	int32_t off = sigmoid_offset(u);
	return x < 0 ? EVO_Q16_HALF - off : EVO_Q16_HALF + off;
}

/* sigmoid(4.9 x): the scaled magnitude is rounded to nearest (ties away
 * from zero, which keeps the symmetry) and clamped where the table ends. */
static evo_q16 neat_sigmoid(evo_q16 x)
{
	uint64_t s = ((uint64_t)magnitude(x) * NEAT_SLOPE_Q16 + 32768) >> 16;
	return sigmoid_signed(x, s < SIGMOID_END ? (uint32_t)s : SIGMOID_END);
}

/* tanh(x) = 2 sigmoid(2x) - 1 = 2 (sigmoid(2x) - 1/2): odd by
 * construction, and it saturates where 2x leaves the table. */
static evo_q16 tanh_q16(evo_q16 x)
{
	uint32_t u = magnitude(x);
	int32_t r = 2 * sigmoid_offset(u < SIGMOID_END / 2 ? 2 * u : SIGMOID_END);
	return x < 0 ? -r : r;
}

static evo_q16 gauss(evo_q16 x)
{
	uint32_t u = magnitude(x);
	if (u >= GAUSS_END)
		return 0;
	return (evo_q16)(EVO_Q16_ONE - (int32_t)evo_table_lerp(
					   gauss_cp, gauss_dd, u, GAUSS_SHIFT));
}

evo_q16 evo_act_apply(unsigned act, evo_q16 x)
{
	switch (act) {
	case EVO_ACT_IDENTITY:
		return x;
	case EVO_ACT_SIGMOID:
		return sigmoid_signed(x, magnitude(x));
	case EVO_ACT_NEAT_SIGMOID:
		return neat_sigmoid(x);
	case EVO_ACT_TANH:
		return tanh_q16(x);
	case EVO_ACT_RELU:
		return x > 0 ? x : 0;
	case EVO_ACT_STEP:
		return x > 0 ? EVO_Q16_ONE : 0;
	case EVO_ACT_CLAMPED:
		return evo_q16_clamp01(x);
	case EVO_ACT_GAUSS:
		return gauss(x);
	default:
		return 0;
	}
}

void evo_net_eval(const evo_net *net, evo_q16 *act, const evo_q16 *in,
		  evo_q16 *out)
{
	const evo_net_node *node = net->nodes;
	uint32_t i;

	for (i = 0; i < net->n_in; i++)
		act[i] = in[i];
	for (; i < net->n_nodes; i++, node++) {
		const evo_net_link *l = net->links + node->link_start;
		const evo_net_link *end = l + node->link_count;
		/* Products are exact in Q32; the sum is rounded once. */
		int64_t sum = (int64_t)node->bias * EVO_Q16_ONE;
		for (; l < end; l++)
			sum += (int64_t)l->weight * act[l->src];
		act[i] = evo_act_apply(node->act, evo_q32_to_q16(sum));
	}
	for (i = 0; i < net->n_out; i++)
		out[i] = act[net->out[i]];
}

int evo_net_is_recurrent(const evo_net *net)
{
	uint32_t i;

	for (i = net->n_in; i < net->n_nodes; i++) {
		const evo_net_node *node = &net->nodes[i - net->n_in];
		uint32_t k;
		for (k = 0; k < node->link_count; k++)
			if (net->links[node->link_start + k].src >= i)
				return 1;
	}
	return 0;
}
