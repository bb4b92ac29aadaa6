/* core/src/flash.c: a mind image sent over CAN, the host's sender and the
 * robot's receiver wired together through a bus that loses, corrupts and
 * cuts frames on demand. Whatever happens on the way, the receiver either
 * switches once to exactly the image sent, or refuses with a reason and
 * never switches. */
#include <string.h>

#include "evo/flash.h"
#include "evo/mac.h"
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
	unsigned flip_id;      /* frames of this id have a bit flipped */
	unsigned timeouts;
	/* every host -> robot frame, as a recorder on the bus keeps them */
	evo_can_frame rec[512];
	unsigned n_rec;
} bus;

static const uint8_t key_a[32] = "evo's test key, thirty-two bytes";
static const uint8_t key_b[16] = "another key, 16.";

static void bus_init(bus *s, const uint8_t *image, uint32_t len,
		     uint32_t names_hash, uint32_t slot_size)
{
	memset(s, 0, sizeof *s);
	memset(slot, 0xFF, sizeof slot);
	writes_failing_at = ~0u;
	evo_flash_rx_def def = {names_hash, 1024,	TIMEOUT_MS, 16,
				slot_write, NULL,	NULL,	    0};
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
	if (s->n_rec < sizeof s->rec / sizeof s->rec[0])
		s->rec[s->n_rec++] = *f;
	if (k >= s->cut_after)
		return;
	if (s->p_down > 0 && rng_unit(&s->drop) < s->p_down)
		return;
	if ((k == s->corrupt_at || f->id == s->flip_id) && f->len > 1)
		f->data[f->len - 1] ^= 0x04;
	evo_can_frame reply[EVO_FLASH_RX_REPLIES];
	switch (evo_flash_rx_frame(&s->rx, f, s->now, reply)) {
	case EVO_FLASH_RX_REPLY:
		for (unsigned i = 0; i < s->rx.replies; i++)
			to_host(s, &reply[i]);
		break;
	case EVO_FLASH_RX_SWITCH:
		s->switches++;
		evo_flash_rx_switched(&s->rx, 1000 + s->switches, reply);
		for (unsigned i = 0; i < s->rx.replies; i++)
			to_host(s, &reply[i]);
		break;
	default:
		break;
	}
}

/* Both ends keyed (either may be NULL: no key). */
static void bus_keys(bus *s, const uint8_t *robot, size_t robot_len,
		     const uint8_t *host, size_t host_len)
{
	s->rx.def.key = robot;
	s->rx.def.key_len = (uint32_t)robot_len;
	if (host)
		evo_flash_tx_key(&s->tx, host, host_len);
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
	CHECK_EQ_INT(s.tx.robot_counter, 0); /* a robot's first transfer */
	CHECK_EQ_INT(s.tx.counter, 1);
	CHECK_EQ_INT(s.tx.replies_dropped, 0);
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
	evo_can_frame f = {EVO_FLASH_DATA, 8, {3}}, rr[EVO_FLASH_RX_REPLIES];
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, rr), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(rr[0].data[0], EVO_FLASH_REFUSED);
	CHECK_EQ_INT(rr[0].data[1], EVO_FLASH_ERR_NO_TRANSFER);
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, rr), EVO_FLASH_RX_NONE);
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
	evo_can_frame f, rr[EVO_FLASH_RX_REPLIES];
	CHECK(evo_flash_tx_next(&s.tx, &f));
	f.data[0] = 1; /* the version before keys and counters */
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, rr), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(rr[0].data[0], EVO_FLASH_REFUSED);
	CHECK_EQ_INT(rr[0].data[1], EVO_FLASH_ERR_VERSION);
	CHECK_EQ_INT(evo_wire_get_u32(rr[0].data + 4), EVO_FLASH_VERSION);
	/* an END before the last segment */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	CHECK(evo_flash_tx_next(&s.tx, &f));
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, rr), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(rr[0].data[0], EVO_FLASH_READY);
	f.id = EVO_FLASH_END;
	f.len = 8;
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, rr), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(rr[0].data[0], EVO_FLASH_REFUSED);
	CHECK_EQ_INT(rr[0].data[1], EVO_FLASH_ERR_INCOMPLETE);
	/* a segment of the wrong length is asked for again */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	CHECK(evo_flash_tx_next(&s.tx, &f));
	evo_flash_rx_frame(&s.rx, &f, 0, rr);
	evo_flash_tx_reply(&s.tx, rr);
	CHECK(evo_flash_tx_next(&s.tx, &f));
	f.len = 5;
	CHECK_EQ_INT(evo_flash_rx_frame(&s.rx, &f, 0, rr), EVO_FLASH_RX_REPLY);
	CHECK_EQ_INT(rr[0].data[0], EVO_FLASH_RESEND);
	CHECK_EQ_INT(rr[0].data[1], EVO_FLASH_ERR_FRAME);
	CHECK_EQ_INT(evo_wire_get_u16(rr[0].data + 2), 0);
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


/* A reply as a forger on the bus would send it. */
static evo_can_frame forged(evo_flash_kind kind, uint8_t reason, uint32_t next,
			    uint32_t detail)
{
	evo_can_frame f;
	evo_flash_reply(&f, kind, reason, next, detail);
	return f;
}

/* Issue 27, item 12: replies that answer nothing the sender sent are
 * dropped, so a forger with no robot behind it never gets a transfer
 * reported as done. */
TEST(forged_replies_never_finish_a_transfer)
{
	evo_flash_tx t;
	evo_can_frame f, r;
	uint32_t total = evo_flash_segments((uint32_t)b.image_len);
	evo_flash_tx_init(&t, b.image, (uint32_t)b.image_len, 16);
	/* before any BEGIN: nothing is awaited */
	r = forged(EVO_FLASH_READY, 16, 0, 0);
	evo_flash_tx_reply(&t, &r);
	r = forged(EVO_FLASH_DONE, 0, total, 7);
	evo_flash_tx_reply(&t, &r);
	CHECK_EQ_INT(t.stage, EVO_FLASH_TX_BEGIN);
	CHECK_EQ_INT(t.replies_dropped, 2);
	CHECK(evo_flash_tx_next(&t, &f) && f.id == EVO_FLASH_BEGIN);
	/* a READY granting more than was asked, then a fair one */
	r = forged(EVO_FLASH_READY, 65, 0, 0);
	evo_flash_tx_reply(&t, &r);
	CHECK_EQ_INT(t.stage, EVO_FLASH_TX_BEGIN);
	r = forged(EVO_FLASH_READY, 16, 0, 0);
	evo_flash_tx_reply(&t, &r);
	CHECK_EQ_INT(t.stage, EVO_FLASH_TX_DATA);
	/* a second READY for the one BEGIN sent: out of turn */
	evo_flash_tx_reply(&t, &r);
	CHECK_EQ_INT(t.replies_dropped, 4);
	/* three segments sent: an ACK of every segment, of four, or a
	 * RESEND from beyond them answers nothing sent */
	for (int i = 0; i < 3; i++)
		CHECK(evo_flash_tx_next(&t, &f) && f.id == EVO_FLASH_DATA);
	r = forged(EVO_FLASH_ACK, 0, total, 0);
	evo_flash_tx_reply(&t, &r);
	r = forged(EVO_FLASH_ACK, 0, 4, 0);
	evo_flash_tx_reply(&t, &r);
	r = forged(EVO_FLASH_RESEND, EVO_FLASH_ERR_SEQUENCE, 9, 0);
	evo_flash_tx_reply(&t, &r);
	CHECK_EQ_INT(t.acked, 0);
	CHECK_EQ_INT(t.stage, EVO_FLASH_TX_DATA);
	/* a DONE before any END */
	r = forged(EVO_FLASH_DONE, 0, total, 7);
	evo_flash_tx_reply(&t, &r);
	CHECK_EQ_INT(t.stage, EVO_FLASH_TX_DATA);
	CHECK_EQ_INT(t.replies_dropped, 8);
	/* what was sent is acknowledged as before */
	r = forged(EVO_FLASH_ACK, 0, 3, 0);
	evo_flash_tx_reply(&t, &r);
	CHECK_EQ_INT(t.acked, 3);
	CHECK_EQ_INT(t.replies_dropped, 8);
}

/* The same forger, as a bus that carries its replies beside the robot's
 * (here: a robot that never answers): the sender never finishes with
 * DONE, however often the forger says it. */
TEST(a_forger_without_a_robot_cannot_say_done)
{
	evo_flash_tx t;
	evo_can_frame f, r;
	uint32_t total = evo_flash_segments((uint32_t)b.image_len);
	evo_flash_tx_init(&t, b.image, (uint32_t)b.image_len, 16);
	for (unsigned round = 0; round < 50; round++) {
		while (evo_flash_tx_next(&t, &f))
			;
		r = forged(EVO_FLASH_ACK, 0, total, 0);
		evo_flash_tx_reply(&t, &r);
		r = forged(EVO_FLASH_DONE, 0, total, 1);
		evo_flash_tx_reply(&t, &r);
		evo_flash_tx_timeout(&t);
	}
	CHECK(t.stage != EVO_FLASH_TX_FINISHED);
	CHECK(t.replies_dropped >= 100);
}

/* Issue 27, item 13: transfers A then B; A's frames, recorded on the
 * bus and played again, are refused (STALE) and the robot keeps B. */
TEST(a_replayed_transfer_is_refused)
{
	static bus s;
	static evo_can_frame rec_a[512];
	uint32_t mine = evo_wire_get_u32(b.image + 16);
	/* A and B: the same image, sent twice (what tells them apart is
	 * the counter) */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.rx.counter, 1);
	unsigned n_a = s.n_rec;
	memcpy(rec_a, s.rec, sizeof rec_a);
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 8);
	s.n_rec = 0;
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.switches, 2);
	CHECK_EQ_INT(s.rx.counter, 2);
	CHECK_EQ_INT(evo_wire_get_u32(slot + b.image_len), 2);
	/* the replay: every frame of A as it was sent */
	evo_can_frame rr[EVO_FLASH_RX_REPLIES];
	unsigned refused = 0, switched = 0;
	for (unsigned i = 0; i < n_a; i++) {
		evo_flash_rx_result res =
		    evo_flash_rx_frame(&s.rx, &rec_a[i], s.now, rr);
		if (res == EVO_FLASH_RX_SWITCH)
			switched++;
		if (res == EVO_FLASH_RX_REPLY &&
		    rr[0].data[0] == EVO_FLASH_REFUSED) {
			refused++;
			CHECK_EQ_INT(rr[0].data[1], EVO_FLASH_ERR_STALE);
			CHECK_EQ_INT(evo_wire_get_u32(rr[0].data + 4), 2);
		}
	}
	CHECK_EQ_INT(switched, 0);
	CHECK_EQ_INT(refused, 1);
	CHECK_EQ_INT(s.rx.counter, 2);
}

/* The counter lives in the slot, after the image: a robot that starts
 * again from it knows it, and refuses a counter not above it unless the
 * transfer is forced. */
TEST(the_counter_survives_a_restart_and_force_overrides_it)
{
	static bus s;
	uint32_t mine = evo_wire_get_u32(b.image + 16);
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	evo_flash_tx_counter(&s.tx, 40, 0);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(evo_flash_rx_counter_at(slot, SLOT,
					     (uint32_t)b.image_len),
		     40);
	/* erased flash and a slot too small hold no counter */
	static uint8_t erased[64];
	memset(erased, 0xFF, sizeof erased);
	CHECK_EQ_INT(evo_flash_rx_counter_at(erased, 64, 16), 0);
	CHECK_EQ_INT(evo_flash_rx_counter_at(slot, 64, 62), 0);
	/* the robot starts again: its receiver learns the counter */
	static _Alignas(8) uint8_t kept[SLOT];
	memcpy(kept, slot, SLOT);
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	s.rx.counter =
	    evo_flash_rx_counter_at(kept, SLOT, (uint32_t)b.image_len);
	evo_flash_tx_counter(&s.tx, 40, 0);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_STALE);
	CHECK_EQ_INT(s.tx.detail, 40);
	CHECK_EQ_INT(s.switches, 0);
	/* forced, an older counter goes, and becomes the robot's */
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 16);
	evo_flash_tx_counter(&s.tx, 3, 1);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.rx.counter, 3);
	/* without a counter given, the sender goes on from the robot's */
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 16);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.tx.counter, 4);
	/* a robot at the last counter takes no more, but forced */
	s.rx.counter = EVO_FLASH_COUNTER_MAX;
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 16);
	run(&s);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_STALE);
}

/* With a key: the transfer switches, READY and DONE come with their
 * tags, and anything made without the key is refused. */
TEST(a_keyed_transfer_switches_and_a_keyless_one_does_not)
{
	static bus s;
	uint32_t mine = evo_wire_get_u32(b.image + 16);
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	bus_keys(&s, key_a, sizeof key_a, key_a, sizeof key_a);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	CHECK_EQ_INT(s.switches, 1);
	CHECK_EQ_INT(s.tx.tags_bad, 0);
	/* BEGIN, the segments, AUTH, END */
	CHECK_EQ_INT(s.tx.frames,
		     3 + evo_flash_segments((uint32_t)b.image_len));
	/* the robot has a key, the sender none: not sent */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	bus_keys(&s, key_a, sizeof key_a, NULL, 0);
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_KEYED);
	CHECK_EQ_INT(s.tx.frames, 1);
	/* the sender has a key, the robot none: not sent either */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	bus_keys(&s, NULL, 0, key_a, sizeof key_a);
	run(&s);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_UNKEYED);
	CHECK_EQ_INT(s.switches, 0);
	/* another key: its READY's tag does not verify, nothing is sent */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	bus_keys(&s, key_a, sizeof key_a, key_b, sizeof key_b);
	run(&s);
	CHECK(s.tx.stage != EVO_FLASH_TX_FINISHED);
	CHECK(s.tx.tags_bad > 0);
	CHECK_EQ_INT(s.switches, 0);
	/* the image's tag changed on the way: refused AUTH */
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	bus_keys(&s, key_a, sizeof key_a, key_a, sizeof key_a);
	s.flip_id = EVO_FLASH_AUTH;
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_REFUSED);
	CHECK_EQ_INT(s.tx.reason, EVO_FLASH_ERR_AUTH);
	CHECK_EQ_INT(s.switches, 0);
}

/* A forger who sees every frame of a keyed transfer but has no key: its
 * DONE, its READY, and the robot's tags of an earlier transfer played
 * again, are not taken. */
TEST(a_keyed_sender_takes_no_untagged_or_replayed_done)
{
	static bus s;
	uint32_t mine = evo_wire_get_u32(b.image + 16);
	bus_init(&s, b.image, (uint32_t)b.image_len, mine, SLOT);
	bus_keys(&s, key_a, sizeof key_a, key_a, sizeof key_a);
	/* the first transfer's DONE and its tag, as a recorder keeps them */
	evo_can_frame done[2];
	run(&s);
	CHECK_EQ_INT(s.tx.kind, EVO_FLASH_DONE);
	evo_flash_reply(&done[0], EVO_FLASH_DONE, 0, s.tx.total, 1001);
	done[1].id = EVO_FLASH_TAG;
	done[1].len = 8;
	evo_flash_tag(key_a, sizeof key_a, 'R', s.tx.begin, done[0].data, 8,
		      s.tx.end, done[1].data);
	/* a second transfer, its robot silent after the segments: the
	 * replayed DONE and tag (counter 1, this one's 2) do not finish it,
	 * nor does an untagged DONE */
	evo_flash_tx_init(&s.tx, b.image, (uint32_t)b.image_len, 16);
	evo_flash_tx_key(&s.tx, key_a, sizeof key_a);
	s.cut_after = s.down + 1 + s.tx.total; /* BEGIN and the segments */
	evo_can_frame f;
	for (int i = 0; i < 400 && s.tx.stage != EVO_FLASH_TX_END; i++) {
		if (evo_flash_tx_next(&s.tx, &f))
			to_robot(&s, &f);
	}
	CHECK_EQ_INT(s.tx.stage, EVO_FLASH_TX_END);
	while (evo_flash_tx_next(&s.tx, &f))
		to_robot(&s, &f);
	CHECK_EQ_INT(s.tx.counter, 2);
	evo_flash_tx_reply(&s.tx, &done[0]);
	evo_flash_tx_reply(&s.tx, &done[1]);
	CHECK(s.tx.stage != EVO_FLASH_TX_FINISHED);
	CHECK_EQ_INT(s.tx.tags_bad, 1);
	evo_can_frame r = forged(EVO_FLASH_DONE, 0, s.tx.total, 5);
	evo_flash_tx_reply(&s.tx, &r);
	CHECK(s.tx.stage != EVO_FLASH_TX_FINISHED);
}

/* CONFIG: without a key, DLC 2 as before; with one, only with its tag,
 * bound to the robot's counter. */
TEST(config_needs_the_key_when_the_robot_has_one)
{
	evo_flash_rx rx;
	evo_flash_rx_def def = {1, 1024, TIMEOUT_MS, 16, slot_write, NULL,
				NULL, 0};
	evo_flash_rx_init(&rx, &def);
	evo_can_frame f = {EVO_WIRE_CONFIG, 2, {0x10, 0x27}};
	uint32_t ms = 0;
	CHECK_EQ_INT(evo_flash_config_check(&rx, &f, &ms), 1);
	CHECK_EQ_INT(ms, 10000);
	rx.def.key = key_a;
	rx.def.key_len = sizeof key_a;
	rx.counter = 7;
	CHECK_EQ_INT(evo_flash_config_check(&rx, &f, &ms), 0);
	evo_flash_config_make(key_a, sizeof key_a, 7, 250, &f);
	CHECK_EQ_INT(f.len, 8);
	ms = 0;
	CHECK_EQ_INT(evo_flash_config_check(&rx, &f, &ms), 1);
	CHECK_EQ_INT(ms, 250);
	/* made with another key, or before the robot's last transfer */
	evo_flash_config_make(key_b, sizeof key_b, 7, 250, &f);
	CHECK_EQ_INT(evo_flash_config_check(&rx, &f, &ms), 0);
	evo_flash_config_make(key_a, sizeof key_a, 6, 250, &f);
	CHECK_EQ_INT(evo_flash_config_check(&rx, &f, &ms), 0);
	/* a value changed on the way */
	evo_flash_config_make(key_a, sizeof key_a, 7, 250, &f);
	f.data[1] ^= 0xFF;
	CHECK_EQ_INT(evo_flash_config_check(&rx, &f, &ms), 0);
}

/* The tag is HMAC-SHA-256 over the domain byte and the parts, cut to 8
 * bytes: checked against the MAC of the same bytes in one buffer. */
TEST(a_tag_is_the_hmac_of_its_parts)
{
	uint8_t a[8] = {1, 2, 3, 4, 5, 6, 7, 8}, bb[8] = {9, 9, 9, 9, 9, 9, 9,
							   9};
	uint8_t body[5] = {'h', 'e', 'l', 'l', 'o'}, msg[22], mac[32], tag[8];
	msg[0] = 'I';
	memcpy(msg + 1, a, 8);
	memcpy(msg + 9, body, 5);
	memcpy(msg + 14, bb, 8);
	evo_hmac_sha256(key_a, sizeof key_a, msg, sizeof msg, mac);
	evo_flash_tag(key_a, sizeof key_a, 'I', a, body, 5, bb, tag);
	CHECK(memcmp(mac, tag, 8) == 0);
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
	RUN(forged_replies_never_finish_a_transfer);
	RUN(a_forger_without_a_robot_cannot_say_done);
	RUN(a_replayed_transfer_is_refused);
	RUN(the_counter_survives_a_restart_and_force_overrides_it);
	RUN(a_keyed_transfer_switches_and_a_keyless_one_does_not);
	RUN(a_keyed_sender_takes_no_untagged_or_replayed_done);
	RUN(config_needs_the_key_when_the_robot_has_one);
	RUN(a_tag_is_the_hmac_of_its_parts);
	return test_summary();
}
