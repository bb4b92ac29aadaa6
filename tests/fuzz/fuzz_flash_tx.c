/* libFuzzer target for the host's side of `evo flash` (core/src/flash.c):
 * the sender, fed replies by whoever is on the bus. The input is
 *
 *   flags (u8), then records of 10 bytes: action (u8), DLC (u8), 8 bytes
 *
 * flags bit 0: the sender has a key; bit 1: it was given a counter. Each
 * record either lets the sender send what it has (action bit 0 clear:
 * frames to nowhere), lets its wait time out (action 1 mod 4), or hands
 * it a frame: a REPLY or a TAG (bit 2) with the record's bytes, where
 * action bit 3 puts the reply's `next` right for what was sent so far,
 * so that the fuzzer reaches the later stages.
 *
 * Besides crashes and sanitizer reports it checks the sender's promises:
 * it never counts more segments acknowledged than it sent, nor sends
 * beyond the image or its window; it reaches DONE only after sending END
 * for an image every segment of which was acknowledged; with a key it
 * never reaches DONE at all (no robot with the key is on this bus, and
 * the fuzzer cannot make the robot's tag). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/flash.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const uint8_t key[16] = "fuzz's 16B key.";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	/* a stand-in image: the sender reads only its bytes and header */
	static _Alignas(8) uint8_t img[700];
	for (size_t i = 0; i < sizeof img; i++)
		img[i] = (uint8_t)(i * 7u);
	if (size < 1)
		return 0;
	uint8_t flags = data[0];
	data++;
	size--;
	evo_flash_tx t;
	evo_flash_tx_init(&t, img, sizeof img, 8);
	if (flags & 1u)
		evo_flash_tx_key(&t, key, sizeof key);
	if (flags & 2u)
		evo_flash_tx_counter(&t, flags >> 2, (flags & 0x80u) != 0);
	int end_sent = 0;
	for (; size >= 10; data += 10, size -= 10) {
		uint8_t action = data[0];
		evo_can_frame f;
		if (!(action & 1u)) {
			while (evo_flash_tx_next(&t, &f)) {
				if (f.id == EVO_FLASH_END)
					end_sent = 1;
				if (f.id == EVO_FLASH_DATA &&
				    (t.next > t.total ||
				     t.next > t.acked + t.window))
					abort();
				if (f.len > 8)
					abort();
			}
			continue;
		}
		if ((action & 3u) == 1u) {
			evo_flash_tx_timeout(&t);
			continue;
		}
		f.id = (action & 4u) ? EVO_FLASH_TAG : EVO_FLASH_REPLY;
		f.len = (uint8_t)(data[1] % 9u);
		memcpy(f.data, data + 2, 8);
		if ((action & 8u) && f.len == 8) {
			uint32_t next = (action & 16u) ? t.sent : t.total;
			evo_wire_put_u16(f.data + 2, (uint16_t)next);
		}
		evo_flash_tx_reply(&t, &f);
		if (t.acked > t.sent || t.acked > t.total || t.next > t.total ||
		    t.window < 1 || t.window > EVO_FLASH_WINDOW_MAX)
			abort();
		if (t.readies > t.begins)
			abort();
		if (t.stage == EVO_FLASH_TX_FINISHED &&
		    t.kind == EVO_FLASH_DONE &&
		    ((flags & 1u) || !end_sent || t.acked != t.total))
			abort();
	}
	return 0;
}
