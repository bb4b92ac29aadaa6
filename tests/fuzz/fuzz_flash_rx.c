/* libFuzzer target for the robot's side of `evo flash` (core/src/flash.c):
 * the receiver the firmware runs on every frame of a transfer. The input
 * is a window byte, a schedule and an image:
 *
 *   window (u8), n (u8), n schedule bytes, then the image sent
 *
 * The host's sender sends the image (the robot takes the names hash in the
 * image's header as its own) while the schedule decides the fate of each
 * frame to the robot: delivered, lost, a bit flipped, or delivered twice.
 * With the window's top bit set, the schedule and image are instead raw
 * frames (id selector, DLC, 8 bytes) thrown at a receiver mid-transfer.
 * With bit 6 set, robot and sender share a key (the window is then bits
 * 0-5): transfers carry their tags, and in the raw mode the receiver
 * must never switch, since no frame the fuzzer makes carries a tag made
 * with the key. The first schedule byte is the robot's counter.
 *
 * Besides crashes and sanitizer reports it checks the receiver's promises:
 * it writes only whole words inside its slot; every reply is a well-formed
 * REPLY; it switches only to an image that evo_mind_open takes with a
 * state that fits, and, when at most one frame was damaged, only to the
 * very image sent, with a counter above the robot's, written after it;
 * the exchange always ends. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/flash.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define SLOT	  8192
#define STATE_MAX 4096

static _Alignas(8) uint8_t slot[SLOT];
static evo_flash_rx rx;
static evo_flash_tx tx;
static uint32_t names;
static unsigned switches;

static int slot_write(void *ctx, uint32_t offset, const uint8_t word[4])
{
	(void)ctx;
	if (offset % 4u || offset + 4u > SLOT)
		abort();
	memcpy(slot + offset, word, 4);
	return 0;
}

static const uint8_t key[32] = "the fuzz target's key, 32 bytes";
static int keyed;

/* The replies of one call: a REPLY, and with a key its tag after READY
 * and DONE only. */
static void check_replies(const evo_can_frame *r)
{
	if (rx.replies < 1 || rx.replies > EVO_FLASH_RX_REPLIES)
		abort();
	if (r[0].id != EVO_FLASH_REPLY || r[0].len != 8 ||
	    r[0].data[0] > EVO_FLASH_REFUSED)
		abort();
	if (r[0].data[0] == EVO_FLASH_REFUSED &&
	    r[0].data[1] >= EVO_FLASH_REASON_COUNT)
		abort();
	int tagged = keyed && (r[0].data[0] == EVO_FLASH_READY ||
			       r[0].data[0] == EVO_FLASH_DONE);
	if (rx.replies != 1u + (unsigned)tagged)
		abort();
	if (tagged && (r[1].id != EVO_FLASH_TAG || r[1].len != 8))
		abort();
}

/* What the receiver answered to one frame, checked: the frames to pass
 * on (0 .. EVO_FLASH_RX_REPLIES). */
static unsigned deliver(const evo_can_frame *f, uint32_t now, evo_can_frame *r)
{
	uint32_t before = rx.counter;
	switch (evo_flash_rx_frame(&rx, f, now, r)) {
	case EVO_FLASH_RX_NONE:
		return 0;
	case EVO_FLASH_RX_REPLY:
		check_replies(r);
		return rx.replies;
	case EVO_FLASH_RX_SWITCH: {
		evo_mind m;
		if (evo_mind_open(slot, rx.mind.length, names, &m) != EVO_OK ||
		    evo_state_size(&m) > STATE_MAX || rx.mind.base != slot)
			abort();
		/* fresh, and kept after the image */
		if (rx.counter > EVO_FLASH_COUNTER_MAX ||
		    (!rx.force && rx.counter <= before) ||
		    evo_flash_rx_counter_at(slot, SLOT, rx.mind.length) !=
			rx.counter)
			abort();
		switches++;
		evo_flash_rx_switched(&rx, 7, r);
		check_replies(r);
		return rx.replies;
	}
	default:
		abort();
	}
}

static void raw_frames(const uint8_t *d, size_t n)
{
	static const uint16_t ids[] = {EVO_FLASH_BEGIN, EVO_FLASH_DATA,
				       EVO_FLASH_END,	EVO_FLASH_REPLY,
				       EVO_FLASH_AUTH,	EVO_FLASH_TAG,
				       EVO_WIRE_CONFIG, EVO_FLASH_DATA};
	uint32_t now = 0;
	evo_can_frame f, r[EVO_FLASH_RX_REPLIES];
	for (; n >= 10; d += 10, n -= 10) {
		f.id = ids[d[0] & 7u];
		f.len = (uint8_t)(d[1] % 9u);
		memcpy(f.data, d + 2, 8);
		now += d[0] >> 3;
		if (f.id == EVO_WIRE_CONFIG) {
			/* with a key, no CONFIG the fuzzer makes is taken */
			uint32_t ms;
			if (evo_flash_config_check(&rx, &f, &ms) &&
			    (keyed || f.len != 2 ||
			     ms != evo_wire_get_u16(f.data)))
				abort();
			continue;
		}
		deliver(&f, now, r);
		if (evo_flash_rx_poll(&rx, now, r) == EVO_FLASH_RX_REPLY)
			check_replies(r);
	}
	if (keyed && switches)
		abort(); /* a transfer switched without the key */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 2)
		return 0;
	unsigned window = data[0];
	size_t n_sched = data[1];
	if (size < 2 + n_sched)
		return 0;
	const uint8_t *sched = data + 2;
	const uint8_t *image = sched + n_sched;
	size_t len = size - 2 - n_sched;
	/* an image as evo_mind_open needs it: 4-byte aligned */
	static _Alignas(8) uint8_t img[EVO_FLASH_LENGTH_MAX / 4];
	if (len > sizeof img)
		len = sizeof img;
	len &= ~(size_t)3;
	memcpy(img, image, len);
	names = len >= 20 ? evo_wire_get_u32(img + 16) : 0;
	memset(slot, 0xFF, sizeof slot);
	switches = 0;
	keyed = (window & 0x40u) != 0;
	evo_flash_rx_def def = {names,		STATE_MAX, 1000, 32, slot_write,
				NULL,		keyed ? key : NULL,
				keyed ? (uint32_t)sizeof key : 0u};
	evo_flash_rx_init(&rx, &def);
	evo_flash_rx_target(&rx, slot, SLOT);
	rx.counter = n_sched ? sched[0] : 0;
	if (window & 0x80u) {
		raw_frames(sched, size - 2);
		return 0;
	}
	evo_flash_tx_init(&tx, img, (uint32_t)len, window & 0x3Fu);
	if (keyed)
		evo_flash_tx_key(&tx, key, sizeof key);
	uint32_t now = 0;
	unsigned k = 0, damaged = 0, idle = 0;
	evo_can_frame f, r[EVO_FLASH_RX_REPLIES];
	/* Every frame costs a millisecond and every wait 300: the robot's
	 * 1000 ms timeout ends any transfer the schedule starves, and the
	 * sender is bounded by the frames and waits below. */
	for (unsigned steps = 0; tx.stage != EVO_FLASH_TX_FINISHED; steps++) {
		if (steps > 200000 || idle > 64)
			break; /* the host gives up, as evo flash does */
		if (!evo_flash_tx_next(&tx, &f)) {
			now += 300;
			idle++;
			if (evo_flash_rx_poll(&rx, now, r) ==
			    EVO_FLASH_RX_REPLY) {
				check_replies(r);
				evo_flash_tx_reply(&tx, &r[0]);
			}
			evo_flash_tx_timeout(&tx);
			continue;
		}
		now++;
		uint8_t s = k < n_sched ? sched[k] : 0;
		k++;
		unsigned times = 1;
		switch (s & 3u) {
		case 1:
			continue; /* lost */
		case 2:
			if (f.len) {
				f.data[(s >> 2) % f.len] ^=
				    (uint8_t)(1u << (s >> 5));
				damaged++;
			}
			break;
		case 3:
			times = 2;
			break;
		default:
			break;
		}
		while (times--) {
			unsigned got = deliver(&f, now, r);
			for (unsigned i = 0; i < got; i++) {
				uint32_t p = tx.progress;
				evo_flash_tx_reply(&tx, &r[i]);
				if (tx.progress != p)
					idle = 0;
			}
		}
	}
	if (switches > 1)
		abort();
	if (switches && damaged <= 1 &&
	    (rx.mind.length != len || memcmp(slot, img, len) != 0))
		abort();
	if (tx.stage == EVO_FLASH_TX_FINISHED && tx.kind == EVO_FLASH_DONE &&
	    !switches)
		abort();
	return 0;
}
