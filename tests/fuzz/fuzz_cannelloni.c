/* libFuzzer target for evo's reading of cannelloni datagrams
 * (sim/remote/can_format.c), which evo runs on every UDP datagram a peer
 * sends. Besides crashes and sanitizer reports it checks the decoder's
 * promises: every frame taken is a classic frame with an 11-bit id, and
 * an accepted datagram of evo's frames only encodes back to its bytes. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "remote/can.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static evo_can_frame out[256];
static uint8_t again[70000];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	unsigned long bad[EVO_CAN_BAD_COUNT] = {0};
	int n = -1;
	int r = evo_cannelloni_decode(data, size, out, 256, &n, bad);
	if (n < 0 || n > 256)
		abort();
	for (int i = 0; i < n; i++)
		if (out[i].id > 0x7FF || out[i].len > 8)
			abort();
	unsigned long dropped = 0;
	for (int k = 0; k < EVO_CAN_BAD_COUNT; k++)
		dropped += bad[k];
	if (r != 0 && dropped == 0)
		abort(); /* a refusal is always counted */
	if (r == 0 && dropped == 0 && size >= 5) {
		size_t len = evo_cannelloni_encode(out, n, data[2], again,
						   sizeof again);
		if (len != size || memcmp(again, data, size) != 0)
			abort();
	}
	return 0;
}
