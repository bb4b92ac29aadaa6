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

/* sin(k * pi / 128) in Q16 for k = 0..63; k = 64 is 1.0 (65536). */
static const uint16_t sin_quarter[64] = {
	0,     1608,  3216,  4821,  6424,  8022,  9616,  11204, 12785, 14359,
	15924, 17479, 19024, 20557, 22078, 23586, 25080, 26558, 28020, 29466,
	30893, 32303, 33692, 35062, 36410, 37736, 39040, 40320, 41576, 42806,
	44011, 45190, 46341, 47464, 48559, 49624, 50660, 51665, 52639, 53581,
	54491, 55368, 56212, 57022, 57798, 58538, 59244, 59914, 60547, 61145,
	61705, 62228, 62714, 63162, 63572, 63944, 64277, 64571, 64827, 65043,
	65220, 65358, 65457, 65516,
};

static int32_t quarter(unsigned i)
{
	return i >= 64 ? 65536 : sin_quarter[i];
}

evo_q16 var_sin01(uint32_t phase)
{
	unsigned quadrant = phase >> 30;
	uint32_t p = phase & 0x3FFFFFFFu;
	if (quadrant & 1u)
		p = 0x40000000u - p; /* falling half of each lobe: mirror */
	unsigned i = p >> 24;
	int32_t frac = (int32_t)((p >> 8) & 0xFFFFu);
	int32_t s = quarter(i);
	if (frac)
		s += (int32_t)(((quarter(i + 1) - s) * frac + 32768) >> 16);
	if (quadrant & 2u)
		s = -s;
	return (s + EVO_Q16_ONE + 1) >> 1;
}

uint32_t var_sin_step(evo_q16 w)
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

void var_reset(unsigned type, evo_var_state *v)
{
	v->value = 0;
	v->a = 0;
	v->b = 0;
	if (type == EVO_VAR_SINWAVE) {
		v->b = (int32_t)VAR_RADIAN_TURNS;
		v->value = var_sin01(0);
	} else if (type == EVO_VAR_COUNTER) {
		v->b = EVO_Q16_HALF;
	}
	v->prev = v->value;
}

void var_update(unsigned type, evo_var_state *v, int written, evo_q16 w)
{
	v->prev = v->value;
	switch (type) {
	case EVO_VAR_SINWAVE:
		if (written)
			v->b = (int32_t)var_sin_step(w);
		v->a = (int32_t)((uint32_t)v->a + (uint32_t)v->b);
		v->value = var_sin01((uint32_t)v->a);
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
