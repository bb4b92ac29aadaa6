/* The three variable types of the tutorial, deterministic in fixed point.
 *
 * VariableModule            a holds nothing; value is the last written
 *                           value, 0.0 until written.
 * TickWaveSinVariableModule a = phase in 2^-32 turns, b = step per tick.
 *                           Reads (sin(phase) + 1) / 2; the phase starts
 *                           at 0 and advances one radian a tick, so
 *                           unwritten it reads (sin t + 1) / 2 at tick t.
 *                           A written value w sets the step, linearly from
 *                           1/1000 rad (w = 0) to 3 rad (w = 1); it keeps
 *                           the last step set while nobody writes.
 * CounterVariableModule     a = count 0..10, b = the last written level.
 *                           Reads count / 10. A rising edge (last level
 *                           <= 0.8, new level > 0.8) counts up, past 10
 *                           back to 0; a falling edge (last >= 0.2, new
 *                           < 0.2) resets to 0. The level starts at 0.5. */
#include "variables.h"

#include "evo/formats.h"
#include "table.h"

/* sin(k * pi / 128) in Q16 for k = 0 .. 64, rounded to nearest, stored as
 * table.h describes (79 bytes instead of 128). */
static const uint16_t sin_cp[8] = {
	0, 1608, 25080, 1478, 46341, 1123, 60547, 598,
};
static const int8_t sin_dd[63] = {
	-1,  -4,  -3,  -6,  -5,  -7,  -8,  -8,  -10, -11, -11, -13, -13,
	-14, -15, -17, -17, -17, -20, -18, -22, -20, -23, -23, -23, -25,
	-25, -27, -26, -27, -29, -29, -29, -31, -30, -32, -32, -33, -33,
	-34, -34, -35, -35, -37, -35, -37, -38, -36, -39, -38, -38, -39,
	-39, -39, -40, -40, -39, -41, -40, -40, -40, -41, -40,
};

evo_q16 evo_var_sin01(uint32_t phase)
{
	unsigned quadrant = phase >> 30;
	uint32_t p = phase & 0x3FFFFFFFu;
	if (quadrant & 1u)
		p = 0x40000000u - p; /* falling half of each lobe: mirror */
	/* A quarter turn in 2^30 steps: table index in the top 6 bits,
	 * interpolated over the next 16; p = 2^30 is the peak, 1. */
	int32_t s = p >> 30
			? EVO_Q16_ONE
			: (int32_t)evo_table_lerp(sin_cp, sin_dd, p >> 8, 16);
	if (quadrant & 2u)
		s = -s;
	return (s + EVO_Q16_ONE + 1) >> 1;
}

uint32_t evo_var_sin_step(evo_q16 w)
{
	/* 2^32 * 0.001 / (2 pi) and 2^32 * 2.999 / (2 pi), rounded. */
	const uint32_t lo = 683565u, span = 2050012262u;
	uint64_t x = (uint64_t)(uint32_t)evo_q16_clamp01(w) * span;
	return lo + (uint32_t)((x + 32768u) >> 16);
}

/* count / 10 in Q16 rounded to nearest, for count 0 .. 10: 104857 / 16 is
 * 6553.5625, close enough to 6553.6 that every one of the eleven comes out
 * as round(count * 65536 / 10) (test_variables checks all of them). */
static evo_q16 counter_value(int32_t count)
{
	return (count * 104857 + 10) >> 4;
}

#define LEVEL_HIGH 52429 /* 0.8 */
#define LEVEL_LOW 13107	 /* 0.2 */

void evo_var_reset(unsigned type, evo_var_state *v)
{
	v->value = 0;
	v->a = 0;
	v->b = 0;
	if (type == EVO_VAR_SINWAVE) {
		v->b = (int32_t)EVO_VAR_RADIAN_TURNS;
		v->value = evo_var_sin01(0);
	} else if (type == EVO_VAR_COUNTER) {
		v->b = EVO_Q16_HALF;
	}
	v->prev = v->value;
}

void evo_var_update(unsigned type, evo_var_state *v, int written, evo_q16 w)
{
	v->prev = v->value;
	switch (type) {
	case EVO_VAR_SINWAVE:
		if (written)
			v->b = (int32_t)evo_var_sin_step(w);
		v->a = (int32_t)((uint32_t)v->a + (uint32_t)v->b);
		v->value = evo_var_sin01((uint32_t)v->a);
		break;
	case EVO_VAR_COUNTER:
		if (written) {
			if (v->b <= LEVEL_HIGH && w > LEVEL_HIGH)
				v->a = v->a >= 10 ? 0 : v->a + 1;
			else if (v->b >= LEVEL_LOW && w < LEVEL_LOW)
				v->a = 0;
			v->b = w;
		}
		v->value = counter_value(v->a);
		break;
	default:
		if (written)
			v->value = w;
		break;
	}
}
