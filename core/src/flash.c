/* A mind image sent over CAN (evo/flash.h): the robot's receiver and the
 * host's sender. */
#include "evo/flash.h"

#include "evo/mac.h"

static const char *const reasons[] = {
#define EVO_FLASH_REASON_TEXT(code, text) text,
    EVO_FLASH_REASON_LIST(EVO_FLASH_REASON_TEXT)
#undef EVO_FLASH_REASON_TEXT
};

const char *evo_flash_reason_str(evo_flash_reason r)
{
	if ((unsigned)r >= EVO_FLASH_REASON_COUNT)
		return "unknown reason";
	return reasons[r];
}

void evo_flash_reply(evo_can_frame *f, evo_flash_kind kind, uint8_t reason,
		     uint32_t next, uint32_t detail)
{
	f->id = EVO_FLASH_REPLY;
	f->len = 8;
	f->data[0] = (uint8_t)kind;
	f->data[1] = reason;
	evo_wire_put_u16(f->data + 2, (uint16_t)next);
	evo_wire_put_u32(f->data + 4, detail);
}

void evo_flash_tag(const uint8_t *key, size_t key_len, uint8_t domain,
		   const uint8_t a[8], const uint8_t *body, uint32_t n,
		   const uint8_t b[8], uint8_t tag[EVO_FLASH_TAG_BYTES])
{
	/* The domain byte keeps a tag of one kind from passing for another:
	 * a reply's tag can never be an image's. */
	evo_hmac h;
	uint8_t mac[EVO_SHA256_BYTES];
	evo_hmac_init(&h, key, key_len);
	evo_hmac_update(&h, &domain, 1);
	evo_hmac_update(&h, a, 8);
	evo_hmac_update(&h, body, n);
	evo_hmac_update(&h, b, 8);
	evo_hmac_final(&h, mac);
	for (unsigned i = 0; i < EVO_FLASH_TAG_BYTES; i++)
		tag[i] = mac[i];
}

/* ---- the robot's receiver ------------------------------------------------ */

void evo_flash_rx_init(evo_flash_rx *rx, const evo_flash_rx_def *def)
{
	uint8_t *p = (uint8_t *)rx;
	for (size_t i = 0; i < sizeof *rx; i++)
		p[i] = 0;
	rx->def = *def;
	if (rx->def.window == 0)
		rx->def.window = 1;
	if (rx->def.window > EVO_FLASH_WINDOW_MAX)
		rx->def.window = EVO_FLASH_WINDOW_MAX;
}

void evo_flash_rx_target(evo_flash_rx *rx, const uint8_t *slot, uint32_t size)
{
	rx->slot = slot;
	rx->slot_size = size;
}

uint32_t evo_flash_rx_counter_at(const uint8_t *slot, uint32_t size,
				 uint32_t image_len)
{
	if (image_len % 4u || image_len > size || size - image_len < 4u)
		return 0;
	uint32_t c = evo_wire_get_u32(slot + image_len);
	return c > EVO_FLASH_COUNTER_MAX ? 0 : c;
}

/* With a key, a reply the host must be able to trust (READY, DONE) is
 * followed by its tag, bound to this transfer's BEGIN and END. */
static evo_flash_rx_result tagged(evo_flash_rx *rx, evo_can_frame *reply,
				  const uint8_t end[8])
{
	static const uint8_t none[8] = {0};
	rx->replies = 1;
	if (!rx->def.key)
		return EVO_FLASH_RX_REPLY;
	reply[1].id = EVO_FLASH_TAG;
	reply[1].len = 8;
	evo_flash_tag(rx->def.key, rx->def.key_len, 'R', rx->begin,
		      reply[0].data, 8, end ? end : none, reply[1].data);
	rx->replies = 2;
	return EVO_FLASH_RX_REPLY;
}

/* End the transfer under way with a reason; the frames of it still on
 * the way are then ignored, so one refusal is said once. */
static evo_flash_rx_result refuse(evo_flash_rx *rx, evo_flash_reason why,
				  uint32_t detail, evo_can_frame *reply)
{
	rx->active = 0;
	rx->quiet = 1;
	rx->replies = 1;
	evo_flash_reply(reply, EVO_FLASH_REFUSED, (uint8_t)why, rx->next,
			detail);
	return EVO_FLASH_RX_REPLY;
}

static evo_flash_rx_result begin(evo_flash_rx *rx, const evo_can_frame *f,
				 uint32_t now_ms, evo_can_frame *reply)
{
	rx->active = 0;
	rx->quiet = 0;
	rx->done = 0;
	rx->gap_said = rx->dup_said = 0;
	rx->n_word = 0;
	rx->next = rx->acked = rx->written = rx->crc = 0;
	rx->has_tag = 0;
	rx->force = 0;
	for (unsigned i = 0; i < 8u; i++)
		rx->begin[i] = f->data[i];
	if (f->len != 8)
		return refuse(rx, EVO_FLASH_ERR_FRAME, 0, reply);
	if (f->data[0] != EVO_FLASH_VERSION)
		return refuse(rx, EVO_FLASH_ERR_VERSION, EVO_FLASH_VERSION,
			      reply);
	uint32_t len = 4u * evo_wire_get_u16(f->data + 2);
	/* the image, and the counter's word after it */
	if (len > rx->slot_size || rx->slot_size - len < 4u || !rx->slot)
		return refuse(rx, EVO_FLASH_ERR_SIZE, rx->slot_size, reply);
	if (len < sizeof(evo_image_header))
		return refuse(rx, EVO_FLASH_ERR_IMAGE, EVO_ERR_IMAGE_LENGTH,
			      reply);
	/* The image's own header is checked again at the end: this is
	 * only so that another robot's image is refused before it is sent. */
	if (evo_wire_get_u32(f->data + 4) != rx->def.names_hash)
		return refuse(rx, EVO_FLASH_ERR_NAMES, rx->def.names_hash,
			      reply);
	uint8_t w = f->data[1] & (uint8_t)~EVO_FLASH_FORCE;
	rx->force = (f->data[1] & EVO_FLASH_FORCE) != 0;
	rx->window = w == 0 ? 1 : w > rx->def.window ? rx->def.window : w;
	rx->length = len;
	rx->active = 1;
	rx->last_ms = now_ms;
	evo_flash_reply(reply, EVO_FLASH_READY, rx->window,
			rx->def.key ? EVO_FLASH_KEYED : 0u, rx->counter);
	return tagged(rx, reply, NULL);
}

/* Ask for the segments from rx->next again, once per gap. */
static evo_flash_rx_result resend(evo_flash_rx *rx, evo_flash_reason why,
				  evo_can_frame *reply)
{
	if (rx->gap_said)
		return EVO_FLASH_RX_NONE;
	rx->gap_said = 1;
	rx->replies = 1;
	rx->acked = rx->next;
	evo_flash_reply(reply, EVO_FLASH_RESEND, (uint8_t)why, rx->next, 0);
	return EVO_FLASH_RX_REPLY;
}

static evo_flash_rx_result data(evo_flash_rx *rx, const evo_can_frame *f,
				uint32_t now_ms, evo_can_frame *reply)
{
	if (!rx->active) {
		if (rx->quiet)
			return EVO_FLASH_RX_NONE;
		return refuse(rx, EVO_FLASH_ERR_NO_TRANSFER, 0, reply);
	}
	rx->last_ms = now_ms;
	if (f->len < 2 || f->len > 8)
		return resend(rx, EVO_FLASH_ERR_FRAME, reply);
	uint32_t total = evo_flash_segments(rx->length);
	/* The sender keeps fewer than 128 segments in flight, so the
	 * 8-bit difference says whether this one is behind, the one
	 * expected, or ahead (some were lost). */
	int8_t d = (int8_t)(uint8_t)(f->data[0] - (uint8_t)rx->next);
	if (d < 0 || (d == 0 && rx->next >= total)) {
		/* Sent again after an ACK was lost: say where we are. */
		if (rx->dup_said)
			return EVO_FLASH_RX_NONE;
		rx->dup_said = 1;
		rx->replies = 1;
		rx->acked = rx->next;
		evo_flash_reply(reply, EVO_FLASH_ACK, 0, rx->next, 0);
		return EVO_FLASH_RX_REPLY;
	}
	if (d > 0)
		return resend(rx, EVO_FLASH_ERR_SEQUENCE, reply);
	uint32_t off = rx->next * EVO_FLASH_SEGMENT;
	uint32_t n = rx->length - off < EVO_FLASH_SEGMENT ? rx->length - off
							  : EVO_FLASH_SEGMENT;
	if (f->len != 1u + n)
		return resend(rx, EVO_FLASH_ERR_FRAME, reply);
	for (uint32_t i = 0; i < n; i++) {
		rx->word[rx->n_word++] = f->data[1 + i];
		if (rx->n_word < 4)
			continue;
		rx->n_word = 0;
		if (rx->def.write(rx->def.ctx, rx->written, rx->word) != 0)
			return refuse(rx, EVO_FLASH_ERR_WRITE, rx->written,
				      reply);
		/* What the slot holds, not what was meant to go there. */
		rx->crc = evo_crc32(rx->crc, rx->slot + rx->written, 4);
		rx->written += 4;
	}
	rx->next++;
	rx->gap_said = rx->dup_said = 0;
	if (rx->next == total ||
	    rx->next - rx->acked >= (rx->window + 1u) / 2u) {
		rx->replies = 1;
		rx->acked = rx->next;
		evo_flash_reply(reply, EVO_FLASH_ACK, 0, rx->next, 0);
		return EVO_FLASH_RX_REPLY;
	}
	return EVO_FLASH_RX_NONE;
}

/* AUTH: the transfer's tag, checked at END. */
static evo_flash_rx_result auth(evo_flash_rx *rx, const evo_can_frame *f,
				uint32_t now_ms)
{
	if (!rx->active || f->len != 8)
		return EVO_FLASH_RX_NONE; /* END says what is missing */
	rx->last_ms = now_ms;
	for (unsigned i = 0; i < EVO_FLASH_TAG_BYTES; i++)
		rx->tag[i] = f->data[i];
	rx->has_tag = 1;
	return EVO_FLASH_RX_NONE;
}

static int same8(const uint8_t *a, const uint8_t *b)
{
	unsigned d = 0;
	for (unsigned i = 0; i < 8u; i++)
		d |= (unsigned)(a[i] ^ b[i]);
	return d == 0;
}

static evo_flash_rx_result end(evo_flash_rx *rx, const evo_can_frame *f,
			       uint32_t now_ms, evo_can_frame *reply)
{
	if (!rx->active) {
		if (rx->done && f->len == 8 && same8(f->data, rx->end)) {
			/* its DONE was lost: say it again */
			evo_flash_reply(reply, EVO_FLASH_DONE, 0,
					evo_flash_segments(rx->done_length),
					rx->done_tick);
			return tagged(rx, reply, rx->end);
		}
		if (rx->quiet)
			return EVO_FLASH_RX_NONE;
		return refuse(rx, EVO_FLASH_ERR_NO_TRANSFER, 0, reply);
	}
	rx->last_ms = now_ms;
	if (f->len != 8)
		return refuse(rx, EVO_FLASH_ERR_FRAME, 0, reply);
	for (unsigned i = 0; i < 8u; i++)
		rx->end[i] = f->data[i];
	if (rx->next != evo_flash_segments(rx->length))
		return refuse(rx, EVO_FLASH_ERR_INCOMPLETE, rx->next, reply);
	if (rx->crc != evo_wire_get_u32(f->data))
		return refuse(rx, EVO_FLASH_ERR_CRC, rx->crc, reply);
	if (rx->def.key) {
		/* Over the slot's bytes as written, BEGIN (length, names,
		 * force) and END (CRC, counter): nothing of it can be
		 * changed, or taken from another transfer. */
		uint8_t want[EVO_FLASH_TAG_BYTES];
		evo_flash_tag(rx->def.key, rx->def.key_len, 'I', rx->begin,
			      rx->slot, rx->length, rx->end, want);
		if (!rx->has_tag ||
		    !evo_mac_equal(want, rx->tag, EVO_FLASH_TAG_BYTES))
			return refuse(rx, EVO_FLASH_ERR_AUTH, 0, reply);
	}
	/* Freshness: a transfer recorded and played again carries the
	 * counter it had, which the robot has passed since. */
	uint32_t counter = evo_wire_get_u32(f->data + 4);
	if (counter > EVO_FLASH_COUNTER_MAX ||
	    (!rx->force && counter <= rx->counter))
		return refuse(rx, EVO_FLASH_ERR_STALE, rx->counter, reply);
	evo_status st =
	    evo_mind_open(rx->slot, rx->length, rx->def.names_hash, &rx->mind);
	/* bytes after the image's own length: not the image evo made */
	if (st == EVO_OK && rx->mind.length != rx->length)
		st = EVO_ERR_IMAGE_LENGTH;
	if (st != EVO_OK)
		return refuse(rx, EVO_FLASH_ERR_IMAGE, (uint32_t)st, reply);
	size_t need = evo_state_size(&rx->mind);
	if (need > rx->def.state_max)
		return refuse(rx, EVO_FLASH_ERR_STATE, (uint32_t)need, reply);
	/* The counter goes with the image, in the slot's next word, so a
	 * robot that starts again from this slot knows it. */
	if (rx->def.write(rx->def.ctx, rx->length, f->data + 4) != 0 ||
	    evo_wire_get_u32(rx->slot + rx->length) != counter)
		return refuse(rx, EVO_FLASH_ERR_WRITE, rx->length, reply);
	rx->counter = counter;
	rx->active = 0;
	rx->quiet = 1;
	rx->done = 1;
	rx->done_length = rx->length;
	rx->done_crc = rx->crc;
	return EVO_FLASH_RX_SWITCH;
}

evo_flash_rx_result evo_flash_rx_frame(evo_flash_rx *rx, const evo_can_frame *f,
				       uint32_t now_ms, evo_can_frame *reply)
{
	switch (f->id) {
	case EVO_FLASH_BEGIN:
		return begin(rx, f, now_ms, reply);
	case EVO_FLASH_DATA:
		return data(rx, f, now_ms, reply);
	case EVO_FLASH_AUTH:
		return auth(rx, f, now_ms);
	case EVO_FLASH_END:
		return end(rx, f, now_ms, reply);
	default:
		return EVO_FLASH_RX_NONE;
	}
}

evo_flash_rx_result evo_flash_rx_poll(evo_flash_rx *rx, uint32_t now_ms,
				      evo_can_frame *reply)
{
	/* Unsigned difference: right across the clock's wrap. */
	if (!rx->active || now_ms - rx->last_ms <= rx->def.timeout_ms)
		return EVO_FLASH_RX_NONE;
	return refuse(rx, EVO_FLASH_ERR_TIMEOUT, rx->def.timeout_ms, reply);
}

void evo_flash_rx_switched(evo_flash_rx *rx, uint32_t last_tick,
			   evo_can_frame *reply)
{
	rx->done_tick = last_tick;
	evo_flash_reply(reply, EVO_FLASH_DONE, 0,
			evo_flash_segments(rx->done_length), last_tick);
	tagged(rx, reply, rx->end);
}

/* A CONFIG's tag: bound to the value and to the robot's counter, so one
 * recorded before the robot's last transfer is refused after it. */
static void config_tag(const uint8_t *key, size_t key_len, uint32_t counter,
		       const uint8_t value[2], uint8_t tag[EVO_FLASH_TAG_BYTES])
{
	uint8_t a[8] = {0}, b[8] = {0};
	a[0] = value[0];
	a[1] = value[1];
	evo_wire_put_u32(b, counter);
	evo_flash_tag(key, key_len, 'C', a, NULL, 0, b, tag);
}

int evo_flash_config_check(const evo_flash_rx *rx, const evo_can_frame *f,
			   uint32_t *timeout_ms)
{
	if (!rx->def.key) {
		if (f->len != 2)
			return 0;
	} else {
		uint8_t want[EVO_FLASH_TAG_BYTES];
		if (f->len != 8)
			return 0;
		config_tag(rx->def.key, rx->def.key_len, rx->counter, f->data,
			   want);
		if (!evo_mac_equal(want, f->data + 2, 6))
			return 0;
	}
	*timeout_ms = evo_wire_get_u16(f->data);
	return 1;
}

void evo_flash_config_make(const uint8_t *key, size_t key_len,
			   uint32_t counter, uint16_t timeout_ms,
			   evo_can_frame *f)
{
	uint8_t tag[EVO_FLASH_TAG_BYTES];
	f->id = EVO_WIRE_CONFIG;
	f->len = 8;
	evo_wire_put_u16(f->data, timeout_ms);
	config_tag(key, key_len, counter, f->data, tag);
	for (unsigned i = 0; i < 6u; i++)
		f->data[2 + i] = tag[i];
}

/* ---- the host's sender -----------------------------------------------------
 */

void evo_flash_tx_init(evo_flash_tx *t, const uint8_t *image, uint32_t len,
		       unsigned window)
{
	uint8_t *p = (uint8_t *)t;
	for (size_t i = 0; i < sizeof *t; i++)
		p[i] = 0;
	t->image = image;
	t->length = len;
	t->total = evo_flash_segments(len);
	t->window =
	    (uint8_t)(window < 1u		      ? 1u
		      : window > EVO_FLASH_WINDOW_MAX ? EVO_FLASH_WINDOW_MAX
						      : window);
	t->crc = evo_crc32(0, image, len);
	t->stage = EVO_FLASH_TX_BEGIN;
}

void evo_flash_tx_key(evo_flash_tx *t, const uint8_t *key, size_t key_len)
{
	t->key = key;
	t->key_len = (uint32_t)key_len;
}

void evo_flash_tx_counter(evo_flash_tx *t, uint32_t counter, int force)
{
	t->counter_set = counter != 0;
	t->counter = counter;
	t->force = force != 0;
}

int evo_flash_tx_next(evo_flash_tx *t, evo_can_frame *f)
{
	for (unsigned i = 0; i < 8u; i++)
		f->data[i] = 0;
	switch (t->stage) {
	case EVO_FLASH_TX_BEGIN:
		if (t->waiting)
			return 0;
		f->id = EVO_FLASH_BEGIN;
		f->len = 8;
		f->data[0] = EVO_FLASH_VERSION;
		f->data[1] =
		    (uint8_t)(t->window | (t->force ? EVO_FLASH_FORCE : 0u));
		evo_wire_put_u16(f->data + 2, (uint16_t)(t->length / 4u));
		evo_wire_put_u32(
		    f->data + 4,
		    t->length >= 20u ? evo_wire_get_u32(t->image + 16) : 0u);
		for (unsigned i = 0; i < 8u; i++)
			t->begin[i] = f->data[i];
		t->begins++;
		break;
	case EVO_FLASH_TX_DATA: {
		if (t->next >= t->total || t->next >= t->acked + t->window)
			return 0;
		uint32_t off = t->next * EVO_FLASH_SEGMENT;
		uint32_t n = t->length - off < EVO_FLASH_SEGMENT
				 ? t->length - off
				 : EVO_FLASH_SEGMENT;
		f->id = EVO_FLASH_DATA;
		f->len = (uint8_t)(1u + n);
		f->data[0] = (uint8_t)t->next;
		for (uint32_t i = 0; i < n; i++)
			f->data[1 + i] = t->image[off + i];
		if (t->next < t->sent)
			t->resent_segments++;
		t->next++;
		if (t->next > t->sent)
			t->sent = t->next;
		t->frames++;
		return 1;
	}
	case EVO_FLASH_TX_END:
		if (t->waiting)
			return 0;
		if (t->key && !t->waiting_auth) {
			/* the tag first, END right after it */
			f->id = EVO_FLASH_AUTH;
			f->len = 8;
			evo_flash_tag(t->key, t->key_len, 'I', t->begin,
				      t->image, t->length, t->end, f->data);
			t->waiting_auth = 1;
			t->frames++;
			return 1;
		}
		t->waiting_auth = 0;
		f->id = EVO_FLASH_END;
		f->len = 8;
		for (unsigned i = 0; i < 8u; i++)
			f->data[i] = t->end[i];
		break;
	case EVO_FLASH_TX_FINISHED:
	default:
		return 0;
	}
	t->waiting = 1;
	t->frames++;
	return 1;
}

static void finish(evo_flash_tx *t, evo_flash_kind kind, uint8_t reason,
		   uint32_t detail)
{
	t->stage = EVO_FLASH_TX_FINISHED;
	t->kind = kind;
	t->reason = (evo_flash_reason)reason;
	t->detail = detail;
	t->progress++;
}

/* A reply that answers nothing sent: forged, from another transfer, or
 * out of turn. Counted, and otherwise ignored. */
static void drop(evo_flash_tx *t)
{
	t->replies_dropped++;
}

/* READY, once trusted: the robot has begun the transfer this BEGIN asked
 * for. The counter END will carry is known from here. */
static void ready(evo_flash_tx *t, const uint8_t *r)
{
	uint8_t granted = r[1];
	uint32_t robot = evo_wire_get_u32(r + 4);
	if (granted < t->window)
		t->window = granted;
	t->readies++;
	t->robot_counter = robot;
	if (!t->counter_set)
		t->counter = robot + 1u; /* past COUNTER_MAX: refused STALE */
	evo_wire_put_u32(t->end, t->crc);
	evo_wire_put_u32(t->end + 4, t->counter);
	t->stage = EVO_FLASH_TX_DATA;
	t->waiting = 0;
	t->waiting_auth = 0;
	/* Also after segments: a BEGIN sent again was answered, and the
	 * robot has begun anew. */
	t->acked = t->next = t->sent = 0;
	t->progress++;
}

static void tag_reply(evo_flash_tx *t, const evo_can_frame *f)
{
	static const uint8_t none[8] = {0};
	if (!t->key || !t->pending || f->len != 8) {
		drop(t);
		return;
	}
	uint8_t want[EVO_FLASH_TAG_BYTES];
	int is_done = t->pending_reply[0] == EVO_FLASH_DONE;
	evo_flash_tag(t->key, t->key_len, 'R', t->begin, t->pending_reply, 8,
		      is_done ? t->end : none, want);
	if (!evo_mac_equal(want, f->data, EVO_FLASH_TAG_BYTES)) {
		/* a forger's tag: the genuine one may still come */
		t->tags_bad++;
		return;
	}
	t->pending = 0;
	if (is_done)
		finish(t, EVO_FLASH_DONE, 0,
		       evo_wire_get_u32(t->pending_reply + 4));
	else
		ready(t, t->pending_reply);
}

/* Hold a READY or DONE until its tag (keyed), or take it now. */
static void trusted(evo_flash_tx *t, const evo_can_frame *f)
{
	if (t->key) {
		for (unsigned i = 0; i < 8u; i++)
			t->pending_reply[i] = f->data[i];
		t->pending = 1;
		return;
	}
	if (f->data[0] == EVO_FLASH_DONE)
		finish(t, EVO_FLASH_DONE, 0, evo_wire_get_u32(f->data + 4));
	else
		ready(t, f->data);
}

void evo_flash_tx_reply(evo_flash_tx *t, const evo_can_frame *f)
{
	if (t->stage == EVO_FLASH_TX_FINISHED)
		return;
	if (f->id == EVO_FLASH_TAG) {
		tag_reply(t, f);
		return;
	}
	if (f->id != EVO_FLASH_REPLY)
		return; /* not the transfer's: the ticks' frames, say */
	if (f->len != 8 || t->begins == 0) {
		drop(t);
		return;
	}
	uint8_t kind = f->data[0], reason = f->data[1];
	uint32_t n = evo_wire_get_u16(f->data + 2);
	uint32_t detail = evo_wire_get_u32(f->data + 4);
	switch (kind) {
	case EVO_FLASH_READY:
		/* One READY per BEGIN sent: in answer to the one awaited, or
		 * to one sent again; granting no more than was asked. */
		if (t->readies >= t->begins ||
		    (t->stage != EVO_FLASH_TX_BEGIN &&
		     t->stage != EVO_FLASH_TX_DATA) ||
		    reason < 1 || reason > EVO_FLASH_WINDOW_MAX ||
		    (n & ~(uint32_t)EVO_FLASH_KEYED) != 0) {
			drop(t);
			return;
		}
		if ((n & EVO_FLASH_KEYED) && !t->key) {
			finish(t, EVO_FLASH_REFUSED, EVO_FLASH_ERR_KEYED, 0);
			return;
		}
		if (!(n & EVO_FLASH_KEYED) && t->key) {
			finish(t, EVO_FLASH_REFUSED, EVO_FLASH_ERR_UNKEYED, 0);
			return;
		}
		trusted(t, f);
		return;
	case EVO_FLASH_ACK:
		/* Only segments sent since READY can have arrived. An ACK
		 * of no more than was acknowledged is the robot saying
		 * where it is again (segments sent twice): nothing new. */
		if (t->stage == EVO_FLASH_TX_DATA && n <= t->acked &&
		    reason == 0)
			return;
		if (t->stage != EVO_FLASH_TX_DATA || n > t->sent ||
		    reason != 0) {
			drop(t);
			return;
		}
		t->acked = n;
		if (t->next < n)
			t->next = n;
		t->progress++;
		if (t->acked == t->total) {
			t->stage = EVO_FLASH_TX_END;
			t->waiting = 0;
		}
		return;
	case EVO_FLASH_RESEND:
		/* The robot has every segment before n, and only those: not
		 * fewer than it acknowledged, not more than were sent. */
		if (t->stage != EVO_FLASH_TX_DATA || n < t->acked ||
		    n > t->sent ||
		    (reason != EVO_FLASH_ERR_SEQUENCE &&
		     reason != EVO_FLASH_ERR_FRAME)) {
			drop(t);
			return;
		}
		t->acked = t->next = n;
		t->resends_asked++;
		t->progress++;
		return;
	case EVO_FLASH_DONE:
		/* Only for the END sent, of every segment. */
		if (t->stage != EVO_FLASH_TX_END || !t->waiting ||
		    n != t->total || reason != 0) {
			drop(t);
			return;
		}
		trusted(t, f);
		return;
	case EVO_FLASH_REFUSED:
		/* Before READY, the end of an earlier transfer is not this
		 * one's. A refusal ends the transfer whoever said it: a
		 * forger can stop a transfer (as one can by jamming the
		 * bus), never make a robot seem to switch. */
		if (t->stage == EVO_FLASH_TX_BEGIN &&
		    (reason == EVO_FLASH_ERR_NO_TRANSFER ||
		     reason == EVO_FLASH_ERR_TIMEOUT)) {
			drop(t);
			return;
		}
		if (reason == EVO_FLASH_OK ||
		    reason >= EVO_FLASH_ERR_KEYED) {
			drop(t);
			return;
		}
		finish(t, EVO_FLASH_REFUSED, reason, detail);
		return;
	default:
		drop(t);
		return;
	}
}

void evo_flash_tx_timeout(evo_flash_tx *t)
{
	switch (t->stage) {
	case EVO_FLASH_TX_BEGIN:
	case EVO_FLASH_TX_END:
		t->waiting = 0;
		t->waiting_auth = 0;
		return;
	case EVO_FLASH_TX_DATA:
		t->next = t->acked;
		return;
	default:
		return;
	}
}
