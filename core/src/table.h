/* Private: increasing tables, interpolated linearly, stored compactly.
 *
 * A table t, sampled at equal steps, is stored as its second differences,
 * which are small where the first ones are not: for each 16th entry c a
 * checkpoint holds t[c] and its rise t[c+1] - t[c] (cp, two uint16 each),
 * and dd[j] = (t[j+2] - t[j+1]) - (t[j+1] - t[j]) - 1 for every j (int8;
 * the -1 brings gauss's largest, 128, into range). A lookup walks at most
 * 15 steps from its checkpoint. The runtime's tables (sigmoid and gauss in
 * net.c, the quarter sine in variables.c) take about 60% of the bytes of
 * plain uint16 arrays this way, which the 4 KB flash budget of a
 * Cortex-M0+ needs; the values, and so every result, are the same. */
#ifndef EVO_TABLE_H
#define EVO_TABLE_H

#include <stdint.h>

/* t[i] + rise[i] * frac / 2^shift, rounded as fixed.h rounds (half up),
 * where i = u >> shift and frac = u's low shift bits. Every rise must be
 * non-negative, and rise[i] stored: i below 16 * (checkpoints - 1) + the
 * dd entries that follow the last checkpoint, plus one. */
uint32_t evo_table_lerp(const uint16_t *cp, const int8_t *dd, uint32_t u,
			unsigned shift);

#endif
