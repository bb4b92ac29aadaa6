#include "table.h"

uint32_t evo_table_lerp(const uint16_t *cp, const int8_t *dd, uint32_t u,
			unsigned shift)
{
	uint32_t i = u >> shift;
	uint32_t frac = u & ((1u << shift) - 1);
	uint32_t j = i & ~15u;
	int32_t t = cp[j / 8], rise = cp[j / 8 + 1];
	for (; j < i; j++) {
		t += rise;
		rise += dd[j] + 1;
	}
	return (uint32_t)t +
	       (((uint32_t)rise * frac + (1u << (shift - 1))) >> shift);
}
