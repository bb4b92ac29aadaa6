/* evo — fixed-point network evaluation and activation functions.
 *
 * This file is part of the MIND runtime that a Cortex-M0+ carries, so it
 * stays small: two compact tables, one interpolation routine, integer
 * arithmetic only. docs/fixed-point.md documents the format, the tables
 * and their measured error. */
#include <stddef.h>
#include <stdint.h>

#include "evo/net.h"

/* Rounding (fixed.h) and the sign handling below rely on >> of a negative
 * value being arithmetic, which GCC and Clang guarantee but C11 does not. */
_Static_assert((-1 >> 1) == -1, "arithmetic right shift required");
_Static_assert(((int64_t)-1 >> 1) == -1, "arithmetic right shift required");

/* The sum cannot overflow: |weight| < 2^23 (Q16 of 128), |act| <= 2^31,
 * so a product is below 2^54; 256 of them stay below 2^62, and the bias
 * (below 2^39 in Q32) plus the rounding half-ulp keep it under 2^63. */
_Static_assert(EVO_NET_MAX_FANIN <= 256 && EVO_NET_WEIGHT_MAX <= 128,
	       "the 64-bit node sum is sized for these limits");

/* sigmoid(i / 16) - 1/2 in Q16 for i = 0 .. 127, rounded to nearest. The
 * last entry is the asymptote 1/2 instead of sigmoid(8) - 1/2, so the
 * function meets its saturation value continuously at x = 8. Negative
 * arguments use sigmoid(-x) = 1 - sigmoid(x), and tanh is built from the
 * same table, which is why it holds an offset from 1/2. */
static const uint16_t sigmoid_tab[129] = {
	0, 1024, 2045, 3063, 4075, 5079, 6073, 7056, 8025, 8980, 9919, 10840,
	11743, 12625, 13486, 14326, 15143, 15936, 16706, 17452, 18173, 18870,
	19542, 20189, 20813, 21411, 21986, 22538, 23066, 23571, 24054, 24516,
	24956, 25376, 25776, 26157, 26519, 26864, 27191, 27502, 27797, 28076,
	28341, 28592, 28830, 29055, 29268, 29470, 29660, 29840, 30010, 30170,
	30322, 30465, 30600, 30727, 30847, 30960, 31067, 31167, 31262, 31351,
	31435, 31515, 31589, 31659, 31726, 31788, 31846, 31901, 31953, 32002,
	32048, 32091, 32132, 32170, 32206, 32240, 32271, 32301, 32329, 32356,
	32381, 32404, 32426, 32447, 32466, 32484, 32501, 32517, 32532, 32547,
	32560, 32573, 32584, 32596, 32606, 32616, 32625, 32634, 32642, 32649,
	32657, 32663, 32670, 32676, 32681, 32686, 32691, 32696, 32700, 32704,
	32708, 32712, 32715, 32718, 32721, 32724, 32727, 32729, 32732, 32734,
	32736, 32738, 32740, 32741, 32743, 32745, 32768,
};

/* 1 - e^(-(i / 32)^2) in Q16 for i = 0 .. 109, rounded to nearest. Stored
 * as the complement so that gauss(0) = 1 (65536) fits in 16 bits. Beyond
 * 109/32 the function is below one ulp and gauss gives 0. */
static const uint16_t gauss_tab[110] = {
	0, 64, 256, 573, 1016, 1581, 2264, 3062, 3971, 4984, 6097, 7304, 8597,
	9971, 11417, 12928, 14497, 16115, 17776, 19471, 21192, 22933, 24685,
	26441, 28195, 29939, 31669, 33377, 35059, 36709, 38323, 39897, 41427,
	42909, 44343, 45724, 47051, 48323, 49538, 50697, 51799, 52844, 53832,
	54764, 55642, 56465, 57237, 57957, 58629, 59253, 59832, 60368, 60862,
	61318, 61736, 62120, 62471, 62791, 63083, 63348, 63588, 63805, 64001,
	64177, 64336, 64478, 64605, 64718, 64819, 64909, 64989, 65059, 65121,
	65176, 65224, 65266, 65303, 65336, 65364, 65388, 65409, 65428, 65444,
	65458, 65469, 65479, 65488, 65496, 65502, 65507, 65512, 65516, 65519,
	65522, 65524, 65526, 65528, 65529, 65530, 65531, 65532, 65533, 65533,
	65534, 65534, 65535, 65535, 65535, 65535, 65535,
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

/* Linear interpolation in an increasing table at u (Q16, u >> shift must
 * be a valid index with a successor). Differences are non-negative, so
 * the arithmetic stays unsigned; the rounding matches fixed.h. */
static uint32_t table_lerp(const uint16_t *tab, uint32_t u, unsigned shift)
{
	uint32_t i = u >> shift;
	uint32_t frac = u & ((1u << shift) - 1);
	uint32_t rise = (uint32_t)(tab[i + 1] - tab[i]);
	return tab[i] + ((rise * frac + (1u << (shift - 1))) >> shift);
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
	return (int32_t)table_lerp(sigmoid_tab, u, SIGMOID_SHIFT);
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
	return (evo_q16)(EVO_Q16_ONE - (int32_t)table_lerp(gauss_tab, u, GAUSS_SHIFT));
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
