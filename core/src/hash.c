#include "evo/image.h"

/* Bitwise CRC-32: no 1 KB table, which matters more on a 4 KB runtime
 * budget than speed does (an image is checked once, at open). */
uint32_t evo_crc32(uint32_t crc, const void *data, size_t len)
{
	const uint8_t *p = data;
	crc = ~crc;
	while (len--) {
		crc ^= *p++;
		for (int k = 0; k < 8; k++)
			crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
	}
	return ~crc;
}

static uint32_t fnv_bytes(uint32_t h, const char *s, int with_nul)
{
	while (*s) {
		h ^= (uint8_t)*s++;
		h *= 16777619u;
	}
	if (with_nul)
		h *= 16777619u; /* h ^= 0 is a no-op */
	return h;
}

uint32_t evo_name_hash(const char *s)
{
	return fnv_bytes(2166136261u, s, 0);
}

static uint32_t fnv_list(uint32_t h, const char *const *names, unsigned n)
{
	for (unsigned i = 0; i < n; i++)
		h = fnv_bytes(h, names[i], 1);
	h ^= 0x1Eu;
	return h * 16777619u;
}

uint32_t evo_names_hash(const char *const *sensors, unsigned n_sensors,
			const char *const *actuators, unsigned n_actuators,
			const char *const *vars, unsigned n_vars)
{
	uint32_t h = 2166136261u;
	h = fnv_list(h, sensors, n_sensors);
	h = fnv_list(h, actuators, n_actuators);
	return fnv_list(h, vars, n_vars);
}
