/* core/src/flash.c: a mind image sent over CAN, the host's sender and the
 * robot's receiver wired together through a bus that loses, corrupts and
 * cuts frames on demand. Whatever happens on the way, the receiver either
 * switches once to exactly the image sent, or refuses with a reason and
 * never switches. */
#include <string.h>

#include "evo/flash.h"
#include "harness.h"
#include "support/minibuild.h"
#include "support/rng.h"

#define SLOT	    8192
#define TIMEOUT_MS  3000u /* the robot's */
#define ACK_WAIT_MS 500u  /* the host's */

static minibuild b, other;
static _Alignas(8) uint8_t slot[SLOT];
static unsigned writes_failing_at = ~0u;

static int slot_write(void *ctx, uint32_t offset, const uint8_t word[4])
{
	(void)ctx;
	if (offset >= writes_failing_at)
		return -1;
	memcpy(slot + offset, word, 4);
	return 0;
}

/* A mind of a few skills: a few hundred bytes, some dozens of segments. */
static void build(minibuild *m, unsigned sensors)
{
	static const uint8_t se[] = {EVO_IN_SE, EVO_IN_SE, EVO_IN_SE};
	static const uint8_t mo[] = {EVO_OUT_MO, EVO_OUT_MO, EVO_OUT_MO};
	static const uint16_t idx[] = {0, 1, 2};
	mb_init(m, sensors, 3, 0);
	mb_copy(m, "Master", 3, se, idx, mo, idx);
	mb_copy(m, "A", 3, se, idx, mo, idx);
	mb_counter(m, "B", 0.25, EVO_OUT_MO, 2);
	mb_finish(m);
}

/* The bus between them, and what it does to frames. */
typedef struct bus {
	evo_flash_tx tx;
	evo_flash_rx rx;
	uint32_t now;	   /* ms */
	unsigned switches; /* EVO_FLASH_RX_SWITCH returned */
	unsigned down, up; /* frames carried each way */
	rng drop;
	double p_down, p_up;   /* each frame lost with this probability */
	unsigned cut_after;    /* host -> robot frames after this are lost */
	unsigned corrupt_at;   /* this host -> robot frame has a bit flipped */
	unsigned lose_up_kind; /* lose the first reply of this kind + 1 */
	unsigned timeouts;
} bus;

static void bus_init(bus *s, const uint8_t *image, uint32_t len,
		     uint32_t names_hash, uint32_t slot_size)
{
	memset(s, 0, sizeof *s);
	memset(slot, 0xFF, sizeof slot);
	writes_failing_at = ~0u;
	evo_flash_rx_def def = {names_hash, 1024,	TIMEOUT_MS,
				16,	    slot_write, NULL};
	evo_flash_rx_init(&s->rx, &def);
	evo_flash_rx_target(&s->rx, slot, slot_size);
	evo_flash_tx_init(&s->tx, image, len, 16);
	s->drop = rng_seed(1);
	s->cut_after = ~0u;
	s->corrupt_at = ~0u;
}

static void to_host(bus *s, const evo_can_frame *r)
{
	if (s->lose_up_kind && r->data[0] == s->lose_up_kind - 1) {
		s->lose_up_kind = 0;
		return;
	}
	if (s->p_up > 0 && rng_unit(&s->drop) < s->p_up)
		return;
	s->up++;
	evo_flash_tx_reply(&s->tx, r);
}

static void to_robot(bus *s, evo_can_frame *f)
{
	unsigned k = s->down++;
	if (k >= s->cut_after)
		return;
	if (s->p_down > 0 && rng_unit(&s->drop) < s->p_down)
		return;
	if (k == s->corrupt_at && f->len > 1)
		f->data[f->len - 1] ^= 0x04;
	evo_can_frame reply;
	switch (evo_flash_rx_frame(&s->rx, f, s->now, &reply)) {
	case EVO_FLASH_RX_REPLY:
		to_host(s, &reply);
		break;
	case EVO_FLASH_RX_SWITCH:
		s->switches++;
		evo_flash_rx_switched(&s->rx, 1000 + s->switches, &reply);
		to_host(s, &reply);
		break;
	default:
		break;
	}
}

/* Run until the sender is finished (or gives up after many timeouts).
 * One frame a millisecond; with nothing to send, the host waits for its
 * ack timeout. */
static void run(bus *s)
{
	evo_can_frame f, r;
	while (s->tx.stage != EVO_FLASH_TX_FINISHED && s->timeouts < 50) {
		if (evo_flash_tx_next(&s->tx, &f)) {
			s->now++;
			to_robot(s, &f);
			continue;
		}
		uint32_t progress = s->tx.progress;
		for (uint32_t t = 0;
		     t < ACK_WAIT_MS && progress == s->tx.progress; t += 100) {
			s->now += 100;
			if (evo_flash_rx_poll(&s->rx, s->now, &r) ==
			    EVO_FLASH_RX_REPLY)
				to_host(s, &r);
		}
		if (progress == s->tx.progress) {
			s->timeouts++;
			evo_flash_tx_timeout(&s->tx);
		}
	}
}

TEST(reasons_have_messages)
{
	for (unsigned r = 0; r < EVO_FLASH_REASON_COUNT; r++) {
		const char *m = evo_flash_reason_str((evo_flash_reason)r);
		CHECK(m && strlen(m) > 1 && strcmp(m, "unknown reason") != 0);
	}
	CHECK_EQ_STR(evo_flash_reason_str(EVO_FLASH_REASON_COUNT),
		     "unknown reason");
}

TEST(image_arrives_and_switches_once)
{
	bus s;
	CHECK(b.image_len > 40 * EVO_FLASH_SEGMENT);
	bus_init(&s, b.image, (uint32_t)b.image_len,
		 evo_wire_get_u32(b.image + 16), SLOT);
	run(&s);
	CHECK_EQ_INT(s.tx.stage, EVO_FLASH_TX_FINISHED);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.tx.detail, 1001); /* the tick the bus said */
	CHECK_EQ_INT(s.switches, 1);
	CHECK(memcmp(slot, b.image, b.image_len) == 0);
	CHECK_EQ_INT(s.rx.mind.length, b.image_len);
	/* BEGIN, every segment once, END; and nothing timed out */
	CHECK_EQ_INT(s.tx.frames,
		     2 + evo_flash_segments((uint32_t)b.image_len));
	CHECK_EQ_INT(s.tx.resent_segments, 0);
	CHECK_EQ_INT(s.timeouts, 0);
	CHECK_EQ_INT(s.tx.robot_slot, SLOT);
	/* The robot acks every half window: the host never waits idle. */
	CHECK(s.up >= evo_flash_segments((uint32_t)b.image_len) / 8);
}

TEST(window_of_one_still_arrives)
{
	bus s;
	bus_init(&s, b.image, (uint32_t)b.image_len,
		 evo_wire_get_u32(b.image + 16), SLOT);
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 1);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.switches, 1);
	CHECK(memcmp(slot, b.image, b.image_len) == 0);
}

/* Frames lost both ways, at many rates and seeds: always the same image,
 * switched to exactly once. */
TEST(lost_frames_are_sent_again)
{
	unsigned runs = 0, resent = 0;
	for (unsigned seed = 1; seed <= 200; seed++) {
		bus s;
		bus_init(&s, b.image, (uint32_t)b.image_len,
			 evo_wire_get_u32(b.image + 16), SLOT);
		s.drop = rng_seed(seed);
		s.p_down = 0.002 * (seed % 50);
		s.p_up = 0.001 * (seed % 30);
		run(&s);
		if (s.tx.kind != EVO_FLASH_DONE || s.switches != 1 ||
		    memcmp(slot, b.image, b.image_len) != 0) {
			CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
			CHECK_EQ_INT(s.switches, 1);
			CHECK_EQ_INT(seed, 0);
			return;
		}
		resent += s.tx.resent_segments;
		runs++;
	}
	CHECK_EQ_INT(runs, 200);
	CHECK(resent > 0);
}

/* Each single frame lost in turn, host to robot. */
TEST(any_one_lost_frame_is_recovered)
{
	unsigned total = 2 + evo_flash_segments((uint32_t)b.image_len);
	for (unsigned k = 0; k < total; k++) {
		bus s;
		bus_init(&s, b.image, (uint32_t)b.image_len,
			 evo_wire_get_u32(b.image + 16), SLOT);
		s.corrupt_at = ~0u;
		/* lose frame k only: p_down 0, so use cut + resume */
		evo_can_frame f;
		unsigned sent = 0;
		while (s.tx.stage != EVO_FLASH_TX_FINISHED && s.timeouts < 20) {
			if (evo_flash_tx_next(&s.tx, &f)) {
				s.now++;
				if (sent++ == k) {
					s.down++;
					continue;
				}
				to_robot(&s, &f);
				continue;
			}
			s.timeouts++;
			s.now += ACK_WAIT_MS;
			evo_flash_tx_timeout(&s.tx);
		}
		if (s.tx.kind != EVO_FLASH_DONE || s.switches != 1) {
			CHECK_EQ_INT(k, ~0u);
			return;
		}
	}
}

/* A lost DONE: the host sends END again and hears DONE again, and the
 * robot does not switch twice. */
TEST(lost_done_is_said_again)
{
	bus s;
	bus_init(&s, b.image, (uint32_t)b.image_len,
		 evo_wire_get_u32(b.image + 16), SLOT);
	s.lose_up_kind = EVO_FLASH_DONE + 1;
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.tx.detail, 1001);
	CHECK_EQ_INT(s.switches, 1);
	CHECK_EQ_INT(s.timeouts, 1);
}

/* A bit flipped in a segment on the way: the final CRC says so, and the
 * robot does not switch. */
TEST(corrupted_segment_is_refused)
{
	for (unsigned k = 1;
	     k < 2 + evo_flash_segments((uint32_t)b.image_len) - 1; k += 7) {
		bus s;
		bus_init(&s, b.image, (uint32_t)b.image_len,
			 evo_wire_get_u32(b.image + 16), SLOT);
		s.corrupt_at = k;
		run(&s);
		CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
		CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_CRC);
		CHECK_EQ_INT(s.switches, 0);
		CHECK(s.tx.detail != s.tx.crc);
	}
}

/* The transfer cut at every frame in turn: the robot gives it up after
 * its timeout, says so, and never switches. */
TEST(transfer_cut_anywhere_never_switches)
{
	unsigned total = 2 + evo_flash_segments((uint32_t)b.image_len);
	for (unsigned k = 0; k < total; k++) {
		bus s;
		bus_init(&s, b.image, (uint32_t)b.image_len,
			 evo_wire_get_u32(b.image + 16), SLOT);
		s.cut_after = k;
		run(&s);
		CHECK_EQ_INT(s.switches, 0);
		if (k == 0) {
			/* nothing began: the host hears nothing */
			CHECK(s.tx.stage != EVO_FLASH_TX_FINISHED);
		} else {
			CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
			CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_TIMEOUT);
			CHECK_EQ_INT(s.tx.detail, TIMEOUT_MS);
		}
		CHECK(!s.rx.active);
	}
	/* After the timeout, a late segment is answered once, not per
	 * frame. */
	bus s;
	bus_init(&s, b.image, (uint32_t)b.image_len,
		 evo_wire_get_u32(b.image + 16), SLOT);
	evo_can_frame f = {EVO_FLASH_DATA, 8, {3}}, r;
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, &r), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(r.data[0], EVO_FLASH_REFUSED);
	CHECK_EQ_INT(r.data[1], EVO_FLASH_ERR_NO_TRANSFER);
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, &r), EVO_FLASH_RX_NONE);
}

TEST(another_robots_image_is_refused_at_begin)
{
	bus s;
	bus_init(&s, other.image, (uint32_t)other.image_len,
		 evo_wire_get_u32(b.image + 16), SLOT);
	CHECK(evo_wire_get_u32(other.image + 16) !=
	      evo_wire_get_u32(b.image + 16));
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_NAMES);
	CHECK_EQ_INT(s.tx.detail, evo_wire_get_u32(b.image + 16));
	CHECK_EQ_INT(s.tx.frames, 1); /* no segment was sent */
	CHECK_EQ_INT(s.switches, 0);
}

/* A BEGIN that names the robot's hash over an image that is not its own:
 * the image's own header is checked at the end. */
TEST(image_checked_again_at_end)
{
	static _Alignas(4) uint8_t img[16384];
	bus s;
	memcpy(img, other.image, other.image_len);
	uint32_t mine = evo_wire_get_u32(b.image + 16);
	/* BEGIN takes the hash from the header: lie there, then fix the
	 * image's CRC so only the names are wrong... and the CRC */
	bus_init(&s, img, (uint32_t)other.image_len, mine, SLOT);
	evo_wire_put_u32(img + 16, mine);
	evo_flash_tx_init(&s.tx, img, (uint32_t)other.image_len, 16);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_IMAGE);
	CHECK_EQ_INT(s.tx.detail, EVO_ERR_IMAGE_CRC);
	CHECK_EQ_INT(s.switches, 0);
	/* with the CRC repaired, the layout's sensor count gives it away */
	uint32_t crc = evo_crc32(0, img + 16, other.image_len - 16);
	evo_wire_put_u32(img + 12, crc);
	bus_init(&s, img, (uint32_t)other.image_len, mine, SLOT);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_IMAGE);
	CHECK(s.tx.detail != EVO_OK && s.tx.detail != EVO_ERR_IMAGE_CRC);
	CHECK_EQ_INT(s.switches, 0);
}

/* An image with bytes after its own length (its header says less than
 * was sent) is not the image evo made: refused, never switched to. */
TEST(bytes_after_the_image_are_refused)
{
	static _Alignas(4) uint8_t img[16384];
	bus s;
	memcpy(img, b.image, b.image_len);
	memset(img + b.image_len, 0, 64);
	bus_init(&s, img, (uint32_t)b.image_len + 64,
		 evo_wire_get_u32(b.image + 16), SLOT);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_IMAGE);
	CHECK_EQ_INT(s.tx.detail, EVO_ERR_IMAGE_LENGTH);
	CHECK_EQ_INT(s.switches, 0);
	/* the image alone goes */
	bus_init(&s, b.image, (uint32_t)b.image_len,
		 evo_wire_get_u32(b.image + 16), SLOT);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.switches, 1);
}

TEST(refusals_at_begin_and_end)
{
	bus s;
	uint32_t mine = evo_wire_get_u32(b.image + 16);
	/* too large for the slot */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, 64);
	run(&s);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_SIZE);
	CHECK_EQ_INT(s.tx.detail, 64);
	/* a state larger than the robot's RAM for it */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	s.rx.def.state_max = 16;
	run(&s);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_STATE);
	CHECK_EQ_INT(s.tx.detail, evo_state_size(&b.mind));
	CHECK_EQ_INT(s.switches, 0);
	/* the slot does not take a write */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	writes_failing_at = 64;
	run(&s);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_WRITE);
	CHECK_EQ_INT(s.tx.detail, 64);
	CHECK_EQ_INT(s.switches, 0);
	/* another version */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	evo_can_frame f, r;
	CHECK(evo_flash_tx_next(&s.tx, &f));
	f.data[0] = 2;
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, &r), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(r.data[0], EVO_FLASH_REFUSED);
	CHECK_EQ_INT(r.data[1], EVO_FLASH_ERR_VERSION);
	CHECK_EQ_INT(evo_wire_get_u32(r.data + 4), EVO_FLASH_VERSION);
	/* an END before the last segment */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	CHECK(evo_flash_tx_next(&s.tx, &f));
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, &r), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(r.data[0], EVO_FLASH_READY);
	f.id = EVO_FLASH_END;
	f.len = 4;
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, &r), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(r.data[0], EVO_FLASH_REFUSED);
	CHECK_EQ_INT(r.data[1], EVO_FLASH_ERR_INCOMPLETE);
	/* a segment of the wrong length is asked for again */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	CHECK(evo_flash_tx_next(&s.tx, &f));
	evo_flash_rx_frame(&s.rx, &f, 0, &r);
	evo_flash_tx_reply(&s.tx, &r);
	CHECK(evo_flash_tx_next(&s.tx, &f));
	f.len = 5;
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, &r), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(r.data[0], EVO_FLASH_RESEND);
	CHECK_EQ_INT(r.data[1], EVO_FLASH_ERR_FRAME);
	CHECK_EQ_INT(evo_wire_get_u16(r.data + 2), 0);
}

/* A second transfer into the slot the first one left: the receiver is
 * ready again after a switch, and after a refusal. */
TEST(transfers_follow_each_other)
{
	bus s;
	uint32_t mine = evo_wire_get_u32(b.image + 16);
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	s.corrupt_at = 5;
	run(&s);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_CRC);
	s.corrupt_at = ~0u;
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 16);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.switches, 1);
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 8);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.switches, 2);
}

int main(void)
{
	build(&b, 3);
	build(&other, 2);
	RUN(reasons_have_messages);
	RUN(image_arrives_and_switches_once);
	RUN(window_of_one_still_arrives);
	RUN(lost_frames_are_sent_again);
	RUN(any_one_lost_frame_is_recovered);
	RUN(lost_done_is_said_again);
	RUN(corrupted_segment_is_refused);
	RUN(transfer_cut_anywhere_never_switches);
	RUN(another_robots_image_is_refused_at_begin);
	RUN(image_checked_again_at_end);
	RUN(bytes_after_the_image_are_refused);
	RUN(refusals_at_begin_and_end);
	RUN(transfers_follow_each_other);
	return test_summary();
}
