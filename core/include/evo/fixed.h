/* evo — fixed-point numbers.
 *
 * Every signal, weight, bias and activation in the core is an evo_q16:
 * a signed 32-bit integer holding value * 65536 (Q15.16). Range
 * [-32768, 32768 - 2^-16], resolution 2^-16 (about 1.5e-5).
 *
 * Rounding: results are rounded to the nearest representable value, ties
 * towards +infinity (add half an ulp, then shift right arithmetically).
 * Saturation: results outside the range are clamped to EVO_Q16_MIN or
 * EVO_Q16_MAX, never wrapped.
 *
 * docs/fixed-point.md is the reference for the format. */
#ifndef EVO_FIXED_H
#define EVO_FIXED_H

#include <stdint.h>

typedef int32_t evo_q16;

#define EVO_Q16_ONE ((evo_q16)65536)
#define EVO_Q16_HALF ((evo_q16)32768)
#define EVO_Q16_MAX ((evo_q16)INT32_MAX)
#define EVO_Q16_MIN ((evo_q16)INT32_MIN)

/* Boolean sensor conventions: 0.2 for false, 0.8 for true. */
#define EVO_Q16_FALSE ((evo_q16)13107) /* round(0.2 * 65536) */
#define EVO_Q16_TRUE ((evo_q16)52429)  /* round(0.8 * 65536) */

/* Clamp a 64-bit intermediate into the Q16 range. */
static inline evo_q16 evo_q16_sat(int64_t v)
{
	if (v > INT32_MAX)
		return EVO_Q16_MAX;
	if (v < INT32_MIN)
		return EVO_Q16_MIN;
	return (evo_q16)v;
}

/* Round a Q32 (value * 2^32) intermediate to Q16, saturating. */
static inline evo_q16 evo_q32_to_q16(int64_t v)
{
	/* v + 2^15 cannot overflow for the sums the core forms (see net.c). */
	return evo_q16_sat((v + 32768) >> 16);
}

/* a * b, rounded and saturated. */
static inline evo_q16 evo_q16_mul(evo_q16 a, evo_q16 b)
{
	return evo_q32_to_q16((int64_t)a * b);
}

/* n / d for d > 0, truncated: exactly what C's 64-bit division gives, but
 * by shift and subtract on 32-bit words. A Cortex-M0+ has no divide
 * instruction, and the C operator would link libgcc's general 64-bit
 * division (__udivmoddi4, about 0.5 KB, a tenth of the runtime's flash
 * budget). Schoolbook long division in base 2^32: each word of n is
 * divided with the remainder of the word above it; the remainder stays
 * below d, so it fits 32 bits once the bit shifted out of it (carry) is
 * accounted for. The weighted means of the tick have a quotient below
 * 2^17, so their high word is skipped and the loop runs 32 times. */
static inline uint64_t evo_u64_div_u32_soft(uint64_t n, uint32_t d)
{
	uint32_t w[2] = {(uint32_t)(n >> 32), (uint32_t)n};
	uint32_t r = 0;
	int k = 0;
	if (w[0] < d) { /* the high word of the quotient is 0 */
		r = w[0];
		w[0] = 0;
		k = 1;
	}
	for (; k < 2; k++) {
		uint32_t q = w[k];
		for (int i = 0; i < 32; i++) {
			uint32_t carry = r >> 31;
			r = (r << 1) | (q >> 31);
			q <<= 1;
			if (carry || r >= d) {
				r -= d; /* mod 2^32: the true value is < d */
				q |= 1;
			}
		}
		w[k] = q;
	}
	return (uint64_t)w[0] << 32 | w[1];
}

/* n / d for d > 0, truncated. A 64-bit host divides in one instruction,
 * a few dozen times faster than the loop above (which every host tick
 * ran, a twentieth of a robot's tick in make bench); the quotient is the
 * same to the bit, as tests/core/test_fixed.c checks. The firmware's
 * Cortex-M cores take the loop. */
static inline uint64_t evo_u64_div_u32(uint64_t n, uint32_t d)
{
#if defined(__x86_64__) || defined(__aarch64__)
	return n / d;
#else
	return evo_u64_div_u32_soft(n, d);
#endif
}

/* Clamp to the signal range [0, 1]. */
static inline evo_q16 evo_q16_clamp01(evo_q16 v)
{
	return v < 0 ? 0 : v > EVO_Q16_ONE ? EVO_Q16_ONE : v;
}

#ifndef EVO_FREESTANDING
/* Host-side conversions; never called on the firmware's tick path. The
 * double is rounded to the nearest Q16 (ties away from zero) and saturated;
 * NaN, which no integer holds, becomes 0. */
static inline evo_q16 evo_q16_from_double(double d)
{
	double s = d * 65536.0;
	if (s != s) /* NaN */
		return 0;
	if (s >= 2147483647.0)
		return EVO_Q16_MAX;
	if (s <= -2147483648.0)
		return EVO_Q16_MIN;
	return (evo_q16)(s < 0 ? s - 0.5 : s + 0.5);
}

/* A sensor value as Q16, by the one rule for sensor values from any
 * source (docs/mind.md, "Sensor values"): clamped to [0, 1], so -inf
 * reads 0 and +inf 1; NaN reads 0.5, the neutral value, which is also
 * what `evo tick` gives a sensor it is not told about. Every double that
 * becomes a sensor's Q16 on the host goes through here. */
static inline evo_q16 evo_q16_from_sensor(double v)
{
	if (v != v) /* NaN */
		return EVO_Q16_HALF;
	if (v <= 0)
		return 0;
	if (v >= 1)
		return EVO_Q16_ONE;
	return evo_q16_from_double(v);
}

static inline double evo_q16_to_double(evo_q16 q)
{
	return (double)q / 65536.0;
}
#endif

/* Activation functions of network nodes. The numbering is part of the mind
 * image format: append, never reorder. */
#define EVO_ACT_LIST(X)                                                        \
	X(EVO_ACT_IDENTITY, "identity")   /* f(x) = x                     */   \
	X(EVO_ACT_SIGMOID, "sigmoid")     /* 1 / (1 + e^-x)               */   \
	X(EVO_ACT_NEAT_SIGMOID, "neat_sigmoid") /* 1 / (1 + e^-4.9x)      */   \
	X(EVO_ACT_TANH, "tanh")           /* tanh(x)                      */   \
	X(EVO_ACT_RELU, "relu")           /* max(0, x)                    */   \
	X(EVO_ACT_STEP, "step")           /* x > 0 ? 1 : 0                */   \
	X(EVO_ACT_CLAMPED, "clamped")     /* min(1, max(0, x))            */   \
	X(EVO_ACT_GAUSS, "gauss")         /* e^(-x^2)                     */

typedef enum evo_act {
#define EVO_ACT_ENUM(code, name) code,
	EVO_ACT_LIST(EVO_ACT_ENUM)
#undef EVO_ACT_ENUM
		EVO_ACT_COUNT
} evo_act;

/* The name of an activation as written in .net files, or NULL. */
const char *evo_act_name(unsigned act);

/* f(x) for activation act; an unknown act gives 0. */
evo_q16 evo_act_apply(unsigned act, evo_q16 x);

#endif
