/* A mind image sent over CAN (evo/flash.h): the robot's receiver and the
 * host's sender. */
#include "evo/flash.h"

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

/* End the transfer under way with a reason; the frames of it still on
 * the way are then ignored, so one refusal is said once. */
static evo_flash_rx_result refuse(evo_flash_rx *rx, evo_flash_reason why,
				  uint32_t detail, evo_can_frame *reply)
{
	rx->active = 0;
	rx->quiet = 1;
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
	if (f->len != 8)
		return refuse(rx, EVO_FLASH_ERR_FRAME, 0, reply);
	if (f->data[0] != EVO_FLASH_VERSION)
		return refuse(rx, EVO_FLASH_ERR_VERSION, EVO_FLASH_VERSION,
			      reply);
	uint32_t len = 4u * evo_wire_get_u16(f->data + 2);
	if (len > rx->slot_size || !rx->slot)
		return refuse(rx, EVO_FLASH_ERR_SIZE, rx->slot_size, reply);
	if (len < sizeof(evo_image_header))
		return refuse(rx, EVO_FLASH_ERR_IMAGE, EVO_ERR_IMAGE_LENGTH,
			      reply);
	/* The image's own header is checked again at the end: this is
	 * only so that another robot's image is refused before it is sent. */
	if (evo_wire_get_u32(f->data + 4) != rx->def.names_hash)
		return refuse(rx, EVO_FLASH_ERR_NAMES, rx->def.names_hash,
			      reply);
	uint8_t w = f->data[1];
	rx->window = w == 0 ? 1 : w > rx->def.window ? rx->def.window : w;
	rx->length = len;
	rx->active = 1;
	rx->last_ms = now_ms;
	evo_flash_reply(reply, EVO_FLASH_READY, rx->window, 0, rx->slot_size);
	return EVO_FLASH_RX_REPLY;
}

/* Ask for the segments from rx->next again, once per gap. */
static evo_flash_rx_result resend(evo_flash_rx *rx, evo_flash_reason why,
				  evo_can_frame *reply)
{
	if (rx->gap_said)
		return EVO_FLASH_RX_NONE;
	rx->gap_said = 1;
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
		rx->acked = rx->next;
		evo_flash_reply(reply, EVO_FLASH_ACK, 0, rx->next, 0);
		return EVO_FLASH_RX_REPLY;
	}
	return EVO_FLASH_RX_NONE;
}

static evo_flash_rx_result end(evo_flash_rx *rx, const evo_can_frame *f,
			       uint32_t now_ms, evo_can_frame *reply)
{
	if (!rx->active) {
		if (rx->done && f->len == 4 &&
		    evo_wire_get_u32(f->data) == rx->done_crc) {
			/* its DONE was lost: say it again */
			evo_flash_reply(reply, EVO_FLASH_DONE, 0,
					evo_flash_segments(rx->done_length),
					rx->done_tick);
			return EVO_FLASH_RX_REPLY;
		}
		if (rx->quiet)
			return EVO_FLASH_RX_NONE;
		return refuse(rx, EVO_FLASH_ERR_NO_TRANSFER, 0, reply);
	}
	rx->last_ms = now_ms;
	if (f->len != 4)
		return refuse(rx, EVO_FLASH_ERR_FRAME, 0, reply);
	if (rx->next != evo_flash_segments(rx->length))
		return refuse(rx, EVO_FLASH_ERR_INCOMPLETE, rx->next, reply);
	if (rx->crc != evo_wire_get_u32(f->data))
		return refuse(rx, EVO_FLASH_ERR_CRC, rx->crc, reply);
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
		f->data[1] = t->window;
		evo_wire_put_u16(f->data + 2, (uint16_t)(t->length / 4u));
		evo_wire_put_u32(
		    f->data + 4,
		    t->length >= 20u ? evo_wire_get_u32(t->image + 16) : 0u);
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
		f->id = EVO_FLASH_END;
		f->len = 4;
		evo_wire_put_u32(f->data, t->crc);
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

void evo_flash_tx_reply(evo_flash_tx *t, const evo_can_frame *f)
{
	if (f->id != EVO_FLASH_REPLY || f->len != 8 ||
	    t->stage == EVO_FLASH_TX_FINISHED)
		return;
	uint8_t kind = f->data[0], reason = f->data[1];
	uint32_t n = evo_wire_get_u16(f->data + 2);
	uint32_t detail = evo_wire_get_u32(f->data + 4);
	switch (kind) {
	case EVO_FLASH_READY:
		/* Also after segments: a BEGIN sent again was answered, and
		 * the robot has begun anew. */
		if (reason >= 1 && reason < t->window)
			t->window = reason;
		t->stage = EVO_FLASH_TX_DATA;
		t->waiting = 0;
		t->acked = t->next = 0;
		t->robot_slot = detail;
		t->progress++;
		return;
	case EVO_FLASH_ACK:
		if (t->stage != EVO_FLASH_TX_DATA || n <= t->acked ||
		    n > t->total)
			return;
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
		if (t->stage != EVO_FLASH_TX_DATA || n > t->total)
			return;
		/* The robot has every segment before n, and only those. */
		t->acked = t->next = n;
		t->resends_asked++;
		t->progress++;
		return;
	case EVO_FLASH_DONE:
		if (t->stage == EVO_FLASH_TX_END)
			finish(t, EVO_FLASH_DONE, reason, detail);
		return;
	case EVO_FLASH_REFUSED:
		/* Before READY, the end of an earlier transfer is not this
		 * one's. */
		if (t->stage == EVO_FLASH_TX_BEGIN &&
		    (reason == EVO_FLASH_ERR_NO_TRANSFER ||
		     reason == EVO_FLASH_ERR_TIMEOUT))
			return;
		finish(t, EVO_FLASH_REFUSED, reason, detail);
		return;
	default:
		return;
	}
}

void evo_flash_tx_timeout(evo_flash_tx *t)
{
	switch (t->stage) {
	case EVO_FLASH_TX_BEGIN:
	case EVO_FLASH_TX_END:
		t->waiting = 0;
		return;
	case EVO_FLASH_TX_DATA:
		t->next = t->acked;
		return;
	default:
		return;
	}
}
