/* Fuzz target: evo_mind_open, evo_state_init and evo_mind_step on
 * arbitrary bytes. The target repairs the length and CRC fields first, so
 * the fuzzer reaches the layout checks behind them; any image they accept
 * must then run without reading or writing out of bounds. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/evo.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static _Alignas(8) uint8_t image[1 << 16];
	static _Alignas(8) uint8_t state[1 << 20];
	if (size > sizeof image)
		return 0;
	memcpy(image, data, size);
	size_t len = size & ~(size_t)3;
	uint32_t hash = 0;
	if (len >= sizeof(evo_image_header)) {
		evo_image_header *h = (evo_image_header *)image;
		h->length = (uint32_t)len;
		h->crc = evo_crc32(0, image + 16, len - 16);
		hash = h->names_hash;
	}
	evo_mind m;
	if (evo_mind_open(image, len, hash, &m) != EVO_OK)
		return 0;
	evo_state *s;
	if (evo_state_size(&m) > sizeof state ||
	    evo_state_init(&m, state, sizeof state, &s) != EVO_OK)
		return 0;
	evo_q16 sensors[EVO_MAX_SENSORS], actuators[EVO_MAX_ACTUATORS];
	for (unsigned i = 0; i < EVO_MAX_SENSORS; i++)
		sensors[i] = (evo_q16)(i * 3001u % 65537u);
	for (int t = 0; t < 4; t++)
		evo_mind_step(&m, s, sensors, actuators);
	return 0;
}
